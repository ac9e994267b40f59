//! **ffr**: floating frame of reference (FFR) code generation and simulation
//! for flexible multibody dynamics.
//!
//! - [`codegen`]: exact symbolic generator of FFR element kernels from shape functions.
//! - [`flex_body`]: the attribute that generates a body at compile time.
//! - [`runtime`]: the dynamics (bodies, joints, forces, generalized-α, RK4).
//! - [`compiled`]: the built-in shapes' kernels compiled into this crate, and
//!   [`TapeKernels`]: kernels of shapes chosen at run time, on tapes
//!   (`ffr_runtime::tape`).
//! - [`scenes`]: the benchmark scenes, written against the public API.
//! - [`report`]: `ffr report`, work-precision diagrams of the scenes.

pub use ffr_codegen as codegen;
pub use ffr_macros::*;
pub use ffr_runtime as runtime;
pub use nalgebra;

pub mod cli;
pub mod compiled;
pub mod modal;
pub mod output;
pub mod plot;
pub mod reference;
pub mod report;
pub mod scene;
pub mod scenes;
pub mod stability;

pub use crate::runtime::tape::TapeKernels;
pub use compiled::{BeamSpec, FrameModel, Kernels};
