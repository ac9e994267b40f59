//! The divergence monitor: stops a run whose numbers are still finite but
//! whose result is no longer valid, with [`Error::Diverged`].
//!
//! After every step [`System::simulate`](crate::System::simulate) checks:
//!
//! - **deformation**: the elastic displacement `|Σ_j s_j(x) q_j|` of every
//!   flexible body at 17 points along its axis stays below
//!   [`Monitor::deformation`] times the body's length (a floating frame of
//!   reference with small elastic coordinates cannot describe more);
//! - **energy** (every 16 steps, when no drive does work: no prescribed coordinate that moves
//!   and no driving constraint): the energy gained beyond the work applied,
//!   `ΔE_exc = E(t) − E(0) − W(t) + D(t)`, stays below [`Monitor::energy`]
//!   times the scale `S = T(0) + V_el(0) + V_springs(0) + ∫|P_applied| dt +
//!   D(t) + Σ_b m_b (|g| L_b + (L_b/t_end)²)` (`W`, `D` integrated by the
//!   trapezoidal rule; `L_b` a body's length, or its radius of gyration),
//!   or, once above, does not grow by ten times more nor beyond `10⁶ S` (a
//!   step load's violent first steps may gain energy that then decays; a
//!   divergence keeps growing);
//! - **restarts**: after 100 steps, fewer than [`Monitor::restart_fraction`]
//!   of the steps needed their Newton iteration restarted from rest.
//!
//! Nothing is allocated after the run's watch is set up (`Watch::new`).

use crate::assembly::Assembly;
use crate::body::{Body, PointShape};
use crate::error::{Error, Result};
use crate::integrator::{State, Summary};

/// Bounds of the divergence monitor ([module docs](self)); on by default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Monitor {
    /// Check at all.
    pub enabled: bool,
    /// Largest elastic displacement, in body lengths (default 1).
    pub deformation: f64,
    /// Largest energy gain beyond the applied work, in units of the energy
    /// scale `S` (default 1).
    pub energy: f64,
    /// Largest fraction of steps restarted from rest (default 0.5).
    pub restart_fraction: f64,
}

impl Default for Monitor {
    fn default() -> Self {
        Self {
            enabled: true,
            deformation: 1.0,
            energy: 1.0,
            restart_fraction: 0.5,
        }
    }
}

impl Monitor {
    /// No checks (for studies that follow a run past its validity).
    pub fn off() -> Self {
        Self {
            enabled: false,
            ..Self::default()
        }
    }
}

/// Sample points per flexible body.
const SAMPLES: usize = 17;
/// An energy excess above the bound that grows by this factor more is a
/// divergence.
const GROWTH: f64 = 10.0;
/// An energy excess above this many energy scales is a divergence at once.
const GROSS: f64 = 1e6;
/// The energy is evaluated every this many steps (the work every step): an
/// energy evaluation costs about a residual, and at every step it made small
/// scenes 30 % slower (`benches/monitor.rs`).
const ENERGY_EVERY: usize = 16;
/// Steps before the restart fraction is judged.
const MIN_STEPS: usize = 100;

struct Sampled {
    body: usize,
    f0: usize,
    length: f64,
    points: Vec<(f64, PointShape)>,
}

/// The largest elastic section rotation of a flexible body over a run
/// (or at a static solution): the angle of the section rotation `R(ψ)`
/// relative to the body's frame ([`crate::section::rotation_angle`]) at
/// the 17 points the monitor samples, tracked whether or not the monitor
/// is on. One floating frame is accurate while it stays small (the
/// scene layer warns past a threshold).
#[derive(Clone, Debug, PartialEq)]
pub struct ElasticRotation {
    /// The body (index in the system).
    pub body: usize,
    /// The largest angle (rad).
    pub angle: f64,
    /// When (s).
    pub t: f64,
    /// Where, on the body's own axis (m).
    pub x: f64,
}

/// The sampled points of the flexible bodies with a length, for
/// [`ElasticRotation`] (no allocation after [`Rotations::new`]).
pub(crate) struct Rotations {
    sampled: Vec<Sampled>,
    /// One per sampled body, in order.
    pub(crate) max: Vec<ElasticRotation>,
}

impl Rotations {
    /// The sample points of `sys`'s flexible bodies.
    pub(crate) fn new<B: Body>(sys: &crate::System<B>) -> Result<Self> {
        let mut sampled = Vec::new();
        let mut max = Vec::new();
        for (i, b) in sys.bodies.iter().enumerate() {
            let lay = b.body.layout();
            if b.nf == 0 {
                continue;
            }
            let Some(l) = lay.length.filter(|l| *l > 0.0 && l.is_finite()) else {
                continue;
            };
            let mut points = Vec::with_capacity(SAMPLES);
            for k in 0..SAMPLES {
                let x = l * k as f64 / (SAMPLES - 1) as f64;
                points.push((x, b.body.point_shape(x)?));
            }
            sampled.push(Sampled {
                body: i,
                f0: b.f_offset(),
                length: l,
                points,
            });
            max.push(ElasticRotation {
                body: i,
                angle: 0.0,
                t: 0.0,
                x: 0.0,
            });
        }
        Ok(Self { sampled, max })
    }

    /// Update the largest angles with the state `q` at time `t`.
    pub(crate) fn observe(&mut self, t: f64, q: &[f64]) {
        for (s, m) in self.sampled.iter().zip(self.max.iter_mut()) {
            for (x, p) in &s.points {
                let mut psi = nalgebra::Vector3::zeros();
                for (j, _, rj) in &p.entries {
                    let qj = q[s.f0 + j];
                    for k in 0..3 {
                        psi[k] += rj[k] * qj;
                    }
                }
                let a = crate::section::rotation_angle(&psi);
                if a > m.angle {
                    *m = ElasticRotation {
                        body: s.body,
                        angle: a,
                        t,
                        x: *x,
                    };
                }
            }
        }
    }
}

/// The elastic rotations of `sys`'s flexible bodies at the state `q`
/// (time `t`): [`ElasticRotation`] of that state alone (a static solution).
pub fn elastic_rotations<B: Body>(
    sys: &crate::System<B>,
    t: f64,
    q: &[f64],
) -> Result<Vec<ElasticRotation>> {
    let mut r = Rotations::new(sys)?;
    r.observe(t, q);
    Ok(r.max)
}

/// The monitor's state during one run.
pub(crate) struct Watch {
    settings: Monitor,
    flex: Vec<Sampled>,
    /// Energy balance applies (no drive does work).
    balance: bool,
    e0: f64,
    /// `T(0) + V_el(0) + V_springs(0) + Σ m (|g| L + (L/t_end)²)`.
    base: f64,
    work: f64,
    work_abs: f64,
    dissipated: f64,
    last: Option<(f64, crate::Power)>,
    /// The excess when it first went above the bound (reset below it).
    first_excess: Option<f64>,
}

impl Watch {
    /// Prepare the checks for a run of `sys` from `state` to `t_end`.
    pub fn new<B: Body>(
        asm: &mut Assembly<B>,
        settings: Monitor,
        state: &State,
        t_end: f64,
    ) -> Result<Self> {
        let sys = asm.sys;
        let mut flex = Vec::new();
        let mut floor = 0.0;
        let g = sys.gravity.norm();
        let moving = |d: &crate::Driver| {
            let [_, fd, fdd] = d.eval(0.0);
            !(d.is_uniform() && fd == 0.0 && fdd == 0.0)
        };
        let driven = sys.prescribed.iter().any(|(_, d)| moving(d))
            || sys.constraints.iter().any(|c| {
                c.rows.iter().any(|r| {
                    r.offset.as_ref().is_some_and(moving)
                        || r.v1.iter().chain(&r.v2).any(|term| match &term.coef {
                            crate::joint::Coef::Const(_) => false,
                            crate::joint::Coef::Cos(d) | crate::joint::Coef::Sin(d) => moving(d),
                        })
                })
            });
        for (i, b) in sys.bodies.iter().enumerate() {
            let lay = b.body.layout();
            let m = asm.mass_diagonal(&state.q, &[b.offset])[0];
            let length = match lay.length {
                Some(l) if l > 0.0 && l.is_finite() => l,
                _ => {
                    let rot: Vec<usize> = (b.offset + b.d..b.f_offset()).collect();
                    let j = asm
                        .mass_diagonal(&state.q, &rot)
                        .into_iter()
                        .fold(0.0f64, f64::max);
                    let j = if b.n_theta == 4 { j / 4.0 } else { j };
                    if m > 0.0 {
                        (j / m).sqrt()
                    } else {
                        0.0
                    }
                }
            };
            if m.is_finite() && length.is_finite() {
                let l_t = if t_end > 0.0 { length / t_end } else { 0.0 };
                floor += m * (g * length + l_t * l_t);
            }
            if b.nf > 0 {
                if let Some(l) = lay.length.filter(|l| *l > 0.0) {
                    let mut points = Vec::with_capacity(SAMPLES);
                    for k in 0..SAMPLES {
                        let x = l * k as f64 / (SAMPLES - 1) as f64;
                        points.push((x, b.body.point_shape(x)?));
                    }
                    flex.push(Sampled {
                        body: i,
                        f0: b.f_offset(),
                        length: l,
                        points,
                    });
                }
            }
        }
        let e = asm.energy(&state.q, &state.v);
        Ok(Self {
            settings,
            flex,
            balance: !driven,
            e0: e.total(),
            base: e.kinetic.abs() + e.elastic.abs() + e.springs.abs() + floor,
            work: 0.0,
            work_abs: 0.0,
            dissipated: 0.0,
            last: Some((state.t, asm.power(state.t, &state.q, &state.v))),
            first_excess: None,
        })
    }

    /// Check the state after a step; `Err(Error::Diverged)` stops the run.
    pub fn after_step<B: Body>(
        &mut self,
        asm: &mut Assembly<B>,
        state: &State,
        summary: &Summary,
    ) -> Result<()> {
        if !self.settings.enabled {
            return Ok(());
        }
        let fail = |reason: String| {
            Err(Error::Diverged {
                step: summary.steps,
                t: state.t,
                reason,
            })
        };
        for s in &self.flex {
            for (x, p) in &s.points {
                let mut u = [0.0f64; 3];
                for (j, sj, _) in &p.entries {
                    let qj = state.q[s.f0 + j];
                    for k in 0..3 {
                        u[k] += sj[k] * qj;
                    }
                }
                let d = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
                // `!(d <= bound)`: a NaN deformation fails the check too.
                #[allow(clippy::neg_cmp_op_on_partial_ord)]
                if !(d <= self.settings.deformation * s.length) {
                    return fail(format!(
                        "body `{}` is deformed by {d:.3e} m at x = {x:.4} m, more than {} × its length {:.4} m: the elastic coordinates have left any valid range",
                        asm.sys.bodies[s.body].name, self.settings.deformation, s.length
                    ));
                }
            }
        }
        if summary.steps >= MIN_STEPS
            && summary.restarts as f64 > self.settings.restart_fraction * summary.steps as f64
        {
            return fail(format!(
                "{} of {} steps needed their Newton iteration restarted from rest: the solution is not followed any more",
                summary.restarts, summary.steps
            ));
        }
        if self.balance {
            let p = asm.power(state.t, &state.q, &state.v);
            if let Some((t0, p0)) = self.last {
                let h = 0.5 * (state.t - t0);
                self.work += h * (p0.applied + p.applied);
                self.work_abs += h * (p0.applied.abs() + p.applied.abs());
                self.dissipated += h * (p0.dissipated + p.dissipated);
            }
            self.last = Some((state.t, p));
            if !summary.steps.is_multiple_of(ENERGY_EVERY) {
                return Ok(());
            }
            let e = asm.energy(&state.q, &state.v).total();
            let excess = e - self.e0 - self.work + self.dissipated;
            let scale = self.base + self.work_abs + self.dissipated.abs();
            let bound = self.settings.energy * scale;
            if excess <= bound {
                self.first_excess = None;
            } else {
                // Above the bound: a transient (a step load's first steps)
                // may come back; growth by ten more, or by GROSS, is not.
                let first = *self.first_excess.get_or_insert(excess);
                // `!(x <= bound)`: a NaN excess fails the check too.
                #[allow(clippy::neg_cmp_op_on_partial_ord)]
                if !(excess <= GROWTH * first) || !(excess <= GROSS * scale) {
                    return fail(format!(
                        "the energy grew to {e:.4e} J from {:.4e} J with {:.4e} J of work applied and {:.4e} J dissipated: {excess:.3e} J gained from nowhere and growing ({first:.3e} J when it first passed {} × the energy scale {scale:.3e} J)",
                        self.e0, self.work, self.dissipated, self.settings.energy
                    ));
                }
            }
        }
        Ok(())
    }
}
