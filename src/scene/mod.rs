//! Scene files: a TOML description of bodies, joints, drives, motors,
//! forces and outputs, run by `ffr run SCENE.toml` (format: `docs/scenes.md`),
//! or compiled into a crate by `ffr_codegen::Builder::scene`.

pub mod emit;
pub mod load;
pub mod run;

pub use load::{
    from_str, load, load_with, DefaultKernels, EnergyPart, FlexSpec, GeneralKernels,
    KernelProvider, Output, OutputKind, Scene, SceneError,
};
pub use run::{run, SceneRun};
