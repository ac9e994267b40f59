//! From a scene file to a [`Scene`]: checked, with errors at `file:line:col`,
//! and with what the scene fixes folded in (a body whose frame a revolute
//! joint to the ground and an angle drive determine completely gets its frame
//! coordinates prescribed, so it runs its elastic equations only).

use crate::codegen::scene::quoted as q;
use crate::codegen::scene::{flex_models, FlexBodyModel, RawScene};
use crate::codegen::Location;
pub use crate::error::SceneError;
use crate::runtime::nalgebra::Vector3;
use crate::runtime::{Body, System};
use crate::scene::model::{FlexSpec, Output, Scene, MAX_RECORDED_VALUES};
use crate::scene::provider::{DefaultKernels, KernelProvider};
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;

mod bodies;
mod forces;
mod integrator;
mod joints;
mod markers;
mod outputs;
mod profiles;

use forces::force;
use integrator::integrator;
use markers::Markers;
use outputs::output;

fn scene_error(e: crate::codegen::Error) -> SceneError {
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

struct Ctx<'a> {
    file: &'a str,
    text: &'a str,
    /// Where in `text` the spans start (a table parsed on its own, such as
    /// a motor's target profile, has spans relative to its own text).
    base: usize,
}

impl Ctx<'_> {
    fn err(&self, span: Range<usize>, msg: impl Into<String>) -> SceneError {
        SceneError {
            location: Some(Location::of(self.file, self.text, self.base + span.start)),
            // The runtime's errors carry their kind; the scene's say where.
            message: msg.into().replace("invalid input: ", ""),
        }
    }
}

fn pos_f64(c: &Ctx, v: &Spanned<f64>, what: &str) -> Result<f64, SceneError> {
    let x = *v.get_ref();
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(c.err(
            v.span(),
            format!("`{what}` must be a finite number > 0, found {x:?}"),
        ))
    }
}

fn fin_f64(c: &Ctx, v: &Spanned<f64>, what: &str) -> Result<f64, SceneError> {
    let x = *v.get_ref();
    if x.is_finite() {
        Ok(x)
    } else {
        Err(c.err(
            v.span(),
            format!("`{what}` must be a finite number, found {x:?}"),
        ))
    }
}

fn vec_n(c: &Ctx, v: &Spanned<Vec<f64>>, n: usize, what: &str) -> Result<Vector3<f64>, SceneError> {
    let x = v.get_ref();
    if x.len() != n {
        return Err(c.err(
            v.span(),
            format!(
                "`{what}` needs {n} components in a {n}-D scene, found {}",
                x.len()
            ),
        ));
    }
    if let Some(bad) = x.iter().find(|y| !y.is_finite()) {
        return Err(c.err(v.span(), format!("`{what}` must be finite, found {bad:?}")));
    }
    let mut out = Vector3::zeros();
    out.as_mut_slice()[..n].copy_from_slice(x);
    Ok(out)
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

/// Load a scene from its text; `file` names it in errors, `base` resolves
/// relative shape paths.
pub fn from_str(
    text: &str,
    file: &str,
    base: &Path,
    provider: &dyn KernelProvider,
) -> Result<Scene, SceneError> {
    let c = Ctx {
        file,
        text,
        base: 0,
    };
    let raw: RawScene = crate::codegen::scene::parse(text, file).map_err(scene_error)?;
    crate::codegen::scene::check(&raw, text, file).map_err(scene_error)?;
    build(&c, raw, base, provider)
}

/// What every section of a scene file is read against: the scene's
/// dimension and end time, where relative shape paths start, the kernel
/// provider, the generator's model of each flexible body, which bodies'
/// frames a joint folds into prescribed coordinates, and the markers.
struct Env<'a> {
    dim: usize,
    t_end: f64,
    base: &'a Path,
    provider: &'a dyn KernelProvider,
    models: &'a [FlexBodyModel],
    folded: Vec<Option<usize>>,
    markers: Markers<'a>,
}

/// What the sections add to, in file order: the system, the notes on what
/// was folded in, how each body runs, the flexible bodies as built.
struct Parts {
    sys: System<Box<dyn Body>>,
    notes: Vec<String>,
    kernels: Vec<(String, String)>,
    flex: Vec<FlexSpec>,
}

fn build(
    c: &Ctx,
    raw: RawScene,
    base: &Path,
    provider: &dyn KernelProvider,
) -> Result<Scene, SceneError> {
    let dim = crate::codegen::scene::dimension_of(&raw, c.text, c.file).map_err(scene_error)?;
    let models = flex_models(&raw, c.text, c.file).map_err(scene_error)?;
    let t_end = pos_f64(c, &raw.t_end, "t_end")?;
    let dt = pos_f64(c, &raw.dt, "dt")?;
    if dt > t_end {
        return Err(c.err(
            raw.dt.span(),
            format!("`dt` = {dt:?} is longer than `t_end` = {t_end:?}"),
        ));
    }
    if t_end / dt > 1e9 {
        return Err(c.err(
            raw.dt.span(),
            format!(
                "t_end/dt = {:e} steps is more than a scene may take (1e9)",
                t_end / dt
            ),
        ));
    }
    let integrator = integrator(c, &raw.integrator)?;
    let names: Vec<String> = raw.bodies.keys().map(|k| k.get_ref().clone()).collect();
    if names.is_empty() {
        return Err(c.err(
            raw.dimension.span(),
            "a scene needs at least one body under [bodies.NAME]",
        ));
    }
    let rigid: Vec<bool> = raw.bodies.values().map(|b| b.mass.is_some()).collect();
    // Which bodies' frames are folded into prescribed coordinates.
    let folding = raw.folded();
    let folded: Vec<Option<usize>> = names.iter().map(|n| folding.get(n).copied()).collect();
    let env = Env {
        dim,
        t_end,
        base,
        provider,
        models: &models,
        folded,
        markers: Markers {
            c,
            dim,
            names,
            rigid,
        },
    };
    let mut parts = Parts {
        sys: System::with_dim(dim),
        notes: Vec::new(),
        kernels: Vec::new(),
        flex: Vec::new(),
    };
    bodies::add_bodies(c, &raw, &env, &mut parts)?;
    // Gravity.
    if let Some(g) = &raw.gravity {
        let gv = vec_n(c, g, dim, "gravity")?;
        parts
            .sys
            .set_gravity(gv)
            .map_err(|e| c.err(g.span(), e.to_string()))?;
    }
    let joint_spans = joints::add_joints(c, &raw, &env, &mut parts)?;
    // Forces.
    for f in &raw.forces {
        force(c, &env.markers, &mut parts.sys, f)?;
    }
    // Outputs.
    let mut outputs = Vec::new();
    for o in &raw.outputs {
        let out = output(c, &env.markers, &parts.sys, o)?;
        if outputs.iter().any(|x: &Output| x.name == out.name) || out.name == "t" {
            return Err(c.err(
                o.name.span(),
                format!(
                    "output `{}` is named twice (or `t`, the time column)",
                    q(&out.name)
                ),
            ));
        }
        outputs.push(out);
    }
    // The recorded run must fit in memory: every output and `t` at every step.
    let values = (t_end / dt + 2.0) * (outputs.len() + 1) as f64;
    if values > MAX_RECORDED_VALUES as f64 {
        return Err(c.err(
            raw.dt.span(),
            format!(
                "t_end / dt = {:.3e} steps × {} columns (t and {} outputs) = {values:.3e} recorded values: more than the limit of {MAX_RECORDED_VALUES} ({} MiB of memory); use a larger `dt`, a shorter `t_end` or fewer outputs",
                t_end / dt,
                outputs.len() + 1,
                outputs.len(),
                (MAX_RECORDED_VALUES * 8) >> 20
            ),
        ));
    }
    // The initial state: the joints must close by moving the bodies' frames
    // (or the elastic states the scene gives), and none may be redundant.
    if let Err(crate::runtime::Error::Joint {
        joint,
        kind,
        reason,
    }) = parts.sys.initial_state(0.0)
    {
        let span = joint_spans
            .get(joint)
            .cloned()
            .unwrap_or_else(|| raw.dt.span());
        return Err(c.err(span, format!("{kind} joint: {reason}")));
    }
    Ok(Scene {
        origin: c.file.to_string(),
        description: raw.description,
        system: parts.sys,
        t_end,
        dt,
        integrator,
        outputs,
        flex: parts.flex,
        kernels: parts.kernels,
        notes: parts.notes,
    })
}

/// The scene files shipped with ffr (`scenes/`).
pub fn builtin_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes")
}
