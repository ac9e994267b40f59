//! From a scene file to a [`Scene`]: checked, with errors at `file:line:col`,
//! and with what the scene fixes folded in (a body whose frame a revolute
//! joint to the ground and an angle drive determine completely gets its frame
//! coordinates prescribed, so it runs its elastic equations only).

use crate::codegen::scene::quoted as q;
use crate::codegen::scene::{
    flex_models, FlexBodyModel, RawBody, RawForce, RawIntegrator, RawMotor, RawOutput, RawProfile,
    RawScene, RawTarget,
};
use crate::codegen::Location;
use crate::kernels::{BeamSpec, Kernels};
use crate::runtime::nalgebra::{Matrix3, Unit, UnitQuaternion, Vector2, Vector3};
use crate::runtime::spec::{Param, Params, Reference};
use crate::runtime::{
    Body, BodyId, Driver, ElementKernels, GeneralizedAlpha, Integrator, KernelBody, Marker, Pose,
    Rayleigh, RigidBody, Rk4Baumgarte, System, TorqueLaw,
};
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use toml::Spanned;

/// A scene file that does not load: where and what.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// `file:line:col`, when the problem has a place.
    pub location: Option<Location>,
    /// What is wrong and what is allowed.
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.location {
            Some(l) => write!(f, "{l}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for SceneError {}

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

/// What an output column records.
#[derive(Clone, Debug, PartialEq)]
pub enum OutputKind {
    /// Global position of a marker (component 0, 1, 2).
    Position(usize),
    /// Elastic displacement of a marker in its body's frame.
    Deflection(usize),
    /// Global velocity of a marker.
    Velocity(usize),
    /// The angle of the marker's x axis in the global x–y plane, or, with a
    /// reference marker `a`, about `a`'s z axis (`atan2(x·y_a, x·x_a)`),
    /// unwrapped along the run.
    Angle,
    /// An energy: total, kinetic, elastic, gravity or springs; or the
    /// work done on the system so far by point forces and motors, or taken
    /// out by dampers (trapezoidal rule over the steps).
    Energy(EnergyPart),
}

/// Which energy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnergyPart {
    /// `T + V`.
    Total,
    /// `T`.
    Kinetic,
    /// Elastic.
    Elastic,
    /// Gravitational.
    Gravity,
    /// Springs.
    Springs,
    /// `∫ P_applied dt`: work of the point forces and motors since `t = 0`.
    Work,
    /// `∫ P_dissipated dt`: energy taken out by the dampers since `t = 0`.
    Dissipated,
}

/// An output column.
#[derive(Clone, Debug)]
pub struct Output {
    /// Column name.
    pub name: String,
    /// What it records.
    pub kind: OutputKind,
    /// Where (ground for energies).
    pub marker: Marker,
    /// Reference marker of a relative angle.
    pub relative_to: Option<Marker>,
}

/// How a flexible body of a scene is made.
#[derive(Clone, Debug, PartialEq)]
pub struct FlexSpec {
    /// What the generator needs (options, what the scene fixes).
    pub model: FlexBodyModel,
    /// The beam (shape resolved against the scene file, mesh, parameters).
    pub beam: BeamSpec,
}

/// Supplies the element kernels of a scene's flexible bodies: the built-in
/// compiled ones or tapes (`ffr run`), or a compiled scene's own.
pub trait KernelProvider {
    /// The kernels for `spec`, and how they run (`compiled`, `tape`, …).
    #[allow(clippy::type_complexity)]
    fn kernels(&self, spec: &FlexSpec) -> crate::Result<(Box<dyn ElementKernels>, &'static str)>;
}

/// Built-in compiled kernels when they exist, else tapes of the body's
/// specialized kernels.
pub struct DefaultKernels;

/// The general kernels whatever the scene: a spatial scene and a free
/// frame, the body every scene could use (for comparisons with what
/// [`DefaultKernels`] specializes; `ffr run --general`).
pub struct GeneralKernels;

impl KernelProvider for GeneralKernels {
    fn kernels(&self, spec: &FlexSpec) -> crate::Result<(Box<dyn ElementKernels>, &'static str)> {
        let m = &spec.model;
        #[cfg(feature = "builtin-kernels")]
        if let Some(k) = crate::kernels::builtin(
            &spec.beam.shape,
            3,
            true,
            m.options.formalism,
            m.options.stiffening,
        ) {
            return Ok((Box::new(Kernels::Compiled(k)), "compiled, general"));
        }
        let shape = crate::codegen::Shape::resolve(&spec.beam.shape, None)?;
        let options = crate::runtime::spec::KernelOptions::new()
            .formalism(m.options.formalism)
            .stiffening(m.options.stiffening)
            .scene(crate::runtime::spec::SceneDim::Spatial);
        let model = crate::codegen::KernelModel::new(shape, options);
        let k = Kernels::Tape(Box::new(crate::runtime::tape::TapeKernels::new(&model)?));
        Ok((Box::new(k), "tape, general"))
    }
}

impl KernelProvider for DefaultKernels {
    /// The beam's own kernels: its options are the scene's model (the
    /// loader builds `spec.beam` from `spec.model`), so a shape file's tape
    /// is generated once.
    fn kernels(&self, spec: &FlexSpec) -> crate::Result<(Box<dyn ElementKernels>, &'static str)> {
        let k: Kernels = spec.beam.kernels()?;
        let path = k.path();
        Ok((Box::new(k), path))
    }
}

/// The most values a scene run records (`t` and every output at every
/// step), checked at load time: 2²⁵ values (256 MiB as numbers, about 0.7 GB as CSV text).
pub const MAX_RECORDED_VALUES: usize = 1 << 25;

/// A loaded scene, ready to run.
pub struct Scene {
    /// The file it came from.
    pub origin: String,
    /// Its description line, if any.
    pub description: Option<String>,
    /// The system.
    pub system: System<Box<dyn Body>>,
    /// End time (s).
    pub t_end: f64,
    /// Step (s).
    pub dt: f64,
    /// Integrator.
    pub integrator: Integrator,
    /// Output columns (after `t`).
    pub outputs: Vec<Output>,
    /// The flexible bodies as built.
    pub flex: Vec<FlexSpec>,
    /// How each body runs: `compiled`, `tape`, `rigid`.
    pub kernels: Vec<(String, String)>,
    /// What the loader folded in or left out (one line each).
    pub notes: Vec<String>,
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

const PARAMS: &str = "length, rho, area, iy, iz, e, g, j";

fn parse_params(
    c: &Ctx,
    body: &str,
    raw: &RawBody,
    span: Range<usize>,
) -> Result<(Params, [bool; 8], Range<usize>), SceneError> {
    let Some(p) = &raw.params else {
        return Err(c.err(
            span,
            format!("flexible body `{body}` needs `params = {{ {PARAMS} }}` (SI units)"),
        ));
    };
    let mut v = [0.0; 8];
    let mut given = [false; 8];
    for (k, val) in p.get_ref() {
        let Some(i) = Param::FIELDS.iter().position(|f| f.field() == k.get_ref()) else {
            return Err(c.err(
                k.span(),
                format!(
                    "unknown parameter `{}`: expected one of {PARAMS}",
                    q(k.get_ref())
                ),
            ));
        };
        v[i] = fin_f64(c, val, k.get_ref())?;
        given[i] = true;
    }
    if !given[0] {
        return Err(c.err(p.span(), format!("body `{body}`: `params` needs `length`")));
    }
    Ok((Params::from_array(v), given, p.span()))
}

/// A marker in the scene's syntax.
#[derive(Clone, Debug)]
enum MarkerRef {
    Ground(Vector3<f64>),
    Origin(BodyId),
    Axis(BodyId, f64),
    Point(BodyId, Vector3<f64>),
}

struct Builder<'a> {
    c: &'a Ctx<'a>,
    dim: usize,
    names: Vec<String>,
    rigid: Vec<bool>,
}

impl Builder<'_> {
    fn marker_ref(&self, s: &Spanned<String>) -> Result<MarkerRef, SceneError> {
        let text = s.get_ref().trim();
        let allowed = || {
            format!(
                "a marker is `ground@[x, y{}]`, `NAME` (a body's frame origin), `NAME@x=…` (a point on a beam's axis) or `NAME@[x, y{}]` (a point fixed in a body's frame); bodies: {}",
                if self.dim == 3 { ", z" } else { "" },
                if self.dim == 3 { ", z" } else { "" },
                self.names.join(", ")
            )
        };
        let (name, rest) = match text.split_once('@') {
            Some((n, r)) => (n.trim(), Some(r.trim())),
            None => (text, None),
        };
        let point = |r: &str| -> Option<Vector3<f64>> {
            let inner = r.strip_prefix('[')?.strip_suffix(']')?;
            let xs: Vec<f64> = inner
                .split(',')
                .map(|x| x.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
                .collect::<Option<_>>()?;
            if xs.len() != self.dim {
                return None;
            }
            let mut v = Vector3::zeros();
            v.as_mut_slice()[..self.dim].copy_from_slice(&xs);
            Some(v)
        };
        if name == "ground" {
            let p = rest.and_then(point).ok_or_else(|| {
                self.c.err(
                    s.span(),
                    format!(
                        "`{text}`: the ground needs a point, `ground@[x, y{}]`; {}",
                        if self.dim == 3 { ", z" } else { "" },
                        allowed(),
                        text = q(text)
                    ),
                )
            })?;
            return Ok(MarkerRef::Ground(p));
        }
        let Some(i) = self.names.iter().position(|n| n == name) else {
            return Err(self.c.err(
                s.span(),
                format!(
                    "`{text}`: no body named `{name}`; {}",
                    allowed(),
                    text = q(text),
                    name = q(name)
                ),
            ));
        };
        let b = BodyId(i);
        match rest {
            None => Ok(MarkerRef::Origin(b)),
            Some(r) if r.starts_with("x=") || r.starts_with("x =") => {
                let v = r.split_once('=').map(|(_, v)| v.trim()).unwrap_or("");
                let x: f64 = v
                    .parse()
                    .ok()
                    .filter(|x: &f64| x.is_finite())
                    .ok_or_else(|| {
                        self.c.err(
                            s.span(),
                            format!(
                                "`{text}`: `x=` needs a number; {}",
                                allowed(),
                                text = q(text)
                            ),
                        )
                    })?;
                if self.rigid[i] {
                    return Err(self.c.err(
                        s.span(),
                        format!("`{text}`: `{name}` is rigid and has no axis; give a body-frame point `{name}@[x, y{}]`", if self.dim == 3 { ", z" } else { "" }, text = q(text)),
                    ));
                }
                Ok(MarkerRef::Axis(b, x))
            }
            Some(r) => point(r).map(|p| MarkerRef::Point(b, p)).ok_or_else(|| {
                self.c.err(
                    s.span(),
                    format!("`{text}`: not a marker; {}", allowed(), text = q(text)),
                )
            }),
        }
    }

    fn marker(
        &self,
        sys: &System<Box<dyn Body>>,
        s: &Spanned<String>,
    ) -> Result<Marker, SceneError> {
        Ok(match self.marker_ref(s)? {
            MarkerRef::Ground(p) => Marker::ground(p),
            MarkerRef::Origin(b) => Marker::origin(b),
            MarkerRef::Point(b, p) => Marker::at(b, p),
            MarkerRef::Axis(b, x) => sys
                .point(b, x)
                .map_err(|e| self.c.err(s.span(), format!("`{}`: {e}", q(s.get_ref()))))?,
        })
    }
}

fn profile(
    c: &Ctx,
    p: &Spanned<RawProfile>,
    key: &str,
    t_end: f64,
    who: &str,
) -> Result<Driver, SceneError> {
    profile_at(c, p.span(), p.get_ref(), key, t_end, who)
}

/// A profile whose table is at `span`.
fn profile_at(
    c: &Ctx,
    span: std::ops::Range<usize>,
    r: &RawProfile,
    key: &str,
    t_end: f64,
    who: &str,
) -> Result<Driver, SceneError> {
    // Bounds of |f|, |ḟ|, |f̈| on [0, t_end]: each must be finite, or the
    // prescribed motion overflows during the run.
    let bounded = |bounds: &[(&str, f64)]| -> Result<(), SceneError> {
        match bounds.iter().find(|(_, b)| !b.is_finite()) {
            None => Ok(()),
            Some((what, b)) => Err(c.err(
                span.clone(),
                format!(
                    "{who}: the profile's {what} reaches {b:?} before t_end = {t_end:?}: beyond the range of f64"
                ),
            )),
        }
    };
    let name = match key {
        "angle" => r.angle.as_ref(),
        _ => r.slide.as_ref(),
    }
    .ok_or_else(|| c.err(span.clone(), format!("the drive needs `{key} = \"…\"`: one of spin-up, constant-rate, constant, harmonic")))?;
    let need = |v: &Option<Spanned<f64>>, what: &str| -> Result<f64, SceneError> {
        v.as_ref()
            .ok_or_else(|| {
                c.err(
                    name.span(),
                    format!("profile `{}` needs `{what}`", q(name.get_ref())),
                )
            })
            .and_then(|x| fin_f64(c, x, what))
    };
    let opt = |v: &Option<Spanned<f64>>, what: &str, d: f64| -> Result<f64, SceneError> {
        v.as_ref().map_or(Ok(d), |x| fin_f64(c, x, what))
    };
    match name.get_ref().as_str() {
        "spin-up" => {
            let omega = need(&r.omega, "omega")?;
            let ramp = r
                .ramp
                .as_ref()
                .ok_or_else(|| c.err(name.span(), "profile `spin-up` needs `ramp` (s)"))
                .and_then(|x| pos_f64(c, x, "ramp"))?;
            let start = opt(&r.start, "start", 0.0)?;
            bounded(&[
                (
                    "value (start + omega (t_end + ramp))",
                    start.abs() + omega.abs() * (t_end + ramp),
                ),
                ("rate (2 omega)", 2.0 * omega.abs()),
                ("acceleration (2 omega/ramp)", 2.0 * omega.abs() / ramp),
            ])?;
            Ok(Driver::spin_up(omega, ramp).map(move |[f, fd, fdd]| [start + f, fd, fdd]))
        }
        "constant-rate" => {
            let w = r
                .omega
                .as_ref()
                .or(r.rate.as_ref())
                .ok_or_else(|| {
                    c.err(
                        name.span(),
                        "profile `constant-rate` needs `omega` (rad/s, or m/s for a slide)",
                    )
                })
                .and_then(|x| fin_f64(c, x, "omega"))?;
            let start = opt(&r.start, "start", 0.0)?;
            bounded(&[
                ("value (start + omega t_end)", start.abs() + w.abs() * t_end),
                ("rate (omega)", w.abs()),
            ])?;
            Ok(Driver::linear(start, w))
        }
        "constant" => Ok(Driver::constant(need(&r.value, "value")?)),
        "harmonic" => {
            let start = opt(&r.start, "start", 0.0)?;
            let a = need(&r.amplitude, "amplitude")?;
            let nu = need(&r.frequency, "frequency")?;
            let phase = opt(&r.phase, "phase", 0.0)?;
            let w = 2.0 * std::f64::consts::PI * nu.abs();
            bounded(&[
                ("value (start + amplitude)", start.abs() + a.abs()),
                ("rate (amplitude 2π frequency)", a.abs() * w),
                ("acceleration (amplitude (2π frequency)²)", a.abs() * w * w),
                (
                    "phase (2π frequency t_end + phase)",
                    w * t_end + phase.abs(),
                ),
            ])?;
            Ok(Driver::harmonic(start, a, nu, phase))
        }
        other => Err(c.err(
            name.span(),
            format!(
                "unknown profile `{other}`: expected spin-up, constant-rate, constant or harmonic",
                other = q(other)
            ),
        )),
    }
}

fn integrator(c: &Ctx, r: &Option<Spanned<RawIntegrator>>) -> Result<Integrator, SceneError> {
    let Some(r) = r else {
        return Ok(Integrator::default());
    };
    let i = r.get_ref();
    match i.kind.get_ref().as_str() {
        "generalized-alpha" => {
            let mut g = GeneralizedAlpha::default();
            if let Some(x) = &i.rho_inf {
                g.rho_inf = fin_f64(c, x, "rho_inf")?;
                if !(0.0..=1.0).contains(&g.rho_inf) {
                    return Err(c.err(
                        x.span(),
                        format!("`rho_inf` must be in [0, 1], found {:?}", g.rho_inf),
                    ));
                }
            }
            if let Some(x) = &i.rtol {
                g.rtol = pos_f64(c, x, "rtol")?;
                if g.rtol >= 1.0 {
                    return Err(c.err(
                        x.span(),
                        format!(
                            "`rtol` (the relative Newton tolerance) must be in (0, 1), found {:?}",
                            g.rtol
                        ),
                    ));
                }
            }
            Ok(Integrator::GeneralizedAlpha(g))
        }
        "rk4" => {
            let mut k = Rk4Baumgarte::default();
            if let Some(x) = &i.alpha {
                k.alpha = fin_f64(c, x, "alpha")?;
            }
            if let Some(x) = &i.beta {
                k.beta = fin_f64(c, x, "beta")?;
            }
            Ok(Integrator::Rk4(k))
        }
        other => Err(c.err(
            i.kind.span(),
            format!(
                "unknown integrator `{other}`: expected generalized-alpha or rk4",
                other = q(other)
            ),
        )),
    }
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
    let b = Builder {
        c,
        dim,
        names: names.clone(),
        rigid,
    };
    // Which bodies' frames are folded into prescribed coordinates.
    let folding = raw.folded();
    let folded: Vec<Option<usize>> = names.iter().map(|n| folding.get(n).copied()).collect();
    let mut sys: System<Box<dyn Body>> = System::with_dim(dim);
    let mut notes = Vec::new();
    let mut kernels_used = Vec::new();
    let mut flex = Vec::new();
    let mut ids = Vec::new();
    for ((name, body), fold) in raw.bodies.iter().zip(&folded) {
        let (name_s, rb) = (name.get_ref(), body);
        let span = body.span().unwrap_or(0..0);
        let pose = pose(c, rb, dim, span.clone())?;
        let boxed: Box<dyn Body> = if let Some(m) = &rb.mass {
            for (k, v) in [
                ("shape", rb.shape.is_some()),
                ("elements", rb.elements.is_some()),
                ("params", rb.params.is_some()),
            ] {
                if v {
                    return Err(c.err(span.clone(), format!("body `{name_s}` has `mass` (rigid) and `{k}` (flexible): give one kind")));
                }
            }
            let mass = pos_f64(c, m, "mass")?;
            let com = match &rb.centre {
                Some(v) => vec_n(c, v, dim, "centre")?,
                None => Vector3::zeros(),
            };
            let inertia = rb.inertia.as_ref().ok_or_else(|| c.err(span.clone(), format!("rigid body `{name_s}` needs `inertia` (planar: a number about the centre of mass; spatial: [Ixx, Iyy, Izz] or a 3×3 table)")))?;
            let rbody = if dim == 2 {
                let j = inertia
                    .get_ref()
                    .as_float()
                    .or_else(|| inertia.get_ref().as_integer().map(|i| i as f64))
                    .ok_or_else(|| {
                        c.err(
                            inertia.span(),
                            "planar `inertia` is one number (kg m², about the centre of mass)",
                        )
                    })?;
                RigidBody::planar(mass, j, Vector2::new(com.x, com.y))
            } else {
                let m3 = inertia3(c, inertia)?;
                RigidBody::spatial(mass, m3, com)
            }
            .map_err(|e| c.err(span.clone(), format!("body `{name_s}`: {e}")))?;
            kernels_used.push((name_s.clone(), "rigid".to_string()));
            Box::new(rbody)
        } else {
            let shape = rb.shape.as_ref().ok_or_else(|| c.err(span.clone(), format!("body `{name_s}` needs `shape = \"beam2\"` (flexible) or `mass = …` (rigid)")))?;
            let elements = rb.elements.as_ref().ok_or_else(|| {
                c.err(
                    span.clone(),
                    format!("flexible body `{name_s}` needs `elements = N`"),
                )
            })?;
            let n = *elements.get_ref();
            if !(1..=ffr_spec_max() as i64).contains(&n) {
                return Err(c.err(
                    elements.span(),
                    format!("`elements` must be 1 to {}, found {n}", ffr_spec_max()),
                ));
            }
            let reference = match &rb.reference {
                Some(r) => r.get_ref().parse::<Reference>().map_err(|_| {
                    c.err(
                        r.span(),
                        format!(
                            "unknown reference condition `{}`: expected clamped, pinned or free",
                            q(r.get_ref())
                        ),
                    )
                })?,
                None => Reference::Clamped,
            };
            let model = models
                .iter()
                .find(|m| &m.name == name_s)
                .expect("every flexible body has a model")
                .clone();
            let stiffening = model.options.stiffening;
            let modal = modal_settings(c, name_s, rb, n as usize)?;
            let (params, given, params_span) = parse_params(c, name_s, rb, span.clone())?;
            let shape_s = shape.get_ref();
            let resolved = if crate::codegen::Shape::builtin(shape_s).is_some() {
                shape_s.clone()
            } else {
                base.join(shape_s).display().to_string()
            };
            let beam = BeamSpec {
                shape: resolved,
                elements: n as usize,
                reference,
                // The scene's model: what it fixes, carried unchanged.
                options: model.options,
                params,
                force_tape: false,
            };
            let _ = fold;
            let spec = FlexSpec { model, beam };
            let (kernels, path) = provider
                .kernels(&spec)
                .map_err(|e| c.err(shape.span(), format!("body `{name_s}`: {e}")))?;
            let dimension = kernels.info().dim;
            if dimension > dim {
                return Err(c.err(shape.span(), format!("body `{name_s}`: shape `{shape_s}` is spatial; a planar scene needs a planar shape", shape_s = q(shape_s))));
            }
            // A parameter the body uses must be given (a missing one would
            // be reported as zero).
            let used = &kernels.info().params_used;
            if let Some(missing) = Param::FIELDS
                .iter()
                .enumerate()
                .find(|(i, f)| !given[*i] && used.contains(f))
            {
                let names: Vec<&str> = used.iter().map(|p| p.field()).collect();
                return Err(c.err(
                    params_span,
                    format!(
                        "body `{name_s}`: `params` needs `{}`: shape `{shape_s}` in this scene uses {}",
                        missing.1.field(),
                        names.join(", "), shape_s = q(shape_s)),
                ));
            }
            let kb = KernelBody::new(kernels, params, n as usize, reference)
                .map_err(|e| c.err(span.clone(), format!("body `{name_s}`: {e}")))?;
            let boxed: Box<dyn Body> = match &modal {
                None => {
                    kernels_used.push((name_s.clone(), path.to_string()));
                    Box::new(kb)
                }
                Some((settings, modes_span)) => {
                    let b = &spec.beam;
                    let mb = crate::modal::ReducibleBody::from_parts(
                        &b.shape,
                        b.elements,
                        b.reference,
                        b.options.formalism,
                        b.params,
                    )
                    .and_then(|r| r.runtime_body(settings, stiffening, Box::new(kb)))
                    .map_err(|e| c.err(modes_span.clone(), format!("body `{name_s}`: {e}")))?;
                    kernels_used.push((
                        name_s.clone(),
                        format!(
                            "modal, {} modes ({path} full body for markers)",
                            mb.layout().nf
                        ),
                    ));
                    Box::new(mb)
                }
            };
            flex.push(spec);
            boxed
        };
        let id = sys
            .add_body(name_s, boxed, pose)
            .map_err(|e| c.err(span.clone(), e.to_string()))?;
        if let Some(d) = &rb.damping {
            if rigid_body(rb) {
                return Err(c.err(
                    d.span(),
                    format!("body `{name_s}` is rigid: `damping` is for elastic coordinates"),
                ));
            }
            let r = Rayleigh {
                alpha: d
                    .get_ref()
                    .alpha
                    .as_ref()
                    .map_or(Ok(0.0), |x| fin_f64(c, x, "alpha"))?,
                beta: d
                    .get_ref()
                    .beta
                    .as_ref()
                    .map_or(Ok(0.0), |x| fin_f64(c, x, "beta"))?,
            };
            sys.set_damping(id, r)
                .map_err(|e| c.err(d.span(), e.to_string()))?;
        }
        let v = match &rb.velocity {
            Some(v) => vec_n(c, v, dim, "velocity")?,
            None => Vector3::zeros(),
        };
        let w = match &rb.omega {
            None => Vector3::zeros(),
            Some(o) => match (dim, o.get_ref()) {
                (2, toml::Value::Float(x)) => Vector3::new(0.0, 0.0, *x),
                (2, toml::Value::Integer(x)) => Vector3::new(0.0, 0.0, *x as f64),
                (3, toml::Value::Array(a)) if a.len() == 3 => {
                    let xs: Option<Vec<f64>> = a
                        .iter()
                        .map(|x| x.as_float().or_else(|| x.as_integer().map(|i| i as f64)))
                        .collect();
                    let xs = xs.ok_or_else(|| c.err(o.span(), "`omega` must be three numbers"))?;
                    Vector3::new(xs[0], xs[1], xs[2])
                }
                _ => {
                    return Err(c.err(
                        o.span(),
                        if dim == 2 {
                            "planar `omega` is one number (rad/s about z)"
                        } else {
                            "spatial `omega` is [ωx, ωy, ωz] (rad/s, global)"
                        },
                    ))
                }
            },
        };
        if v.norm() > 0.0 || w.norm() > 0.0 {
            sys.set_velocity(id, v, w)
                .map_err(|e| c.err(span.clone(), e.to_string()))?;
        }
        if let Some(el) = &rb.elastic {
            if rigid_body(rb) {
                return Err(c.err(
                    el.span(),
                    format!("body `{name_s}` is rigid: `elastic` is the initial state of a flexible body"),
                ));
            }
            let labels = sys.body(id).layout().labels.clone();
            let by_label = |t: &Option<Spanned<crate::codegen::scene::RawLabelled>>,
                            what: &str|
             -> Result<Vec<f64>, SceneError> {
                let mut out = vec![0.0; labels.len()];
                for (k, x) in t.iter().flat_map(|t| t.get_ref()) {
                    let Some(i) = labels.iter().position(|l| l == k.get_ref()) else {
                        return Err(c.err(
                            k.span(),
                            format!(
                                "body `{name_s}` has no elastic coordinate `{}`; its coordinates are {}",
                                q(k.get_ref()),
                                labels.join(", ")
                            ),
                        ));
                    };
                    out[i] = fin_f64(c, x, &format!("{what}.{}", k.get_ref()))?;
                }
                Ok(out)
            };
            let q_f = by_label(&el.get_ref().q, "q")?;
            let qd_f = by_label(&el.get_ref().qd, "qd")?;
            sys.set_elastic(id, &q_f, &qd_f)
                .map_err(|e| c.err(el.span(), e.to_string()))?;
        }
        ids.push(id);
    }
    // Gravity.
    if let Some(g) = &raw.gravity {
        let gv = vec_n(c, g, dim, "gravity")?;
        sys.set_gravity(gv)
            .map_err(|e| c.err(g.span(), e.to_string()))?;
    }
    // Joints; `joint_spans[k]` is where constraint `k` of the system was
    // written (a joint with a drive adds two).
    let mut joint_spans: Vec<Range<usize>> = Vec::new();
    for (ji, jr) in raw.joints.iter().enumerate() {
        let j = jr;
        if let Some(prev) = ji.checked_sub(1) {
            let span = raw.joints[prev].span();
            joint_spans.resize(sys.constraints().len(), span);
        }
        let kind = jr.kind.get_ref().as_str();
        let bm = b.marker(&sys, &jr.b)?;
        if kind == "ground" {
            if jr.a.is_some() || jr.drive.is_some() || jr.motor.is_some() {
                return Err(c.err(j.span(), "a `ground` joint fixes body `b` where it starts: it takes no `a`, `drive` or `motor`"));
            }
            let MarkerRef::Origin(bid) = b.marker_ref(&jr.b)? else {
                return Err(c.err(
                    jr.b.span(),
                    "a `ground` joint takes a body name as `b` (it fixes the body's frame)",
                ));
            };
            sys.ground(bid)
                .map_err(|e| c.err(j.span(), e.to_string()))?;
            notes.push(format!(
                "body `{}`: frame fixed by a ground joint (prescribed coordinates)",
                names[bid.0]
            ));
            continue;
        }
        let a = jr.a.as_ref().ok_or_else(|| {
            c.err(
                j.span(),
                format!("a `{kind}` joint needs markers `a` and `b`"),
            )
        })?;
        let am = b.marker(&sys, a)?;
        if let Some(bi) = folded.iter().position(|f| *f == Some(ji)) {
            // Revolute to the ground at the body's frame origin, angle drive:
            // prescribe the frame (origin fixed, angle driven).
            let bid = BodyId(bi);
            let drive = profile(
                c,
                jr.drive.as_ref().expect("checked"),
                "angle",
                t_end,
                &format!("the drive of {}", joint_name(ji, jr)),
            )?;
            let entry = sys.body_entry(bid);
            let (o, d) = (entry.offset, entry.d);
            let (q0, _) = sys.initial_coords();
            let origin =
                Vector3::from_iterator((0..3).map(|k| if k < d { q0[o + k] } else { 0.0 }));
            let MarkerRef::Ground(p) = b.marker_ref(a)? else {
                unreachable!()
            };
            if (origin - p).norm() > 1e-12 * (1.0 + p.norm()) {
                return Err(c.err(a.span(), format!("the revolute joint's ground point {:?} is not at body `{}`'s frame origin {:?}: put the body's `position` at the joint", &p.as_slice()[..dim], names[bi], &origin.as_slice()[..dim])));
            }
            sys.prescribe_rotation_about_z(bid, drive)
                .map_err(|e| c.err(j.span(), e.to_string()))?;
            notes.push(format!(
                "body `{}`: revolute joint to the ground with an angle drive folded into prescribed frame coordinates ({})",
                names[bi],
                if b.rigid[bi] { "no equations left" } else { "elastic equations only" }
            ));
            continue;
        }
        if kind == "spherical" && dim == 2 {
            return Err(c.err(jr.kind.span(), "a `spherical` joint needs a spatial scene (dimension = 3); a planar scene has ground, fixed, revolute and prismatic joints"));
        }
        let res = match kind {
            "revolute" => sys.revolute(am.clone(), bm.clone()),
            "fixed" => sys.fixed(am.clone(), bm.clone()),
            "spherical" => sys.spherical(am.clone(), bm.clone()),
            "prismatic" => sys.prismatic(am.clone(), bm.clone()),
            other => {
                return Err(c.err(jr.kind.span(), format!("unknown joint kind `{other}`: expected ground, fixed, revolute, spherical or prismatic", other = q(other))));
            }
        };
        res.map_err(|e| c.err(jr.kind.span(), e.to_string()))?;
        if let Some(d) = &jr.drive {
            match kind {
                "revolute" => {
                    let f = profile(c, d, "angle", t_end, &format!("the drive of {}", joint_name(ji, jr)))?;
                    sys.prescribe_rotation(am.clone(), bm.clone(), f)
                }
                "prismatic" => {
                    let f = profile(c, d, "slide", t_end, &format!("the drive of {}", joint_name(ji, jr)))?;
                    sys.prescribe_slide(am.clone(), bm.clone(), f)
                }
                _ => return Err(c.err(d.span(), format!("a `{kind}` joint has no drive: drives are for revolute (angle) and prismatic (slide) joints"))),
            }
            .map_err(|e| c.err(d.span(), e.to_string()))?;
        }
        if let Some(m) = &jr.motor {
            if kind != "revolute" {
                return Err(c.err(
                    m.span(),
                    "motors act in revolute joints (a torque about the joint axis)",
                ));
            }
            let law = motor(c, m, t_end, &joint_name(ji, jr))?;
            sys.add_torque(am, bm, law)
                .map_err(|e| c.err(m.span(), e.to_string()))?;
        }
    }
    if let Some(last) = raw.joints.last() {
        joint_spans.resize(sys.constraints().len(), last.span());
    }
    // Forces.
    for f in &raw.forces {
        force(c, &b, &mut sys, f)?;
    }
    // Outputs.
    let mut outputs = Vec::new();
    for o in &raw.outputs {
        let out = output(c, &b, &sys, o)?;
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
    let _ = ids;
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
    }) = sys.initial_state(0.0)
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
        system: sys,
        t_end,
        dt,
        integrator,
        outputs,
        flex,
        kernels: kernels_used,
        notes,
    })
}

fn rigid_body(rb: &RawBody) -> bool {
    rb.mass.is_some()
}

fn ffr_spec_max() -> usize {
    crate::runtime::spec::MAX_ELEMENTS
}

fn inertia3(c: &Ctx, v: &Spanned<toml::Value>) -> Result<Matrix3<f64>, SceneError> {
    let num = |x: &toml::Value| x.as_float().or_else(|| x.as_integer().map(|i| i as f64));
    let bad = || {
        c.err(v.span(), "spatial `inertia` is [Ixx, Iyy, Izz] or a 3×3 table [[…], […], […]] (kg m², about the centre of mass)")
    };
    let a = v.get_ref().as_array().ok_or_else(bad)?;
    if a.len() == 3 && a.iter().all(|x| num(x).is_some()) {
        let d: Vec<f64> = a.iter().map(|x| num(x).expect("checked")).collect();
        return Ok(Matrix3::from_diagonal(&Vector3::new(d[0], d[1], d[2])));
    }
    if a.len() == 3 {
        let mut m = Matrix3::zeros();
        for (i, row) in a.iter().enumerate() {
            let r = row.as_array().filter(|r| r.len() == 3).ok_or_else(bad)?;
            for (j, x) in r.iter().enumerate() {
                m[(i, j)] = num(x).ok_or_else(bad)?;
            }
        }
        return Ok(m);
    }
    Err(bad())
}

fn pose(c: &Ctx, rb: &RawBody, dim: usize, span: Range<usize>) -> Result<Pose, SceneError> {
    let p = match &rb.position {
        Some(v) => vec_n(c, v, dim, "position")?,
        None => Vector3::zeros(),
    };
    if dim == 2 {
        if let Some(o) = &rb.orientation {
            return Err(c.err(o.span(), "a planar body has `angle`, not `orientation`"));
        }
        let a = rb
            .angle
            .as_ref()
            .map_or(Ok(0.0), |x| fin_f64(c, x, "angle"))?;
        Ok(Pose::planar(p.x, p.y, a))
    } else {
        if let Some(a) = &rb.angle {
            return Err(c.err(
                a.span(),
                "a spatial body has `orientation = { axis = [x, y, z], angle = … }`, not `angle`",
            ));
        }
        let q = match &rb.orientation {
            None => UnitQuaternion::identity(),
            Some(o) => {
                let ax = vec_n(c, &o.get_ref().axis, 3, "axis")?;
                if ax.norm() == 0.0 {
                    return Err(c.err(o.get_ref().axis.span(), "`axis` must not be zero"));
                }
                let ang = fin_f64(c, &o.get_ref().angle, "angle")?;
                UnitQuaternion::from_axis_angle(&Unit::new_normalize(ax), ang)
            }
        };
        let _ = span;
        Ok(Pose::spatial(p, q))
    }
}

/// How messages name joint `i` (0-based): `joint 2 (revolute, a =
/// `hub`, b = `arm`)`.
fn joint_name(i: usize, j: &crate::codegen::scene::RawJoint) -> String {
    format!(
        "joint {} (`{}`{}, b = `{}`)",
        i + 1,
        q(j.kind.get_ref()),
        j.a.as_ref()
            .map_or(String::new(), |a| format!(", a = `{}`", q(a.get_ref()))),
        q(j.b.get_ref())
    )
}

fn motor(c: &Ctx, m: &Spanned<RawMotor>, t_end: f64, joint: &str) -> Result<TorqueLaw, SceneError> {
    let r = m.get_ref();
    match (&r.torque, &r.target) {
        (Some(t), None) => {
            let tau = fin_f64(c, t, "torque")?;
            if r.kp.is_some() || r.kd.is_some() {
                return Err(c.err(
                    m.span(),
                    "a motor has `torque` (constant) or `target` with `kp`, `kd` (PD), not both",
                ));
            }
            Ok(TorqueLaw::Torque(Arc::new(move |_| tau)))
        }
        (None, Some(target)) => {
            let drv = match target.get_ref() {
                RawTarget::Angle(x) if x.is_finite() => Driver::constant(*x),
                RawTarget::Angle(x) => {
                    return Err(c.err(
                        target.span(),
                        format!("motor `target` must be a finite angle, found {x:?}"),
                    ))
                }
                RawTarget::Profile(p) => profile_at(
                    c,
                    target.span(),
                    p,
                    "angle",
                    t_end,
                    &format!("the motor target of {joint}"),
                )?,
            };
            let kp =
                r.kp.as_ref()
                    .ok_or_else(|| c.err(m.span(), "a PD motor needs `kp` (N m/rad)"))
                    .and_then(|x| fin_f64(c, x, "kp"))?;
            let kd = r.kd.as_ref().map_or(Ok(0.0), |x| fin_f64(c, x, "kd"))?;
            for (what, v, x) in [("kp", &r.kp, kp), ("kd", &r.kd, kd)] {
                if let (Some(v), true) = (v, x < 0.0) {
                    return Err(c.err(
                        v.span(),
                        format!("`{what}` (a PD gain) must be ≥ 0, found {x:?}"),
                    ));
                }
            }
            Ok(TorqueLaw::Pd {
                target: drv,
                kp,
                kd,
            })
        }
        _ => Err(c.err(
            m.span(),
            "a motor is `{ torque = τ }` or `{ target = φ, kp = …, kd = … }`",
        )),
    }
}

fn force(
    c: &Ctx,
    b: &Builder,
    sys: &mut System<Box<dyn Body>>,
    f: &RawForce,
) -> Result<(), SceneError> {
    let r = f;
    fn need<'v>(
        c: &Ctx,
        f: &RawForce,
        v: &'v Option<Spanned<String>>,
        what: &str,
    ) -> Result<&'v Spanned<String>, SceneError> {
        v.as_ref().ok_or_else(|| {
            c.err(
                f.span(),
                format!("a `{}` force needs `{what}`", f.kind.get_ref()),
            )
        })
    }
    let numr = |v: &Option<Spanned<f64>>, what: &str| -> Result<f64, SceneError> {
        v.as_ref()
            .ok_or_else(|| {
                c.err(
                    f.span(),
                    format!("a `{}` force needs `{what}`", r.kind.get_ref()),
                )
            })
            .and_then(|x| fin_f64(c, x, what))
    };
    // The two ends of a spring, damper or torque element: they must be able
    // to move relative to each other, or the element does nothing (its
    // energy would be reported all the same).
    let ends = |c: &Ctx| -> Result<(), SceneError> {
        let (Some(sa), Some(sb)) = (&r.a, &r.b) else {
            return Ok(());
        };
        let (ma, mb) = (b.marker_ref(sa)?, b.marker_ref(sb)?);
        let kind = q(r.kind.get_ref());
        let same = |why: String| {
            Err(c.err(
                sb.span(),
                format!(
                    "the `{kind}` force's ends `a` = `{}` and `b` = `{}` {why}: such a force does nothing (it would still report energy); give two ends that move relative to each other",
                    q(sa.get_ref()),
                    q(sb.get_ref())
                ),
            ))
        };
        let rigid_ends = |x: &MarkerRef| match x {
            MarkerRef::Origin(i) | MarkerRef::Point(i, _) => Some(*i),
            _ => None,
        };
        match (&ma, &mb) {
            (MarkerRef::Ground(_), MarkerRef::Ground(_)) => {
                same("are both fixed to the ground".into())
            }
            (MarkerRef::Axis(i, x), MarkerRef::Axis(j, y)) if i == j && x == y => {
                same(format!("are the same point of body `{}`", b.names[i.0]))
            }
            _ => match (rigid_ends(&ma), rigid_ends(&mb)) {
                (Some(i), Some(j)) if i == j => same(format!(
                    "are both fixed in the frame of body `{}`",
                    b.names[i.0]
                )),
                _ => Ok(()),
            },
        }
    };
    // Non-negative coefficients, checked here so that the message is located.
    let nonneg = |v: &Option<Spanned<f64>>, what: &str| -> Result<(), SceneError> {
        match v {
            Some(x) if *x.get_ref() < 0.0 => Err(c.err(
                x.span(),
                format!("`{what}` must be ≥ 0, found {:?}", x.get_ref()),
            )),
            _ => Ok(()),
        }
    };
    match r.kind.get_ref().as_str() {
        "spring-damper" => {
            nonneg(&r.stiffness, "stiffness")?;
            nonneg(&r.damping, "damping")?;
            nonneg(&r.rest_length, "rest_length")?;
        }
        "rotational-spring-damper" => {
            nonneg(&r.stiffness, "stiffness")?;
            nonneg(&r.damping, "damping")?;
        }
        _ => {}
    }
    match r.kind.get_ref().as_str() {
        "point" => {
            let at = need(c, f, &r.at, "at")?;
            if let MarkerRef::Ground(_) = b.marker_ref(at)? {
                return Err(c.err(
                    at.span(),
                    format!(
                        "a `point` force at the ground (`{}`) does nothing: put it on a body",
                        q(at.get_ref())
                    ),
                ));
            }
            let m = b.marker(sys, at)?;
            let fv = r.force.as_ref().ok_or_else(|| c.err(f.span(), "a `point` force needs `force = [Fx, Fy(, Fz)]` (N)"))?;
            let fv = vec_n(c, fv, b.dim, "force")?;
            let res = match r.axes.as_ref().map(|a| a.get_ref().as_str()) {
                None | Some("global") => sys.add_point_force(m, move |_| fv),
                Some("body") => sys.add_follower_force(m, move |_| fv),
                Some(other) => return Err(c.err(r.axes.as_ref().expect("some").span(), format!("`axes` is \"global\" or \"body\", found `{other}`", other = q(other)))),
            };
            res.map_err(|e| c.err(f.span(), e.to_string()))
        }
        "spring-damper" => {
            ends(c)?;
            let (a, bb) = (b.marker(sys, need(c, f, &r.a, "a")?)?, b.marker(sys, need(c, f, &r.b, "b")?)?);
            sys.add_spring_damper(a, bb, numr(&r.stiffness, "stiffness")?, r.damping.as_ref().map_or(Ok(0.0), |x| fin_f64(c, x, "damping"))?, numr(&r.rest_length, "rest_length")?)
                .map_err(|e| c.err(f.span(), e.to_string()))
        }
        "rotational-spring-damper" => {
            ends(c)?;
            let (a, bb) = (b.marker(sys, need(c, f, &r.a, "a")?)?, b.marker(sys, need(c, f, &r.b, "b")?)?);
            let law = TorqueLaw::SpringDamper {
                stiffness: numr(&r.stiffness, "stiffness")?,
                damping: r.damping.as_ref().map_or(Ok(0.0), |x| fin_f64(c, x, "damping"))?,
                rest_angle: r.rest_angle.as_ref().map_or(Ok(0.0), |x| fin_f64(c, x, "rest_angle"))?,
            };
            sys.add_torque(a, bb, law).map_err(|e| c.err(f.span(), e.to_string()))
        }
        "torque" => {
            ends(c)?;
            let (a, bb) = (b.marker(sys, need(c, f, &r.a, "a")?)?, b.marker(sys, need(c, f, &r.b, "b")?)?);
            let tau = numr(&r.torque, "torque")?;
            sys.add_torque(a, bb, TorqueLaw::Torque(Arc::new(move |_| tau))).map_err(|e| c.err(f.span(), e.to_string()))
        }
        other => Err(c.err(r.kind.span(), format!("unknown force kind `{other}`: expected point, spring-damper, rotational-spring-damper or torque", other = q(other)))),
    }
}

fn output(
    c: &Ctx,
    b: &Builder,
    sys: &System<Box<dyn Body>>,
    o: &RawOutput,
) -> Result<Output, SceneError> {
    let r = o;
    let name = r.name.get_ref().clone();
    if name.is_empty()
        || name
            .chars()
            .any(|ch| ch == ',' || ch == '"' || ch.is_control())
    {
        return Err(c.err(r.name.span(), "an output name must be non-empty without commas, quotes or control characters (it is a CSV column)"));
    }
    let comp = |dflt: Option<usize>| -> Result<usize, SceneError> {
        match &r.component {
            None => dflt.ok_or_else(|| {
                c.err(
                    o.span(),
                    format!(
                        "output `{}` needs `component = \"x\"`, `\"y\"`{}",
                        q(&name),
                        if b.dim == 3 { " or `\"z\"`" } else { "" }
                    ),
                )
            }),
            Some(s) => match s.get_ref().as_str() {
                "x" => Ok(0),
                "y" => Ok(1),
                "z" if b.dim == 3 => Ok(2),
                other => Err(c.err(
                    s.span(),
                    format!(
                        "`component` is x, y{} — found `{other}`",
                        if b.dim == 3 { " or z" } else { "" },
                        other = q(other)
                    ),
                )),
            },
        }
    };
    let at = || {
        r.at.as_ref().ok_or_else(|| {
            c.err(
                o.span(),
                format!("output `{}` needs `at = \"MARKER\"`", q(&name)),
            )
        })
    };
    let kind = match r.kind.get_ref().as_str() {
        "position" => OutputKind::Position(comp(None)?),
        "deflection" => OutputKind::Deflection(comp(None)?),
        "velocity" => OutputKind::Velocity(comp(None)?),
        "angle" => OutputKind::Angle,
        "energy" => {
            let part = match r.component.as_ref().map(|s| s.get_ref().as_str()) {
                None | Some("total") => EnergyPart::Total,
                Some("kinetic") => EnergyPart::Kinetic,
                Some("elastic") => EnergyPart::Elastic,
                Some("gravity") => EnergyPart::Gravity,
                Some("springs") => EnergyPart::Springs,
                Some("work") => EnergyPart::Work,
                Some("dissipated") => EnergyPart::Dissipated,
                Some(other) => return Err(c.err(r.component.as_ref().expect("some").span(), format!("energy `component` is total, kinetic, elastic, gravity, springs, work or dissipated — found `{other}`", other = q(other)))),
            };
            return Ok(Output { name, kind: OutputKind::Energy(part), marker: Marker::ground(Vector3::zeros()), relative_to: None });
        }
        other => return Err(c.err(r.kind.span(), format!("unknown output kind `{other}`: expected position, deflection, angle, velocity or energy", other = q(other)))),
    };
    let marker = b.marker(sys, at()?)?;
    if matches!(kind, OutputKind::Deflection(_)) && marker.body.is_none() {
        return Err(c.err(
            at()?.span(),
            "a deflection is measured on a body, not on the ground",
        ));
    }
    let relative_to = match &r.a {
        Some(a) if kind == OutputKind::Angle => Some(b.marker(sys, a)?),
        Some(a) => {
            return Err(c.err(
                a.span(),
                "`a` (a reference marker) is only for angle outputs",
            ))
        }
        None => None,
    };
    Ok(Output {
        name,
        kind,
        marker,
        relative_to,
    })
}

/// The scene files shipped with ffr (`scenes/`).
pub fn builtin_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

/// The modal reduction a flexible body's keys ask for (`modes`, `reduction`,
/// `boundary_nodes`, `static_modes`, `modal_damping`), with the span errors
/// about it point at; `None` without `modes`.
#[allow(clippy::type_complexity)]
fn modal_settings(
    c: &Ctx,
    name: &str,
    rb: &crate::codegen::scene::RawBody,
    elements: usize,
) -> Result<Option<(crate::modal::ModalSettings, std::ops::Range<usize>)>, SceneError> {
    let Some(modes) = &rb.modes else {
        for (key, span) in [
            ("reduction", rb.reduction.as_ref().map(|x| x.span())),
            (
                "boundary_nodes",
                rb.boundary_nodes.as_ref().map(|x| x.span()),
            ),
            ("static_modes", rb.static_modes.as_ref().map(|x| x.span())),
            ("modal_damping", rb.modal_damping.as_ref().map(|x| x.span())),
        ] {
            if let Some(span) = span {
                return Err(c.err(
                    span,
                    format!("body `{name}`: `{key}` needs `modes = K` (a modal body)"),
                ));
            }
        }
        return Ok(None);
    };
    let k = *modes.get_ref();
    if !(1..=4096).contains(&k) {
        return Err(c.err(
            modes.span(),
            format!("body `{name}`: `modes` must be a positive number of normal modes, found {k}"),
        ));
    }
    let cb = match rb
        .reduction
        .as_ref()
        .map(|r| (r.get_ref().as_str(), r.span()))
    {
        None | Some(("modal", _)) => false,
        Some(("craig-bampton", _)) => true,
        Some((other, span)) => {
            return Err(c.err(
                span,
                format!(
                    "body `{name}`: `reduction` is \"modal\" or \"craig-bampton\", found `{other}`",
                    other = q(other)
                ),
            ))
        }
    };
    let boundary = match (&rb.boundary_nodes, cb) {
        (Some(b), false) => {
            return Err(c.err(
                b.span(),
                format!("body `{name}`: `boundary_nodes` is for `reduction = \"craig-bampton\"`"),
            ))
        }
        (Some(b), true) => {
            let mut out = Vec::new();
            for &node in b.get_ref() {
                if !(0..=elements as i64).contains(&node) {
                    return Err(c.err(
                        b.span(),
                        format!("body `{name}`: boundary node {node} out of range: the body has nodes 0 to {elements}"),
                    ));
                }
                out.push(node as usize);
            }
            if out.is_empty() {
                return Err(c.err(
                    b.span(),
                    format!("body `{name}`: `boundary_nodes` is empty"),
                ));
            }
            out
        }
        (None, true) => vec![elements],
        (None, false) => Vec::new(),
    };
    let damping = match &rb.modal_damping {
        None => Vec::new(),
        Some(v) => {
            let num = |x: &toml::Value| x.as_float().or_else(|| x.as_integer().map(|i| i as f64));
            let zs: Option<Vec<f64>> = match v.get_ref() {
                toml::Value::Array(a) => a.iter().map(num).collect(),
                x => num(x).map(|z| vec![z]),
            };
            let zs = zs
                .filter(|zs| !zs.is_empty() && zs.iter().all(|z| z.is_finite() && *z >= 0.0))
                .ok_or_else(|| {
                    c.err(
                        v.span(),
                        format!("body `{name}`: `modal_damping` is a ratio ζ ≥ 0 for every normal mode, or a list of one per normal mode"),
                    )
                })?;
            zs
        }
    };
    Ok(Some((
        crate::modal::ModalSettings {
            modes: k as usize,
            boundary,
            static_modes: rb.static_modes.as_ref().is_none_or(|s| *s.get_ref()),
            damping,
        },
        modes.span(),
    )))
}
