//! The vocabulary shared by the generator (`ffr-codegen`) and the runtime
//! (`ffr-runtime`): what an elastic coordinate is ([`Kind`]), how a body frame
//! is fixed to a body ([`Reference`]), how a body of `N` equal elements numbers
//! its elastic coordinates ([`Mesh`]), the body parameters ([`Params`]) and the
//! model options ([`Formalism`], [`Stiffening`], [`SceneDim`], [`FrameModel`],
//! together [`KernelOptions`]), sections that vary along the span
//! ([`SectionProp`], [`SectionModel`], the exact element moments
//! [`element_moments`]), masses attached to a beam ([`AttachedMass`]), and a scene as resolved data ([`scene`]: what a
//! scene file says, checked, before anything is built from it).
//!
//! It has no dependencies (feature `clap`: `clap::ValueEnum` for the
//! options), so that both sides use one definition of each
//! concept (the numbering of `q_f` in particular) without the generator
//! depending on the runtime or the other way round.

mod attached;
mod kernel_kind;
mod kernel_options;
mod location;
mod mesh;
mod options;
mod params;
pub mod scene;
mod section;
mod segments;
pub mod text;

pub use attached::{AttachedMass, AttachedMassError};
pub use kernel_kind::KernelKind;
pub use kernel_options::{FrameModel, KernelOptions, SceneDim};
pub use location::Location;
pub use mesh::{
    check_nodes, Dof, ElementCoordinate, Kind, Mesh, MeshError, Reference, MAX_ELEMENTS,
};
pub use options::{Formalism, Stiffening};
pub use params::{Param, ParamError, Params};
pub use section::{
    element_moments, fill_moments, twisted_moments, SectionError, SectionModel, SectionProp,
};
pub use segments::{check_segments, uniform_bounds, SegmentError, MAX_SEGMENTS};

/// Offsets of the flat array of one element's invariants for `n` element
/// coordinates, and its length: `[m, S_t0 (3), S̄ (3 n), S̄_kl (9 n²; k, l,
/// a, b), Ī_kl (9 n; k, l, a), Θ_kl (9), m_ff (n²), K_ff (n²)]` (row-major).
/// Generated `element_invariants` kernels write this layout; the runtime
/// assembles body invariants from it.
pub fn invariant_layout(n: usize) -> ([usize; 8], usize) {
    let sizes = [1, 3, 3 * n, 9 * n * n, 9 * n, 9, n * n, n * n];
    let mut off = [0; 8];
    let mut t = 0;
    for (o, s) in off.iter_mut().zip(sizes) {
        *o = t;
        t += s;
    }
    (off, t)
}
