//! A free flexible pendulum: a beam body (planar `beam2` in a planar scene or
//! spatial `beam3` in a spatial scene with Euler parameters; consistent
//! formalism, `clamped` reference so that the body frame is tangent to the
//! beam at node 0, no geometric stiffening) pinned at node 0 to the ground by
//! a revolute joint about global z, released at rest and undeformed from the
//! horizontal, under gravity `−9.81 e_y`, with no damping (no Rayleigh
//! damping; by default generalized-α with `ρ∞ = 1`, which adds no numerical
//! dissipation).
//!
//! The continuous system conserves the total energy `T + V_elastic + V_gravity`
//! exactly and stays on the constraint manifold. What a run measures is
//! therefore the integrator's error:
//!
//! - **energy drift** `max |E(t) − E(0)| / E_ref`, `E_ref = m g L / 2` (the
//!   potential energy a rigid rod releases swinging from horizontal to
//!   vertical): generalized-α is second order, so the drift is `O(dt²)`;
//! - **position constraint violation** `max ‖Φ‖∞`: the index-3
//!   generalized-α scheme solves `Φ(q_{n+1}) = 0` in every step, so `Φ` is
//!   only the Newton tolerance (not an `O(dt^k)` error);
//! - **velocity constraint violation** `max ‖Φ_q q̇‖∞`: not enforced by the
//!   index-3 scheme; it is an integration error (`O(dt²)` here).

use clap::{Args, ValueEnum};
use ffr::kernels::{BeamSpec, Kernels};
use ffr::runtime::nalgebra::Vector3;
use ffr::runtime::spec::{Formalism, KernelOptions, Params, Reference};
use ffr::runtime::{
    Body, BodyId, GeneralizedAlpha, Integrator, KernelBody, Marker, Pose, Rk4Baumgarte, StepView,
    System,
};
use std::ops::ControlFlow;
use std::time::Instant;

/// Gravitational acceleration of the scene (m/s², along −y).
pub const GRAVITY: f64 = 9.81;

/// An aluminium bar, 1 m, 10 × 10 mm: first bending frequency of the pinned
/// bar about 230 rad/s, static tip sag of the horizontal cantilever under its
/// own weight about 6 mm.
pub const ALUMINIUM_BAR: Params = Params {
    length: 1.0,
    rho: 2700.0,
    area: 1.0e-4,
    iy: 1.0e-8 / 12.0,
    iz: 1.0e-8 / 12.0,
    e: 7.0e10,
    g: 2.6e10,
    j: 0.1406e-8,
};

/// The beam shape of a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Beam {
    /// Planar Euler–Bernoulli beam (a planar scene).
    Beam2,
    /// Spatial Euler–Bernoulli beam with torsion (a spatial scene, Euler parameters).
    Beam3,
}

impl Beam {
    /// The built-in shape name.
    pub fn name(self) -> &'static str {
        match self {
            Beam::Beam2 => "beam2",
            Beam::Beam3 => "beam3",
        }
    }

    /// The scene dimension it runs in: 2 for `beam2`, 3 for `beam3`.
    pub fn scene_dim(self) -> usize {
        match self {
            Beam::Beam2 => 2,
            Beam::Beam3 => 3,
        }
    }
}

/// `elements` equal elements of `beam` (consistent formalism, no
/// geometric stiffening) in its own scene dimension, on compiled kernels.
pub fn beam_spec(beam: Beam, elements: usize, reference: Reference, params: Params) -> BeamSpec {
    BeamSpec {
        shape: beam.name().into(),
        elements,
        reference,
        options: KernelOptions::new(),
        params,
        force_tape: false,
    }
}

/// The integrator of a run (shared by the scenes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Method {
    /// Generalized-α (index 3), by default with `ρ∞ = 1`: no numerical dissipation.
    Alpha,
    /// Explicit RK4 on the index-1 form, Baumgarte `α = β = 10/s`.
    Rk4,
}

impl Method {
    /// The runtime integrator: generalized-α with `ρ∞ = 1` and the runtime's
    /// default Newton tolerance, or RK4.
    pub fn integrator(self) -> Integrator {
        let d = GeneralizedAlpha::default();
        self.integrator_with(1.0, d.rtol)
    }

    /// The runtime integrator; generalized-α with spectral radius `rho_inf`
    /// and Newton iterations stopping at the relative acceleration tolerance
    /// `rtol` (RK4 has neither).
    pub fn integrator_with(self, rho_inf: f64, rtol: f64) -> Integrator {
        match self {
            Method::Alpha => Integrator::GeneralizedAlpha(GeneralizedAlpha {
                rtol,
                max_iter: 30,
                ..GeneralizedAlpha::with_rho_inf(rho_inf)
            }),
            Method::Rk4 => Integrator::Rk4(Rk4Baumgarte::default()),
        }
    }

    /// Global order of accuracy.
    pub fn order(self) -> f64 {
        match self {
            Method::Alpha => 2.0,
            Method::Rk4 => 4.0,
        }
    }
}

/// Options of a pendulum run.
#[derive(Args, Clone, Debug, PartialEq)]
pub struct PendulumArgs {
    /// Beam shape (beam2: planar scene; beam3: spatial scene).
    #[arg(long, value_enum, default_value_t = Beam::Beam2)]
    pub beam: Beam,
    /// Number of elements of the 1 m bar (1 to 64).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u16).range(1..=64))]
    pub elements: u16,
    /// End time (s).
    #[arg(long, default_value_t = 1.0)]
    pub t_end: f64,
    /// Time step (s).
    #[arg(long, default_value_t = 1e-3)]
    pub dt: f64,
    /// Integrator.
    #[arg(long, value_enum, default_value_t = Method::Alpha)]
    pub method: Method,
    /// Generalized-α spectral radius at infinite frequency (1: no numerical
    /// dissipation; lower values damp the unresolved high modes).
    #[arg(long, default_value_t = 1.0)]
    pub rho_inf: f64,
    /// Inertia formalism of the bar: consistent or lumped (nodal masses
    /// with HRZ rotary inertia).
    #[arg(long, value_enum, default_value_t = Formalism::Consistent)]
    pub formalism: Formalism,
}

impl Default for PendulumArgs {
    fn default() -> Self {
        Self {
            beam: Beam::Beam2,
            elements: 4,
            t_end: 1.0,
            dt: 1e-3,
            method: Method::Alpha,
            rho_inf: 1.0,
            formalism: Formalism::Consistent,
        }
    }
}

impl PendulumArgs {
    /// The integrator of the run.
    pub fn integrator(&self) -> Integrator {
        self.method
            .integrator_with(self.rho_inf, GeneralizedAlpha::default().rtol)
    }
}

/// What a pendulum run measured.
#[derive(Clone, Debug, PartialEq)]
pub struct PendulumReport {
    /// Steps taken.
    pub steps: usize,
    /// Total energy at `t = 0` (J).
    pub energy0: f64,
    /// `E_ref = m g L / 2` (J).
    pub energy_ref: f64,
    /// `max_t |E(t) − E(0)| / E_ref`.
    pub energy_drift: f64,
    /// `(E(t_end) − E(0)) / E_ref`.
    pub energy_change: f64,
    /// `max_t ‖Φ‖∞` (joint and, in space, Euler-parameter normalization).
    pub max_phi: f64,
    /// `max_t ‖Φ_q q̇ + Φ_t‖∞`.
    pub max_phi_dot: f64,
    /// Largest elastic displacement of the free end, in the body frame (m).
    pub max_tip_deflection: f64,
    /// Lowest global `y` of the free end (m; `−L` when it swings through the vertical).
    pub min_tip_y: f64,
    /// Global position of the free end at the end of the run (m).
    pub final_tip: Vector3<f64>,
    /// Newton iterations (generalized-α).
    pub newton_iterations: usize,
    /// Iteration-matrix factorizations (generalized-α).
    pub jacobians: usize,
    /// Wall time of the simulation (s).
    pub wall: f64,
}

/// The pendulum scene with body `body` (a beam of length `L` along body x
/// from its frame origin): node 0 pinned to the ground at the origin by a
/// revolute joint about global z, gravity `−9.81 e_y`. Planar for a body
/// generated for a planar scene, spatial (Euler parameters, spatial revolute)
/// otherwise.
pub fn scene<B: Body>(body: B) -> Result<(System<B>, BodyId), Box<dyn std::error::Error>> {
    let d = body.layout().scene_dim;
    let mut sys = System::with_dim(d);
    let b = sys.add_body("bar", body, Pose::identity(d))?;
    let pin = sys.point(b, 0.0)?;
    sys.revolute(Marker::ground(Vector3::zeros()), pin)?;
    sys.set_gravity(Vector3::new(0.0, -GRAVITY, 0.0))?;
    Ok((sys, b))
}

/// A system of one compiled beam body, and the body.
pub type BeamScene = (System<KernelBody<Kernels>>, BodyId);

/// The pendulum system of `args` (compiled beam body, [`scene`]).
pub fn system(args: &PendulumArgs) -> Result<BeamScene, Box<dyn std::error::Error>> {
    system_with(args, ALUMINIUM_BAR)
}

/// [`system`] with the bar's parameters `params` instead of
/// [`ALUMINIUM_BAR`] (scale and stiffness studies).
pub fn system_with(
    args: &PendulumArgs,
    params: Params,
) -> Result<BeamScene, Box<dyn std::error::Error>> {
    let mut spec = beam_spec(
        args.beam,
        args.elements as usize,
        Reference::Clamped,
        params,
    );
    spec.options.formalism = args.formalism;
    scene(spec.body()?)
}

/// `‖Φ‖∞` and `‖Φ_q q̇ + Φ_t‖∞` at the state of `view`, using caller-owned
/// buffers (sized on the first call).
pub fn constraint_violation<B: Body>(
    view: &mut StepView<B>,
    r: &mut Vec<f64>,
    vv: &mut Vec<f64>,
) -> (f64, f64) {
    let s = view.state;
    let (n, m) = (s.q.len(), s.lambda.len());
    r.resize(n + m, 0.0);
    vv.resize(m, 0.0);
    view.assembly.residual(s.t, &s.q, &s.v, &s.a, &s.lambda, r);
    view.assembly.velocity_violation(&s.v, &s.q, vv);
    let inf = |x: &[f64]| x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    (inf(&r[n..]), inf(vv))
}

/// Run the pendulum and measure energy drift and constraint violation.
pub fn run(args: &PendulumArgs) -> Result<PendulumReport, Box<dyn std::error::Error>> {
    run_with(args, ALUMINIUM_BAR, |_| ControlFlow::Continue(()))
}

/// [`run`] with the bar's parameters `params`, and `stop` asked after every
/// step whether to go on (a time limit; a stopped run is reported as far as
/// it went, with [`PendulumReport::steps`] short of the full run).
pub fn run_with(
    args: &PendulumArgs,
    params: Params,
    mut stop: impl FnMut(f64) -> ControlFlow<()>,
) -> Result<PendulumReport, Box<dyn std::error::Error>> {
    for (name, v) in [("--t-end", args.t_end), ("--dt", args.dt)] {
        if !v.is_finite() || v <= 0.0 {
            return Err(format!("{name} must be a positive number, found {v}").into());
        }
    }
    if !(0.0..=1.0).contains(&args.rho_inf) {
        return Err(format!("--rho-inf must be in [0, 1], found {}", args.rho_inf).into());
    }
    let (sys, b) = system_with(args, params)?;
    let body = sys.body(b);
    let length = body
        .layout()
        .length
        .ok_or("the pendulum needs a beam body")?;
    let energy_ref = body.invariants().mass * GRAVITY * length / 2.0;
    let tip = sys.point(b, length)?;
    let fo = sys.body_entry(b).f_offset();
    let (mut rbuf, mut vv) = (Vec::new(), Vec::new());

    let mut r = PendulumReport {
        steps: 0,
        energy0: f64::NAN,
        energy_ref,
        energy_drift: 0.0,
        energy_change: 0.0,
        max_phi: 0.0,
        max_phi_dot: 0.0,
        max_tip_deflection: 0.0,
        min_tip_y: 0.0,
        final_tip: Vector3::zeros(),
        newton_iterations: 0,
        jacobians: 0,
        wall: 0.0,
    };
    let t0 = Instant::now();
    let summary = sys.simulate(args.t_end, args.dt, &args.integrator(), |v| {
        let e = v.energy().total();
        if v.step == 0 {
            r.energy0 = e;
        }
        r.energy_change = (e - r.energy0) / energy_ref;
        r.energy_drift = r.energy_drift.max(r.energy_change.abs());
        let (phi, phi_dot) = constraint_violation(v, &mut rbuf, &mut vv);
        r.max_phi = r.max_phi.max(phi);
        r.max_phi_dot = r.max_phi_dot.max(phi_dot);
        let q = &v.state.q;
        let mut u = Vector3::zeros();
        for (dof, s, _) in &tip.shape.entries {
            u += Vector3::from(*s) * q[fo + dof];
        }
        r.max_tip_deflection = r.max_tip_deflection.max(u.norm());
        r.min_tip_y = r.min_tip_y.min(v.assembly.marker_position(&tip, q).y);
        r.final_tip = v.assembly.marker_position(&tip, q);
        stop(v.state.t)
    })?;
    r.wall = t0.elapsed().as_secs_f64();
    r.steps = summary.steps;
    r.newton_iterations = summary.newton_iterations;
    r.jacobians = summary.jacobians;
    Ok(r)
}

/// [`run`] and print a short summary.
pub fn run_and_print(args: &PendulumArgs) -> Result<PendulumReport, Box<dyn std::error::Error>> {
    let r = run(args)?;
    crate::outln!(
        "flexible pendulum: {} × {} (aluminium 1 m, 10 × 10 mm, clamped reference, compiled kernels), pinned at node 0, g = {GRAVITY} m/s², no damping",
        args.elements,
        args.beam.name()
    )?;
    let method = match args.method {
        Method::Alpha => format!("generalized-α ρ∞ = {}", args.rho_inf),
        Method::Rk4 => "RK4 (Baumgarte α = β = 10/s)".into(),
    };
    crate::outln!(
        "{method}, dt = {} s, t_end = {} s: {} steps, {} Newton iterations, {} iteration matrices, wall {:.3} s",
        args.dt, args.t_end, r.steps, r.newton_iterations, r.jacobians, r.wall
    )?;
    crate::outln!(
        "energy: E(0) = {:.6} J, E_ref = m g L/2 = {:.6} J, max |E − E(0)|/E_ref = {:.3e}, (E(t_end) − E(0))/E_ref = {:.3e}",
        r.energy0, r.energy_ref, r.energy_drift, r.energy_change
    )?;
    crate::outln!(
        "constraints: max ‖Φ‖∞ = {:.3e}, max ‖Φ̇‖∞ = {:.3e}",
        r.max_phi,
        r.max_phi_dot
    )?;
    crate::outln!(
        "free end: lowest y = {:.4} m, largest elastic displacement = {:.3e} m",
        r.min_tip_y,
        r.max_tip_deflection
    )?;
    Ok(r)
}
