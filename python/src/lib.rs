//! The Python package `ffr` (module `ffr._ffr`, re-exported by
//! `ffr/__init__.py`): scene files loaded, set by dotted keys
//! ([`ffr::scene::SceneText`]) and run with the GIL released, their outputs
//! as numpy arrays; a body's modes and invariants; a scene's linear model
//! and Campbell diagram. Every computation is the library's (the same as
//! the command line's); this crate converts arguments and results and maps
//! errors to `ffr.SceneError`, `ffr.SimulationError` and their base
//! `ffr.FfrError`, with the messages the command line prints.
//!
//! Built by maturin (`python/pyproject.toml`, feature `extension-module`);
//! the API is in `docs/python.md` and `ffr/_ffr.pyi`.

use ffr::codegen::modal::ModalBasis;
use ffr::kernels::BeamSpec;
use ffr::modal::{to_runtime, ReducibleBody};
use ffr::runtime::nalgebra::DMatrix;
use ffr::runtime::spec::text::{quoted, snippet};
use ffr::runtime::spec::{Formalism, KernelOptions, Params, Reference};
use ffr::runtime::{Interrupt, Invariants};
use ffr::scene::linear::At;
use ffr::scene::{SceneText, SceneValue};
use numpy::{PyArray1, PyArray2, PyUntypedArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyKeyError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

mod simulation;

create_exception!(
    ffr,
    FfrError,
    PyException,
    "An error of ffr: the message names the problem and, for input from a file, where (`file:line:col: …`)."
);
create_exception!(
    ffr,
    SceneError,
    FfrError,
    "A scene that does not load, or a key or value that does not fit it: the loader's located message."
);
create_exception!(
    ffr,
    SimulationError,
    FfrError,
    "A run or an analysis that failed (no convergence, divergence, a singular matrix, outputs that are not finite): why, and when. From Scene.run(), `run` is the RunResult of the samples up to the failure (None before the first sample and for the other calls)."
);

/// The longest message of an exception from the library, in characters
/// (longer ones are cut with `…`).
const MAX_MESSAGE_CHARS: usize = 2000;

/// A message as an exception carries it: control, bidirectional and other
/// invisible characters escaped (`\u{1b}`, `\n`), so that printing it
/// cannot move a terminal's cursor or reorder its text, and cut to
/// [`MAX_MESSAGE_CHARS`] ([`snippet`], the command line's rule).
fn clean(m: &str) -> String {
    snippet(m, MAX_MESSAGE_CHARS)
}

/// The library's error as the Python exception of its kind: a scene
/// error as `SceneError`, a runtime failure as `SimulationError`,
/// anything else as `FfrError` (`file` prefixed, as the command line
/// prefixes it, when the error has no place of its own); an interrupted
/// call as `KeyboardInterrupt` (its signal handler's own exception is
/// raised instead where there is one: [`detach_interruptible`]).
fn py_err(e: ffr::Error, file: Option<&str>) -> PyErr {
    let prefixed = |m: String| {
        clean(&match file {
            Some(f) => format!("{f}: {m}"),
            None => m,
        })
    };
    match e {
        ffr::Error::Runtime(ffr::runtime::Error::Interrupted) => {
            pyo3::exceptions::PyKeyboardInterrupt::new_err(())
        }
        ffr::Error::Scene(s) => SceneError::new_err(clean(&s.to_string())),
        ffr::Error::Runtime(r) => SimulationError::new_err(prefixed(r.to_string())),
        other => FfrError::new_err(prefixed(other.to_string())),
    }
}

fn scene_err(e: impl std::fmt::Display) -> PyErr {
    SceneError::new_err(clean(&e.to_string()))
}

/// How often a computation without the GIL takes it back to run Python's
/// signal handlers (Ctrl-C).
const SIGNAL_CHECK: Duration = Duration::from_millis(50);

/// The signal check of a long call (an [`Interrupt`]): at most every
/// [`SIGNAL_CHECK`], the GIL taken and Python's signal handlers run
/// (`PyErr_CheckSignals`, which runs them only in the main thread); the
/// exception a handler raised (`KeyboardInterrupt` for Ctrl-C) is kept
/// and stops the call.
struct Signals {
    next: Mutex<Instant>,
    raised: Mutex<Option<PyErr>>,
}

impl Signals {
    fn check(&self) -> bool {
        let now = Instant::now();
        {
            let mut next = self.next.lock().unwrap_or_else(|e| e.into_inner());
            if now < *next {
                return false;
            }
            *next = now + SIGNAL_CHECK;
        }
        match Python::attach(|py| py.check_signals()) {
            Ok(()) => false,
            Err(e) => {
                *self.raised.lock().unwrap_or_else(|e| e.into_inner()) = Some(e);
                true
            }
        }
    }
}

/// Whether this is Python's main thread (the one that runs signal
/// handlers).
fn in_main_thread(py: Python<'_>) -> bool {
    let threading = match py.import("threading") {
        Ok(t) => t,
        Err(_) => return true,
    };
    match (
        threading.call_method0("current_thread"),
        threading.call_method0("main_thread"),
    ) {
        (Ok(current), Ok(main)) => current.is(&main),
        _ => true,
    }
}

/// Run `f` without the GIL, handing it an [`Interrupt`] that runs
/// Python's signal handlers every [`SIGNAL_CHECK`]: an exception one of
/// them raised (Ctrl-C's `KeyboardInterrupt`) is raised as soon as the
/// call stops, whatever it returned; a signal that came after its last
/// check is handled before anything else (numpy is touched only after).
/// Called from another thread than the main one, where Python runs no
/// signal handlers, `f` gets [`Interrupt::NEVER`] (and never waits for
/// the GIL).
fn detach_interruptible<T: Send>(
    py: Python<'_>,
    f: impl for<'a> FnOnce(Interrupt<'a>) -> T + Send,
) -> PyResult<T> {
    let signals = Signals {
        next: Mutex::new(Instant::now() + SIGNAL_CHECK),
        raised: Mutex::new(None),
    };
    let check = || signals.check();
    let main = in_main_thread(py);
    let out = py.detach(|| {
        f(if main {
            Interrupt::new(&check)
        } else {
            Interrupt::NEVER
        })
    });
    if let Some(e) = signals
        .raised
        .into_inner()
        .unwrap_or_else(|e| e.into_inner())
    {
        return Err(e);
    }
    py.check_signals()?;
    Ok(out)
}

/// A Python value as a scene value: bool, int, float, str, a list or tuple
/// of them, a dict with str keys (an inline table); numpy scalars and
/// arrays as the Python values of their `tolist()` (a 0-d array is its
/// number); other numbers by their `__index__` / `__float__`.
fn scene_value(v: &Bound<'_, PyAny>) -> PyResult<SceneValue> {
    scene_value_at(v, 0)
}

/// [`scene_value`] at nesting `depth`: deeper than the library takes
/// (`MAX_VALUE_DEPTH`, also a list that contains itself) raises.
fn scene_value_at(v: &Bound<'_, PyAny>, depth: usize) -> PyResult<SceneValue> {
    if depth > ffr::scene::edit::MAX_VALUE_DEPTH {
        return Err(PyValueError::new_err(format!(
            "a value nested more than {} lists or dicts deep",
            ffr::scene::edit::MAX_VALUE_DEPTH
        )));
    }
    if v.is_instance_of::<PyBool>() {
        return Ok(SceneValue::Bool(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return v.extract::<i64>().map(SceneValue::Int).map_err(|_| {
            PyValueError::new_err(format!(
                "{}: an integer out of the range of a scene file's integers (64 bits)",
                repr(v)
            ))
        });
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(SceneValue::Float(v.extract()?));
    }
    if let Ok(s) = v.cast::<PyString>() {
        return Ok(SceneValue::Str(s.to_cow()?.into_owned()));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut entries = Vec::with_capacity(d.len());
        for (k, x) in d.iter() {
            let Ok(k) = k.cast::<PyString>() else {
                return Err(PyTypeError::new_err(format!(
                    "a table's keys are strings, not {}",
                    type_name(&k)
                )));
            };
            entries.push((k.to_cow()?.into_owned(), scene_value_at(&x, depth + 1)?));
        }
        return Ok(SceneValue::Table(entries));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let items: Vec<SceneValue> = v
            .try_iter()?
            .map(|x| scene_value_at(&x?, depth + 1))
            .collect::<PyResult<_>>()?;
        return Ok(SceneValue::Array(items));
    }
    if is_numpy(v) {
        // An array or a numpy scalar: its Python value(s), which are
        // then checked as above (a 0-d array and a scalar give a number).
        let py_value = v.call_method0("tolist").map_err(|_| {
            PyTypeError::new_err(format!(
                "a numpy value that has no Python value (tolist() failed): {}",
                repr(v)
            ))
        })?;
        if !is_numpy(&py_value) {
            return scene_value_at(&py_value, depth);
        }
    } else {
        if v.hasattr("__index__").unwrap_or(false) {
            if let Ok(i) = v.call_method0("__index__").and_then(|i| i.extract::<i64>()) {
                return Ok(SceneValue::Int(i));
            }
        }
        if v.hasattr("__float__").unwrap_or(false) {
            if let Ok(x) = v.call_method0("__float__").and_then(|x| x.extract::<f64>()) {
                return Ok(SceneValue::Float(x));
            }
        }
    }
    Err(PyTypeError::new_err(format!(
        "a scene value is a bool, int, float, str, list or dict, not {} ({})",
        type_name(v),
        repr(v)
    )))
}

/// Whether `v` is a numpy array or scalar (by its type's module, without
/// importing numpy's Python side).
fn is_numpy(v: &Bound<'_, PyAny>) -> bool {
    v.get_type().module().is_ok_and(|m| {
        m.to_cow()
            .is_ok_and(|m| m == "numpy" || m.starts_with("numpy."))
    })
}

/// A value's `repr()` for a message: escaped and cut ([`quoted`]).
fn repr(v: &Bound<'_, PyAny>) -> String {
    v.repr()
        .ok()
        .and_then(|r| r.to_cow().ok().map(|r| quoted(&r)))
        .unwrap_or_else(|| "<a value without repr()>".into())
}

/// A value's type name for a message, escaped and cut.
fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type()
        .name()
        .ok()
        .and_then(|n| n.to_cow().ok().map(|n| quoted(&n)))
        .unwrap_or_else(|| "?".into())
}

/// A sequence argument (`speeds`, `boundary`, `inputs`, `outputs`): a list,
/// a tuple, a 1-d numpy array or another sequence of `T`; a 0-d numpy
/// array, a str or a bare number is refused with a message naming the
/// argument.
fn sequence<T>(v: &Bound<'_, PyAny>, name: &str, of: &str) -> PyResult<Vec<T>>
where
    T: for<'a, 'py> FromPyObject<'a, 'py>,
{
    let refuse = |why: String| {
        PyTypeError::new_err(format!(
            "{name} = {}: expected a sequence of {of}{why}",
            repr(v)
        ))
    };
    if is_numpy(v) {
        let ndim: usize = v.getattr("ndim").and_then(|n| n.extract()).unwrap_or(0);
        if ndim != 1 {
            return Err(refuse(format!(
                ", not a {ndim}-d numpy {}",
                if ndim == 0 {
                    "array or scalar (wrap one value in a list: [x])"
                } else {
                    "array"
                }
            )));
        }
        return sequence(&v.call_method0("tolist")?, name, of);
    }
    if v.is_instance_of::<PyString>() || !v.hasattr("__len__").unwrap_or(false) {
        return Err(refuse(format!(", not {}", type_name(v))));
    }
    let mut out = Vec::new();
    for (i, x) in v.try_iter().map_err(|_| refuse(String::new()))?.enumerate() {
        let x = x?;
        let x = if is_numpy(&x) {
            x.call_method0("tolist")?
        } else {
            x
        };
        out.push(
            x.extract::<T>()
                .map_err(|_| refuse(format!(": item {i} is {} ({})", type_name(&x), repr(&x))))?,
        );
    }
    Ok(out)
}

/// A scene value as Python's.
fn py_value(py: Python<'_>, v: &SceneValue) -> PyResult<Py<PyAny>> {
    Ok(match v {
        SceneValue::Bool(b) => PyBool::new(py, *b).to_owned().into_any().unbind(),
        SceneValue::Int(i) => i.into_pyobject(py)?.into_any().unbind(),
        SceneValue::Float(x) => x.into_pyobject(py)?.into_any().unbind(),
        SceneValue::Str(s) => s.into_pyobject(py)?.into_any().unbind(),
        SceneValue::Array(items) => {
            let l = PyList::empty(py);
            for x in items {
                l.append(py_value(py, x)?)?;
            }
            l.into_any().unbind()
        }
        SceneValue::Table(entries) => {
            let d = PyDict::new(py);
            for (k, x) in entries {
                d.set_item(k, py_value(py, x)?)?;
            }
            d.into_any().unbind()
        }
    })
}

/// A scene file's text with the values set so far, and the scene built
/// from it (checked and ready to run).
#[pyclass(module = "ffr", name = "Scene", frozen)]
struct Scene {
    state: std::sync::RwLock<Loaded>,
}

#[derive(Clone)]
struct Loaded {
    text: SceneText,
    built: Arc<ffr::scene::Scene>,
}

impl Scene {
    fn new(text: SceneText) -> PyResult<Self> {
        // Resolved and built now, as `ffr run` does: errors at their place.
        let built = Arc::new(text.load().map_err(scene_err)?);
        Ok(Scene {
            state: std::sync::RwLock::new(Loaded { text, built }),
        })
    }

    fn snapshot(&self) -> Loaded {
        self.state.read().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// Set every `(key, value)` on a copy, build the scene once, keep the
    /// copy only if it builds.
    fn set_all(&self, items: Vec<(String, SceneValue)>) -> PyResult<()> {
        let mut text = self.snapshot().text;
        for (k, v) in items {
            text.set(&k, v).map_err(scene_err)?;
        }
        let built = Arc::new(text.load().map_err(scene_err)?);
        *self.state.write().unwrap_or_else(|e| e.into_inner()) = Loaded { text, built };
        Ok(())
    }
}

#[pymethods]
impl Scene {
    /// Read a scene file (relative shape files against its directory).
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        let text = SceneText::read(&path).map_err(scene_err)?;
        Scene::new(text)
    }

    /// A scene from its text; `file` names it in errors, `base` (default:
    /// the current directory) resolves relative shape files.
    #[staticmethod]
    #[pyo3(signature = (text, file = "<string>", base = None))]
    fn from_str(text: &str, file: &str, base: Option<PathBuf>) -> PyResult<Self> {
        let base = base.unwrap_or_else(|| PathBuf::from("."));
        Scene::new(SceneText::parse(text, file, &base).map_err(scene_err)?)
    }

    /// Set the value at a dotted key (`bodies.beam.params.e`,
    /// `joints.0.drive.omega`, `t_end`); the scene is then resolved and
    /// built as `ffr run` does it, and a key or value it refuses raises
    /// `SceneError` with the loader's located message (the scene is left as
    /// it was).
    fn set(&self, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_all(vec![(key.to_string(), scene_value(value)?)])
    }

    /// Set several keys at once (a dict of dotted keys to values), checked
    /// together: for changes that only fit together.
    fn update(&self, values: &Bound<'_, PyDict>) -> PyResult<()> {
        let mut items = Vec::with_capacity(values.len());
        for (k, v) in values.iter() {
            items.push((k.extract::<String>()?, scene_value(&v)?));
        }
        self.set_all(items)
    }

    /// The value at a dotted key, or `None` if the scene has none there: a
    /// table as a dict, an array of tables (`[[joints]]`) as a list of
    /// dicts.
    fn get(&self, py: Python<'_>, key: &str) -> PyResult<Option<Py<PyAny>>> {
        self.snapshot()
            .text
            .get(key)
            .map(|v| py_value(py, &v))
            .transpose()
    }

    /// The file's name as errors give it.
    #[getter]
    fn file(&self) -> String {
        self.snapshot().text.file().to_string()
    }

    /// The scene's text as it reads now (the file with the values set).
    #[getter]
    fn text(&self) -> String {
        self.snapshot().text.text()
    }

    /// The keys set so far and their values, in the order they were last
    /// set (a key set again replaces its earlier value).
    #[getter]
    fn overrides(&self, py: Python<'_>) -> PyResult<Vec<(String, Py<PyAny>)>> {
        self.snapshot()
            .text
            .overrides()
            .iter()
            .map(|(k, v)| Ok((k.clone(), py_value(py, v)?)))
            .collect()
    }

    /// Run the scene (the GIL released), recording every output at every
    /// step. A run that stops early raises `SimulationError` with the
    /// command line's message. `vtk = DIR` also writes the ParaView time
    /// series of `ffr run --vtk DIR --every EVERY` (the same bytes;
    /// docs/vtk.md); a series that cannot be written raises `FfrError`
    /// before the run.
    #[pyo3(signature = (vtk = None, every = 1))]
    fn run(&self, py: Python<'_>, vtk: Option<PathBuf>, every: usize) -> PyResult<RunResult> {
        // The samples of a run that stopped early or is not valid go with
        // its `SimulationError` as `.run` (none before the first sample).
        if every == 0 {
            return Err(PyValueError::new_err(
                "every = 0: the VTK series writes every K-th step, K ≥ 1",
            ));
        }
        if vtk.is_none() && every != 1 {
            return Err(PyValueError::new_err("every = … goes with vtk = DIR"));
        }
        let scene = self.snapshot().built;
        let mut options = ffr::scene::RunOptions::default();
        options.vtk = vtk.map(|dir| ffr::scene::vtk::VtkOptions { dir, every });
        let r = detach_interruptible(py, move |stop| {
            ffr::scene::run_interruptible(&scene, &options, stop)
        })?
        .map_err(|e| py_err(e, None))?;
        let failed = match &r.failed {
            Some(f) => Some(format!(
                "the run stopped at t = {:.6} s: {f}",
                r.t.last().copied().unwrap_or(0.0)
            )),
            None => non_finite(&r),
        };
        if let Some(message) = failed {
            let e = SimulationError::new_err(clean(&message));
            if !r.t.is_empty() {
                let run = Py::new(py, RunResult::new(py, r)?)?;
                e.value(py).setattr("run", run)?;
            }
            return Err(e);
        }
        warn_all(py, &r.warnings)?;
        RunResult::new(py, r)
    }

    /// A simulation of the scene as it is now, stepped by the caller
    /// (`sim.step(inputs={…})`, `sim.advance(t)`, `sim.outputs`,
    /// `sim.state()` / `sim.restore(state)`): the steps of `run()`, one at
    /// a time. Later `set` calls on the scene do not change it. A scene
    /// whose initial state is refused raises as `run()` does.
    fn simulation(&self) -> PyResult<simulation::Simulation> {
        simulation::Simulation::new(self.snapshot().built)
    }

    /// The static equilibrium under the scene's loads at t = 0 (the GIL
    /// released), as `ffr static --json` gives it: a dict `{"outputs":
    /// {NAME: value, …}, "steps": K, "iterations": n, "warnings": [TEXT,
    /// …]}`, plus `"rotations"` (each flexible body's largest elastic
    /// section rotation there, as `RunResult.rotations`); each warning is
    /// also issued once as a `RuntimeWarning`. `steps = K` takes
    /// K equal load increments (default: automatic). No equilibrium (a
    /// mechanism, an unstable state, no convergence) raises
    /// `SimulationError` with the command line's message.
    #[pyo3(name = "static", signature = (steps = None))]
    fn static_<'py>(
        &self,
        py: Python<'py>,
        steps: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let steps = match steps {
            None => None,
            Some(v) => Some(load_steps(v)?),
        };
        let loaded = self.snapshot();
        let scene = loaded.built;
        let file = loaded.text.file().to_string();
        let options = ffr::scene::statics::StaticOptions { steps };
        let s = detach_interruptible(py, move |stop| {
            ffr::scene::statics::solve_interruptible(&scene, &options, stop)
        })?
        .map_err(|e| py_err(e, Some(&file)))?;
        let outputs = PyDict::new(py);
        for (n, v) in s.names.iter().zip(&s.values) {
            outputs.set_item(n, v)?;
        }
        let out = PyDict::new(py);
        out.set_item("outputs", outputs)?;
        out.set_item("steps", s.steps)?;
        out.set_item("iterations", s.iterations)?;
        out.set_item("warnings", s.warnings.clone())?;
        out.set_item("rotations", rotations_list(py, &s.rotations)?)?;
        warn_all(py, &s.warnings)?;
        Ok(out)
    }

    fn __repr__(&self) -> String {
        const LISTED: usize = 8;
        let t = self.snapshot().text;
        let file = snippet(t.file(), 200);
        if t.overrides().is_empty() {
            format!("ffr.Scene({file:?})")
        } else {
            let mut set: Vec<String> = t
                .overrides()
                .iter()
                .take(LISTED)
                .map(|(k, v)| format!("{} = {}", quoted(k), quoted(&v.to_string())))
                .collect();
            if t.overrides().len() > LISTED {
                set.push(format!("and {} more", t.overrides().len() - LISTED));
            }
            format!("ffr.Scene({file:?}, with {})", set.join(", "))
        }
    }
}

/// Why a run that reached its end is not valid, as `ffr run` refuses it: a
/// time or an output value that is not finite (the first, named, with its
/// time).
fn non_finite(r: &ffr::scene::SceneRun) -> Option<String> {
    if let Some((i, v)) = r.t.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Some(format!(
            "the time of sample {i} is {v}, not a finite number: the run is not valid"
        ));
    }
    for (n, c) in r.names.iter().zip(&r.columns) {
        if let Some((i, v)) = c.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            let at =
                r.t.get(i)
                    .map_or(String::new(), |t| format!(" at t = {t:?} s"));
            return Some(format!(
                "output `{}` is {v}{at}, not a finite number: the run is not valid",
                quoted(n)
            ));
        }
    }
    None
}

/// A scene run: each output by name as a numpy array (`result["tip_x"]`),
/// the times `t`, and the run's statistics.
#[pyclass(module = "ffr", name = "RunResult", frozen)]
struct RunResult {
    t: Py<PyArray1<f64>>,
    names: Vec<String>,
    columns: Vec<Py<PyArray1<f64>>>,
    /// Steps taken.
    #[pyo3(get)]
    steps: usize,
    /// Newton iterations.
    #[pyo3(get)]
    newton_iterations: usize,
    /// Iteration-matrix factorizations.
    #[pyo3(get)]
    jacobians: usize,
    /// Steps whose Newton iteration was started again from rest.
    #[pyo3(get)]
    restarts: usize,
    /// Steps done in halves.
    #[pyo3(get)]
    splits: usize,
    /// Wall time of the simulation (s), as the library measures it.
    #[pyo3(get)]
    wall: f64,
    /// Warnings about a valid result outside the model's accuracy (a body
    /// that turned past what one floating frame describes), as `ffr run`
    /// prints them; each was also issued once as a `RuntimeWarning`.
    #[pyo3(get)]
    warnings: Vec<String>,
    /// Each flexible body's largest elastic section rotation over the run:
    /// a list of dicts `{body, segment, segments, angle, t, x}` (angle in
    /// rad relative to its segment's frame, when, where on the whole
    /// body's axis; `segment` 1-based of `segments`).
    rotations: Py<PyList>,
}

impl RunResult {
    /// The run's vectors handed to numpy (no copy).
    fn new(py: Python<'_>, r: ffr::scene::SceneRun) -> PyResult<Self> {
        let rotations = rotations_list(py, &r.rotations)?.unbind();
        let columns = r
            .columns
            .into_iter()
            .map(|c| PyArray1::from_vec(py, c).unbind())
            .collect();
        Ok(RunResult {
            warnings: r.warnings,
            rotations,
            t: PyArray1::from_vec(py, r.t).unbind(),
            names: r.names,
            columns,
            steps: r.steps,
            newton_iterations: r.newton_iterations,
            jacobians: r.jacobians,
            restarts: r.restarts,
            splits: r.splits,
            wall: r.wall,
        })
    }
}

#[pymethods]
impl RunResult {
    /// The times (s).
    #[getter]
    fn t(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.t.clone_ref(py)
    }

    /// Each flexible body's largest elastic section rotation over the run.
    #[getter]
    fn rotations(&self, py: Python<'_>) -> Py<PyList> {
        self.rotations.clone_ref(py)
    }

    /// The output names, in the scene's order.
    fn keys(&self) -> Vec<String> {
        self.names.clone()
    }

    fn __getitem__(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyArray1<f64>>> {
        match self.names.iter().position(|n| n == name) {
            Some(i) => Ok(self.columns[i].clone_ref(py)),
            None => Err(PyKeyError::new_err(format!(
                "no output `{}`; the outputs are {}",
                quoted(name),
                names_list(&self.names)
            ))),
        }
    }

    fn __contains__(&self, name: &str) -> bool {
        self.names.iter().any(|n| n == name)
    }

    fn __len__(&self) -> usize {
        self.names.len()
    }

    fn __iter__(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        Ok(PyList::new(py, &self.names)?
            .try_iter()?
            .into_any()
            .unbind())
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "ffr.RunResult({} samples, outputs {}, {} steps, wall {:.3} s)",
            PyUntypedArrayMethods::len(self.t.bind(py)),
            names_list(&self.names),
            self.steps,
            self.wall
        )
    }
}

/// Names for a message: each quoted ([`quoted`]), at most 16 (then `…`).
fn names_list(names: &[String]) -> String {
    const LISTED: usize = 16;
    let mut out: Vec<String> = names.iter().take(LISTED).map(|n| quoted(n)).collect();
    if names.len() > LISTED {
        out.push(format!("… ({} in all)", names.len()));
    }
    out.join(", ")
}

/// Issue each warning once as a Python `RuntimeWarning` (pointing at the
/// caller's line); with warnings turned into errors, the first raises.
fn warn_all(py: Python<'_>, warnings: &[String]) -> PyResult<()> {
    let category = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
    for w in warnings {
        let text = std::ffi::CString::new(clean(w)).expect("snippet escapes NUL");
        PyErr::warn(py, category.as_any(), &text, 1)?;
    }
    Ok(())
}

/// The largest elastic rotations as a list of dicts.
fn rotations_list<'py>(
    py: Python<'py>,
    rotations: &[ffr::scene::frames::BodyRotation],
) -> PyResult<Bound<'py, PyList>> {
    let out = PyList::empty(py);
    for r in rotations {
        let d = PyDict::new(py);
        d.set_item("body", &r.body)?;
        d.set_item("segment", r.segment.0)?;
        d.set_item("segments", r.segment.1)?;
        d.set_item("angle", r.angle)?;
        d.set_item("t", r.t)?;
        d.set_item("x", r.x)?;
        out.append(d)?;
    }
    Ok(out)
}

fn matrix<'py>(py: Python<'py>, m: &DMatrix<f64>) -> Bound<'py, PyArray2<f64>> {
    let a = numpy::ndarray::Array2::from_shape_fn((m.nrows(), m.ncols()), |(i, j)| m[(i, j)]);
    PyArray2::from_owned_array(py, a)
}

const AXES: [&str; 3] = ["x", "y", "z"];

/// The invariants as a dict keyed like `ffr invariants --json`.
fn invariants_dict<'py>(
    py: Python<'py>,
    inv: &Invariants,
    dofs: &[String],
) -> PyResult<Bound<'py, PyDict>> {
    let d = inv.dim;
    let n = inv.nf();
    let out = PyDict::new(py);
    out.set_item("mass", inv.mass)?;
    out.set_item("St0", PyArray1::from_slice(py, &inv.s_t0.as_slice()[..d]))?;
    let sbar = numpy::ndarray::Array2::from_shape_fn((d, n), |(k, a)| inv.s_bar[(k, a)]);
    out.set_item("Sbar", PyArray2::from_owned_array(py, sbar))?;
    let (skl, ikl, theta) = (PyDict::new(py), PyDict::new(py), PyDict::new(py));
    for k in 0..d {
        for l in 0..d {
            let key = format!("{}{}", AXES[k], AXES[l]);
            skl.set_item(&key, matrix(py, &inv.s_kl[k][l]))?;
            ikl.set_item(&key, PyArray1::from_slice(py, inv.i_kl[k][l].as_slice()))?;
            theta.set_item(&key, inv.theta[(k, l)])?;
        }
    }
    out.set_item("Skl", skl)?;
    out.set_item("Ikl", ikl)?;
    out.set_item("theta", theta)?;
    out.set_item("mff", matrix(py, &inv.m_ff))?;
    out.set_item("Kff", matrix(py, &inv.k_ff))?;
    out.set_item("dofs", dofs.to_vec())?;
    Ok(out)
}

/// A scene given as an `ffr.Scene` or a path.
fn scene_text(scene: &Bound<'_, PyAny>) -> PyResult<SceneText> {
    if let Ok(s) = scene.cast::<Scene>() {
        return Ok(s.get().snapshot().text);
    }
    let path: PathBuf = scene
        .extract()
        .map_err(|_| PyTypeError::new_err("scene: an ffr.Scene or a path to a scene file"))?;
    SceneText::read(&path).map_err(scene_err)
}

fn parse<T: std::str::FromStr<Err = String>>(s: &str) -> PyResult<T> {
    s.parse()
        .map_err(|e: String| PyValueError::new_err(clean(&e)))
}

/// The body the keyword arguments describe: a scene's flexible body
/// (`scene` and `body`) or a beam of `shape` and `elements` (the command
/// line's flags and defaults).
struct BodyArgs {
    shape: Option<String>,
    elements: Option<usize>,
    reference: Option<String>,
    formalism: Option<String>,
    params: [Option<f64>; 8],
}

impl BodyArgs {
    fn any(&self) -> bool {
        self.shape.is_some()
            || self.elements.is_some()
            || self.reference.is_some()
            || self.formalism.is_some()
            || self.params.iter().any(Option::is_some)
    }

    fn params(&self) -> Params {
        let d = Params::STEEL_BAR;
        let p = &self.params;
        Params {
            length: p[0].unwrap_or(d.length),
            rho: p[1].unwrap_or(d.rho),
            area: p[2].unwrap_or(d.area),
            iy: p[3].unwrap_or(d.iy),
            iz: p[4].unwrap_or(d.iz),
            e: p[5].unwrap_or(d.e),
            g: p[6].unwrap_or(d.g),
            j: p[7].unwrap_or(d.j),
        }
    }

    fn shape(&self) -> String {
        self.shape.clone().unwrap_or_else(|| "beam3".into())
    }

    fn elements(&self) -> PyResult<usize> {
        match self.elements.unwrap_or(1) {
            n @ 1..=256 => Ok(n),
            n => Err(PyValueError::new_err(format!(
                "elements = {n}: expected 1 to 256"
            ))),
        }
    }

    fn reference(&self) -> PyResult<Reference> {
        self.reference
            .as_deref()
            .map_or(Ok(Reference::Clamped), parse)
    }

    fn formalism(&self) -> PyResult<Formalism> {
        self.formalism
            .as_deref()
            .map_or(Ok(Formalism::Consistent), parse)
    }

    /// With `scene`: the built scene (its file's name for errors), after
    /// checking that no body argument was given too.
    fn scene(
        &self,
        py: Python<'_>,
        scene: Option<&Bound<'_, PyAny>>,
        body: Option<&str>,
    ) -> PyResult<Option<(Arc<ffr::scene::Scene>, String)>> {
        match (scene, body) {
            (None, None) => Ok(None),
            (Some(_), None) | (None, Some(_)) => Err(PyValueError::new_err(
                "scene and body go together: the flexible body `body` of the scene `scene`",
            )),
            (Some(s), Some(_)) => {
                if self.any() {
                    return Err(PyValueError::new_err(
                        "with scene and body, the body is the scene's: give no shape, elements, reference, formalism or parameters",
                    ));
                }
                if let Ok(s) = s.cast::<Scene>() {
                    let l = s.get().snapshot();
                    return Ok(Some((l.built, l.text.file().to_string())));
                }
                let text = scene_text(s)?;
                let file = text.file().to_string();
                let built = py.detach(move || text.load()).map_err(scene_err)?;
                Ok(Some((Arc::new(built), file)))
            }
        }
    }
}

/// A body's invariants at its parameters, keyed like `ffr invariants --json`.
#[pyfunction]
#[pyo3(signature = (shape = None, elements = None, reference = None, formalism = None, *, length = None, rho = None, area = None, iy = None, iz = None, e = None, g = None, j = None, tape = false, scene = None, body = None))]
#[allow(clippy::too_many_arguments)]
fn invariants<'py>(
    py: Python<'py>,
    shape: Option<String>,
    elements: Option<usize>,
    reference: Option<String>,
    formalism: Option<String>,
    length: Option<f64>,
    rho: Option<f64>,
    area: Option<f64>,
    iy: Option<f64>,
    iz: Option<f64>,
    e: Option<f64>,
    g: Option<f64>,
    j: Option<f64>,
    tape: bool,
    scene: Option<&Bound<'py, PyAny>>,
    body: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let args = BodyArgs {
        shape,
        elements,
        reference,
        formalism,
        params: [length, rho, area, iy, iz, e, g, j],
    };
    if tape && scene.is_some() {
        return Err(PyValueError::new_err(
            "tape applies to a body of shape and elements, not to a scene's body",
        ));
    }
    let b = match args.scene(py, scene, body)? {
        Some((s, file)) => ffr::invariants::of_scene_body(&s, body.unwrap_or_default())
            .map_err(|e| py_err(e, Some(&file)))?,
        None => {
            let beam = BeamSpec {
                shape: args.shape(),
                elements: args.elements()?,
                reference: args.reference()?,
                options: KernelOptions::new().formalism(args.formalism()?),
                params: args.params(),
                force_tape: tape,
            };
            py.detach(|| ffr::invariants::of_beam(&beam))
                .map_err(|e| py_err(e, None))?
        }
    };
    invariants_dict(py, &b.invariants, &b.dofs)
}

/// The modal reduction as a dict keyed like `ffr modes --json`.
fn modes_dict<'py>(
    py: Python<'py>,
    body: &ReducibleBody,
    basis: &ModalBasis,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("body", body.description())?;
    out.set_item("reduction", basis.reduction_name())?;
    out.set_item("omega", PyArray1::from_slice(py, &basis.frequencies))?;
    let hz: Vec<f64> = basis
        .frequencies
        .iter()
        .map(|w| w / std::f64::consts::TAU)
        .collect();
    out.set_item("hz", PyArray1::from_vec(py, hz))?;
    out.set_item("labels", basis.labels.clone())?;
    out.set_item("dofs", body.dofs.clone())?;
    out.set_item("phi", matrix(py, &basis.phi))?;
    out.set_item("modal_mass", matrix(py, &basis.modal_mass))?;
    out.set_item("modal_stiffness", matrix(py, &basis.modal_stiffness))?;
    let projected = to_runtime(&body.invariants.project(&basis.phi));
    out.set_item(
        "invariants",
        invariants_dict(py, &projected, &basis.labels)?,
    )?;
    Ok(out)
}

/// A body's modes: modal truncation to `count` modes (default every
/// elastic mode) or, with `boundary` nodes, Craig–Bampton; keyed like
/// `ffr modes --json`.
#[pyfunction]
#[pyo3(signature = (shape = None, elements = None, reference = None, formalism = None, *, count = None, boundary = None, length = None, rho = None, area = None, iy = None, iz = None, e = None, g = None, j = None, scene = None, body = None))]
#[allow(clippy::too_many_arguments)]
fn modes<'py>(
    py: Python<'py>,
    shape: Option<String>,
    elements: Option<usize>,
    reference: Option<String>,
    formalism: Option<String>,
    count: Option<usize>,
    boundary: Option<&Bound<'py, PyAny>>,
    length: Option<f64>,
    rho: Option<f64>,
    area: Option<f64>,
    iy: Option<f64>,
    iz: Option<f64>,
    e: Option<f64>,
    g: Option<f64>,
    j: Option<f64>,
    scene: Option<&Bound<'py, PyAny>>,
    body: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let boundary: Vec<usize> = match boundary {
        Some(b) if !b.is_none() => sequence(b, "boundary", "node numbers")?,
        _ => Vec::new(),
    };
    let args = BodyArgs {
        shape,
        elements,
        reference,
        formalism,
        params: [length, rho, area, iy, iz, e, g, j],
    };
    let (b, file) = match args.scene(py, scene, body)? {
        Some((s, file)) => {
            let (whole, f) = s
                .whole_body(body.unwrap_or_default())
                .map_err(|e| FfrError::new_err(clean(&e.to_string())))?;
            (
                ReducibleBody::of_scene_body(f, whole).map_err(|e| py_err(e, Some(&file)))?,
                Some(file),
            )
        }
        None => {
            let (shape, n, r, f, p) = (
                args.shape(),
                args.elements()?,
                args.reference()?,
                args.formalism()?,
                args.params(),
            );
            (
                py.detach(|| ReducibleBody::from_parts(&shape, n, r, f, p))
                    .map_err(|e| py_err(e, None))?,
                None,
            )
        }
    };
    let basis = py
        .detach(|| b.reduce(count, &boundary, "count"))
        .map_err(|e| py_err(e, file.as_deref()))?;
    modes_dict(py, &b, &basis)
}

/// `steps = K` of `Scene.static`: an integer (an `int` or a numpy
/// integer, by `__index__`) from 1 to `MAX_STEPS`; a bool or a float is
/// refused, not rounded.
fn load_steps(v: &Bound<'_, PyAny>) -> PyResult<usize> {
    let max = ffr::scene::statics::MAX_STEPS;
    let message = || {
        format!(
            "steps = {}: expected a whole number of load increments from 1 to {max}",
            repr(v)
        )
    };
    if v.is_instance_of::<PyBool>()
        || v.is_instance_of::<PyFloat>()
        || !v.hasattr("__index__").unwrap_or(false)
    {
        return Err(PyTypeError::new_err(message()));
    }
    match v.call_method0("__index__").and_then(|k| k.extract::<i64>()) {
        Ok(k) if k >= 1 && k as u64 <= max as u64 => Ok(k as usize),
        Ok(_) => Err(PyValueError::new_err(message())),
        Err(_) => Err(PyTypeError::new_err(message())),
    }
}

/// The state a linear model is taken about: a time (s) or `"static"`.
fn at(v: &Bound<'_, PyAny>) -> PyResult<At> {
    if let Ok(s) = v.cast::<PyString>() {
        if s.to_cow()? == "static" {
            return Ok(At::Static);
        }
    } else if let Ok(t) = v.extract::<f64>() {
        if t.is_finite() && t >= 0.0 {
            return Ok(At::Time(t));
        }
    }
    Err(PyValueError::new_err(format!(
        "at = {}: expected a time in seconds (finite, ≥ 0) or \"static\"",
        repr(v)
    )))
}

/// A scene's linear model `ẋ = A x + B u`, `y = C x + D u` about its state
/// at time `at` (the scene run to it) or its static equilibrium
/// (`at="static"`), as `ffr linearize --json` gives it: `states`, `inputs`,
/// `outputs`, `A`, `B`, `C`, `D`, and `eigenvalues` (complex).
#[pyfunction]
#[pyo3(signature = (scene, at = None, inputs = None, outputs = None))]
fn linearize<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    at: Option<&Bound<'py, PyAny>>,
    inputs: Option<&Bound<'py, PyAny>>,
    outputs: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let at = at.map_or(Ok(At::Time(0.0)), self::at)?;
    let names = |v: Option<&Bound<'py, PyAny>>, name| {
        v.filter(|v| !v.is_none())
            .map(|v| sequence::<String>(v, name, "names (str)"))
            .transpose()
    };
    let inputs = names(inputs, "inputs")?;
    let outputs = names(outputs, "outputs")?;
    let text = scene_text(scene)?;
    let file = text.file().to_string();
    let spec = text.spec().map_err(scene_err)?;
    let m = detach_interruptible(py, |stop| {
        ffr::scene::linear::linearize_scene_interruptible(
            &spec,
            &ffr::scene::DefaultKernels,
            at,
            inputs.as_deref(),
            outputs.as_deref(),
            stop,
        )
    })?
    .map_err(|e| py_err(e, Some(&file)))?;
    let ev = ffr::runtime::linear::eigenvalues(&m.a).map_err(|e| py_err(e.into(), Some(&file)))?;
    let ev: Vec<numpy::Complex64> = ev
        .iter()
        .map(|l| numpy::Complex64::new(l.re, l.im))
        .collect();
    let out = PyDict::new(py);
    out.set_item("states", m.states.clone())?;
    out.set_item("inputs", m.inputs.clone())?;
    out.set_item("outputs", m.outputs.clone())?;
    out.set_item("A", matrix(py, &m.a))?;
    out.set_item("B", matrix(py, &m.b))?;
    out.set_item("C", matrix(py, &m.c))?;
    out.set_item("D", matrix(py, &m.d))?;
    out.set_item("eigenvalues", PyArray1::from_vec(py, ev))?;
    Ok(out)
}

/// A Campbell diagram: the scene's lowest `count` modes while its driven
/// revolute joint (`joint`, 1-based; default the first) turns at each of
/// `speeds` (rad/s), as `ffr campbell --json` gives it: `speeds`, `joint`,
/// `modes` (per speed, a list of `{omega, hz, zeta, label}`) and
/// `warnings` (a flexible body turning without geometric stiffening, a
/// speed with growing modes), each also issued once as a `RuntimeWarning`.
#[pyfunction]
#[pyo3(signature = (scene, speeds, joint = None, count = 10))]
fn campbell<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    speeds: &Bound<'py, PyAny>,
    joint: Option<usize>,
    count: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let speeds = sequence::<f64>(speeds, "speeds", "rates (rad/s)")?;
    if count == 0 {
        return Err(PyValueError::new_err(
            "count = 0: ask for at least one mode",
        ));
    }
    if joint == Some(0) {
        return Err(PyValueError::new_err(
            "joint = 0: joints are numbered from 1 in file order",
        ));
    }
    let text = scene_text(scene)?;
    let file = text.file().to_string();
    let spec = text.spec().map_err(scene_err)?;
    let c = detach_interruptible(py, |stop| {
        ffr::scene::linear::campbell_interruptible(
            &spec,
            &ffr::scene::DefaultKernels,
            &speeds,
            joint.map(|j| j - 1),
            count,
            &mut |_, _, _, _| Ok(()),
            stop,
        )
    })?
    .map_err(|e| py_err(e, Some(&file)))?;
    let out = PyDict::new(py);
    out.set_item("speeds", PyArray1::from_slice(py, &c.speeds))?;
    out.set_item("joint", c.joint + 1)?;
    let modes = PyList::empty(py);
    for ms in &c.modes {
        let l = PyList::empty(py);
        for m in ms {
            let d = PyDict::new(py);
            d.set_item("omega", m.omega)?;
            d.set_item("hz", m.hz)?;
            d.set_item("zeta", m.zeta)?;
            d.set_item("label", &m.label)?;
            l.append(d)?;
        }
        modes.append(l)?;
    }
    out.set_item("modes", modes)?;
    out.set_item("warnings", c.warnings.clone())?;
    warn_all(py, &c.warnings)?;
    Ok(out)
}

/// The extension module `ffr._ffr`.
#[pymodule]
fn _ffr(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    // numpy's C API now, while importing: loaded lazily by the first call
    // that makes an array, its import would run with a Ctrl-C of that
    // call pending, fail, and the numpy crate would panic.
    py.import("numpy")?;
    drop(PyArray1::<f64>::zeros(py, 0, false));
    m.add("FfrError", py.get_type::<FfrError>())?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    // The run up to the failure, set on the instances a run raises.
    py.get_type::<SimulationError>().setattr("run", py.None())?;
    m.add("SimulationError", py.get_type::<SimulationError>())?;
    m.add_class::<Scene>()?;
    m.add_class::<RunResult>()?;
    m.add_class::<simulation::Simulation>()?;
    m.add_class::<simulation::SimulationState>()?;
    m.add_function(wrap_pyfunction!(invariants, m)?)?;
    m.add_function(wrap_pyfunction!(modes, m)?)?;
    m.add_function(wrap_pyfunction!(linearize, m)?)?;
    m.add_function(wrap_pyfunction!(campbell, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
