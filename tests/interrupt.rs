//! The long calls' `…_interruptible` forms (time runs, the static solver,
//! linearization, Campbell diagrams) stop with `Error::Interrupted` when
//! their `Interrupt` asks, at the poll it asks, and leave the scene as it
//! was: run again, it gives the numbers of a run never interrupted.

use ffr::runtime::{Error, Interrupt};
use ffr::scene::linear::{self, At};
use ffr::scene::{DefaultKernels, RunOptions, SceneText};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

fn text(name: &str) -> SceneText {
    SceneText::read(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes")
            .join(name),
    )
    .unwrap()
}

fn interrupted<T: std::fmt::Debug>(r: ffr::Result<T>) -> bool {
    matches!(r, Err(ffr::Error::Runtime(Error::Interrupted)))
}

/// A check that asks to stop at its `n`-th call, and its count of calls.
struct StopAt {
    n: usize,
    calls: AtomicUsize,
}

impl StopAt {
    fn new(n: usize) -> Self {
        StopAt {
            n,
            calls: AtomicUsize::new(0),
        }
    }
    fn check(&self) -> bool {
        self.calls.fetch_add(1, Ordering::Relaxed) + 1 >= self.n
    }
    fn calls(&self) -> usize {
        self.calls.load(Ordering::Relaxed)
    }
}

#[test]
fn a_run_stops_at_the_step_it_is_asked_to_and_runs_again_unchanged() {
    let mut t = text("spin_up.toml");
    t.set("t_end", 0.5.into()).unwrap();
    let scene = t.load().unwrap();
    let stop = StopAt::new(10);
    let check = || stop.check();
    let r = ffr::scene::run_interruptible(&scene, &RunOptions::default(), Interrupt::new(&check));
    assert!(interrupted(r), "not interrupted");
    // Polled once per sample (the initial state, then each step): the
    // tenth poll was after step 9, and there were no more.
    assert_eq!(stop.calls(), 10);
    let again =
        ffr::scene::run_interruptible(&scene, &RunOptions::default(), Interrupt::NEVER).unwrap();
    let plain = ffr::scene::run(&scene).unwrap();
    assert_eq!(again.steps, 50);
    assert_eq!(again.columns, plain.columns);
    // A check that never asks is polled at every sample.
    let never = StopAt::new(usize::MAX);
    let check = || never.check();
    let r = ffr::scene::run_interruptible(&scene, &RunOptions::default(), Interrupt::new(&check))
        .unwrap();
    assert_eq!(never.calls(), r.t.len());
    assert_eq!(r.columns, plain.columns);
}

#[test]
fn the_static_solver_stops_at_the_newton_iteration_it_is_asked_to() {
    let mut t = text("boom_payload.toml");
    t.set("bodies.boom.elements", 2.into()).unwrap();
    let scene = t.load().unwrap();
    let options = ffr::scene::statics::StaticOptions { steps: Some(20) };
    let full = ffr::scene::statics::solve(&scene, &options).unwrap();
    assert!(full.iterations > 20, "{}", full.iterations);
    let stop = StopAt::new(7);
    let check = || stop.check();
    let r = ffr::scene::statics::solve_interruptible(&scene, &options, Interrupt::new(&check));
    assert!(interrupted(r), "not interrupted");
    assert_eq!(stop.calls(), 7);
    let again = ffr::scene::statics::solve(&scene, &options).unwrap();
    assert_eq!(again.values, full.values);
}

#[test]
fn linearize_and_campbell_stop_when_asked() {
    let mut t = text("spin_up.toml");
    t.set("bodies.beam.elements", 2.into()).unwrap();
    let spec = t.spec().unwrap();
    // The run to the operating time: stopped at its fifth sample.
    let stop = StopAt::new(5);
    let check = || stop.check();
    let r = linear::linearize_scene_interruptible(
        &spec,
        &DefaultKernels,
        At::Time(1.0),
        None,
        None,
        Interrupt::new(&check),
    );
    assert!(interrupted(r), "not interrupted");
    assert_eq!(stop.calls(), 5);
    // At the third speed of three: the first two were done.
    let stop = StopAt::new(usize::MAX);
    let check = || stop.check();
    let mut speeds_done = 0;
    linear::campbell_interruptible(
        &spec,
        &DefaultKernels,
        &[0.0, 1.0, 2.0],
        None,
        2,
        &mut |_, _, _, _| {
            speeds_done += 1;
            Ok(())
        },
        Interrupt::new(&check),
    )
    .unwrap();
    let per_diagram = stop.calls();
    assert_eq!(speeds_done, 3);
    let stop = StopAt::new(per_diagram);
    let check = || stop.check();
    let mut speeds_done = 0;
    let r = linear::campbell_interruptible(
        &spec,
        &DefaultKernels,
        &[0.0, 1.0, 2.0],
        None,
        2,
        &mut |_, _, _, _| {
            speeds_done += 1;
            Ok(())
        },
        Interrupt::new(&check),
    );
    // The last poll is the last Newton iteration of the last speed.
    assert!(interrupted(r), "not interrupted");
    assert_eq!(speeds_done, 2);
    let plain = linear::campbell(&spec, &DefaultKernels, &[0.0, 1.0, 2.0], None, 2).unwrap();
    assert_eq!(plain.modes.len(), 3);
}
