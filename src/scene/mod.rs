//! Scenes: bodies, joints, drives, motors, forces and outputs, built into a
//! system and run. A scene comes from a TOML file (`ffr run SCENE.toml`,
//! format: `docs/scenes.md`; feature `scene-files`) or is compiled into a
//! crate by `ffr_codegen::Builder::scene`, which carries the resolved scene
//! as generated data (no file is parsed at start-up).
//!
//! - `SceneSpec` (in `ffr_spec::scene`, also [`spec`]): a scene as resolved data;
//! - [`build`](mod@build): from a `SceneSpec` to a [`Scene`], one file per section;
//! - `load` (feature `scene-files`): from a file to a [`Scene`];
//! - [`model`]: the built scene and its output columns;
//! - [`provider`]: where flexible bodies get their kernels;
//! - [`run`](mod@run): the run and its recorded columns;
//! - [`simulation`]: a scene stepped by its caller ([`Simulation`]: inputs,
//!   outputs, exact save and restore);
//! - [`linear`]: linear models (`A, B, C, D`) and Campbell diagrams;
//! - [`statics`]: the static equilibrium under the scene's loads and its
//!   outputs (`ffr static`);
//! - `edit` (feature `scene-files`): scene variants by dotted keys
//!   (`bodies.beam.params.e`), loaded with the loader's located errors;
//! - `vtk` (feature `vtk`): ParaView time series and mode-shape animations;
//! - `emit` (feature `scene-files`): a scene's specialized kernels as Rust.

pub mod build;
#[cfg(feature = "scene-files")]
pub mod edit;
#[cfg(feature = "scene-files")]
pub mod emit;
pub mod frames;
pub mod linear;
#[cfg(feature = "scene-files")]
pub mod load;
pub mod model;
pub mod provider;
pub mod run;
pub mod simulation;
pub mod statics;
#[cfg(feature = "vtk")]
pub mod vtk;

pub use crate::error::SceneError;
pub use crate::runtime::spec::scene as spec;
pub use crate::runtime::spec::scene::{FlexSpec, SceneSpec};
pub use build::build;
#[cfg(feature = "scene-files")]
pub use edit::{SceneText, SceneValue};
#[cfg(feature = "scene-files")]
pub use load::{from_str, load, load_with};
pub use model::{input_files, EnergyPart, Input, Output, OutputKind, Scene, MAX_RECORDED_VALUES};
pub use provider::KernelProvider;
#[cfg(feature = "scene-files")]
pub use provider::{DefaultKernels, GeneralKernels};
pub use run::{run, run_interruptible, run_with, RunOptions, SceneRun};
pub use simulation::{Simulation, SimulationState};
