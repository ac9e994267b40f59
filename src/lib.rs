//! **ffr**: floating frame of reference (FFR) flexible multibody dynamics
//! from generated code.
//!
//! What a crate that simulates flexible bodies depends on (its `build.rs`
//! depends on `ffr-codegen` only as a build-dependency):
//!
//! - [`flex_body`]: the attribute that generates a body's element kernels at
//!   compile time;
//! - [`runtime`]: bodies, joints, forces, generalized-α and RK4;
//! - [`prelude`]: the names a simulation uses;
//! - [`Error`]: one error type to match on.
//!
//! Behind features:
//!
//! - `scene`: `scene` (scenes built from resolved data, `SceneSpec`, and
//!   run): all a compiled scene (`ffr_codegen::Builder::scene`) needs;
//! - `scene-files` (implies `scene`): `scene::load` (TOML scene files),
//!   `kernels::BeamSpec` (a beam described at run time, on tapes of the
//!   generator's programs), `modal` (reduced bodies), `fe` (a scene's bodies
//!   from finite-element matrices; `ffr-codegen`'s feature `fe`) and
//!   `codegen` (plain names: the items exist only with the feature);
//! - `builtin-kernels` (implies `scene-files`): the built-in shapes'
//!   compiled kernels, used by `BeamSpec` and scene files instead of tapes.
//!
//! The command line (`ffr run`, `ffr report`, …) is the package `ffr-cli`.

pub use ffr_macros::*;
pub use ffr_runtime as runtime;
pub use nalgebra;

mod error;
pub mod prelude;

pub use error::{Error, Result, SceneError};

#[cfg(feature = "scene-files")]
pub use ffr_codegen as codegen;
#[cfg(feature = "scene-files")]
pub mod fe;
#[cfg(feature = "scene-files")]
pub mod invariants;
#[cfg(feature = "scene-files")]
pub mod kernels;
#[cfg(feature = "scene-files")]
pub mod modal;
#[cfg(feature = "scene")]
pub mod scene;

#[cfg(feature = "scene-files")]
pub use crate::runtime::tape::TapeKernels;
#[cfg(feature = "scene-files")]
pub use kernels::{BeamSpec, FrameModel, Kernels};
