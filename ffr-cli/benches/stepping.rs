//! The stepping API's cost: 100 steps of the default spin-up
//! (`scenes/spin_up.toml`, from t = 1 s, inside the spin-up ramp) through
//! `ffr::scene::Simulation::step` (which also evaluates the outputs and
//! the inputs' profiles) against the runtime's own step
//! (`ffr::runtime::Stepper::step`, the loop `System::simulate` runs),
//! side by side; each sample starts from the same saved state (the
//! restore is outside the timing).
//!
//! `cargo bench -p ffr-cli --bench stepping`

use criterion::{criterion_group, criterion_main, Criterion};
use ffr::runtime::Stepper;
use ffr::scene::Simulation;
use std::sync::Arc;
use std::time::{Duration, Instant};

const STEPS: usize = 100;

fn stepping(c: &mut Criterion) {
    let dir = ffr::scene::load::builtin_dir();
    let scene = Arc::new(ffr::scene::load(&dir.join("spin_up.toml")).expect("built-in scene"));
    let mut group = c.benchmark_group("spin_up 100 steps");
    group.sample_size(30);

    let mut sim = Simulation::new(scene.clone()).expect("initial state");
    sim.advance_to(1.0).expect("runs");
    let start = sim.save_state();
    group.bench_function("Simulation::step", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                sim.restore_state(&start).expect("same scene");
                let t = Instant::now();
                for _ in 0..STEPS {
                    sim.step().expect("steps");
                }
                total += t.elapsed();
                std::hint::black_box(sim.outputs());
            }
            total
        })
    });

    let mut stepper =
        Stepper::new(&scene.system, scene.t_end, &scene.integrator).expect("initial state");
    for _ in 0..100 {
        stepper.step(scene.dt).expect("runs");
    }
    let start = stepper.save();
    group.bench_function("runtime Stepper::step", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                stepper.restore(&start).expect("same system");
                let t = Instant::now();
                for _ in 0..STEPS {
                    stepper.step(scene.dt).expect("steps");
                }
                total += t.elapsed();
                std::hint::black_box(stepper.state());
            }
            total
        })
    });
    group.finish();
}

criterion_group!(benches, stepping);
criterion_main!(benches);
