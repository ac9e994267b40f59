//! No heap allocation in `fmi2DoStep`, `fmi2SetReal` and `fmi2GetReal` on
//! the success path after a warm-up (a counting global allocator), with
//! inputs set before every step: the FMU adds no allocation to the
//! library's allocation-free step.

use ffr_fmu::ffi::*;
use std::alloc::{GlobalAlloc, Layout, System as Sys};
use std::cell::Cell;
use std::ffi::CString;
use std::path::Path;
use std::sync::Arc;

struct Counting;

thread_local! {
    static COUNT: Cell<usize> = const { Cell::new(0) };
}

// SAFETY: forwards to the system allocator, counting calls.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        COUNT.with(|c| c.set(c.get() + 1));
        // SAFETY: the caller's layout.
        unsafe { Sys.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        // SAFETY: a pointer of this allocator.
        unsafe { Sys.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        COUNT.with(|c| c.set(c.get() + 1));
        // SAFETY: a pointer of this allocator.
        unsafe { Sys.realloc(p, l, n) }
    }
}

#[global_allocator]
static A: Counting = Counting;

fn count() -> usize {
    COUNT.with(Cell::get)
}

#[test]
fn do_step_and_values_allocate_nothing() {
    let scene_path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/two_link_arm_inputs.toml");
    let dir = std::env::temp_dir().join(format!("ffr-fmu-alloc-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(&scene_path, dir.join("arm.toml")).unwrap();
    let scene = Arc::new(ffr::scene::load(&scene_path).unwrap());
    let sim = ffr::scene::Simulation::new(scene.clone()).unwrap();
    let m = ffr_fmu::description::Manifest {
        guid: "{alloc}".into(),
        model_identifier: "arm".into(),
        model_name: "arm".into(),
        description: None,
        scene: "arm.toml".into(),
        inputs: sim
            .input_names()
            .iter()
            .map(|n| (n.to_string(), sim.input(n).unwrap()))
            .collect(),
        outputs: scene
            .outputs
            .iter()
            .map(|o| (o.name.clone(), String::new()))
            .collect(),
        parameters: Vec::new(),
        dt: scene.dt,
        t_end: scene.t_end,
    };
    assert_eq!(m.inputs.len(), 2);
    std::fs::write(dir.join(ffr_fmu::description::MANIFEST), m.to_json()).unwrap();
    let name = CString::new("alloc").unwrap();
    let guid = CString::new("{alloc}").unwrap();
    let uri = CString::new(format!("file://{}", dir.display())).unwrap();
    let cb = fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    };
    let dt = scene.dt;
    let outs: Vec<u32> = (2..2 + m.outputs.len() as u32).collect();
    let mut values = vec![0.0; outs.len()];
    // SAFETY: valid strings and callbacks; the component as FMI says.
    unsafe {
        let c = fmi2Instantiate(
            name.as_ptr(),
            fmi2CoSimulation,
            guid.as_ptr(),
            uri.as_ptr(),
            &cb,
            0,
            0,
        );
        assert!(!c.is_null());
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), fmi2OK);
        assert_eq!(fmi2EnterInitializationMode(c), fmi2OK);
        assert_eq!(fmi2ExitInitializationMode(c), fmi2OK);
        let call = |k: u32, n: u32| {
            let u = [0.01 * f64::from(k % 3), -0.05 * f64::from(k % 2)];
            assert_eq!(fmi2SetReal(c, [0u32, 1].as_ptr(), 2, u.as_ptr()), fmi2OK);
            assert_eq!(
                fmi2DoStep(c, f64::from(k) * dt, f64::from(n) * dt, 1),
                fmi2OK
            );
        };
        for k in 0..20 {
            call(k, 1);
        }
        let before = count();
        for k in 20..120 {
            call(k, 1);
            assert_eq!(
                fmi2GetReal(c, outs.as_ptr(), outs.len(), values.as_mut_ptr()),
                fmi2OK
            );
        }
        let after = count();
        assert_eq!(after - before, 0, "allocations in 100 calls");
        assert!(values.iter().all(|v| v.is_finite()));
        fmi2FreeInstance(c);
    }
    let _ = std::fs::remove_dir_all(dir);
}
