//! `fmi2DoStep` of one scene step through the exported C functions against
//! the library's own `Simulation::step`, side by side in one run (issue 37's
//! goal: ≤ 1.05×).
//!
//! First, for two scenes (the two-link flexible arm, a typical step, and
//! the pendulum, the cheapest shipped scene, where a fixed overhead weighs
//! most), interleaved pairs: `N` steps from the same saved state at t = 0
//! by each route (states restored outside the timed loops), the order
//! alternating, timed by the thread's CPU clock; printed are the minimum
//! per step of each route, the ratio of the minima and the median of the
//! pairs' ratios. Then criterion's own measurement of both routes on the
//! arm (each sample restarts from t = 0).
//!
//! `cargo bench -p ffr-fmu -p ffr-cli --bench do_step` (with ffr-cli: the
//! features of the release build, nothing recompiled)

use criterion::{criterion_group, criterion_main, Criterion};
use ffr_fmu::ffi::*;
use std::ffi::CString;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// CPU time of this thread (s).
fn cpu() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: a valid, writable timespec; a clock id the platform defines.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0);
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// A scene both ways: its simulation with the state at t = 0, and an FMU
/// instance of it (resources in a temporary directory) with its state at
/// t = 0.
struct Both {
    sim: ffr::scene::Simulation,
    start: ffr::scene::SimulationState,
    comp: fmi2Component,
    state: fmi2FMUstate,
    dt: f64,
    dir: PathBuf,
    _strings: [CString; 3],
    _callbacks: Box<fmi2CallbackFunctions>,
}

impl Both {
    fn new(scene_file: &str) -> Both {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let scene_path = root.join("scenes").join(scene_file);
        let dir =
            std::env::temp_dir().join(format!("ffr-fmu-bench-{scene_file}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::copy(&scene_path, dir.join(scene_file)).unwrap();
        let scene = Arc::new(ffr::scene::load(&scene_path).unwrap());
        let sim = ffr::scene::Simulation::new(scene.clone()).unwrap();
        let m = ffr_fmu::description::Manifest {
            guid: "{bench}".into(),
            model_identifier: "bench".into(),
            model_name: "bench".into(),
            description: None,
            scene: scene_file.into(),
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
        std::fs::write(dir.join(ffr_fmu::description::MANIFEST), m.to_json()).unwrap();
        let strings = [
            CString::new("bench").unwrap(),
            CString::new("{bench}").unwrap(),
            CString::new(format!("file://{}", dir.display())).unwrap(),
        ];
        let callbacks = Box::new(fmi2CallbackFunctions {
            logger: None,
            allocateMemory: None,
            freeMemory: None,
            stepFinished: None,
            componentEnvironment: std::ptr::null_mut(),
        });
        let mut state: fmi2FMUstate = std::ptr::null_mut();
        // SAFETY: valid strings and callbacks that outlive the instance.
        let comp = unsafe {
            let c = fmi2Instantiate(
                strings[0].as_ptr(),
                fmi2CoSimulation,
                strings[1].as_ptr(),
                strings[2].as_ptr(),
                &*callbacks,
                fmi2False,
                fmi2False,
            );
            assert!(!c.is_null());
            assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), fmi2OK);
            assert_eq!(fmi2EnterInitializationMode(c), fmi2OK);
            assert_eq!(fmi2ExitInitializationMode(c), fmi2OK);
            assert_eq!(fmi2GetFMUstate(c, &mut state), fmi2OK);
            c
        };
        Both {
            start: sim.save_state(),
            sim,
            comp,
            state,
            dt: scene.dt,
            dir,
            _strings: strings,
            _callbacks: callbacks,
        }
    }

    /// `n` steps of the simulation from t = 0.
    fn by_sim(&mut self, n: u64) -> Duration {
        self.sim.restore_state(&self.start).unwrap();
        let t0 = Instant::now();
        for _ in 0..n {
            self.sim.step().unwrap();
        }
        t0.elapsed()
    }

    /// `n` calls of `fmi2DoStep(k dt, dt)` from t = 0.
    fn by_fmi(&mut self, n: u64) -> Duration {
        // SAFETY: a live component and state.
        assert_eq!(unsafe { fmi2SetFMUstate(self.comp, self.state) }, fmi2OK);
        let t0 = Instant::now();
        for k in 0..n {
            // SAFETY: a live component.
            let s = unsafe { fmi2DoStep(self.comp, k as f64 * self.dt, self.dt, fmi2True) };
            debug_assert_eq!(s, fmi2OK);
        }
        t0.elapsed()
    }

    /// CPU seconds per step of `n` steps by `route`.
    fn cpu_per_step(&mut self, n: u64, fmi: bool) -> f64 {
        // Restore outside the timed part.
        if fmi {
            // SAFETY: a live component and state.
            assert_eq!(unsafe { fmi2SetFMUstate(self.comp, self.state) }, fmi2OK);
        } else {
            self.sim.restore_state(&self.start).unwrap();
        }
        let c0 = cpu();
        if fmi {
            for k in 0..n {
                // SAFETY: a live component.
                let s = unsafe { fmi2DoStep(self.comp, k as f64 * self.dt, self.dt, fmi2True) };
                assert_eq!(s, fmi2OK);
            }
        } else {
            for _ in 0..n {
                self.sim.step().unwrap();
            }
        }
        (cpu() - c0) / n as f64
    }
}

impl Drop for Both {
    fn drop(&mut self) {
        // SAFETY: a live component and state, freed once.
        unsafe {
            fmi2FreeFMUstate(self.comp, &mut self.state);
            fmi2FreeInstance(self.comp);
        }
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// The interleaved comparison, printed.
fn interleaved(scene: &str, n: u64, pairs: usize) {
    let mut b = Both::new(scene);
    let (mut s, mut f) = (Vec::new(), Vec::new());
    for p in 0..pairs {
        if p % 2 == 0 {
            s.push(b.cpu_per_step(n, false));
            f.push(b.cpu_per_step(n, true));
        } else {
            f.push(b.cpu_per_step(n, true));
            s.push(b.cpu_per_step(n, false));
        }
    }
    let mut ratios: Vec<f64> = f.iter().zip(&s).map(|(f, s)| f / s).collect();
    ratios.sort_by(f64::total_cmp);
    let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    println!(
        "{scene}: {pairs} interleaved pairs of {n} steps from t = 0 (thread CPU time): Simulation::step {:.3} µs, fmi2DoStep {:.3} µs per step (minima); ratio of minima {:.4}, median ratio of pairs {:.4}",
        min(&s) * 1e6,
        min(&f) * 1e6,
        min(&f) / min(&s),
        ratios[pairs / 2]
    );
}

fn bench(c: &mut Criterion) {
    interleaved("two_link_arm.toml", 1000, 31);
    interleaved("pendulum.toml", 1000, 31);
    let mut b = Both::new("two_link_arm.toml");
    let mut g = c.benchmark_group("one scene step (two_link_arm, dt = 1e-3)");
    g.bench_function("Simulation::step", |bb| bb.iter_custom(|n| b.by_sim(n)));
    g.bench_function("fmi2DoStep (through the C functions)", |bb| {
        bb.iter_custom(|n| b.by_fmi(n))
    });
    g.finish();
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
