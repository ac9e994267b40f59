//! Mutation fuzzing of study files (issue 36): the shipped study
//! (`bench/sweep/spin_up_40.toml`), the example of `docs/sweep.md` and a
//! study of the pendulum scene, mutated at the level of their text, through
//! the study reader (`ffr_cli::sweep::read`: the TOML, the axes and their
//! ranges and seeded samples, the figures, the reference CSVs) and the
//! case expansion; one case in [`RUN_EVERY`] also runs one of its cases
//! (`run_case`) when that case is at most [`MAX_STEPS`] steps of at most 32
//! elements (the study's `t_end` is first cut to 0.05 s, so most are).
//!
//! Mutations (one per case, 2–4 in one case of four; from a seeded
//! `proptest` RNG): a number scaled by `10^k`, negated, set to 0, to a huge
//! or tiny value (`±1e308`, `1e-308`), to `nan`/`inf`, to a large integer;
//! a string replaced (axis keys that overlap others, `joints.00`, keys
//! with escape sequences, bidi overrides and newlines, empty and long
//! keys; statistics, outputs; reference files that are missing, a
//! directory, with a column named twice or a bad number); a line deleted,
//! duplicated or moved; an axis or figure line inserted (ranges whose
//! width overflows, samples of a huge `sd`, many values, references).
//!
//! For every case, with a counting allocator:
//! - no panic;
//! - either a refusal: one line, naming the study file (`fuzz.toml:line:col`
//!   for the file's own errors), with no raw control or bidi character; or
//!   a study whose cases are at most `MAX_CASES`, every number of every
//!   axis finite, no two axes on one place, the figures' references within
//!   `MAX_REFERENCE_VALUES`; a case run gives finite figures, one per
//!   figure, or a failed row with a one-line escaped message;
//! - at most [`MAX_LIVE_BYTES`] of heap live at any time.
//!
//! `cargo test --test fuzz_studies` runs [`DEFAULT_CASES`] cases with a
//! fixed seed; more with `FFR_FUZZ_CASES=20000 [FFR_FUZZ_SEED=7] cargo test
//! --release --test fuzz_studies -- --nocapture` (the case in progress is
//! kept in `$TMPDIR/ffr-fuzz-studies-PID/fuzz.toml`; a failure prints it).

use ffr::scene::SceneValue;
use ffr_cli::reference::{Reference, MAX_REFERENCE_VALUES};
use ffr_cli::sweep::{self, cases, Study};
use proptest::prelude::RngExt;
use proptest::test_runner::{RngAlgorithm, TestRng};
use std::alloc::{GlobalAlloc, Layout, System as Sys};
use std::cell::Cell;
use std::path::{Path, PathBuf};

const DEFAULT_CASES: usize = 600;
/// One case in this many runs one of its study's cases.
const RUN_EVERY: usize = 3;
/// Steps a case run may take.
const MAX_STEPS: f64 = 200.0;
/// Heap that may be live at once while a case is read and run (the
/// references alone may hold 128 MiB; the fuzzed ones are small).
const MAX_LIVE_BYTES: isize = 256 << 20;

// A counting allocator, per thread: the heap a thread holds (what it
// allocated less what it freed) and its peak since the last reset.
struct Counting;
thread_local! {
    static LIVE: Cell<isize> = const { Cell::new(0) };
    static PEAK: Cell<isize> = const { Cell::new(0) };
}

fn add(n: isize) {
    let _ = LIVE.try_with(|l| {
        let now = l.get() + n;
        l.set(now);
        let _ = PEAK.try_with(|p| p.set(p.get().max(now)));
    });
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let p = Sys.alloc(l);
        if !p.is_null() {
            add(l.size() as isize);
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        add(-(l.size() as isize));
        Sys.dealloc(p, l)
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        let q = Sys.realloc(p, l, n);
        if !q.is_null() {
            add(n as isize - l.size() as isize);
        }
        q
    }
}

#[global_allocator]
static A: Counting = Counting;

/// Heap this thread holds now, and its peak since then: (live, peak).
fn reset_peak() -> isize {
    let live = LIVE.with(Cell::get);
    PEAK.with(|p| p.set(live));
    live
}

fn peak() -> isize {
    PEAK.with(Cell::get)
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The seed studies, their scene named by file name (copied beside them).
fn seeds() -> Vec<String> {
    let bench = std::fs::read_to_string(root().join("bench/sweep/spin_up_40.toml"))
        .unwrap()
        .replace("../../scenes/spin_up.toml", "spin_up.toml");
    let docs = std::fs::read_to_string(root().join("docs/sweep.md")).unwrap();
    // The first TOML block of docs/sweep.md, comments uncommented.
    let start = docs.find("```toml\n").unwrap() + "```toml\n".len();
    let end = start + docs[start..].find("```").unwrap();
    let example = docs[start..end]
        .lines()
        .map(|l| {
            l.strip_prefix("# \"")
                .map_or(l.to_string(), |r| format!("\"{r}"))
        })
        .collect::<Vec<_>>()
        .join("\n")
        .replace("reference.csv", "ref.csv");
    let pendulum = "scene = \"pendulum.toml\"\n[axes]\n\"bodies.bar.params.e\" = { from = 5e10, to = 7e10, steps = 3 }\n\"joints.0.b\" = [\"bar\"]\ngravity = [[0.0, -9.81], [0.0, -1.62]]\n\"integrator.rho_inf\" = { uniform = [0.5, 1.0], samples = 2, seed = 3 }\n[collect]\nangle_min = { output = \"angle\", stat = \"min\" }\nenergy = { output = \"energy\", stat = \"absmax\" }\ntip = { output = \"tip_y\", stat = \"max_abs_error\", reference = \"pref.csv\", column = \"tip_y\" }\n".to_string();
    vec![bench, example, pendulum]
}

/// Byte ranges `(start, end)` of tokens in a text.
type Spans = Vec<(usize, usize)>;

/// Spans of number literals and of basic strings in `text`.
fn tokens(text: &str) -> (Spans, Spans) {
    let b = text.as_bytes();
    let (mut nums, mut strs) = (Vec::new(), Vec::new());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c == b'#' {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        if c == b'"' {
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

const STRINGS: [&str; 30] = [
    "joints.0.drive.omega",
    "joints.00.drive.omega",
    "joints.0.drive",
    "joints.0",
    "joints.1.drive.omega",
    "joints.0.drive.ramp",
    "bodies.beam.elements",
    "bodies.beam",
    "bodies.beam.params.e",
    "bodies.bar.params.e",
    "t_end",
    "dt",
    "integrator.kind",
    "joints.0.dr\\u202eive.omega",
    "joints\\u001b]0;X\\u0007.0",
    "bodies.be\\nam.elements",
    "a..b",
    "",
    "min",
    "max_error",
    "max_abs_error",
    "median",
    "tip_transverse",
    "tip_axial",
    "angle",
    "ref.csv",
    "dup.csv",
    "bad.csv",
    "nowhere.csv",
    ".",
];

const LINES: [&str; 22] = [
    "t_end = { from = -1e308, to = 1e308, steps = 3 }",
    "dt = { uniform = [-1e308, 1e308], samples = 2, seed = 1 }",
    "\"joints.0.drive.omega\" = { normal = [1e308, 1e308], samples = 5, seed = 2 }",
    "\"joints.0.drive.omega\" = { normal = [0.0, 1e300], samples = 3, seed = 9 }",
    "\"joints.00.drive.omega\" = [1.0]",
    "\"joints.0.drive\" = [{ angle = \"spin-up\", omega = 2.0, ramp = 1.0 }]",
    "\"joints.0\" = [1.0]",
    "t_end = { from = 1, to = 9223372036854775807, step = 1 }",
    "t_end = { from = -9223372036854775808, to = 9223372036854775807, step = 9223372036854775807 }",
    "\"bodies.beam.elements\" = { from = 1, to = 100000, step = 1 }",
    "dt = { from = 1e-3, to = 2e-3, steps = 100000 }",
    "t_end = { uniform = [0.01, 0.02], samples = 100000, seed = 0 }",
    "t_end = { samples = 3, seed = -1, uniform = [1.0, 2.0] }",
    "t_end = []",
    "t_end = {}",
    "t_end = [1979-05-27]",
    "e9 = { output = \"tip_transverse\", stat = \"max_error\", reference = \"ref.csv\" }",
    "e8 = { output = \"tip_transverse\", stat = \"max_abs_error\", reference = \"dup.csv\" }",
    "e7 = { output = \"tip_axial\", stat = \"max_error\", reference = \"bad.csv\", column = \"tip_axial\" }",
    "e6 = { output = \"tip_axial\", stat = \"max_error\", reference = \".\" }",
    "e5 = { output = \"tip_axial\", stat = \"min\", column = \"x\" }",
    "\"x\\u202e\" = { output = \"tip_axial\", stat = \"min\" }",
];

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
            0..=2 if !nums.is_empty() => {
                let (s, e) = *pick(rng, &nums);
                let old: f64 = t[s..e].replace('_', "").parse().unwrap_or(1.0);
                let new = match rng.random_range(0..7) {
                    0 => format!("{:e}", old * 10f64.powi(rng.random_range(-12..=12))),
                    1 => format!("{:e}", -old),
                    2 => "0".into(),
                    3 => pick(
                        rng,
                        &[
                            "1e308", "-1e308", "1e-308", "nan", "inf", "-inf", "1e9", "-1",
                        ],
                    )
                    .to_string(),
                    4 => pick(
                        rng,
                        &[
                            "100000",
                            "100001",
                            "9223372036854775807",
                            "-9223372036854775808",
                            "2",
                        ],
                    )
                    .to_string(),
                    5 => format!("{}", rng.random_range(0..300)),
                    _ => format!("{:e}", old * 2.0),
                };
                t.replace_range(s..e, &new);
            }
            3..=5 if !strs.is_empty() => {
                let (s, e) = *pick(rng, &strs);
                let inner = t[s + 1..e.saturating_sub(1).max(s + 1)].to_string();
                let new = match rng.random_range(0..4) {
                    0 => inner.repeat(rng.random_range(2..40)),
                    1 => format!("{inner}\\u0007"),
                    _ => pick(rng, &STRINGS).to_string(),
                };
                t.replace_range(s..e, &format!("\"{}\"", new.replace('"', "")));
            }
            6 | 7 => {
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
            _ => {
                // An axis after `[axes]` or a figure after `[collect]`, or
                // anywhere.
                let line = *pick(rng, &LINES);
                let lines: Vec<&str> = t.lines().collect();
                let section = if line.contains("output") {
                    "[collect]"
                } else {
                    "[axes]"
                };
                let k = match (
                    rng.random_range(0..4),
                    lines.iter().position(|l| *l == section),
                ) {
                    (0, _) | (_, None) => rng.random_range(0..=lines.len()),
                    (_, Some(i)) => i + 1,
                };
                let mut out: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
                out.insert(k, line.to_string());
                t = out.join("\n");
            }
        }
    }
    t
}

/// No control (but `\n` where allowed) or bidi/invisible character raw.
fn raw_char(s: &str) -> Option<char> {
    s.chars().find(|&c| {
        c.is_control()
            || ('\u{200b}'..='\u{200f}').contains(&c)
            || ('\u{2028}'..='\u{202e}').contains(&c)
            || ('\u{2066}'..='\u{2069}').contains(&c)
    })
}

/// Whether two keys reach one place (an index by its number), checked
/// here on their own.
fn same_place(a: &str, b: &str) -> bool {
    let norm = |k: &str| -> Vec<String> {
        k.split('.')
            .map(|s| match s.parse::<u128>() {
                Ok(i) if s.bytes().all(|c| c.is_ascii_digit()) => i.to_string(),
                _ => s.to_string(),
            })
            .collect()
    };
    let (x, y) = (norm(a), norm(b));
    let n = x.len().min(y.len());
    x[..n] == y[..n]
}

#[derive(Debug, Default)]
struct Counts {
    refused: usize,
    read: usize,
    ran: usize,
    failed: usize,
}

fn check_study(study: &Study) -> Result<(), String> {
    let n = cases::count(&study.axes);
    if n == 0 || n > sweep::MAX_CASES {
        return Err(format!("{n} cases"));
    }
    for (i, a) in study.axes.iter().enumerate() {
        if a.values.is_empty() {
            return Err(format!("axis `{}` without values", a.key));
        }
        for v in &a.values {
            if let SceneValue::Float(x) = v {
                if !x.is_finite() {
                    return Err(format!("axis `{}` has the value {x}", a.key));
                }
            }
        }
        if let Some(b) = study.axes[..i].iter().find(|b| same_place(&b.key, &a.key)) {
            return Err(format!("axes `{}` and `{}` on one place", b.key, a.key));
        }
    }
    // Every case's values, at the ends and in the middle.
    for c in [0, n / 2, n - 1] {
        if cases::values(&study.axes, c).len() != study.axes.len() {
            return Err(format!("case {c} has not one value per axis"));
        }
    }
    let header = sweep::results::header(study);
    for (i, h) in header.iter().enumerate() {
        if header[..i].contains(h) {
            return Err(format!("column `{h}` twice in the header"));
        }
        if let Some(c) = raw_char(h) {
            return Err(format!("raw {c:?} in the header"));
        }
    }
    let mut refs: Vec<&std::sync::Arc<Reference>> = Vec::new();
    for f in &study.figures {
        if let Some((r, column)) = &f.reference {
            if r.column(column).is_none() {
                return Err(format!("figure `{}` has no column `{column}`", f.name));
            }
            if !refs.iter().any(|x| std::sync::Arc::ptr_eq(x, r)) {
                refs.push(r);
            }
        }
    }
    let held: usize = refs.iter().map(|r| r.numbers()).sum();
    if held > MAX_REFERENCE_VALUES {
        return Err(format!("references hold {held} numbers"));
    }
    Ok(())
}

/// Run one case of `study` if it is small; `None` if it is not.
fn run_one(study: &Study, rng: &mut TestRng) -> Option<Result<bool, String>> {
    let mut study = study.clone();
    study.scene.set("t_end", 0.05.into()).ok()?;
    let n = cases::count(&study.axes);
    let case = rng.random_range(0..n);
    let mut scene = study.scene.clone();
    for (a, v) in study.axes.iter().zip(cases::values(&study.axes, case)) {
        scene.set(&a.key, v.clone()).ok()?;
    }
    let spec = scene.spec().ok()?;
    if !(spec.t_end / spec.dt <= MAX_STEPS) {
        return None;
    }
    let big = spec.bodies.iter().any(|b| match &b.kind {
        ffr_spec::scene::BodyKind::Flexible(f) => f.elements > 32,
        _ => false,
    });
    if big {
        return None;
    }
    let r = sweep::run_case(&study, case);
    Some(match &r.failure {
        None if r.figures.len() != study.figures.len() => Err(format!(
            "{} figures for {}",
            r.figures.len(),
            study.figures.len()
        )),
        None => match r.figures.iter().find(|x| !x.is_finite()) {
            Some(x) => Err(format!("case {case} ok with the figure {x}")),
            None => Ok(true),
        },
        Some(m) if m.is_empty() => Err("a failed case without a message".into()),
        Some(m) => match raw_char(m) {
            Some(c) => Err(format!("raw {c:?} in the failed case's message {m:?}")),
            None => Ok(false),
        },
    })
}

/// The directory the cases are written to, with the scenes and references.
fn workdir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("ffr-fuzz-studies-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let scenes = root().join("scenes");
    for s in ["spin_up.toml", "pendulum.toml"] {
        std::fs::copy(scenes.join(s), d.join(s)).unwrap();
    }
    // References: the spin-up's outputs over 0–20 s, the pendulum's tip.
    let mut r = String::from("t,tip_axial,tip_transverse\n");
    let mut p = String::from("t,tip_x,tip_y\n");
    for k in 0..=400 {
        let t = k as f64 * 0.05;
        r.push_str(&format!("{t:?},{:?},{:?}\n", -1e-3 * t, -0.1 * t.sin()));
        p.push_str(&format!("{t:?},{:?},{:?}\n", t.cos(), -t.sin()));
    }
    std::fs::write(d.join("ref.csv"), &r).unwrap();
    std::fs::write(d.join("pref.csv"), &p).unwrap();
    std::fs::write(
        d.join("dup.csv"),
        "t,tip_transverse,tip_transverse\n0,1,2\n30,1,2\n",
    )
    .unwrap();
    std::fs::write(
        d.join("bad.csv"),
        "t,tip_axial,tip_transverse\n0,0,0\n1,nan,0\n",
    )
    .unwrap();
    d
}

#[test]
fn fuzz_studies() {
    let cases: usize = std::env::var("FFR_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(DEFAULT_CASES);
    let seed: u64 = std::env::var("FFR_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(36);
    let dir = workdir();
    let texts = seeds();
    let mut seed_bytes = [0u8; 32];
    seed_bytes[..8].copy_from_slice(&seed.to_le_bytes());
    let mut rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes);
    let path = dir.join("fuzz.toml");
    let shown = path.display().to_string();
    let mut counts = Counts::default();
    let mut worst_peak = 0isize;
    let start = std::time::Instant::now();
    for case in 0..cases {
        let src = rng.random_range(0..texts.len());
        let text = mutate(&mut rng, &texts[src]);
        std::fs::write(&path, &text).unwrap();
        let base = reset_peak();
        let read = std::panic::catch_unwind(|| sweep::read(&path));
        let fail = |why: String| -> ! {
            panic!("case {case} (seed {seed}): {why}\n--- study ---\n{text}\n---")
        };
        let study = match read {
            Err(_) => fail("the study reader panicked".into()),
            Ok(Err(e)) => {
                let m = e.to_string();
                if m.is_empty() || m.contains('\n') {
                    fail(format!("refusal not one line: {m:?}"));
                }
                if !m.starts_with(&shown) {
                    fail(format!("refusal without the study file: {m}"));
                }
                if let Some(c) = raw_char(&m) {
                    fail(format!("raw {c:?} in the refusal {m:?}"));
                }
                if m.chars().count() > shown.chars().count() + 2200 {
                    fail(format!("a refusal of {} characters", m.chars().count()));
                }
                counts.refused += 1;
                None
            }
            Ok(Ok(s)) => {
                if let Err(why) = check_study(&s) {
                    fail(why);
                }
                counts.read += 1;
                Some(s)
            }
        };
        if let Some(study) = study.filter(|_| case % RUN_EVERY == 0) {
            match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                run_one(&study, &mut rng)
            })) {
                Err(_) => fail("running a case panicked".into()),
                Ok(None) => {}
                Ok(Some(Err(why))) => fail(why),
                Ok(Some(Ok(true))) => counts.ran += 1,
                Ok(Some(Ok(false))) => counts.failed += 1,
            }
        }
        let p = peak() - base;
        worst_peak = worst_peak.max(p);
        if p > MAX_LIVE_BYTES {
            fail(format!("{p} bytes of heap live at once"));
        }
    }
    println!(
        "fuzz_studies: {cases} cases (seed {seed}) in {:.1} s: {counts:?}; peak heap of a case {:.1} MiB",
        start.elapsed().as_secs_f64(),
        worst_peak as f64 / (1 << 20) as f64
    );
    assert!(counts.refused > 0 && counts.read > 0, "{counts:?}");
}

/// Issue 36: a reference CSV cost ~26 times its size in memory (the whole
/// file, every column as numbers, vectors grown by doubling). A 10 MB CSV
/// of 20 columns of which a study names one: the heap held at once while
/// it is read is within the numbers stored (t and that column) and the
/// reader's buffers, below the file's own size.
#[test]
fn a_reference_costs_the_columns_it_stores() {
    let dir = std::env::temp_dir().join(format!("ffr-fuzz-ref-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("wide.csv");
    let rows = 200_000;
    let mut text = String::from("t,tip_transverse");
    for c in 0..19 {
        text.push_str(&format!(",c{c}"));
    }
    text.push('\n');
    for k in 0..rows {
        text.push_str(&format!("{:?},{:?}", k as f64 * 1e-4, k as f64 * 1e-6));
        text.push_str(&",0.125".repeat(19));
        text.push('\n');
    }
    std::fs::write(&p, &text).unwrap();
    let size = text.len() as isize;
    drop(text);
    let base = reset_peak();
    let r = Reference::read_columns(&p, Some(&["tip_transverse"]), 0).unwrap();
    let used = peak() - base;
    let stored = (rows * 2 * 8) as isize;
    assert_eq!(r.numbers(), rows * 2);
    assert_eq!(r.values[0][rows - 1], (rows - 1) as f64 * 1e-6);
    assert!(
        used < stored + stored / 4 + (256 << 10),
        "{used} bytes of heap for {stored} bytes of numbers from a {size}-byte file"
    );
    assert!(used < size / 2, "{used} bytes for a {size}-byte file");
    let _ = std::fs::remove_dir_all(&dir);
}
