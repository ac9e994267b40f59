//! Scene files: a TOML description of bodies, joints, drives, motors,
//! forces and outputs, run by `ffr run SCENE.toml` (format: `docs/scenes.md`),
//! or compiled into a crate by `ffr_codegen::Builder::scene`.
//!
//! - [`load`](mod@load): from the file to a [`Scene`], one file per TOML section;
//! - [`model`]: the loaded scene and its output columns;
//! - [`provider`]: where flexible bodies get their kernels;
//! - [`run`](mod@run): the run and its recorded columns;
//! - [`emit`]: a scene's specialized kernels as Rust.

pub mod emit;
pub mod load;
pub mod model;
pub mod provider;
pub mod run;

pub use load::{from_str, load, load_with, SceneError};
pub use model::{EnergyPart, FlexSpec, Output, OutputKind, Scene, MAX_RECORDED_VALUES};
pub use provider::{DefaultKernels, GeneralKernels, KernelProvider};
pub use run::{run, SceneRun};
