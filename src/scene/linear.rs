//! Linear models and Campbell diagrams of scenes ([`crate::runtime::linear`]
//! does the mathematics).
//!
//! - Inputs by name: `jointN` (the `N`-th `[[joints]]` entry, 1-based, a
//!   revolute joint whose angle is not prescribed): a torque about the
//!   joint's axis on `b` (`−τ` on `a`), N m; `forceN` (the `N`-th
//!   `[[forces]]` entry): a point force's magnitude along its direction
//!   (global, or the body's for a follower force), N, or a torque's, N m.
//!   A point force with a `profile` `f(t)` is the same input, `u` along
//!   `force/|force|` whatever `f`: the model is about the force's value at
//!   the operating time, `f(T) force` (`f(0) force` for [`At::Static`]),
//!   which sets the operating state and, for a follower force, its load
//!   stiffness; the run's own force is `u(t) = f(t) |force|`;
//!   `driveN`: the acceleration (rad/s², m/s²) of a perturbation of joint
//!   `N`'s drive, whose angle (or slide) and rate become states.
//!   The scene's named inputs (`[[inputs]]`) by name: a `torque` input is
//!   its joint's `jointN`, a `drive-acceleration` input its joint's
//!   `driveN`, a `force` input the force along its `direction` as given
//!   (`∂Q/∂u`, not normalized).
//!   By default every joint with a motor, every point force and torque, and
//!   the named inputs.
//! - Outputs: the scene's `[[outputs]]` by name; by default all but the
//!   energies (which are not linear outputs).
//! - The state: the scene's at time `T` (run to `T` with its integrator,
//!   `T = 0` the consistent initial state), or its static equilibrium under
//!   its loads at `t = 0` ([`At::Static`]).
//! - Campbell diagrams: the driven revolute joint to the ground turns at
//!   constant rates; at each, the steady deformed state in the rotating
//!   frame (Newton on the residual) and the eigenvalues about it.

use crate::runtime::linear::{
    eigenvalues, linearize, linearize_with_inputs, steady_state_interruptible, InputLoad,
    LinearInput, LinearModel, LinearOutput, SteadyMotion,
};
use crate::runtime::nalgebra::{Complex, DMatrix, DVector, Vector3};
use crate::runtime::spec::scene::{
    BodyKind, ForceKind, JointKind, MarkerPoint, Orientation, ProfileSpec, SceneSpec,
};
use crate::runtime::spec::FrameModel;
use crate::runtime::{ForceAxes, ForceElement, Interrupt, State, TorqueLaw};
use crate::scene::model::{OutputKind, Scene};
use crate::scene::provider::KernelProvider;
use std::ops::ControlFlow;
use std::sync::Arc;

/// Where a scene is linearized.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum At {
    /// Its state at time `T` (s).
    Time(f64),
    /// Its static equilibrium under its loads at `t = 0`.
    Static,
}

/// The inputs a scene offers by default (names as in the module
/// documentation).
pub fn default_inputs(spec: &SceneSpec) -> Vec<String> {
    let mut out: Vec<String> = spec
        .joints
        .iter()
        .enumerate()
        .filter(|(_, j)| j.motor.is_some())
        .map(|(i, _)| format!("joint{}", i + 1))
        .collect();
    out.extend(
        spec.forces
            .iter()
            .enumerate()
            .filter(|(_, f)| matches!(f.kind, ForceKind::Point { .. } | ForceKind::Torque { .. }))
            .map(|(i, _)| format!("force{}", i + 1)),
    );
    out.extend(spec.inputs.iter().map(|i| i.name.clone()));
    out
}

/// The `jointN` or `driveN` name of a named torque or drive-acceleration
/// input, the name itself otherwise.
fn canonical<'a>(spec: &SceneSpec, name: &'a str) -> std::borrow::Cow<'a, str> {
    use crate::runtime::spec::scene::InputKind;
    match spec.inputs.iter().find(|i| i.name == name).map(|i| &i.kind) {
        Some(InputKind::Torque { joint }) => format!("joint{}", joint + 1).into(),
        Some(InputKind::DriveAcceleration { joint }) => format!("drive{}", joint + 1).into(),
        _ => name.into(),
    }
}

fn index_of(name: &str, prefix: &str) -> Option<usize> {
    name.strip_prefix(prefix)?
        .parse::<usize>()
        .ok()
        .filter(|&k| k >= 1)
}

/// The unit loads of the named inputs.
pub fn inputs(
    spec: &SceneSpec,
    scene: &Scene,
    names: &[String],
) -> crate::Result<Vec<LinearInput>> {
    let sys = &scene.system;
    let avail = || default_inputs(spec).join(", ");
    let mut out = Vec::new();
    for given in names {
        let name = &*canonical(spec, given);
        // User text in messages: escaped and cut.
        let qn = crate::runtime::spec::text::quoted(given);
        let named_force = spec.inputs.iter().find_map(|i| match &i.kind {
            crate::runtime::spec::scene::InputKind::Force {
                at,
                direction,
                follower,
            } if i.name == *given => Some((at, *direction, *follower)),
            _ => None,
        });
        let load = if let Some((at, direction, follower)) = named_force {
            let d = Vector3::from(direction);
            InputLoad::Force(Box::new(ForceElement::Point {
                marker: super::build::marker(sys, at)?,
                force: Arc::new(move |_| d),
                axes: if follower {
                    ForceAxes::Marker
                } else {
                    ForceAxes::Global
                },
            }))
        } else if let Some(k) = index_of(name, "drive") {
            let j = spec.joints.get(k - 1).ok_or_else(|| {
                format!("input `{qn}`: the scene has {} joints", spec.joints.len())
            })?;
            if j.drive.is_none() {
                return Err(format!("input `{qn}`: joint {k} ({}) has no drive", j.b.text).into());
            }
            let constraint = drive_constraint(spec, k - 1).ok_or_else(|| {
                format!(
                    "input `{qn}`: joint {k}'s drive is folded into prescribed coordinates; linearize the scene through `linearize_scene`, which unfolds it"
                )
            })?;
            InputLoad::Drive { constraint }
        } else if let Some(k) = index_of(name, "joint") {
            let j = spec.joints.get(k - 1).ok_or_else(|| {
                format!("input `{qn}`: the scene has {} joints", spec.joints.len())
            })?;
            if j.kind != JointKind::Revolute || j.folds.is_some() || j.drive.is_some() {
                return Err(format!(
                    "input `{qn}`: joint {k} ({}) is {}: a torque input needs a revolute joint whose angle is free",
                    j.b.text,
                    if j.kind != JointKind::Revolute { "not revolute" } else { "driven (its angle is prescribed)" }
                )
                .into());
            }
            let a = j.a.as_ref().ok_or("a revolute joint has two markers")?;
            InputLoad::Force(Box::new(ForceElement::Torque {
                a: super::build::marker(sys, a)?,
                b: super::build::marker(sys, &j.b)?,
                law: TorqueLaw::Torque(Arc::new(|_| 1.0)),
            }))
        } else if let Some(k) = index_of(name, "force") {
            let f = spec.forces.get(k - 1).ok_or_else(|| {
                format!("input `{qn}`: the scene has {} forces", spec.forces.len())
            })?;
            InputLoad::Force(Box::new(match &f.kind {
                // A profiled force's input is the same: an added force
                // along `force`; the profile's value at the operating time
                // is part of the operating point (module documentation).
                ForceKind::Point {
                    at,
                    force,
                    follower,
                    ..
                } => {
                    let dir = Vector3::from(*force);
                    let norm = dir.norm();
                    if !(norm > 0.0) {
                        return Err(format!(
                            "input `{qn}`: force {k} is zero and has no direction"
                        )
                        .into());
                    }
                    let unit = dir / norm;
                    ForceElement::Point {
                        marker: super::build::marker(sys, at)?,
                        force: Arc::new(move |_| unit),
                        axes: if *follower {
                            ForceAxes::Marker
                        } else {
                            ForceAxes::Global
                        },
                    }
                }
                ForceKind::Torque { a, b, .. } => ForceElement::Torque {
                    a: super::build::marker(sys, a)?,
                    b: super::build::marker(sys, b)?,
                    law: TorqueLaw::Torque(Arc::new(|_| 1.0)),
                },
                _ => {
                    return Err(format!(
                    "input `{qn}`: force {k} is a spring–damper, part of the system, not an input"
                )
                    .into())
                }
            }))
        } else {
            return Err(format!(
                "unknown input `{qn}`: inputs are the scene's [[inputs]] by name, `jointN` (a torque in revolute joint N), `forceN` (the amplitude of force N) and `driveN` (the acceleration of joint N's drive); this scene's defaults are: {}",
                avail()
            )
            .into());
        };
        out.push(LinearInput {
            name: given.clone(),
            load,
        });
    }
    Ok(out)
}

/// The system constraint of joint `ji`'s drive (0-based in `[[joints]]`),
/// as the builder adds them: first the cut joints of segmented bodies
/// (one per cut), then per joint: a ground or folded joint none, any other
/// its own and then its drive's.
fn drive_constraint(spec: &SceneSpec, ji: usize) -> Option<usize> {
    let mut c: usize = spec
        .bodies
        .iter()
        .map(|b| match &b.kind {
            BodyKind::Flexible(f) => f.segments.saturating_sub(1),
            _ => 0,
        })
        .sum();
    for (i, j) in spec.joints.iter().enumerate() {
        if j.kind == JointKind::Ground || j.folds.is_some() {
            if i == ji {
                return None;
            }
            continue;
        }
        if i == ji {
            return j.drive.as_ref().map(|_| c + 1);
        }
        c += 1 + usize::from(j.drive.is_some());
    }
    None
}

/// The outputs a scene offers by default: every output but the energies.
pub fn default_outputs(scene: &Scene) -> Vec<String> {
    scene
        .outputs
        .iter()
        .filter(|o| !matches!(o.kind, OutputKind::Energy(_)))
        .map(|o| o.name.clone())
        .collect()
}

/// The named outputs.
pub fn outputs(scene: &Scene, names: &[String]) -> crate::Result<Vec<LinearOutput>> {
    names
        .iter()
        .map(|name| {
            let qn = crate::runtime::spec::text::quoted(name);
            let o = scene.outputs.iter().find(|o| &o.name == name).ok_or_else(|| {
                format!(
                    "unknown output `{qn}`: the scene's linear outputs are: {}",
                    default_outputs(scene).join(", ")
                )
            })?;
            if matches!(o.kind, OutputKind::Energy(_)) {
                return Err(format!(
                    "output `{qn}` is an energy, not a linear output (positions, velocities, deflections and angles are)"
                )
                .into());
            }
            Ok(LinearOutput {
                name: o.name.clone(),
                kind: o.kind,
                marker: o.marker.clone(),
                relative_to: o.relative_to.clone(),
            })
        })
        .collect()
}

/// The shortest positive operating time, in steps `dt` of the scene: a
/// time run to `T` takes one step of `T` when `T < dt`, and a step much
/// shorter than the scene's makes an iteration matrix `∝ 1/T²` that no
/// longer represents the dynamics (below about `10⁻¹⁵⁴ s` it overflows);
/// the state at such a time is the initial state to within `T/dt` of one
/// step's motion: `--at 0`.
pub const MIN_OPERATING_TIME_IN_STEPS: f64 = 1e-12;

/// The scene's state at `at`, checked by the validity check every state
/// passes ([`crate::runtime::monitor::check_state`]: finite, each flexible
/// body deformed by less than its size, finite energy): the static
/// equilibrium (checked by its solver), the initial state (`T = 0`) or the
/// state a time run reaches at `T` (its divergence monitor on, the last
/// state checked). A time `0 < T <` [`MIN_OPERATING_TIME_IN_STEPS`] `× dt`
/// is refused (use `T = 0`).
pub fn operating_state(scene: &Scene, at: At) -> crate::Result<State> {
    operating_state_interruptible(scene, at, Interrupt::NEVER)
}

/// [`operating_state`], polling `interrupt` after every step of the run to
/// `T` or Newton iteration of the static solver
/// ([`crate::runtime::Error::Interrupted`] when it asks to stop).
pub fn operating_state_interruptible(
    scene: &Scene,
    at: At,
    interrupt: Interrupt<'_>,
) -> crate::Result<State> {
    let sys = &scene.system;
    let checked = |state: State, what: String| -> crate::Result<State> {
        match crate::runtime::monitor::check_state(sys, &state.q, &state.v) {
            Ok(()) => Ok(state),
            Err(why) => {
                Err(format!("{what} is not valid: {why}; no linear model is taken about it").into())
            }
        }
    };
    match at {
        At::Static => {
            // The solver of `ffr static` (automatic load stepping), which
            // applies the validity check to the equilibrium it reaches.
            let start = sys.initial_state(0.0)?;
            Ok(crate::runtime::statics::equilibrium_interruptible(
                sys,
                0.0,
                &start,
                SteadyMotion::Rest,
                &crate::runtime::statics::StaticOptions::default(),
                interrupt,
            )?
            .state)
        }
        At::Time(t) if !(t.is_finite() && t >= 0.0) => {
            Err(format!("--at {}: a time must be finite and ≥ 0", short(t)).into())
        }
        At::Time(0.0) => checked(sys.initial_state(0.0)?, "the initial state".into()),
        At::Time(t) if t < MIN_OPERATING_TIME_IN_STEPS * scene.dt => Err(format!(
            "--at {}: a time below {MIN_OPERATING_TIME_IN_STEPS:e} × the scene's step dt = {} s is the initial state to within round-off (and a step that short is not one the integrator can take): use --at 0 for the initial state, or a time of at least {} s",
            short(t),
            short(scene.dt),
            short(MIN_OPERATING_TIME_IN_STEPS * scene.dt)
        )
        .into()),
        At::Time(t) if !scene.inputs.is_empty() => {
            Ok(operating_point(scene, t, interrupt)?.0).and_then(|s| {
                checked(s, format!("the state at t = {} s", short(t)))
            })
        }
        At::Time(t) => {
            let s = sys.simulate(t, scene.dt.min(t), &scene.integrator, |_| {
                if interrupt.requested() {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            })?;
            if s.stopped {
                return Err(crate::runtime::Error::Interrupted.into());
            }
            checked(s.last, format!("the state at t = {} s", short(t)))
        }
    }
}

/// The state of a scene with inputs at time `t` (a run to `t` with step
/// `min(dt, t)`, the inputs' profiles applied as `ffr run` applies them),
/// and its inputs' values and drive perturbations there (a profile's value
/// at `t`, where the next step would start).
#[allow(clippy::type_complexity)]
fn operating_point(
    scene: &Scene,
    t: f64,
    interrupt: Interrupt<'_>,
) -> crate::Result<(State, Vec<f64>, Vec<[f64; 3]>)> {
    use crate::runtime::integrator::{step_count, step_length};
    let dt = scene.dt.min(t);
    crate::runtime::integrator::check_settings(t, dt, &scene.integrator)?;
    let mut s = super::simulation::Stepping::new(scene)?;
    for _ in 0..step_count(t, dt)? {
        s.step(step_length(s.stepper().state().t, t, dt))?;
        interrupt.check()?;
    }
    let st = s.stepper();
    let values = scene
        .inputs
        .iter()
        .enumerate()
        .map(|(k, i)| match &i.profile {
            Some(p) => p(st.state().t),
            None => st.inputs()[k],
        })
        .collect();
    Ok((st.state().clone(), values, st.drive_states().to_vec()))
}

/// Linearize the scene `spec` at `at` with the named inputs and outputs
/// (`None`: the defaults), its flexible bodies' kernels from `provider`. A
/// drive input on a joint the reader folded into prescribed coordinates
/// (a revolute joint to the ground at a body's frame origin) unfolds it
/// into a revolute joint and a driving constraint, whose driver the input
/// perturbs (the same motion, the same eigenvalues, two more states).
pub fn linearize_scene(
    spec: &SceneSpec,
    provider: &dyn KernelProvider,
    at: At,
    input_names: Option<&[String]>,
    output_names: Option<&[String]>,
) -> crate::Result<LinearModel> {
    linearize_scene_interruptible(
        spec,
        provider,
        at,
        input_names,
        output_names,
        Interrupt::NEVER,
    )
}

/// [`linearize_scene`], polling `interrupt` while it finds the operating
/// state ([`operating_state_interruptible`]).
pub fn linearize_scene_interruptible(
    spec: &SceneSpec,
    provider: &dyn KernelProvider,
    at: At,
    input_names: Option<&[String]>,
    output_names: Option<&[String]>,
    interrupt: Interrupt<'_>,
) -> crate::Result<LinearModel> {
    let default_in = default_inputs(spec);
    let names = input_names.unwrap_or(&default_in);
    let mut spec = spec.clone();
    for n in names {
        if let Some(k) = index_of(&canonical(&spec, n), "drive") {
            let Some(j) = spec.joints.get_mut(k - 1) else {
                continue;
            };
            if let (Some(b), Some(_)) = (j.folds, &j.drive) {
                j.folds = None;
                // The body's frame is free now: the general kernels.
                if let BodyKind::Flexible(f) = &mut spec.bodies[b].kind {
                    f.options.frame = FrameModel::Free;
                }
            }
        }
    }
    let scene = super::build(&spec, provider)?;
    let ins = inputs(&spec, &scene, names)?;
    let outs = match output_names {
        Some(n) => outputs(&scene, n)?,
        None => outputs(&scene, &default_outputs(&scene))?,
    };
    // Refuse a model too large to hold densely before the run to `T`.
    let drives = ins
        .iter()
        .filter(|i| matches!(i.load, InputLoad::Drive { .. }))
        .count();
    crate::runtime::linear::check_dense_size(&scene.system, drives)?;
    let (state, values) = match at {
        At::Time(t)
            if !scene.inputs.is_empty()
                && t.is_finite()
                && t >= MIN_OPERATING_TIME_IN_STEPS * scene.dt =>
        {
            let (s, u, d) = operating_point(&scene, t, interrupt)?;
            let what = format!("the state at t = {} s", short(t));
            if let Err(why) = crate::runtime::monitor::check_state(&scene.system, &s.q, &s.v) {
                return Err(format!(
                    "{what} is not valid: {why}; no linear model is taken about it"
                )
                .into());
            }
            (s, Some((u, d)))
        }
        _ => (operating_state_interruptible(&scene, at, interrupt)?, None),
    };
    interrupt.check()?;
    let values = values.as_ref().map(|(u, d)| (u.as_slice(), d.as_slice()));
    Ok(linearize_with_inputs(
        &scene.system,
        &state,
        &ins,
        &outs,
        values,
    )?)
}

/// One mode of a Campbell diagram.
#[derive(Clone, Debug, PartialEq)]
pub struct CampbellMode {
    /// `|λ|` (rad/s).
    pub omega: f64,
    /// `|λ|/2π` (Hz).
    pub hz: f64,
    /// Damping ratio `−Re λ/|λ|`.
    pub zeta: f64,
    /// The dominant motion: `flap` (out of the plane of rotation, body z),
    /// `lag` (in the plane, body y), `axial`, `torsion`, `rigid` (a frame
    /// coordinate), or the coordinate's own label.
    pub label: String,
    /// The eigenvector in the system's coordinates: `(index, value)` of each
    /// free coordinate (largest entry of the independent coordinates'
    /// vector 1; phase arbitrary).
    pub vector: Vec<(usize, Complex<f64>)>,
}

/// The kind of motion of a coordinate label (`blade.uz_3` → `flap`).
fn motion_kind(label: &str) -> String {
    let tail = label.rsplit('.').next().unwrap_or(label);
    let kind = tail.split('_').next().unwrap_or(tail);
    match kind {
        "ux" => "axial",
        "uy" | "rz" => "lag",
        "uz" | "ry" => "flap",
        "rx" => "torsion",
        "x" | "y" | "z" | "theta" | "e0" | "e1" | "e2" | "e3" => "rigid",
        other => other,
    }
    .to_string()
}

/// The modes of a linear model, one per oscillating pair (and each real
/// eigenvalue), lowest `|λ|` first, at most `count`, labelled by the
/// kinetic-energy participation `Re(q̄_i (M q)_i)` of each coordinate kind
/// in the eigenvector (inverse iteration on `λ²M̂ + λĈ + K̂`; the modes of
/// a repeated eigenvalue `M̂`-orthogonal to each other).
pub fn modes(
    sys_labels: &[String],
    model: &LinearModel,
    count: usize,
) -> crate::Result<Vec<CampbellMode>> {
    let ev = eigenvalues(&model.a)?;
    let nz = model.independent.len();
    let mut out = Vec::new();
    // The eigenvectors of the current cluster of equal eigenvalues (a double
    // frequency: each vector is kept M̂-orthogonal to the earlier ones, so
    // that the two modes of a pair get their two motions).
    let mut cluster: Vec<(Complex<f64>, DVector<Complex<f64>>)> = Vec::new();
    for l in ev {
        if out.len() >= count {
            break;
        }
        let w = l.norm();
        if l.im < -1e-9 * w {
            continue; // the conjugate of a pair
        }
        cluster.retain(|(m, _)| (m - l).norm() <= 1e-6 * (1.0 + w));
        let (label, z) = mode_label(sys_labels, model, nz, l, &cluster);
        let vector = if nz == 0 {
            Vec::new()
        } else {
            let qv = model.basis.map(|x| Complex::new(x, 0.0)) * &z;
            model
                .parts
                .free
                .iter()
                .enumerate()
                .map(|(i, &g)| (g, qv[i]))
                .collect()
        };
        cluster.push((l, z));
        out.push(CampbellMode {
            omega: w,
            hz: w / std::f64::consts::TAU,
            zeta: if w > 0.0 { -l.re / w } else { 0.0 },
            label,
            vector,
        });
    }
    Ok(out)
}

/// The label of the mode of eigenvalue `l` and its vector `z` (independent
/// coordinates), by inverse iteration on `λ²M̂ + λĈ + K̂`, orthogonal (in
/// `M̂`) to the vectors `prev` of the same eigenvalue.
fn mode_label(
    labels: &[String],
    model: &LinearModel,
    nz: usize,
    l: Complex<f64>,
    prev: &[(Complex<f64>, DVector<Complex<f64>>)],
) -> (String, DVector<Complex<f64>>) {
    let c = |x: f64| Complex::new(x, 0.0);
    if nz == 0 {
        return (String::new(), DVector::zeros(0));
    }
    let mh = model.m_hat.map(c);
    let deflate = |z: &mut DVector<Complex<f64>>| {
        for (_, v) in prev {
            let mv = &mh * v;
            let num = mv.dotc(z);
            let den = mv.dotc(v);
            if den.norm() > 0.0 {
                *z -= v * (num / den);
            }
        }
    };
    // P(λ) shifted by a little so that it factors; three inverse iterations.
    let s = l + Complex::new(1e-9 * (1.0 + l.norm()), 1e-9 * (1.0 + l.norm()));
    let p = DMatrix::from_fn(nz, nz, |i, j| {
        s * s * c(model.m_hat[(i, j)]) + s * c(model.c_hat[(i, j)]) + c(model.k_hat[(i, j)])
    });
    let lu = p.lu();
    let mut z = DVector::from_fn(nz, |i, _| Complex::new(1.0 + 0.1 * (i as f64).sin(), 0.0));
    deflate(&mut z);
    for _ in 0..3 {
        match lu.solve(&z) {
            Some(mut x) => {
                deflate(&mut x);
                let n = x.iter().map(|v| v.norm()).fold(0.0, f64::max);
                if !(n > 0.0) || !n.is_finite() {
                    break;
                }
                z = x / c(n);
            }
            None => break,
        }
    }
    let nb = model.basis.map(c);
    let qv = &nb * &z;
    let mq = model.parts.m.map(c) * &qv;
    let mut sums: Vec<(String, f64)> = Vec::new();
    for (i, &g) in model.parts.free.iter().enumerate() {
        let e = (qv[i].conj() * mq[i]).re.abs();
        let k = motion_kind(&labels[g]);
        match sums.iter_mut().find(|(n, _)| *n == k) {
            Some((_, s)) => *s += e,
            None => sums.push((k, e)),
        }
    }
    let label = sums
        .into_iter()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(k, _)| k)
        .unwrap_or_default();
    (label, z)
}

/// A Campbell diagram: per speed, the lowest `count` modes.
#[derive(Clone, Debug, PartialEq)]
pub struct Campbell {
    /// The speeds `Ω` (rad/s).
    pub speeds: Vec<f64>,
    /// The joint (0-based index in `[[joints]]`) that turns.
    pub joint: usize,
    /// Per speed, the modes, lowest first.
    pub modes: Vec<Vec<CampbellMode>>,
    /// What the diagram may not show ([`stiffening_warnings`]: a flexible
    /// body turning with the joint without geometric stiffening), one
    /// sentence each, located at the body's table.
    pub warnings: Vec<String>,
}

/// The bodies that turn with joint `ji` (0-based in `[[joints]]`): its
/// body `b` and every body joined to one of them by another joint (the
/// ground excluded), by index in `[[bodies]]`.
fn turning_bodies(spec: &SceneSpec, ji: usize) -> Vec<usize> {
    let body = |m: &crate::runtime::spec::scene::MarkerSpec| match m.point {
        MarkerPoint::Ground(_) => None,
        MarkerPoint::Origin(b)
        | MarkerPoint::Axis(b, _)
        | MarkerPoint::Point(b, _)
        | MarkerPoint::Node(b, _) => Some(b),
    };
    let mut set: Vec<usize> = body(&spec.joints[ji].b).into_iter().collect();
    loop {
        let before = set.len();
        for (k, j) in spec.joints.iter().enumerate() {
            if k == ji {
                continue;
            }
            let (a, b) = (j.a.as_ref().and_then(body), body(&j.b));
            for (x, y) in [(a, b), (b, a)] {
                if let (Some(x), Some(y)) = (x, y) {
                    if set.contains(&x) && !set.contains(&y) {
                        set.push(y);
                    }
                }
            }
        }
        if set.len() == before {
            break;
        }
    }
    set.sort_unstable();
    set
}

/// Warnings for a Campbell diagram turning joint `ji` (0-based): each
/// flexible body that turns with it (joined to its body, `turning_bodies`)
/// without geometric stiffening, whose bending frequencies then cannot
/// rise with the speed (no centrifugal stiffening, only spin softening):
/// located at the body's table, saying what to do (`stiffening = true`;
/// an FE body has none, being linear elastic from `M` and `K`).
pub fn stiffening_warnings(spec: &SceneSpec, ji: usize) -> Vec<String> {
    use crate::runtime::spec::Stiffening;
    let mut out = Vec::new();
    for b in turning_bodies(spec, ji) {
        let body = &spec.bodies[b];
        let q = crate::runtime::spec::text::quoted(&body.name);
        match &body.kind {
            BodyKind::Flexible(f) if f.options.stiffening == Stiffening::Off => out.push(format!(
                "{}: body `{q}` turns with joint {} but has no geometric stiffening, so its bending (flap and lag) frequencies cannot rise with the speed (only spin softening is modelled): set `stiffening = true` in [bodies.{q}]",
                body.at,
                ji + 1
            )),
            BodyKind::Fe(_) => out.push(format!(
                "{}: FE body `{q}` turns with joint {} but has no geometric stiffening (it is not available from M and K alone), so its bending frequencies cannot rise with the speed: model it as a beam with `stiffening = true` to see them rise",
                body.at,
                ji + 1
            )),
            _ => {}
        }
    }
    out
}

/// The Campbell diagram of the scene `spec`: for each speed `Ω` the driven
/// revolute joint to the ground (`joint`, 0-based in `[[joints]]`, or the
/// first) turns at the constant rate `Ω` (its drive replaced); the steady
/// state of the rotating system at `t = 0` (rigid rotation about the
/// joint's axis, global z through its ground point; elastic coordinates
/// steady), found by Newton from the undeformed state; the eigenvalues of
/// the linear model about it.
pub fn campbell(
    spec: &SceneSpec,
    provider: &dyn KernelProvider,
    speeds: &[f64],
    joint: Option<usize>,
    count: usize,
) -> crate::Result<Campbell> {
    campbell_with(spec, provider, speeds, joint, count, &mut |_, _, _, _| {
        Ok(())
    })
}

/// A mode whose damping ratio is below this is growing (undamped modes
/// come out at `|ζ| ≈ 10⁻¹⁶`).
const GROWING_ZETA: f64 = -1e-6;

/// At most this many growing modes are named in one warning (the rest
/// counted).
const NAMED_GROWING: usize = 4;

/// A number in short form: `{:?}` (shortest round trip) between 10⁻³ and
/// 10⁶, else `{:e}` (`1e15`, not `1000000000000000.0`).
fn short(x: f64) -> String {
    if x == 0.0 || (1e-3..1e6).contains(&x.abs()) || !x.is_finite() {
        format!("{x:?}")
    } else {
        format!("{x:e}")
    }
}

/// The warning of a Campbell speed `w` whose `modes` include growing ones:
/// `ζ = −1` (a real eigenvalue `λ > 0`: a divergence, the two eigenvalues
/// of a pair that spin softening has brought through zero frequency, as
/// for a body without stiffening or an FE body) or `−1 < ζ < 0` (a
/// flutter: an oscillation that grows). Eigenvalues at round-off of zero
/// (below `10⁻⁹` of the speed and of the largest `|λ|` listed) are not
/// counted.
pub fn divergence_warning(w: f64, modes: &[CampbellMode]) -> Option<String> {
    let scale = modes
        .iter()
        .map(|m| m.omega)
        .fold(w.abs().max(1.0), f64::max);
    let growing: Vec<String> = modes
        .iter()
        .enumerate()
        .filter(|(_, m)| m.zeta < GROWING_ZETA && m.omega > 1e-9 * scale)
        .map(|(k, m)| {
            let kind = if m.zeta <= -1.0 + 1e-9 {
                "divergent"
            } else {
                "flutter"
            };
            format!(
                "mode {} ({}, |λ| = {:.4e} rad/s, ζ = {:.3e}, {kind})",
                k + 1,
                crate::runtime::spec::text::quoted(&m.label),
                m.omega,
                m.zeta
            )
        })
        .collect();
    if growing.is_empty() {
        return None;
    }
    let count = growing.len();
    let mut named = growing[..count.min(NAMED_GROWING)].join(", ");
    if count > NAMED_GROWING {
        named.push_str(&format!(" and {} more", count - NAMED_GROWING));
    }
    let (verb, tail) = if growing.len() == 1 {
        ("grows", "its frequency is not a vibration of the rotor")
    } else {
        ("grow", "their frequencies are not vibrations of the rotor")
    };
    Some(format!(
        "Ω = {} rad/s: the steady rotation is unstable: {named} {verb} (ζ = −1: a real eigenvalue λ > 0, one of a divergent pair — a frequency that spin softening brought through zero, as for a body without geometric stiffening or an FE body; −1 < ζ < 0: an oscillation that grows); {tail}",
        short(w)
    ))
}

/// Refuse a Campbell diagram of joint `ji` (0-based) whose turning bodies
/// (`turning_bodies`) include one held to the ground by another joint: such
/// a body cannot turn rigidly with the rotor (the slider of a slider-crank
/// on its prismatic joint), so there is no steady rotating state. A second
/// revolute joint to the ground on the rotor's own axis (a bearing:
/// ground point on the axis, axes about z only) is allowed.
fn held_to_ground(spec: &SceneSpec, ji: usize) -> crate::Result<()> {
    let turning = turning_bodies(spec, ji);
    let driven = &spec.joints[ji];
    let axis = match driven.a.as_ref().map(|a| a.point) {
        Some(MarkerPoint::Ground(p)) => p,
        _ => return Ok(()),
    };
    let body_of = |m: &crate::runtime::spec::scene::MarkerSpec| match m.point {
        MarkerPoint::Ground(_) => None,
        MarkerPoint::Origin(b)
        | MarkerPoint::Axis(b, _)
        | MarkerPoint::Point(b, _)
        | MarkerPoint::Node(b, _) => Some(b),
    };
    for (k, j) in spec.joints.iter().enumerate() {
        if k == ji {
            continue;
        }
        let ground = match &j.a {
            None => Some(axis).filter(|_| j.kind == JointKind::Ground),
            Some(a) => match a.point {
                MarkerPoint::Ground(p) => Some(p),
                _ => None,
            },
        };
        let (Some(p), Some(b)) = (ground, body_of(&j.b)) else {
            continue;
        };
        if !turning.contains(&b) {
            continue;
        }
        let bearing = j.kind == JointKind::Revolute
            && p[0] == axis[0]
            && p[1] == axis[1]
            && j.a.as_ref().and_then(|a| a.axes).is_none();
        if bearing {
            continue;
        }
        let name = crate::runtime::spec::text::quoted(&spec.bodies[b].name);
        return Err(crate::SceneError {
            location: Some(j.at.clone()),
            message: format!(
                "joint {} (a {} joint of body `{name}` to the ground) holds a body that turns with joint {} (joined to its rotor through the other joints), so it cannot turn rigidly with it: the scene has no steady rotating state to linearize about; a Campbell diagram needs a rotor whose bodies are joined to the ground only by the driven joint",
                k + 1,
                j.kind.name(),
                ji + 1
            ),
        }
        .into());
    }
    Ok(())
}

/// The joint a Campbell diagram turns: `joint` (0-based in `[[joints]]`),
/// which must be a revolute joint with a drive, or the first such joint;
/// a scene with a body that turns with it but is held to the ground by
/// another joint (no steady rotating state) is refused.
pub fn campbell_joint(spec: &SceneSpec, joint: Option<usize>) -> crate::Result<usize> {
    let driven = |j: &crate::runtime::spec::scene::JointSpec| {
        j.kind == JointKind::Revolute && j.drive.is_some()
    };
    let ji = match joint {
        Some(k) => {
            let j = spec.joints.get(k).ok_or_else(|| {
                format!("--joint {}: the scene has {} joints", k + 1, spec.joints.len())
            })?;
            if !driven(j) {
                return Err(format!(
                    "--joint {}: joint {} ({}) is not a revolute joint with a drive",
                    k + 1,
                    k + 1,
                    j.b.text
                )
                .into());
            }
            k
        }
        None => spec.joints.iter().position(driven).ok_or(
            "the scene has no revolute joint with a drive: a Campbell diagram turns one at constant speeds",
        )?,
    };
    held_to_ground(spec, ji)?;
    Ok(ji)
}

/// What [`campbell_with`] calls at each speed: its index, the scene built
/// at that speed, the steady state, the modes.
pub type EachSpeed<'a> =
    dyn FnMut(usize, &super::Scene, &State, &[CampbellMode]) -> crate::Result<()> + 'a;

/// [`campbell`], calling `each(i, scene, steady state, modes)` for the
/// `i`-th speed (0-based) after its modes are found (e.g. to write their
/// animations, [`super::vtk::write_linear_modes`]).
pub fn campbell_with(
    spec: &SceneSpec,
    provider: &dyn KernelProvider,
    speeds: &[f64],
    joint: Option<usize>,
    count: usize,
    each: &mut EachSpeed<'_>,
) -> crate::Result<Campbell> {
    campbell_interruptible(spec, provider, speeds, joint, count, each, Interrupt::NEVER)
}

/// [`campbell_with`], polling `interrupt` at every speed and every Newton
/// iteration of its steady state ([`crate::runtime::Error::Interrupted`]
/// when it asks to stop).
pub fn campbell_interruptible(
    spec: &SceneSpec,
    provider: &dyn KernelProvider,
    speeds: &[f64],
    joint: Option<usize>,
    count: usize,
    each: &mut EachSpeed<'_>,
    interrupt: Interrupt<'_>,
) -> crate::Result<Campbell> {
    let ji = campbell_joint(spec, joint)?;
    let j = &spec.joints[ji];
    let center = match j.a.as_ref().map(|a| a.point) {
        Some(MarkerPoint::Ground(p)) => p,
        _ => {
            return Err(format!(
                "joint {} ({}): a Campbell diagram needs the driven joint between the ground (`a = \"ground@[…]\"`) and a body",
                ji + 1,
                j.b.text
            )
            .into())
        }
    };
    // The rotor turns about `a`'s z axis: marker axes of its own must keep
    // it on global z (the steady rotation is about global z).
    if let Some(Orientation::AxisAngle { axis, angle }) = j.a.as_ref().and_then(|a| a.axes) {
        let n = Vector3::from(axis).normalize();
        let z = Vector3::z();
        // Rodrigues: R e_z = cos φ e_z + sin φ (n × e_z) + (1 − cos φ) n_z n.
        let rz = z * angle.cos() + n.cross(&z) * angle.sin() + n * (n.z * (1.0 - angle.cos()));
        if (rz - z).norm() > 1e-12 {
            return Err(format!(
                "joint {} ({}): a Campbell diagram turns the rotor about global z, and marker `a` = `{}` has axes whose z is [{:.3e}, {:.3e}, {:.3e}]: turn them about z only",
                ji + 1,
                j.b.text,
                crate::runtime::spec::text::quoted(j.a.as_ref().map_or("", |a| a.text.as_str())),
                rz.x,
                rz.y,
                rz.z
            )
            .into());
        }
    }
    if let Some((g, gat)) = &spec.gravity {
        if g[0] != 0.0 || g[1] != 0.0 {
            return Err(crate::SceneError {
                location: Some(gat.clone()),
                message: format!(
                    "gravity {g:?} is not along the rotation axis (global z): it turns with the rotor in the rotating frame, so there is no steady state to linearize about"
                ),
            }
            .into());
        }
    }
    let (profile, at) = j.drive.clone().expect("driven");
    let start = match profile {
        ProfileSpec::SpinUp { start, .. }
        | ProfileSpec::ConstantRate { start, .. }
        | ProfileSpec::Harmonic { start, .. } => start,
        ProfileSpec::Constant(v) => v,
    };
    let mut warnings = stiffening_warnings(spec, ji);
    if let Some(w) = speeds.iter().find(|w| !w.is_finite()) {
        return Err(format!("--speeds: {w} is not a finite rate").into());
    }
    let mut modes = Vec::with_capacity(speeds.len());
    for (i, &w) in speeds.iter().enumerate() {
        interrupt.check()?;
        let mut s = spec.clone();
        s.joints[ji].drive = Some((ProfileSpec::ConstantRate { start, rate: w }, at.clone()));
        let scene = super::build(&s, provider)?;
        let sys = &scene.system;
        let at_speed = |e: &dyn std::fmt::Display| format!("Ω = {} rad/s: {e}", short(w));
        crate::runtime::linear::check_dense_size(sys, 0).map_err(|e| at_speed(&e))?;
        let init = sys.initial_state(0.0).map_err(|e| at_speed(&e))?;
        // The steady state passes the validity check in its solver
        // (`crate::runtime::monitor::check_state`).
        let state = steady_state_interruptible(
            sys,
            0.0,
            &init,
            SteadyMotion::Rotation { center, omega: w },
            interrupt,
        )
        .map_err(|e| match e {
            crate::runtime::Error::Interrupted => crate::Error::from(e),
            e => at_speed(&e).into(),
        })?;
        let model = linearize(sys, &state, &[], &[]).map_err(|e| at_speed(&e))?;
        let labels = crate::runtime::linear::coordinate_labels(sys);
        let m = self::modes(&labels, &model, count).map_err(|e| at_speed(&e))?;
        if let Some(d) = divergence_warning(w, &m) {
            warnings.push(d);
        }
        each(i, &scene, &state, &m)?;
        modes.push(m);
    }
    Ok(Campbell {
        speeds: speeds.to_vec(),
        joint: ji,
        modes,
        warnings,
    })
}
