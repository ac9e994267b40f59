//! From a parsed scene file to a [`SceneSpec`]: every value checked (with
//! errors at `file:line:col`), names looked up, markers parsed, profiles and
//! motors chosen, defaults filled in. What only building the system can
//! check (a joint that does not close, a parameter the kernels need) is left
//! to the builder, with the locations it needs to say where.

use crate::error::{Error, Location};
use crate::scene::quoted as q;
use crate::scene::{flex_models, RawScene};
use ffr_spec::scene::SceneSpec;
use std::ops::Range;
use std::path::Path;
use toml::Spanned;

mod bodies;
mod forces;
mod inputs;
mod integrator;
mod joints;
mod markers;
mod outputs;
mod profiles;
mod sections;

use ffr_spec::scene::MAX_RECORDED_VALUES;

pub(crate) struct Ctx<'a> {
    pub(crate) file: &'a str,
    pub(crate) text: &'a str,
}

impl Ctx<'_> {
    pub(crate) fn err(&self, span: Range<usize>, msg: impl Into<String>) -> Error {
        Error::Scene {
            location: self.loc(span),
            message: msg.into(),
        }
    }

    pub(crate) fn loc(&self, span: Range<usize>) -> Location {
        Location::of(self.file, self.text, span.start)
    }
}

pub(crate) fn pos_f64(c: &Ctx, v: &Spanned<f64>, what: &str) -> Result<f64, Error> {
    let x = *v.get_ref();
    if x.is_finite() && x > 0.0 && !x.is_normal() {
        Err(c.err(
            v.span(),
            format!(
                "`{what}` = {} is subnormal: below {:e}, the smallest normal f64, products with it underflow to 0",
                ffr_spec::text::Num(x),
                f64::MIN_POSITIVE
            ),
        ))
    } else if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(c.err(
            v.span(),
            format!("`{what}` must be a finite number > 0, found {x:?}"),
        ))
    }
}

pub(crate) fn fin_f64(c: &Ctx, v: &Spanned<f64>, what: &str) -> Result<f64, Error> {
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

pub(crate) fn vec_n(
    c: &Ctx,
    v: &Spanned<Vec<f64>>,
    n: usize,
    what: &str,
) -> Result<[f64; 3], Error> {
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
    let mut out = [0.0; 3];
    out[..n].copy_from_slice(x);
    Ok(out)
}

/// The resolved scene of a parsed and checked ([`crate::scene::check`])
/// scene file; `file` names it in errors, `base` resolves relative shape
/// paths.
pub fn resolve(raw: &RawScene, text: &str, file: &str, base: &Path) -> Result<SceneSpec, Error> {
    let c = Ctx { file, text };
    let dim = crate::scene::dimension_of(raw, text, file)?;
    let models = flex_models(raw, text, file)?;
    let t_end = pos_f64(&c, &raw.t_end, "t_end")?;
    let dt = pos_f64(&c, &raw.dt, "dt")?;
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
    let integrator = integrator::integrator(&c, &raw.integrator)?;
    let names: Vec<String> = raw.bodies.keys().map(|k| k.get_ref().clone()).collect();
    if names.is_empty() {
        return Err(c.err(
            raw.dimension.span(),
            "a scene needs at least one body under [bodies.NAME]",
        ));
    }
    let rigid: Vec<bool> = raw.bodies.values().map(|b| b.mass.is_some()).collect();
    let fe: Vec<bool> = raw.bodies.values().map(|b| b.fe.is_some()).collect();
    let markers = markers::Markers {
        c: &c,
        dim,
        names,
        rigid,
        fe,
    };
    let bodies = bodies::bodies(&c, raw, dim, base, &models)?;
    let gravity = match &raw.gravity {
        Some(g) => Some((vec_n(&c, g, dim, "gravity")?, c.loc(g.span()))),
        None => None,
    };
    let joints = joints::joints(&c, raw, t_end, &markers)?;
    let forces = raw
        .forces
        .iter()
        .enumerate()
        .map(|(i, f)| forces::force(&c, &markers, f, i, t_end))
        .collect::<Result<Vec<_>, _>>()?;
    let inputs = inputs::inputs(&c, raw, &markers, &joints, t_end)?;
    let mut outputs: Vec<ffr_spec::scene::OutputSpec> = Vec::new();
    for o in &raw.outputs {
        let out = outputs::output(&c, &markers, o)?;
        if outputs.iter().any(|x| x.name == out.name) || out.name == "t" {
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
    Ok(SceneSpec {
        origin: file.to_string(),
        description: raw.description.clone(),
        dim,
        t_end,
        dt,
        dt_at: c.loc(raw.dt.span()),
        integrator,
        gravity,
        bodies,
        joints,
        forces,
        outputs,
        inputs,
    })
}

/// Read, parse, check and resolve the scene file at `path` (named `origin`
/// in errors; relative shape paths against its directory).
pub fn resolve_file(path: &Path, origin: &str) -> Result<SceneSpec, Error> {
    let text = crate::scene::read(path)?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    resolve_str(&text, origin, &base)
}

/// Parse, check and resolve a scene from its text.
pub fn resolve_str(text: &str, origin: &str, base: &Path) -> Result<SceneSpec, Error> {
    let raw = crate::scene::parse(text, origin)?;
    crate::scene::check(&raw, text, origin)?;
    resolve(&raw, text, origin, base)
}
