//! What a scene fixes for the generator: which bodies are flexible, with
//! which kernel options (scene dimension, stiffening, formalism), and
//! whether their frame motion is prescribed (a revolute joint to the ground
//! at the frame origin with an angle drive) with `ā ≡ 0` (no gravity).

use super::{quoted, scene_err, RawScene};
use crate::error::Error;
use std::ops::Range;
use toml::Spanned;

/// What the generator needs of a flexible body of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct FlexBodyModel {
    /// Body name.
    pub name: String,
    /// Its shape as written (a built-in name, or a path relative to the scene file).
    pub shape: String,
    /// Span of the shape string (for errors).
    pub span: Range<usize>,
    /// Its kernel options: the scene's dimension, a free frame unless a
    /// folded joint prescribes its motion (then at rest when, in addition,
    /// the scene has no gravity: `ā = Aᵀ(R̈ − g) ≡ 0`).
    pub options: ffr_spec::KernelOptions,
}

/// The stiffening model of `stiffening = true | false | "second-order" | "fourth-order"`.
pub fn stiffening_of(
    v: &Spanned<toml::Value>,
    text: &str,
    file: &str,
) -> Result<ffr_spec::Stiffening, Error> {
    match v.get_ref() {
        toml::Value::Boolean(b) => Ok(ffr_spec::Stiffening::from_bool(*b)),
        toml::Value::String(s) if matches!(s.as_str(), "second-order" | "fourth-order" | "off") => {
            Ok(s.parse().expect("checked"))
        }
        other => Err(scene_err(
            text,
            file,
            v.span(),
            format!(
                "`stiffening` must be true, false, \"second-order\" or \"fourth-order\", found a {}",
                other.type_str()
            ),
        )),
    }
}

/// The scene's dimension (2 or 3).
pub fn dimension_of(raw: &RawScene, text: &str, file: &str) -> Result<usize, Error> {
    match *raw.dimension.get_ref() {
        2 => Ok(2),
        3 => Ok(3),
        d => Err(scene_err(
            text,
            file,
            raw.dimension.span(),
            format!("`dimension` must be 2 (planar) or 3 (spatial), found {d}"),
        )),
    }
}

/// What the generator needs of each flexible body of a scene, in body-name
/// order: its options, and what the scene fixes (frame motion prescribed by
/// a folded joint; `ā ≡ 0` when, in addition, there is no gravity).
pub fn flex_models(raw: &RawScene, text: &str, file: &str) -> Result<Vec<FlexBodyModel>, Error> {
    let dim = dimension_of(raw, text, file)?;
    let folded = raw.folded();
    let gravity = raw.has_gravity();
    let mut out = Vec::new();
    for (name, rb) in &raw.bodies {
        let name = name.get_ref();
        let Some(shape) = &rb.shape else { continue };
        let formalism = match &rb.formalism {
            Some(f) => f.get_ref().parse().map_err(|_: String| {
                scene_err(
                    text,
                    file,
                    f.span(),
                    format!(
                        "unknown formalism `{}`: expected consistent or lumped",
                        quoted(f.get_ref())
                    ),
                )
            })?,
            None => ffr_spec::Formalism::Consistent,
        };
        let stiffening = match &rb.stiffening {
            Some(v) => stiffening_of(v, text, file)?,
            None => ffr_spec::Stiffening::Off,
        };
        let fixed = folded.contains_key(name.as_str());
        out.push(FlexBodyModel {
            name: name.clone(),
            shape: shape.get_ref().clone(),
            span: shape.span(),
            options: ffr_spec::KernelOptions {
                formalism,
                stiffening,
                scene: ffr_spec::SceneDim::from_dim(dim),
                frame: ffr_spec::FrameModel::from_flags(!fixed, fixed && !gravity),
            },
        });
    }
    Ok(out)
}
