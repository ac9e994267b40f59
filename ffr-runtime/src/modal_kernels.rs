//! Generated kernels of a modal body's inertia equations (`ffr emit
//! --modes`, `#[flex_body(modes = …)]`, `BodyConfig::modes`): the projected
//! equations of `docs/theory.md` §13, "Modal bodies as generated code",
//! unrolled over the modes with the projected invariants as constants. A
//! [`ModalBody`](crate::ModalBody) made by
//! [`ModalBody::with_kernels`](crate::ModalBody::with_kernels) calls them in
//! place of the run-time equations (`InertiaTerms`).
//!
//! The inputs and outputs are those of the element kernels
//! ([`crate::kernel`]) with the modes as the coordinates (`x0` unused):
//! row-major slices, outputs not written are structurally zero (callers
//! clear them first), work arrays owned by the caller, nothing allocated.

use crate::kernel::{KernelInput, MassOut, ResidualOut, TangentOut};

/// The inertia kernels of one modal body (see the module documentation).
/// Object safe.
pub trait ModalKernels: Send + Sync {
    /// Number of modes `k` (the coordinates).
    fn modes(&self) -> usize;

    /// Scene dimension the kernels were generated for: 2 (frame motion in
    /// the x–y plane) or 3.
    fn scene_dim(&self) -> usize;

    /// Whether `f_f` includes the linear elastic force `K̃ η` (generated for
    /// a body without geometric stiffening; with stiffening the caller adds
    /// the elastic force).
    fn linear_elastic(&self) -> bool;

    /// Scratch space (f64 values) a call needs from its caller (0 for
    /// compiled kernels).
    fn scratch(&self) -> usize {
        0
    }

    /// `S_t` and the acceleration-linear blocks at `η = q`.
    fn mass(&self, q: &[f64], out: &mut MassOut, scratch: &mut [f64]);

    /// `f_r`, `f_θ`, `f_f`.
    fn residual(&self, x: &KernelInput, out: &mut ResidualOut, scratch: &mut [f64]);

    /// The residual and its derivatives (`β' ∂/∂η̈ + γ' ∂/∂η̇ + ∂/∂η`, and
    /// by the frame motion).
    fn tangent(&self, x: &KernelInput, bp: f64, gp: f64, out: &mut TangentOut, scratch: &mut [f64]);

    /// `f_f` only.
    fn residual_elastic(&self, x: &KernelInput, f_e: &mut [f64], scratch: &mut [f64]);

    /// `f_f` and `β' ∂f_f/∂η̈ + γ' ∂f_f/∂η̇ + ∂f_f/∂η`.
    // The generated signature, like `ElementKernels::tangent_elastic`.
    #[allow(clippy::too_many_arguments)]
    fn tangent_elastic(
        &self,
        x: &KernelInput,
        bp: f64,
        gp: f64,
        f_e: &mut [f64],
        k_ee: &mut [f64],
        scratch: &mut [f64],
    );
}
