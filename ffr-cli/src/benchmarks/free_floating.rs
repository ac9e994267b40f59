//! A free-floating flexible body: a beam (`beam3` in space, `beam2` in the
//! plane; `pinned` reference, so the elastic coordinates exclude rigid-body
//! motion; compiled kernels) with no joints, no gravity, no damping.
//!
//! Its linear momentum `p = ∫ρ ṙ dV` and angular momentum about the global
//! origin `H = ∫ρ r × ṙ dV` are exact invariants of the continuous equations
//! of motion. Two different statements are checked here, and they must not be
//! confused:
//!
//! 1. **Round-off (the equations of motion):** at arbitrary states `(q, q̇)`
//!    the accelerations `q̈` the runtime solves from its equations (the
//!    consistent initial state of a system started there,
//!    [`System::initial_state`]) make the time derivatives `ṗ` and `Ḣ`,
//!    evaluated analytically from the body's mass blocks and invariants
//!    ([`momentum_rates`]), vanish to round-off relative to the size of the
//!    terms that cancel. This is an exact identity of the model (inertia
//!    forces, elastic forces), so any bound above a few hundred ulps would
//!    hide an error ([`check_rates`]).
//! 2. **Integrator accuracy (trajectories):** no integrator of the runtime
//!    conserves `p` or `H` exactly in these coordinates (both are nonlinear in
//!    `q`: `A(θ)`, `S_t(q_f)`, `Ī_θθ(q_f)`), so along a trajectory they drift by
//!    the global error of the integrator: `O(dt²)` for generalized-α,
//!    `O(dt⁴)` for RK4 ([`drift`], [`drift_study`]). That is not round-off and
//!    is not claimed to be. Only when an explicit step is so small that the
//!    truncation error falls below the accumulated round-off does the drift
//!    sit at the round-off floor: conservation to round-off by accuracy, not
//!    by the structure of the integrator.
//!
//! Formulas (theory: `docs/theory.md`; `ω̄ = Ḡθ̇` body angular velocity,
//! `Ȧ = A ω̃`, `ω̄̇ = Ḡθ̈` because `Ḡ̇θ̇ = 0` for one planar angle and for Euler
//! parameters):
//!
//! - `p = m Ṙ + A (ω̄ × S_t + S̄ q̇_f)`, `Ṡ_t = S̄ q̇_f`,
//!   `ṗ = m R̈ + A ω̃ (ω̄ × S_t + S̄ q̇_f) + A (ω̄̇ × S_t + ω̄ × S̄ q̇_f + S̄ q̈_f)`;
//! - `H = R × p + (A S_t) × Ṙ + A h̄`, `h̄ = Ī_θθ ω̄ + Ī_θf q̇_f`,
//!   `Ḣ = Ṙ × p + R × ṗ + A(ω̄ × S_t + S̄ q̇_f) × Ṙ + (A S_t) × R̈ + A ω̃ h̄ + A ḣ̄`,
//!   `ḣ̄ = İ_θθ ω̄ + Ī_θθ ω̄̇ + İ_θf q̇_f + Ī_θf q̈_f`;
//! - `U̇_kl = (Ī_kl + Ī_lk)·q̇_f + q̇_fᵀ S̄_kl q_f + q_fᵀ S̄_kl q̇_f`,
//!   `İ_θθ = tr(U̇) I − U̇`; row `r` of `İ_θf` is `q̇_fᵀ (S̄_ab − S̄_ba)`,
//!   `(r, a, b)` cyclic.

use crate::benchmarks::pendulum::{beam_spec, constraint_violation, Beam, BeamScene};
use clap::Args;
use ffr::kernels::{BeamSpec, Kernels};
use ffr::runtime::nalgebra::{
    Cholesky, DMatrix, DVector, Matrix3, Matrix3xX, Quaternion, SymmetricEigen, UnitQuaternion,
    Vector3, Vector4,
};
use ffr::runtime::rotation::Rotation;
use ffr::runtime::spec::{Params, Reference};
use ffr::runtime::{Assembly, Body, BodyId, BodyMass, KernelBody, Pose, System};
use std::ops::ControlFlow;
use std::time::Instant;

pub use crate::benchmarks::pendulum::Method;

/// A soft polymer bar (nylon-like), 1 m, 10 × 10 mm: free–free first bending
/// frequency about 95 rad/s, so a body spinning at a few rad/s visibly
/// couples rigid and elastic motion, while the highest (axial, rotary)
/// modes of a few elements stay within reach of an explicit step of 1e-4 s.
pub const POLYMER_BAR: Params = Params {
    length: 1.0,
    rho: 1150.0,
    area: 1.0e-4,
    iy: 1.0e-8 / 12.0,
    iz: 1.0e-8 / 12.0,
    e: 2.5e9,
    g: 0.9e9,
    j: 0.1406e-8,
};

/// Young's and shear moduli of the "inertia only" bar (Pa): parameters a
/// body uses must be positive, so instead of `E = G = 0` the bar gets moduli
/// whose elastic forces, about 1e-200 of the inertial ones, are zero to every
/// digit the checks can see.
pub const NEGLIGIBLE_E: f64 = 1e-200;

/// The body's description: `beam` with `elements` elements, `pinned`
/// reference. `stiff == false` sets `E` and `G` to [`NEGLIGIBLE_E`]
/// (generated inertia only, `K_ff ≈ 0`).
pub fn free_spec(beam: Beam, elements: usize, stiff: bool) -> BeamSpec {
    let mut p = POLYMER_BAR;
    if !stiff {
        p.e = NEGLIGIBLE_E;
        p.g = NEGLIGIBLE_E;
    }
    beam_spec(beam, elements, Reference::Pinned, p)
}

/// The body (compiled kernels).
pub fn free_body(
    beam: Beam,
    elements: usize,
    stiff: bool,
) -> Result<KernelBody<Kernels>, Box<dyn std::error::Error>> {
    Ok(free_spec(beam, elements, stiff).body()?)
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

/// `ṗ` and `Ḣ` of `body` in a scene of dimension `d` at its coordinates
/// `q = [R (d), θ (1 or 4), q_f]`, velocities `v` and accelerations `a`:
/// the values `S_t`, `S̄`, `Ī_θθ`, `Ī_θf` from the body's mass blocks (what
/// its equations use), their rates from its invariants (module docs).
pub fn momentum_rates<B: Body + ?Sized>(
    body: &B,
    d: usize,
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> Rates {
    let nth = if d == 2 { 1 } else { 4 };
    let fo = d + nth;
    let lay = body.layout();
    let nf = lay.nf;
    let inv = body.invariants();
    let mut work = body.work();
    let mut mass = BodyMass::zeros(nf, lay.half_bandwidth);
    body.mass(&q[fo..], &mut work, &mut mass);
    let rot = Rotation::new(&q[d..fo]);
    let vec3 = |s: &[f64]| {
        let mut x = Vector3::zeros();
        x.as_mut_slice()[..d].copy_from_slice(&s[..d]);
        x
    };
    let (r, rd, rdd) = (vec3(q), vec3(v), vec3(a));
    let w = rot.omega(&v[d..fo]);
    let wd = rot.omega(&a[d..fo]);
    let qf = DVector::from_column_slice(&q[fo..]);
    let qfd = DVector::from_column_slice(&v[fo..]);
    let qfdd = DVector::from_column_slice(&a[fo..]);
    let aa = rot.a;
    let s_t = Vector3::from(mass.s_t);
    let s_bar = Matrix3xX::from_fn(nf, |i, j| mass.m_ref_f[i * nf + j]);
    let i_tf = Matrix3xX::from_fn(nf, |i, j| mass.m_ref_f[(3 + i) * nf + j]);
    let i_tt = Matrix3::from_fn(|i, j| mass.m_ref_frame[(3 + i) * 6 + 3 + j]);
    let st_dot: Vector3<f64> = &s_bar * &qfd;

    // Linear momentum.
    let pbar = w.cross(&s_t) + st_dot;
    let p = rd * inv.mass + aa * pbar;
    let (p_dot, p_scale) = sum_with_scale(&[
        rdd * inv.mass,
        aa * w.cross(&pbar),
        aa * wd.cross(&s_t),
        aa * w.cross(&st_dot),
        aa * (&s_bar * &qfdd),
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
    let mut i_tf_dot = Matrix3xX::zeros(nf);
    for (row, (ka, kb)) in [(1, 2), (2, 0), (0, 1)].into_iter().enumerate() {
        let rv = (inv.s_kl[ka][kb].transpose() - inv.s_kl[kb][ka].transpose()) * &qfd;
        i_tf_dot.set_row(row, &rv.transpose());
    }
    let hbar = i_tt * w + &i_tf * &qfd;
    let hbar_dot = i_tt_dot * w + i_tt * wd + i_tf_dot * &qfd + &i_tf * &qfdd;
    let ast = aa * s_t;
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
/// [`Assembly::momentum`] along the curve `(q + s q̇ + ½ s² q̈, q̇ + s q̈)`,
/// step `h`: an independent check of the formulas of [`momentum_rates`]
/// (truncation `O(h²)`). For Euler parameters `q̈` must satisfy
/// `eᵀë = −ėᵀė` so that the curve leaves the unit sphere only at `O(s³)`.
pub fn rates_by_differences<B: Body>(
    asm: &mut Assembly<B>,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    h: f64,
) -> (Vector3<f64>, Vector3<f64>) {
    let mut at = |s: f64| {
        let qs: Vec<f64> = (0..q.len())
            .map(|i| q[i] + s * v[i] + 0.5 * s * s * a[i])
            .collect();
        let vs: Vec<f64> = (0..q.len()).map(|i| v[i] + s * a[i]).collect();
        asm.momentum(&qs, &vs)
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
    /// Angular velocity `ω` (rad/s).
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

/// A one-body system holding `body` at a random state: uniform components
/// of the given sizes, a random orientation (uniform angle in the plane, a
/// normalized random quaternion in space), a random angular velocity
/// (global axes; only z in the plane).
pub fn random_system<B: Body>(
    body: B,
    rng: &mut Lcg,
    s: &StateScales,
) -> Result<(System<B>, BodyId), Box<dyn std::error::Error>> {
    let d = body.layout().scene_dim;
    let nf = body.layout().nf;
    let mut sys = System::with_dim(d);
    let mut r = || rng.next_f64();
    let pos = Vector3::new(r(), r(), if d == 3 { r() } else { 0.0 }) * s.position;
    let vel = Vector3::new(r(), r(), if d == 3 { r() } else { 0.0 }) * s.velocity;
    let pose = if d == 2 {
        Pose::planar(pos.x, pos.y, std::f64::consts::PI * r())
    } else {
        let e = Vector4::new(r(), r(), r(), r()).normalize();
        Pose::spatial(
            pos,
            UnitQuaternion::from_quaternion(Quaternion::new(e[0], e[1], e[2], e[3])),
        )
    };
    let omega = if d == 2 {
        Vector3::new(0.0, 0.0, r())
    } else {
        Vector3::new(r(), r(), r())
    } * s.omega;
    let q_f: Vec<f64> = (0..nf).map(|_| s.q_f * r()).collect();
    let qd_f: Vec<f64> = (0..nf).map(|_| s.qd_f * r()).collect();
    let b = sys.add_body("body", body, pose)?;
    sys.set_velocity(b, vel, omega)?;
    sys.set_elastic(b, &q_f, &qd_f)?;
    Ok((sys, b))
}

/// Accelerations of a system without the velocity terms of its equations
/// (`M q̈ + Φ_qᵀ λ = Q(q, 0)`, `Φ_q q̈ = γ(q, q̇)`): a deliberately wrong
/// model, to show that the rate check sees the quadratic velocity terms.
pub fn accelerations_without_velocity_terms<B: Body>(
    asm: &mut Assembly<B>,
    q: &[f64],
    v: &[f64],
) -> Result<Vec<f64>, Box<dyn std::error::Error>> {
    let (n, m) = (asm.n, asm.m);
    let zeros = vec![0.0; n];
    let mut r = vec![0.0; n + m];
    asm.residual(0.0, q, &zeros, &zeros, &vec![0.0; m], &mut r);
    let mut gam = vec![0.0; m];
    asm.gamma(0.0, v, &mut gam);
    asm.mass_system(0.0, q);
    asm.factor(0.0, "mass system")?;
    let mut rhs = vec![0.0; n + m];
    for i in 0..n {
        rhs[i] = -r[i];
    }
    rhs[n..].copy_from_slice(&gam);
    let mut x = vec![0.0; n + m];
    asm.solve(&rhs, &mut x);
    x.truncate(n);
    Ok(x)
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
    /// Smallest `|ṗ| / p_scale` and `|Ḣ| / h_scale` with the velocity terms
    /// left out of the equations (a wrong model: must be far above round-off).
    pub without_qv: (f64, f64),
    /// Largest difference between [`momentum_rates`] and
    /// [`rates_by_differences`] (step `1e-5 s`) for the wrong model's
    /// accelerations (where `ṗ`, `Ḣ` do not vanish), relative to the scales:
    /// the formulas themselves, checked against the runtime's momenta.
    pub formula_vs_differences: (f64, f64),
}

/// Evaluate [`momentum_rates`] at `states` random states of a free `beam`
/// (`stiff`: real `E`, `G`; else `K_ff ≈ 0`, a purely inertial check), with
/// the accelerations of the consistent initial state the runtime computes
/// for a system started there.
pub fn check_rates(
    beam: Beam,
    elements: usize,
    stiff: bool,
    scales: &StateScales,
    states: usize,
    seed: u64,
) -> Result<RateCheck, Box<dyn std::error::Error>> {
    let spec = free_spec(beam, elements, stiff);
    check_rates_of(|| Ok(spec.body()?), scales, states, seed)
}

/// [`check_rates`] for the free bodies `body()` makes (e.g. with attached
/// masses), in the scene dimension the body is written for.
pub fn check_rates_of<B: Body>(
    body: impl Fn() -> Result<B, Box<dyn std::error::Error>>,
    scales: &StateScales,
    states: usize,
    seed: u64,
) -> Result<RateCheck, Box<dyn std::error::Error>> {
    let d = body()?.layout().scene_dim;
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
        let (sys, b) = random_system(body()?, &mut rng, scales)?;
        let s = sys.initial_state(0.0)?;
        let (q, v, a) = (&s.q, &s.v, &s.a);
        let body = sys.body(b);
        let r = momentum_rates(body, d, q, v, a);
        out.worst_p = out.worst_p.max(r.p_rel());
        out.worst_h = out.worst_h.max(r.h_rel());
        out.worst_abs.0 = out.worst_abs.0.max(r.p_dot.norm());
        out.worst_abs.1 = out.worst_abs.1.max(r.h_dot.norm());
        out.min_scale.0 = out.min_scale.0.min(r.p_scale);
        out.min_scale.1 = out.min_scale.1.min(r.h_scale);
        let mut asm = Assembly::new(&sys)?;
        let wrong = accelerations_without_velocity_terms(&mut asm, q, v)?;
        let rw = momentum_rates(body, d, q, v, &wrong);
        out.without_qv.0 = out.without_qv.0.min(rw.p_rel());
        out.without_qv.1 = out.without_qv.1.min(rw.h_rel());
        let (pd, hd) = rates_by_differences(&mut asm, q, v, &wrong, 1e-5);
        let f = &mut out.formula_vs_differences;
        f.0 = f.0.max((pd - rw.p_dot).norm() / rw.p_scale);
        f.1 = f.1.max((hd - rw.h_dot).norm() / rw.h_scale);
    }
    Ok(out)
}

// ------------------------------------------------------------ (2) trajectories

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
    /// Integrator (generalized-α with ρ∞ = 1 and the Newton tolerance
    /// tightened to 1e-12, or RK4).
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
pub fn elastic_modes<B: Body + ?Sized>(body: &B) -> Vec<(f64, DVector<f64>)> {
    let inv = body.invariants();
    let l = Cholesky::new(inv.m_ff.clone())
        .expect("m_ff is positive definite")
        .l();
    let li: DMatrix<f64> = l.try_inverse().expect("invertible Cholesky factor");
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

/// A free body (no joints, no forces) at pose `(0.1, −0.2, 0.3)` (plane:
/// angle 0.3; space: Euler angles `(0.2, −0.3, 0.5)`), frame velocity `v`,
/// angular velocity `omega` (global; only z in the plane) and elastic state
/// `(q_f, q̇_f)`.
pub fn scene<B: Body>(
    body: B,
    v: Vector3<f64>,
    omega: Vector3<f64>,
    q_f: &[f64],
    qd_f: &[f64],
) -> Result<(System<B>, BodyId), Box<dyn std::error::Error>> {
    let d = body.layout().scene_dim;
    let mut sys = System::with_dim(d);
    let pose = if d == 2 {
        Pose::planar(0.1, -0.2, 0.3)
    } else {
        Pose::spatial(
            Vector3::new(0.1, -0.2, 0.3),
            UnitQuaternion::from_euler_angles(0.2, -0.3, 0.5),
        )
    };
    let b = sys.add_body("body", body, pose)?;
    sys.set_velocity(b, v, omega)?;
    sys.set_elastic(b, q_f, qd_f)?;
    Ok((sys, b))
}

/// The free-floating scene: frame velocity `(0.3, −0.1, 0.2)` m/s, angular
/// velocity `(0.5, 1, 2)` rad/s (in the plane only the z component), the
/// body deformed in its first elastic mode (amplitude `amplitude`) and moving
/// in its second at rate `ω₂ · amplitude`.
pub fn system(args: &FreeFloatingArgs) -> Result<BeamScene, Box<dyn std::error::Error>> {
    let body = free_body(args.beam, args.elements as usize, true)?;
    let modes = elastic_modes(&body);
    if modes.len() < 2 {
        return Err("the body needs at least two elastic modes".into());
    }
    let q_f = &modes[0].1 * args.amplitude;
    let qd_f = &modes[1].1 * (args.amplitude * modes[1].0);
    scene(
        body,
        Vector3::new(0.3, -0.1, 0.2),
        Vector3::new(0.5, 1.0, 2.0),
        q_f.as_slice(),
        qd_f.as_slice(),
    )
}

/// Drift of the invariants along one trajectory.
#[derive(Clone, Debug, PartialEq)]
pub struct Drift {
    /// Step (s).
    pub dt: f64,
    /// Steps taken.
    pub steps: usize,
    /// `|p(0)|`.
    pub p0: f64,
    /// `|H(0)|`.
    pub h0: f64,
    /// `max_t |p(t) − p(0)| / |p(0)|`.
    pub dp: f64,
    /// `max_t |H(t) − H(0)| / |H(0)|`.
    pub dh: f64,
    /// `max_t |E(t) − E(0)| / E(0)`.
    pub de: f64,
    /// Largest `‖Φ‖∞` (Euler-parameter normalization `½(eᵀe − 1)`; 0 in the plane).
    pub max_phi: f64,
    /// Highest elastic frequency of the body (rad/s) and `ω_max · dt`.
    pub omega_max_dt: (f64, f64),
    /// Newton iterations and iteration matrices (generalized-α).
    pub newton: (usize, usize),
    /// Wall time (s).
    pub wall: f64,
}

/// Newton tolerance of the trajectories with generalized-α (relative, on
/// the accelerations): tighter than the default 1e-10 so that the drift
/// measured is the discretization error, not the iteration's.
pub const DRIFT_RTOL: f64 = 1e-12;

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
    let w_max = elastic_modes(sys.body(b)).last().map_or(0.0, |m| m.0);
    let mut out = Drift {
        dt: args.dt,
        steps: 0,
        p0: f64::NAN,
        h0: f64::NAN,
        dp: 0.0,
        dh: 0.0,
        de: 0.0,
        max_phi: 0.0,
        omega_max_dt: (w_max, w_max * args.dt),
        newton: (0, 0),
        wall: 0.0,
    };
    let (mut p0, mut h0, mut e0) = (Vector3::zeros(), Vector3::zeros(), 0.0);
    let (mut rbuf, mut vv) = (Vec::new(), Vec::new());
    let t0 = Instant::now();
    let summary = sys.simulate(
        args.t_end,
        args.dt,
        &args.method.integrator_with(1.0, DRIFT_RTOL),
        |v| {
            let (p, h) = v.momentum();
            let e = v.energy().total();
            if v.step == 0 {
                (p0, h0, e0) = (p, h, e);
                out.p0 = p.norm();
                out.h0 = h.norm();
            }
            out.dp = out.dp.max((p - p0).norm() / out.p0);
            out.dh = out.dh.max((h - h0).norm() / out.h0);
            out.de = out.de.max((e - e0).abs() / e0.abs());
            out.max_phi = out
                .max_phi
                .max(constraint_violation(v, &mut rbuf, &mut vv).0);
            ControlFlow::Continue(())
        },
    )?;
    out.wall = t0.elapsed().as_secs_f64();
    out.steps = summary.steps;
    out.newton = (summary.newton_iterations, summary.jacobians);
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
        "free-floating {} × {} (polymer bar 1 m, 10 × 10 mm, pinned reference, compiled kernels), {}, no forces",
        args.elements,
        args.beam.name(),
        if args.beam.scene_dim() == 2 {
            "in the plane"
        } else {
            "in space"
        }
    )
}
