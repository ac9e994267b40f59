//! Fuzzing of `linearize` and `campbell` arguments (issue 36): the
//! shipped scenes with seeded random operating points (`--at`: `static`,
//! 0, a few steps, times that are tiny, huge, negative or not finite),
//! input and output names (the defaults, names out of range, of the wrong
//! kind, empty, long, with control characters and bidi overrides), speeds
//! (0, ordinary, huge, overflowing, negative, not finite), joints and
//! mode counts, through the library in-process
//! (`ffr::scene::linear::{linearize_scene, campbell}`, what the commands
//! call).
//!
//! For every case, in a thread of its own with a counting allocator:
//! - no panic;
//! - a refusal is one non-empty line without raw control characters;
//! - success means finite results: every entry of `A`, `B`, `C`, `D`
//!   finite and of the model's sizes, its eigenvalues finite; a Campbell
//!   diagram with a list of finite modes per speed;
//! - at most [`MAX_LIVE_BYTES`] of heap live at any time.
//!
//! `cargo test --test fuzz_linear` runs [`DEFAULT_CASES`] cases with a
//! fixed seed; more with `FFR_FUZZ_CASES=10000 [FFR_FUZZ_SEED=7] cargo
//! test --release --test fuzz_linear -- --nocapture`, only some of the
//! scenes with `FFR_FUZZ_SCENES=pendulum.toml,spin_up.toml`.

mod live_heap;

use ffr::runtime::linear::eigenvalues;
use ffr::scene::linear::{campbell, default_inputs, linearize_scene, At};
use ffr::scene::{DefaultKernels, SceneSpec};
use proptest::prelude::RngExt;
use proptest::test_runner::{RngAlgorithm, TestRng};
use std::path::Path;

const DEFAULT_CASES: usize = 300;
/// Heap that may be live at once while a case runs.
const MAX_LIVE_BYTES: usize = 512 << 20;

/// The shipped scenes fuzzed (the 5-MW blade, whose dense model takes
/// seconds in a debug build, only in longer runs).
const SCENES: [&str; 12] = [
    "pendulum.toml",
    "flexible_pendulum.toml",
    "two_link_arm.toml",
    "slider_crank.toml",
    "spin_up.toml",
    "spin_up_modal.toml",
    "spin_up_gravity.toml",
    "precone.toml",
    "boom_payload.toml",
    "l_frame.toml",
    "free_floating.toml",
    "blade_5mw.toml",
];

fn pick<'a, T>(rng: &mut TestRng, xs: &'a [T]) -> &'a T {
    &xs[rng.random_range(0..xs.len())]
}

/// A number of the kinds a hostile user types.
fn number(rng: &mut TestRng, scale: f64) -> f64 {
    match rng.random_range(0..10) {
        0 => 0.0,
        1 => -scale * rng.random_range(0.0..10.0),
        2 => *pick(rng, &[f64::NAN, f64::INFINITY, f64::NEG_INFINITY]),
        3 => *pick(rng, &[1e-300, 5e-324, 1e-15, 1e-160]),
        4 => *pick(rng, &[1e15, 1e20, 1e155, 1e300, f64::MAX]),
        _ => scale * 10f64.powf(rng.random_range(-3.0..3.0)),
    }
}

/// A name: a default, a neighbour of one, or hostile text.
fn name(rng: &mut TestRng, defaults: &[String]) -> String {
    let k = rng.random_range(0..12);
    match k {
        0..=3 if !defaults.is_empty() => pick(rng, defaults).clone(),
        4 => format!("joint{}", rng.random_range(0..8)),
        5 => format!("force{}", rng.random_range(0..8)),
        6 => format!("drive{}", rng.random_range(0..8)),
        7 => String::new(),
        8 => "x".repeat(rng.random_range(60..5000)),
        9 => "a\u{1b}]0;owned\u{7}\u{1b}[2J\nb\u{202e}c".into(),
        10 => format!("joint{}", u64::MAX),
        _ => "tip_y".into(),
    }
}

fn names(rng: &mut TestRng, defaults: &[String]) -> Option<Vec<String>> {
    if rng.random_range(0..3) == 0 {
        return None;
    }
    let n = rng.random_range(0..4);
    Some((0..n).map(|_| name(rng, defaults)).collect())
}

/// A refusal as the commands print it: one line, not empty, no raw
/// control characters, a bounded length.
fn refusal(what: &str, msg: &str) -> Result<(), String> {
    if msg.is_empty() || msg.contains('\n') || msg.chars().any(|c| c.is_control()) {
        return Err(format!("{what}: refusal not one clean line: {msg:?}"));
    }
    if msg.chars().count() > 4000 {
        return Err(format!("{what}: refusal of {} characters", msg.len()));
    }
    Ok(())
}

/// One case; `Ok(true)` for a result, `Ok(false)` for a refusal.
fn case(rng: &mut TestRng, spec: &SceneSpec) -> Result<bool, String> {
    let dt = spec.dt;
    if rng.random_range(0..2) == 0 {
        let at = match rng.random_range(0..6) {
            0 => At::Static,
            1 => At::Time(0.0),
            2 => At::Time(dt * rng.random_range(1..8) as f64),
            _ => At::Time(number(rng, dt)),
        };
        // A time run to `T` takes `T/dt` steps: keep cases short.
        if let At::Time(t) = at {
            if t.is_finite() && t > 10.0 * dt {
                return Ok(false);
            }
        }
        let ins = names(rng, &default_inputs(spec));
        let out_names: Vec<String> = spec.outputs.iter().map(|o| o.name.clone()).collect();
        let outs = names(rng, &out_names);
        let what = format!("linearize at {at:?}, inputs {ins:?}, outputs {outs:?}");
        match linearize_scene(spec, &DefaultKernels, at, ins.as_deref(), outs.as_deref()) {
            Err(e) => refusal(&what, &e.to_string()).map(|_| false),
            Ok(m) => {
                let ns = m.states.len();
                let (ni, no) = (m.inputs.len(), m.outputs.len());
                let shapes = [
                    (m.a.shape(), (ns, ns)),
                    (m.b.shape(), (ns, ni)),
                    (m.c.shape(), (no, ns)),
                    (m.d.shape(), (no, ni)),
                ];
                if let Some((got, want)) = shapes.iter().find(|(g, w)| g != w) {
                    return Err(format!("{what}: a matrix of {got:?}, expected {want:?}"));
                }
                for (n, x) in [("A", &m.a), ("B", &m.b), ("C", &m.c), ("D", &m.d)] {
                    if x.iter().any(|v| !v.is_finite()) {
                        return Err(format!("{what}: {n} not finite"));
                    }
                }
                let ev = eigenvalues(&m.a).map_err(|e| format!("{what}: eigenvalues: {e}"))?;
                if ev.iter().any(|l| !(l.re.is_finite() && l.im.is_finite())) {
                    return Err(format!("{what}: an eigenvalue not finite"));
                }
                Ok(true)
            }
        }
    } else {
        let n = rng.random_range(1..4);
        let speeds: Vec<f64> = (0..n).map(|_| number(rng, 50.0)).collect();
        let joint = match rng.random_range(0..4) {
            0 => Some(rng.random_range(0..6)),
            _ => None,
        };
        let count = *pick(rng, &[0, 1, 3, 10, 1000, usize::MAX]);
        let what = format!("campbell speeds {speeds:?}, joint {joint:?}, count {count}");
        match campbell(spec, &DefaultKernels, &speeds, joint, count) {
            Err(e) => refusal(&what, &e.to_string()).map(|_| false),
            Ok(c) => {
                if c.modes.len() != speeds.len() {
                    return Err(format!("{what}: {} lists of modes", c.modes.len()));
                }
                for m in c.modes.iter().flatten() {
                    if !(m.omega.is_finite() && m.hz.is_finite() && m.zeta.is_finite()) {
                        return Err(format!("{what}: a mode not finite: {m:?}"));
                    }
                }
                for w in &c.warnings {
                    refusal(&what, w)?;
                }
                Ok(true)
            }
        }
    }
}

#[test]
fn fuzz_linear() {
    let cases: usize = std::env::var("FFR_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(DEFAULT_CASES);
    let long = std::env::var("FFR_FUZZ_CASES").is_ok();
    let seed: u64 = std::env::var("FFR_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(36);
    let dir = ffr::scene::load::builtin_dir();
    // `FFR_FUZZ_SCENES=a.toml,b.toml` fuzzes only those of the scenes.
    let chosen: Vec<&str> = match std::env::var("FFR_FUZZ_SCENES") {
        Ok(list) => SCENES
            .iter()
            .copied()
            .filter(|s| list.split(',').any(|x| x.trim() == *s))
            .collect(),
        Err(_) if long => SCENES.to_vec(),
        Err(_) => SCENES[..11].to_vec(),
    };
    assert!(
        !chosen.is_empty(),
        "FFR_FUZZ_SCENES names none of {SCENES:?}"
    );
    let scenes = &chosen[..];
    let specs: Vec<SceneSpec> = scenes
        .iter()
        .map(|s| ffr::scene::load::load_spec(&dir.join(s)).expect("a shipped scene"))
        .collect();
    let mut seed_bytes = [0u8; 32];
    seed_bytes[..8].copy_from_slice(&seed.to_le_bytes());
    let mut rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes);
    let (mut results, mut refusals) = (0usize, 0usize);
    let mut slowest = (0.0f64, String::new());
    let started = std::time::Instant::now();
    for k in 0..cases {
        let src = rng.random_range(0..specs.len());
        let spec = specs[src].clone();
        // Each case its own RNG (from the main one), so a thread owns it.
        let mut sub = [0u8; 32];
        sub[..8].copy_from_slice(&rng.random_range(0..u64::MAX).to_le_bytes());
        let mut case_rng = TestRng::from_seed(RngAlgorithm::ChaCha, &sub);
        let heap = live_heap::mark();
        let t0 = std::time::Instant::now();
        let outcome = std::thread::spawn(move || case(&mut case_rng, &spec)).join();
        let secs = t0.elapsed().as_secs_f64();
        let peak = heap.peak();
        match outcome {
            Err(p) => {
                let msg = p
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                panic!("case {k} ({}) panicked: {msg}", scenes[src]);
            }
            Ok(Err(why)) => panic!("case {k} ({}): {why}", scenes[src]),
            Ok(Ok(true)) => results += 1,
            Ok(Ok(false)) => refusals += 1,
        }
        assert!(
            peak <= MAX_LIVE_BYTES,
            "case {k} ({}) had {peak} bytes live at once",
            scenes[src]
        );
        if secs > slowest.0 {
            slowest = (secs, format!("case {k} ({})", scenes[src]));
        }
    }
    println!(
        "{cases} cases (seed {seed}): {results} results, {refusals} refusals in {:.1} s; slowest {:.2} s ({})",
        started.elapsed().as_secs_f64(),
        slowest.0,
        slowest.1
    );
    // The fuzzer must reach results, not only refusals.
    assert!(results > cases / 10, "{results} results of {cases}");
}

/// Issue 36: four 256-element beam3 bodies (over 6000 coordinates, which
/// `ffr run` integrates banded) would need dense matrices of gigabytes
/// for a linear model or a Campbell steady state: refused before any is
/// allocated, naming the limit (before, `linearize` grew past 3 GB).
#[test]
fn a_linear_model_too_large_to_hold_densely_is_refused_before_allocation() {
    let mut text = String::from(
        "dimension = 3\nt_end = 0.01\ndt = 0.01\n\n[[joints]]\nkind = \"revolute\"\na = \"ground@[0.0, 0.0, 0.0]\"\nb = \"b0\"\ndrive = { angle = \"constant-rate\", omega = 1.0 }\n",
    );
    for i in 0..4 {
        text.push_str(&format!(
            "\n[bodies.b{i}]\nshape = \"beam3\"\nelements = 256\nreference = \"clamped\"\nparams = {{ length = 1.0, rho = 2766.67, area = 7.2968e-5, iy = 8.2189e-9, iz = 8.2189e-9, e = 6.8952e10, g = 2.5922e10, j = 1.64378e-8 }}\nposition = [{i}.0, 0.0, 0.0]\n"
        ));
        if i > 0 {
            text.push_str(&format!(
                "\n[[joints]]\nkind = \"revolute\"\na = \"b{}@x=1.0\"\nb = \"b{i}\"\n",
                i - 1
            ));
        }
    }
    let spec = ffr::codegen::scene::resolve_str(&text, "big.toml", Path::new(".")).unwrap();
    let heap = live_heap::mark();
    let e = linearize_scene(&spec, &DefaultKernels, At::Time(0.0), None, None)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("MAX_DENSE_UNKNOWNS") && e.contains("more than the limit of 2048"),
        "{e}"
    );
    let e = campbell(&spec, &DefaultKernels, &[1.0], None, 4)
        .unwrap_err()
        .to_string();
    assert!(e.contains("MAX_DENSE_UNKNOWNS"), "{e}");
    // Building the scene costs what `ffr run` costs; a dense matrix of
    // the 6000-odd unknowns alone would be 300 MB.
    let peak = heap.peak();
    assert!(peak < 100 << 20, "{peak} bytes live at once");
}
