//! Exact symbolic generator of floating-frame-of-reference (FFR) code.
//!
//! From a shape description (the element shape-function matrix `S`, see
//! [`shape`]) and a body made of `N` such elements ([`BodySpec`]) it computes
//! the inertia shape integrals `m`, `S_t0`, `S̄`, `S̄_kl`, `Ī_kl`, `Θ_kl`,
//! `m_ff` and the stiffness `K_ff` exactly ([`body`]), turns them and the
//! `q_f`-dependent terms `S_t`, `Ī_θθ`, `Ī_θf` (and optionally geometric
//! stiffening) into straight-line programs ([`generate`]), and emits
//! unrolled, formatted Rust implementing `ffr_runtime::FlexBody` ([`emit`]).
//! No floating point is used before emission; literals are the exact
//! rationals rounded to nearest.
//!
//! Names and conventions follow the project's theory sheet.

pub mod body;
pub mod builder;
pub mod emit;
pub mod error;
pub mod expr;
pub mod generate;
pub mod limits;
pub mod numeric;
pub mod poly;
pub mod program;
pub mod sanitize;
pub mod shape;

pub use body::{BodySpec, Dof, Formalism, Reference};
pub use builder::Builder;
pub use emit::{emit_file, EmitOptions};
pub use error::{Error, Location};
pub use generate::{generate, Generated, Options};
pub use numeric::{NumericInertia, NumericInvariants, ParamValues};
pub use program::Target;
pub use shape::{Kind, Shape};
