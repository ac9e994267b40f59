//! Static equilibrium and steady rotation: one Newton driver with load
//! stepping, shared by `ffr static`, `ffr linearize --at static` and the
//! steady state of a Campbell diagram ([`crate::linear::steady_state`]).
//!
//! # The equations
//!
//! At rest (`q̇ = q̈ = 0`, prescribed coordinates held at their values at
//! `t`, their rates zero) the residual of the equations of motion is the
//! static balance `r(q, λ) = −Q(q) + Φ_qᵀ λ = 0`, `Φ(q, t) = 0` over the
//! free coordinates and the multipliers, with the tangent
//!
//! ```text
//! J = [K + ∂(Φ_qᵀ λ)/∂q, Φ_qᵀ; Φ_q, 0],   K = ∂r/∂q,
//! ```
//!
//! the stiffness part of the generalized-α iteration matrix, assembled in
//! the same bordered block-banded structure
//! ([`Assembly::static_matrix`]): the cost and memory of an iteration are
//! those of a time step. A steady rotation about the global z axis at the
//! rate `Ω` ([`SteadyMotion::Rotation`]) has `q̇(q)`, `q̈(q)` of the rigid
//! rotation and the exact tangent `K + C ∂q̇/∂q + M ∂q̈/∂q` (dense, from
//! [`Assembly::tangent_parts`]; the Campbell scenes are small).
//!
//! # Load stepping
//!
//! Gravity and the applied loads (point forces, constant motor torques)
//! are scaled by the load factor `λ ∈ [0, 1]` ([`Assembly::set_load_scale`]);
//! for a steady rotation also `Ω² → λ Ω²` (the centrifugal load). Whatever
//! else is out of balance at the start — a spring away from its rest
//! length, a PD motor away from its target, a given initial deflection —
//! is released by the same factor: the equations of increment `λ` are
//!
//! ```text
//! R(q, λ_mult; λ) = r_λ(q, λ_mult) − (1 − λ) r₀ = 0,   Φ(q, t) = 0,
//! ```
//!
//! with `r₀` the residual of the free coordinates at the start without
//! loads (`λ = 0`, no multipliers), so the start solves `λ = 0` exactly
//! and `λ = 1` is the scene's problem. Automatic stepping tries the whole
//! load at once; a failed increment is tried again from the last converged
//! state with half the increment (at most [`MAX_HALVINGS`] times, and
//! after two quick successes the increment doubles again, never beyond
//! its first value). `steps = K` takes `K` equal increments and fails if
//! one does. Each increment starts from the last converged state.
//!
//! # Newton's iteration
//!
//! `J Δ = −R`, `q += Δ_q`, `λ_mult += Δ_λ`, on the exact tangent (so it
//! converges quadratically). Converged when every update of a free
//! coordinate is below `10⁻¹⁰` of its scale — its own `|q|`, plus the
//! largest `|q|` of its class (a body's frame translations, frame
//! rotations, elastic translations, elastic rotations; a beam's two
//! elastic classes linked by its length), plus `10⁻⁶` of the largest of
//! all — and every multiplier update likewise relative to its joint's
//! multipliers; or when the updates stop shrinking within `10⁴` of that
//! tolerance (round-off), as the integrator judges its steps. At most
//! [`MAX_ITERATIONS`] iterations per increment; a non-finite residual or
//! update fails the increment.
//!
//! At rest the iteration keeps to stable equilibria. The sign of `det J`
//! (from the factors, [`Assembly::det_sign`]) is `(−1)^m sign det K̂`,
//! `K̂ = NᵀKN` the stiffness on the constraint manifold (`m` constraint
//! rows, `N` a null-space basis of `Φ_q`). Where `K̂` is singular or has
//! `det K̂ < 0` (an odd number of unstable directions: a pendulum above
//! its pivot or horizontal), or where a Newton update would turn a body
//! frame by more than 0.5 rad, the matrix is shifted by the mass matrix,
//! `J + μ [M 0; 0 0]` (`μ` raised 16-fold until the shifted stiffness is
//! positive in that sense and the step short; lowered 16-fold after each
//! step, to 0). The shifted update is a step of heavily damped motion
//! towards a stable equilibrium (pseudo-transient continuation), so a
//! pendulum released horizontal reaches its hanging state. At the state
//! reached (`λ = 1`) the unshifted `J` is checked: a zero pivot, a
//! singular direction (the solution of `J̃ y = b` for the
//! unit-free equilibrated `J̃ = D_r J D_c` larger than `1/(64 ε)`: the
//! coordinate that dominates `y` is named) or `det K̂ < 0` is an error — a
//! mechanism (an equilibrium that is not unique: a free body, a pendulum
//! with no load along its swing) or an unstable equilibrium. An even
//! number of unstable directions leaves `det K̂ > 0` and is not seen.
//! Neither the shift nor these checks apply to a steady rotation, whose
//! stability involves the gyroscopic terms (the Campbell eigenvalues show
//! it).

use crate::assembly::Assembly;
use crate::body::Body;
use crate::error::{Error, Result};
use crate::integrator::State;
use crate::interrupt::Interrupt;
use crate::linear::{steady_rates, SteadyMotion};
use crate::system::System;
use nalgebra::DMatrix;

/// The most load increments (`steps`), automatic or fixed.
pub const MAX_STEPS: usize = 10_000;
/// Newton iterations per load increment.
pub const MAX_ITERATIONS: usize = 100;
/// A failed increment is halved at most this many times in a row (to
/// `2⁻¹²` of the load).
pub const MAX_HALVINGS: u32 = 12;
/// Relative tolerance on the Newton updates.
pub const RTOL: f64 = 1e-10;
/// Failed increments of one automatic path, in all.
const MAX_FAILURES: u32 = 2 * MAX_HALVINGS;
/// The mass shift is raised at most this many times in one iteration.
const MAX_SHIFTS: usize = 40;
/// The largest frame rotation of one update (rad): a planar angle; an
/// Euler parameter changes by half of it.
const MAX_TURN: f64 = 0.5;
/// The equilibrated inverse of a singular matrix: beyond this the matrix
/// is singular to working precision.
const SINGULAR: f64 = 1.0 / (64.0 * f64::EPSILON);

/// Why a state is unstable.
const INDEFINITE: &str = "the tangent stiffness on the constraint manifold has a negative determinant (an odd number of unstable directions)";

/// The message of an equilibrium that is not unique.
fn mechanism(load: f64, why: &str) -> String {
    format!(
        "the scene is a mechanism under its loads: at the equilibrium reached (load fraction {load}) {why}, so the equilibrium is not unique (e.g. a free body, or a pendulum with no load along its swing); hold that motion by a joint, a spring or a load"
    )
}

/// The message of an unstable equilibrium.
fn unstable(load: f64, why: &str) -> String {
    format!(
        "the equilibrium reached (load fraction {load}) is unstable: {why}, e.g. a pendulum balanced above its pivot or a column past its buckling load; start the scene nearer a stable equilibrium"
    )
}

/// How the load is stepped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StaticOptions {
    /// `Some(K)`: `K` equal load increments (`1 ≤ K ≤` [`MAX_STEPS`]), an
    /// error if one fails; `None`: automatic (the whole load, halved on
    /// failure).
    pub steps: Option<usize>,
}

/// A static equilibrium or steady state, and how it was reached.
#[derive(Clone, Debug, PartialEq)]
pub struct Equilibrium {
    /// The state (`q̇ = q̈ = 0` at rest; the rigid rotation's rates for a
    /// steady rotation).
    pub state: State,
    /// Load increments that converged.
    pub steps: usize,
    /// Newton iterations, in all (also those of failed increments).
    pub iterations: usize,
}

/// The static equilibrium of `sys` under its loads at time `t` from
/// `start` (module documentation): prescribed coordinates held at their
/// values at `t`, gravity, point forces and motor torques at their values
/// at `t`, stepped from 0 as `options` says.
pub fn static_equilibrium<B: Body>(
    sys: &System<B>,
    t: f64,
    start: &State,
    options: &StaticOptions,
) -> Result<Equilibrium> {
    equilibrium(sys, t, start, SteadyMotion::Rest, options)
}

/// The steady state of `sys` with `motion` (rest: [`static_equilibrium`];
/// a rotation: the centrifugal load stepped with the loads) from `start`.
pub fn equilibrium<B: Body>(
    sys: &System<B>,
    t: f64,
    start: &State,
    motion: SteadyMotion,
    options: &StaticOptions,
) -> Result<Equilibrium> {
    equilibrium_interruptible(sys, t, start, motion, options, Interrupt::NEVER)
}

/// [`equilibrium`], polling `interrupt` at every Newton iteration: when it
/// asks to stop, [`Error::Interrupted`].
pub fn equilibrium_interruptible<B: Body>(
    sys: &System<B>,
    t: f64,
    start: &State,
    motion: SteadyMotion,
    options: &StaticOptions,
    interrupt: Interrupt<'_>,
) -> Result<Equilibrium> {
    if let Some(k) = options.steps {
        if !(1..=MAX_STEPS).contains(&k) {
            return Err(Error::InvalidInput(format!(
                "{k} load increments: between 1 and {MAX_STEPS}"
            )));
        }
    }
    if !t.is_finite() {
        return Err(Error::InvalidInput(format!("t = {t} is not finite")));
    }
    if let SteadyMotion::Rotation { center, omega } = motion {
        if !(omega.is_finite() && center.iter().all(|x| x.is_finite())) {
            return Err(Error::InvalidInput(format!(
                "a steady rotation at Ω = {omega} rad/s about {center:?}: not finite"
            )));
        }
    }
    if let SteadyMotion::Rotation { .. } = motion {
        // The steady rotation's Newton matrix is dense.
        crate::linear::check_dense_size(sys, 0)?;
    }
    let n = sys.n_coords();
    if start.q.len() != n {
        return Err(Error::InvalidInput(format!(
            "the start has {} coordinates, the system {n}",
            start.q.len()
        )));
    }
    let mut path = Path::new(sys, t, motion, interrupt)?;
    path.run(start, options)
}

/// What went wrong in one increment.
enum Failure {
    /// No convergence in [`MAX_ITERATIONS`].
    NoConvergence { update: f64 },
    /// The matrix stayed singular or indefinite (or a step too long) and
    /// no shift helps: why.
    Stuck(String),
    /// A non-finite residual.
    NonFinite,
    /// An equilibrium was found that is not unique (`singular`) or not
    /// stable: no smaller increment changes that.
    Fatal { singular: bool, why: String },
    /// The caller asked to stop ([`Interrupt`]).
    Interrupted,
}

/// The outcome of one factorization.
enum Factored {
    /// The sign of `det J`.
    Ok(f64),
    /// Singular: where.
    Singular(String),
}

struct Path<'s, B: Body> {
    asm: Assembly<'s, B>,
    sys: &'s System<B>,
    interrupt: Interrupt<'s>,
    t: f64,
    motion: SteadyMotion,
    what: &'static str,
    n: usize,
    m: usize,
    free: Vec<usize>,
    is_free: Vec<bool>,
    /// Free frame-rotation coordinates and the largest update of each.
    turns: Vec<(usize, f64)>,
    r: Vec<f64>,
    r0: Vec<f64>,
    rhs: Vec<f64>,
    x: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    /// Prescribed rates and accelerations at `t` (a steady rotation scales
    /// them with the speed).
    presc_v: Vec<f64>,
    presc_a: Vec<f64>,
    /// The dense factors of a steady rotation.
    dense: Option<nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>>,
    coord_class: Vec<u32>,
    mult_class: Vec<u32>,
    class_link: Vec<crate::assembly::ClassLink>,
    coord_classes: usize,
    class_max: Vec<f64>,
    class_floor: Vec<f64>,
    /// The first shift (lazily, from the first state that needs one).
    mu_start: Option<f64>,
    /// Why the last unshifted matrix was refused (for messages).
    last_problem: Option<String>,
}

impl<'s, B: Body> Path<'s, B> {
    fn new(
        sys: &'s System<B>,
        t: f64,
        motion: SteadyMotion,
        interrupt: Interrupt<'s>,
    ) -> Result<Self> {
        let asm = Assembly::new(sys)?;
        let (n, m) = (asm.n, asm.m);
        let free = asm.free_coordinates();
        let mut is_free = vec![false; n];
        for &c in &free {
            is_free[c] = true;
        }
        let mut turns = Vec::new();
        for b in sys.bodies() {
            let o = b.offset + b.d;
            let bound = if b.n_theta == 1 {
                MAX_TURN
            } else {
                0.5 * MAX_TURN
            };
            turns.extend(
                (o..o + b.n_theta)
                    .filter(|&c| is_free[c])
                    .map(|c| (c, bound)),
            );
        }
        let (cc, mc, links) = asm.classes();
        let (coord_class, mult_class, class_link) = (cc.to_vec(), mc.to_vec(), links.to_vec());
        let coord_classes = coord_class
            .iter()
            .map(|&k| k as usize + 1)
            .max()
            .unwrap_or(0);
        let classes = class_link.len();
        Ok(Self {
            asm,
            sys,
            interrupt,
            t,
            motion,
            what: match motion {
                SteadyMotion::Rest => "static equilibrium",
                SteadyMotion::Rotation { .. } => "steady state",
            },
            n,
            m,
            free,
            is_free,
            turns,
            r: vec![0.0; n + m],
            r0: vec![0.0; n + m],
            rhs: vec![0.0; n + m],
            x: vec![0.0; n + m],
            v: vec![0.0; n],
            a: vec![0.0; n],
            presc_v: vec![0.0; n],
            presc_a: vec![0.0; n],
            dense: None,
            coord_class,
            mult_class,
            class_link,
            coord_classes,
            class_max: vec![0.0; classes],
            class_floor: vec![0.0; classes],
            mu_start: None,
            last_problem: None,
        })
    }

    fn at_rest(&self) -> bool {
        self.motion == SteadyMotion::Rest
    }

    fn error(&self, reason: String) -> Error {
        Error::NoEquilibrium {
            what: self.what,
            t: self.t,
            reason,
        }
    }

    /// `q̇`, `q̈` at load factor `load`: zero at rest (the prescribed
    /// coordinates held); the rigid rotation at `√load Ω` with the
    /// prescribed rates scaled alike. The derivatives `∂q̇/∂q`, `∂q̈/∂q`.
    fn set_rates(&mut self, load: f64, q: &[f64]) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
        match self.motion {
            SteadyMotion::Rest => None,
            SteadyMotion::Rotation { center, omega } => {
                let s = load.sqrt();
                for c in 0..self.n {
                    if !self.is_free[c] {
                        self.v[c] = s * self.presc_v[c];
                        self.a[c] = load * self.presc_a[c];
                    }
                }
                let w = SteadyMotion::Rotation {
                    center,
                    omega: s * omega,
                };
                Some(steady_rates(
                    self.sys,
                    &self.free,
                    w,
                    q,
                    &mut self.v,
                    &mut self.a,
                ))
            }
        }
    }

    /// The residual at `(q, λ)` with the load factor `load` into `self.r`.
    fn residual(&mut self, load: f64, q: &[f64], lam: &[f64]) {
        self.asm.set_load_scale(load);
        self.set_rates(load, q);
        self.asm
            .residual(self.t, q, &self.v, &self.a, lam, &mut self.r);
    }

    /// Assemble the (shifted) tangent and the residual at `(q, λ)` with
    /// the load factor `load`, and factor it.
    fn evaluate(&mut self, load: f64, q: &[f64], lam: &[f64], mu: f64) -> Factored {
        self.asm.set_load_scale(load);
        let rates = self.set_rates(load, q);
        let t = self.t;
        match rates {
            None => {
                self.asm
                    .static_matrix(t, q, &self.v, &self.a, lam, mu, 0.0, &mut self.r);
                match self.asm.factor(t, "static tangent stiffness") {
                    Ok(()) => Factored::Ok(self.asm.det_sign()),
                    Err(Error::Singular { detail, .. }) => Factored::Singular(detail),
                    Err(e) => Factored::Singular(e.to_string()),
                }
            }
            Some((dv, da)) => {
                let parts = self.asm.tangent_parts(t, q, &self.v, &self.a, lam);
                self.asm.residual(t, q, &self.v, &self.a, lam, &mut self.r);
                let (nu, m) = (self.free.len(), self.m);
                let mut jm = DMatrix::zeros(nu + m, nu + m);
                let mut kk = &parts.k + &parts.c * &dv + &parts.m * &da;
                if mu != 0.0 {
                    kk += &parts.m * mu;
                }
                jm.view_mut((0, 0), (nu, nu)).copy_from(&kk);
                jm.view_mut((0, nu), (nu, m))
                    .copy_from(&parts.phi_q.transpose());
                jm.view_mut((nu, 0), (m, nu)).copy_from(&parts.phi_q);
                let lu = jm.lu();
                if lu.is_invertible() {
                    self.dense = Some(lu);
                    // The sign is not used: a steady rotation is not
                    // checked for stability here (module documentation).
                    Factored::Ok(1.0)
                } else {
                    self.dense = None;
                    Factored::Singular(
                        "the dense steady-state matrix [K + C ∂q̇/∂q + M ∂q̈/∂q, Φ_qᵀ; Φ_q, 0] has a zero pivot".into(),
                    )
                }
            }
        }
    }

    /// `x = J⁻¹ rhs` with the factors of the last [`Path::evaluate`].
    fn solve(&mut self) {
        match &self.dense {
            Some(lu) if !self.at_rest() => {
                let (n, m) = (self.n, self.m);
                let nu = self.free.len();
                let b = nalgebra::DVector::from_iterator(
                    nu + m,
                    self.free
                        .iter()
                        .map(|&c| self.rhs[c])
                        .chain((0..m).map(|k| self.rhs[n + k])),
                );
                let y = lu.solve(&b);
                self.x.iter_mut().for_each(|x| *x = 0.0);
                match y {
                    Some(y) => {
                        for (i, &c) in self.free.iter().enumerate() {
                            self.x[c] = y[i];
                        }
                        for k in 0..m {
                            self.x[n + k] = y[nu + k];
                        }
                    }
                    None => self.x.iter_mut().for_each(|x| *x = f64::NAN),
                }
            }
            _ => self.asm.solve(&self.rhs, &mut self.x),
        }
    }

    /// `rhs = −R`: the residual of the free coordinates less `(1 − λ) r₀`,
    /// and of the constraint rows.
    fn set_rhs(&mut self, load: f64) {
        let n = self.n;
        for c in 0..n {
            self.rhs[c] = if self.is_free[c] {
                -(self.r[c] - (1.0 - load) * self.r0[c])
            } else {
                0.0
            };
        }
        for k in 0..self.m {
            self.rhs[n + k] = -self.r[n + k];
        }
    }

    /// The largest update relative to its tolerance: coordinates, then
    /// multipliers (module documentation).
    fn update_error(&mut self, q: &[f64], lam: &[f64]) -> (f64, f64) {
        let n = self.n;
        self.class_max.iter_mut().for_each(|x| *x = 0.0);
        for &c in &self.free {
            let k = self.coord_class[c] as usize;
            self.class_max[k] = self.class_max[k].max(q[c].abs());
        }
        for (k, l) in lam.iter().enumerate() {
            let cl = self.mult_class[k] as usize;
            self.class_max[cl] = self.class_max[cl].max(l.abs());
        }
        for (k, link) in self.class_link.iter().enumerate() {
            self.class_floor[k] =
                crate::assembly::class_floor(self.class_max[k], link, &self.class_max);
        }
        let (coords, mults) = self
            .class_max
            .split_at(self.coord_classes.min(self.class_max.len()));
        let q_all = coords.iter().fold(0.0f64, |s, x| s.max(*x));
        let l_all = mults.iter().fold(0.0f64, |s, x| s.max(*x));
        let mut err_q = 0.0f64;
        for &c in &self.free {
            let k = self.coord_class[c] as usize;
            let scale =
                RTOL * (q[c].abs() + self.class_floor[k] + 1e-6 * q_all) + f64::MIN_POSITIVE;
            err_q = err_q.max(self.x[c].abs() / scale);
        }
        let mut err_l = 0.0f64;
        for (k, l) in lam.iter().enumerate() {
            let cl = self.mult_class[k] as usize;
            let scale = RTOL * (l.abs() + self.class_max[cl] + 1e-6 * l_all) + f64::MIN_POSITIVE;
            err_l = err_l.max(self.x[n + k].abs() / scale);
        }
        (err_q, err_l)
    }

    /// Whether the determinant's sign says `det K̂ < 0` (at rest).
    fn indefinite(&self, sign: f64) -> bool {
        let parity = if self.m.is_multiple_of(2) { 1.0 } else { -1.0 };
        self.at_rest() && sign * parity < 0.0
    }

    /// The first mass shift `μ` (1/s²): `10⁻⁶` of the largest
    /// `|J_cc|/M_cc` of the free coordinates (the stiffest coordinate's
    /// frequency squared), and at least what turns a frame by about the
    /// step bound under its present residual (`|R_c|/(bound · M_cc)`);
    /// `1` if both are 0 (a mechanism of rigid bodies without load).
    fn first_shift(&mut self, load: f64, q: &[f64], lam: &[f64]) -> f64 {
        if let Some(mu) = self.mu_start {
            return mu;
        }
        let t = self.t;
        let mass = self.asm.mass_diagonal(q, &self.free);
        self.asm.set_load_scale(load);
        let mut r = vec![0.0; self.n + self.m];
        self.asm
            .static_matrix(t, q, &self.v, &self.a, lam, 0.0, 0.0, &mut r);
        let stiff = self.asm.matrix_diagonal(&self.free);
        let mut w2 = 0.0f64;
        for (k, s) in mass.iter().zip(&stiff) {
            if *k > 0.0 {
                w2 = w2.max(s.abs() / k);
            }
        }
        let mut turn = 0.0f64;
        for &(c, bound) in &self.turns {
            let i = self.free.binary_search(&c).expect("a free coordinate");
            if mass[i] > 0.0 {
                turn = turn.max(self.rhs[c].abs() / (bound * mass[i]));
            }
        }
        let mu = (1e-6 * w2).max(turn);
        let mu = if mu > 0.0 && mu.is_finite() { mu } else { 1.0 };
        self.mu_start = Some(mu);
        mu
    }

    /// Newton's iteration for the load factor `load` from `(q, λ)`.
    fn newton(
        &mut self,
        load: f64,
        q: &mut [f64],
        lam: &mut [f64],
        iterations: &mut usize,
    ) -> std::result::Result<(), Failure> {
        let (n, m) = (self.n, self.m);
        let shift_allowed = self.at_rest();
        let mut mu = 0.0f64;
        let mut mu_restart = 0.0f64;
        let mut shifted_converged = false;
        // Smallest updates since the last shift (round-off detection).
        let (mut least, mut least_l) = (f64::INFINITY, f64::INFINITY);
        let mut pure = 0usize;
        let mut last = f64::INFINITY;
        for _ in 0..MAX_ITERATIONS {
            if self.interrupt.requested() {
                return Err(Failure::Interrupted);
            }
            let mut shifts = 0;
            loop {
                let f = self.evaluate(load, q, lam, mu);
                self.set_rhs(load);
                if !self.rhs.iter().all(|x| x.is_finite()) {
                    return Err(Failure::NonFinite);
                }
                // What is wrong with this matrix or its update, and
                // whether it is singular (rather than indefinite).
                let problem = match f {
                    Factored::Singular(d) => {
                        Some((true, format!("the tangent stiffness is singular ({d})")))
                    }
                    Factored::Ok(sign) if self.indefinite(sign) => {
                        Some((false, INDEFINITE.to_string()))
                    }
                    Factored::Ok(_) => {
                        self.solve();
                        if !self.x.iter().all(|x| x.is_finite()) {
                            Some((true, "the Newton update is not finite".to_string()))
                        } else if shift_allowed
                            && self.turns.iter().any(|&(c, bound)| self.x[c].abs() > bound)
                        {
                            Some((
                                true,
                                format!(
                                    "the Newton update turns a body frame by more than {MAX_TURN} rad (a nearly singular tangent stiffness)"
                                ),
                            ))
                        } else {
                            None
                        }
                    }
                };
                let Some((singular, why)) = problem else {
                    break;
                };
                if mu == 0.0 {
                    if shifted_converged {
                        return Err(Failure::Fatal { singular, why });
                    }
                    self.last_problem = Some(why.clone());
                }
                if !shift_allowed || shifts >= MAX_SHIFTS {
                    return Err(Failure::Stuck(why));
                }
                mu = if mu > 0.0 {
                    16.0 * mu
                } else if mu_restart > 0.0 {
                    mu_restart
                } else {
                    self.first_shift(load, q, lam)
                };
                shifts += 1;
            }
            for &c in &self.free {
                q[c] += self.x[c];
            }
            for k in 0..m {
                lam[k] += self.x[n + k];
            }
            *iterations += 1;
            let (err_q, err_l) = self.update_error(q, lam);
            let err = err_q.max(err_l);
            last = err;
            if mu == 0.0 {
                shifted_converged = false;
                let stalled = pure >= 1 && err >= 0.5 * least && err <= 1e4;
                let mults_stalled = m > 0 && err_q <= 1.0 && pure >= 1 && err_l >= 0.5 * least_l;
                if err <= 1.0 || stalled || mults_stalled {
                    return Ok(());
                }
                least = least.min(err);
                least_l = least_l.min(err_l);
                pure += 1;
            } else {
                let start = self.mu_start.unwrap_or(mu);
                if err <= 1.0 && mu <= start {
                    // The state is an equilibrium (a shifted step that
                    // does not move it): now without the shift.
                    shifted_converged = true;
                    mu_restart = 16.0 * mu;
                    mu = 0.0;
                } else {
                    mu /= 16.0;
                    if mu < 1e-8 * start {
                        mu_restart = 16.0 * mu;
                        mu = 0.0;
                    }
                }
                least = f64::INFINITY;
                least_l = f64::INFINITY;
                pure = 0;
            }
        }
        Err(Failure::NoConvergence { update: last })
    }

    /// Why an increment failed, in words.
    fn cause(&self, f: &Failure) -> String {
        match f {
            Failure::NoConvergence { update } => {
                let mut s = format!(
                    "Newton did not converge in {MAX_ITERATIONS} iterations (the last update {update:.3e} times its tolerance)"
                );
                if let Some(p) = &self.last_problem {
                    s.push_str(&format!("; on the way {p}"));
                }
                s
            }
            Failure::Stuck(why) => why.clone(),
            Failure::NonFinite => "the residual is not finite".to_string(),
            Failure::Fatal { why, .. } => why.clone(),
            Failure::Interrupted => "interrupted".to_string(),
        }
    }

    fn run(&mut self, start: &State, options: &StaticOptions) -> Result<Equilibrium> {
        let (n, m, t) = (self.n, self.m, self.t);
        let mut q = start.q.clone();
        self.asm
            .apply_prescribed(t, &mut q, &mut self.presc_v, &mut self.presc_a);
        if self.at_rest() {
            self.presc_v.iter_mut().for_each(|x| *x = 0.0);
            self.presc_a.iter_mut().for_each(|x| *x = 0.0);
        }
        for c in 0..n {
            if !self.is_free[c] {
                self.v[c] = self.presc_v[c];
                self.a[c] = self.presc_a[c];
            }
        }
        if !q.iter().all(|x| x.is_finite()) {
            return Err(Error::InvalidInput(format!(
                "the start of the {} is not finite",
                self.what
            )));
        }
        let mut lam = vec![0.0; m];
        // r₀: what is out of balance at the start without loads.
        self.residual(0.0, &q, &lam);
        self.r0.copy_from_slice(&self.r);
        if !self.r0.iter().all(|x| x.is_finite()) {
            return Err(self.error("the residual at the start is not finite".into()));
        }
        let first = options.steps.map_or(1.0, |k| 1.0 / k as f64);
        let (mut done, mut delta) = (0.0f64, first);
        let (mut steps, mut iterations) = (0usize, 0usize);
        let (mut depth, mut failures, mut quick) = (0u32, 0u32, 0u32);
        let (mut q_ok, mut lam_ok) = (q.clone(), lam.clone());
        while done < 1.0 {
            let mut target = match options.steps {
                Some(k) => (steps + 1) as f64 / k as f64,
                None => (done + delta).min(1.0),
            };
            if 1.0 - target <= 1e-12 {
                target = 1.0;
            }
            let before = iterations;
            match self.newton(target, &mut q, &mut lam, &mut iterations) {
                Ok(()) => {
                    done = target;
                    steps += 1;
                    q_ok.copy_from_slice(&q);
                    lam_ok.copy_from_slice(&lam);
                    if iterations - before <= 6 {
                        quick += 1;
                    } else {
                        quick = 0;
                    }
                    if options.steps.is_none() && depth > 0 && quick >= 2 {
                        depth -= 1;
                        delta = (2.0 * delta).min(first);
                        quick = 0;
                    }
                    if steps > MAX_STEPS {
                        return Err(self.error(format!(
                            "more than {MAX_STEPS} load increments (load fraction {done:.6} reached)"
                        )));
                    }
                }
                Err(Failure::Interrupted) => return Err(Error::Interrupted),
                Err(Failure::Fatal { singular, why }) => {
                    let reason = if singular {
                        let named = self.singular_direction(target, &q, &lam);
                        mechanism(target, &format!("{why}{named}"))
                    } else {
                        unstable(target, &why)
                    };
                    return Err(self.error(reason));
                }
                Err(f) => {
                    let cause = self.cause(&f);
                    if let Some(k) = options.steps {
                        return Err(self.error(format!(
                            "load increment {} of {k} (load fraction {done:.6} → {target:.6}) failed: {cause}; {}",
                            steps + 1,
                            self.advice()
                        )));
                    }
                    failures += 1;
                    if depth >= MAX_HALVINGS || failures > MAX_FAILURES {
                        return Err(self.error(format!(
                            "the load cannot be equilibrated beyond load fraction {done:.6}: the increment to {target:.6} failed after {depth} halvings ({cause}); {}",
                            self.advice()
                        )));
                    }
                    q.copy_from_slice(&q_ok);
                    lam.copy_from_slice(&lam_ok);
                    depth += 1;
                    delta *= 0.5;
                    quick = 0;
                }
            }
        }
        if self.at_rest() {
            self.check_final(&q, &lam)?;
        }
        // The rates of the state.
        self.set_rates(1.0, &q);
        let (v, a) = if self.at_rest() {
            (vec![0.0; n], vec![0.0; n])
        } else {
            (self.v.clone(), self.a.clone())
        };
        self.asm.set_load_scale(1.0);
        // The validity check every path that produces a state applies
        // ([`crate::monitor::check_state`]): a solution of the equations
        // whose deformation no floating frame describes is not a result.
        if let Err(why) = crate::monitor::check_state(self.sys, &q, &v) {
            let advice = if self.at_rest() {
                "loads this large deform the body beyond what one floating frame with small elastic coordinates describes: smaller loads, a stiffer body, or a beam split into `segments`"
            } else {
                "at this speed the body deforms beyond what one floating frame with small elastic coordinates describes: a lower speed, a stiffer body, or `stiffening = true` on a beam"
            };
            return Err(self.error(format!("the state reached is not valid: {why}; {advice}")));
        }
        Ok(Equilibrium {
            state: State {
                t,
                q,
                v,
                a,
                lambda: lam,
            },
            steps,
            iterations,
        })
    }

    /// What the message suggests.
    fn advice(&self) -> &'static str {
        if self.at_rest() {
            "the loads may have no equilibrium (a mechanism they move, e.g. a free body under gravity or a pendulum under a torque above its weight's, or a load past a limit or buckling point)"
        } else {
            "the loads may have no steady state (e.g. spin softening past a bending frequency)"
        }
    }

    /// The unshifted tangent at the equilibrium reached: a zero pivot, a
    /// singular direction or `det K̂ < 0` is an error (module
    /// documentation).
    fn check_final(&mut self, q: &[f64], lam: &[f64]) -> Result<()> {
        let t = self.t;
        self.asm.set_load_scale(1.0);
        self.asm
            .static_matrix(t, q, &self.v, &self.a, lam, 0.0, 0.0, &mut self.r);
        let (dr, dc) = self.asm.equilibration();
        if let Err(e) = self.asm.factor(t, "static tangent stiffness") {
            let d = match e {
                Error::Singular { detail, .. } => detail,
                other => other.to_string(),
            };
            let named = self.singular_direction(1.0, q, lam);
            return Err(self.error(mechanism(
                1.0,
                &format!("the tangent stiffness is singular ({d}){named}"),
            )));
        }
        if self.indefinite(self.asm.det_sign()) {
            return Err(self.error(unstable(1.0, INDEFINITE)));
        }
        let (worst, u) = self.probe(&dr, &dc, false);
        if !(worst <= SINGULAR) {
            let what = if u == usize::MAX {
                "the tangent stiffness is singular (a probe of it has no finite solution)"
                    .to_string()
            } else {
                format!(
                    "the tangent stiffness is singular to working precision (its equilibrated inverse exceeds 1/(64 ε)); its direction without stiffness is mostly {}",
                    self.asm.describe_unknown(u)
                )
            };
            return Err(self.error(mechanism(1.0, &what)));
        }
        Ok(())
    }

    /// The direction in which the unshifted tangent at `(q, λ)` has no
    /// stiffness, as `; its direction without stiffness is mostly …`: the
    /// coordinate that dominates the equilibrated probe of the matrix
    /// shifted by a little mass, `μ = 10⁻⁸` of the first shift (the
    /// column at which an elimination fails is not always that
    /// direction). Empty if that does not factor either.
    fn singular_direction(&mut self, load: f64, q: &[f64], lam: &[f64]) -> String {
        let t = self.t;
        let mu = 1e-8 * self.first_shift(load, q, lam);
        self.asm.set_load_scale(load);
        self.asm
            .static_matrix(t, q, &self.v, &self.a, lam, 0.0, 0.0, &mut self.r);
        let (dr, dc) = self.asm.equilibration();
        self.asm
            .static_matrix(t, q, &self.v, &self.a, lam, mu, 0.0, &mut self.r);
        if self.asm.factor(t, "static tangent stiffness").is_err() {
            return String::new();
        }
        match self.probe(&dr, &dc, true) {
            (_, u) if u != usize::MAX => format!(
                "; its direction without stiffness is mostly {}",
                self.asm.describe_unknown(u)
            ),
            _ => String::new(),
        }
    }

    /// With the factored matrix `J`: `y = D_c⁻¹ J⁻¹ D_r⁻¹ b` (the solution
    /// of the equilibrated `J̃ y = b`, `b` of order 1 on every unknown),
    /// its largest `|y_u|` and that unknown (`usize::MAX` if none is
    /// finite); over the coordinates only with `coords_only`.
    fn probe(&mut self, dr: &[f64], dc: &[f64], coords_only: bool) -> (f64, usize) {
        let (n, m) = (self.n, self.m);
        let used = |u: usize, is_free: &[bool]| if u < n { is_free[u] } else { !coords_only };
        for u in 0..n + m {
            let b = 1.0 + 0.5 * (1.3 * u as f64 + 0.7).sin();
            self.rhs[u] = if used(u, &self.is_free) || u >= n {
                b / dr[u]
            } else {
                0.0
            };
        }
        self.asm.solve(&self.rhs, &mut self.x);
        let mut worst = (0.0f64, usize::MAX);
        for u in 0..n + m {
            if used(u, &self.is_free) {
                let y = (self.x[u] / dc[u]).abs();
                if !(y <= worst.0) {
                    worst = (y, u);
                }
            }
        }
        worst
    }
}
