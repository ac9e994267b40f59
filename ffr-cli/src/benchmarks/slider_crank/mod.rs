//! The flexible slider-crank of B. Simeon (Test Set for IVP Solvers, problem
//! "Slider crank"; Simeon 1996): rigid crank driven at 150 rad/s, flexible
//! steel connecting rod between two revolute joints, sliding block on a
//! prismatic joint along the global x axis; no gravity, no damping, linear
//! stiffness, `0 ≤ t ≤ 0.1 s`. The rod is a compiled `beam2` body
//! (consistent formalism, `pinned` reference), started from the benchmark's
//! consistent initial values (projected onto the constraints by the
//! runtime's initial state) and compared with its published solution at
//! `t = 0.1 s`.
//!
//! The benchmark discretizes the rod (frame: x from the crank pin to the
//! slider pin) by two lateral modes `v = q₁ sin(πξ) + q₂ sin(2πξ)`, `ξ = x/l`,
//! and a quadratic axial ansatz `u = q₃ 4ξ(1−ξ) + q₄ ξ(2ξ−1)` (`q₃`, `q₄`: axial
//! displacement of the midpoint and of the slider end), section rotary
//! inertia neglected. The midpoint deflection is exactly `q₁`.
//! [`SimeonRod`] rebuilds that rod as a runtime [`Body`] from its invariants,
//! to check the scene against the published numbers with the benchmark's own
//! discretization and to measure what the discretization changes.

use clap::Args;
use ffr::kernels::BeamSpec;
use ffr::runtime::nalgebra::{Vector2, Vector3};
use ffr::runtime::spec::{KernelOptions, Params, Reference};
use ffr::runtime::{
    Body, BodyId, Driver, Error as RtError, GeneralizedAlpha, Integrator, Marker, Pose, RigidBody,
    State, System,
};
use std::f64::consts::PI;

mod simeon_rod;
pub use simeon_rod::{simeon_rod, SimeonRod};
use std::io::Write;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// Crank length (m).
pub const CRANK_LENGTH: f64 = 0.15;
/// Rod length (m).
pub const ROD_LENGTH: f64 = 0.30;
/// Crank speed (rad/s).
pub const CRANK_SPEED: f64 = 150.0;
/// Crank mass (kg).
pub const CRANK_MASS: f64 = 0.36;
/// Crank moment of inertia about its pivot (kg m²), centre of mass at mid-length.
pub const CRANK_INERTIA: f64 = 0.002727;
/// Slider mass (kg).
pub const SLIDER_MASS: f64 = 0.075552;
/// Rod width `b` (m).
pub const ROD_WIDTH: f64 = 0.008;
/// Rod height `h` (m), in the plane of motion.
pub const ROD_HEIGHT: f64 = 0.008;
/// Young's modulus (Pa).
pub const YOUNG: f64 = 2.0e11;
/// Density (kg/m³).
pub const DENSITY: f64 = 7870.0;

/// Rod data (SI): 0.3 m steel, 8 × 8 mm (`I = b h³/12`; `G` and `J` do not
/// enter the planar model).
pub const ROD: Params = Params {
    length: ROD_LENGTH,
    rho: DENSITY,
    area: ROD_WIDTH * ROD_HEIGHT,
    iy: ROD_HEIGHT * ROD_WIDTH * ROD_WIDTH * ROD_WIDTH / 12.0,
    iz: ROD_WIDTH * ROD_HEIGHT * ROD_HEIGHT * ROD_HEIGHT / 12.0,
    e: YOUNG,
    g: YOUNG / 2.6,
    j: 0.1406 * ROD_WIDTH * ROD_WIDTH * ROD_WIDTH * ROD_WIDTH,
};

/// End time of the benchmark (s).
pub const T_END: f64 = 0.1;

// ------------------------------------------------------------------ benchmark data

/// A state of Simeon's model: rod angle `φ₂`, slider `x₃`, `q = (q₁..q₄)`
/// and their rates (the crank angle is `150 t`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimeonState {
    /// `φ₂` (rad).
    pub phi2: f64,
    /// `x₃` (m).
    pub x3: f64,
    /// `q₁, q₂` (lateral mode amplitudes, m), `q₃, q₄` (axial nodal values, m).
    pub q: [f64; 4],
    /// `φ̇₂` (rad/s).
    pub phi2_dot: f64,
    /// `ẋ₃` (m/s).
    pub x3_dot: f64,
    /// `q̇` (m/s).
    pub q_dot: [f64; 4],
}

/// The benchmark's consistent initial values "close to smooth motion" at
/// `t = 0` (`φ₁ = 0`, `φ̇₁ = 150`), from which its reference solution starts.
pub const SIMEON_INIT: SimeonState = SimeonState {
    phi2: 0.0,
    x3: 0.450016933,
    q: [0.0, 0.0, 1.03339863e-5, 1.69327969e-5],
    phi2_dot: -74.9957670,
    x3_dot: -2.68938672e-6,
    q_dot: [0.444896105, 4.63434311e-3, -1.78591076e-6, -2.68938672e-6],
};

/// The published reference solution at `t = 0.1 s` (velocities of `q₃, q₄`
/// not used here and left at NaN).
pub const PUBLISHED: SimeonState = SimeonState {
    phi2: -0.3311734987910881,
    x3: 0.169737332671841,
    q: [
        1.893192460247178e-4,
        2.375751865617931e-5,
        -5.323907988763734e-6,
        -8.36328314161684e-6,
    ],
    phi2_dot: 60.25346682645789,
    x3_dot: -8.753116989887888,
    q_dot: [
        -3.005536801092212e-2,
        -5.500488291932075e-3,
        f64::NAN,
        f64::NAN,
    ],
};

// ------------------------------------------------------------------ initial fields

/// A planar displacement field along a beam body's x axis (`0 ≤ x ≤ L`):
/// lateral `v(x)` (body y), its slope `v'(x)`, and axial `u(x)` (body x).
/// Used for displacements and, likewise, for velocities `v̇, v̇', u̇`.
#[derive(Clone)]
pub struct BeamField {
    /// Lateral displacement `v(x)`.
    pub v: Arc<dyn Fn(f64) -> f64 + Send + Sync>,
    /// Slope `v'(x)` (the small rotation about body z).
    pub dv: Arc<dyn Fn(f64) -> f64 + Send + Sync>,
    /// Axial displacement `u(x)`.
    pub u: Arc<dyn Fn(f64) -> f64 + Send + Sync>,
}

impl std::fmt::Debug for BeamField {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "BeamField")
    }
}

/// Highest node index among `kind_node` labels.
pub fn last_node(labels: &[String]) -> Option<usize> {
    labels
        .iter()
        .filter_map(|l| l.split_once('_')?.1.parse::<usize>().ok())
        .max()
}

/// Index of the coordinate labelled `label`.
pub fn dof_index(labels: &[String], label: &str) -> Option<usize> {
    labels.iter().position(|l| l == label)
}

impl BeamField {
    /// From closures `v`, `v'`, `u`.
    pub fn new(
        v: impl Fn(f64) -> f64 + Send + Sync + 'static,
        dv: impl Fn(f64) -> f64 + Send + Sync + 'static,
        u: impl Fn(f64) -> f64 + Send + Sync + 'static,
    ) -> Self {
        Self {
            v: Arc::new(v),
            dv: Arc::new(dv),
            u: Arc::new(u),
        }
    }
    /// The zero field.
    pub fn zero() -> Self {
        Self::new(|_| 0.0, |_| 0.0, |_| 0.0)
    }
    /// Nodal coordinates of a planar beam body of length `length` with
    /// `N` equal elements (labels `kind_node`, nodes at `x_i = i L / N`):
    /// `ux_i = u(x_i)`, `uy_i = v(x_i)`, `rz_i = v'(x_i)`. Coordinates the
    /// reference conditions removed are simply absent; any other label
    /// (a spatial or non-beam body) is an error.
    pub fn nodal_coordinates(
        &self,
        labels: &[String],
        length: f64,
    ) -> Result<Vec<f64>, Box<dyn std::error::Error>> {
        let n = last_node(labels)
            .filter(|&n| n > 0)
            .ok_or("the body has no beam node labels")?;
        labels
            .iter()
            .map(|lab| {
                let (kind, node) = lab
                    .split_once('_')
                    .and_then(|(k, i)| Some((k, i.parse::<usize>().ok()?)))
                    .ok_or_else(|| format!("`{lab}` is no beam node label"))?;
                let x = length * node as f64 / n as f64;
                let val = match kind {
                    "ux" => (self.u)(x),
                    "uy" => (self.v)(x),
                    "rz" => (self.dv)(x),
                    _ => {
                        return Err(format!(
                            "`{lab}`: a planar beam field has no `{kind}` component"
                        )
                        .into())
                    }
                };
                if val.is_finite() {
                    Ok(val)
                } else {
                    Err(format!("the field is not finite at `{lab}`").into())
                }
            })
            .collect()
    }
}

/// The rod's initial elastic state.
#[derive(Clone, Debug, Default)]
pub enum RodElastic {
    /// Undeformed, at rest relative to its frame.
    #[default]
    Undeformed,
    /// Displacement and velocity fields projected onto a beam rod's nodal
    /// coordinates ([`BeamField::nodal_coordinates`]).
    Fields {
        /// Displacements `v, v', u`.
        q: BeamField,
        /// Velocities `v̇, v̇', u̇`.
        qd: BeamField,
    },
    /// The rod's elastic coordinates and velocities as they are (any body).
    Coordinates {
        /// `q_f`.
        q_f: Vec<f64>,
        /// `q̇_f`.
        qd_f: Vec<f64>,
    },
}

/// Initial conditions of the slider-crank at `t = 0` (crank angle 0, crank
/// speed [`CRANK_SPEED`]). They are made consistent by the runtime's initial
/// projection ([`System::initial_state`]): mass-weighted least-squares
/// corrections onto the position and velocity constraints.
#[derive(Clone, Debug)]
pub struct SliderCrankInit {
    /// Rod angle `φ₂` (rad; frame x axis from the crank pin to the slider pin).
    pub rod_angle: f64,
    /// Rod angular velocity `φ̇₂` (rad/s).
    pub rod_rate: f64,
    /// Slider position on the x axis (m).
    pub slider_x: f64,
    /// Slider velocity (m/s).
    pub slider_v: f64,
    /// Elastic state of the rod.
    pub elastic: RodElastic,
}

impl SliderCrankInit {
    /// The rigid mechanism at `θ = 0`: rod along +x, `φ̇₂ = −(l_c/l_r) θ̇`,
    /// slider at `l_c + l_r` at rest, rod undeformed.
    pub fn rigid() -> Self {
        Self {
            rod_angle: 0.0,
            rod_rate: -CRANK_LENGTH / ROD_LENGTH * CRANK_SPEED,
            slider_x: CRANK_LENGTH + ROD_LENGTH,
            slider_v: 0.0,
            elastic: RodElastic::Undeformed,
        }
    }
}

impl Default for SliderCrankInit {
    fn default() -> Self {
        Self::rigid()
    }
}

/// Simeon's displacement field for coordinates `q`: `v = q₁ sin πξ + q₂ sin 2πξ`,
/// `u = q₃ 4ξ(1−ξ) + q₄ ξ(2ξ−1)`, `ξ = x/l`.
pub fn simeon_field(q: [f64; 4]) -> BeamField {
    let l = ROD_LENGTH;
    BeamField::new(
        move |x| q[0] * (PI * x / l).sin() + q[1] * (2.0 * PI * x / l).sin(),
        move |x| (q[0] * (PI * x / l).cos() + 2.0 * q[1] * (2.0 * PI * x / l).cos()) * PI / l,
        move |x| {
            let s = x / l;
            q[2] * 4.0 * s * (1.0 - s) + q[3] * s * (2.0 * s - 1.0)
        },
    )
}

/// Initial conditions for a beam rod from a state of Simeon's model: rigid
/// coordinates as they are, the elastic fields projected onto the nodes
/// (`uy = v`, `rz = v'`, `ux = u` at each node, likewise for the rates).
pub fn beam_init(s: &SimeonState) -> SliderCrankInit {
    SliderCrankInit {
        rod_angle: s.phi2,
        rod_rate: s.phi2_dot,
        slider_x: s.x3,
        slider_v: s.x3_dot,
        elastic: RodElastic::Fields {
            q: simeon_field(s.q),
            qd: simeon_field(s.q_dot),
        },
    }
}

/// Initial conditions for [`SimeonRod`] from a state of Simeon's model.
pub fn simeon_init(s: &SimeonState) -> SliderCrankInit {
    SliderCrankInit {
        rod_angle: s.phi2,
        rod_rate: s.phi2_dot,
        slider_x: s.x3,
        slider_v: s.x3_dot,
        elastic: RodElastic::Coordinates {
            q_f: s.q.to_vec(),
            qd_f: s.q_dot.to_vec(),
        },
    }
}

// ------------------------------------------------------------------ the scene

/// The slider-crank system and where its bodies are.
pub struct SliderCrank {
    /// The system (crank and slider rigid, the rod any planar body).
    pub system: System<Box<dyn Body>>,
    /// Crank body.
    pub crank: BodyId,
    /// Rod body.
    pub rod: BodyId,
    /// Slider body.
    pub slider: BodyId,
    /// Index in `q` of the rod's midpoint deflection coordinate (`uy` of
    /// the middle node).
    pub mid_uy: usize,
}

/// The slider-crank with `rod` (a planar body along its x axis from the
/// crank pin, its frame origin, to the slider pin at `x = 0.3 m`; its
/// coordinate labelled `uy_{N/2}`, `N` its highest node label, is the
/// midpoint deflection) from the initial conditions `init`:
///
/// - crank (0.15 m, 0.36 kg, `J = 0.002727 kg m²` about its pivot, centre of
///   mass at mid-length): frame prescribed, pivot at the origin, angle
///   `150 t` ([`System::prescribe_rotation_about_z`]);
/// - revolute joints crank tip – rod at `x = 0` and rod at `x = l` – slider;
/// - slider (0.075552 kg): a prismatic joint along the global x axis
///   ([`System::prismatic`]: `y = 0`, no rotation).
pub fn slider_crank_with(
    rod: Box<dyn Body>,
    init: &SliderCrankInit,
) -> Result<SliderCrank, Box<dyn std::error::Error>> {
    slider_crank_guided(rod, init, SliderGuide::Prismatic)
}

/// How the slider is kept on the x axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SliderGuide {
    /// A prismatic joint between the ground and the slider (two constraint
    /// rows, `y = 0` and no rotation, with multipliers).
    Prismatic,
    /// The slider's `y` and angle prescribed as 0 (eliminated coordinates;
    /// the way the scene was built before the runtime had prismatic joints).
    Coordinates,
}

/// [`slider_crank_with`] with a choice of how the slider is guided.
pub fn slider_crank_guided(
    rod: Box<dyn Body>,
    init: &SliderCrankInit,
    guide: SliderGuide,
) -> Result<SliderCrank, Box<dyn std::error::Error>> {
    let lay = rod.layout();
    if lay.dim != 2 || lay.scene_dim != 2 {
        return Err("the slider-crank is planar: the rod must be a planar body generated for a planar scene".into());
    }
    let labels = lay.labels.clone();
    let n = last_node(&labels).ok_or("the rod has no node labels")?;
    if !n.is_multiple_of(2) {
        return Err(format!("the rod needs an even number of elements (has {n})").into());
    }
    let mid =
        dof_index(&labels, &format!("uy_{}", n / 2)).ok_or("the rod has no middle-node uy")?;
    let (q_f, qd_f) = match &init.elastic {
        RodElastic::Undeformed => (None, None),
        RodElastic::Fields { q, qd } => (
            Some(q.nodal_coordinates(&labels, ROD_LENGTH)?),
            Some(qd.nodal_coordinates(&labels, ROD_LENGTH)?),
        ),
        RodElastic::Coordinates { q_f, qd_f } => (Some(q_f.clone()), Some(qd_f.clone())),
    };
    let (lc, lr, w) = (CRANK_LENGTH, ROD_LENGTH, CRANK_SPEED);
    let mut sys: System<Box<dyn Body>> = System::planar();
    let crank = RigidBody::planar(
        CRANK_MASS,
        CRANK_INERTIA - CRANK_MASS * (lc / 2.0) * (lc / 2.0),
        Vector2::new(lc / 2.0, 0.0),
    )?;
    let c = sys.add_body("crank", Box::new(crank), Pose::planar(0.0, 0.0, 0.0))?;
    let r = sys.add_body("rod", rod, Pose::planar(lc, 0.0, init.rod_angle))?;
    let s = sys.add_body(
        "slider",
        Box::new(RigidBody::planar(SLIDER_MASS, 1e-6, Vector2::zeros())?),
        Pose::planar(init.slider_x, 0.0, 0.0),
    )?;
    // Crank: pivot at the origin, angle 150 t.
    sys.prescribe_rotation_about_z(c, Driver::linear(0.0, w))?;
    let crank_pin = sys.point(r, 0.0)?;
    sys.revolute(Marker::at(c, Vector3::new(lc, 0.0, 0.0)), crank_pin)?;
    let slider_pin = sys.point(r, lr)?;
    sys.revolute(slider_pin, Marker::origin(s))?;
    // Slider on the x axis, not turning.
    match guide {
        SliderGuide::Prismatic => {
            sys.prismatic(Marker::ground(Vector3::zeros()), Marker::origin(s))?
        }
        SliderGuide::Coordinates => {
            sys.prescribe_coordinate(s, 1, Driver::constant(0.0))?;
            sys.prescribe_coordinate(s, 2, Driver::constant(0.0))?;
        }
    }
    // Velocities at θ = 0: the crank tip (the rod origin) moves with l_c θ̇ along +y.
    sys.set_velocity(c, Vector3::zeros(), Vector3::new(0.0, 0.0, w))?;
    sys.set_velocity(
        r,
        Vector3::new(0.0, lc * w, 0.0),
        Vector3::new(0.0, 0.0, init.rod_rate),
    )?;
    sys.set_velocity(s, Vector3::new(init.slider_v, 0.0, 0.0), Vector3::zeros())?;
    if let (Some(q_f), Some(qd_f)) = (q_f, qd_f) {
        sys.set_elastic(r, &q_f, &qd_f)?;
    }
    let mid_uy = sys.body_entry(r).f_offset() + mid;
    Ok(SliderCrank {
        system: sys,
        crank: c,
        rod: r,
        slider: s,
        mid_uy,
    })
}

/// Samples of a slider-crank run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SliderCrankRun {
    /// Times (s).
    pub t: Vec<f64>,
    /// Rod angle `φ₂` (rad).
    pub rod_angle: Vec<f64>,
    /// Slider position `x₃` (m).
    pub slider_x: Vec<f64>,
    /// Midpoint deflection (m): `uy` of the rod's middle node.
    pub mid_deflection: Vec<f64>,
    /// Its rate (m/s).
    pub mid_velocity: Vec<f64>,
    /// Largest `‖Φ‖∞` over the run (joints).
    pub max_phi: f64,
    /// The rod's elastic coordinates at the end.
    pub rod_q_f: Vec<f64>,
    /// Their rates at the end.
    pub rod_qd_f: Vec<f64>,
    /// Newton iterations and iteration matrices.
    pub newton: (usize, usize),
    /// The final state of the system.
    pub last: Option<State>,
}

impl SliderCrank {
    /// Run to `t_end` with step `dt`, sampling rod angle, slider position and
    /// the midpoint deflection and its rate at every step.
    pub fn run_samples(
        &self,
        t_end: f64,
        dt: f64,
        integrator: &Integrator,
    ) -> Result<SliderCrankRun, RtError> {
        let mut out = SliderCrankRun::default();
        let sys = &self.system;
        let (ir, is) = (sys.offset(self.rod) + 2, sys.offset(self.slider));
        let (mut rbuf, mut vv) = (Vec::new(), Vec::new());
        let summary = sys.simulate(t_end, dt, integrator, |v| {
            let (q, qd) = (&v.state.q, &v.state.v);
            out.t.push(v.state.t);
            out.rod_angle.push(q[ir]);
            out.slider_x.push(q[is]);
            out.mid_deflection.push(q[self.mid_uy]);
            out.mid_velocity.push(qd[self.mid_uy]);
            let phi = crate::benchmarks::pendulum::constraint_violation(v, &mut rbuf, &mut vv).0;
            out.max_phi = out.max_phi.max(phi);
            ControlFlow::Continue(())
        })?;
        let e = sys.body_entry(self.rod);
        let (fo, nf) = (e.f_offset(), e.nf);
        out.rod_q_f = summary.last.q[fo..fo + nf].to_vec();
        out.rod_qd_f = summary.last.v[fo..fo + nf].to_vec();
        out.newton = (summary.newton_iterations, summary.jacobians);
        out.last = Some(summary.last);
        Ok(out)
    }
}

/// The generated rod: `elements` (even) `beam2` elements, consistent
/// formalism, `pinned` reference (chord frame), no geometric stiffening
/// (the benchmark's rod is linear), compiled kernels.
pub fn beam_rod(elements: usize) -> BeamSpec {
    BeamSpec {
        shape: "beam2".into(),
        elements,
        reference: Reference::Pinned,
        options: KernelOptions::new(),
        params: ROD,
        force_tape: false,
    }
}

/// The integrator of the study: generalized-α with `ρ∞ = 0.9` (slight
/// numerical damping of the unresolved axial and higher bending modes).
pub fn integrator() -> Integrator {
    Integrator::GeneralizedAlpha(GeneralizedAlpha::with_rho_inf(0.9))
}

/// Run the scene with `rod` from `init` to `t_end` with step `dt`.
pub fn simulate(
    rod: Box<dyn Body>,
    init: &SliderCrankInit,
    t_end: f64,
    dt: f64,
) -> Result<SliderCrankRun, Box<dyn std::error::Error>> {
    Ok(slider_crank_with(rod, init)?.run_samples(t_end, dt, &integrator())?)
}

/// Run the generated rod with `elements` elements from [`SIMEON_INIT`].
pub fn simulate_beam(
    elements: usize,
    t_end: f64,
    dt: f64,
) -> Result<SliderCrankRun, Box<dyn std::error::Error>> {
    simulate(
        Box::new(beam_rod(elements).body()?),
        &beam_init(&SIMEON_INIT),
        t_end,
        dt,
    )
}

/// Amplitude of the lateral sine mode `k` in a planar beam rod's deflection:
/// `a_k = (2/l) ∫₀ˡ v(x) sin(kπx/l) dx`, `v` the Hermite-cubic interpolation of
/// the nodal `uy_i`, `rz_i` (absent coordinates are zero), by 6-point
/// Gauss–Legendre quadrature per element. For a pinned–pinned rod the sines
/// are the exact bending modes, so `a_1`, `a_2` are what Simeon's `q₁`, `q₂`
/// approximate; the midpoint deflection is `a_1 − a_3 + a_5 − …`.
pub fn sine_amplitude(labels: &[String], q_f: &[f64], k: u32) -> f64 {
    let n = last_node(labels).unwrap_or(0);
    if n == 0 || q_f.len() != labels.len() {
        return f64::NAN;
    }
    let get =
        |kind: &str, i: usize| dof_index(labels, &format!("{kind}_{i}")).map_or(0.0, |j| q_f[j]);
    // 6-point Gauss–Legendre on [−1, 1].
    const X: [f64; 3] = [
        0.238_619_186_083_196_9,
        0.661_209_386_466_264_5,
        0.932_469_514_203_152,
    ];
    const W: [f64; 3] = [
        0.467_913_934_572_691,
        0.360_761_573_048_138_6,
        0.171_324_492_379_170_3,
    ];
    let (len, le) = (ROD_LENGTH, ROD_LENGTH / n as f64);
    let mut sum = 0.0;
    for e in 0..n {
        let (v1, t1, v2, t2) = (
            get("uy", e),
            get("rz", e),
            get("uy", e + 1),
            get("rz", e + 1),
        );
        for (xg, wg) in X
            .iter()
            .flat_map(|&x| [-x, x])
            .zip(W.iter().flat_map(|&w| [w, w]))
        {
            let s = 0.5 * (xg + 1.0);
            let v = (1.0 - 3.0 * s * s + 2.0 * s * s * s) * v1
                + le * (s - 2.0 * s * s + s * s * s) * t1
                + (3.0 * s * s - 2.0 * s * s * s) * v2
                + le * (-s * s + s * s * s) * t2;
            let x = (e as f64 + s) * le;
            sum += wg * 0.5 * le * v * (k as f64 * PI * x / len).sin();
        }
    }
    2.0 / len * sum
}

// ------------------------------------------------------------------ command line

/// Options of a slider-crank run.
#[derive(Args, Debug, Clone)]
pub struct SliderCrankArgs {
    /// Number of beam2 elements of the rod (even, 2 to 64).
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u16).range(2..=64))]
    pub elements: u16,
    /// Time step (s).
    #[arg(long, default_value_t = 2.5e-5)]
    pub dt: f64,
    /// End time (s); the published values are at 0.1 s.
    #[arg(long, default_value_t = T_END)]
    pub t_end: f64,
    /// Where to write `t,phi2,x3,mid_deflection` (default: results/slider_crank_nN.csv, N the elements).
    #[arg(long)]
    pub csv: Option<PathBuf>,
}

impl Default for SliderCrankArgs {
    fn default() -> Self {
        Self {
            elements: 8,
            dt: 2.5e-5,
            t_end: T_END,
            csv: None,
        }
    }
}

/// What a run produced.
pub struct Report {
    /// The samples.
    pub run: SliderCrankRun,
    /// Wall time of the simulation (s).
    pub wall: f64,
    /// CSV written.
    pub csv: PathBuf,
}

/// Check the options, run, write the CSV and print the comparison with the
/// published solution.
pub fn run(args: &SliderCrankArgs) -> Result<Report, Box<dyn std::error::Error>> {
    for (name, v) in [("--t-end", args.t_end), ("--dt", args.dt)] {
        if !v.is_finite() || v <= 0.0 {
            return Err(format!("{name} must be a positive number, found {v}").into());
        }
    }
    if args.dt > args.t_end {
        return Err(format!("--dt {} is longer than --t-end {}", args.dt, args.t_end).into());
    }
    if !args.elements.is_multiple_of(2) {
        return Err(format!(
            "--elements must be even (a node at the midpoint), found {}",
            args.elements
        )
        .into());
    }
    let csv = args.csv.clone().unwrap_or_else(|| {
        PathBuf::from("results").join(format!("slider_crank_n{}.csv", args.elements))
    });
    let t0 = Instant::now();
    let run = simulate_beam(args.elements as usize, args.t_end, args.dt)?;
    let wall = t0.elapsed().as_secs_f64();
    write_csv(&csv, &run)?;

    let steps = run.t.len().saturating_sub(1);
    crate::outln!(
        "flexible slider-crank (Simeon, IVP test set): crank 0.15 m at 150 rad/s, steel rod 0.3 m 8×8 mm as {} beam2 elements (pinned, consistent, compiled kernels), slider 0.075552 kg on a prismatic joint",
        args.elements
    )?;
    let last = run.t.len() - 1;
    crate::outln!(
        "t = {:.4} s: midpoint deflection {:.6e} m, phi2 {:.10} rad, x3 {:.10} m",
        run.t[last],
        run.mid_deflection[last],
        run.rod_angle[last],
        run.slider_x[last]
    )?;
    if (run.t[last] - T_END).abs() < 1e-9 {
        let rel = |a: f64, b: f64| (a - b) / b.abs();
        crate::outln!(
            "published at 0.1 s: midpoint deflection {:.6e} m ({:+.2} %), phi2 {:.10} ({:+.1e} rad), x3 {:.10} ({:+.1e} m)",
            PUBLISHED.q[0],
            100.0 * rel(run.mid_deflection[last], PUBLISHED.q[0]),
            PUBLISHED.phi2,
            run.rod_angle[last] - PUBLISHED.phi2,
            PUBLISHED.x3,
            run.slider_x[last] - PUBLISHED.x3,
        )?;
    } else {
        crate::outln!(
            "(the published values are at t = 0.1 s: midpoint deflection {:.6e} m)",
            PUBLISHED.q[0]
        )?;
    }
    let peak = run
        .mid_deflection
        .iter()
        .fold(0.0f64, |a, b| a.max(b.abs()));
    crate::outln!(
        "max |midpoint deflection| {peak:.4e} m, max ‖Φ‖∞ {:.1e}",
        run.max_phi
    )?;
    crate::outln!(
        "steps: {steps} of dt = {} s ({} Newton iterations, {} iteration matrices), wall time {wall:.3} s",
        args.dt, run.newton.0, run.newton.1
    )?;
    crate::outln!("wrote {}", csv.display())?;
    Ok(Report { run, wall, csv })
}

fn write_csv(path: &Path, r: &SliderCrankRun) -> std::io::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    let tmp = path.with_extension("csv.tmp");
    {
        let mut f = std::io::BufWriter::new(std::fs::File::create(&tmp)?);
        writeln!(f, "t,phi2,x3,mid_deflection")?;
        for i in 0..r.t.len() {
            writeln!(
                f,
                "{},{},{},{}",
                r.t[i], r.rod_angle[i], r.slider_x[i], r.mid_deflection[i]
            )?;
        }
        f.flush()?;
    }
    std::fs::rename(&tmp, path)
}
