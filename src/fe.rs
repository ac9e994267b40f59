//! FE bodies of scenes (`fe = { nodes, mass, stiffness }`, docs/fe.md): the
//! files a scene names read and checked as it says (with its
//! `stiffness_scale`), the body with its reference condition, and one line
//! describing it. The scene builder runs them reduced
//! ([`crate::runtime::ModalBody`] over a [`crate::runtime::NodalBody`]);
//! `ffr invariants`, `ffr modes` and `ffr export` take them from here.

use crate::codegen::fe::{FeBody, FeModel, FeReference};
use crate::runtime::spec::scene::FeSpec;
use std::path::Path;

/// The model of `f`'s files, its stiffness scaled by `f.stiffness_scale`.
/// Errors name the file (and `file:line:col` inside it).
pub fn model(f: &FeSpec) -> Result<FeModel, String> {
    let mut model = FeModel::load(
        Path::new(&f.nodes),
        Path::new(&f.mass),
        Path::new(&f.stiffness),
    )
    .map_err(|e| e.to_string())?;
    if f.stiffness_scale != 1.0 {
        model.stiffness *= f.stiffness_scale;
        if model.stiffness.iter().any(|v| !v.is_finite()) {
            return Err(format!(
                "`stiffness_scale` = {:e} makes a stiffness entry overflow f64",
                f.stiffness_scale
            ));
        }
    }
    Ok(model)
}

/// `f`'s reference condition.
pub fn reference(f: &FeSpec) -> FeReference {
    if f.free {
        FeReference::Free
    } else {
        FeReference::Clamped
    }
}

/// The body of `f` ([`model`], then its reference condition and interface).
pub fn body(f: &FeSpec) -> Result<FeBody, String> {
    FeBody::new(model(f)?, reference(f), &f.interface).map_err(|e| e.to_string())
}

/// One line naming an FE body: nodes, elastic coordinates, reference,
/// interface ([`FeBody::describe`]).
pub fn describe(body: &FeBody) -> String {
    body.describe()
}
