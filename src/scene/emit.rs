//! The specialized Rust of a scene's flexible bodies (`ffr emit --scene`).

use std::path::Path;

/// The generated file `Builder::scene` writes for the scene at `path`, with
/// the scene type named `type_name`.
pub fn scene_file(path: &Path, type_name: &str) -> crate::Result<String> {
    let origin = path.display().to_string();
    Ok(crate::codegen::builder::generate_scene(
        path,
        &origin,
        type_name,
        "::ffr::runtime",
    )?)
}
