//! The spin-up beam of Kane, Ryan & Banerjee (1987): a cantilever clamped
//! to a hub whose angle is prescribed,
//! `θ(t) = (ω_s/T)(t²/2 + (T/2π)²(cos(2πt/T) − 1))` for `t < T`,
//! `ω_s (t − T/2)` after (theory: `docs/theory.md`).
//!
//! Planar: a beam2 body in a planar scene, frame origin fixed, frame angle
//! `θ(t)`. Spatial: a beam3 body in a spatial scene, its Euler parameters
//! prescribed as the rotation `θ(t)` about global z. In both the frame motion
//! is prescribed, so the body runs its elastic kernels only. With
//! [`SpinUp::modal`] the beam is reduced to modes ([`ffr::modal`]).

use ffr::kernels::{BeamSpec, FrameModel, Kernels};
use ffr::modal::{modal_body, modal_body_tape, ModalSettings};
use ffr::runtime::spec::{Formalism, KernelOptions, Params, Reference, SceneDim, Stiffening};
use ffr::runtime::{
    Driver, Error as RtError, GeneralizedAlpha, Integrator, KernelBody, ModalBody, PointShape,
    Pose, System,
};
use std::ops::ControlFlow;

/// Beam data of the benchmark (SI units); the section's torsion data (not
/// given by the benchmark) are those of a solid circle of the same area.
pub const KRB: Params = Params {
    length: 8.0,
    rho: 2766.67,
    area: 7.2968e-5,
    iy: 8.2189e-9,
    iz: 8.2189e-9,
    e: 6.8952e10,
    g: 2.6e10,
    j: 1.6438e-8,
};

/// Settings of a spin-up run.
#[derive(Clone, Debug, PartialEq)]
pub struct SpinUp {
    /// Final spin rate `ω_s` (rad/s).
    pub omega_s: f64,
    /// Ramp time `T` (s), 15 in the benchmark.
    pub t_ramp: f64,
    /// End time (s).
    pub t_end: f64,
    /// Step (s).
    pub dt: f64,
    /// Integrator.
    pub integrator: Integrator,
    /// Number of elements.
    pub elements: usize,
    /// Stiffening model.
    pub stiffening: Stiffening,
    /// Inertia formalism.
    pub formalism: Formalism,
    /// Spatial model (beam3, Euler parameters) instead of planar (beam2).
    pub spatial: bool,
    /// Beam parameters.
    pub params: Params,
    /// Run the general body (kernels for a spatial scene and a free frame)
    /// instead of the one specialized for this scene (planar if planar,
    /// prescribed hub at rest, no gravity): comparisons.
    pub general: bool,
    /// Run on tapes instead of the compiled kernels (comparisons).
    pub force_tape: bool,
    /// Reduce the beam to modes (`None`: the full nodal body).
    pub modal: Option<ModalSettings>,
    /// Gravity along the spin axis, `−z` (m/s²; spatial model only, 0 in
    /// the benchmark): the beam also bends out of the rotation plane.
    pub gravity: f64,
    /// Run the beam as this many FFR sub-bodies (`segments = N` of a scene
    /// file, issue 35; a divisor of [`SpinUp::elements`]); 1: one body.
    /// Above 1 the run goes through the scene module
    /// ([`segmented_scene`]).
    pub segments: usize,
}

impl SpinUp {
    /// `ω_s`, `T = 15 s`, `t_end = 20 s`, `dt = 0.01 s`, generalized-α
    /// `ρ∞ = 0.8`, 8 elements, fourth-order stiffening, planar.
    pub fn new(omega_s: f64) -> Self {
        Self {
            omega_s,
            t_ramp: 15.0,
            t_end: 20.0,
            dt: 0.01,
            integrator: Integrator::GeneralizedAlpha(GeneralizedAlpha::with_rho_inf(0.8)),
            elements: 8,
            stiffening: Stiffening::FourthOrder,
            formalism: Formalism::Consistent,
            spatial: false,
            params: KRB,
            general: false,
            force_tape: false,
            modal: None,
            gravity: 0.0,
            segments: 1,
        }
    }

    /// The body's description.
    pub fn beam(&self) -> BeamSpec {
        BeamSpec {
            shape: if self.spatial { "beam3" } else { "beam2" }.into(),
            elements: self.elements,
            reference: Reference::Clamped,
            options: KernelOptions {
                formalism: self.formalism,
                stiffening: self.stiffening,
                scene: self.general.then_some(SceneDim::Spatial),
                frame: if self.general {
                    FrameModel::Free
                } else if self.gravity != 0.0 {
                    // gravity is a frame acceleration `ā = −Aᵀg` to the body
                    FrameModel::Prescribed
                } else {
                    FrameModel::PrescribedAtRest
                },
            },
            params: self.params,
            force_tape: self.force_tape,
        }
    }

    /// The hub angle driver.
    pub fn driver(&self) -> Driver {
        Driver::spin_up(self.omega_s, self.t_ramp)
    }
}

/// Why a run stopped early.
#[derive(Clone, Debug, PartialEq)]
pub struct Divergence {
    /// Time (s).
    pub t: f64,
    /// What happened (tip beyond the beam length, or the integrator's error).
    pub reason: String,
}

/// Tip displacement history of a spin-up run, in the rotating hub (body) frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SpinUpResult {
    /// Times (s).
    pub t: Vec<f64>,
    /// Tip displacement along the hub-frame x axis (m).
    pub tip_axial: Vec<f64>,
    /// Tip displacement along the hub-frame y axis (m; negative = lagging).
    pub tip_transverse: Vec<f64>,
    /// Tip displacement along the hub-frame z axis (m; spatial model).
    pub tip_lateral: Vec<f64>,
    /// Set if the run diverged (|tip| > L) or the integrator failed.
    pub diverged: Option<Divergence>,
    /// Steps taken.
    pub steps: usize,
    /// Newton iterations.
    pub newton_iterations: usize,
    /// Iteration-matrix factorizations.
    pub jacobians: usize,
    /// Steps whose Newton iteration was started again from rest.
    pub restarts: usize,
    /// Steps done in halves.
    pub splits: usize,
    /// Wall time of the simulation alone (s).
    pub wall: f64,
    /// CPU time of the simulation alone, this thread (s).
    pub cpu: f64,
    /// The body's one-line description.
    pub body: String,
    /// `compiled`, `tape` or `modal`.
    pub kernels: &'static str,
}

impl SpinUpResult {
    /// `(t, value)` of the most negative transverse tip deflection.
    pub fn min_transverse(&self) -> Option<(f64, f64)> {
        self.t
            .iter()
            .zip(&self.tip_transverse)
            .map(|(a, b)| (*a, *b))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }
    /// Largest `|tip_transverse|` for `t ≥ t_from`.
    pub fn max_abs_transverse_after(&self, t_from: f64) -> f64 {
        self.t
            .iter()
            .zip(&self.tip_transverse)
            .filter(|(t, _)| **t >= t_from)
            .map(|(_, v)| v.abs())
            .fold(0.0, f64::max)
    }
    /// Linear interpolation of the transverse deflection at `t`.
    pub fn transverse_at(&self, t: f64) -> Option<f64> {
        interpolate(&self.t, &self.tip_transverse, t)
    }
}

/// Linear interpolation of samples `(ts, ys)` at `t` (`None` outside).
pub fn interpolate(ts: &[f64], ys: &[f64], t: f64) -> Option<f64> {
    if ts.is_empty() || t < ts[0] || t > *ts.last()? {
        return None;
    }
    let i = ts.partition_point(|&x| x < t);
    if i == 0 {
        return ys.first().copied();
    }
    let (t0, t1) = (ts[i - 1], ts[i]);
    let w = (t - t0) / (t1 - t0);
    Some(ys[i - 1] * (1.0 - w) + ys[i] * w)
}

/// `ω_s` finite and `T > 0`, gravity finite and only in the spatial
/// model, or an error naming them.
fn check_drive(cfg: &SpinUp) -> Result<(), Box<dyn std::error::Error>> {
    if !(cfg.omega_s.is_finite() && cfg.t_ramp > 0.0 && cfg.t_ramp.is_finite()) {
        return Err(format!(
            "spin-up needs a finite ω_s and T > 0 (got {}, {})",
            cfg.omega_s, cfg.t_ramp
        )
        .into());
    }
    if !cfg.gravity.is_finite() || (cfg.gravity != 0.0 && !cfg.spatial) {
        return Err(format!(
            "spin-up: gravity along the spin axis needs the spatial model and a finite value (got {})",
            cfg.gravity
        )
        .into());
    }
    Ok(())
}

/// A planar or spatial system of `body` alone, its frame origin at the
/// global origin and its angle about z prescribed by the spin-up driver.
fn hub_system<B: ffr::runtime::Body>(
    cfg: &SpinUp,
    body: B,
) -> Result<System<B>, Box<dyn std::error::Error>> {
    let mut sys = if cfg.spatial {
        System::spatial()
    } else {
        System::planar()
    };
    let b = sys.add_body("beam", body, Pose::identity(sys.dim()))?;
    sys.prescribe_rotation_about_z(b, cfg.driver())?;
    if cfg.gravity != 0.0 {
        sys.set_gravity(ffr::runtime::nalgebra::Vector3::new(0.0, 0.0, -cfg.gravity))?;
    }
    Ok(sys)
}

/// A second copy of the beam body, to evaluate its point shapes and
/// energies beside the system that owns the first.
pub type Probe = KernelBody<Kernels>;

/// The spin-up system with its one beam body.
pub type BeamSystem = System<KernelBody<Kernels>>;

/// The spin-up system: the beam clamped to the hub (its frame origin fixed
/// at the global origin) with the hub angle prescribed.
pub fn system(cfg: &SpinUp) -> Result<(BeamSystem, Probe), Box<dyn std::error::Error>> {
    check_drive(cfg)?;
    let body = cfg.beam().body()?;
    let probe = cfg.beam().body()?;
    let sys = hub_system(cfg, body)?;
    Ok((sys, probe))
}

/// Run the spin-up: the tip is the point at `x = L` of the beam's axis.
/// Divergence (|tip| > L) or an integrator failure stops the run and is
/// reported in [`SpinUpResult::diverged`]; bad input is an `Err`.
pub fn run(cfg: &SpinUp) -> Result<SpinUpResult, Box<dyn std::error::Error>> {
    if cfg.segments > 1 {
        return run_segmented(cfg);
    }
    run_with(cfg, |_| ControlFlow::Continue(()))
}

/// [`run`] with `stop` asked after every step whether to go on (a time
/// limit; a stopped run is reported as far as it went, with
/// [`SpinUpResult::steps`] short of the full run and no divergence).
pub fn run_with(
    cfg: &SpinUp,
    stop: impl FnMut(f64) -> ControlFlow<()>,
) -> Result<SpinUpResult, Box<dyn std::error::Error>> {
    let length = cfg.params.length;
    if cfg.segments > 1 {
        return Err(format!(
            "spin-up: {} segments run through the scene module (`run`), without a stop callback",
            cfg.segments
        )
        .into());
    }
    match &cfg.modal {
        None => {
            let (sys, probe) = system(cfg)?;
            let tip = ffr::runtime::Body::point_shape(&probe, length)?;
            simulate(cfg, sys, &tip, probe.kernels().path(), stop)
        }
        Some(settings) => {
            let (sys, tip) = modal_system(cfg, settings)?;
            simulate(cfg, sys, &tip, "modal", stop)
        }
    }
}

/// The spin-up system with the beam reduced to modes as `settings` say, and
/// the tip's point shape.
pub fn modal_system(
    cfg: &SpinUp,
    settings: &ModalSettings,
) -> Result<(System<ModalBody>, PointShape), Box<dyn std::error::Error>> {
    check_drive(cfg)?;
    // With --tape the generated modal kernels run on tapes.
    let body = if cfg.force_tape {
        modal_body_tape(&cfg.beam(), settings)?
    } else {
        modal_body(&cfg.beam(), settings)?
    };
    let tip = ffr::runtime::Body::point_shape(&body, cfg.params.length)?;
    let sys = hub_system(cfg, body)?;
    Ok((sys, tip))
}

fn simulate<B: ffr::runtime::Body>(
    cfg: &SpinUp,
    sys: System<B>,
    tip: &PointShape,
    kernels: &'static str,
    mut stop: impl FnMut(f64) -> ControlFlow<()>,
) -> Result<SpinUpResult, Box<dyn std::error::Error>> {
    let length = cfg.params.length;
    let fo = sys.bodies()[0].f_offset();
    let mut res = SpinUpResult {
        kernels,
        body: sys.bodies()[0].body.layout().description.clone(),
        ..SpinUpResult::default()
    };
    let n_samples = (cfg.t_end / cfg.dt).ceil() as usize + 1;
    res.t.reserve(n_samples);
    res.tip_axial.reserve(n_samples);
    res.tip_transverse.reserve(n_samples);
    if cfg.spatial {
        res.tip_lateral.reserve(n_samples);
    }
    let start = std::time::Instant::now();
    let c0 = crate::clock::thread_cpu_seconds();
    let run = sys.simulate(cfg.t_end, cfg.dt, &cfg.integrator, |v| {
        let q = &v.state.q;
        let mut u = [0.0; 3];
        for (dof, s, _) in &tip.entries {
            for k in 0..3 {
                u[k] += s[k] * q[fo + dof];
            }
        }
        res.t.push(v.state.t);
        res.tip_axial.push(u[0]);
        res.tip_transverse.push(u[1]);
        if cfg.spatial {
            res.tip_lateral.push(u[2]);
        }
        let norm = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
        if !(norm <= length) {
            res.diverged = Some(Divergence {
                t: v.state.t,
                reason: format!("tip displacement {norm:.3} m exceeds the beam length {length} m"),
            });
            return ControlFlow::Break(());
        }
        stop(v.state.t)
    });
    res.wall = start.elapsed().as_secs_f64();
    res.cpu = crate::clock::thread_cpu_seconds() - c0;
    match run {
        Ok(s) => {
            res.steps = s.steps;
            res.newton_iterations = s.newton_iterations;
            res.jacobians = s.jacobians;
            res.restarts = s.restarts;
            res.splits = s.splits;
        }
        Err(
            e @ (RtError::Diverged { .. }
            | RtError::NoConvergence { .. }
            | RtError::NonFinite { .. }
            | RtError::Unstable { .. }
            | RtError::Singular { .. }
            | RtError::StepFailed { .. }),
        ) => {
            // The steps recorded before the failure (the summary is lost).
            res.steps = res.t.len().saturating_sub(1);
            res.diverged = Some(Divergence {
                t: res.t.last().copied().unwrap_or(0.0),
                reason: e.to_string(),
            });
        }
        Err(e) => return Err(e.into()),
    }
    Ok(res)
}

/// The spin-up modelled in space with the hub as a joint: the beam (`beam3`
/// if `cfg.spatial`, else `beam2` generated for a spatial scene) in a
/// spatial scene with Euler parameters, a revolute joint between a ground
/// marker at the origin and the body-frame origin (`R = 0`, `z_g · x_b =
/// z_g · y_b = 0`: the rotations about x and y locked) and the hub angle
/// `θ(t)` imposed by [`System::prescribe_rotation`] (`x_b · (cos θ y_g −
/// sin θ x_g) = 0`). Unlike [`system`], whose frame motion is prescribed
/// (eliminated), the frame coordinates here are unknowns of the integrator,
/// held by 6 joint rows and the Euler-parameter normalization; the body's
/// kernels need their reference rows.
pub fn joint_driven_system(
    cfg: &SpinUp,
) -> Result<(BeamSystem, Probe), Box<dyn std::error::Error>> {
    check_drive(cfg)?;
    let spec = cfg.beam().scene_dim(3).frame(FrameModel::Free);
    let body = spec.body()?;
    let probe = spec.body()?;
    let mut sys = System::spatial();
    let b = sys.add_body("beam", body, Pose::identity(3))?;
    let hub = ffr::runtime::Marker::ground(ffr::runtime::nalgebra::Vector3::zeros());
    let origin = ffr::runtime::Marker::origin(b);
    sys.revolute(hub.clone(), origin.clone())?;
    sys.prescribe_rotation(hub, origin, cfg.driver())?;
    Ok((sys, probe))
}

/// A number as TOML reads it back exactly (Rust's shortest round-trip
/// form, always with a fraction or an exponent).
fn toml_number(x: f64) -> String {
    format!("{x:?}")
}

/// The spin-up as a scene file's text: the model of [`system`] (the beam
/// clamped to a hub at the origin, a revolute joint to the ground driven by
/// the spin-up profile, gravity along −z if any), with `segments =
/// cfg.segments`, and the tip deflections in the hub (root segment's)
/// frame as outputs `tip_axial`, `tip_transverse` and, in space,
/// `tip_lateral`. The integrator line is generalized-α ρ∞ = 0.8; the run
/// uses [`SpinUp::integrator`] ([`segmented_scene`]).
pub fn scene_text(cfg: &SpinUp) -> String {
    let n = toml_number;
    let p = &cfg.params;
    let stiffening = match cfg.stiffening {
        Stiffening::Off => "false",
        Stiffening::SecondOrder => "\"second-order\"",
        Stiffening::FourthOrder => "\"fourth-order\"",
    };
    let formalism = match cfg.formalism {
        Formalism::Consistent => "consistent",
        Formalism::Lumped => "lumped",
    };
    let (dim, shape, position) = if cfg.spatial {
        (3, "beam3", "[0.0, 0.0, 0.0]")
    } else {
        (2, "beam2", "[0.0, 0.0]")
    };
    let mut s = format!(
        "description = \"KRB spin-up beam ({shape}, {} elements in {} segments, {} rad/s)\"\n\
         dimension = {dim}\n",
        cfg.elements, cfg.segments, cfg.omega_s
    );
    if cfg.gravity != 0.0 {
        s += &format!("gravity = [0.0, 0.0, {}]\n", n(-cfg.gravity));
    }
    s += &format!(
        "t_end = {}\ndt = {}\nintegrator = {{ kind = \"generalized-alpha\", rho_inf = 0.8 }}\n\n\
         [bodies.beam]\nshape = \"{shape}\"\nelements = {}\nsegments = {}\n\
         reference = \"clamped\"\nstiffening = {stiffening}\nformalism = \"{formalism}\"\n\
         params = {{ length = {}, rho = {}, area = {}, iy = {}, iz = {}, e = {}, g = {}, j = {} }}\n\
         position = {position}\n",
        n(cfg.t_end),
        n(cfg.dt),
        cfg.elements,
        cfg.segments,
        n(p.length),
        n(p.rho),
        n(p.area),
        n(p.iy),
        n(p.iz),
        n(p.e),
        n(p.g),
        n(p.j),
    );
    let ground = if cfg.spatial {
        "[0.0, 0.0, 0.0]"
    } else {
        s += "angle = 0.0\n";
        "[0.0, 0.0]"
    };
    s += &format!(
        "\n[[joints]]\nkind = \"revolute\"\na = \"ground@{ground}\"\nb = \"beam\"\n\
         drive = {{ angle = \"spin-up\", omega = {}, ramp = {} }}\n",
        n(cfg.omega_s),
        n(cfg.t_ramp)
    );
    let mut outputs = vec![("tip_axial", "x"), ("tip_transverse", "y")];
    if cfg.spatial {
        outputs.push(("tip_lateral", "z"));
    }
    for (name, c) in outputs {
        s += &format!(
            "\n[[outputs]]\nname = \"{name}\"\nkind = \"deflection\"\nat = \"beam@x={}\"\ncomponent = \"{c}\"\n",
            n(p.length)
        );
    }
    s
}

/// The scene of [`scene_text`], loaded with the built-in kernels, its
/// integrator [`SpinUp::integrator`].
pub fn segmented_scene(cfg: &SpinUp) -> Result<ffr::scene::Scene, Box<dyn std::error::Error>> {
    check_drive(cfg)?;
    if cfg.modal.is_some() || cfg.general || cfg.force_tape {
        return Err(
            "spin-up: segments run the scene's compiled nodal bodies (no modal, general or tape variant)"
                .into(),
        );
    }
    let mut scene = ffr::scene::from_str(
        &scene_text(cfg),
        "spin-up (segments)",
        &ffr::scene::load::builtin_dir(),
        &ffr::scene::DefaultKernels,
    )?;
    scene.integrator = cfg.integrator;
    Ok(scene)
}

/// The spin-up with the beam run as [`SpinUp::segments`] sub-bodies (also
/// 1: the scene module's run of the same model as [`run`]), through
/// [`segmented_scene`] and `ffr::scene::run`: the CPU time is that of the
/// scene's run (its `System::simulate` and the recording of the tip
/// deflections at every step; the scene is built before the clock starts).
/// A run that stopped early is reported in [`SpinUpResult::diverged`].
pub fn run_segmented(cfg: &SpinUp) -> Result<SpinUpResult, Box<dyn std::error::Error>> {
    let scene = segmented_scene(cfg)?;
    let c0 = crate::clock::thread_cpu_seconds();
    let start = std::time::Instant::now();
    let r = ffr::scene::run(&scene)?;
    let wall = start.elapsed().as_secs_f64();
    let cpu = crate::clock::thread_cpu_seconds() - c0;
    let col = |name: &str| {
        r.names
            .iter()
            .position(|n| n == name)
            .map(|i| r.columns[i].clone())
            .unwrap_or_default()
    };
    let length = cfg.params.length;
    let mut res = SpinUpResult {
        tip_axial: col("tip_axial"),
        tip_transverse: col("tip_transverse"),
        tip_lateral: col("tip_lateral"),
        t: r.t.clone(),
        steps: r.steps,
        newton_iterations: r.newton_iterations,
        jacobians: r.jacobians,
        restarts: r.restarts,
        splits: r.splits,
        wall,
        cpu,
        body: format!(
            "{} {} elements in {} segments",
            if cfg.spatial { "beam3" } else { "beam2" },
            cfg.elements,
            cfg.segments
        ),
        kernels: "compiled",
        diverged: None,
    };
    // As `simulate`: the first sample whose tip left the beam's length.
    let far = (0..res.t.len()).find(|&k| {
        let w = res.tip_lateral.get(k).copied().unwrap_or(0.0);
        let norm = (res.tip_axial[k].powi(2) + res.tip_transverse[k].powi(2) + w * w).sqrt();
        !(norm <= length)
    });
    if let Some(k) = far {
        res.diverged = Some(Divergence {
            t: res.t[k],
            reason: format!("tip displacement exceeds the beam length {length} m"),
        });
    } else if let Some(f) = r.failed {
        res.diverged = Some(Divergence {
            t: res.t.last().copied().unwrap_or(0.0),
            reason: f,
        });
    }
    Ok(res)
}
