//! FFR dynamics of flexible multibody systems (floating frame of reference,
//! Shabana's notation; see the project's theory sheet).
//!
//! - [`body`]: what a body provides ([`FlexBody`], [`Invariants`]).
//! - [`model`]: one body's mass matrix, quadratic velocity vector, forces, energy.
//! - [`system`]: bodies, joints ([`joint`]), markers ([`marker`]), force elements ([`force`]), drivers ([`driver`]).
//! - [`integrator`]: generalized-α (index 3) and RK4–Baumgarte.
//! - [`scenes`]: benchmark scenes (spin-up, pendulum, free-floating body, slider-crank).

pub mod body;
pub mod driver;
pub mod error;
pub mod force;
pub mod integrator;
pub mod joint;
pub mod linalg;
pub mod marker;
pub mod model;
pub mod rigid;
pub mod rotation;
pub mod scenes;
pub mod system;

pub use body::{
    CompiledBody, FlexBody, InertiaTerms, InvariantBody, Invariants, MassBlocks, Params,
};
pub use driver::Driver;
pub use error::{Error, Result};
pub use force::ForceElement;
pub use integrator::{GeneralizedAlpha, Integrator, Rk4Baumgarte, StepView, Summary, Trajectory};
pub use joint::Constraint;
pub use marker::{BodyId, Marker};
pub use model::{BodyModel, Rayleigh};
pub use nalgebra;
pub use rigid::RigidBody;
pub use system::{ConstraintEval, Energy, Pose, State, System};

#[cfg(test)]
mod testing;
#[cfg(test)]
mod tests;
