//! Exact symbolic generator of floating-frame-of-reference (FFR) code.
//!
//! From a shape description (the element shape-function matrix `S`, see
//! [`shape`]) it computes the element's inertia shape integrals and
//! stiffness exactly ([`body`]; `m`, `S_t0`, `S̄`, `S̄_kl`, `Ī_kl`, `Θ_kl`,
//! `m_ff`, `K_ff` as rational polynomials in the parameters), the
//! stiffening energies ([`energy`]) and the element's equations of motion in
//! body axes with the derivatives a Newton iteration needs ([`eom`], with the
//! chain rule through named intermediates in [`dag`]); turns them into
//! straight-line programs with the parameters folded into per-body
//! coefficients ([`program`], [`kernel`]); and emits unrolled, formatted
//! Rust implementing the runtime's `ElementKernels` ([`emit`]), from a build
//! script ([`Builder`]) or the `#[flex_body]` attribute. No floating point
//! is used before emission; literals are the exact rationals rounded to
//! nearest. The theory is in the repository's `docs/theory.md`.

pub mod body;
pub mod builder;
#[cfg(any(feature = "sections", feature = "fe"))]
mod csv_table;
pub mod dag;
pub mod emit;
pub mod energy;
pub mod eom;
pub mod error;
#[cfg(feature = "modal")]
pub mod export;
pub mod expr;
#[cfg(feature = "fe")]
pub mod fe;
pub mod flex_body;
pub mod kernel;
pub mod limits;
#[cfg(feature = "modal")]
pub mod modal;
pub mod poly;
pub mod program;
pub mod sanitize;
#[cfg(feature = "scene")]
pub mod scene;
#[cfg(feature = "sections")]
pub mod sections;
pub mod shape;

pub use body::{BodySpec, Dof, ExactInvariants, Formalism, Reference};
pub use builder::{BodyConfig, Builder, KernelConfig};
pub use emit::{emit_body_file, emit_kernels_file, EmitOptions};
pub use eom::KernelModel;
pub use error::{Error, Location};
/// How `BodyConfig::modes` and `#[flex_body(modes = …)]` reduce a body (as
/// a scene file's `modes`, `boundary`, `static_modes`, `modal_damping`).
pub use ffr_spec::scene::ModalSettings;
pub use ffr_spec::{
    FrameModel, KernelOptions, Params, SceneDim, SectionModel, SectionProp, Stiffening,
    MAX_SEGMENTS,
};
pub use kernel::{generate_checked, generate_kernels, KernelSet};
pub use shape::{Kind, Shape};
