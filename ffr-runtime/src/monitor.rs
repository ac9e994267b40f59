//! The divergence monitor: stops a run whose numbers are still finite but
//! whose result is no longer valid, with [`Error::Diverged`].
//!
//! After every step [`System::simulate`](crate::System::simulate) checks:
//!
//! - **deformation** ([`Validity`]): the elastic displacement
//!   `|Σ_j s_j q_j|` of every flexible body stays below
//!   [`Monitor::deformation`] times the body's size (a floating frame of
//!   reference with small elastic coordinates cannot describe more): a
//!   beam (or a modal body on a beam) at 17 points along its axis against
//!   its length, an FE body at its nodes (the node each elastic coordinate
//!   moves most, and up to 64 nodes evenly spread) against its nodes'
//!   bounding-box diagonal;
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
//!
//! The same deformation bound, with finite coordinates, rates and energy,
//! is the validity check of a single state, [`check_state`], which every
//! other path that produces a state applies: `ffr static`, the Campbell
//! steady state, `linearize --at` (`docs/limits-and-errors.md`).

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
    points: Vec<(f64, PointShape)>,
}

/// Nodes sampled per FE body at most (besides the largest node of each
/// elastic coordinate).
const NODE_SAMPLES: usize = 64;

/// A flexible body's points that the validity check samples: a beam's 17
/// points along its axis (`where` the axial position `x`), an FE body's
/// nodes (`where` the node index: for each elastic coordinate the node it
/// moves most, and up to [`NODE_SAMPLES`] nodes evenly spread), and the
/// body's size: a beam's length, an FE body's nodes' bounding-box
/// diagonal.
struct Shaped {
    body: usize,
    f0: usize,
    size: f64,
    nodes: bool,
    points: Vec<(f64, PointShape)>,
}

/// The deformation part of the validity check ([`check_state`], and the
/// monitor after every step): the points of every flexible body — beams,
/// modal bodies, FE bodies — and their sizes. No allocation after
/// [`Validity::new`].
pub struct Validity {
    shaped: Vec<Shaped>,
}

impl Validity {
    /// The sample points of `sys`'s flexible bodies.
    pub fn new<B: Body>(sys: &crate::System<B>) -> Result<Self> {
        let mut shaped = Vec::new();
        for (i, b) in sys.bodies.iter().enumerate() {
            if b.nf == 0 {
                continue;
            }
            let lay = b.body.layout();
            if let Some(l) = lay.length.filter(|l| *l > 0.0 && l.is_finite()) {
                let mut points = Vec::with_capacity(SAMPLES);
                for k in 0..SAMPLES {
                    let x = l * k as f64 / (SAMPLES - 1) as f64;
                    points.push((x, b.body.point_shape(x)?));
                }
                shaped.push(Shaped {
                    body: i,
                    f0: b.f_offset(),
                    size: l,
                    nodes: false,
                    points,
                });
                continue;
            }
            let n = b.body.node_count();
            if n == 0 {
                continue;
            }
            // The bounding box of the nodes, and the node each elastic
            // coordinate moves most.
            let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            let mut most = vec![(0.0f64, usize::MAX); b.nf];
            let stride = n.div_ceil(NODE_SAMPLES).max(1);
            let mut picked: Vec<usize> = Vec::new();
            for node in 0..n {
                let s = b.body.node_shape(node)?;
                for k in 0..3 {
                    lo[k] = lo[k].min(s.u0[k]);
                    hi[k] = hi[k].max(s.u0[k]);
                }
                for (j, sj, _) in &s.entries {
                    let a = (sj[0] * sj[0] + sj[1] * sj[1] + sj[2] * sj[2]).sqrt();
                    if *j < most.len() && a > most[*j].0 {
                        most[*j] = (a, node);
                    }
                }
                if node % stride == 0 || node == n - 1 {
                    picked.push(node);
                }
            }
            picked.extend(most.iter().filter(|m| m.1 != usize::MAX).map(|m| m.1));
            picked.sort_unstable();
            picked.dedup();
            let size = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
            if !(size > 0.0 && size.is_finite()) {
                continue;
            }
            let mut points = Vec::with_capacity(picked.len());
            for node in picked {
                points.push((node as f64, b.body.node_shape(node)?));
            }
            shaped.push(Shaped {
                body: i,
                f0: b.f_offset(),
                size,
                nodes: true,
                points,
            });
        }
        Ok(Self { shaped })
    }

    /// Why the elastic coordinates of `q` are not valid: the first sampled
    /// point displaced by more than `bound` times its body's size (or by a
    /// displacement that is not finite), in words; `None` if none is.
    pub fn deformation<B: Body>(
        &self,
        sys: &crate::System<B>,
        q: &[f64],
        bound: f64,
    ) -> Option<String> {
        for s in &self.shaped {
            for (x, p) in &s.points {
                let mut u = [0.0f64; 3];
                for (j, sj, _) in &p.entries {
                    let qj = q[s.f0 + j];
                    for k in 0..3 {
                        u[k] += sj[k] * qj;
                    }
                }
                let d = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
                // `!(d <= bound)`: a NaN deformation fails the check too.
                #[allow(clippy::neg_cmp_op_on_partial_ord)]
                if !(d <= bound * s.size) {
                    let name = ffr_spec::text::quoted(&sys.bodies[s.body].name);
                    let (at, what) = if s.nodes {
                        (
                            format!("node {}", *x as usize),
                            "its size (nodes' bounding-box diagonal)",
                        )
                    } else {
                        (format!("x = {x:.4} m"), "its length")
                    };
                    return Some(format!(
                        "body `{name}` is deformed by {d:.3e} m at {at}, more than {bound} × {what} {:.4} m: the elastic coordinates have left any valid range",
                        s.size
                    ));
                }
            }
        }
        None
    }
}

/// The validity check of a state, shared by every path that produces one
/// (time runs after every step through the monitor, `ffr static`, the
/// Campbell steady state, `linearize --at`): every coordinate and rate
/// finite, every flexible body — beam, modal or FE — deformed by at most
/// the monitor's [`Monitor::deformation`] times its size (a beam's length,
/// an FE body's nodes' bounding-box diagonal), and the energy at the
/// state finite. `Err(reason)` says which, with the numbers.
pub fn check_state<B: Body>(
    sys: &crate::System<B>,
    q: &[f64],
    v: &[f64],
) -> std::result::Result<(), String> {
    let labels = || crate::linear::coordinate_labels(sys);
    if let Some(i) = q.iter().position(|x| !x.is_finite()) {
        return Err(format!(
            "coordinate `{}` is {}, not finite",
            ffr_spec::text::quoted(&labels()[i]),
            q[i]
        ));
    }
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(format!(
            "the rate of coordinate `{}` is {}, not finite",
            ffr_spec::text::quoted(&labels()[i]),
            v[i]
        ));
    }
    let bound = if sys.monitor.deformation.is_finite() && sys.monitor.deformation > 0.0 {
        sys.monitor.deformation
    } else {
        Monitor::default().deformation
    };
    let validity = Validity::new(sys).map_err(|e| e.to_string())?;
    if let Some(why) = validity.deformation(sys, q, bound) {
        return Err(why);
    }
    let mut asm = Assembly::new(sys).map_err(|e| e.to_string())?;
    let e = asm.energy(q, v);
    let parts = [
        ("kinetic", e.kinetic),
        ("elastic", e.elastic),
        ("gravity", e.gravity),
        ("spring", e.springs),
    ];
    if let Some((what, x)) = parts.iter().find(|(_, x)| !x.is_finite()) {
        return Err(format!("the {what} energy is {x}, not finite"));
    }
    Ok(())
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

/// What a [`Watch`] accumulates over a run (its integrals and the first
/// excess), saved and restored with a stepper's state.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct WatchState {
    work: f64,
    work_abs: f64,
    dissipated: f64,
    last: Option<(f64, crate::Power)>,
    first_excess: Option<f64>,
}

/// The monitor's state during one run.
pub(crate) struct Watch {
    settings: Monitor,
    validity: Validity,
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
        let validity = Validity::new(sys)?;
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
        for b in sys.bodies.iter() {
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
        }
        let e = asm.energy(&state.q, &state.v);
        Ok(Self {
            settings,
            validity,
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

    /// What it has accumulated.
    pub(crate) fn save(&self) -> WatchState {
        WatchState {
            work: self.work,
            work_abs: self.work_abs,
            dissipated: self.dissipated,
            last: self.last,
            first_excess: self.first_excess,
        }
    }

    /// Put back what [`Watch::save`] gave.
    pub(crate) fn restore(&mut self, s: &WatchState) {
        self.work = s.work;
        self.work_abs = s.work_abs;
        self.dissipated = s.dissipated;
        self.last = s.last;
        self.first_excess = s.first_excess;
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
        if let Some(why) = self
            .validity
            .deformation(asm.sys, &state.q, self.settings.deformation)
        {
            return fail(why);
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
