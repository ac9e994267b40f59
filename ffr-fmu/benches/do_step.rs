//! `fmi2DoStep` of one scene step through the exported C functions against
//! the library's own `Simulation::step`, side by side in one run (issue 37's
//! goal: ≤ 1.05×). Each measurement starts both from the same saved state
//! at t = 0 (restored outside the timed loop), so both time the same steps.
//!
//! `cargo bench -p ffr-fmu --bench do_step`

use criterion::{criterion_group, criterion_main, Criterion};
use ffr_fmu::ffi::*;
use std::ffi::CString;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A resources directory for `scene` (the scene file and the manifest).
fn resources(scene: &Path, tag: &str) -> (PathBuf, String) {
    let dir = std::env::temp_dir().join(format!("ffr-fmu-bench-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let name = scene.file_name().unwrap().to_string_lossy().into_owned();
    std::fs::copy(scene, dir.join(&name)).unwrap();
    let loaded = Arc::new(ffr::scene::load(scene).unwrap());
    let sim = ffr::scene::Simulation::new(loaded.clone()).unwrap();
    let m = ffr_fmu::description::Manifest {
        guid: "{bench}".into(),
        model_identifier: "bench".into(),
        model_name: "bench".into(),
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
            .map(|o| (o.name.clone(), String::new()))
            .collect(),
        parameters: Vec::new(),
        dt: loaded.dt,
        t_end: loaded.t_end,
    };
    std::fs::write(dir.join(ffr_fmu::description::MANIFEST), m.to_json()).unwrap();
    let uri = format!("file://{}", dir.display());
    (dir, uri)
}

fn bench(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let scene_path = root.join("scenes/two_link_arm.toml");
    let (dir, uri) = resources(&scene_path, "arm");
    let scene = Arc::new(ffr::scene::load(&scene_path).unwrap());
    let dt = scene.dt;

    let mut sim = ffr::scene::Simulation::new(scene).unwrap();
    let start = sim.save_state();

    let name = CString::new("bench").unwrap();
    let guid = CString::new("{bench}").unwrap();
    let curi = CString::new(uri).unwrap();
    let callbacks = fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    };
    // SAFETY: valid strings and callbacks; the component is used as FMI says.
    let comp = unsafe {
        let c = fmi2Instantiate(
            name.as_ptr(),
            fmi2CoSimulation,
            guid.as_ptr(),
            curi.as_ptr(),
            &callbacks,
            fmi2False,
            fmi2False,
        );
        assert!(!c.is_null());
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), fmi2OK);
        assert_eq!(fmi2EnterInitializationMode(c), fmi2OK);
        assert_eq!(fmi2ExitInitializationMode(c), fmi2OK);
        c
    };
    let mut state: fmi2FMUstate = std::ptr::null_mut();
    // SAFETY: a live component.
    assert_eq!(unsafe { fmi2GetFMUstate(comp, &mut state) }, fmi2OK);

    let mut g = c.benchmark_group("one scene step (two_link_arm, dt = 1e-3)");
    g.bench_function("Simulation::step", |b| {
        b.iter_custom(|iters| {
            sim.restore_state(&start).unwrap();
            let t0 = Instant::now();
            for _ in 0..iters {
                sim.step().unwrap();
            }
            t0.elapsed()
        })
    });
    g.bench_function("fmi2DoStep (through the C functions)", |b| {
        b.iter_custom(|iters| {
            // SAFETY: a live component and state.
            assert_eq!(unsafe { fmi2SetFMUstate(comp, state) }, fmi2OK);
            let mut t = 0.0;
            let t0 = Instant::now();
            for k in 0..iters {
                // SAFETY: a live component.
                let s = unsafe { fmi2DoStep(comp, t, dt, fmi2True) };
                debug_assert_eq!(s, fmi2OK);
                t = (k + 1) as f64 * dt;
            }
            t0.elapsed()
        })
    });
    g.finish();
    // SAFETY: a live component and state, freed once.
    unsafe {
        assert_eq!(fmi2FreeFMUstate(comp, &mut state), fmi2OK);
        fmi2FreeInstance(comp);
    }
    let _ = std::fs::remove_dir_all(dir);
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4));
    targets = bench
}
criterion_main!(benches);
