//! The flexible slider-crank of B. Simeon (Test Set for IVP Solvers, problem
//! "Slider crank"; Simeon 1996): rigid crank driven at 150 rad/s, flexible
//! steel connecting rod, sliding block; no gravity, no damping, linear
//! stiffness, `0 ≤ t ≤ 0.1 s`. The rod is a generated `beam2` body
//! (consistent formalism, `pinned` reference, evaluated on tapes), started
//! from the benchmark's consistent initial values and compared with its
//! published solution at `t = 0.1 s`.
//!
//! The benchmark discretizes the rod (frame: x from the crank pin to the
//! slider pin) by two lateral modes `v = q₁ sin(πξ) + q₂ sin(2πξ)`, `ξ = x/l`,
//! and a quadratic axial ansatz `u = q₃ 4ξ(1−ξ) + q₄ ξ(2ξ−1)` (`q₃`, `q₄`: axial
//! displacement of the midpoint and of the slider end), section rotary
//! inertia neglected. The midpoint deflection is exactly `q₁`.
//! [`simeon_rod`] rebuilds that rod in the runtime from its invariants, to
//! check the scene against the published numbers with the benchmark's own
//! discretization and to measure what the discretization changes.

use crate::codegen::{BodySpec, Options, ParamValues, Reference, Shape};
use crate::evaluated::EvaluatedBody;
use crate::runtime::nalgebra::{Matrix3, Vector3};
use crate::runtime::scenes::{
    self, BeamField, RodElastic, SliderCrankInit, SliderCrankRun, ROD_LENGTH,
};
use crate::runtime::{
    FlexBody, GeneralizedAlpha, InertiaTerms, Integrator, InvariantBody, Invariants,
};
use clap::Args;
use std::f64::consts::PI;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

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
pub const ROD: ParamValues = ParamValues {
    length: ROD_LENGTH,
    rho: DENSITY,
    area: ROD_WIDTH * ROD_HEIGHT,
    iy: ROD_HEIGHT * ROD_WIDTH * ROD_WIDTH * ROD_WIDTH / 12.0,
    iz: ROD_WIDTH * ROD_HEIGHT * ROD_HEIGHT * ROD_HEIGHT / 12.0,
    e: YOUNG,
    g: YOUNG / 2.6,
    j: 0.1406 * ROD_WIDTH * ROD_WIDTH * ROD_WIDTH * ROD_WIDTH,
};

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

/// End time of the benchmark (s).
pub const T_END: f64 = 0.1;

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

/// The generated rod: `elements` (even) `beam2` elements, consistent
/// formalism, `pinned` reference (chord frame), no geometric stiffening.
pub fn beam_rod(elements: usize) -> Result<EvaluatedBody, crate::codegen::Error> {
    let spec = BodySpec::new(Shape::resolve("beam2", None)?, elements, Reference::Pinned)?;
    EvaluatedBody::new(&spec, Options { stiffening: false }, ROD)
}

/// Simeon's own rod discretization as a runtime body, from its invariants
/// (consistent FFR inertia of the shape functions above, no section terms in
/// `S`, `J₂ = m (l²/3 + h²/12)` as in the benchmark data). The axial block
/// of `S̄_xx` (and so of `m_ff`) is multiplied by `axial_mass_factor`: the
/// benchmark's code (`crank.f`) uses `ρbhl·[8 1; 1 2]` where the quadratic
/// ansatz gives `ρbhl/15·[8 1; 1 2]` — pass 15 to reproduce it, 1 for the
/// ansatz's own mass. Elastic coordinates `(q₁, q₂, q₃, q₄)` carry the labels
/// `uy_1, mode2, ux_1, ux_2` (node 1 the midpoint, node 2 the slider pin), so
/// the scene finds the pins and the midpoint. With `rotary_inertia` the section's
/// rotary inertia (the `−y v'` axial displacement of the beam shapes), which
/// the benchmark neglects, is added.
pub fn simeon_rod(axial_mass_factor: f64, rotary_inertia: bool) -> Box<dyn FlexBody> {
    let (l, h, a) = (ROD_LENGTH, ROD_HEIGHT, ROD_WIDTH * ROD_HEIGHT);
    let m = DENSITY * a * l;
    let ei = YOUNG * ROD_WIDTH * h * h * h / 12.0;
    let ea = YOUNG * a;
    let mut inv = Invariants::zeros(2, 4);
    inv.mass = m;
    inv.s_t0 = Vector3::new(m * l / 2.0, 0.0, 0.0);
    // ∫ S_x dξ = (0, 0, 2/3, 1/6), ∫ S_y dξ = (2/π, 0, 0, 0).
    inv.s_bar[(0, 2)] = m * 2.0 / 3.0;
    inv.s_bar[(0, 3)] = m / 6.0;
    inv.s_bar[(1, 0)] = m * 2.0 / PI;
    let (x, y) = (0, 1);
    let f = axial_mass_factor;
    for (i, j, v) in [(2, 2, 8.0), (2, 3, 1.0), (3, 2, 1.0), (3, 3, 2.0)] {
        inv.s_kl[x][x][(i, j)] = f * m * v / 15.0;
    }
    inv.s_kl[y][y][(0, 0)] = m / 2.0;
    inv.s_kl[y][y][(1, 1)] = m / 2.0;
    if rotary_inertia {
        // S_x gains −y v'(x): ∫ρ S_xᵀ S_x gains ρ I_z ∫ v'_k² dx = m h²/12 (kπ/l)²/2
        // (all other invariants unchanged: ∫y dA = 0, v_k(0) = v_k(l) = 0).
        for k in 0..2 {
            let kp = (k + 1) as f64 * PI / l;
            inv.s_kl[x][x][(k, k)] = m * h * h / 12.0 * kp * kp / 2.0;
        }
    }
    // S̄_xy(a, b) = ∫ρ S_x,a S_y,b: ∫N₃ sin πξ = 16/π³, ∫N₄ sin πξ = 1/π − 8/π³,
    // ∫N₄ sin 2πξ = −1/(2π), ∫N₃ sin 2πξ = 0.
    let p3 = PI * PI * PI;
    for (i, j, v) in [
        (2, 0, 16.0 / p3),
        (3, 0, 1.0 / PI - 8.0 / p3),
        (3, 1, -0.5 / PI),
    ] {
        inv.s_kl[x][y][(i, j)] = m * v;
        inv.s_kl[y][x][(j, i)] = m * v;
    }
    // Ī_xx = ∫ρ x S_x = m l (0, 0, 1/3, 1/6), Ī_xy = ∫ρ x S_y = m l (1/π, −1/(2π), 0, 0).
    inv.i_kl[x][x][2] = m * l / 3.0;
    inv.i_kl[x][x][3] = m * l / 6.0;
    inv.i_kl[x][y][0] = m * l / PI;
    inv.i_kl[x][y][1] = -m * l / (2.0 * PI);
    inv.theta = Matrix3::from_diagonal(&Vector3::new(m * l * l / 3.0, m * h * h / 12.0, 0.0));
    inv.m_ff = &inv.s_kl[x][x] + &inv.s_kl[y][y];
    // K: EI π⁴/(2 l³) (1, 16) laterally, EA/l [16/3 −8/3; −8/3 7/3] axially.
    let kb = ei * PI.powi(4) / (2.0 * l * l * l);
    inv.k_ff[(0, 0)] = kb;
    inv.k_ff[(1, 1)] = 16.0 * kb;
    for (i, j, v) in [
        (2, 2, 16.0 / 3.0),
        (2, 3, -8.0 / 3.0),
        (3, 2, -8.0 / 3.0),
        (3, 3, 7.0 / 3.0),
    ] {
        inv.k_ff[(i, j)] = ea / l * v;
    }
    Box::new(SimeonRod(InvariantBody::new(inv)))
}

/// Initial conditions for [`simeon_rod`] from a state of Simeon's model.
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

struct SimeonRod(InvariantBody);

impl FlexBody for SimeonRod {
    fn nf(&self) -> usize {
        4
    }
    fn dim(&self) -> usize {
        2
    }
    fn dof_labels(&self) -> Vec<String> {
        ["uy_1", "mode2", "ux_1", "ux_2"].map(String::from).to_vec()
    }
    fn invariants(&self) -> Invariants {
        self.0.invariants()
    }
    fn inertia_terms(&self, q_f: &[f64], out: &mut InertiaTerms) {
        self.0.inertia_terms(q_f, out)
    }
}

/// The integrator of the study: generalized-α with `ρ∞ = 0.9` (slight
/// numerical damping of the unresolved axial and higher bending modes).
pub fn integrator() -> Integrator {
    Integrator::GeneralizedAlpha(GeneralizedAlpha::with_rho_inf(0.9))
}

/// Run the scene with `rod` from `init` to `t_end` with step `dt`.
pub fn simulate(
    rod: Box<dyn FlexBody>,
    init: &SliderCrankInit,
    t_end: f64,
    dt: f64,
) -> Result<SliderCrankRun, crate::runtime::Error> {
    scenes::slider_crank_with(rod, init)?.run_samples(t_end, dt, &integrator())
}

/// Run the generated rod with `elements` elements from [`SIMEON_INIT`].
pub fn simulate_beam(
    elements: usize,
    t_end: f64,
    dt: f64,
) -> Result<SliderCrankRun, Box<dyn std::error::Error>> {
    let rod = beam_rod(elements)?;
    Ok(simulate(
        Box::new(rod),
        &beam_init(&SIMEON_INIT),
        t_end,
        dt,
    )?)
}

/// Amplitude of the lateral sine mode `k` in a planar beam rod's deflection:
/// `a_k = (2/l) ∫₀ˡ v(x) sin(kπx/l) dx`, `v` the Hermite-cubic interpolation of
/// the nodal `uy_i`, `rz_i` (absent coordinates are zero), by 6-point
/// Gauss–Legendre quadrature per element. For a pinned–pinned rod the sines
/// are the exact bending modes, so `a_1`, `a_2` are what Simeon's `q₁`, `q₂`
/// approximate; the midpoint deflection is `a_1 − a_3 + a_5 − …`.
pub fn sine_amplitude(labels: &[String], q_f: &[f64], k: u32) -> f64 {
    let n = scenes::last_node(labels).unwrap_or(0);
    if n == 0 || q_f.len() != labels.len() {
        return f64::NAN;
    }
    let get = |kind: &str, i: usize| {
        crate::runtime::marker::dof_index(labels, &format!("{kind}_{i}")).map_or(0.0, |j| q_f[j])
    };
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
    /// Where to write `t,phi2,x3,mid_deflection` (default: results/slider_crank_n<elements>.csv).
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
    if args.elements % 2 != 0 {
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
    println!(
        "flexible slider-crank (Simeon, IVP test set): crank 0.15 m at 150 rad/s, steel rod 0.3 m 8×8 mm as {} beam2 elements (pinned, consistent), slider 0.075552 kg",
        args.elements
    );
    let last = run.t.len() - 1;
    println!(
        "t = {:.4} s: midpoint deflection {:.6e} m, phi2 {:.10} rad, x3 {:.10} m",
        run.t[last], run.mid_deflection[last], run.rod_angle[last], run.slider_x[last]
    );
    if (run.t[last] - T_END).abs() < 1e-9 {
        let rel = |a: f64, b: f64| (a - b) / b.abs();
        println!(
            "published at 0.1 s: midpoint deflection {:.6e} m ({:+.2} %), phi2 {:.10} ({:+.1e} rad), x3 {:.10} ({:+.1e} m)",
            PUBLISHED.q[0],
            100.0 * rel(run.mid_deflection[last], PUBLISHED.q[0]),
            PUBLISHED.phi2,
            run.rod_angle[last] - PUBLISHED.phi2,
            PUBLISHED.x3,
            run.slider_x[last] - PUBLISHED.x3,
        );
    } else {
        println!(
            "(the published values are at t = 0.1 s: midpoint deflection {:.6e} m)",
            PUBLISHED.q[0]
        );
    }
    let peak = run
        .mid_deflection
        .iter()
        .fold(0.0f64, |a, b| a.max(b.abs()));
    println!("max |midpoint deflection| {peak:.4e} m");
    println!(
        "steps: {steps} of dt = {} s, wall time {wall:.3} s",
        args.dt
    );
    println!("wrote {}", csv.display());
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
