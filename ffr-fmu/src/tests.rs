//! The C functions called directly, as an importer calls them: results
//! against `ffr::scene::Simulation` stepped alongside (bit for bit), saved
//! states, independent instances, and every refusal (status, logged
//! message, nothing changed), including a panic caught at the boundary.

use crate::description::{Manifest, Parameter, MANIFEST};
use crate::ffi::*;
use ffr::scene::Simulation;
use std::ffi::{c_char, c_int, CStr, CString};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The log of one instance: (status, category, message).
type Log = Mutex<Vec<(c_int, String, String)>>;

extern "C" fn logger(
    env: fmi2ComponentEnvironment,
    _name: fmi2String,
    status: fmi2Status,
    category: fmi2String,
    message: fmi2String,
) {
    // SAFETY: `env` is the `Log` of this test's instance; the strings are
    // the FMU's NUL-terminated ones.
    unsafe {
        let log = &*(env as *const Log);
        let s = |p: *const c_char| CStr::from_ptr(p).to_string_lossy().into_owned();
        log.lock().unwrap().push((status, s(category), s(message)));
    }
}

/// A resources directory for a scene file (copied beside the manifest),
/// one per call: tests run in parallel threads, and two of them writing
/// one directory read each other's half-written manifest (CI:
/// "ffr-fmu.json: not valid JSON: EOF while parsing").
fn resources(scene: &Path, params: &[&str], tag: &str) -> PathBuf {
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("ffr-fmu-test-{tag}-{}-{k}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let name = scene.file_name().unwrap().to_string_lossy().into_owned();
    std::fs::copy(scene, dir.join(&name)).unwrap();
    let loaded = Arc::new(ffr::scene::load(scene).unwrap());
    let sim = Simulation::new(loaded.clone()).unwrap();
    let text = ffr::scene::SceneText::read(scene).unwrap();
    let m = Manifest {
        guid: format!("{{{tag}}}"),
        model_identifier: "t".into(),
        model_name: "t".into(),
        description: None,
        scene: name,
        inputs: sim
            .input_names()
            .iter()
            .map(|n| (n.to_string(), sim.input(n).unwrap()))
            .collect(),
        outputs: loaded
            .outputs
            .iter()
            .map(|o| (o.name.clone(), "x".into()))
            .collect(),
        parameters: params
            .iter()
            .map(|k| Parameter {
                key: k.to_string(),
                start: match text.get(k) {
                    Some(ffr::scene::SceneValue::Float(x)) => x,
                    other => panic!("{k}: {other:?}"),
                },
            })
            .collect(),
        dt: loaded.dt,
        t_end: loaded.t_end,
    };
    std::fs::write(dir.join(MANIFEST), m.to_json()).unwrap();
    dir
}

/// An instance and its log.
struct Fmu {
    c: fmi2Component,
    log: Box<Log>,
    _callbacks: Box<fmi2CallbackFunctions>,
}

impl Fmu {
    fn try_new(dir: &Path, guid: &str) -> (Option<Fmu>, Vec<String>) {
        let log: Box<Log> = Box::new(Mutex::new(Vec::new()));
        // SAFETY: the logger has the variadic logger's fixed arguments and
        // reads no variadic one (the FMU passes none); as FMPy's logger.
        let logger_fn: fmi2CallbackLogger = unsafe {
            std::mem::transmute::<
                extern "C" fn(
                    fmi2ComponentEnvironment,
                    fmi2String,
                    fmi2Status,
                    fmi2String,
                    fmi2String,
                ),
                fmi2CallbackLogger,
            >(logger)
        };
        let callbacks = Box::new(fmi2CallbackFunctions {
            logger: Some(logger_fn),
            allocateMemory: None,
            freeMemory: None,
            stepFinished: None,
            componentEnvironment: (&*log as *const Log).cast_mut().cast(),
        });
        let name = CString::new("test").unwrap();
        let guid = CString::new(guid).unwrap();
        let uri = CString::new(format!("file://{}", dir.display()).replace(' ', "%20")).unwrap();
        // SAFETY: valid strings and callbacks that outlive the instance.
        let c = unsafe {
            fmi2Instantiate(
                name.as_ptr(),
                fmi2CoSimulation,
                guid.as_ptr(),
                uri.as_ptr(),
                &*callbacks,
                fmi2False,
                fmi2False,
            )
        };
        let messages: Vec<String> = log.lock().unwrap().iter().map(|m| m.2.clone()).collect();
        if c.is_null() {
            (None, messages)
        } else {
            (
                Some(Fmu {
                    c,
                    log,
                    _callbacks: callbacks,
                }),
                messages,
            )
        }
    }

    fn new(dir: &Path, guid: &str) -> Fmu {
        match Fmu::try_new(dir, guid) {
            (Some(f), _) => f,
            (None, m) => panic!("not instantiated: {m:?}"),
        }
    }

    /// Setup, initialization with `params` (vr, value) set in it.
    fn init(&self, params: &[(u32, f64)]) {
        // SAFETY: a live component.
        unsafe {
            assert_eq!(fmi2SetupExperiment(self.c, 0, 0.0, 0.0, 0, 0.0), fmi2OK);
            assert_eq!(fmi2EnterInitializationMode(self.c), fmi2OK);
            for (vr, v) in params {
                assert_eq!(self.set(&[*vr], &[*v]), fmi2OK, "{:?}", self.last());
            }
            assert_eq!(
                fmi2ExitInitializationMode(self.c),
                fmi2OK,
                "{:?}",
                self.last()
            );
        }
    }

    fn set(&self, vr: &[u32], v: &[f64]) -> fmi2Status {
        // SAFETY: a live component; arrays of the length given.
        unsafe { fmi2SetReal(self.c, vr.as_ptr(), vr.len(), v.as_ptr()) }
    }

    fn get(&self, vr: &[u32]) -> Result<Vec<f64>, fmi2Status> {
        let mut out = vec![0.0; vr.len()];
        // SAFETY: a live component; arrays of the length given.
        let s = unsafe { fmi2GetReal(self.c, vr.as_ptr(), vr.len(), out.as_mut_ptr()) };
        if s == fmi2OK {
            Ok(out)
        } else {
            Err(s)
        }
    }

    fn step(&self, t: f64, h: f64) -> fmi2Status {
        // SAFETY: a live component.
        unsafe { fmi2DoStep(self.c, t, h, fmi2True) }
    }

    /// The last logged message.
    fn last(&self) -> String {
        self.log
            .lock()
            .unwrap()
            .last()
            .map(|m| m.2.clone())
            .unwrap_or_default()
    }

    fn last_status(&self) -> c_int {
        self.log.lock().unwrap().last().map_or(-1, |m| m.0)
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        // SAFETY: a live component, freed once.
        unsafe { fmi2FreeInstance(self.c) };
    }
}

fn arm() -> (PathBuf, PathBuf) {
    let scene = root().join("scenes/two_link_arm.toml");
    let dir = resources(&scene, &[], "arm");
    (scene, dir)
}

fn output_vrs(sim: &Simulation) -> Vec<u32> {
    let ni = sim.input_names().len() as u32;
    (ni..ni + sim.output_names().len() as u32).collect()
}

#[test]
fn steps_through_the_c_functions_are_the_simulations_bit_for_bit() {
    let (scene, dir) = arm();
    let mut sim = Simulation::new(Arc::new(ffr::scene::load(&scene).unwrap())).unwrap();
    let dt = sim.scene().dt;
    let vrs = output_vrs(&sim);
    let f = Fmu::new(&dir, "{arm}");
    f.init(&[]);
    assert_eq!(f.get(&vrs).unwrap(), sim.outputs());
    // One step at a time, then five per call (h = 5 dt as an importer
    // computes it: a difference of products).
    let mut t = 0.0;
    for k in 0..40u32 {
        assert_eq!(f.step(t, dt), fmi2OK, "{}", f.last());
        sim.step().unwrap();
        t = f64::from(k + 1) * dt;
        assert_eq!(f.get(&vrs).unwrap(), sim.outputs(), "step {k}");
    }
    for k in 0..10u32 {
        let next = f64::from(40 + 5 * (k + 1)) * dt;
        assert_eq!(f.step(t, next - t), fmi2OK, "{}", f.last());
        for _ in 0..5 {
            sim.step().unwrap();
        }
        t = next;
        assert_eq!(f.get(&vrs).unwrap(), sim.outputs(), "call {k}");
    }
    assert_eq!(sim.steps(), 90);
    let mut last = 0.0;
    // SAFETY: a live component and a valid pointer.
    assert_eq!(
        unsafe { fmi2GetRealStatus(f.c, fmi2LastSuccessfulTime, &mut last) },
        fmi2OK
    );
    assert_eq!(last, sim.time());
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_saved_state_continues_bit_for_bit() {
    let (scene, dir) = arm();
    let sim = Simulation::new(Arc::new(ffr::scene::load(&scene).unwrap())).unwrap();
    let dt = sim.scene().dt;
    let vrs = output_vrs(&sim);
    let f = Fmu::new(&dir, "{arm}");
    f.init(&[]);
    let mut t = 0.0;
    for k in 0..20u32 {
        assert_eq!(f.step(t, dt), fmi2OK);
        t = f64::from(k + 1) * dt;
    }
    let mut state: fmi2FMUstate = std::ptr::null_mut();
    // SAFETY: a live component; `state` is a pointer to a state pointer.
    assert_eq!(unsafe { fmi2GetFMUstate(f.c, &mut state) }, fmi2OK);
    assert!(!state.is_null());
    let run = |t0: f64| {
        let mut out = Vec::new();
        let mut t = t0;
        for k in 0..30u32 {
            assert_eq!(f.step(t, dt), fmi2OK, "{}", f.last());
            t = f64::from(20 + k + 1) * dt;
            out.push(f.get(&vrs).unwrap());
        }
        out
    };
    let first = run(t);
    // SAFETY: a live component and state.
    assert_eq!(unsafe { fmi2SetFMUstate(f.c, state) }, fmi2OK);
    assert_eq!(run(t), first);
    // Overwritten in place, then freed (the pointer set to null); a freed
    // state is refused.
    let kept = state;
    // SAFETY: as above.
    unsafe {
        assert_eq!(fmi2GetFMUstate(f.c, &mut state), fmi2OK);
        assert_eq!(state, kept);
        assert_eq!(fmi2FreeFMUstate(f.c, &mut state), fmi2OK);
        assert!(state.is_null());
        assert_eq!(fmi2SetFMUstate(f.c, kept), fmi2Error);
    }
    assert!(f.last().contains("not a live state"), "{}", f.last());
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn instances_are_independent() {
    // Two instances of one FMU with different parameters, stepped in turn,
    // each equal to its own simulation stepped alone.
    let scene = root().join("scenes/spin_up.toml");
    let key = "joints.0.drive.omega";
    let dir = resources(&scene, &[key], "indep");
    let base = Simulation::new(Arc::new(ffr::scene::load(&scene).unwrap())).unwrap();
    let vrs = output_vrs(&base);
    let pvr = vrs.last().unwrap() + 1;
    let dt = base.scene().dt;
    let alone = |omega: Option<f64>| {
        let mut text = ffr::scene::SceneText::read(&scene).unwrap();
        if let Some(w) = omega {
            text.set(key, w.into()).unwrap();
        }
        let mut sim = Simulation::new(Arc::new(text.load().unwrap())).unwrap();
        (0..25)
            .map(|_| {
                sim.step().unwrap();
                sim.outputs().to_vec()
            })
            .collect::<Vec<_>>()
    };
    let a = Fmu::new(&dir, "{indep}");
    let b = Fmu::new(&dir, "{indep}");
    a.init(&[(pvr, 6.0)]);
    b.init(&[]);
    assert_eq!(a.get(&[pvr]).unwrap(), [6.0]);
    assert_eq!(b.get(&[pvr]).unwrap(), [4.0]);
    let (mut ra, mut rb) = (Vec::new(), Vec::new());
    let mut t = 0.0;
    for k in 0..25u32 {
        assert_eq!(a.step(t, dt), fmi2OK);
        assert_eq!(b.step(t, dt), fmi2OK);
        t = f64::from(k + 1) * dt;
        ra.push(a.get(&vrs).unwrap());
        rb.push(b.get(&vrs).unwrap());
    }
    assert_eq!(ra, alone(Some(6.0)));
    assert_eq!(rb, alone(None));
    assert_ne!(ra, rb);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn bad_calls_are_refused_with_a_message_and_change_nothing() {
    let scene = root().join("scenes/spin_up.toml");
    let key = "joints.0.drive.omega";
    let dir = resources(&scene, &[key], "bad");
    let sim = Simulation::new(Arc::new(ffr::scene::load(&scene).unwrap())).unwrap();
    let vrs = output_vrs(&sim);
    let pvr = vrs.last().unwrap() + 1;
    let dt = sim.scene().dt;
    let f = Fmu::new(&dir, "{bad}");
    let refused = |s: fmi2Status, says: &str| {
        assert_eq!(s, fmi2Error, "{}", f.last());
        assert_eq!(f.last_status(), fmi2Error);
        assert!(f.last().contains(says), "{:?} lacks {says:?}", f.last());
    };
    // SAFETY: a live component throughout; null pointers are what is tested.
    unsafe {
        refused(fmi2DoStep(f.c, 0.0, dt, 0), "not allowed in instantiated");
        refused(fmi2SetupExperiment(f.c, 0, 0.0, 1.0, 0, 0.0), "startTime 1");
        refused(f.set(&[pvr], &[f64::NAN]), "NaN for `joints.0.drive.omega`");
        refused(f.set(&[pvr], &[f64::INFINITY]), "not a finite number");
        assert_eq!(f.get(&[pvr]).unwrap(), [4.0]);
        refused(f.set(&[vrs[0]], &[1.0]), "outputs cannot be set");
        refused(
            f.set(&[9999], &[1.0]),
            "value reference 9999 is not a variable",
        );
        // A refused array sets none of its values.
        refused(f.set(&[pvr, 9999], &[5.0, 1.0]), "9999");
        assert_eq!(f.get(&[pvr]).unwrap(), [4.0]);
        refused(f.get(&[0, 12345]).unwrap_err(), "12345");
        refused(
            fmi2GetReal(f.c, std::ptr::null(), 1, [0.0].as_mut_ptr()),
            "vr is a null pointer",
        );
        assert_eq!(
            fmi2GetReal(f.c, std::ptr::null(), 0, std::ptr::null_mut()),
            fmi2OK
        );
        let mut i = 0;
        refused(
            fmi2GetInteger(f.c, [pvr].as_ptr(), 1, &mut i),
            "no Integer variables",
        );
        f.init(&[]);
        refused(
            f.set(&[pvr], &[5.0]),
            "set only before fmi2ExitInitializationMode",
        );
        refused(f.step(0.0, 0.0), "communicationStepSize 0");
        refused(f.step(0.0, -dt), "must be positive");
        refused(f.step(0.0, f64::NAN), "must be positive");
        refused(
            f.step(0.0, 1.5 * dt),
            "not a whole number of the scene's steps",
        );
        refused(f.step(0.0, 0.4 * dt), "not a whole number");
        refused(f.step(dt, dt), "is not the FMU's time 0");
        refused(f.step(0.0, 1e300), "at most");
        let mut size = 0usize;
        refused(
            fmi2SerializedFMUstateSize(f.c, std::ptr::null_mut(), &mut size),
            "not supported",
        );
        refused(fmi2CancelStep(f.c), "no step is pending");
        refused(fmi2GetFMUstate(f.c, std::ptr::null_mut()), "null pointer");
        refused(
            fmi2SetFMUstate(f.c, std::ptr::null_mut()),
            "not a live state",
        );
        let bogus = CString::new("logNothing").unwrap();
        refused(
            fmi2SetDebugLogging(f.c, 1, 1, [bogus.as_ptr()].as_ptr()),
            "unknown log category",
        );
        // Nothing moved: the first step from 0 is the simulation's first.
        assert_eq!(f.step(0.0, dt), fmi2OK);
        let mut s2 = Simulation::new(Arc::new(ffr::scene::load(&scene).unwrap())).unwrap();
        s2.step().unwrap();
        assert_eq!(f.get(&vrs).unwrap(), s2.outputs());
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_failed_step_is_a_discard_and_a_saved_state_goes_on() {
    // The spin-up beam driven 2000 times faster: its elastic displacement
    // passes the body's size within the ramp and the run stops.
    let scene = root().join("scenes/spin_up.toml");
    let key = "joints.0.drive.omega";
    let dir = resources(&scene, &[key], "fail");
    let sim = Simulation::new(Arc::new(ffr::scene::load(&scene).unwrap())).unwrap();
    let vrs = output_vrs(&sim);
    let pvr = vrs.last().unwrap() + 1;
    let dt = sim.scene().dt;
    let f = Fmu::new(&dir, "{fail}");
    f.init(&[(pvr, 8000.0)]);
    let mut state: fmi2FMUstate = std::ptr::null_mut();
    // SAFETY: a live component.
    assert_eq!(unsafe { fmi2GetFMUstate(f.c, &mut state) }, fmi2OK);
    let mut t = 0.0;
    let mut k = 0u32;
    let status = loop {
        let s = f.step(t, dt);
        if s != fmi2OK || k > 2000 {
            break s;
        }
        k += 1;
        t = f64::from(k) * dt;
    };
    assert_eq!(status, fmi2Discard, "{}", f.last());
    assert_eq!(f.last_status(), fmi2Discard);
    assert!(f.last().contains("the run stopped at t ="), "{}", f.last());
    let (mut last, mut term) = (f64::NAN, 0);
    // SAFETY: a live component and valid pointers.
    unsafe {
        assert_eq!(
            fmi2GetRealStatus(f.c, fmi2LastSuccessfulTime, &mut last),
            fmi2OK
        );
        assert_eq!(fmi2GetBooleanStatus(f.c, fmi2Terminated, &mut term), fmi2OK);
    }
    // The time reached (the FMU's is a sum of steps, `t` here a product).
    assert!((last - t).abs() <= 1e-12, "{last} {t}");
    assert_eq!(term, fmi2True);
    // Further steps are refused with the failure; the outputs stay readable.
    assert_eq!(f.step(t, dt), fmi2Error);
    assert!(
        f.last().contains("the simulation failed at t ="),
        "{}",
        f.last()
    );
    assert!(f.get(&vrs).is_ok());
    // Back to t = 0: steps again, as the first time.
    // SAFETY: a live component and state.
    assert_eq!(unsafe { fmi2SetFMUstate(f.c, state) }, fmi2OK);
    assert_eq!(f.step(0.0, dt), fmi2OK, "{}", f.last());
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_missing_resource_or_another_guid_is_no_instance_and_a_message() {
    let (_, dir) = arm();
    let (none, m) = Fmu::try_new(&dir, "{other}");
    assert!(none.is_none());
    assert!(
        m.iter()
            .any(|m| m.contains("fmuGUID \"{other}\" is not this FMU's")),
        "{m:?}"
    );
    std::fs::remove_file(dir.join("two_link_arm.toml")).unwrap();
    let (none, m) = Fmu::try_new(&dir, "{arm}");
    assert!(none.is_none());
    assert!(m.iter().any(|m| m.contains("two_link_arm.toml")), "{m:?}");
    std::fs::remove_file(dir.join(MANIFEST)).unwrap();
    let (none, m) = Fmu::try_new(&dir, "{arm}");
    assert!(none.is_none());
    assert!(
        m.iter().any(|m| m.contains("ffr-fmu.json: cannot be read")),
        "{m:?}"
    );
    // Model Exchange, a null name and a non-file URI are refused too.
    let g = CString::new("{arm}").unwrap();
    let u = CString::new("http://example.org/r").unwrap();
    let cb = fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    };
    // SAFETY: valid pointers or nulls.
    unsafe {
        let n = CString::new("x").unwrap();
        assert!(fmi2Instantiate(
            n.as_ptr(),
            fmi2ModelExchange,
            g.as_ptr(),
            u.as_ptr(),
            &cb,
            0,
            0
        )
        .is_null());
        assert!(fmi2Instantiate(
            std::ptr::null(),
            fmi2CoSimulation,
            g.as_ptr(),
            u.as_ptr(),
            &cb,
            0,
            0
        )
        .is_null());
        assert!(fmi2Instantiate(
            n.as_ptr(),
            fmi2CoSimulation,
            g.as_ptr(),
            u.as_ptr(),
            &cb,
            0,
            0
        )
        .is_null());
        assert!(fmi2Instantiate(
            n.as_ptr(),
            fmi2CoSimulation,
            g.as_ptr(),
            u.as_ptr(),
            std::ptr::null(),
            0,
            0
        )
        .is_null());
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_panic_stops_at_the_boundary_and_reset_recovers() {
    let (_, dir) = arm();
    let f = Fmu::new(&dir, "{arm}");
    f.init(&[]);
    let dt = 1e-3;
    crate::ffi::PANIC_NEXT.with(|p| p.set(true));
    assert_eq!(f.step(0.0, dt), fmi2Error);
    assert!(
        f.last()
            .contains("internal error (test panic in fmi2DoStep)"),
        "{}",
        f.last()
    );
    // Broken: only reset (or free) is accepted.
    assert_eq!(f.step(0.0, dt), fmi2Error);
    assert!(f.last().contains("broken"), "{}", f.last());
    // SAFETY: a live component.
    assert_eq!(unsafe { fmi2Reset(f.c) }, fmi2OK);
    f.init(&[]);
    assert_eq!(f.step(0.0, dt), fmi2OK, "{}", f.last());
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn resource_uris_are_decoded() {
    use crate::instance::resource_dir;
    assert_eq!(
        resource_dir("file:///a/b%20c/").unwrap(),
        PathBuf::from("/a/b c/")
    );
    assert_eq!(
        resource_dir("file://localhost/a").unwrap(),
        PathBuf::from("/a")
    );
    assert_eq!(resource_dir("file:/a").unwrap(), PathBuf::from("/a"));
    assert!(resource_dir("file://host/a")
        .unwrap_err()
        .contains("names a host"));
    assert!(resource_dir("file:///a%2")
        .unwrap_err()
        .contains("%-escape"));
    assert!(resource_dir("a/b").unwrap_err().contains("not a file: URI"));
}

#[test]
fn inputs_set_through_the_c_functions_are_held_as_the_simulations() {
    // The shipped arm with two inputs: values set by fmi2SetReal before
    // each call (one or three scene steps), against a simulation with the
    // same values set by index. A NaN is refused and changes nothing.
    let scene = root().join("scenes/two_link_arm_inputs.toml");
    let dir = resources(&scene, &[], "inputs");
    let mut sim = Simulation::new(Arc::new(ffr::scene::load(&scene).unwrap())).unwrap();
    assert_eq!(sim.input_names(), ["elbow_tau", "hand_push"]);
    let vrs = output_vrs(&sim);
    let dt = sim.scene().dt;
    let f = Fmu::new(&dir, "{inputs}");
    f.init(&[(0, 0.02), (1, -0.1)]);
    sim.set_input_at(0, 0.02).unwrap();
    sim.set_input_at(1, -0.1).unwrap();
    assert_eq!(f.get(&vrs).unwrap(), sim.outputs());
    let mut t = 0.0;
    let mut k = 0u32;
    for call in 0..30u32 {
        let (tau, push) = (0.03 * f64::from(call % 5), 0.2 * f64::from(call % 3) - 0.1);
        assert_eq!(f.set(&[0, 1], &[tau, push]), fmi2OK);
        sim.set_input_at(0, tau).unwrap();
        sim.set_input_at(1, push).unwrap();
        let n = 1 + 2 * (call % 2);
        assert_eq!(f.step(t, f64::from(k + n) * dt - t), fmi2OK, "{}", f.last());
        for _ in 0..n {
            sim.step().unwrap();
        }
        k += n;
        t = f64::from(k) * dt;
        assert_eq!(f.get(&vrs).unwrap(), sim.outputs(), "call {call}");
        assert_eq!(f.get(&[0, 1]).unwrap(), [tau, push]);
    }
    assert_eq!(f.set(&[1, 0], &[0.5, f64::NAN]), fmi2Error);
    assert!(f.last().contains("NaN for `elbow_tau`"), "{}", f.last());
    assert_eq!(f.get(&[1]).unwrap(), [0.2 * f64::from(29 % 3) - 0.1]);
    assert_eq!(f.step(t, dt), fmi2OK);
    sim.step().unwrap();
    assert_eq!(f.get(&vrs).unwrap(), sim.outputs());
    let _ = std::fs::remove_dir_all(dir);
}
