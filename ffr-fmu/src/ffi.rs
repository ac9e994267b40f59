//! The FMI 2.0 Co-Simulation C interface (`fmi2Functions.h`,
//! `fmi2FunctionTypes.h`, `fmi2TypesPlatform.h` of FMI 2.0.5, the default
//! platform types), unprefixed as a shared library exports them.
//!
//! Every function checks its component against the live instances (a
//! pointer that `fmi2Instantiate` did not return, or one already freed, is
//! `fmi2Error` without touching it), checks null pointers and value
//! references before reading or writing anything, and runs inside
//! `catch_unwind`: a panic never crosses the C boundary; it is logged, the
//! call returns `fmi2Error` and the instance accepts only `fmi2Reset` and
//! `fmi2FreeInstance` after it. Refusals are logged through the importer's
//! logger (category `logStatusError`; failed steps `logStatusDiscard`),
//! whatever `loggingOn` says.

#![allow(non_camel_case_types, non_snake_case, non_upper_case_globals)]

use crate::instance::{Instance, Mode, Refusal, SavedState};
use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Mutex;

/// `fmi2Status`.
pub type fmi2Status = c_int;
/// `fmi2OK`.
pub const fmi2OK: fmi2Status = 0;
/// `fmi2Warning`.
pub const fmi2Warning: fmi2Status = 1;
/// `fmi2Discard`.
pub const fmi2Discard: fmi2Status = 2;
/// `fmi2Error`.
pub const fmi2Error: fmi2Status = 3;
/// `fmi2Fatal`.
pub const fmi2Fatal: fmi2Status = 4;
/// `fmi2Pending`.
pub const fmi2Pending: fmi2Status = 5;

/// `fmi2Type`.
pub type fmi2Type = c_int;
/// `fmi2ModelExchange`.
pub const fmi2ModelExchange: fmi2Type = 0;
/// `fmi2CoSimulation`.
pub const fmi2CoSimulation: fmi2Type = 1;

/// `fmi2StatusKind`.
pub type fmi2StatusKind = c_int;
/// `fmi2DoStepStatus`.
pub const fmi2DoStepStatus: fmi2StatusKind = 0;
/// `fmi2PendingStatus`.
pub const fmi2PendingStatus: fmi2StatusKind = 1;
/// `fmi2LastSuccessfulTime`.
pub const fmi2LastSuccessfulTime: fmi2StatusKind = 2;
/// `fmi2Terminated`.
pub const fmi2Terminated: fmi2StatusKind = 3;

/// `fmi2Component`.
pub type fmi2Component = *mut c_void;
/// `fmi2ComponentEnvironment`.
pub type fmi2ComponentEnvironment = *mut c_void;
/// `fmi2FMUstate`.
pub type fmi2FMUstate = *mut c_void;
/// `fmi2ValueReference`.
pub type fmi2ValueReference = c_uint;
/// `fmi2Real`.
pub type fmi2Real = f64;
/// `fmi2Integer`.
pub type fmi2Integer = c_int;
/// `fmi2Boolean`.
pub type fmi2Boolean = c_int;
/// `fmi2String`.
pub type fmi2String = *const c_char;
/// `fmi2Byte`.
pub type fmi2Byte = c_char;
/// `fmi2True`.
pub const fmi2True: fmi2Boolean = 1;
/// `fmi2False`.
pub const fmi2False: fmi2Boolean = 0;

/// `fmi2CallbackLogger` (variadic: the message is a printf format; ffr
/// passes no arguments and writes `%` as `%%`).
pub type fmi2CallbackLogger = unsafe extern "C" fn(
    fmi2ComponentEnvironment,
    fmi2String,
    fmi2Status,
    fmi2String,
    fmi2String,
    ...
);

/// `fmi2CallbackFunctions`.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct fmi2CallbackFunctions {
    /// Where messages go.
    pub logger: Option<fmi2CallbackLogger>,
    /// Not used (`canNotUseMemoryManagementFunctions`).
    pub allocateMemory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    /// Not used.
    pub freeMemory: Option<unsafe extern "C" fn(*mut c_void)>,
    /// Not used (no asynchronous steps).
    pub stepFinished: Option<unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2Status)>,
    /// Passed back to the logger.
    pub componentEnvironment: fmi2ComponentEnvironment,
}

/// What `fmi2Instantiate` returns a pointer to.
pub struct Component {
    logger: Option<fmi2CallbackLogger>,
    env: fmi2ComponentEnvironment,
    name: CString,
    logging: bool,
    /// The instance.
    pub inst: Instance,
}

// SAFETY: the environment pointer is only handed back to the importer's
// logger, from whichever thread the importer calls in on (FMI lets one
// instance be called from different threads, one call at a time).
unsafe impl Send for Component {}

/// The live components and saved states (addresses), so that a pointer
/// that was never returned, or was freed, is refused instead of used.
struct Registry {
    components: Vec<usize>,
    /// (state, owning component)
    states: Vec<(usize, usize)>,
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry {
    components: Vec::new(),
    states: Vec::new(),
});

fn registry() -> std::sync::MutexGuard<'static, Registry> {
    // A panic never happens while the lock is held; recover anyway.
    REGISTRY.lock().unwrap_or_else(|e| e.into_inner())
}

fn is_live(c: fmi2Component) -> bool {
    !c.is_null() && registry().components.contains(&(c as usize))
}

/// Log `message` through the component's logger (`%` escaped).
fn log_to(
    logger: Option<fmi2CallbackLogger>,
    env: fmi2ComponentEnvironment,
    name: &CStr,
    status: fmi2Status,
    category: &str,
    message: &str,
) {
    let Some(logger) = logger else { return };
    let clean = |s: &str| CString::new(s.replace('%', "%%").replace('\0', " ")).unwrap_or_default();
    let (category, message) = (clean(category), clean(message));
    // SAFETY: the importer's logger with valid NUL-terminated strings that
    // live for the call; no variadic arguments (the `%` are escaped).
    unsafe {
        logger(
            env,
            name.as_ptr(),
            status,
            category.as_ptr(),
            message.as_ptr(),
        )
    };
}

impl Component {
    fn log(&self, status: fmi2Status, category: &str, message: &str) {
        log_to(self.logger, self.env, &self.name, status, category, message);
    }
}

/// Text of a panic's payload.
fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic".into())
}

#[cfg(test)]
thread_local! {
    /// Tests: make the next call through [`with`] panic inside its guard.
    pub(crate) static PANIC_NEXT: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Run `f` on a live component inside `catch_unwind`, turning its result
/// into a status and logging a refusal, a discard or a panic.
fn with(
    c: fmi2Component,
    what: &str,
    f: impl FnOnce(&mut Component) -> Result<(), Refusal>,
) -> fmi2Status {
    if !is_live(c) {
        return fmi2Error;
    }
    // SAFETY: `c` is a live component (returned by fmi2Instantiate, not yet
    // freed); the importer calls one instance from one thread at a time.
    let comp = unsafe { &mut *(c as *mut Component) };
    let r = catch_unwind(AssertUnwindSafe(|| {
        if comp.inst.mode == Mode::Broken && what != "fmi2Reset" {
            return Err(Refusal::Error(
                "the instance is broken by an earlier internal error: only fmi2Reset or fmi2FreeInstance".into(),
            ));
        }
        #[cfg(test)]
        if PANIC_NEXT.with(|p| p.replace(false)) {
            panic!("test panic in {what}");
        }
        f(comp)
    }));
    let status = match r {
        Ok(Ok(())) => return fmi2OK,
        Ok(Err(Refusal::Error(m))) => (fmi2Error, "logStatusError", format!("{what}: {m}")),
        Ok(Err(Refusal::Discard(m))) => (fmi2Discard, "logStatusDiscard", format!("{what}: {m}")),
        Err(p) => {
            comp.inst.mode = Mode::Broken;
            (
                fmi2Error,
                "logStatusError",
                format!(
                    "{what}: internal error ({}); the instance accepts only fmi2Reset or fmi2FreeInstance now",
                    panic_text(p.as_ref())
                ),
            )
        }
    };
    let _ = catch_unwind(AssertUnwindSafe(|| comp.log(status.0, status.1, &status.2)));
    status.0
}

/// A slice from a C array, `&[]` for `n = 0` (whatever the pointer).
///
/// # Safety
/// `p` points to `n` valid elements when `n > 0`.
unsafe fn slice<'a, T>(p: *const T, n: usize, what: &str) -> Result<&'a [T], Refusal> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(Refusal::Error(format!("{what} is a null pointer")));
    }
    // SAFETY: the caller's promise.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// A mutable slice from a C array (as [`slice`]).
///
/// # Safety
/// `p` points to `n` valid writable elements when `n > 0`.
unsafe fn slice_mut<'a, T>(p: *mut T, n: usize, what: &str) -> Result<&'a mut [T], Refusal> {
    if n == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err(Refusal::Error(format!("{what} is a null pointer")));
    }
    // SAFETY: the caller's promise.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// A C string argument, or a refusal naming it.
///
/// # Safety
/// `p` is null or a NUL-terminated string.
unsafe fn text<'a>(p: fmi2String, what: &str) -> Result<&'a str, String> {
    if p.is_null() {
        return Err(format!("{what} is a null pointer"));
    }
    // SAFETY: the caller's promise.
    unsafe { CStr::from_ptr(p) }
        .to_str()
        .map_err(|_| format!("{what} is not UTF-8"))
}

/// `fmi2GetTypesPlatform`: `"default"`.
#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

/// `fmi2GetVersion`: `"2.0"`.
#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

/// `fmi2Instantiate`: the instance with its scene built from
/// `fmuResourceLocation` (a `file:` URI of the unpacked `resources/`); null
/// with a logged message when anything is wrong (a Model Exchange request,
/// another FMU's guid, a missing or changed resource, a scene or initial
/// state that fails).
///
/// # Safety
/// The pointers are null or as FMI 2.0 describes them.
#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instanceName: fmi2String,
    fmuType: fmi2Type,
    fmuGUID: fmi2String,
    fmuResourceLocation: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    loggingOn: fmi2Boolean,
) -> fmi2Component {
    let r = catch_unwind(AssertUnwindSafe(|| {
        if functions.is_null() {
            return std::ptr::null_mut();
        }
        // SAFETY: non-null; the importer's callback struct.
        let cb = unsafe { *functions };
        // SAFETY: as the caller promises.
        let name = unsafe { text(instanceName, "instanceName") };
        let cname = CString::new(*name.as_ref().unwrap_or(&"?")).unwrap_or_default();
        let fail = |m: String| {
            log_to(
                cb.logger,
                cb.componentEnvironment,
                &cname,
                fmi2Error,
                "logStatusError",
                &format!("fmi2Instantiate: {m}"),
            );
            std::ptr::null_mut()
        };
        let name = match name {
            Ok(n) => n,
            Err(m) => return fail(m),
        };
        if fmuType != fmi2CoSimulation {
            return fail(format!(
                "fmuType {fmuType}: this FMU is for Co-Simulation only (fmi2CoSimulation = 1)"
            ));
        }
        // SAFETY: as the caller promises.
        let (guid, uri) = match unsafe {
            (
                text(fmuGUID, "fmuGUID"),
                text(fmuResourceLocation, "fmuResourceLocation"),
            )
        } {
            (Ok(g), Ok(u)) => (g, u),
            (Err(m), _) | (_, Err(m)) => return fail(m),
        };
        let dir = match crate::instance::resource_dir(uri) {
            Ok(d) => d,
            Err(m) => return fail(m),
        };
        let inst = match Instance::new(name, guid, &dir) {
            Ok(i) => i,
            Err(m) => return fail(m),
        };
        let comp = Box::new(Component {
            logger: cb.logger,
            env: cb.componentEnvironment,
            name: cname.clone(),
            logging: loggingOn != fmi2False,
            inst,
        });
        if comp.logging {
            comp.log(fmi2OK, "logAll", "fmi2Instantiate: scene loaded, t = 0");
        }
        let p = Box::into_raw(comp);
        registry().components.push(p as usize);
        p as fmi2Component
    }));
    r.unwrap_or(std::ptr::null_mut())
}

/// `fmi2FreeInstance`: the instance and the states it saved; a pointer that
/// is not a live instance is ignored.
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        let states: Vec<usize> = {
            let mut reg = registry();
            let Some(i) = reg.components.iter().position(|x| *x == c as usize) else {
                return;
            };
            reg.components.swap_remove(i);
            let mine: Vec<usize> = reg
                .states
                .iter()
                .filter(|(_, o)| *o == c as usize)
                .map(|(s, _)| *s)
                .collect();
            reg.states.retain(|(_, o)| *o != c as usize);
            mine
        };
        for s in states {
            // SAFETY: a state fmi2GetFMUstate boxed, now unregistered.
            drop(unsafe { Box::from_raw(s as *mut SavedState) });
        }
        // SAFETY: a live component, now unregistered: freed once.
        drop(unsafe { Box::from_raw(c as *mut Component) });
    }));
}

/// `fmi2SetDebugLogging`: `loggingOn` for the categories given (all when
/// none are); an unknown category is an error.
///
/// # Safety
/// `categories` points to `nCategories` strings when `nCategories > 0`.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    loggingOn: fmi2Boolean,
    nCategories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    with(c, "fmi2SetDebugLogging", |comp| {
        // SAFETY: the caller's promise.
        let cats = unsafe { slice(categories, nCategories, "categories")? };
        for p in cats {
            // SAFETY: the caller's promise.
            let name = unsafe { text(*p, "a category") }.map_err(Refusal::Error)?;
            if !crate::description::LOG_CATEGORIES
                .iter()
                .any(|(n, _)| *n == name)
            {
                return Err(Refusal::Error(format!(
                    "unknown log category {name:?} (this FMU's: logStatusError, logStatusDiscard, logAll)"
                )));
            }
        }
        comp.logging = loggingOn != fmi2False;
        Ok(())
    })
}

/// `fmi2SetupExperiment`: `startTime` must be 0; the tolerance and stop
/// time are not used (steps go on past the scene's `t_end`).
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    _toleranceDefined: fmi2Boolean,
    _tolerance: fmi2Real,
    startTime: fmi2Real,
    _stopTimeDefined: fmi2Boolean,
    _stopTime: fmi2Real,
) -> fmi2Status {
    with(c, "fmi2SetupExperiment", |comp| {
        comp.inst.setup_experiment(startTime)
    })
}

/// `fmi2EnterInitializationMode`.
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    with(c, "fmi2EnterInitializationMode", |comp| {
        comp.inst.enter_initialization()
    })
}

/// `fmi2ExitInitializationMode`: the scene re-resolved with the parameters
/// set (when one changed), the inputs applied.
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    with(c, "fmi2ExitInitializationMode", |comp| {
        comp.inst.exit_initialization()
    })
}

/// `fmi2Terminate`.
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    with(c, "fmi2Terminate", |comp| comp.inst.terminate())
}

/// `fmi2Reset`: back to the instantiated state (t = 0, starts).
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    with(c, "fmi2Reset", |comp| comp.inst.reset())
}

/// `fmi2GetReal`: inputs (held values), outputs (at the current time),
/// parameters.
///
/// # Safety
/// `vr` and `value` point to `nvr` elements when `nvr > 0`.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    with(c, "fmi2GetReal", |comp| {
        // SAFETY: the caller's promise.
        let (vr, value) = unsafe { (slice(vr, nvr, "vr")?, slice_mut(value, nvr, "value")?) };
        comp.inst.get_real(vr, value)
    })
}

/// `fmi2SetReal`: inputs (held until set again) and, before the end of
/// initialization, parameters; a non-finite value is refused and nothing
/// is set.
///
/// # Safety
/// `vr` and `value` point to `nvr` elements when `nvr > 0`.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    with(c, "fmi2SetReal", |comp| {
        // SAFETY: the caller's promise.
        let (vr, value) = unsafe { (slice(vr, nvr, "vr")?, slice(value, nvr, "value")?) };
        comp.inst.set_real(vr, value)
    })
}

/// Refuse value references of a type the FMU has none of.
fn no_variables_of(comp: &Component, vr: &[u32], ty: &str) -> Result<(), Refusal> {
    match vr.first() {
        None => Ok(()),
        Some(r) => {
            let what = comp
                .inst
                .manifest
                .var(*r)
                .map(|v| format!("the Real variable `{}`", comp.inst.manifest.name(v)))
                .unwrap_or_else(|| "not a variable of this FMU".into());
            Err(Refusal::Error(format!(
                "value reference {r} is {what}: this FMU has no {ty} variables"
            )))
        }
    }
}

macro_rules! no_type {
    ($get:ident, $set:ident, $t:ty, $name:literal) => {
        /// Every value reference is an error: the FMU has no variables of this type.
        ///
        /// # Safety
        /// `vr` and `value` point to `nvr` elements when `nvr > 0`.
        #[no_mangle]
        pub unsafe extern "C" fn $get(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: *mut $t,
        ) -> fmi2Status {
            with(c, stringify!($get), |comp| {
                // SAFETY: the caller's promise.
                let (vr, _) = unsafe { (slice(vr, nvr, "vr")?, slice_mut(value, nvr, "value")?) };
                no_variables_of(comp, vr, $name)
            })
        }

        /// Every value reference is an error: the FMU has no variables of this type.
        ///
        /// # Safety
        /// `vr` and `value` point to `nvr` elements when `nvr > 0`.
        #[no_mangle]
        pub unsafe extern "C" fn $set(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: *const $t,
        ) -> fmi2Status {
            with(c, stringify!($set), |comp| {
                // SAFETY: the caller's promise.
                let (vr, _) = unsafe { (slice(vr, nvr, "vr")?, slice(value, nvr, "value")?) };
                no_variables_of(comp, vr, $name)
            })
        }
    };
}

no_type!(fmi2GetInteger, fmi2SetInteger, fmi2Integer, "Integer");
no_type!(fmi2GetBoolean, fmi2SetBoolean, fmi2Boolean, "Boolean");
no_type!(fmi2GetString, fmi2SetString, fmi2String, "String");

/// `fmi2GetFMUstate`: a copy of the simulation's state, the held inputs
/// and the parameters; a new state when `*FMUstate` is null, else the
/// state there (one this FMU returned) overwritten.
///
/// # Safety
/// `FMUstate` is null or points to a state pointer.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    with(c, "fmi2GetFMUstate", |comp| {
        if FMUstate.is_null() {
            return Err(Refusal::Error("FMUstate is a null pointer".into()));
        }
        let owner = c as usize;
        let saved = comp.inst.save()?;
        // SAFETY: non-null, the caller's promise.
        let old = unsafe { *FMUstate };
        if old.is_null() {
            let p = Box::into_raw(Box::new(saved));
            registry().states.push((p as usize, owner));
            // SAFETY: non-null.
            unsafe { *FMUstate = p as fmi2FMUstate };
        } else {
            if !registry().states.iter().any(|(s, _)| *s == old as usize) {
                return Err(Refusal::Error(
                    "*FMUstate is neither null nor a state of this FMU".into(),
                ));
            }
            // SAFETY: a live state of ours.
            unsafe { *(old as *mut SavedState) = saved };
        }
        Ok(())
    })
}

/// `fmi2SetFMUstate`: exact (the simulation continues bit for bit as it
/// did from there); a pointer that is not a live state is refused.
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    with(c, "fmi2SetFMUstate", |comp| {
        if !registry()
            .states
            .iter()
            .any(|(s, _)| *s == FMUstate as usize)
        {
            return Err(Refusal::Error(
                "FMUstate is not a live state of this FMU (null, freed or never returned by fmi2GetFMUstate)".into(),
            ));
        }
        // SAFETY: a live state of ours.
        let s = unsafe { &*(FMUstate as *const SavedState) };
        comp.inst.restore(s)
    })
}

/// `fmi2FreeFMUstate`: frees the state and sets `*FMUstate` to null (a null
/// state is nothing to free).
///
/// # Safety
/// `FMUstate` is null or points to a state pointer.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    with(c, "fmi2FreeFMUstate", |_| {
        if FMUstate.is_null() {
            return Err(Refusal::Error("FMUstate is a null pointer".into()));
        }
        // SAFETY: non-null, the caller's promise.
        let s = unsafe { *FMUstate };
        if s.is_null() {
            return Ok(());
        }
        {
            let mut reg = registry();
            let Some(i) = reg.states.iter().position(|(x, _)| *x == s as usize) else {
                return Err(Refusal::Error(
                    "*FMUstate is not a live state of this FMU".into(),
                ));
            };
            reg.states.swap_remove(i);
        }
        // SAFETY: a state of ours, now unregistered: freed once.
        drop(unsafe { Box::from_raw(s as *mut SavedState) });
        // SAFETY: non-null.
        unsafe { *FMUstate = std::ptr::null_mut() };
        Ok(())
    })
}

const NO_SERIALIZATION: &str =
    "serialized states are not supported (canSerializeFMUstate = false); fmi2GetFMUstate / fmi2SetFMUstate are";

/// Not supported (`canSerializeFMUstate = false`): `fmi2Error`.
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    _FMUstate: fmi2FMUstate,
    _size: *mut usize,
) -> fmi2Status {
    with(c, "fmi2SerializedFMUstateSize", |_| {
        Err(Refusal::Error(NO_SERIALIZATION.into()))
    })
}

/// Not supported (`canSerializeFMUstate = false`): `fmi2Error`.
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    _FMUstate: fmi2FMUstate,
    _serializedState: *mut fmi2Byte,
    _size: usize,
) -> fmi2Status {
    with(c, "fmi2SerializeFMUstate", |_| {
        Err(Refusal::Error(NO_SERIALIZATION.into()))
    })
}

/// Not supported (`canSerializeFMUstate = false`): `fmi2Error`.
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    _serializedState: *const fmi2Byte,
    _size: usize,
    _FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    with(c, "fmi2DeSerializeFMUstate", |_| {
        Err(Refusal::Error(NO_SERIALIZATION.into()))
    })
}

/// Not supported (`providesDirectionalDerivative = false`): `fmi2Error`.
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    _vUnknown_ref: *const fmi2ValueReference,
    _nUnknown: usize,
    _vKnown_ref: *const fmi2ValueReference,
    _nKnown: usize,
    _dvKnown: *const fmi2Real,
    _dvUnknown: *mut fmi2Real,
) -> fmi2Status {
    with(c, "fmi2GetDirectionalDerivative", |_| {
        Err(Refusal::Error(
            "directional derivatives are not provided (providesDirectionalDerivative = false); `ffr linearize` gives the scene's linear model".into(),
        ))
    })
}

/// Not supported (`canInterpolateInputs = false`): `fmi2Error`.
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *const fmi2Real,
) -> fmi2Status {
    with(c, "fmi2SetRealInputDerivatives", |_| {
        Err(Refusal::Error(
            "input derivatives are not used (canInterpolateInputs = false): inputs are held over a communication step".into(),
        ))
    })
}

/// Not supported (`maxOutputDerivativeOrder = 0`): `fmi2Error`.
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *mut fmi2Real,
) -> fmi2Status {
    with(c, "fmi2GetRealOutputDerivatives", |_| {
        Err(Refusal::Error(
            "output derivatives are not provided (maxOutputDerivativeOrder = 0)".into(),
        ))
    })
}

/// `fmi2DoStep`: `communicationStepSize / dt` whole scene steps from
/// `currentCommunicationPoint` (which must be the FMU's time), the inputs
/// held; not a whole number of steps (to 1e-9 relative), zero, negative or
/// non-finite: `fmi2Error`, nothing stepped. A failed scene step:
/// `fmi2Discard` with the run's message; the FMU stays at the last step
/// that succeeded (`fmi2LastSuccessfulTime`) and refuses further steps
/// until a state is set or it is reset.
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    with(c, "fmi2DoStep", |comp| {
        comp.inst
            .do_step(currentCommunicationPoint, communicationStepSize)
    })
}

/// `fmi2CancelStep`: no step is ever pending (steps are synchronous): `fmi2Error`.
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    with(c, "fmi2CancelStep", |_| {
        Err(Refusal::Error(
            "no step is pending (fmi2DoStep never returns fmi2Pending)".into(),
        ))
    })
}

/// Write `v` through a status pointer.
fn put<T>(p: *mut T, v: T) -> Result<(), Refusal> {
    if p.is_null() {
        return Err(Refusal::Error("value is a null pointer".into()));
    }
    // SAFETY: non-null; the importer's pointer to a `T`.
    unsafe { *p = v };
    Ok(())
}

/// `fmi2GetStatus(fmi2DoStepStatus)`: `fmi2OK`, or `fmi2Discard` after a
/// failed step (never pending); other kinds are errors.
///
/// # Safety
/// `value` is null or points to an `fmi2Status`.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Status,
) -> fmi2Status {
    with(c, "fmi2GetStatus", |comp| match s {
        fmi2DoStepStatus => put(
            value,
            if comp.inst.sim.failed().is_some() {
                fmi2Discard
            } else {
                fmi2OK
            },
        ),
        _ => Err(Refusal::Error(format!(
            "status kind {s} has no fmi2Status value here (fmi2DoStepStatus = 0 has)"
        ))),
    })
}

/// `fmi2GetRealStatus(fmi2LastSuccessfulTime)`: the time of the last step
/// that succeeded; other kinds are errors.
///
/// # Safety
/// `value` is null or points to an `fmi2Real`.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    with(c, "fmi2GetRealStatus", |comp| match s {
        fmi2LastSuccessfulTime => put(value, comp.inst.last_successful_time),
        _ => Err(Refusal::Error(format!(
            "status kind {s} has no real value (fmi2LastSuccessfulTime = 2 has)"
        ))),
    })
}

/// No integer status: `fmi2Error`.
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    _value: *mut fmi2Integer,
) -> fmi2Status {
    with(c, "fmi2GetIntegerStatus", |_| {
        Err(Refusal::Error(format!(
            "status kind {s} has no integer value"
        )))
    })
}

/// `fmi2GetBooleanStatus(fmi2Terminated)`: true after a failed step (the
/// simulation cannot go on without a saved state or a reset); other kinds
/// are errors.
///
/// # Safety
/// `value` is null or points to an `fmi2Boolean`.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    with(c, "fmi2GetBooleanStatus", |comp| match s {
        fmi2Terminated => put(
            value,
            if comp.inst.sim.failed().is_some() {
                fmi2True
            } else {
                fmi2False
            },
        ),
        _ => Err(Refusal::Error(format!(
            "status kind {s} has no boolean value (fmi2Terminated = 3 has)"
        ))),
    })
}

/// No string status (no step is ever pending): `fmi2Error`.
///
/// # Safety
/// `c` is null or a pointer `fmi2Instantiate` returned.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    _value: *mut fmi2String,
) -> fmi2Status {
    with(c, "fmi2GetStringStatus", |_| {
        Err(Refusal::Error(format!(
            "status kind {s} has no string value (no step is ever pending)"
        )))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pointer_that_is_not_an_instance_is_refused_untouched() {
        let mut x = 0u64;
        let bogus = (&mut x as *mut u64).cast::<c_void>();
        // SAFETY: the functions check the component before using it.
        unsafe {
            assert_eq!(fmi2DoStep(bogus, 0.0, 1.0, 0), fmi2Error);
            assert_eq!(fmi2Terminate(std::ptr::null_mut()), fmi2Error);
            assert_eq!(fmi2Reset(bogus), fmi2Error);
            fmi2FreeInstance(bogus);
        }
        assert_eq!(x, 0);
    }

    #[test]
    fn version_and_platform_are_the_standards() {
        // SAFETY: static NUL-terminated strings.
        unsafe {
            assert_eq!(CStr::from_ptr(fmi2GetVersion()).to_str(), Ok("2.0"));
            assert_eq!(
                CStr::from_ptr(fmi2GetTypesPlatform()).to_str(),
                Ok("default")
            );
        }
    }
}
