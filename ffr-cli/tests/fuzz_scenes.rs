//! Mutation fuzzing of scene files (issue 17): the built-in scenes, mutated
//! at the level of their text, through the loader and the runner.
//!
//! Mutations (one per case, 2–4 in one case of four; from a seeded `proptest` RNG): a number scaled
//! by `10^k` (`k` in −12..12), negated, set to 0, to a huge or tiny value
//! or to `nan`/`inf`; a string replaced (body names, markers with shifted
//! `x = …` or points, profile and kind names, control characters); a line
//! deleted, duplicated or moved; an unknown or misplaced key inserted
//! (`rate`, `alpha`, `slide`, `at`, `component`, `rho_inf`, a force
//! `profile`, a marker table with `axes`, `[[inputs]]` tables and their
//! keys, …); a body
//! moved off its joint. `t_end` is then cut to at most 200 steps (and
//! elements to at most 32) so that a case runs in well under a second.
//!
//! For every case, in a thread of its own with a counting allocator:
//! - no panic;
//! - either a refusal naming `fuzz.toml:line:col` (or a failed run whose
//!   reason is given), or a run whose every output is finite at every step
//!   and that reached `t_end`, every deflection within twice its body's
//!   length (the divergence monitor's bound);
//! - at most [`MAX_LIVE_BYTES`] of heap live at any time;
//! - a scene with inputs also steps through `ffr::scene::Simulation` with
//!   huge, tiny and non-finite input values, then restores its first
//!   state: errors with messages, no panic.
//!
//! `cargo test --test fuzz_scenes` runs [`DEFAULT_CASES`] cases with a fixed
//! seed; more with `FFR_FUZZ_CASES=5000 [FFR_FUZZ_SEED=7] cargo test
//! --release --test fuzz_scenes -- --nocapture` (the case in progress is
//! kept in `target/tmp/fuzz_scene_current.toml`).

use ffr::scene::{self, DefaultKernels};
use proptest::prelude::RngExt;
use proptest::test_runner::{RngAlgorithm, TestRng};
use std::alloc::{GlobalAlloc, Layout, System as Sys};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

const DEFAULT_CASES: usize = 400;
/// Heap that may be live at once while a case runs.
const MAX_LIVE_BYTES: usize = 512 << 20;
/// Steps a case may take.
const MAX_STEPS: f64 = 200.0;

struct Counting;
static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let p = Sys.alloc(l);
        if !p.is_null() {
            let now = LIVE.fetch_add(l.size(), Ordering::Relaxed) + l.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        LIVE.fetch_sub(l.size(), Ordering::Relaxed);
        Sys.dealloc(p, l)
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        let q = Sys.realloc(p, l, n);
        if !q.is_null() {
            LIVE.fetch_sub(l.size(), Ordering::Relaxed);
            let now = LIVE.fetch_add(n, Ordering::Relaxed) + n;
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        q
    }
}

#[global_allocator]
static A: Counting = Counting;

const SCENES: [&str; 10] = [
    "spin_up.toml",
    "spin_up_modal.toml",
    "precone.toml",
    "slider_crank.toml",
    "pendulum.toml",
    "free_floating.toml",
    "two_link_arm.toml",
    "boom_payload.toml",
    "l_frame.toml",
    "two_link_arm_inputs.toml",
];

/// Byte ranges `(start, end)` of tokens in a text.
type Spans = Vec<(usize, usize)>;

/// Spans of number literals and of basic strings in `text`.
fn tokens(text: &str) -> (Spans, Spans) {
    let b = text.as_bytes();
    let (mut nums, mut strs) = (Vec::new(), Vec::new());
    let mut i = 0;
    let mut comment = false;
    while i < b.len() {
        let c = b[i];
        if c == b'\n' {
            comment = false;
        }
        if comment {
            i += 1;
            continue;
        }
        if c == b'#' {
            comment = true;
        } else if c == b'"' {
            let s = i;
            i += 1;
            while i < b.len() && b[i] != b'"' && b[i] != b'\n' {
                i += 1;
            }
            strs.push((s, (i + 1).min(b.len())));
        } else if (c.is_ascii_digit() || c == b'-')
            && i > 0
            && matches!(b[i - 1], b' ' | b'=' | b'[' | b',')
        {
            let s = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b"+-._".contains(&b[i])) {
                i += 1;
            }
            nums.push((s, i));
            continue;
        }
        i += 1;
    }
    (nums, strs)
}

fn pick<'a, T>(rng: &mut TestRng, xs: &'a [T]) -> &'a T {
    &xs[rng.random_range(0..xs.len())]
}

fn mutate(rng: &mut TestRng, text: &str) -> String {
    let mut t = text.to_string();
    let n = if rng.random_range(0..4) == 0 {
        rng.random_range(2..=4)
    } else {
        1
    };
    for _ in 0..n {
        let (nums, strs) = tokens(&t);
        match rng.random_range(0..10) {
            0..=3 if !nums.is_empty() => {
                let (s, e) = *pick(rng, &nums);
                let old: f64 = t[s..e].replace('_', "").parse().unwrap_or(1.0);
                let new = match rng.random_range(0..8) {
                    0 => format!("{:e}", old * 10f64.powi(rng.random_range(-12..=12))),
                    1 => format!("{:e}", -old),
                    2 => "0".into(),
                    3 => pick(rng, &["1e300", "1e-300", "nan", "inf", "-inf", "1e9"]).to_string(),
                    4 => format!("{}", rng.random_range(0..300)),
                    5 => format!("{:e}", old * (1.0 + rng.random_range(-0.01..0.01))),
                    6 => format!("{:e}", old + rng.random_range(-0.01..0.01)),
                    _ => format!("{:e}", old * 2.0),
                };
                t.replace_range(s..e, &new);
            }
            4 | 5 if !strs.is_empty() => {
                let (s, e) = *pick(rng, &strs);
                let inner = t[s + 1..e.saturating_sub(1).max(s + 1)].to_string();
                let new = match rng.random_range(0..7) {
                    0 => inner.replacen("x=", "x=0.5", 1),
                    1 => inner.replace("0.0", "0.001"),
                    2 => pick(
                        rng,
                        &[
                            "ground@[0.0, 0.0]",
                            "beam@x=0.0",
                            "rod",
                            "a_b",
                            "aB",
                            "fn",
                            "x\u{1b}[31m<&",
                        ],
                    )
                    .to_string(),
                    3 => pick(
                        rng,
                        &[
                            "harmonic",
                            "spin-up",
                            "constant",
                            "rk4",
                            "fixed",
                            "prismatic",
                            "spherical",
                            "energy",
                            "angle",
                            "work",
                            "drive-acceleration",
                            "force",
                        ],
                    )
                    .to_string(),
                    4 => inner.repeat(rng.random_range(2..5)),
                    5 => String::new(),
                    _ => format!("{inner}\\u0007"),
                };
                t.replace_range(s..e, &format!("\"{}\"", new.replace('"', "")));
            }
            6 => {
                let lines: Vec<&str> = t.lines().collect();
                let k = rng.random_range(0..lines.len());
                let mut out: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
                match rng.random_range(0..3) {
                    0 => {
                        out.remove(k);
                    }
                    1 => out.insert(k, lines[k].to_string()),
                    _ => {
                        let l = out.remove(k);
                        let j = rng.random_range(0..=out.len());
                        out.insert(j, l);
                    }
                }
                t = out.join("\n");
            }
            7 | 8 => {
                // A key that may not apply where it lands.
                let key = pick(
                    rng,
                    &[
                        "rate = 2.0",
                        "alpha = 10.0",
                        "beta = 10.0",
                        "slide = \"constant\"",
                        "at = \"ground@[0.0, 0.0]\"",
                        "component = \"x\"",
                        "rho_inf = 0.5",
                        "rtol = 1e300",
                        "elements = 256",
                        "position = [0.001, 0.0]",
                        "angle = 0.3",
                        "kind = \"spring-damper\"",
                        "stiffness = 1e12",
                        "torque = 1e9",
                        "profile = { kind = \"harmonic\", amplitude = 1.0, frequency = 2.0 }",
                        "profile = { table = [[0.0, 0.0], [0.05, 1.0]] }",
                        "b = { at = \"leg1@x=1.0\", axes = { angle = 0.5 } }",
                        "joint = 1",
                        "joint = 3",
                        "direction = [0.0, 1e300]",
                        "kind = \"drive-acceleration\"",
                        "kind = \"torque\"",
                        "start = 1e9",
                        "axes = \"body\"",
                        "[[inputs]]\nname = \"u\"\nkind = \"drive-acceleration\"\njoint = 1",
                        "[[inputs]]\nname = \"u\"\nkind = \"torque\"\njoint = 1\nstart = 0.1",
                    ],
                );
                let lines: Vec<&str> = t.lines().collect();
                let k = rng.random_range(0..=lines.len());
                let mut out: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
                out.insert(k, key.to_string());
                t = out.join("\n");
            }
            _ => {
                // A body off its place: shift its `position` by up to 1 cm.
                if let Some(p) = t.find("position = [") {
                    let s = p + "position = [".len();
                    let e = s + t[s..].find([',', ']']).unwrap_or(0);
                    if let Ok(x) = t[s..e].trim().parse::<f64>() {
                        let shifted = format!("{:?}", x + rng.random_range(-0.01..0.01));
                        t.replace_range(s..e, &shifted);
                    }
                }
            }
        }
    }
    t
}

/// Cut `t_end` to at most [`MAX_STEPS`] steps and elements to 32.
fn bounded(text: &str) -> String {
    let num = |key: &str| -> Option<f64> {
        text.lines()
            .find_map(|l| {
                l.trim()
                    .strip_prefix(key)?
                    .trim()
                    .strip_prefix('=')
                    .map(str::trim)
            })
            .and_then(|v| v.replace('_', "").parse().ok())
    };
    let mut out: Vec<String> = text
        .lines()
        .map(|l| {
            let tl = l.trim_start();
            if let Some(v) = tl
                .strip_prefix("elements")
                .and_then(|r| r.trim().strip_prefix('='))
            {
                if v.trim().parse::<f64>().is_ok_and(|n| n > 32.0) {
                    return "elements = 32".to_string();
                }
            }
            l.to_string()
        })
        .collect();
    if let (Some(t_end), Some(dt)) = (num("t_end"), num("dt")) {
        if dt > 0.0 && dt.is_finite() && t_end / dt > MAX_STEPS {
            for l in &mut out {
                if l.trim_start().starts_with("t_end") {
                    *l = format!("t_end = {:e}", MAX_STEPS * dt);
                }
            }
        }
    }
    out.join("\n")
}

#[derive(Debug, Default)]
struct Counts {
    refused: usize,
    failed: usize,
    ran: usize,
}

fn check(text: &str, base: &Path) -> Result<&'static str, String> {
    let scene = match scene::from_str(text, "fuzz.toml", base, &DefaultKernels) {
        Ok(s) => s,
        Err(e) => {
            let msg = e.to_string();
            if msg.is_empty() || msg.contains('\n') {
                return Err(format!("refusal not one line: {msg:?}"));
            }
            if !msg.starts_with("fuzz.toml") {
                return Err(format!("refusal without a location: {msg}"));
            }
            return Ok("refused");
        }
    };
    if scene.t_end / scene.dt > MAX_STEPS * 1.01 {
        return Ok("refused");
    }
    let run = match scene::run(&scene) {
        Ok(r) => r,
        Err(e) => {
            let msg = e.to_string();
            if msg.is_empty() {
                return Err("run error without a message".into());
            }
            return Ok("failed");
        }
    };
    if let Some(f) = &run.failed {
        if f.is_empty() {
            return Err("failed run without a reason".into());
        }
        return Ok("failed");
    }
    for ((name, col), out) in run.names.iter().zip(&run.columns).zip(&scene.outputs) {
        // A deflection is bounded by the monitor (its body's length at 17
        // points of the axis; twice that anywhere between them).
        if let (scene::OutputKind::Deflection(_), Some(b)) = (&out.kind, out.marker.body) {
            let l = scene.system.bodies()[b.0]
                .body
                .layout()
                .length
                .unwrap_or(f64::INFINITY);
            if let Some(v) = col.iter().find(|v| v.abs() > 2.0 * l) {
                return Err(format!(
                    "run succeeded with deflection `{name}` = {v} m on a body of length {l} m"
                ));
            }
        }
        if col.len() != run.t.len() {
            return Err(format!(
                "output `{name}` has {} values for {} times",
                col.len(),
                run.t.len()
            ));
        }
        if let Some(v) = col.iter().find(|v| !v.is_finite()) {
            return Err(format!("run succeeded with output `{name}` = {v}"));
        }
    }
    // The stepping API on the same scene: inputs set to huge, tiny and
    // non-finite values, a few steps, save and restore: errors, no panic.
    if !scene.inputs.is_empty() {
        let mut sim = match scene::Simulation::new(std::sync::Arc::new(
            scene::from_str(text, "fuzz.toml", base, &DefaultKernels).expect("loaded once"),
        )) {
            Ok(s) => s,
            Err(_) => return Ok("failed"),
        };
        let saved = sim.save_state();
        for (k, v) in [1e300, f64::NAN, -0.5, 1e-300].into_iter().enumerate() {
            let _ = sim.set_input_at(k % scene.inputs.len(), v);
            if sim.step().is_err() {
                if sim.failed().is_none_or(str::is_empty) {
                    return Err("a failed step without a message".into());
                }
                break;
            }
        }
        sim.restore_state(&saved)
            .map_err(|e| format!("restore refused: {e}"))?;
    }
    let t_last = run.t.last().copied().unwrap_or(f64::NAN);
    if !((t_last - scene.t_end).abs() <= 1e-9 * scene.t_end.max(1.0)) {
        return Err(format!(
            "run succeeded but stopped at t = {t_last}, not t_end = {}",
            scene.t_end
        ));
    }
    Ok("ran")
}

#[test]
fn fuzz_scenes() {
    let cases: usize = std::env::var("FFR_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(DEFAULT_CASES);
    let seed: u64 = std::env::var("FFR_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(17);
    let dir = ffr::scene::load::builtin_dir();
    let texts: Vec<String> = SCENES
        .iter()
        .map(|s| std::fs::read_to_string(dir.join(s)).expect("built-in scene"))
        .collect();
    let mut seed_bytes = [0u8; 32];
    seed_bytes[..8].copy_from_slice(&seed.to_le_bytes());
    let mut rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes);
    let keep = std::env::var("FFR_FUZZ_CASES").is_ok();
    let tmp = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/tmp");
    let mut counts = Counts::default();
    let mut slowest = (0.0, String::new());
    for case in 0..cases {
        let src = rng.random_range(0..texts.len());
        let text = bounded(&mutate(&mut rng, &texts[src]));
        if keep {
            let _ = std::fs::create_dir_all(&tmp);
            let _ = std::fs::write(tmp.join("fuzz_scene_current.toml"), &text);
        }
        let base = dir.clone();
        let t2 = text.clone();
        PEAK.store(LIVE.load(Ordering::Relaxed), Ordering::Relaxed);
        let start_live = LIVE.load(Ordering::Relaxed);
        let started = std::time::Instant::now();
        let outcome = std::thread::spawn(move || check(&t2, &base)).join();
        let secs = started.elapsed().as_secs_f64();
        let peak = PEAK.load(Ordering::Relaxed).saturating_sub(start_live);
        let what = match outcome {
            Err(p) => {
                let msg = p
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                panic!(
                    "case {case} (from {}) panicked: {msg}\n--- scene ---\n{text}",
                    SCENES[src]
                );
            }
            Ok(Err(why)) => panic!(
                "case {case} (from {}): {why}\n--- scene ---\n{text}",
                SCENES[src]
            ),
            Ok(Ok(w)) => w,
        };
        assert!(
            peak <= MAX_LIVE_BYTES,
            "case {case} (from {}) had {peak} bytes live at once\n--- scene ---\n{text}",
            SCENES[src]
        );
        match what {
            "refused" => counts.refused += 1,
            "failed" => counts.failed += 1,
            _ => counts.ran += 1,
        }
        if secs > slowest.0 {
            slowest = (secs, text.clone());
        }
    }
    println!(
        "{cases} cases (seed {seed}): {} refused, {} failed with a reason, {} ran; slowest {:.2} s",
        counts.refused, counts.failed, counts.ran, slowest.0
    );
    if keep {
        let _ = std::fs::write(tmp.join("fuzz_scene_slowest.toml"), &slowest.1);
    }
    // The fuzzer must reach the runner, not only the loader's refusals.
    assert!(counts.ran + counts.failed > cases / 10, "{counts:?}");
}
