//! FFR dynamics of flexible multibody systems (floating frame of reference,
//! Shabana's notation; theory in the repository's `docs/theory.md`).
//!
//! - [`kernel`]: what generated code provides per element ([`ElementKernels`]).
//! - [`body`]: a body's generalized forces, derivatives and mass blocks
//!   ([`Body`]); [`kernel_body`]: bodies assembled from element kernels;
//!   [`rigid`]: rigid bodies; [`modal`]: bodies reduced to modes.
//! - [`system`]: bodies, prescribed coordinates, joints ([`joint`]) at
//!   markers ([`marker`]), force elements ([`force`]), drivers ([`driver`]).
//! - [`assembly`]: residual and analytic iteration matrix in the structure of
//!   [`linalg::BorderedSystem`] (banded elastic blocks bordered by frame and
//!   constraint rows).
//! - [`integrator`]: generalized-α (index 3) and RK4–Baumgarte.
//! - [`linear`]: linear models `ẋ = A x + B u`, `y = C x + D u` on the
//!   constraint manifold, eigenvalues; [`statics`]: static equilibria and
//!   steady rotations (one Newton driver with load stepping).

pub mod assembly;
mod attached;
pub mod body;
pub mod driver;
pub mod error;
pub mod force;
mod inertia;
pub mod initial;
pub mod integrator;
pub mod interrupt;
pub mod joint;
pub mod kernel;
pub mod kernel_body;
pub mod linalg;
pub mod linear;
pub mod marker;
pub mod modal;
pub mod modal_kernels;
#[cfg(feature = "tape")]
pub mod modal_tape;
pub mod monitor;
pub mod nodal;
pub mod rigid;
pub mod rotation;
pub mod section;
pub mod segmented;
pub mod statics;
pub mod system;
#[cfg(feature = "tape")]
pub mod tape;

pub use assembly::Assembly;
pub use body::{
    sample_bits, BandBuf, Body, BodyForces, BodyLayout, BodyMass, BodyState, BodyTangent, BodyWork,
    InnerWork, Invariants, PointShape, ScalarLayout,
};
pub use driver::Driver;
pub use error::{Error, Result};
pub use ffr_spec as spec;
pub use force::{ForceAxes, ForceElement, TorqueLaw};
pub use integrator::{
    GeneralizedAlpha, Integrator, Rk4Baumgarte, State, StepView, Stepper, StepperState, Summary,
};
pub use interrupt::Interrupt;
pub use joint::Constraint;
pub use kernel::{
    CompiledBody, ElementKernels, KernelInfo, KernelInput, MassOut, ResidualOut, TangentOut,
};
pub use kernel_body::KernelBody;
pub use marker::{BodyId, Marker};
pub use modal::{ModalBody, ModalConsts, ModalData};
pub use modal_kernels::ModalKernels;
pub use monitor::Monitor;
pub use nalgebra;
pub use nodal::NodalBody;
pub use rigid::RigidBody;
pub use segmented::SegmentGroup;
pub use system::{BodyEntry, Pose, Rayleigh, System};

/// Energy of a configuration (J).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energy {
    /// `½ q̇ᵀ M q̇`.
    pub kinetic: f64,
    /// `½ q_fᵀ K_ff q_f + U_nl`.
    pub elastic: f64,
    /// `−g · (m R + A S_t)` summed over bodies.
    pub gravity: f64,
    /// `½ k (l − l₀)²` summed over springs.
    pub springs: f64,
}

impl Energy {
    /// Total mechanical energy.
    pub fn total(&self) -> f64 {
        self.kinetic + self.elastic + self.gravity + self.springs
    }
}

/// Rates of work at a state (W): what the force elements and the damping
/// put into the system and take out of it. With them the mechanical energy
/// balances, `E(t) − E(0) = ∫ applied dt − ∫ dissipated dt`, when no
/// prescribed motion (a drive, a prescribed coordinate) does work.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Power {
    /// Power of the point forces (`F · ṗ`) and of the motors (`τ φ̇` of a
    /// constant-torque or PD law).
    pub applied: f64,
    /// Power the dampers take out (`≥ 0`): `c l̇²` of each spring–damper,
    /// `c φ̇²` of each rotational spring–damper, `q̇_fᵀ (α m_ff + β K_ff) q̇_f`
    /// of each body with Rayleigh damping.
    pub dissipated: f64,
}
