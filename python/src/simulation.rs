//! `ffr.Simulation`: a scene stepped from Python (`scene.simulation()`),
//! over the library's [`ffr::scene::Simulation`]: inputs set between
//! steps, outputs read after each, the state saved and restored exactly.
//! The same steps as `Scene.run()` (the library's run is a loop over the
//! same step), the GIL released while stepping.

use crate::{clean, detach_interruptible, py_err, SimulationError};
use ffr::runtime::spec::text::quoted;
use pyo3::exceptions::{PyKeyError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyFloat, PyInt};
use std::sync::Arc;

/// A scene stepped by its caller (made by `Scene.simulation()`).
///
/// Not shared between threads at once: a call that finds another one
/// running on the same simulation raises `RuntimeError` (pyo3's borrow
/// check) instead of waiting.
#[pyclass(module = "ffr", name = "Simulation")]
pub(crate) struct Simulation {
    sim: ffr::scene::Simulation,
    /// Input values checked and waiting to be set (reused: no allocation
    /// per step for a dict of known size).
    pending: Vec<(usize, f64)>,
}

/// A saved [`Simulation`] state (`Simulation.state()`), put back by
/// `Simulation.restore(state)`; opaque.
#[pyclass(module = "ffr", name = "SimulationState", frozen)]
pub(crate) struct SimulationState {
    state: ffr::scene::SimulationState,
}

impl Simulation {
    pub(crate) fn new(scene: Arc<ffr::scene::Scene>) -> PyResult<Self> {
        let file = scene.origin.clone();
        let sim = ffr::scene::Simulation::new(scene).map_err(|e| py_err(e, Some(&file)))?;
        Ok(Simulation {
            sim,
            pending: Vec::new(),
        })
    }

    /// The input values of `inputs` (a dict of input names to numbers),
    /// all checked before any is set: an unknown name raises `KeyError`,
    /// a value that is not a finite real number `ValueError` / `TypeError`
    /// (and nothing is set).
    fn check_inputs(&mut self, inputs: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        self.pending.clear();
        let Some(inputs) = inputs else {
            return Ok(());
        };
        for (k, v) in inputs.iter() {
            let name: String = k.extract().map_err(|_| {
                PyTypeError::new_err(format!(
                    "an input name must be a str, not {}",
                    clean(
                        &k.get_type()
                            .name()
                            .map(|n| n.to_string())
                            .unwrap_or_default()
                    )
                ))
            })?;
            let index = self
                .sim
                .input_index(&name)
                .map_err(|e| PyKeyError::new_err(clean(&e.to_string())))?;
            let value = number(&v).map_err(|why| {
                PyTypeError::new_err(clean(&format!("input `{}`: {why}", quoted(&name))))
            })?;
            if !value.is_finite() {
                return Err(PyValueError::new_err(clean(&format!(
                    "{}: input `{}` must be finite (got {value})",
                    self.sim.scene().origin,
                    quoted(&name)
                ))));
            }
            self.pending.push((index, value));
        }
        Ok(())
    }

    /// Set the checked inputs.
    fn apply_inputs(&mut self) -> PyResult<()> {
        for &(i, v) in &self.pending {
            self.sim
                .set_input_at(i, v)
                .map_err(|e| PyValueError::new_err(clean(&e.to_string())))?;
        }
        Ok(())
    }

    /// A failed step as `SimulationError` (the command line's message).
    fn failure(&self, e: ffr::Error) -> PyErr {
        match (&e, self.sim.failed()) {
            (ffr::Error::Runtime(ffr::runtime::Error::Interrupted), _) => py_err(e, None),
            (_, Some(f)) => SimulationError::new_err(clean(f)),
            _ => PyValueError::new_err(clean(&e.to_string())),
        }
    }
}

/// A real number from Python: a float, an int, a numpy scalar (anything
/// with `__float__` that is not a str or bytes).
fn number(v: &Bound<'_, PyAny>) -> Result<f64, String> {
    if let Ok(f) = v.cast::<PyFloat>() {
        return Ok(f.value());
    }
    if v.is_instance_of::<PyInt>() || v.hasattr("__float__").unwrap_or(false) {
        return v
            .extract::<f64>()
            .map_err(|e| format!("not a real number ({e})"));
    }
    Err(format!(
        "not a real number (a {})",
        v.get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_default()
    ))
}

#[pymethods]
impl Simulation {
    /// The time (s).
    #[getter]
    fn t(&self) -> f64 {
        self.sim.time()
    }

    /// The scene's step (s): what one `step()` advances.
    #[getter]
    fn dt(&self) -> f64 {
        self.sim.scene().dt
    }

    /// Steps taken.
    #[getter]
    fn steps(&self) -> usize {
        self.sim.steps()
    }

    /// The scene's input names (`[[inputs]]`), in file order.
    #[getter]
    fn input_names(&self) -> Vec<String> {
        self.sim
            .input_names()
            .into_iter()
            .map(str::to_string)
            .collect()
    }

    /// The scene's output names (`[[outputs]]`), in order.
    #[getter]
    fn output_names(&self) -> Vec<String> {
        self.sim
            .output_names()
            .into_iter()
            .map(str::to_string)
            .collect()
    }

    /// The inputs' values now: a dict of input names to floats.
    #[getter]
    fn inputs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for name in self.sim.input_names() {
            let v = self
                .sim
                .input(name)
                .map_err(|e| PyValueError::new_err(clean(&e.to_string())))?;
            d.set_item(name, v)?;
        }
        Ok(d)
    }

    /// The outputs at `t`: a dict of output names to floats (what
    /// `Scene.run()` records at that sample).
    #[getter]
    fn outputs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, v) in self.sim.output_names().into_iter().zip(self.sim.outputs()) {
            d.set_item(name, *v)?;
        }
        Ok(d)
    }

    /// The message of the step that failed, or None (a failed simulation
    /// refuses further steps until `restore`).
    #[getter]
    fn failed(&self) -> Option<String> {
        self.sim.failed().map(clean)
    }

    /// Set `inputs` (a dict of input names to values; they hold until set
    /// again) and take one step of `dt`, the GIL released. An unknown
    /// name raises `KeyError`, a value that is not a finite number
    /// `ValueError` or `TypeError`, before anything changes; a step that
    /// fails raises `SimulationError` with the command line's message.
    #[pyo3(signature = (inputs = None))]
    fn step(&mut self, py: Python<'_>, inputs: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        self.check_inputs(inputs)?;
        if let Some(f) = self.sim.failed() {
            return Err(SimulationError::new_err(clean(f)));
        }
        self.apply_inputs()?;
        let sim = &mut self.sim;
        match py.detach(|| sim.step()) {
            Ok(()) => Ok(()),
            Err(e) => Err(self.failure(e)),
        }
    }

    /// Set `inputs` as `step` does, then take whole steps until `t` (s) is
    /// reached, the GIL released; Ctrl-C stops it at a step
    /// (`KeyboardInterrupt`, the simulation usable at the step reached). A
    /// `t` behind the time or between two steps raises `ValueError` before
    /// any step.
    #[pyo3(signature = (t, inputs = None))]
    fn advance(
        &mut self,
        py: Python<'_>,
        t: &Bound<'_, PyAny>,
        inputs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<()> {
        let t = number(t).map_err(|why| PyTypeError::new_err(format!("t: {why}")))?;
        self.check_inputs(inputs)?;
        if let Some(f) = self.sim.failed() {
            return Err(SimulationError::new_err(clean(f)));
        }
        self.apply_inputs()?;
        let sim = &mut self.sim;
        let r = detach_interruptible(py, move |stop| sim.advance_to_interruptible(t, stop))?;
        r.map_err(|e| self.failure(e))
    }

    /// Everything the next step depends on, to put back with `restore`.
    fn state(&self) -> SimulationState {
        SimulationState {
            state: self.sim.save_state(),
        }
    }

    /// Put back a state from `state()`: the simulation continues bit for
    /// bit as it did from there (a failure is forgotten). A state of
    /// another scene raises `ValueError`.
    fn restore(&mut self, state: &SimulationState) -> PyResult<()> {
        self.sim
            .restore_state(&state.state)
            .map_err(|e| PyValueError::new_err(clean(&e.to_string())))
    }

    fn __repr__(&self) -> String {
        format!(
            "ffr.Simulation({:?}, t = {}, steps = {}{})",
            clean(&self.sim.scene().origin),
            self.sim.time(),
            self.sim.steps(),
            if self.sim.failed().is_some() {
                ", failed"
            } else {
                ""
            }
        )
    }
}

#[pymethods]
impl SimulationState {
    /// The time of the state (s).
    #[getter]
    fn t(&self) -> f64 {
        self.state.time()
    }

    fn __repr__(&self) -> String {
        format!("ffr.SimulationState(t = {})", self.state.time())
    }
}
