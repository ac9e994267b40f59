//! One FMU instance: the manifest, the scene's text (for parameters), the
//! simulation, the held input values and the FMI state machine. Everything
//! here returns `Result<_, Refusal>`; the C functions (`crate::ffi`) turn
//! that into an `fmi2Status` and a logged message.

use crate::description::{Manifest, Var, MANIFEST};
use ffr::scene::{SceneText, SceneValue, Simulation, SimulationState};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The most scene steps one `fmi2DoStep` takes (a communication step of
/// more is refused before stepping: a huge step would look like a hang).
pub const MAX_STEPS_PER_CALL: u64 = 100_000_000;

/// Relative tolerance of a communication step that must be a whole number
/// of scene steps (relative to the step), and of `currentCommunicationPoint`
/// against the FMU's time (relative to the larger of `dt` and the time: the
/// FMU's time is a sum of steps, an importer's often a product).
pub const STEP_TOLERANCE: f64 = 1e-9;

/// Where an instance is in the FMI 2.0 Co-Simulation state machine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// After `fmi2Instantiate` or `fmi2Reset`.
    Instantiated,
    /// Between `fmi2EnterInitializationMode` and `fmi2ExitInitializationMode`.
    Initialization,
    /// After initialization: steps.
    Step,
    /// After `fmi2Terminate`.
    Terminated,
    /// After an internal error (a panic): only `fmi2Reset` and
    /// `fmi2FreeInstance` are accepted.
    Broken,
}

impl Mode {
    fn name(self) -> &'static str {
        match self {
            Mode::Instantiated => "instantiated (before fmi2EnterInitializationMode)",
            Mode::Initialization => "initialization mode",
            Mode::Step => "step mode",
            Mode::Terminated => "terminated",
            Mode::Broken => "broken by an internal error (only fmi2Reset or fmi2FreeInstance)",
        }
    }
}

/// Why a call was refused or failed.
#[derive(Clone, Debug, PartialEq)]
pub enum Refusal {
    /// The call is wrong (bad arguments, wrong mode): `fmi2Error`.
    Error(String),
    /// A step failed (the simulation stopped): `fmi2Discard`.
    Discard(String),
}

impl Refusal {
    /// The message.
    pub fn message(&self) -> &str {
        match self {
            Refusal::Error(m) | Refusal::Discard(m) => m,
        }
    }
}

fn err(m: impl Into<String>) -> Refusal {
    Refusal::Error(m.into())
}

/// What `fmi2GetFMUstate` saves: the simulation's state and the values held
/// at the inputs and parameters, and the mode.
#[derive(Clone)]
pub struct SavedState {
    sim: SimulationState,
    inputs: Vec<f64>,
    parameters: Vec<f64>,
    built_with: Vec<f64>,
    mode: Mode,
}

/// An FMU instance.
pub struct Instance {
    /// `instanceName`.
    pub name: String,
    /// The FMU's manifest.
    pub manifest: Manifest,
    /// The scene file inside the resources.
    scene_path: PathBuf,
    /// The scene as instantiated (parameters at their starts).
    base: Arc<ffr::scene::Scene>,
    /// The simulation (rebuilt at `fmi2ExitInitializationMode` when a
    /// parameter changed).
    pub sim: Simulation,
    /// The values held at the inputs (zero-order hold).
    inputs: Vec<f64>,
    /// The parameters' values.
    parameters: Vec<f64>,
    /// The parameters' values the simulation was built with.
    built_with: Vec<f64>,
    /// The mode.
    pub mode: Mode,
    /// The time of the last step that succeeded (`fmi2LastSuccessfulTime`).
    pub last_successful_time: f64,
}

/// The local directory of `fmuResourceLocation`: a `file:` URI
/// (`file:///dir`, `file://localhost/dir`, `file:/dir`, with `%XX`
/// escapes) or, leniently, a plain absolute path.
pub fn resource_dir(uri: &str) -> Result<PathBuf, String> {
    let rest = if let Some(r) = uri.strip_prefix("file://") {
        if let Some(r) = r.strip_prefix("localhost") {
            r
        } else if r.starts_with('/') {
            r
        } else {
            return Err(format!(
                "fmuResourceLocation {uri:?} names a host: only local file: URIs are read"
            ));
        }
    } else if let Some(r) = uri.strip_prefix("file:") {
        r
    } else if uri.starts_with('/') {
        uri
    } else {
        return Err(format!(
            "fmuResourceLocation {uri:?} is not a file: URI (file:///path/to/resources)"
        ));
    };
    let bytes = rest.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| format!("fmuResourceLocation {uri:?} has a bad %-escape"))?;
            out.push(hex);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    #[cfg(unix)]
    let p = {
        use std::os::unix::ffi::OsStringExt;
        PathBuf::from(std::ffi::OsString::from_vec(out))
    };
    #[cfg(not(unix))]
    let p = PathBuf::from(String::from_utf8_lossy(&out).into_owned());
    Ok(p)
}

/// The scene at `path` with `parameters` set at their keys: a parameter
/// whose scene value is an integer is set as an integer when it is one.
fn load_scene(
    path: &Path,
    manifest: &Manifest,
    values: Option<&[f64]>,
) -> Result<ffr::scene::Scene, String> {
    let mut text = SceneText::read(path).map_err(|e| e.to_string())?;
    if let Some(values) = values {
        for (p, v) in manifest.parameters.iter().zip(values) {
            let value = match text.get(&p.key) {
                Some(SceneValue::Int(_)) if v.fract() == 0.0 && v.abs() < 9.0e15 => {
                    SceneValue::Int(*v as i64)
                }
                _ => SceneValue::Float(*v),
            };
            text.set(&p.key, value).map_err(|e| e.to_string())?;
        }
    }
    text.load().map_err(|e| e.to_string())
}

impl Instance {
    /// Instantiate from the resources directory: read the manifest, check
    /// the guid, load the scene and start its simulation (t = 0).
    pub fn new(name: &str, guid: &str, resources: &Path) -> Result<Instance, String> {
        let mpath = resources.join(MANIFEST);
        let text = std::fs::read_to_string(&mpath).map_err(|e| {
            format!(
                "{}: cannot be read ({e}): the FMU's resources are incomplete (was it written by `ffr fmu`?)",
                mpath.display()
            )
        })?;
        let manifest =
            Manifest::from_json(&text).map_err(|e| format!("{}: {e}", mpath.display()))?;
        if manifest.guid != guid {
            return Err(format!(
                "fmuGUID {guid:?} is not this FMU's {:?}: the model description and the resources are of different FMUs",
                manifest.guid
            ));
        }
        let scene_path = resources.join(&manifest.scene);
        let scene = load_scene(&scene_path, &manifest, None)?;
        let base = Arc::new(scene);
        let sim = Simulation::new(base.clone()).map_err(|e| e.to_string())?;
        let names: Vec<&str> = sim.input_names();
        let declared: Vec<&str> = manifest.inputs.iter().map(|(n, _)| n.as_str()).collect();
        let outs: Vec<&str> = sim.output_names();
        let declared_out: Vec<&str> = manifest.outputs.iter().map(|(n, _)| n.as_str()).collect();
        if names != declared || outs != declared_out {
            return Err(format!(
                "{}: the scene's inputs {names:?} and outputs {outs:?} are not the FMU's {declared:?} and {declared_out:?}: the resources were changed after `ffr fmu`",
                scene_path.display()
            ));
        }
        let inputs: Vec<f64> = manifest.inputs.iter().map(|(_, s)| *s).collect();
        let parameters: Vec<f64> = manifest.parameters.iter().map(|p| p.start).collect();
        let mut inst = Instance {
            name: name.to_string(),
            scene_path,
            base,
            sim,
            built_with: parameters.clone(),
            inputs,
            parameters,
            mode: Mode::Instantiated,
            last_successful_time: 0.0,
            manifest,
        };
        inst.apply_inputs().map_err(|e| e.message().to_string())?;
        Ok(inst)
    }

    fn apply_inputs(&mut self) -> Result<(), Refusal> {
        for (i, v) in self.inputs.iter().enumerate() {
            self.sim
                .set_input_at(i, *v)
                .map_err(|e| err(e.to_string()))?;
        }
        Ok(())
    }

    fn expect(&self, what: &str, modes: &[Mode]) -> Result<(), Refusal> {
        if modes.contains(&self.mode) {
            Ok(())
        } else {
            Err(err(format!(
                "{what} is not allowed in {}",
                self.mode.name()
            )))
        }
    }

    /// `fmi2SetupExperiment`: the start time must be 0 (a scene starts there).
    pub fn setup_experiment(&mut self, start: f64) -> Result<(), Refusal> {
        self.expect("fmi2SetupExperiment", &[Mode::Instantiated])?;
        if start != 0.0 {
            return Err(err(format!(
                "startTime {start}: a scene starts at t = 0 (startTime must be 0)"
            )));
        }
        Ok(())
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization(&mut self) -> Result<(), Refusal> {
        self.expect("fmi2EnterInitializationMode", &[Mode::Instantiated])?;
        self.mode = Mode::Initialization;
        Ok(())
    }

    /// `fmi2ExitInitializationMode`: the scene re-resolved with the
    /// parameters when one differs from the values it was built with, the
    /// held inputs applied.
    pub fn exit_initialization(&mut self) -> Result<(), Refusal> {
        self.expect("fmi2ExitInitializationMode", &[Mode::Initialization])?;
        if self.parameters != self.built_with {
            let scene = load_scene(&self.scene_path, &self.manifest, Some(&self.parameters))
                .map_err(|e| err(format!("the parameters give no valid scene: {e}")))?;
            let sim = Simulation::new(Arc::new(scene))
                .map_err(|e| err(format!("the parameters give no valid initial state: {e}")))?;
            self.sim = sim;
            self.built_with = self.parameters.clone();
        }
        self.apply_inputs()?;
        self.mode = Mode::Step;
        Ok(())
    }

    /// `fmi2Terminate`.
    pub fn terminate(&mut self) -> Result<(), Refusal> {
        self.expect(
            "fmi2Terminate",
            &[Mode::Step, Mode::Initialization, Mode::Terminated],
        )?;
        self.mode = Mode::Terminated;
        Ok(())
    }

    /// `fmi2Reset`: as instantiated (parameters and inputs at their starts,
    /// t = 0), also after an internal error.
    pub fn reset(&mut self) -> Result<(), Refusal> {
        self.sim = Simulation::new(self.base.clone()).map_err(|e| err(e.to_string()))?;
        self.parameters = self.manifest.parameters.iter().map(|p| p.start).collect();
        self.built_with = self.parameters.clone();
        self.inputs = self.manifest.inputs.iter().map(|(_, s)| *s).collect();
        self.apply_inputs()?;
        self.mode = Mode::Instantiated;
        self.last_successful_time = 0.0;
        Ok(())
    }

    fn var(&self, vr: u32) -> Result<Var, Refusal> {
        self.manifest.var(vr).ok_or_else(|| {
            err(format!(
                "value reference {vr} is not a variable of this FMU (0 to {})",
                self.manifest.variable_count().saturating_sub(1)
            ))
        })
    }

    /// Check every value reference before any value is read or set.
    pub fn check_refs(&self, vrs: &[u32]) -> Result<(), Refusal> {
        for vr in vrs {
            self.var(*vr)?;
        }
        Ok(())
    }

    /// `fmi2GetReal`: every reference checked first; `out` untouched on error.
    pub fn get_real(&self, vrs: &[u32], out: &mut [f64]) -> Result<(), Refusal> {
        self.expect(
            "fmi2GetReal",
            &[
                Mode::Instantiated,
                Mode::Initialization,
                Mode::Step,
                Mode::Terminated,
            ],
        )?;
        self.check_refs(vrs)?;
        let outputs = self.sim.outputs();
        for (vr, o) in vrs.iter().zip(out.iter_mut()) {
            *o = match self.var(*vr)? {
                Var::Input(i) => self.inputs[i],
                Var::Output(i) => outputs[i],
                Var::Parameter(i) => self.parameters[i],
            };
        }
        Ok(())
    }

    /// `fmi2SetReal`: inputs in any mode before termination, parameters
    /// before the end of initialization; every reference and value checked
    /// before any is set (a refusal changes nothing).
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), Refusal> {
        self.expect(
            "fmi2SetReal",
            &[Mode::Instantiated, Mode::Initialization, Mode::Step],
        )?;
        for (vr, v) in vrs.iter().zip(values) {
            let var = self.var(*vr)?;
            let name = self.manifest.name(var);
            match var {
                Var::Output(_) => {
                    return Err(err(format!(
                        "value reference {vr} is the output `{name}`: outputs cannot be set"
                    )))
                }
                Var::Parameter(_) if !matches!(self.mode, Mode::Instantiated | Mode::Initialization) => {
                    return Err(err(format!(
                        "the parameter `{name}` (value reference {vr}) is set only before fmi2ExitInitializationMode (variability fixed)"
                    )))
                }
                _ => {}
            }
            if !v.is_finite() {
                return Err(err(format!(
                    "{v} for `{name}` (value reference {vr}) is not a finite number: refused, nothing set"
                )));
            }
        }
        for (vr, v) in vrs.iter().zip(values) {
            match self.var(*vr)? {
                Var::Input(i) => {
                    if self.mode == Mode::Step {
                        self.sim
                            .set_input_at(i, *v)
                            .map_err(|e| err(e.to_string()))?;
                    }
                    self.inputs[i] = *v;
                }
                Var::Parameter(i) => self.parameters[i] = *v,
                Var::Output(_) => unreachable!("refused above"),
            }
        }
        Ok(())
    }

    /// The number of scene steps of a communication step `h` from `t`.
    pub fn steps_of(&self, t: f64, h: f64) -> Result<u64, Refusal> {
        let dt = self.sim.scene().dt;
        let now = self.sim.time();
        if !t.is_finite() || (t - now).abs() > STEP_TOLERANCE * dt.max(now.abs()) {
            return Err(err(format!(
                "currentCommunicationPoint {t} is not the FMU's time {now}: steps continue from where the last one ended (set a saved state with fmi2SetFMUstate to go back)"
            )));
        }
        if !(h > 0.0) || !h.is_finite() {
            return Err(err(format!(
                "communicationStepSize {h}: a step must be positive and finite"
            )));
        }
        let n = (h / dt).round();
        if n < 1.0 || (n * dt - h).abs() > STEP_TOLERANCE * h {
            return Err(err(format!(
                "communicationStepSize {h} is not a whole number of the scene's steps dt = {dt} (to 1e-9 relative): the FMU takes whole steps; use a multiple of dt"
            )));
        }
        if n > MAX_STEPS_PER_CALL as f64 {
            return Err(err(format!(
                "communicationStepSize {h} is {n:e} scene steps: at most {MAX_STEPS_PER_CALL} in one fmi2DoStep"
            )));
        }
        Ok(n as u64)
    }

    /// `fmi2DoStep`: whole scene steps, the inputs held; a failed step is a
    /// discard with the run's message, and steps after it are refused until
    /// a state is set or the instance reset.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<(), Refusal> {
        self.expect("fmi2DoStep", &[Mode::Step])?;
        if let Some(m) = self.sim.failed() {
            return Err(err(format!(
                "the simulation failed at t = {}: {m}; set a saved state (fmi2SetFMUstate) or reset the instance to go on",
                self.last_successful_time
            )));
        }
        let n = self.steps_of(t, h)?;
        for _ in 0..n {
            if let Err(e) = self.sim.step() {
                return Err(Refusal::Discard(format!(
                    "the step from t = {} failed: {e}",
                    self.sim.time()
                )));
            }
            self.last_successful_time = self.sim.time();
        }
        Ok(())
    }

    /// `fmi2GetFMUstate`.
    pub fn save(&self) -> Result<SavedState, Refusal> {
        self.expect(
            "fmi2GetFMUstate",
            &[
                Mode::Instantiated,
                Mode::Initialization,
                Mode::Step,
                Mode::Terminated,
            ],
        )?;
        Ok(SavedState {
            sim: self.sim.save_state(),
            inputs: self.inputs.clone(),
            parameters: self.parameters.clone(),
            built_with: self.built_with.clone(),
            mode: self.mode,
        })
    }

    /// `fmi2SetFMUstate`: exact; the state's parameters must be those the
    /// simulation was built with (the simulation refuses a state of another
    /// scene).
    pub fn restore(&mut self, s: &SavedState) -> Result<(), Refusal> {
        self.expect(
            "fmi2SetFMUstate",
            &[
                Mode::Instantiated,
                Mode::Initialization,
                Mode::Step,
                Mode::Terminated,
            ],
        )?;
        if s.parameters.len() != self.parameters.len() || s.inputs.len() != self.inputs.len() {
            return Err(err("the state is of another FMU"));
        }
        if s.built_with != self.built_with {
            return Err(err(format!(
                "the state was saved from the scene with the parameters {:?}, this instance runs it with {:?}: a state is set only on the scene it was saved from",
                s.built_with, self.built_with
            )));
        }
        self.sim
            .restore_state(&s.sim)
            .map_err(|e| err(format!("the state cannot be set: {e}")))?;
        self.inputs.clone_from(&s.inputs);
        self.parameters.clone_from(&s.parameters);
        self.apply_inputs()?;
        self.mode = s.mode;
        self.last_successful_time = self.sim.time();
        Ok(())
    }
}
