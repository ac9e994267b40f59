//! Time integration: generalized-α for the index-3 DAE (Arnold & Brüls 2007)
//! and explicit RK4 on the index-1 form with Baumgarte stabilization.

use crate::error::{Error, Result};
use crate::system::{State, System};
use nalgebra::{DMatrix, DVector, Dyn, LU};
use std::ops::ControlFlow;

/// Generalized-α settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeneralizedAlpha {
    /// Spectral radius at infinite frequency `ρ∞ ∈ [0, 1]` (1: no numerical damping).
    pub rho_inf: f64,
    /// Relative Newton tolerance on the increments.
    pub rtol: f64,
    /// Absolute Newton tolerance on the increments.
    pub atol: f64,
    /// Maximum Newton iterations per step.
    pub max_iter: usize,
}

impl Default for GeneralizedAlpha {
    fn default() -> Self {
        Self {
            rho_inf: 0.8,
            rtol: 1e-9,
            atol: 1e-11,
            max_iter: 30,
        }
    }
}

impl GeneralizedAlpha {
    /// Defaults with this `ρ∞`.
    pub fn with_rho_inf(rho_inf: f64) -> Self {
        Self {
            rho_inf,
            ..Self::default()
        }
    }

    /// `(α_m, α_f, γ, β)`: `α_m = (2ρ∞ − 1)/(ρ∞ + 1)`, `α_f = ρ∞/(ρ∞ + 1)`,
    /// `γ = ½ + α_f − α_m`, `β = ¼ (γ + ½)²`.
    pub fn coefficients(&self) -> (f64, f64, f64, f64) {
        let r = self.rho_inf;
        let am = (2.0 * r - 1.0) / (r + 1.0);
        let af = r / (r + 1.0);
        let g = 0.5 + af - am;
        (am, af, g, 0.25 * (g + 0.5).powi(2))
    }
}

/// Explicit RK4 on `[M Φ_qᵀ; Φ_q 0][q̈; λ] = [Q; γ − 2α Φ̇ − β² Φ]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rk4Baumgarte {
    /// Baumgarte velocity gain `α` (1/s).
    pub alpha: f64,
    /// Baumgarte position gain `β` (1/s).
    pub beta: f64,
}

impl Default for Rk4Baumgarte {
    fn default() -> Self {
        Self {
            alpha: 10.0,
            beta: 10.0,
        }
    }
}

/// An integrator choice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Integrator {
    /// Implicit generalized-α (index 3).
    GeneralizedAlpha(GeneralizedAlpha),
    /// Explicit RK4 with Baumgarte stabilization (index 1).
    Rk4(Rk4Baumgarte),
}

impl Default for Integrator {
    fn default() -> Self {
        Integrator::GeneralizedAlpha(GeneralizedAlpha::default())
    }
}

/// What an observer sees after each step (and once for the initial state, `step == 0`).
#[derive(Debug)]
pub struct StepView<'a> {
    /// Number of steps taken.
    pub step: usize,
    /// The state.
    pub state: &'a State,
    /// Newton iterations of the last step (0 for explicit / initial).
    pub iterations: usize,
}

/// Outcome of a simulation.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// Steps taken.
    pub steps: usize,
    /// The final state.
    pub last: State,
    /// The observer stopped the run early.
    pub stopped: bool,
    /// Total Newton iterations.
    pub newton_iterations: usize,
    /// Iteration-matrix evaluations.
    pub jacobians: usize,
}

/// A stored trajectory.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trajectory {
    /// Times.
    pub t: Vec<f64>,
    /// Coordinates.
    pub q: Vec<DVector<f64>>,
    /// Velocities.
    pub v: Vec<DVector<f64>>,
}

fn check_finite(x: &DVector<f64>, what: &'static str, step: usize, t: f64) -> Result<()> {
    if x.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(Error::NonFinite { what, step, t })
    }
}

impl System {
    /// Integrate from the consistent initial state at `t = 0` to `t_end` with
    /// step `dt`, calling `observer` at the start and after each step (it may
    /// stop the run with `ControlFlow::Break`).
    pub fn simulate(
        &self,
        t_end: f64,
        dt: f64,
        integrator: &Integrator,
        mut observer: impl FnMut(&StepView) -> ControlFlow<()>,
    ) -> Result<Summary> {
        if !(dt > 0.0 && dt.is_finite() && t_end.is_finite() && t_end >= 0.0) {
            return Err(Error::InvalidInput(format!(
                "need dt > 0 and t_end ≥ 0 (got dt = {dt}, t_end = {t_end})"
            )));
        }
        if let Integrator::GeneralizedAlpha(g) = integrator {
            if !(0.0..=1.0).contains(&g.rho_inf) {
                return Err(Error::InvalidInput(format!(
                    "rho_inf = {} is not in [0, 1]",
                    g.rho_inf
                )));
            }
        }
        let n_steps = ((t_end / dt) - 1e-9).ceil().max(0.0) as usize;
        let mut state = self.initial_state(0.0)?;
        let mut summary = Summary {
            steps: 0,
            last: state.clone(),
            stopped: false,
            newton_iterations: 0,
            jacobians: 0,
        };
        if observer(&StepView {
            step: 0,
            state: &state,
            iterations: 0,
        })
        .is_break()
        {
            summary.stopped = true;
            return Ok(summary);
        }
        let mut ga = GaWork::default();
        let mut acc = state.a.clone();
        for step in 0..n_steps {
            let h = (t_end - state.t).min(dt);
            let h = if h < 1e-12 * dt { dt } else { h };
            let iters = match integrator {
                Integrator::GeneralizedAlpha(g) => {
                    let (it, jacs) = self.ga_step(g, &mut state, &mut acc, h, step, &mut ga)?;
                    summary.jacobians += jacs;
                    it
                }
                Integrator::Rk4(r) => {
                    self.rk4_step(r, &mut state, h, step)?;
                    0
                }
            };
            summary.newton_iterations += iters;
            summary.steps = step + 1;
            if observer(&StepView {
                step: step + 1,
                state: &state,
                iterations: iters,
            })
            .is_break()
            {
                summary.stopped = true;
                break;
            }
        }
        summary.last = state;
        Ok(summary)
    }

    /// [`System::simulate`] storing every `every`-th state.
    pub fn simulate_trajectory(
        &self,
        t_end: f64,
        dt: f64,
        integrator: &Integrator,
        every: usize,
    ) -> Result<(Trajectory, Summary)> {
        let mut tr = Trajectory::default();
        let every = every.max(1);
        let s = self.simulate(t_end, dt, integrator, |v| {
            if v.step % every == 0 {
                tr.t.push(v.state.t);
                tr.q.push(v.state.q.clone());
                tr.v.push(v.state.v.clone());
            }
            ControlFlow::Continue(())
        })?;
        Ok((tr, s))
    }

    fn rk4_step(&self, r: &Rk4Baumgarte, s: &mut State, h: f64, step: usize) -> Result<()> {
        let f = |t: f64, q: &DVector<f64>, v: &DVector<f64>| {
            self.accelerations(t, q, v, (r.alpha, r.beta))
        };
        let t = s.t;
        let (a1, _) = f(t, &s.q, &s.v)?;
        let (q2, v2) = (&s.q + &s.v * (h / 2.0), &s.v + &a1 * (h / 2.0));
        let (a2, _) = f(t + h / 2.0, &q2, &v2)?;
        let (q3, v3) = (&s.q + &v2 * (h / 2.0), &s.v + &a2 * (h / 2.0));
        let (a3, _) = f(t + h / 2.0, &q3, &v3)?;
        let (q4, v4) = (&s.q + &v3 * h, &s.v + &a3 * h);
        let (a4, _) = f(t + h, &q4, &v4)?;
        s.q += (&s.v + &v2 * 2.0 + &v3 * 2.0 + &v4) * (h / 6.0);
        s.v += (&a1 + &a2 * 2.0 + &a3 * 2.0 + &a4) * (h / 6.0);
        s.t = t + h;
        check_finite(&s.q, "coordinates", step, t)?;
        check_finite(&s.v, "velocities", step, t)?;
        let (a, l) = f(s.t, &s.q, &s.v)?;
        s.a = a;
        s.lambda = l;
        Ok(())
    }
}

/// Reusable iteration matrix of the generalized-α Newton iterations.
#[derive(Default)]
struct GaWork {
    lu: Option<(LU<f64, Dyn, Dyn>, f64)>,
}

impl System {
    /// Scaled residual `[(M q̈ − Q)/β' + Φ_qᵀ λ̃; Φ]`, `λ̃ = λ/β'`.
    fn ga_residual(
        &self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        a: &DVector<f64>,
        lam: &DVector<f64>,
        bp: f64,
    ) -> DVector<f64> {
        let (n, m) = (self.n_coords(), self.n_constraints());
        let mut r = DVector::zeros(n + m);
        let mut dyn_part = self.mass_matrix(q) * a - self.forces(t, q, v);
        dyn_part /= bp;
        let c = self.constraints(t, q);
        dyn_part += c.jac.transpose() * lam;
        r.rows_mut(0, n).copy_from(&dyn_part);
        r.rows_mut(n, m).copy_from(&c.phi);
        r
    }

    /// Iteration matrix `∂r/∂(q, λ̃)` with `∂q̇/∂q = γ'`, `∂q̈/∂q = β'`: body
    /// blocks and the interaction rows (force elements, `Φ_qᵀλ̃`, `Φ`) by
    /// forward differences, `∂r/∂λ̃ = [Φ_qᵀ; 0]` exactly.
    #[allow(clippy::too_many_arguments)]
    fn ga_jacobian(
        &self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        a: &DVector<f64>,
        lam: &DVector<f64>,
        bp: f64,
        gp: f64,
    ) -> DMatrix<f64> {
        let (n, m) = (self.n_coords(), self.n_constraints());
        let mut j = DMatrix::zeros(n + m, n + m);
        let eps_of = |x: f64| 1e-7 * (1.0 + x.abs());
        // Body blocks.
        for i in 0..self.n_bodies() {
            let o = self.offsets_of(i);
            let nb = self.body(crate::BodyId(i)).n_coords();
            let mut qb = q.as_slice()[o..o + nb].to_vec();
            let mut vb = v.as_slice()[o..o + nb].to_vec();
            let mut ab = a.as_slice()[o..o + nb].to_vec();
            let r0 = self.body_residual(i, &qb, &vb, &ab);
            for k in 0..nb {
                let e = eps_of(qb[k]);
                let (q0, v0, a0) = (qb[k], vb[k], ab[k]);
                qb[k] += e;
                vb[k] += gp * e;
                ab[k] += bp * e;
                let r1 = self.body_residual(i, &qb, &vb, &ab);
                (qb[k], vb[k], ab[k]) = (q0, v0, a0);
                let col = (r1 - &r0) / (e * bp);
                j.view_mut((o, o + k), (nb, 1)).copy_from(&col);
            }
        }
        // Interactions.
        if m > 0 || self.has_elements() {
            let inter = |q: &DVector<f64>, v: &DVector<f64>| {
                let c = self.constraints(t, q);
                let mut r = DVector::zeros(n + m);
                let f = -self.element_forces(t, q, v) / bp + c.jac.transpose() * lam;
                r.rows_mut(0, n).copy_from(&f);
                r.rows_mut(n, m).copy_from(&c.phi);
                (r, c.jac)
            };
            let (r0, jac) = inter(q, v);
            let (mut qp, mut vp) = (q.clone(), v.clone());
            for k in 0..n {
                let e = eps_of(q[k]);
                qp[k] += e;
                vp[k] += gp * e;
                let (r1, _) = inter(&qp, &vp);
                qp[k] = q[k];
                vp[k] = v[k];
                let mut col = j.column_mut(k);
                col += (r1 - &r0) / e;
            }
            j.view_mut((0, n), (n, m)).copy_from(&jac.transpose());
        }
        j
    }

    /// One generalized-α step (Arnold & Brüls 2007), Newton on `q_{n+1}` and
    /// `λ̃` with a reused iteration matrix. `acc` is the algorithmic acceleration `a`.
    fn ga_step(
        &self,
        g: &GeneralizedAlpha,
        s: &mut State,
        acc: &mut DVector<f64>,
        h: f64,
        step: usize,
        w: &mut GaWork,
    ) -> Result<(usize, usize)> {
        let (am, af, gamma, beta) = g.coefficients();
        let bp = (1.0 - am) / ((1.0 - af) * beta * h * h);
        let gp = gamma / (beta * h);
        let (t0, n) = (s.t, self.n_coords());
        let t = t0 + h;
        // Predictor.
        let a_new = (&s.a * af - &*acc * am) / (1.0 - am);
        let mut v = &s.v + &*acc * (h * (1.0 - gamma)) + &a_new * (h * gamma);
        let mut q = &s.q + &s.v * h + &*acc * (h * h * (0.5 - beta)) + &a_new * (h * h * beta);
        let mut qdd = DVector::zeros(n);
        let mut lam = &s.lambda / bp;
        let mut jacs = 0;
        if w.lu
            .as_ref()
            .is_some_and(|(_, hh)| (*hh - h).abs() > 1e-12 * h)
        {
            w.lu = None;
        }
        let mut prev = f64::INFINITY;
        let mut res_norm = f64::NAN;
        for it in 1..=g.max_iter {
            let r = self.ga_residual(t, &q, &v, &qdd, &lam, bp);
            res_norm = r.norm();
            if !res_norm.is_finite() {
                return Err(Error::NonFinite {
                    what: "residual",
                    step,
                    t: t0,
                });
            }
            if w.lu.is_none() {
                let jm = self.ga_jacobian(t, &q, &v, &qdd, &lam, bp, gp);
                w.lu = Some((jm.lu(), h));
                jacs += 1;
            }
            let (lu, _) = w.lu.as_ref().expect("iteration matrix present");
            let dx = lu.solve(&(-&r)).ok_or(Error::Singular {
                what: "generalized-α iteration matrix",
                t,
            })?;
            if !dx.iter().all(|x| x.is_finite()) {
                w.lu = None;
                return Err(Error::Singular {
                    what: "generalized-α iteration matrix",
                    t,
                });
            }
            let dq = dx.rows(0, n);
            q += &dq;
            v += &dq * gp;
            qdd += &dq * bp;
            lam += dx.rows(n, dx.len() - n);
            let err = dq
                .iter()
                .zip(q.iter())
                .map(|(d, x)| d.abs() / (g.atol + g.rtol * x.abs()))
                .fold(0.0, f64::max);
            if err <= 1.0 {
                // Converged: algorithmic acceleration update.
                *acc = (&qdd * (1.0 - af) + &s.a * af - &*acc * am) / (1.0 - am);
                s.t = t;
                s.q = q;
                s.v = v;
                s.a = qdd;
                s.lambda = lam * bp;
                check_finite(&s.q, "coordinates", step, t0)?;
                return Ok((it, jacs));
            }
            // Slow contraction: refresh the iteration matrix at the current iterate
            // (modified Newton becomes full Newton on hard steps).
            let dn = dq.amax();
            if dn > 0.25 * prev || it >= 4 {
                w.lu = None;
            }
            prev = dn;
        }
        w.lu = None;
        Err(Error::NoConvergence {
            step,
            t: t0,
            residual: res_norm,
            iterations: g.max_iter,
            dt: h,
        })
    }
}

#[cfg(test)]
pub(crate) fn jacobian_check(sys: &System, s: &State, h: f64) -> f64 {
    let (am, af, gamma, beta) = GeneralizedAlpha::default().coefficients();
    let bp = (1.0 - am) / ((1.0 - af) * beta * h * h);
    let gp = gamma / (beta * h);
    let lam = &s.lambda / bp;
    let j = sys.ga_jacobian(s.t, &s.q, &s.v, &s.a, &lam, bp, gp);
    let n = sys.n_coords();
    let mut worst: f64 = 0.0;
    for k in 0..n {
        let e = 1e-6 * (1.0 + s.q[k].abs());
        let mut qp = s.q.clone();
        let mut vp = s.v.clone();
        let mut ap = s.a.clone();
        qp[k] += e;
        vp[k] += gp * e;
        ap[k] += bp * e;
        let r1 = sys.ga_residual(s.t, &qp, &vp, &ap, &lam, bp);
        qp[k] -= 2.0 * e;
        vp[k] -= 2.0 * gp * e;
        ap[k] -= 2.0 * bp * e;
        let r0 = sys.ga_residual(s.t, &qp, &vp, &ap, &lam, bp);
        let col = (r1 - r0) / (2.0 * e);
        let err = (&col - j.column(k)).amax() / (1.0 + j.column(k).amax());
        if err > 1e-4 {
            eprintln!(
                "col {k}: err {err:e} fd {:?} jac {:?}",
                col.as_slice(),
                j.column(k).as_slice()
            );
        }
        worst = worst.max(err);
    }
    worst
}
