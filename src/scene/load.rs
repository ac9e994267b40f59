//! From a scene file to a [`Scene`]: read, parsed, checked and resolved by
//! the generator's scene reader (errors at `file:line:col`), then built
//! ([`crate::scene::build()`]).

use crate::scene::build::build;
use crate::scene::model::Scene;
use crate::scene::provider::{DefaultKernels, KernelProvider};
use crate::SceneError;
use std::path::{Path, PathBuf};

pub(crate) fn scene_error(e: crate::codegen::Error) -> SceneError {
    match e {
        crate::codegen::Error::Scene { location, message } => SceneError {
            location: Some(location),
            message,
        },
        other => SceneError {
            location: None,
            message: other.to_string(),
        },
    }
}

/// Read and load a scene file (relative shape paths against its directory).
pub fn load(path: &Path) -> crate::Result<Scene> {
    load_with(path, &DefaultKernels)
}

/// [`load`] with another kernel provider.
pub fn load_with(path: &Path, provider: &dyn KernelProvider) -> crate::Result<Scene> {
    let file = path.display().to_string();
    let text = crate::codegen::scene::read(path)?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    Ok(from_str(&text, &file, &base, provider)?)
}

/// Read and resolve a scene file to its spec (not built), for commands
/// that build variants of it (a Campbell diagram's speeds).
pub fn load_spec(path: &Path) -> crate::Result<crate::scene::SceneSpec> {
    let file = path.display().to_string();
    let text = crate::codegen::scene::read(path)?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    Ok(crate::codegen::scene::resolve_str(&text, &file, &base).map_err(scene_error)?)
}

/// The files the scene `spec` is read from ([`crate::scene::input_files`]).
pub fn spec_input_files(spec: &crate::scene::SceneSpec) -> Vec<PathBuf> {
    use crate::runtime::spec::scene::BodyKind;
    let mut flex = Vec::new();
    let mut fe = Vec::new();
    for b in &spec.bodies {
        match &b.kind {
            BodyKind::Flexible(f) => flex.push(f.clone()),
            BodyKind::Fe(f) => fe.push(f.clone()),
            BodyKind::Rigid { .. } => {}
        }
    }
    crate::scene::input_files(&spec.origin, &flex, &fe)
}

/// Load a scene from its text; `file` names it in errors, `base` resolves
/// relative shape paths.
pub fn from_str(
    text: &str,
    file: &str,
    base: &Path,
    provider: &dyn KernelProvider,
) -> Result<Scene, SceneError> {
    let spec = crate::codegen::scene::resolve_str(text, file, base).map_err(scene_error)?;
    build(&spec, provider)
}

/// The scene files shipped with ffr (`scenes/`).
pub fn builtin_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes")
}
