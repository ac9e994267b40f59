//! Modal reduction of a body: numeric invariants from the exact ones, modal
//! bases (modal truncation, Craig–Bampton), invariants and polynomial energies
//! projected onto a basis.
//!
//! The pipeline, for a body `spec` at parameter values `p`:
//!
//! 1. [`Invariants::from_exact`]: every exact invariant (a rational polynomial
//!    in the parameters) evaluated with the parameters as exact rationals
//!    (every `f64` is one) and rounded once, so each entry of `m_ff`, `K_ff`,
//!    `S̄_kl`, … is the correctly rounded value of the exact invariant at `p`.
//! 2. [`reduce`] (or [`modal_truncation`], [`craig_bampton`]): a basis `Φ`
//!    (`n_f × k`) with `q_f = Φ η`, from `m_ff` and `K_ff` in `f64`.
//! 3. [`Invariants::project`]: the invariants of the reduced body,
//!    `S̄Φ`, `Φᵀ S̄_kl Φ`, `Ī_kl Φ`, `Φᵀ m_ff Φ`, `Φᵀ K_ff Φ`
//!    (`m`, `S_t0`, `Θ_kl` unchanged) — the same struct with `n_f = k`, the
//!    numeric coefficients of a modal sub-body.
//! 4. [`substitute_params`] and [`project_energy`]: a polynomial strain
//!    energy `U(q_f)` (e.g. [`BodySpec::stiffening_energy`]) at `p`, then as a
//!    polynomial in the modal coordinates `η` (symbols `Sym::Q(j)`, `j` the
//!    mode index).
//!
//! Everything is deterministic: no hash-map iteration, no threads; two runs
//! on the same input give bit-identical results.
//!
//! [`BodySpec::stiffening_energy`]: crate::BodySpec::stiffening_energy

mod basis;
mod energy;
mod invariants;
mod kernels;
mod model;

#[cfg(feature = "fe")]
pub(crate) use basis::complement;
pub use basis::{
    augment, craig_bampton, modal_truncation, reduce, rigid_body_modes, static_loads, ModalBasis,
    ModeKind, Reduction, STATIC_DROP_TOL,
};
pub use energy::{project_energy, substitute_params, MAX_ENERGY_DEGREE};
pub use invariants::{eval_poly, Invariants};
pub use kernels::{exact_invariants, generate_modal_kernels, ModalKernelSet, MAX_GENERATED_MODES};
pub use model::{describe_body, elastic_modes, ModalModel};

/// What can go wrong in a modal reduction.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ModalError {
    /// A polynomial that cannot be evaluated at the given parameters.
    #[error("cannot evaluate `{poly}`: {reason}")]
    Eval {
        /// The polynomial (or term) as text.
        poly: String,
        /// Why.
        reason: String,
    },
    /// Bad input sizes or parameters (wrong basis size, mode count, node index, …).
    #[error("{0}")]
    Input(String),
    /// A matrix that must be positive definite is not.
    #[error("{0}")]
    NotDefinite(String),
}
