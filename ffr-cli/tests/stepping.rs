//! The stepping API (`ffr::scene::Simulation`): stepping a scene gives the
//! bits of `ffr::scene::run`, a saved state continues bit for bit, a failed
//! step is reported as `ffr run` reports it and sticks until a restore, and
//! hostile calls are refused with clear errors and no change.

use ffr::scene::{self, DefaultKernels, Scene, Simulation};
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes")
}

fn load_text(text: &str, name: &str) -> Scene {
    scene::from_str(text, name, &scenes(), &DefaultKernels).unwrap()
}

fn load(name: &str) -> Scene {
    scene::load(&scenes().join(name)).unwrap()
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// Every shipped scene, shortened to at most `max_steps` whole steps (the
/// same scene for the run and the simulation).
fn shipped(max_steps: usize) -> Vec<(String, Scene)> {
    let mut out = Vec::new();
    let mut names: Vec<String> = std::fs::read_dir(scenes())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    names.sort();
    for name in names {
        let mut s = load(&name);
        let cap = s.dt * max_steps as f64;
        if s.t_end > cap {
            s.t_end = cap;
        }
        out.push((name, s));
    }
    assert!(out.len() >= 12, "{} scenes", out.len());
    out
}

/// Stepping a scene with `Simulation::step` gives `run`'s samples bit for
/// bit (every output column, the times and the final state), on every
/// shipped scene (each shortened to 300 steps for the test's time).
#[test]
fn stepping_equals_run_on_every_shipped_scene() {
    for (name, s) in shipped(300) {
        let r = scene::run(&s).unwrap();
        assert!(r.failed.is_none(), "{name}: {:?}", r.failed);
        let last = r.last.clone().unwrap();
        let mut sim = Simulation::new(Arc::new(s)).unwrap();
        assert_eq!(sim.output_names(), r.names, "{name}");
        for k in 0..r.t.len() {
            if k > 0 {
                sim.step().unwrap();
            }
            assert_eq!(sim.time().to_bits(), r.t[k].to_bits(), "{name}: t at {k}");
            for (c, col) in r.columns.iter().enumerate() {
                assert_eq!(
                    sim.outputs()[c].to_bits(),
                    col[k].to_bits(),
                    "{name}: column {} at sample {k}: {} vs {}",
                    r.names[c],
                    sim.outputs()[c],
                    col[k]
                );
            }
        }
        assert_eq!(sim.steps(), r.steps, "{name}");
        assert_eq!(bits(&sim.state().q), bits(&last.q), "{name}");
        assert_eq!(bits(&sim.state().v), bits(&last.v), "{name}");
        assert_eq!(bits(&sim.state().lambda), bits(&last.lambda), "{name}");
        assert_eq!(sim.counters().newton_iterations, r.newton_iterations);
        assert_eq!(sim.counters().jacobians, r.jacobians);
    }
}

/// The first step at which two traces differ, if any.
fn first_difference(a: &[Vec<u64>], b: &[Vec<u64>]) -> Option<usize> {
    (0..a.len().max(b.len())).find(|&k| a.get(k) != b.get(k))
}

/// `m` steps: the outputs and the full state after each, as bits.
fn trace(sim: &mut Simulation, m: usize) -> Vec<Vec<u64>> {
    (0..m)
        .map(|_| {
            sim.step().unwrap();
            let s = sim.state();
            let mut b = vec![sim.time().to_bits()];
            for x in [sim.outputs(), &s.q, &s.v, &s.a, &s.lambda] {
                b.extend(bits(x));
            }
            b
        })
        .collect()
}

/// Run `k` steps, save, run `m` more, restore, run `m` more: the same bits
/// (outputs and state) both times; a second simulation of the same scene,
/// restored from the saved state, continues with the same bits too. On the
/// spin-up (iteration matrix kept over many steps), the flexible two-link
/// arm (angle unwrapping, work and dissipation integrals, monitor) and the
/// free-floating body (Euler parameters).
#[test]
fn save_and_restore_continue_bit_for_bit() {
    for (name, k, m) in [
        ("spin_up.toml", 40, 70),
        ("two_link_arm.toml", 150, 120),
        ("free_floating.toml", 30, 50),
        ("slider_crank.toml", 100, 80),
    ] {
        let s = Arc::new(load(name));
        let mut sim = Simulation::new(s.clone()).unwrap();
        sim.advance_to(k as f64 * s.dt).unwrap();
        assert_eq!(sim.steps(), k);
        let saved = sim.save_state();
        let first = trace(&mut sim, m);
        let counters = sim.counters().clone();
        sim.restore_state(&saved).unwrap();
        assert_eq!(sim.steps(), k, "{name}");
        let second = trace(&mut sim, m);
        assert_eq!(first_difference(&first, &second), None, "{name}: restored");
        assert_eq!(sim.counters(), &counters, "{name}: counters");
        // Into another simulation of the same scene, fresh at t = 0.
        let mut other = Simulation::new(s.clone()).unwrap();
        other.restore_state(&saved).unwrap();
        assert_eq!(other.time().to_bits(), saved.time().to_bits());
        let third = trace(&mut other, m);
        assert_eq!(
            first_difference(&first, &third),
            None,
            "{name}: restored into a second simulation"
        );
        // The uninterrupted simulation from t = 0 gives the same bits too.
        // (Leaving the factored iteration matrix out of the saved state
        // makes the spin-up's restored trace differ at its first step: the
        // matrix is kept over steps and is part of what the next step
        // depends on.)
        let mut straight = Simulation::new(s).unwrap();
        straight.advance_to(k as f64 * straight.scene().dt).unwrap();
        let fourth = trace(&mut straight, m);
        assert_eq!(first_difference(&first, &fourth), None, "{name}: straight");
    }
}

/// A state of another scene is refused and nothing changes.
#[test]
fn a_state_of_another_scene_is_refused() {
    let mut a = Simulation::new(Arc::new(load("pendulum.toml"))).unwrap();
    let b = Simulation::new(Arc::new(load("spin_up.toml"))).unwrap();
    a.step().unwrap();
    let t = a.time();
    let e = a.restore_state(&b.save_state()).unwrap_err().to_string();
    assert!(e.contains("the saved state is of another scene"), "{e}");
    assert_eq!(a.time(), t);
    a.step().unwrap();
}

/// A failed step returns `ffr run`'s message, and every later step returns
/// it again; a restore clears it and the simulation goes on (failing at
/// the same step again, with the same message).
#[test]
fn a_failed_step_sticks_until_a_restore() {
    let text = std::fs::read_to_string(scenes().join("two_link_arm.toml")).unwrap();
    assert!(text.contains("\ninertia = 0.01\n"));
    let text = text.replacen("\ninertia = 0.01\n", "\ninertia = 1e-300\n", 1);
    let s = load_text(&text, "arm.toml");
    let r = scene::run(&s).unwrap();
    let reason = r.failed.clone().expect("the run fails");
    let expected = format!(
        "the run stopped at t = {:.6} s: {reason}",
        r.t.last().unwrap()
    );
    let mut sim = Simulation::new(Arc::new(s)).unwrap();
    let saved = sim.save_state();
    let mut err = None;
    for _ in 0..100_000 {
        if let Err(e) = sim.step() {
            err = Some(e.to_string());
            break;
        }
    }
    let err = err.expect("a step fails");
    assert_eq!(err, expected);
    assert_eq!(sim.failed(), Some(expected.as_str()));
    assert_eq!(sim.steps(), r.steps, "steps before the failure");
    assert_eq!(sim.step().unwrap_err().to_string(), expected);
    assert_eq!(sim.advance_to(1e3).unwrap_err().to_string(), expected);
    sim.restore_state(&saved).unwrap();
    assert_eq!(sim.failed(), None);
    assert_eq!(sim.time(), 0.0);
    sim.step().unwrap();
}

/// `advance_to` a time behind, between steps or not finite is refused
/// before any step; a time on the grid is reached by whole steps (also
/// past the scene's `t_end`).
#[test]
fn advance_to_takes_whole_steps_only() {
    let s = Arc::new(load("pendulum.toml"));
    let dt = s.dt;
    let mut sim = Simulation::new(s.clone()).unwrap();
    sim.advance_to(10.0 * dt).unwrap();
    assert_eq!(sim.steps(), 10);
    for bad in [5.0 * dt, 10.5 * dt, f64::NAN, f64::INFINITY, -1.0] {
        let e = sim.advance_to(bad).unwrap_err().to_string();
        assert!(
            e.contains("cannot advance to") && e.contains("whole steps of dt"),
            "{bad}: {e}"
        );
        assert_eq!(sim.steps(), 10, "{bad}: nothing stepped");
    }
    let e = sim.advance_to(5.0 * dt).unwrap_err().to_string();
    assert!(e.contains("behind"), "{e}");
    // Same time: no step.
    sim.advance_to(10.0 * dt).unwrap();
    assert_eq!(sim.steps(), 10);
    // Past t_end.
    let n = (s.t_end / dt).round() as usize + 5;
    sim.advance_to(n as f64 * dt).unwrap();
    assert_eq!(sim.steps(), n);
    assert!(sim.time() > s.t_end);
}

/// Unknown names, out-of-range indices and non-finite values are refused
/// with a message naming them; an unknown output too.
#[test]
fn unknown_inputs_and_outputs_are_refused() {
    let mut sim = Simulation::new(Arc::new(load("pendulum.toml"))).unwrap();
    let e = sim.set_input("tau", 1.0).unwrap_err().to_string();
    assert!(e.contains("no input `tau`") && e.contains("none"), "{e}");
    let e = sim.set_input_at(0, 1.0).unwrap_err().to_string();
    assert!(e.contains("out of range"), "{e}");
    let e = sim.input("x\u{1b}[31m").unwrap_err().to_string();
    assert!(!e.contains('\u{1b}'), "escaped: {e}");
    let e = sim.output("nothing").unwrap_err().to_string();
    assert!(e.contains("no output `nothing`"), "{e}");
    let name = sim.output_names()[0].to_string();
    assert_eq!(sim.output(&name).unwrap(), sim.outputs()[0]);
}
