//! **ffr**: floating frame of reference (FFR) code generation and simulation
//! for flexible multibody dynamics.
//!
//! - [`codegen`]: exact symbolic generator of FFR terms from shape functions.
//! - [`flex_body`]: the attribute that generates a body at compile time.
//! - [`runtime`]: the dynamics (mass matrix, forces, joints, integrators, scenes).

pub use ffr_codegen as codegen;
pub use ffr_macros::*;
pub use ffr_runtime as runtime;
pub use nalgebra;

pub mod cli;
pub mod evaluated;
pub mod free_floating;
pub mod output;
pub mod pendulum;
pub mod plot;
pub mod slider_crank;
pub mod spin_up;

pub use evaluated::EvaluatedBody;

/// The main job of `cargo run --release`: the spin-up beam at 4 rad/s.
pub fn default_scene() -> Result<(), Box<dyn std::error::Error>> {
    spin_up::run(&spin_up::SpinUpArgs::default()).map(|_| ())
}
