//! Named inputs (`[[inputs]]`): a torque input equals the same constant
//! torque written as a `[[forces]]` element, bit for bit; inputs set
//! through the stepping API equal the same values given as a profile table
//! in the file, bit for bit; a drive-acceleration input moves a folded
//! drive (prescribed coordinates) and a constraint drive by the exact
//! integral of its held values; `linearize` takes the names (the same
//! columns as `jointN` and `driveN`); hostile files and calls are refused
//! with located errors and no change.

use ffr::scene::{self, DefaultKernels, Scene, Simulation};
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes")
}

fn text(name: &str) -> String {
    std::fs::read_to_string(scenes().join(name)).unwrap()
}

fn load(text: &str) -> Scene {
    scene::from_str(text, "test.toml", &scenes(), &DefaultKernels).unwrap()
}

fn load_err(text: &str) -> String {
    match scene::from_str(text, "test.toml", &scenes(), &DefaultKernels) {
        Ok(_) => panic!("the scene should be refused"),
        Err(e) => e.to_string(),
    }
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// A torque input in the elbow (joint 3 of the two-link arm) with a start
/// value gives the run of the same torque as a `[[forces]]` torque element
/// between the joint's markers, bit for bit: the element is evaluated by
/// the same code with the same value (`u` from the input slot, `τ(t)` from
/// the constant), and added after the scene's forces in both cases, so the
/// sums are taken in the same order.
#[test]
fn a_torque_input_equals_the_same_torque_element() {
    let base = text("two_link_arm.toml").replace("t_end = 2.0", "t_end = 0.3");
    let with_input = format!(
        "{base}\n[[inputs]]\nname = \"elbow_tau\"\nkind = \"torque\"\njoint = 3\nstart = 0.05\n"
    );
    let with_force = format!(
        "{base}\n[[forces]]\nkind = \"torque\"\na = \"upper@x=0.5\"\nb = \"forearm\"\ntorque = 0.05\n"
    );
    let a = scene::run(&load(&with_input)).unwrap();
    let b = scene::run(&load(&with_force)).unwrap();
    let plain = scene::run(&load(&base)).unwrap();
    assert!(a.failed.is_none() && b.failed.is_none());
    assert_eq!(a.t.len(), b.t.len());
    for (c, name) in a.names.iter().enumerate() {
        assert_eq!(bits(&a.columns[c]), bits(&b.columns[c]), "{name}");
    }
    // And the torque does something.
    let elbow = a.names.iter().position(|n| n == "elbow").unwrap();
    let (x, y) = (
        a.columns[elbow].last().unwrap(),
        plain.columns[elbow].last().unwrap(),
    );
    assert!((x - y).abs() > 1e-4, "{x} vs {y}");
}

/// The accumulated step times `0, dt, dt + dt, …` (as the simulation adds
/// them), `n` of them.
fn step_times(dt: f64, n: usize) -> Vec<f64> {
    let mut t = vec![0.0];
    for _ in 1..n {
        t.push(t.last().unwrap() + dt);
    }
    t
}

/// Values set through `set_input` before every step equal the same values
/// as a profile table whose rows are at the steps' start times (the
/// simulation's `time()`, written exactly with `{:?}`), bit for bit, on a
/// torque input and a force input at once (set before the first step too:
/// the initial state is made with the values set then, as the table's
/// first row makes it); `run()` of the file with the table gives the same
/// samples.
#[test]
fn api_inputs_equal_a_profile_table_bit_for_bit() {
    let base = text("two_link_arm.toml").replace("t_end = 2.0", "t_end = 0.2");
    let n = 200;
    let times = step_times(1e-3, n);
    let value = |k: usize, j: usize| ((k * 7 + j * 3) % 11) as f64 * 0.01 - 0.05;
    let table = |j: usize| {
        let rows: Vec<String> = times
            .iter()
            .enumerate()
            .map(|(k, t)| format!("[{t:?}, {:?}]", value(k, j)))
            .collect();
        format!("profile = {{ table = [{}] }}\n", rows.join(", "))
    };
    let inputs = |profiles: bool| {
        let p = |j: usize| if profiles { table(j) } else { String::new() };
        format!(
            "\n[[inputs]]\nname = \"tau\"\nkind = \"torque\"\njoint = 3\n{}\n[[inputs]]\nname = \"push\"\nkind = \"force\"\nat = \"forearm@x=0.4\"\ndirection = [0.0, 2.0]\n{}",
            p(0),
            p(1)
        )
    };
    let s_table = Arc::new(load(&format!("{base}{}", inputs(true))));
    let s_api = Arc::new(load(&format!("{base}{}", inputs(false))));
    let mut a = Simulation::new(s_table.clone()).unwrap();
    let mut b = Simulation::new(s_api).unwrap();
    assert_eq!(b.input_names(), ["tau", "push"]);
    let r = scene::run(&s_table).unwrap();
    for k in 0..n {
        assert_eq!(a.time().to_bits(), times[k].to_bits(), "time of step {k}");
        for j in 0..2 {
            b.set_input_at(j, value(k, j)).unwrap();
        }
        assert_eq!(bits(a.outputs()), bits(b.outputs()), "sample {k}");
        for (c, col) in r.columns.iter().enumerate() {
            assert_eq!(
                a.outputs()[c].to_bits(),
                col[k].to_bits(),
                "run, sample {k}"
            );
        }
        a.step().unwrap();
        b.step().unwrap();
        assert_eq!(a.input("tau").unwrap(), value(k, 0));
    }
    assert_eq!(bits(&a.state().q), bits(&b.state().q));
}

/// `δ` of a drive-acceleration input held at `u[k]` over step `k`:
/// `δ(t_k)` by the exact recurrences, from rest.
fn delta(u: &[f64], dt: f64) -> Vec<f64> {
    let (mut d, mut dd) = (0.0, 0.0);
    let mut out = vec![0.0];
    for &uk in u {
        d += dd * dt + 0.5 * uk * dt * dt;
        dd += uk * dt;
        out.push(d);
    }
    out
}

/// A drive-acceleration input on the spin-up's hub (a revolute joint to
/// the ground that the reader folds into the beam's prescribed frame
/// angle): the frame angle is the spin-up angle plus `δ`, `δ̈` the input's
/// held values, integrated exactly (independent recurrences here, to
/// round-off).
#[test]
fn a_drive_acceleration_input_moves_a_folded_drive() {
    let t = text("spin_up.toml").replace("t_end = 20.0", "t_end = 1.0")
        + "\n[[inputs]]\nname = \"hub_acc\"\nkind = \"drive-acceleration\"\njoint = 1\n\n[[outputs]]\nname = \"hub\"\nkind = \"angle\"\nat = \"beam\"\n";
    let s = Arc::new(load(&t));
    assert!(
        s.notes.iter().any(|n| n.contains("folded")),
        "{:?}",
        s.notes
    );
    let mut sim = Simulation::new(s.clone()).unwrap();
    let dt = s.dt;
    let u: Vec<f64> = (0..100).map(|k| ((k / 10) as f64 - 4.0) * 0.3).collect();
    let hub = sim.output_names().iter().position(|n| *n == "hub").unwrap();
    let spin = |t: f64| {
        let (w, tr) = (4.0, 15.0);
        let k = 2.0 * std::f64::consts::PI / tr;
        (w / tr) * (t * t / 2.0 + ((k * t).cos() - 1.0) / (k * k))
    };
    let d = delta(&u, dt);
    for (k, &uk) in u.iter().enumerate() {
        sim.set_input("hub_acc", uk).unwrap();
        sim.step().unwrap();
        let t = sim.time();
        let want = spin(t) + d[k + 1];
        let got = sim.outputs()[hub];
        assert!((got - want).abs() < 1e-12, "t = {t}: {got} vs {want}");
    }
    assert!(
        d[100].abs() > 1e-3,
        "the perturbation is visible: {}",
        d[100]
    );
}

/// The same on a drive that stays a constraint row: a drive added to the
/// two-link arm's elbow (between the upper arm's tip and the forearm, not
/// to the ground): the elbow angle is the drive's (0) plus `δ`, to the
/// constraint's Newton tolerance.
#[test]
fn a_drive_acceleration_input_moves_a_constraint_drive() {
    let t = text("two_link_arm.toml")
        .replace("t_end = 2.0", "t_end = 0.3")
        .replace(
            "a = \"upper@x=0.5\"\nb = \"forearm\"\n\n#",
            "a = \"upper@x=0.5\"\nb = \"forearm\"\ndrive = { angle = \"constant\", value = 0.0 }\n\n#",
        )
        + "\n[[inputs]]\nname = \"elbow_acc\"\nkind = \"drive-acceleration\"\njoint = 3\n";
    let s = Arc::new(load(&t));
    assert!(
        !s.notes.iter().any(|n| n.contains("folded")),
        "{:?}",
        s.notes
    );
    let mut sim = Simulation::new(s.clone()).unwrap();
    let elbow = sim
        .output_names()
        .iter()
        .position(|n| *n == "elbow")
        .unwrap();
    let u: Vec<f64> = (0..300)
        .map(|k| if k < 150 { 20.0 } else { -35.0 })
        .collect();
    let d = delta(&u, s.dt);
    for (k, &uk) in u.iter().enumerate() {
        sim.set_input("elbow_acc", uk).unwrap();
        sim.step().unwrap();
        let got = sim.outputs()[elbow];
        assert!(
            (got - d[k + 1]).abs() < 1e-9,
            "step {k}: {got} vs {}",
            d[k + 1]
        );
    }
    assert!(d[300].abs() > 0.1, "{}", d[300]);
}

/// A saved state holds the input values and the drive perturbation: after
/// a restore, the same input sequence gives the same bits.
#[test]
fn save_and_restore_keep_inputs_and_drive_perturbations() {
    let t = text("spin_up.toml")
        + "\n[[inputs]]\nname = \"hub_acc\"\nkind = \"drive-acceleration\"\njoint = 1\nstart = 0.7\n";
    let s = Arc::new(load(&t));
    let mut sim = Simulation::new(s).unwrap();
    sim.advance_to(0.2).unwrap();
    sim.set_input("hub_acc", -1.5).unwrap();
    sim.advance_to(0.3).unwrap();
    let saved = sim.save_state();
    let run = |sim: &mut Simulation| {
        let mut out = Vec::new();
        for k in 0..50 {
            if k % 7 == 0 {
                sim.set_input("hub_acc", k as f64 * 0.1).unwrap();
            }
            sim.step().unwrap();
            out.push(bits(&sim.state().q));
        }
        out
    };
    let first = run(&mut sim);
    sim.set_input("hub_acc", 99.0).unwrap();
    sim.restore_state(&saved).unwrap();
    assert_eq!(sim.input("hub_acc").unwrap(), -1.5);
    assert_eq!(run(&mut sim), first);
}

/// `linearize` takes the named inputs: a torque input's column is its
/// joint's `jointN` column and a drive-acceleration input's model is its
/// joint's `driveN` model, exactly.
#[test]
fn linearize_takes_named_inputs() {
    use ffr::scene::linear::{linearize_scene, At};
    let arm =
        text("two_link_arm.toml") + "\n[[inputs]]\nname = \"tau\"\nkind = \"torque\"\njoint = 3\n";
    let spec = ffr::codegen::scene::resolve_str(&arm, "arm.toml", &scenes()).unwrap();
    let lin = |names: &[&str]| {
        let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        linearize_scene(&spec, &DefaultKernels, At::Time(0.1), Some(&names), None).unwrap()
    };
    let (a, b) = (lin(&["tau"]), lin(&["joint3"]));
    assert_eq!(a.inputs, ["tau"]);
    assert_eq!(bits(a.b.as_slice()), bits(b.b.as_slice()));
    assert!(a.b.norm() > 0.0);
    // Default inputs include the named ones.
    let d = ffr::scene::linear::default_inputs(&spec);
    assert!(d.contains(&"tau".to_string()), "{d:?}");

    let spin = text("spin_up.toml")
        + "\n[[inputs]]\nname = \"hub_acc\"\nkind = \"drive-acceleration\"\njoint = 1\n";
    let spec = ffr::codegen::scene::resolve_str(&spin, "spin.toml", &scenes()).unwrap();
    let lin = |names: &[&str]| {
        let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        linearize_scene(&spec, &DefaultKernels, At::Time(0.5), Some(&names), None).unwrap()
    };
    let (a, b) = (lin(&["hub_acc"]), lin(&["drive1"]));
    assert_eq!(bits(a.a.as_slice()), bits(b.a.as_slice()));
    assert_eq!(bits(a.b.as_slice()), bits(b.b.as_slice()));
    assert!(a.b.norm() > 0.0);
}

/// Hostile files: each refused at the key, with a message saying what is
/// wrong; no panic.
#[test]
fn bad_inputs_are_refused_where_they_are_written() {
    let arm = text("two_link_arm.toml");
    let with = |body: &str| format!("{arm}\n[[inputs]]\n{body}\n");
    for (body, needle) in [
        ("name = \"u\"\nkind = \"thrust\"", "unknown kind `thrust`"),
        ("name = \"u\"\nkind = \"torque\"", "needs `joint = N`"),
        ("name = \"u\"\nkind = \"torque\"\njoint = 0", "the scene's joints are 1 to 3"),
        ("name = \"u\"\nkind = \"torque\"\njoint = 9", "the scene's joints are 1 to 3"),
        ("name = \"u\"\nkind = \"torque\"\njoint = 2", "is a fixed joint: a torque input needs a revolute joint"),
        ("name = \"u\"\nkind = \"drive-acceleration\"\njoint = 3", "has no drive"),
        ("name = \"joint1\"\nkind = \"torque\"\njoint = 3", "is one of the names `linearize` gives"),
        ("name = \"drive7\"\nkind = \"torque\"\njoint = 3", "is one of the names"),
        ("name = \"\"\nkind = \"torque\"\njoint = 3", "not empty"),
        ("name = \"u\"\nkind = \"force\"\nat = \"forearm@x=0.4\"\ndirection = [0.0, 0.0]", "`direction` is zero"),
        ("name = \"u\"\nkind = \"force\"\nat = \"forearm@x=0.4\"\ndirection = [nan, 1.0]", "must be finite"),
        ("name = \"u\"\nkind = \"force\"\nat = \"forearm@x=0.4\"", "needs `direction"),
        ("name = \"u\"\nkind = \"force\"\nat = \"ground@[0.0, 0.0]\"\ndirection = [1.0, 0.0]", "does nothing"),
        ("name = \"u\"\nkind = \"force\"\nat = \"forearm@x=0.4\"\ndirection = [1.0, 0.0]\naxes = \"local\"", "`axes` is \"global\" or \"body\""),
        ("name = \"u\"\nkind = \"torque\"\njoint = 3\nat = \"forearm\"", "takes no `at`"),
        ("name = \"u\"\nkind = \"torque\"\njoint = 3\nstart = inf", "finite"),
        ("name = \"u\"\nkind = \"torque\"\njoint = 3\nstart = 1.0\nprofile = { table = [[0.0, 1.0]] }", "`start` and `profile`"),
        ("name = \"u\"\nkind = \"torque\"\njoint = 3\nprofile = { table = [[1.0, 1.0], [0.5, 2.0]] }", "must increase strictly"),
        ("name = \"u\"\nkind = \"torque\"\njoint = 3\ngain = 2.0", "unknown field `gain`"),
    ] {
        let e = load_err(&with(body));
        assert!(e.contains(needle), "{body}:\n{e}");
        assert!(e.starts_with("test.toml:"), "located: {e}");
    }
    // A driven joint takes no torque input.
    let e = load_err(&format!(
        "{}\n[[inputs]]\nname = \"u\"\nkind = \"torque\"\njoint = 1\n",
        text("spin_up.toml")
    ));
    assert!(e.contains("is driven"), "{e}");
    // Duplicate names, and two drive inputs on one drive.
    let e = load_err(&format!(
        "{}\n[[inputs]]\nname = \"u\"\nkind = \"torque\"\njoint = 3\n",
        with("name = \"u\"\nkind = \"torque\"\njoint = 3")
    ));
    assert!(e.contains("a second input named `u`"), "{e}");
    let spin = text("spin_up.toml");
    let e = load_err(&format!(
        "{spin}\n[[inputs]]\nname = \"a\"\nkind = \"drive-acceleration\"\njoint = 1\n[[inputs]]\nname = \"b\"\nkind = \"drive-acceleration\"\njoint = 1\n"
    ));
    assert!(e.contains("already has the input `a`"), "{e}");
    // A name with escapes is shown escaped.
    let e = load_err(&with("name = \"joint1\\u001b[31m\"\nkind = \"thrust\""));
    assert!(!e.contains('\u{1b}'), "{e}");
}

/// Hostile calls: a value that is not finite is refused and changes
/// nothing; an unknown name is refused naming the inputs.
#[test]
fn bad_input_values_are_refused_and_change_nothing() {
    let t = text("two_link_arm.toml")
        + "\n[[inputs]]\nname = \"tau\"\nkind = \"torque\"\njoint = 3\nstart = 0.1\n";
    let mut sim = Simulation::new(Arc::new(load(&t))).unwrap();
    sim.step().unwrap();
    let before = sim.save_state();
    let q = bits(&sim.state().q);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let e = sim.set_input("tau", bad).unwrap_err().to_string();
        assert!(e.contains("input `tau` must be finite"), "{e}");
        let e = sim.set_input_at(0, bad).unwrap_err().to_string();
        assert!(e.contains("must be finite"), "{e}");
    }
    assert_eq!(sim.input("tau").unwrap(), 0.1);
    let e = sim.set_input("taw", 1.0).unwrap_err().to_string();
    assert!(e.contains("no input `taw`") && e.contains("`tau`"), "{e}");
    assert_eq!(bits(&sim.state().q), q);
    // Stepping on gives what the saved state gives.
    sim.step().unwrap();
    let after = bits(&sim.state().q);
    sim.restore_state(&before).unwrap();
    sim.step().unwrap();
    assert_eq!(bits(&sim.state().q), after);
}

/// `scenes/two_link_arm_inputs.toml` (shipped): run without a caller, the
/// elbow torque follows its profile; the motor's and the inputs' work and
/// the dampers' dissipation account for the change of the mechanical
/// energy to the integrator's O(dt²) error (the `work` output counts the
/// input torque's power as a motor's): `max |E − E(0) − W + D|` below
/// 2e-4 of `max |W|`, and 3 to 5.5 times less at half the step. The
/// elbow moves away from the arm without inputs once the pulse starts.
#[test]
fn the_shipped_inputs_scene_balances_its_energy() {
    let balance = |text: &str| {
        let r = scene::run(&load(text)).unwrap();
        assert!(r.failed.is_none(), "{:?}", r.failed);
        let col = |n: &str| r.columns[r.names.iter().position(|x| x == n).unwrap()].clone();
        let (e, w, d) = (col("energy"), col("motor_work"), col("dissipated"));
        let worst = (0..e.len())
            .map(|i| (e[i] - e[0] - w[i] + d[i]).abs())
            .fold(0.0, f64::max);
        (worst, w.iter().fold(0.0f64, |a, x| a.max(x.abs())), r)
    };
    let t = text("two_link_arm_inputs.toml").replace("t_end = 2.0", "t_end = 1.5");
    let (b1, w1, r) = balance(&t);
    let (b2, _, _) = balance(&t.replace("dt = 1e-3", "dt = 5e-4"));
    println!("max |E − E0 − W + D| {b1:.3e} J (dt 1e-3), {b2:.3e} J (dt 5e-4), ratio {:.2}; max |W| {w1:.3} J", b1 / b2);
    assert!(b1 < 2e-4 * w1, "{b1:e} vs {w1:e}");
    assert!((3.0..5.5).contains(&(b1 / b2)), "second order: {}", b1 / b2);
    let plain = scene::run(&load(
        &text("two_link_arm.toml").replace("t_end = 2.0", "t_end = 1.5"),
    ))
    .unwrap();
    let elbow = r.names.iter().position(|n| n == "elbow").unwrap();
    let at = |r: &ffr::scene::SceneRun, t: f64| r.columns[elbow][(t / 1e-3).round() as usize];
    assert!(
        (at(&r, 0.25) - at(&plain, 0.25)).abs() < 1e-9,
        "no torque before 0.3 s"
    );
    assert!(
        (at(&r, 1.0) - at(&plain, 1.0)).abs() > 1e-3,
        "the pulse moves the elbow"
    );
}

/// The closed loop of docs/in-the-loop.md ("Stepping API (Rust)"): a P
/// law on the elbow torque of the shipped inputs scene (its target ramped
/// to 0.2 rad over 0.5 s: a torque step on a flexible link's root section
/// rings its highest modes, which ρ∞ = 1 keeps), through `set_input_at`
/// and `step`; then save, advance, restore. Against the arm without the
/// elbow torque, the controller turns the elbow towards its target by
/// about the static share `kp φ*/(kp + k) = 0.04` rad of the elbow spring
/// (k = 2 N m/rad); the arm swings on its shoulder motor meanwhile.
#[test]
fn the_documented_closed_loop_runs() {
    let scene = Arc::new(load(&text("two_link_arm_inputs.toml")));
    let mut sim = Simulation::new(scene).unwrap();
    let tau = sim
        .input_names()
        .iter()
        .position(|n| *n == "elbow_tau")
        .unwrap();
    let elbow = sim
        .output_names()
        .iter()
        .position(|n| *n == "elbow")
        .unwrap();
    let (kp, kd, target) = (0.5, 0.0, 0.2);
    let mut last = sim.outputs()[elbow];
    while sim.time() < 1.0 {
        let angle = sim.outputs()[elbow];
        let rate = (angle - last) / sim.scene().dt;
        last = angle;
        sim.set_input_at(
            tau,
            kp * (target * (sim.time() / 0.5).min(1.0) - angle) - kd * rate,
        )
        .unwrap();
        sim.step().unwrap();
    }
    let saved = sim.save_state();
    let at_one = sim.outputs()[elbow];
    sim.advance_to(1.5).unwrap();
    assert!((sim.time() - 1.5).abs() < 1e-9);
    sim.restore_state(&saved).unwrap();
    assert_eq!(sim.outputs()[elbow], at_one);
    let mut free = Simulation::new(Arc::new(load(&text("two_link_arm.toml")))).unwrap();
    free.advance_to(1.0).unwrap();
    let moved = at_one - free.output("elbow").unwrap();
    println!("elbow at 1 s: {at_one} with the controller, moved by {moved}");
    assert!((0.02..0.06).contains(&moved), "{moved}");
}

/// `linearize` at a time `T` of a scene whose inputs have profiles or
/// drive perturbations runs to `T` as `ffr run` does (the profiles
/// applied), so its operating state is the simulation's at `T` (to the
/// round-off of the last step's length, which the run to `T` computes as
/// `T − t`), and the model is taken with the inputs' values there.
#[test]
fn linearize_runs_to_its_time_with_the_inputs_profiles() {
    use ffr::scene::linear::{linearize_scene, At};
    let t = text("two_link_arm.toml")
        + "\n[[inputs]]\nname = \"elbow_acc\"\nkind = \"drive-acceleration\"\njoint = 3\nstart = 0.5\n"
        + "\n[[inputs]]\nname = \"push\"\nkind = \"force\"\nat = \"forearm@x=0.4\"\ndirection = [0.0, 1.0]\naxes = \"body\"\nprofile = { table = [[0.0, 0.0], [1.0, 0.5]] }\n";
    let t = t.replace(
        "a = \"upper@x=0.5\"\nb = \"forearm\"\n\n#",
        "a = \"upper@x=0.5\"\nb = \"forearm\"\ndrive = { angle = \"constant\", value = 0.0 }\n\n#",
    );
    let spec = ffr::codegen::scene::resolve_str(&t, "arm.toml", &scenes()).unwrap();
    let names = vec!["push".to_string(), "elbow_acc".to_string()];
    let m = linearize_scene(&spec, &DefaultKernels, At::Time(0.6), Some(&names), None).unwrap();
    let mut sim = Simulation::new(Arc::new(load(&t))).unwrap();
    sim.advance_to(0.6).unwrap();
    let worst = m
        .state
        .q
        .iter()
        .zip(&sim.state().q)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-12, "{worst:e}");
    // The elbow drive's perturbation is in that state: ½ u t² = 0.09 rad.
    let elbow = sim.output("elbow").unwrap();
    assert!((elbow - 0.5 * 0.5 * 0.36).abs() < 1e-9, "{elbow}");
}
