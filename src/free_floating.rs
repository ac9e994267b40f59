//! A free-floating flexible body: a generated beam (`beam3` in space, `beam2`
//! in the plane; `pinned` reference, so the elastic coordinates exclude
//! rigid-body motion) with no joints, no gravity, no damping.
//!
//! Its linear momentum `p = ∫ρ ṙ dV` and angular momentum about the global
//! origin `H = ∫ρ r × ṙ dV` are exact invariants of the continuous equations
//! of motion. Two different statements are checked here, and they must not be
//! confused:
//!
//! 1. **Round-off (the equations of motion):** at arbitrary states `(q, q̇)`
//!    the accelerations `q̈` solved from the runtime's equations
//!    ([`System::accelerations`]) make the time derivatives `ṗ` and `Ḣ`,
//!    evaluated analytically from the invariants ([`momentum_rates`]), vanish
//!    to round-off relative to the size of the terms that cancel. This is an
//!    exact identity of the model (mass matrix, quadratic velocity vector,
//!    internal elastic forces), so any bound above a few hundred ulps would
//!    hide an error ([`check_rates`]).
//! 2. **Integrator accuracy (trajectories):** no integrator of the runtime
//!    conserves `p` or `H` exactly in these coordinates (both are nonlinear in
//!    `q`: `A(θ)`, `S_t(q_f)`, `Ī_θθ(q_f)`), so along a trajectory they drift by
//!    the global error of the integrator: `O(dt²)` for generalized-α,
//!    `O(dt⁴)` for RK4 ([`drift`], [`drift_study`]). That is not round-off and
//!    is not claimed to be. Only when an explicit step is so small that the
//!    truncation error falls below the accumulated round-off (RK4, 2-element
//!    bar, `dt = 2.5e-5 s`, `ω_max dt ≈ 0.2`) does the drift sit at the
//!    round-off floor, about 1e-14 relative after 8000 steps and growing with
//!    the number of steps: conservation to round-off by accuracy, not by the
//!    structure of the integrator. (In space this needs the exact `γ = −ėᵀė`
//!    of the Euler-parameter normalization in [`System::gamma`]; the former
//!    finite difference held `eᵀe − 1` near 1e-13 and the momenta with it.)
//!
//! Formulas (theory sheet; `ω̄ = Ḡθ̇` body angular velocity, `Ȧ = A ω̃`,
//! `ω̄̇ = Ḡθ̈` because `Ḡ̇θ̇ = 0` for one planar angle and for Euler parameters):
//!
//! - `p = m Ṙ + A (ω̄ × S_t + S̄ q̇_f)`, `Ṡ_t = S̄ q̇_f`,
//!   `ṗ = m R̈ + A ω̃ (ω̄ × S_t + S̄ q̇_f) + A (ω̄̇ × S_t + ω̄ × S̄ q̇_f + S̄ q̈_f)`;
//! - `H = R × p + (A S_t) × Ṙ + A h̄`, `h̄ = Ī_θθ ω̄ + Ī_θf q̇_f`,
//!   `Ḣ = Ṙ × p + R × ṗ + A(ω̄ × S_t + S̄ q̇_f) × Ṙ + (A S_t) × R̈ + A ω̃ h̄ + A ḣ̄`,
//!   `ḣ̄ = İ_θθ ω̄ + Ī_θθ ω̄̇ + İ_θf q̇_f + Ī_θf q̈_f`;
//! - `U̇_kl = (Ī_kl + Ī_lk)·q̇_f + q̇_fᵀ S̄_kl q_f + q_fᵀ S̄_kl q̇_f`,
//!   `İ_θθ = tr(U̇) I − U̇`; row `r` of `İ_θf` is `q̇_fᵀ (S̄_ab − S̄_ba)`,
//!   `(r, a, b)` cyclic.

use crate::codegen::{ParamValues, Reference};
use crate::evaluated::EvaluatedBody;
use crate::pendulum::{beam_body, Beam};
use crate::runtime::nalgebra::{
    Cholesky, DMatrix, DVector, Matrix3, Matrix3xX, SymmetricEigen, Vector3, Vector4,
};
use crate::runtime::scenes;
use crate::runtime::{BodyId, BodyModel, FlexBody, StepView, System};
use clap::Args;
use std::ops::ControlFlow;
use std::time::Instant;

/// A soft polymer bar (nylon-like), 1 m, 10 × 10 mm: free–free first bending
/// frequency about 95 rad/s, so a body spinning at a few rad/s visibly
/// couples rigid and elastic motion, while the highest (axial, rotary)
/// modes of a few elements stay within reach of an explicit step of 1e-4 s.
pub const POLYMER_BAR: ParamValues = ParamValues {
    length: 1.0,
    rho: 1150.0,
    area: 1.0e-4,
    iy: 1.0e-8 / 12.0,
    iz: 1.0e-8 / 12.0,
    e: 2.5e9,
    g: 0.9e9,
    j: 0.1406e-8,
};

/// The generated body: `beam` with `elements` elements, `pinned` reference.
/// `stiff == false` sets `E = G = 0` (generated inertia only, `K_ff = 0`).
pub fn free_body(
    beam: Beam,
    elements: usize,
    stiff: bool,
) -> Result<EvaluatedBody, crate::codegen::Error> {
    let mut p = POLYMER_BAR;
    if !stiff {
        p.e = 0.0;
        p.g = 0.0;
    }
    beam_body(beam, elements, Reference::Pinned, p)
}

/// Scene dimension of a free `beam`: 2 for `beam2` (in the plane), 3 for `beam3`.
pub fn scene_dim(beam: Beam) -> usize {
    match beam {
        Beam::Beam2 => 2,
        Beam::Beam3 => 3,
    }
}

// ------------------------------------------------------------ (1) round-off

/// `ṗ`, `Ḣ` at one state and the scales they are compared with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rates {
    /// `ṗ` (N).
    pub p_dot: Vector3<f64>,
    /// `Ḣ` about the global origin (N m).
    pub h_dot: Vector3<f64>,
    /// Sum of the norms of the terms of `ṗ` (what cancels).
    pub p_scale: f64,
    /// Sum of the norms of the terms of `Ḣ`, with `|R|·p_scale` for `R × ṗ`.
    pub h_scale: f64,
}

impl Rates {
    /// `|ṗ| / p_scale`.
    pub fn p_rel(&self) -> f64 {
        self.p_dot.norm() / self.p_scale
    }
    /// `|Ḣ| / h_scale`.
    pub fn h_rel(&self) -> f64 {
        self.h_dot.norm() / self.h_scale
    }
}

fn sum_with_scale(terms: &[Vector3<f64>]) -> (Vector3<f64>, f64) {
    terms
        .iter()
        .fold((Vector3::zeros(), 0.0), |(s, n), t| (s + t, n + t.norm()))
}

/// `ṗ` and `Ḣ` of body `m` at body coordinates `q`, velocities `v` and
/// accelerations `a`, from the invariants (module docs).
pub fn momentum_rates(m: &BodyModel, q: &[f64], v: &[f64], a: &[f64]) -> Rates {
    let (d, nth, fo) = (m.dim(), m.n_theta(), m.f_offset());
    let inv = m.invariants();
    let fr = m.frame(q);
    let t = m.inertia_terms(&q[fo..]);
    let vec3 = |s: &[f64]| {
        let mut x = Vector3::zeros();
        x.as_mut_slice()[..d].copy_from_slice(&s[..d]);
        x
    };
    let (r, rd, rdd) = (fr.r, vec3(v), vec3(a));
    let w: Vector3<f64> = &fr.g * DVector::from_column_slice(&v[d..d + nth]);
    let wd: Vector3<f64> = &fr.g * DVector::from_column_slice(&a[d..d + nth]);
    let qf = DVector::from_column_slice(&q[fo..]);
    let qfd = DVector::from_column_slice(&v[fo..]);
    let qfdd = DVector::from_column_slice(&a[fo..]);
    let aa = fr.a;
    let st_dot: Vector3<f64> = &inv.s_bar * &qfd;

    // Linear momentum.
    let pbar = w.cross(&t.s_t) + st_dot;
    let p = rd * inv.mass + aa * pbar;
    let (p_dot, p_scale) = sum_with_scale(&[
        rdd * inv.mass,
        aa * w.cross(&pbar),
        aa * wd.cross(&t.s_t),
        aa * w.cross(&st_dot),
        aa * (&inv.s_bar * &qfdd),
    ]);

    // Angular momentum.
    let mut ud = Matrix3::zeros();
    for k in 0..3 {
        for l in 0..3 {
            let s = &inv.s_kl[k][l];
            ud[(k, l)] = (&inv.i_kl[k][l] + &inv.i_kl[l][k]).dot(&qfd)
                + qfd.dot(&(s * &qf))
                + qf.dot(&(s * &qfd));
        }
    }
    let i_tt_dot = Matrix3::identity() * ud.trace() - ud;
    let mut i_tf_dot = Matrix3xX::zeros(m.nf());
    for (row, (ka, kb)) in [(1, 2), (2, 0), (0, 1)].into_iter().enumerate() {
        let rv = (inv.s_kl[ka][kb].transpose() - inv.s_kl[kb][ka].transpose()) * &qfd;
        i_tf_dot.set_row(row, &rv.transpose());
    }
    let hbar = t.i_theta_theta * w + &t.i_theta_f * &qfd;
    let hbar_dot = i_tt_dot * w + t.i_theta_theta * wd + i_tf_dot * &qfd + &t.i_theta_f * &qfdd;
    let ast = aa * t.s_t;
    let ast_dot = aa * pbar;
    let (h_dot, h_scale) = sum_with_scale(&[
        rd.cross(&p),
        r.cross(&p_dot),
        ast_dot.cross(&rd),
        ast.cross(&rdd),
        aa * w.cross(&hbar),
        aa * hbar_dot,
    ]);
    Rates {
        p_dot,
        h_dot,
        p_scale,
        h_scale: h_scale + r.norm() * p_scale,
    }
}

/// `ṗ` and `Ḣ` by central differences of the runtime's
/// [`BodyModel::momentum`] along the curve `(q + s q̇ + ½ s² q̈, q̇ + s q̈)`,
/// step `h`: an independent check of the formulas of [`momentum_rates`]
/// (truncation `O(h²)`). For Euler parameters `q̈` must satisfy
/// `eᵀë = −ėᵀė` so that the curve leaves the unit sphere only at `O(s³)`.
pub fn rates_by_differences(
    m: &BodyModel,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    h: f64,
) -> (Vector3<f64>, Vector3<f64>) {
    let at = |s: f64| {
        let qs: Vec<f64> = (0..q.len())
            .map(|i| q[i] + s * v[i] + 0.5 * s * s * a[i])
            .collect();
        let vs: Vec<f64> = (0..q.len()).map(|i| v[i] + s * a[i]).collect();
        m.momentum(&qs, &vs)
    };
    let ((p1, h1), (p0, h0)) = (at(h), at(-h));
    ((p1 - p0) / (2.0 * h), (h1 - h0) / (2.0 * h))
}

/// Deterministic pseudo-random numbers in `[-1, 1)` (a 64-bit LCG).
#[derive(Clone, Debug)]
pub struct Lcg(pub u64);

impl Lcg {
    /// The next number.
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// Sizes of a random state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateScales {
    /// Frame origin `R` (m).
    pub position: f64,
    /// Frame velocity `Ṙ` (m/s).
    pub velocity: f64,
    /// Angular velocity `ω̄` (rad/s).
    pub omega: f64,
    /// Elastic coordinates `q_f` (m, rad).
    pub q_f: f64,
    /// Elastic rates `q̇_f` (m/s, rad/s).
    pub qd_f: f64,
}

impl Default for StateScales {
    /// Large deformations (5 % of the length) and fast elastic rates: every
    /// `q_f`-dependent inertia term contributes well above round-off.
    fn default() -> Self {
        Self {
            position: 1.0,
            velocity: 1.0,
            omega: 2.0,
            q_f: 0.05,
            qd_f: 1.0,
        }
    }
}

impl StateScales {
    /// For a body with its real stiffness: elastic displacements of 1e-6 m
    /// (the 1 m polymer bar's axial stiffness `EA/l` is about 1e6 N/m per
    /// element), so that the elastic forces `K_ff q_f` are comparable to the
    /// inertial terms instead of swamping the velocity terms.
    pub fn elastic() -> Self {
        Self {
            q_f: 1e-6,
            qd_f: 0.1,
            ..Self::default()
        }
    }
}

/// A random state of body `m`: uniform components of the given sizes, unit
/// Euler parameters with `ė = ½ Ḡᵀ ω̄` (tangent to the unit sphere).
pub fn random_state(m: &BodyModel, rng: &mut Lcg, s: &StateScales) -> (Vec<f64>, Vec<f64>) {
    let (d, nth, fo, n) = (m.dim(), m.n_theta(), m.f_offset(), m.n_coords());
    let mut q = vec![0.0; n];
    let mut v = vec![0.0; n];
    for i in 0..d {
        q[i] = s.position * rng.next_f64();
        v[i] = s.velocity * rng.next_f64();
    }
    if nth == 1 {
        q[d] = std::f64::consts::PI * rng.next_f64();
        v[d] = s.omega * rng.next_f64();
    } else {
        let e = Vector4::new(
            rng.next_f64(),
            rng.next_f64(),
            rng.next_f64(),
            rng.next_f64(),
        )
        .normalize();
        q[d..d + 4].copy_from_slice(e.as_slice());
        let w = Vector3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) * s.omega;
        let ed = m.frame(&q).g.transpose() * w * 0.5;
        v[d..d + 4].copy_from_slice(ed.as_slice());
    }
    for i in fo..n {
        q[i] = s.q_f * rng.next_f64();
        v[i] = s.qd_f * rng.next_f64();
    }
    (q, v)
}

/// Accelerations of a one-body system without the quadratic velocity vector
/// (`M q̈ = Q − Q_v`): a deliberately wrong model, to show that the rate check
/// sees the velocity terms.
fn accelerations_without_qv(
    sys: &System,
    b: BodyId,
    q: &DVector<f64>,
    v: &DVector<f64>,
) -> DVector<f64> {
    let (n, mc) = (sys.n_coords(), sys.n_constraints());
    let c = sys.constraints(0.0, q);
    let mut k = DMatrix::zeros(n + mc, n + mc);
    k.view_mut((0, 0), (n, n)).copy_from(&sys.mass_matrix(q));
    k.view_mut((0, n), (n, mc)).copy_from(&c.jac.transpose());
    k.view_mut((n, 0), (mc, n)).copy_from(&c.jac);
    let mut rhs = DVector::zeros(n + mc);
    let qv = sys
        .body(b)
        .quadratic_velocity(sys.body_slice(b, q), sys.body_slice(b, v));
    rhs.rows_mut(0, n).copy_from(&(sys.forces(0.0, q, v) - qv));
    if mc > 0 {
        rhs.rows_mut(n, mc).copy_from(&sys.gamma(0.0, q, v));
    }
    let x = k.lu().solve(&rhs).expect("non-singular free-body system");
    x.rows(0, n).into()
}

/// The outcome of [`check_rates`].
#[derive(Clone, Debug, PartialEq)]
pub struct RateCheck {
    /// States evaluated.
    pub states: usize,
    /// Largest `|ṗ| / p_scale` with the runtime's accelerations.
    pub worst_p: f64,
    /// Largest `|Ḣ| / h_scale`.
    pub worst_h: f64,
    /// Largest `|ṗ|` (N) and `|Ḣ|` (N m).
    pub worst_abs: (f64, f64),
    /// Smallest `p_scale` and `h_scale` met.
    pub min_scale: (f64, f64),
    /// Smallest `|ṗ| / p_scale` and `|Ḣ| / h_scale` with `Q_v` left out of the
    /// equations (a wrong model: must be far above round-off).
    pub without_qv: (f64, f64),
    /// Largest difference between [`momentum_rates`] and
    /// [`rates_by_differences`] (step `1e-5 s`) for the wrong model's
    /// accelerations (where `ṗ`, `Ḣ` do not vanish), relative to the scales:
    /// the formulas themselves, checked against the runtime's momenta.
    pub formula_vs_differences: (f64, f64),
}

/// Evaluate [`momentum_rates`] at `states` random states of a free `beam`
/// (`stiff`: real `E`, `G`; else `K_ff = 0`, a purely inertial check).
pub fn check_rates(
    beam: Beam,
    elements: usize,
    stiff: bool,
    scales: &StateScales,
    states: usize,
    seed: u64,
) -> Result<RateCheck, Box<dyn std::error::Error>> {
    let body = free_body(beam, elements, stiff)?;
    let d = scene_dim(beam);
    let mut sys = if d == 2 {
        System::planar()
    } else {
        System::spatial()
    };
    let b = sys.add_body(Box::new(body), crate::runtime::Pose::identity(d))?;
    let mut rng = Lcg(seed);
    let mut out = RateCheck {
        states,
        worst_p: 0.0,
        worst_h: 0.0,
        worst_abs: (0.0, 0.0),
        min_scale: (f64::INFINITY, f64::INFINITY),
        without_qv: (f64::INFINITY, f64::INFINITY),
        formula_vs_differences: (0.0, 0.0),
    };
    for _ in 0..states {
        let (q, v) = random_state(sys.body(b), &mut rng, scales);
        let (q, v) = (DVector::from_vec(q), DVector::from_vec(v));
        let (a, _) = sys.accelerations(0.0, &q, &v, (0.0, 0.0))?;
        let m = sys.body(b);
        let r = momentum_rates(m, q.as_slice(), v.as_slice(), a.as_slice());
        out.worst_p = out.worst_p.max(r.p_rel());
        out.worst_h = out.worst_h.max(r.h_rel());
        out.worst_abs.0 = out.worst_abs.0.max(r.p_dot.norm());
        out.worst_abs.1 = out.worst_abs.1.max(r.h_dot.norm());
        out.min_scale.0 = out.min_scale.0.min(r.p_scale);
        out.min_scale.1 = out.min_scale.1.min(r.h_scale);
        let wrong = accelerations_without_qv(&sys, b, &q, &v);
        let rw = momentum_rates(m, q.as_slice(), v.as_slice(), wrong.as_slice());
        out.without_qv.0 = out.without_qv.0.min(rw.p_rel());
        out.without_qv.1 = out.without_qv.1.min(rw.h_rel());
        let (pd, hd) = rates_by_differences(m, q.as_slice(), v.as_slice(), wrong.as_slice(), 1e-5);
        let f = &mut out.formula_vs_differences;
        f.0 = f.0.max((pd - rw.p_dot).norm() / rw.p_scale);
        f.1 = f.1.max((hd - rw.h_dot).norm() / rw.h_scale);
    }
    Ok(out)
}

// ------------------------------------------------------------ (2) trajectories

/// The integrator of a trajectory: generalized-α runs with Newton
/// tolerances tightened to `rtol = 1e-12`, `atol = 1e-14` (see [`drift`]).
pub use crate::pendulum::Method;

/// Options of a free-floating run.
#[derive(Args, Clone, Debug, PartialEq)]
pub struct FreeFloatingArgs {
    /// Beam shape (beam2: in the plane; beam3: in space).
    #[arg(long, value_enum, default_value_t = Beam::Beam3)]
    pub beam: Beam,
    /// Number of elements of the 1 m bar (1 to 64).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u16).range(1..=64))]
    pub elements: u16,
    /// End time (s).
    #[arg(long, default_value_t = 0.2)]
    pub t_end: f64,
    /// Time step (s).
    #[arg(long, default_value_t = 1e-4)]
    pub dt: f64,
    /// Integrator.
    #[arg(long, value_enum, default_value_t = Method::Rk4)]
    pub method: Method,
    /// Initial elastic amplitude: largest nodal value of the first elastic mode (m).
    #[arg(long, default_value_t = 1e-3)]
    pub amplitude: f64,
}

impl Default for FreeFloatingArgs {
    fn default() -> Self {
        Self {
            beam: Beam::Beam3,
            elements: 2,
            t_end: 0.2,
            dt: 1e-4,
            method: Method::Rk4,
            amplitude: 1e-3,
        }
    }
}

/// Elastic modes of a body: `(ω_i, φ_i)` of `K_ff φ = ω² M_ff φ`, ascending,
/// each `φ` scaled to a largest component of 1.
pub fn elastic_modes(body: &dyn FlexBody) -> Vec<(f64, DVector<f64>)> {
    let inv = body.invariants();
    let l = Cholesky::new(inv.m_ff.clone())
        .expect("m_ff is positive definite")
        .l();
    let li = l.clone().try_inverse().expect("invertible Cholesky factor");
    let c = &li * &inv.k_ff * li.transpose();
    let c = (&c + c.transpose()) * 0.5;
    let eig = SymmetricEigen::new(c);
    let mut modes: Vec<(f64, DVector<f64>)> = (0..eig.eigenvalues.len())
        .map(|i| {
            let phi = li.transpose() * eig.eigenvectors.column(i);
            let s = phi.amax();
            (eig.eigenvalues[i].max(0.0).sqrt(), phi / s)
        })
        .collect();
    modes.sort_by(|a, b| a.0.total_cmp(&b.0));
    modes
}

/// The free-floating scene: frame velocity `(0.3, −0.1, 0.2)` m/s, angular
/// velocity `(0.5, 1, 2)` rad/s (in the plane only the z component), the
/// body deformed in its first elastic mode (amplitude `amplitude`) and moving
/// in its second at rate `ω₂ · amplitude`.
pub fn system(args: &FreeFloatingArgs) -> Result<(System, BodyId), Box<dyn std::error::Error>> {
    let body = free_body(args.beam, args.elements as usize, true)?;
    let modes = elastic_modes(&body);
    if modes.len() < 2 {
        return Err("the body needs at least two elastic modes".into());
    }
    let q_f = &modes[0].1 * args.amplitude;
    let qd_f = &modes[1].1 * (args.amplitude * modes[1].0);
    Ok(scenes::free_floating(
        Box::new(body),
        Vector3::new(0.3, -0.1, 0.2),
        Vector3::new(0.5, 1.0, 2.0),
        q_f.as_slice(),
        qd_f.as_slice(),
    )?)
}

/// Drift of the invariants along one trajectory.
#[derive(Clone, Debug, PartialEq)]
pub struct Drift {
    /// Step (s).
    pub dt: f64,
    /// Steps taken.
    pub steps: usize,
    /// `|p(0)|`, `|H(0)|`.
    pub p0: f64,
    /// `|H(0)|`.
    pub h0: f64,
    /// `max_t |p(t) − p(0)| / |p(0)|`.
    pub dp: f64,
    /// `max_t |H(t) − H(0)| / |H(0)|`.
    pub dh: f64,
    /// `max_t |E(t) − E(0)| / E(0)`.
    pub de: f64,
    /// Largest `‖Φ‖∞` (Euler-parameter normalization; 0 in the plane).
    pub max_phi: f64,
    /// Highest elastic frequency of the body (rad/s) and `ω_max · dt`.
    pub omega_max_dt: (f64, f64),
    /// Wall time (s).
    pub wall: f64,
}

/// Integrate the scene of `args` and record the drift of `p`, `H` and `E`.
pub fn drift(args: &FreeFloatingArgs) -> Result<Drift, Box<dyn std::error::Error>> {
    for (name, v) in [
        ("--t-end", args.t_end),
        ("--dt", args.dt),
        ("--amplitude", args.amplitude),
    ] {
        if !v.is_finite() || v <= 0.0 {
            return Err(format!("{name} must be a positive number, found {v}").into());
        }
    }
    let (sys, b) = system(args)?;
    let w_max = elastic_modes(sys.body(b).body())
        .last()
        .map_or(0.0, |m| m.0);
    let s0 = sys.initial_state(0.0)?;
    let (p0, h0) = sys.momentum(&s0.q, &s0.v);
    let e0 = sys.energy(&s0.q, &s0.v).total();
    let mut out = Drift {
        dt: args.dt,
        steps: 0,
        p0: p0.norm(),
        h0: h0.norm(),
        dp: 0.0,
        dh: 0.0,
        de: 0.0,
        max_phi: 0.0,
        omega_max_dt: (w_max, w_max * args.dt),
        wall: 0.0,
    };
    let t0 = Instant::now();
    let summary = sys.simulate(
        args.t_end,
        args.dt,
        &args.method.integrator_with_tolerances(1e-12, 1e-14),
        |v: &StepView| {
            let (q, qd) = (&v.state.q, &v.state.v);
            let (p, h) = sys.momentum(q, qd);
            out.dp = out.dp.max((p - p0).norm() / out.p0);
            out.dh = out.dh.max((h - h0).norm() / out.h0);
            out.de = out
                .de
                .max((sys.energy(q, qd).total() - e0).abs() / e0.abs());
            out.max_phi = out
                .max_phi
                .max(sys.constraint_violation(v.state.t, q, qd).0);
            ControlFlow::Continue(())
        },
    )?;
    out.wall = t0.elapsed().as_secs_f64();
    out.steps = summary.steps;
    Ok(out)
}

/// A drift study over several steps.
#[derive(Clone, Debug, PartialEq)]
pub struct DriftStudy {
    /// One run per step, in the order given.
    pub runs: Vec<Drift>,
    /// Observed orders `ln(d_i / d_{i+1}) / ln(dt_i / dt_{i+1})` of `(dp, dh)`
    /// between successive runs.
    pub orders: Vec<(f64, f64)>,
}

/// [`drift`] for each step in `steps`, with the observed orders.
pub fn drift_study(
    args: &FreeFloatingArgs,
    steps: &[f64],
) -> Result<DriftStudy, Box<dyn std::error::Error>> {
    let runs = steps
        .iter()
        .map(|&dt| drift(&FreeFloatingArgs { dt, ..args.clone() }))
        .collect::<Result<Vec<_>, _>>()?;
    let orders = runs
        .windows(2)
        .map(|w| {
            let r = (w[0].dt / w[1].dt).ln();
            ((w[0].dp / w[1].dp).ln() / r, (w[0].dh / w[1].dh).ln() / r)
        })
        .collect();
    Ok(DriftStudy { runs, orders })
}

/// One line describing the scene of `args`.
pub fn describe(args: &FreeFloatingArgs) -> String {
    format!(
        "free-floating {} × {} (polymer bar 1 m, 10 × 10 mm, pinned reference), {}, no forces",
        args.elements,
        args.beam.name(),
        if scene_dim(args.beam) == 2 {
            "in the plane"
        } else {
            "in space"
        }
    )
}
