//! Time integration: generalized-α for the index-3 equations (Arnold & Brüls
//! 2007) with Newton iterations on the analytic iteration matrix, and
//! explicit RK4 on the index-1 form with Baumgarte stabilization.
//!
//! Newton convergence is judged on the accelerations a step produces: an
//! iteration is converged when every update of a free coordinate, scaled to
//! an acceleration (`β' Δq`), is below `rtol` times that coordinate's
//! acceleration scale (its own `|q̈|` plus the largest `|q̈|` of its class —
//! frame translations, frame rotations, elastic translations, elastic
//! rotations of one body — plus `10⁻⁶` of the largest of all coordinates'),
//! and likewise every multiplier update relative to its joint's multipliers
//! (plus `10⁻⁶` of the largest of all multipliers; accelerations and
//! multipliers are never compared with each other, their ratio is a mass). This is
//! independent of the step size and of the units, so the answer converges as
//! `dt` shrinks and meshes refine. Updates below the round-off of the
//! positions (of the coordinate's class, and for a beam's elastic rotations
//! and translations also of the other class through the body length) are
//! converged whatever the accelerations: in a steady state they are noise.

use crate::assembly::Assembly;
use crate::body::Body;
use crate::error::{Error, Result};
use crate::system::System;
use std::ops::ControlFlow;

/// Generalized-α settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeneralizedAlpha {
    /// Spectral radius at infinite frequency `ρ∞ ∈ [0, 1]` (1: no numerical damping).
    pub rho_inf: f64,
    /// Relative Newton tolerance on the accelerations.
    pub rtol: f64,
    /// Maximum Newton iterations per step.
    pub max_iter: usize,
}

impl Default for GeneralizedAlpha {
    fn default() -> Self {
        Self {
            rho_inf: 0.8,
            rtol: 1e-10,
            max_iter: 25,
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

/// The state of a system.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Time.
    pub t: f64,
    /// Generalized coordinates.
    pub q: Vec<f64>,
    /// Generalized velocities.
    pub v: Vec<f64>,
    /// Accelerations `q̈`.
    pub a: Vec<f64>,
    /// Lagrange multipliers (one per constraint row incl. normalizations).
    pub lambda: Vec<f64>,
}

/// What an observer sees after each step (and once for the initial state, `step == 0`).
pub struct StepView<'a, 's, B: Body> {
    /// Number of steps taken.
    pub step: usize,
    /// The state.
    pub state: &'a State,
    /// Newton iterations of the last step (0 for explicit / initial).
    pub iterations: usize,
    /// Iteration matrices factored so far (all steps up to this one), so
    /// that a run that fails later can say how many it took.
    pub jacobians: usize,
    /// The assembled equations (energies, momenta, marker positions).
    pub assembly: &'a mut Assembly<'s, B>,
}

impl<B: Body> StepView<'_, '_, B> {
    /// Energies at the state.
    pub fn energy(&mut self) -> crate::Energy {
        self.assembly.energy(&self.state.q, &self.state.v)
    }
    /// Linear and angular momentum (about the origin) at the state.
    pub fn momentum(&mut self) -> (nalgebra::Vector3<f64>, nalgebra::Vector3<f64>) {
        self.assembly.momentum(&self.state.q, &self.state.v)
    }
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
    /// Iteration-matrix evaluations (and factorizations).
    pub jacobians: usize,
    /// Generalized-α steps whose Newton iteration failed from the
    /// extrapolating predictor and was started again from rest.
    pub restarts: usize,
    /// Generalized-α steps that failed from both starts and were done in two
    /// halves (each half counts once; halves may split again).
    pub splits: usize,
    /// The largest elastic section rotation of each flexible body over
    /// the run ([`crate::monitor::ElasticRotation`]).
    pub rotations: Vec<crate::monitor::ElasticRotation>,
}

/// Preallocated vectors of the linear solves.
#[derive(Clone)]
struct Lin {
    r: Vec<f64>,
    x: Vec<f64>,
    rhs: Vec<f64>,
    lam0: Vec<f64>,
    gam: Vec<f64>,
    vv: Vec<f64>,
}

/// Preallocated vectors of the steps.
#[derive(Clone)]
struct Work {
    lin: Lin,
    acc: Vec<f64>,
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    lam: Vec<f64>,
    lam_phys: Vec<f64>,
    k: [Vec<f64>; 8],
    class_max: Vec<f64>,
    class_qmax: Vec<f64>,
    /// Position scale of each class's round-off floor (`class_qmax` plus
    /// its linked class's, converted by the body length).
    class_qfloor: Vec<f64>,
    class_link: Vec<crate::assembly::ClassLink>,
    /// Classes `0..coord_classes` are coordinates', the rest multipliers'.
    coord_classes: usize,
    prev_a: Vec<f64>,
    /// The multipliers of the step before the last (their predictor).
    prev_lam: Vec<f64>,
    prev_h: f64,
    coord_class: Vec<u32>,
    mult_class: Vec<u32>,
    jac_h: f64,
    have_jac: bool,
}

impl Work {
    fn new<B: Body>(asm: &Assembly<B>) -> Self {
        let (n, m) = (asm.n, asm.m);
        let (cc, mc, links) = asm.classes();
        let classes = links.len();
        Self {
            lin: Lin {
                r: vec![0.0; n + m],
                x: vec![0.0; n + m],
                rhs: vec![0.0; n + m],
                lam0: vec![0.0; m],
                gam: vec![0.0; m],
                vv: vec![0.0; m],
            },
            acc: vec![0.0; n],
            q: vec![0.0; n],
            v: vec![0.0; n],
            a: vec![0.0; n],
            lam: vec![0.0; m],
            lam_phys: vec![0.0; m],
            k: std::array::from_fn(|_| vec![0.0; n]),
            class_max: vec![0.0; classes],
            class_qmax: vec![0.0; classes],
            class_qfloor: vec![0.0; classes],
            class_link: links.to_vec(),
            coord_classes: cc.iter().map(|&k| k as usize + 1).max().unwrap_or(0),
            prev_a: vec![0.0; n],
            prev_lam: vec![0.0; m],
            prev_h: 0.0,
            coord_class: cc.to_vec(),
            mult_class: mc.to_vec(),
            jac_h: f64::NAN,
            have_jac: false,
        }
    }
}

fn all_finite(x: &[f64]) -> bool {
    x.iter().all(|v| v.is_finite())
}

/// Check the step and the integrator's settings (`t_end` only for its sign
/// and finiteness).
pub fn check_settings(t_end: f64, dt: f64, integrator: &Integrator) -> Result<()> {
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
        if !(g.rtol > 0.0 && g.rtol < 1.0) || g.max_iter == 0 {
            return Err(Error::InvalidInput(format!(
                "Newton tolerance {} must be in (0, 1) with at least one iteration",
                g.rtol
            )));
        }
    }
    Ok(())
}

/// One integration of a system, a step at a time: the assembled equations,
/// the state, the integrator's history (the generalized-α auxiliary
/// acceleration, the last step's accelerations and multipliers, the
/// iteration matrix and its step length), the divergence monitor and the
/// elastic-rotation tracker. [`System::simulate`] is a loop over
/// [`Stepper::step`]; a caller that decides what happens between steps
/// (inputs, a controller, a co-simulation master) holds a `Stepper`.
/// Nothing is allocated inside a step.
pub struct Stepper<'s, B: Body> {
    asm: Assembly<'s, B>,
    integrator: Integrator,
    /// The end time the monitor's energy floor is scaled with.
    t_end: f64,
    w: Work,
    state: State,
    watch: Option<crate::monitor::Watch>,
    rotations: crate::monitor::Rotations,
    /// Counters (`last` and `rotations` are filled by [`Stepper::finish`]).
    summary: Summary,
    /// Newton iterations of the last step.
    iterations: usize,
}

/// Everything a [`Stepper`]'s next step depends on, copied out
/// ([`Stepper::save`]) to be put back ([`Stepper::restore`]): a restored
/// stepper continues bit for bit as the one saved.
#[derive(Clone)]
pub struct StepperState {
    w: Work,
    state: State,
    solver: crate::linalg::BorderedSystem,
    inputs: Vec<f64>,
    drives: Vec<[f64; 3]>,
    watch: Option<crate::monitor::WatchState>,
    rotations: Vec<crate::monitor::ElasticRotation>,
    summary: Summary,
    iterations: usize,
}

impl std::fmt::Debug for StepperState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StepperState")
            .field("t", &self.state.t)
            .field("steps", &self.summary.steps)
            .finish_non_exhaustive()
    }
}

impl StepperState {
    /// The saved state (time, coordinates, velocities, accelerations,
    /// multipliers).
    pub fn state(&self) -> &State {
        &self.state
    }
    /// Steps taken when it was saved.
    pub fn steps(&self) -> usize {
        self.summary.steps
    }
}

/// A summary with no steps (and empty `last`, `rotations`).
fn empty_summary() -> Summary {
    Summary {
        steps: 0,
        last: State {
            t: 0.0,
            q: Vec::new(),
            v: Vec::new(),
            a: Vec::new(),
            lambda: Vec::new(),
        },
        stopped: false,
        newton_iterations: 0,
        jacobians: 0,
        restarts: 0,
        splits: 0,
        rotations: Vec::new(),
    }
}

/// The consistent initial state of `asm`'s system at `t = 0` (checked),
/// the integrator's work space, the monitor and the rotation tracker.
#[allow(clippy::type_complexity)]
fn start<B: Body>(
    asm: &mut Assembly<'_, B>,
    t_end: f64,
) -> Result<(
    Work,
    State,
    Option<crate::monitor::Watch>,
    crate::monitor::Rotations,
)> {
    let sys = asm.sys;
    let mut w = Work::new(asm);
    let state = initial_state(asm, &mut w.lin, 0.0)?;
    w.acc.copy_from_slice(&state.a);
    // The initial state passes the validity check every later state
    // passes (a body started at 1.8e308 m/s has an infinite energy: it
    // ran until the energy monitor reported NaN J "gained from nowhere").
    if sys.monitor.enabled {
        crate::monitor::check_state(sys, &state.q, &state.v)
            .map_err(|why| Error::InvalidInput(format!("the initial state is not valid: {why}")))?;
    }
    let watch = if sys.monitor.enabled {
        Some(crate::monitor::Watch::new(asm, sys.monitor, &state, t_end)?)
    } else {
        None
    };
    let mut rotations = crate::monitor::Rotations::new(sys)?;
    rotations.observe(state.t, &state.q);
    Ok((w, state, watch, rotations))
}

impl<'s, B: Body> Stepper<'s, B> {
    /// The consistent initial state of `sys` at `t = 0`, checked as
    /// [`System::simulate`] checks it, ready to step with `integrator`.
    /// `t_end` is the end time the divergence monitor scales its energy
    /// floor with (the run's; stepping may go past it).
    pub fn new(sys: &'s System<B>, t_end: f64, integrator: &Integrator) -> Result<Self> {
        check_settings(t_end, 1.0, integrator)?;
        let mut asm = Assembly::new(sys)?;
        let (w, state, watch, rotations) = start(&mut asm, t_end)?;
        Ok(Self {
            asm,
            integrator: *integrator,
            t_end,
            w,
            state,
            watch,
            rotations,
            summary: empty_summary(),
            iterations: 0,
        })
    }

    /// Start again from the consistent initial state at `t = 0` with the
    /// inputs' current values (their drive perturbations at rest): what
    /// setting an input before the first step means. An error (the initial
    /// state with these values is refused) leaves the stepper unchanged.
    pub fn restart(&mut self) -> Result<()> {
        let drives = self.asm.drive_states().to_vec();
        self.asm
            .drive_states_mut()
            .iter_mut()
            .for_each(|d| *d = [0.0; 3]);
        self.asm.sync_inputs();
        match start(&mut self.asm, self.t_end) {
            Ok((w, state, watch, rotations)) => {
                self.w = w;
                self.state = state;
                self.watch = watch;
                self.rotations = rotations;
                self.summary = empty_summary();
                self.iterations = 0;
                Ok(())
            }
            Err(e) => {
                self.asm.drive_states_mut().copy_from_slice(&drives);
                self.asm.sync_inputs();
                Err(e)
            }
        }
    }

    /// One step of length `h` from [`Stepper::state`] (the time after it is
    /// `t + h`). An error leaves the state of the failed step (restore a
    /// saved state to go on) and the counters of the steps before it.
    pub fn step(&mut self, h: f64) -> Result<()> {
        let s = &self.summary;
        let before = (
            s.steps,
            s.newton_iterations,
            s.jacobians,
            s.restarts,
            s.splits,
        );
        let r = self.try_step(h);
        if r.is_err() {
            let s = &mut self.summary;
            (
                s.steps,
                s.newton_iterations,
                s.jacobians,
                s.restarts,
                s.splits,
            ) = before;
        }
        r
    }

    fn try_step(&mut self, h: f64) -> Result<()> {
        let step = self.summary.steps;
        let iters = match &self.integrator {
            Integrator::GeneralizedAlpha(g) => ga_interval(
                &mut self.asm,
                g,
                &mut self.state,
                &mut self.w,
                h,
                step,
                0,
                &mut self.summary,
            )?,
            Integrator::Rk4(r) => {
                rk4_step(&mut self.asm, r, &mut self.state, &mut self.w, h, step)?;
                0
            }
        };
        self.asm.advance_drive_perturbations(self.state.t);
        self.iterations = iters;
        self.summary.newton_iterations += iters;
        self.summary.steps = step + 1;
        self.rotations.observe(self.state.t, &self.state.q);
        if let Some(w) = &mut self.watch {
            w.after_step(&mut self.asm, &self.state, &self.summary)?;
        }
        Ok(())
    }

    /// The state.
    pub fn state(&self) -> &State {
        &self.state
    }

    /// The assembled equations (energies, powers, markers, inputs).
    pub fn assembly(&mut self) -> &mut Assembly<'s, B> {
        &mut self.asm
    }

    /// The values of the system's inputs.
    pub fn inputs(&self) -> &[f64] {
        self.asm.inputs()
    }

    /// The inputs' drive perturbations at the start of the next step
    /// (`[t₀, δ₀, δ̇₀]` per input).
    pub fn drive_states(&self) -> &[[f64; 3]] {
        self.asm.drive_states()
    }

    /// Set input `k` to `value` from the next step on.
    pub fn set_input(&mut self, k: usize, value: f64) {
        self.asm.inputs_mut()[k] = value;
        self.asm.sync_inputs();
    }

    /// The state and the assembled equations at once.
    pub fn state_and_assembly(&mut self) -> (&State, &mut Assembly<'s, B>) {
        (&self.state, &mut self.asm)
    }

    /// The counters so far (steps, Newton iterations, iteration matrices,
    /// restarts, splits; `last` and `rotations` are empty until
    /// [`Stepper::finish`]).
    pub fn counters(&self) -> &Summary {
        &self.summary
    }

    /// Newton iterations of the last step (0 before the first and for RK4).
    pub fn last_iterations(&self) -> usize {
        self.iterations
    }

    /// What an observer sees now.
    pub fn view(&mut self) -> StepView<'_, 's, B> {
        StepView {
            step: self.summary.steps,
            state: &self.state,
            iterations: self.iterations,
            jacobians: self.summary.jacobians,
            assembly: &mut self.asm,
        }
    }

    /// The largest elastic section rotation of each flexible body so far.
    pub fn rotations(&self) -> &[crate::monitor::ElasticRotation] {
        &self.rotations.max
    }

    /// The summary of the integration so far, with the final state.
    pub fn finish(self) -> Summary {
        Summary {
            last: self.state,
            rotations: self.rotations.max,
            ..self.summary
        }
    }

    /// Everything the next step depends on (allocates: a copy of the
    /// state, the integrator's history and the factored iteration matrix).
    pub fn save(&self) -> StepperState {
        StepperState {
            w: self.w.clone(),
            state: self.state.clone(),
            solver: self.asm.solver.clone(),
            inputs: self.asm.inputs().to_vec(),
            drives: self.asm.drive_states().to_vec(),
            watch: self.watch.as_ref().map(|w| w.save()),
            rotations: self.rotations.max.clone(),
            summary: self.summary.clone(),
            iterations: self.iterations,
        }
    }

    /// Put back a state saved from a stepper of the same system (`Err` if
    /// its sizes differ; nothing is changed then).
    pub fn restore(&mut self, s: &StepperState) -> Result<()> {
        let same = s.state.q.len() == self.state.q.len()
            && s.state.lambda.len() == self.state.lambda.len()
            && s.inputs.len() == self.asm.inputs().len()
            && s.rotations.len() == self.rotations.max.len()
            && s.watch.is_some() == self.watch.is_some()
            && s.solver.same_shape(&self.asm.solver);
        if !same {
            return Err(Error::InvalidInput(
                "the saved state is of another system".into(),
            ));
        }
        self.w.clone_from(&s.w);
        self.state.clone_from(&s.state);
        self.asm.solver.clone_from(&s.solver);
        self.asm.inputs_mut().copy_from_slice(&s.inputs);
        self.asm.drive_states_mut().copy_from_slice(&s.drives);
        self.asm.sync_inputs();
        if let (Some(w), Some(saved)) = (&mut self.watch, &s.watch) {
            w.restore(saved);
        }
        self.rotations.max.clone_from(&s.rotations);
        self.summary.clone_from(&s.summary);
        self.iterations = s.iterations;
        Ok(())
    }
}

impl<B: Body> System<B> {
    /// Integrate from the consistent initial state at `t = 0` to `t_end` with
    /// step `dt`, calling `observer` at the start and after each step (it may
    /// stop the run with `ControlFlow::Break`). Nothing is allocated inside a
    /// step. A loop over [`Stepper::step`] (the last step shortened to end
    /// at `t_end`).
    pub fn simulate(
        &self,
        t_end: f64,
        dt: f64,
        integrator: &Integrator,
        mut observer: impl FnMut(&mut StepView<B>) -> ControlFlow<()>,
    ) -> Result<Summary> {
        check_settings(t_end, dt, integrator)?;
        let n_steps = step_count(t_end, dt)?;
        let mut stepper = Stepper::new(self, t_end, integrator)?;
        if observer(&mut stepper.view()).is_break() {
            let mut summary = stepper.finish();
            summary.stopped = true;
            return Ok(summary);
        }
        for _ in 0..n_steps {
            stepper.step(step_length(stepper.state().t, t_end, dt))?;
            if observer(&mut stepper.view()).is_break() {
                let mut summary = stepper.finish();
                summary.stopped = true;
                return Ok(summary);
            }
        }
        Ok(stepper.finish())
    }

    /// The consistent initial state at `t0`: prescribed coordinates from their
    /// drivers, positions and velocities projected onto the constraints
    /// (mass-weighted least-squares corrections of the free coordinates),
    /// accelerations and multipliers from the index-1 equations.
    pub fn initial_state(&self, t0: f64) -> Result<State> {
        let mut asm = Assembly::new(self)?;
        let mut w = Work::new(&asm);
        initial_state(&mut asm, &mut w.lin, t0)
    }
}

fn initial_state<B: Body>(asm: &mut Assembly<B>, w: &mut Lin, t0: f64) -> Result<State> {
    let (n, m) = (asm.n, asm.m);
    let (q0, v0) = asm.sys.initial_coords();
    let mut q = q0.to_vec();
    let mut v = v0.to_vec();
    let mut a = vec![0.0; n];
    asm.apply_prescribed(t0, &mut q, &mut v, &mut a);
    if !all_finite(&q) || !all_finite(&v) || !all_finite(&a) {
        return Err(Error::InvalidInput(format!(
            "non-finite initial state or prescribed motion at t = {t0}"
        )));
    }
    crate::initial::make_consistent(asm, t0, &mut q, &mut v)?;
    let mut lam = vec![0.0; m];
    // Non-finite forces before any step are values too large for f64 (a
    // speed, a load, a stiffness), not a step too long: say so.
    accelerations(asm, w, t0, &q, &v, &mut a, &mut lam, (0.0, 0.0)).map_err(|e| match e {
        Error::Unstable { what, t } => Error::InvalidInput(format!(
            "the {what} of the initial state (t = {t:?} s) are not finite: a value of the scene (a speed, load, stiffness or mass) is too large for double precision (no step has been taken: a smaller step does not help)"
        )),
        other => other,
    })?;
    Ok(State {
        t: t0,
        q,
        v,
        a,
        lambda: lam,
    })
}

/// The number of steps of `dt` that reach `t_end` (the last one possibly
/// shorter, [`step_length`]).
pub fn step_count(t_end: f64, dt: f64) -> Result<usize> {
    let steps_f = (t_end / dt - 1e-9).ceil().max(0.0);
    if steps_f > 1e10 {
        return Err(Error::InvalidInput(format!(
            "t_end / dt = {steps_f:e} steps is more than this program will take"
        )));
    }
    Ok(steps_f as usize)
}

/// The length of the step from `t0` of a run to `t_end` with step `dt`:
/// `dt`, or what is left to `t_end` if that is less (and not a sliver of
/// round-off, below `10⁻¹² dt`).
pub fn step_length(t0: f64, t_end: f64, dt: f64) -> f64 {
    let h = (t_end - t0).min(dt);
    if h < 1e-12 * dt {
        dt
    } else {
        h
    }
}

/// Solve the index-1 equations for the free accelerations (prescribed ones
/// are in `a` already) and the multipliers, with Baumgarte gains `(α, β)`.
#[allow(clippy::too_many_arguments)]
fn accelerations<B: Body>(
    asm: &mut Assembly<B>,
    w: &mut Lin,
    t: f64,
    q: &[f64],
    v: &[f64],
    a: &mut [f64],
    lam: &mut [f64],
    baumgarte: (f64, f64),
) -> Result<()> {
    let (n, m) = (asm.n, asm.m);
    for (c, ac) in a[..n].iter_mut().enumerate() {
        if !asm.is_prescribed(c) {
            *ac = 0.0;
        }
    }
    asm.residual(t, q, v, a, &w.lam0, &mut w.r);
    if !all_finite(&w.r) {
        return Err(Error::Unstable {
            what: "forces or constraint terms",
            t,
        });
    }
    asm.gamma(t, v, &mut w.gam);
    asm.velocity_violation(v, q, &mut w.vv);
    asm.mass_system(t, q);
    asm.factor(t, "mass system [M Φ_qᵀ; Φ_q 0]")?;
    let (al, be) = baumgarte;
    for c in 0..n {
        w.rhs[c] = -w.r[c];
    }
    for k in 0..m {
        w.rhs[n + k] = w.gam[k] - 2.0 * al * w.vv[k] - be * be * w.r[n + k];
    }
    asm.solve(&w.rhs, &mut w.x);
    if !all_finite(&w.x) {
        return Err(Error::Unstable {
            what: "accelerations",
            t,
        });
    }
    for (c, ac) in a[..n].iter_mut().enumerate() {
        if !asm.is_prescribed(c) {
            *ac = w.x[c];
        }
    }
    lam.copy_from_slice(&w.x[n..n + m]);
    Ok(())
}

fn rk4_step<B: Body>(
    asm: &mut Assembly<B>,
    r: &Rk4Baumgarte,
    s: &mut State,
    w: &mut Work,
    h: f64,
    step: usize,
) -> Result<()> {
    let n = asm.n;
    let t = s.t;
    let g = (r.alpha, r.beta);
    // k[2i] = q̇ and k[2i + 1] = q̈ of stage i.
    for (i, c) in [0.0, 0.5, 0.5, 1.0].into_iter().enumerate() {
        let ts = t + c * h;
        for j in 0..n {
            if i == 0 {
                w.q[j] = s.q[j];
                w.v[j] = s.v[j];
            } else {
                w.q[j] = s.q[j] + c * h * w.k[2 * i - 2][j];
                w.v[j] = s.v[j] + c * h * w.k[2 * i - 1][j];
            }
        }
        asm.apply_prescribed(ts, &mut w.q, &mut w.v, &mut w.a);
        accelerations(asm, &mut w.lin, ts, &w.q, &w.v, &mut w.a, &mut w.lam, g)?;
        w.k[2 * i].copy_from_slice(&w.v);
        w.k[2 * i + 1].copy_from_slice(&w.a);
    }
    for j in 0..n {
        s.q[j] += h / 6.0 * (w.k[0][j] + 2.0 * w.k[2][j] + 2.0 * w.k[4][j] + w.k[6][j]);
        s.v[j] += h / 6.0 * (w.k[1][j] + 2.0 * w.k[3][j] + 2.0 * w.k[5][j] + w.k[7][j]);
    }
    s.t = t + h;
    asm.apply_prescribed(s.t, &mut s.q, &mut s.v, &mut s.a);
    if !all_finite(&s.q) || !all_finite(&s.v) {
        return Err(Error::NonFinite {
            what: "coordinates",
            step,
            t,
        });
    }
    accelerations(asm, &mut w.lin, s.t, &s.q, &s.v, &mut s.a, &mut s.lambda, g)
}

/// Updates below this many ulps of a value are round-off.
const ROUNDOFF: f64 = 64.0 * f64::EPSILON;

/// The acceleration-level tolerance of coordinate `c` (class `k`):
/// `rtol (|q̈_c| + max_k |q̈| + 10⁻⁶ max |q̈|) + β' · 64 ε (|q_c| + max_k |q| + max_k' |q| · f)`,
/// the second term the round-off floor of a position update. `k'` is the
/// class linked to `k` with the factor `f` (a beam's elastic rotations and
/// translations, `f = 1/L` and `L`): the linear solve mixes the round-off of
/// every coordinate into each update, so a class whose own positions are at
/// zero (the elastic rotations of a beam that only stretches) still sees the
/// noise of the other's (a rotation of `64 ε |u|/L` moves the points of the
/// beam by round-off of its displacements `u`).
fn coord_scale(g: &GeneralizedAlpha, w: &Work, c: usize, k: usize, bp: f64, all_max: f64) -> f64 {
    g.rtol * (w.a[c].abs() + w.class_max[k] + 1e-6 * all_max)
        + bp * ROUNDOFF * (w.q[c].abs() + w.class_qfloor[k])
        + f64::MIN_POSITIVE
}

/// How a generalized-α step starts its Newton iteration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Predictor {
    /// `q̈` extrapolated linearly from the last two steps.
    Extrapolate,
    /// `q̈ = 0` (free coordinates).
    Rest,
}

/// Steps are split in halves at most this many times (to `h / 2⁸`).
const MAX_SPLITS: u32 = 8;

/// Whether a failed step may succeed from another start or with a shorter
/// step (Newton did not converge, or wandered into a non-finite or singular
/// state), as opposed to an error of the model.
fn retry_may_help(e: &Error) -> bool {
    matches!(
        e,
        Error::NoConvergence { .. }
            | Error::NonFinite { .. }
            | Error::Singular {
                what: "generalized-α iteration matrix",
                ..
            }
    )
}

/// One generalized-α step of length `h`, made robust: if Newton fails from
/// the extrapolating predictor it starts again from rest, and if that fails
/// too the interval is done in two halves (recursively, at most
/// [`MAX_SPLITS`] times). A step that converges at once is exactly
/// [`ga_step`]; `stats` counts the restarts and splits.
#[allow(clippy::too_many_arguments)]
fn ga_interval<B: Body>(
    asm: &mut Assembly<B>,
    g: &GeneralizedAlpha,
    s: &mut State,
    w: &mut Work,
    h: f64,
    step: usize,
    depth: u32,
    stats: &mut Summary,
) -> Result<usize> {
    let first = match ga_step(asm, g, s, w, h, step, Predictor::Extrapolate) {
        Ok((it, jacs)) => {
            stats.jacobians += jacs;
            return Ok(it);
        }
        Err(e) if retry_may_help(&e) => e,
        Err(e) => return Err(e),
    };
    stats.restarts += 1;
    match ga_step(asm, g, s, w, h, step, Predictor::Rest) {
        Ok((it, jacs)) => {
            stats.jacobians += jacs;
            return Ok(it);
        }
        Err(e) if retry_may_help(&e) => {}
        Err(e) => return Err(e),
    }
    if depth >= MAX_SPLITS {
        return Err(first);
    }
    stats.splits += 1;
    let (t0, t_end) = (s.t, s.t + h);
    let halves = ga_interval(asm, g, s, w, 0.5 * h, step, depth + 1, stats).and_then(|a| {
        ga_interval(asm, g, s, w, t_end - s.t, step, depth + 1, stats).map(|b| a + b)
    });
    match halves {
        Err(e) if depth == 0 && retry_may_help(&e) => Err(Error::StepFailed {
            step,
            t: t0,
            halvings: MAX_SPLITS,
            dt_min: h / f64::from(1u32 << MAX_SPLITS),
            cause: Box::new(e),
        }),
        other => other,
    }
}

#[allow(clippy::too_many_arguments)]
fn ga_step<B: Body>(
    asm: &mut Assembly<B>,
    g: &GeneralizedAlpha,
    s: &mut State,
    w: &mut Work,
    h: f64,
    step: usize,
    predictor: Predictor,
) -> Result<(usize, usize)> {
    let (n, m) = (asm.n, asm.m);
    let (am, af, gamma, beta) = g.coefficients();
    let bp = (1.0 - am) / ((1.0 - af) * beta * h * h);
    let gp = gamma / (beta * h);
    let t0 = s.t;
    let t1 = t0 + h;
    // Predictor: q̈_{n+1} extrapolated linearly from the last two steps
    // (constant on the first), or zero, with q and q̇ from the
    // generalized-α relations (prescribed coordinates exact). Any start
    // satisfying the relations works; extrapolation is off by O(h²) in q̈
    // on smooth motion, zero is the safer start where stiff modes ring.
    let ratio = if w.prev_h > 0.0 { h / w.prev_h } else { 0.0 };
    for c in 0..n {
        let qdd = match predictor {
            Predictor::Extrapolate => s.a[c] + ratio * (s.a[c] - w.prev_a[c]),
            Predictor::Rest => 0.0,
        };
        let a_new = ((1.0 - af) * qdd + af * s.a[c] - am * w.acc[c]) / (1.0 - am);
        w.v[c] = s.v[c] + h * (1.0 - gamma) * w.acc[c] + h * gamma * a_new;
        w.q[c] = s.q[c] + h * s.v[c] + h * h * (0.5 - beta) * w.acc[c] + h * h * beta * a_new;
        w.a[c] = qdd;
    }
    asm.apply_prescribed(t1, &mut w.q, &mut w.v, &mut w.a);
    // The multipliers likewise: extrapolated from the last two steps (as
    // q̈, an acceleration-level unknown), or the last step's.
    for k in 0..m {
        let lam = match predictor {
            Predictor::Extrapolate if w.prev_h > 0.0 => {
                s.lambda[k] + ratio * (s.lambda[k] - w.prev_lam[k])
            }
            _ => s.lambda[k],
        };
        w.lam[k] = lam / bp;
    }
    if w.have_jac && (w.jac_h - h).abs() > 1e-12 * h {
        w.have_jac = false;
    }
    let mut jacs = 0;
    let mut prev = f64::INFINITY;
    let mut prev_theta = f64::INFINITY;
    // Smallest update seen in this step (round-off detection).
    let mut least = f64::INFINITY;
    // Smallest multiplier update (scaled) seen in this step.
    let mut least_l = f64::INFINITY;
    let mut fresh = false;
    let mut since_fresh = 0usize;
    let mut res_norm = f64::NAN;
    for it in 1..=g.max_iter {
        if !w.have_jac {
            asm.jacobian(t1, &w.q, &w.v, &w.a, &w.lam, bp, gp, &mut w.lin.r);
            asm.factor(t1, "generalized-α iteration matrix")?;
            jacs += 1;
            w.have_jac = true;
            w.jac_h = h;
            fresh = true;
            since_fresh = 0;
        } else {
            since_fresh += 1;
            // Physical multipliers in the residual.
            for k in 0..m {
                w.lam_phys[k] = w.lam[k] * bp;
            }
            asm.residual(t1, &w.q, &w.v, &w.a, &w.lam_phys, &mut w.lin.r);
        }
        let lin = &mut w.lin;
        for c in 0..n {
            lin.r[c] /= bp;
        }
        res_norm = lin.r.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !res_norm.is_finite() {
            w.have_jac = false;
            return Err(Error::NonFinite {
                what: "residual",
                step,
                t: t0,
            });
        }
        for k in 0..n + m {
            lin.rhs[k] = -lin.r[k];
        }
        asm.solve(&lin.rhs, &mut lin.x);
        if !all_finite(&lin.x) {
            w.have_jac = false;
            return Err(Error::Singular {
                what: "generalized-α iteration matrix",
                t: t1,
                detail: "the Newton update is not finite".into(),
            });
        }
        for c in 0..n {
            if !asm.is_prescribed(c) {
                let d = w.lin.x[c];
                w.q[c] += d;
                w.v[c] += gp * d;
                w.a[c] += bp * d;
            }
        }
        for k in 0..m {
            w.lam[k] += w.lin.x[n + k];
        }
        // Scales per class: largest |q̈| (coordinates) and |λ| (multipliers).
        w.class_max.iter_mut().for_each(|x| *x = 0.0);
        w.class_qmax.iter_mut().for_each(|x| *x = 0.0);
        for c in 0..n {
            if !asm.is_prescribed(c) {
                let k = w.coord_class[c] as usize;
                w.class_max[k] = w.class_max[k].max(w.a[c].abs());
                w.class_qmax[k] = w.class_qmax[k].max(w.q[c].abs());
            }
        }
        for k in 0..m {
            let cl = w.mult_class[k] as usize;
            w.class_max[cl] = w.class_max[cl].max((w.lam[k] * bp).abs());
        }
        for (k, link) in w.class_link.iter().enumerate() {
            w.class_qfloor[k] = crate::assembly::class_floor(w.class_qmax[k], link, &w.class_qmax);
        }
        // The largest |q̈| of all coordinates and the largest |λ| of all
        // multipliers, apart: one is an acceleration, the other a force, and
        // their ratio is the system's mass.
        let (coord_classes, mult_classes) = w.class_max.split_at(w.coord_classes);
        let all_max = coord_classes.iter().fold(0.0f64, |s, x| s.max(*x));
        let all_lam = mult_classes.iter().fold(0.0f64, |s, x| s.max(*x));
        let mut err = 0.0f64;
        for c in 0..n {
            if asm.is_prescribed(c) {
                continue;
            }
            let k = w.coord_class[c] as usize;
            err = err.max((bp * w.lin.x[c]).abs() / coord_scale(g, w, c, k, bp, all_max));
        }
        let err_q = err;
        let mut err_l = 0.0f64;
        for k in 0..m {
            let cl = w.mult_class[k] as usize;
            let l = (w.lam[k] * bp).abs();
            let sc = g.rtol * (l + w.class_max[cl] + 1e-6 * all_lam)
                + ROUNDOFF * (l + w.class_max[cl])
                + f64::MIN_POSITIVE;
            err_l = err_l.max((bp * w.lin.x[n + k]).abs() / sc);
        }
        err = err.max(err_l);
        // Converged: this update was within tolerance, or the contraction
        // says what is left after it is (θ/(1 − θ) · err). The estimate is
        // trusted only in Newton's convergent regime: the update is already
        // small (within 10⁴ of the tolerance) and, after the second
        // iteration, the one before it contracted too. A first contraction
        // after wild iterates (err / prev tiny because prev was huge) proves
        // nothing.
        let theta = err / prev;
        let estimate_valid = theta < 0.5 && err <= 1e4 && (it == 2 || prev_theta < 0.5);
        // Round-off: after an iteration on a fresh matrix the updates have
        // stopped shrinking (they are the noise of the residual's
        // evaluation), and are within 10⁶ of the tolerance. "Stopped
        // shrinking" is judged against the smallest update of the step, not
        // only the previous one: at round-off, refreshing the matrix can
        // alternate a larger and a smaller noise update forever (each
        // smaller than half the one before it, never below the tolerance).
        let stalled = since_fresh >= 1 && err >= 0.5 * least && err <= 1e6;
        // Multipliers whose joint carries no force (the normalization of a
        // free body's Euler parameters, a joint at rest) have no scale of
        // their own: their updates are the noise of the solve, arbitrarily
        // many times their ~0 value. When the coordinates are within
        // tolerance and the multiplier updates have stopped shrinking after
        // a fresh matrix, Newton has nothing left to do (the residual is
        // linear in the multipliers: a real multiplier error would be gone
        // after one iteration on a fresh matrix).
        let multipliers_stalled =
            m > 0 && err_q <= 1.0 && since_fresh >= 1 && err_l >= 0.5 * least_l;
        least_l = least_l.min(err_l);
        if err <= 1.0
            || (estimate_valid && err * theta / (1.0 - theta) <= 1.0)
            || stalled
            || multipliers_stalled
        {
            for c in 0..n {
                w.acc[c] = (w.a[c] * (1.0 - af) + s.a[c] * af - w.acc[c] * am) / (1.0 - am);
            }
            w.prev_h = h;
            w.prev_a.copy_from_slice(&s.a);
            w.prev_lam.copy_from_slice(&s.lambda);
            s.t = t1;
            s.q.copy_from_slice(&w.q);
            asm.project_normalization_rates(&w.q, &mut w.v);
            s.v.copy_from_slice(&w.v);
            s.a.copy_from_slice(&w.a);
            for k in 0..m {
                s.lambda[k] = w.lam[k] * bp;
            }
            return Ok((it, jacs));
        }
        // Slow contraction on an old matrix: refresh it (modified Newton
        // becomes full Newton on hard steps).
        if !fresh && (theta > 0.2 || it >= 4) {
            w.have_jac = false;
        }
        fresh = false;
        prev_theta = theta;
        prev = err;
        least = least.min(err);
    }
    w.have_jac = false;
    Err(Error::NoConvergence {
        step,
        t: t0,
        residual: res_norm,
        iterations: g.max_iter,
        dt: h,
    })
}
