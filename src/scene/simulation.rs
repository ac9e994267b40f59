//! A scene stepped by its caller: inputs set between steps, outputs read
//! after each, the whole state saved and restored exactly.
//!
//! [`Simulation`] owns its scene (an [`Arc<Scene>`]) and everything a run
//! needs (the assembled equations, the integrator's history, the monitor,
//! the outputs' evaluation), so it is `'static + Send`: a Python object or
//! an FMU instance can hold it. Several simulations of one scene are
//! independent (input values live in each simulation's assembly, never in
//! the scene). [`super::run()`] is a loop over the same step
//! (`Stepping::step`), so stepping a scene gives the bits of `ffr run`.
//!
//! The assembled equations borrow the system they assemble
//! ([`crate::runtime::Assembly`]`<'s, B>`); a simulation keeps the scene
//! and the stepper that borrows it together with the `self_cell` crate
//! (a small, audited, dependency-free crate for exactly this: an owner and
//! a dependent that borrows it, in one movable value), rather than giving
//! the runtime's assembly an owned or reference-counted system, which would
//! change every user of the runtime for the sake of this one.

use super::model::{EnergyPart, OutputKind, Scene};
use super::run::Recorder;
use crate::runtime::integrator::step_length;
use crate::runtime::{Body, Power, Stepper, StepperState};
use std::sync::Arc;

/// One integration of a scene with its outputs: the step unit that both
/// [`super::run()`] and [`Simulation`] loop over.
pub(super) struct Stepping<'s> {
    scene: &'s Scene,
    stepper: Stepper<'s, Box<dyn Body>>,
    recorder: Recorder,
    /// The outputs at the state.
    outputs: Vec<f64>,
    wants_power: bool,
    /// Work of the applied loads and dissipated energy so far.
    work: f64,
    dissipated: f64,
    /// The last sample's powers and time.
    last_power: Option<(f64, Power)>,
    /// Per input: set by a caller (its profile no longer applies).
    overridden: Vec<bool>,
}

/// What [`Stepping`] keeps beyond its stepper, saved with it.
#[derive(Clone)]
struct Recorded {
    prev_angle: Vec<f64>,
    outputs: Vec<f64>,
    work: f64,
    dissipated: f64,
    last_power: Option<(f64, Power)>,
    overridden: Vec<bool>,
}

impl<'s> Stepping<'s> {
    /// The consistent initial state of `scene` and its outputs.
    pub(super) fn new(scene: &'s Scene) -> Result<Self, crate::runtime::Error> {
        let stepper = Stepper::new(&scene.system, scene.t_end, &scene.integrator)?;
        let wants_power = scene.outputs.iter().any(|o| {
            matches!(
                o.kind,
                OutputKind::Energy(EnergyPart::Work | EnergyPart::Dissipated)
            )
        });
        let mut s = Self {
            scene,
            stepper,
            recorder: Recorder::new(scene),
            outputs: vec![0.0; scene.outputs.len()],
            wants_power,
            work: 0.0,
            dissipated: 0.0,
            last_power: None,
            overridden: vec![false; scene.inputs.len()],
        };
        s.record();
        Ok(s)
    }

    /// The outputs at the state (and the integrals of work and dissipation
    /// by the trapezoidal rule over the samples).
    fn record(&mut self) {
        let (state, asm) = self.stepper.state_and_assembly();
        let (q, qd) = (&state.q, &state.v);
        if self.wants_power {
            let p = asm.power(state.t, q, qd);
            if let Some((t0, p0)) = self.last_power {
                let h = 0.5 * (state.t - t0);
                self.work += h * (p0.applied + p.applied);
                self.dissipated += h * (p0.dissipated + p.dissipated);
            }
            self.last_power = Some((state.t, p));
        }
        let outputs = &mut self.outputs;
        self.recorder.record(
            self.scene,
            asm,
            q,
            qd,
            (self.work, self.dissipated),
            |i, value| outputs[i] = value,
        );
    }

    /// One step of length `h` and the outputs after it. Each input with a
    /// profile that no caller has set takes the profile's value at the
    /// step's start, held over the step.
    pub(super) fn step(&mut self, h: f64) -> Result<(), crate::runtime::Error> {
        let t = self.stepper.state().t;
        for (k, i) in self.scene.inputs.iter().enumerate() {
            if let (Some(p), false) = (&i.profile, self.overridden[k]) {
                self.stepper.set_input(k, p(t));
            }
        }
        self.stepper.step(h)?;
        self.record();
        Ok(())
    }

    /// Set input `k` (a caller's value: its profile no longer applies).
    /// Before the first step the initial state is made again with it (its
    /// accelerations, multipliers and the powers at `t = 0` depend on the
    /// inputs); if that initial state is refused, nothing changes.
    fn set_input(&mut self, k: usize, value: f64) -> Result<(), crate::runtime::Error> {
        let old = self.stepper.inputs()[k];
        self.stepper.set_input(k, value);
        if self.stepper.counters().steps == 0 {
            if let Err(e) = self.stepper.restart() {
                self.stepper.set_input(k, old);
                return Err(e);
            }
            self.recorder.prev_angle.fill(f64::NAN);
            (self.work, self.dissipated, self.last_power) = (0.0, 0.0, None);
            self.record();
        }
        self.overridden[k] = true;
        Ok(())
    }

    pub(super) fn stepper(&self) -> &Stepper<'s, Box<dyn Body>> {
        &self.stepper
    }

    pub(super) fn into_stepper(self) -> Stepper<'s, Box<dyn Body>> {
        self.stepper
    }

    pub(super) fn outputs(&self) -> &[f64] {
        &self.outputs
    }

    fn save(&self) -> (StepperState, Recorded) {
        (
            self.stepper.save(),
            Recorded {
                prev_angle: self.recorder.prev_angle.clone(),
                outputs: self.outputs.clone(),
                work: self.work,
                dissipated: self.dissipated,
                last_power: self.last_power,
                overridden: self.overridden.clone(),
            },
        )
    }

    fn restore(&mut self, s: &StepperState, r: &Recorded) -> Result<(), crate::runtime::Error> {
        if r.outputs.len() != self.outputs.len()
            || r.prev_angle.len() != self.recorder.prev_angle.len()
        {
            return Err(crate::runtime::Error::InvalidInput(
                "the saved state is of another system".into(),
            ));
        }
        self.stepper.restore(s)?;
        self.recorder.prev_angle.copy_from_slice(&r.prev_angle);
        self.outputs.copy_from_slice(&r.outputs);
        self.work = r.work;
        self.dissipated = r.dissipated;
        self.last_power = r.last_power;
        self.overridden.copy_from_slice(&r.overridden);
        Ok(())
    }
}

type Core<'a> = Stepping<'a>;

self_cell::self_cell!(
    /// A scene and its stepping, which borrows it.
    struct Cell {
        owner: Arc<Scene>,
        #[covariant]
        dependent: Core,
    }
);

/// A scene stepped by its caller (see the [module docs](self)).
///
/// ```no_run
/// # fn main() -> ffr::Result<()> {
/// use std::sync::Arc;
/// let scene = Arc::new(ffr::scene::load(std::path::Path::new("scenes/spin_up.toml"))?);
/// let mut sim = ffr::scene::Simulation::new(scene)?;
/// let saved = sim.save_state();
/// sim.advance_to(0.5)?;
/// println!("{:?} at t = {}", sim.outputs(), sim.time());
/// sim.restore_state(&saved)?; // back at t = 0, bit for bit
/// # Ok(()) }
/// ```
pub struct Simulation {
    cell: Cell,
    /// The message of the failed step, if one failed.
    failed: Option<String>,
    /// Which scene a saved state belongs to.
    fingerprint: u64,
}

/// Everything a [`Simulation`]'s next step depends on: the state, the
/// integrator's history (the generalized-α auxiliary acceleration, the
/// last step's accelerations and multipliers, the factored iteration
/// matrix and its step), the divergence monitor's integrals, the
/// elastic-rotation maxima, the outputs' angle unwrapping and work and
/// dissipation integrals, the input values and the counters. Opaque;
/// [`Simulation::restore_state`] puts it back.
#[derive(Clone)]
pub struct SimulationState {
    stepper: StepperState,
    recorded: Recorded,
    fingerprint: u64,
}

impl std::fmt::Debug for SimulationState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SimulationState")
            .field("t", &self.stepper.state().t)
            .field("steps", &self.stepper.steps())
            .finish_non_exhaustive()
    }
}

impl SimulationState {
    /// The time it was saved at.
    pub fn time(&self) -> f64 {
        self.stepper.state().t
    }
}

/// What identifies a scene's states: its file, sizes, step, inputs and
/// outputs (a state of another scene is refused).
fn fingerprint(scene: &Scene) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    scene.origin.hash(&mut h);
    scene.system.n_coords().hash(&mut h);
    scene.dt.to_bits().hash(&mut h);
    for o in &scene.outputs {
        o.name.hash(&mut h);
    }
    for i in &scene.inputs {
        i.name.hash(&mut h);
    }
    h.finish()
}

impl Simulation {
    /// The consistent initial state of `scene` at `t = 0` and its outputs;
    /// a scene whose initial state `ffr run` refuses is refused with the
    /// same message.
    pub fn new(scene: Arc<Scene>) -> crate::Result<Self> {
        let fingerprint = fingerprint(&scene);
        let cell = Cell::try_new(scene, |s| Stepping::new(s))?;
        Ok(Self {
            cell,
            failed: None,
            fingerprint,
        })
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        self.cell.borrow_owner()
    }

    /// The scene, shared.
    pub fn scene_arc(&self) -> &Arc<Scene> {
        self.cell.borrow_owner()
    }

    /// The scene's input names (`[[inputs]]`), in file order.
    pub fn input_names(&self) -> Vec<&str> {
        self.scene()
            .inputs
            .iter()
            .map(|i| i.name.as_str())
            .collect()
    }

    /// The index of input `name`, or an error naming it and the inputs.
    pub fn input_index(&self, name: &str) -> crate::Result<usize> {
        let inputs = &self.scene().inputs;
        inputs.iter().position(|i| i.name == name).ok_or_else(|| {
            let q = crate::runtime::spec::text::quoted;
            let names: Vec<String> = inputs.iter().map(|i| format!("`{}`", q(&i.name))).collect();
            crate::Error::Invalid(format!(
                "{}: no input `{}`; the scene's inputs are {}",
                self.scene().origin,
                q(name),
                if names.is_empty() {
                    "none (add [[inputs]] tables to the scene)".to_string()
                } else {
                    names.join(", ")
                }
            ))
        })
    }

    /// The value of input `name`.
    pub fn input(&self, name: &str) -> crate::Result<f64> {
        let k = self.input_index(name)?;
        Ok(self.cell.borrow_dependent().stepper().inputs()[k])
    }

    /// Set input `name` to `value` from the next step on (held over each
    /// step). An unknown name or a value that is not finite is an error
    /// naming it, and nothing is changed.
    pub fn set_input(&mut self, name: &str, value: f64) -> crate::Result<()> {
        let k = self.input_index(name)?;
        self.set_input_at(k, value)
    }

    /// [`Simulation::set_input`] by the input's index in
    /// [`Simulation::input_names`] (no look-up of the name).
    pub fn set_input_at(&mut self, index: usize, value: f64) -> crate::Result<()> {
        let n = self.scene().inputs.len();
        if index >= n {
            return Err(crate::Error::Invalid(format!(
                "{}: input index {index} is out of range (the scene has {n} input{})",
                self.scene().origin,
                if n == 1 { "" } else { "s" }
            )));
        }
        if !value.is_finite() {
            let q = crate::runtime::spec::text::quoted;
            return Err(crate::Error::Invalid(format!(
                "{}: input `{}` must be finite (got {value})",
                self.scene().origin,
                q(&self.scene().inputs[index].name)
            )));
        }
        self.cell
            .with_dependent_mut(|_, d| d.set_input(index, value))?;
        Ok(())
    }

    /// One step of the scene's `dt` (steps go on past the scene's `t_end`;
    /// the step that ends at `t_end` ends exactly where `ffr run`'s last
    /// sample is, when `t_end` is a whole number of steps). A failed step
    /// returns the message `ffr run` gives (`the run stopped at t = … s:
    /// …`); the simulation then refuses further steps with it until
    /// [`Simulation::restore_state`].
    pub fn step(&mut self) -> crate::Result<()> {
        if let Some(f) = &self.failed {
            return Err(crate::Error::Invalid(f.clone()));
        }
        let scene = self.scene();
        let (t_end, dt) = (scene.t_end, scene.dt);
        let failed = self.cell.with_dependent_mut(|_, d| {
            let t = d.stepper().state().t;
            let run_h = step_length(t, t_end, dt);
            let h = if (run_h - dt).abs() <= 1e-9 * dt {
                run_h
            } else {
                dt
            };
            d.step(h)
                .err()
                .map(|e| format!("the run stopped at t = {t:.6} s: {e}"))
        });
        match failed {
            None => Ok(()),
            Some(f) => {
                self.failed = Some(f.clone());
                Err(crate::Error::Invalid(f))
            }
        }
    }

    /// Whole steps until [`Simulation::time`] reaches `t` (to `10⁻⁹ dt`).
    /// A `t` that whole steps do not reach (behind the time, not finite,
    /// or between two steps) is an error before any step.
    pub fn advance_to(&mut self, t: f64) -> crate::Result<()> {
        if let Some(f) = &self.failed {
            return Err(crate::Error::Invalid(f.clone()));
        }
        let (now, dt) = (self.time(), self.scene().dt);
        let k = ((t - now) / dt).round();
        if !(t.is_finite() && k >= 0.0 && (t - now - k * dt).abs() <= 1e-9 * dt) {
            return Err(crate::Error::Invalid(format!(
                "{}: cannot advance to t = {t} s from t = {now} s by whole steps of dt = {dt} s{}",
                self.scene().origin,
                if t < now {
                    " (it is behind the simulation's time; restore a saved state to go back)"
                } else {
                    ""
                }
            )));
        }
        for _ in 0..k as u64 {
            self.step()?;
        }
        Ok(())
    }

    /// The time (s).
    pub fn time(&self) -> f64 {
        self.cell.borrow_dependent().stepper().state().t
    }

    /// The scene's output names (`[[outputs]]`), in order.
    pub fn output_names(&self) -> Vec<&str> {
        self.scene()
            .outputs
            .iter()
            .map(|o| o.name.as_str())
            .collect()
    }

    /// The outputs' values at [`Simulation::time`]: what `ffr run` records
    /// at that sample.
    pub fn outputs(&self) -> &[f64] {
        self.cell.borrow_dependent().outputs()
    }

    /// The value of output `name` at [`Simulation::time`].
    pub fn output(&self, name: &str) -> crate::Result<f64> {
        let scene = self.scene();
        match scene.outputs.iter().position(|o| o.name == name) {
            Some(k) => Ok(self.outputs()[k]),
            None => {
                let q = crate::runtime::spec::text::quoted;
                Err(crate::Error::Invalid(format!(
                    "{}: no output `{}`; the scene's outputs are {}",
                    scene.origin,
                    q(name),
                    scene
                        .outputs
                        .iter()
                        .map(|o| format!("`{}`", q(&o.name)))
                        .collect::<Vec<_>>()
                        .join(", ")
                )))
            }
        }
    }

    /// The state (time, coordinates, velocities, accelerations,
    /// multipliers).
    pub fn state(&self) -> &crate::runtime::State {
        self.cell.borrow_dependent().stepper().state()
    }

    /// Everything the next step depends on (allocates; see
    /// [`SimulationState`]).
    pub fn save_state(&self) -> SimulationState {
        let (stepper, recorded) = self.cell.borrow_dependent().save();
        SimulationState {
            stepper,
            recorded,
            fingerprint: self.fingerprint,
        }
    }

    /// Put back a saved state: the simulation continues bit for bit as
    /// the one saved did (and a failure is forgotten). A state of another
    /// scene is refused, and nothing is changed then.
    pub fn restore_state(&mut self, s: &SimulationState) -> crate::Result<()> {
        if s.fingerprint != self.fingerprint {
            return Err(crate::Error::Invalid(format!(
                "{}: the saved state is of another scene",
                self.scene().origin
            )));
        }
        self.cell
            .with_dependent_mut(|_, d| d.restore(&s.stepper, &s.recorded))?;
        self.failed = None;
        Ok(())
    }

    /// After a failed step: its message (further steps are refused with it).
    pub fn failed(&self) -> Option<&str> {
        self.failed.as_deref()
    }

    /// Steps taken.
    pub fn steps(&self) -> usize {
        self.cell.borrow_dependent().stepper().counters().steps
    }

    /// The run's counters so far (steps, Newton iterations, iteration
    /// matrices, restarts, splits).
    pub fn counters(&self) -> &crate::runtime::Summary {
        self.cell.borrow_dependent().stepper().counters()
    }
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("scene", &self.scene().origin)
            .field("t", &self.time())
            .field("steps", &self.steps())
            .field("failed", &self.failed)
            .finish_non_exhaustive()
    }
}

#[cfg(test)]
mod tests {
    fn send<T: Send + 'static>() {}

    #[test]
    fn simulation_is_send_and_static() {
        send::<super::Simulation>();
        send::<super::SimulationState>();
    }
}
