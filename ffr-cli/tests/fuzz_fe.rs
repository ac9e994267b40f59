//! Mutation fuzzing of FE bodies (issue 36): the node file, the Matrix
//! Market mass and stiffness files and the scene's FE keys of a small FE
//! body (a five-node truss bipyramid, its stiffness and lumped mass made
//! here), mutated at the level of their text, then loaded and run.
//!
//! Mutations (1–3 per case, from a seeded `proptest` RNG) in one of the four
//! texts: a number scaled by `10^k` (`k` in −300..300), negated, set to 0,
//! to `nan`/`inf`/`1e999`, to a subnormal, or to a 25-digit integer; a token
//! replaced by garbage, control characters, an escape sequence or a bidi
//! override; a line deleted, duplicated, moved or cut; the Matrix Market
//! banner or size line changed; FE keys inserted (`reference = "free"`,
//! `interface`, `boundary_nodes`, `reduction`, `stiffness_scale`, `modes`).
//!
//! For every case, in a thread of its own with a counting allocator:
//! - no panic;
//! - either a refusal that is one line without control characters, at most
//!   600 characters, or a scene that loads and runs 20 steps to finite
//!   outputs (or stops with a failure that says why);
//! - at most [`MAX_LIVE_BYTES`] of heap live at any time.
//!
//! `cargo test --test fuzz_fe` runs [`DEFAULT_CASES`] cases with a fixed
//! seed; more with `FFR_FUZZ_CASES=20000 [FFR_FUZZ_SEED=7] cargo test
//! --release -p ffr-cli --test fuzz_fe -- --nocapture`.

mod live_heap;

use ffr::scene;
use proptest::prelude::RngExt;
use proptest::test_runner::{RngAlgorithm, TestRng};

const DEFAULT_CASES: usize = 300;
/// Heap that may be live at once while a case runs.
const MAX_LIVE_BYTES: usize = 256 << 20;

/// The bipyramid: a triangle in the plane x = 0.5 and two apexes.
const NODES: [[f64; 3]; 5] = [
    [0.5, 0.0, 0.0],
    [0.5, 0.1, 0.0],
    [0.5, 0.05, 0.0866],
    [0.0, 0.05, 0.03],
    [1.0, 0.05, 0.03],
];

/// The stiffness of bars (EA = 1e6 N) between every pair of nodes.
fn truss_stiffness() -> Vec<Vec<f64>> {
    let n = 3 * NODES.len();
    let mut k = vec![vec![0.0; n]; n];
    for a in 0..NODES.len() {
        for b in a + 1..NODES.len() {
            let d: Vec<f64> = (0..3).map(|i| NODES[b][i] - NODES[a][i]).collect();
            let l = d.iter().map(|x| x * x).sum::<f64>().sqrt();
            let e: Vec<f64> = d.iter().map(|x| x / l).collect();
            for i in 0..3 {
                for j in 0..3 {
                    let v = 1e6 / l * e[i] * e[j];
                    k[3 * a + i][3 * a + j] += v;
                    k[3 * b + i][3 * b + j] += v;
                    k[3 * a + i][3 * b + j] -= v;
                    k[3 * b + i][3 * a + j] -= v;
                }
            }
        }
    }
    k
}

/// The lower triangle of `a` as a `symmetric` Matrix Market file.
fn mtx(a: &[Vec<f64>]) -> String {
    let n = a.len();
    let mut entries = Vec::new();
    for j in 0..n {
        for i in j..n {
            if a[i][j] != 0.0 {
                entries.push(format!("{} {} {:e}", i + 1, j + 1, a[i][j]));
            }
        }
    }
    format!(
        "%%MatrixMarket matrix coordinate real symmetric\n% made by fuzz_fe\n{n} {n} {}\n{}\n",
        entries.len(),
        entries.join("\n")
    )
}

fn files() -> [(&'static str, String); 4] {
    let n = 3 * NODES.len();
    let mut m = vec![vec![0.0; n]; n];
    for (i, row) in m.iter_mut().enumerate() {
        row[i] = 0.2 + 0.1 * (i / 3) as f64;
    }
    let nodes: String = NODES
        .iter()
        .map(|p| format!("{},{},{}\n", p[0], p[1], p[2]))
        .collect();
    let scene = r#"description = "fuzzed FE body"
dimension = 3
gravity = [0.0, -9.81, 0.0]
t_end = 0.02
dt = 1e-3

[bodies.truss]
fe = { nodes = "nodes.csv", mass = "mass.mtx", stiffness = "stiffness.mtx" }
reference = "clamped"
interface = [0, 1, 2]
modes = 2

[[joints]]
kind = "revolute"
a = "ground@[0.0, 0.0, 0.0]"
b = "truss"

[[outputs]]
name = "tip_y"
kind = "position"
at = "truss@node=4"
component = "y"

[[outputs]]
name = "energy"
kind = "energy"
"#;
    [
        ("scene.toml", scene.to_string()),
        ("nodes.csv", format!("x,y,z\n{nodes}")),
        ("mass.mtx", mtx(&m)),
        ("stiffness.mtx", mtx(&truss_stiffness())),
    ]
}

fn pick<'a, T>(rng: &mut TestRng, xs: &'a [T]) -> &'a T {
    &xs[rng.random_range(0..xs.len())]
}

/// Byte spans of number-like tokens (digits, signs, `.`, `e`).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() && (i == 0 || !b[i - 1].is_ascii_alphabetic()) {
            let s = if i > 0 && b[i - 1] == b'-' { i - 1 } else { i };
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b"+-.".contains(&b[i])) {
                i += 1;
            }
            out.push((s, i));
        } else {
            i += 1;
        }
    }
    out
}

const GARBAGE: &[&str] = &[
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e999",
    "1e-310",
    "4.9e-324",
    "99999999999999999999999",
    "0",
    "-0.0",
    "three",
    "1,5",
    "0x10",
    "",
    " ",
    "\u{1b}]0;owned\u{7}\u{1b}[2J",
    "\u{202e}evil",
    "a\nb",
    "\u{0}",
];

const KEYS: &[&str] = &[
    "reference = \"free\"\n",
    "reference = \"pinned\"\n",
    "interface = [0, 1, 2, 3, 4]\n",
    "interface = [4]\n",
    "interface = []\n",
    "interface = [0, 0]\n",
    "interface = [99999999999]\n",
    "boundary_nodes = [4]\n",
    "boundary_nodes = [0]\n",
    "reduction = \"craig-bampton\"\n",
    "stiffness_scale = 1e300\n",
    "stiffness_scale = 1e-300\n",
    "stiffness_scale = 0.0\n",
    "modes = 1000\n",
    "modes = 0\n",
    "static_modes = false\n",
    "segments = 2\n",
    "shape = \"beam3\"\n",
    "elastic = [1.0]\n",
];

fn mutate(rng: &mut TestRng, text: &str, which: usize) -> String {
    let mut t = text.to_string();
    let n = rng.random_range(1..=3);
    for _ in 0..n {
        let nums = numbers(&t);
        match rng.random_range(0..9) {
            0..=2 if !nums.is_empty() => {
                let (s, e) = *pick(rng, &nums);
                let old: f64 = t[s..e].parse().unwrap_or(1.0);
                let new = match rng.random_range(0..5) {
                    0 => format!("{:e}", old * 10f64.powi(rng.random_range(-300..300))),
                    1 => format!("{:e}", -old),
                    2 => "0".to_string(),
                    _ => pick(rng, GARBAGE).to_string(),
                };
                t.replace_range(s..e, &new);
            }
            3 => {
                // A line deleted, duplicated, moved or cut.
                let mut lines: Vec<String> = t.lines().map(str::to_string).collect();
                if lines.is_empty() {
                    continue;
                }
                let i = rng.random_range(0..lines.len());
                match rng.random_range(0..4) {
                    0 => {
                        lines.remove(i);
                    }
                    1 => {
                        let l = lines[i].clone();
                        lines.insert(i, l);
                    }
                    2 => {
                        let l = lines.remove(i);
                        let j = rng.random_range(0..=lines.len());
                        lines.insert(j, l);
                    }
                    _ => {
                        let l = &mut lines[i];
                        let cut = rng.random_range(0..=l.len());
                        let cut = (0..=cut)
                            .rev()
                            .find(|c| l.is_char_boundary(*c))
                            .unwrap_or(0);
                        l.truncate(cut);
                    }
                }
                t = lines.join("\n");
            }
            4 if which == 0 => {
                // An FE key inserted into the body's table.
                let at = t
                    .find("modes = 2\n")
                    .map_or(t.len(), |i| i + "modes = 2\n".len());
                let key: &&str = pick(rng, KEYS);
                t.insert_str(at, key);
            }
            5 if which >= 2 => {
                let banner = pick(
                    rng,
                    &[
                        "%%MatrixMarket matrix coordinate real general",
                        "%%MatrixMarket matrix array real general",
                        "%%MatrixMarket matrix coordinate complex symmetric",
                        "%%MatrixMarket matrix coordinate pattern symmetric",
                        "% no banner",
                    ],
                );
                if let Some(end) = t.find('\n') {
                    t.replace_range(..end, banner);
                }
            }
            6 => {
                // Garbage at a random place.
                let mut at = rng.random_range(0..=t.len());
                while !t.is_char_boundary(at) {
                    at -= 1;
                }
                let junk: &&str = pick(rng, GARBAGE);
                t.insert_str(at, junk);
            }
            7 if which >= 2 => {
                // An entry added out of place or repeated.
                let i = rng.random_range(1..20);
                let j = rng.random_range(1..20);
                t.push_str(&format!("\n{i} {j} 1.5e0\n"));
            }
            _ => {}
        }
    }
    t
}

/// One case in its own directory: `Err` with what went wrong.
fn case(dir: &std::path::Path, texts: &[(&str, String)]) -> Result<&'static str, String> {
    std::fs::create_dir_all(dir).unwrap();
    for (name, text) in texts {
        std::fs::write(dir.join(name), text).unwrap();
    }
    let path = dir.join("scene.toml");
    let check_message = |e: &str| -> Result<(), String> {
        if e.contains('\n') || e.chars().any(|c| c.is_control()) || e.chars().count() > 600 {
            return Err(format!("a message not one short escaped line: {e:?}"));
        }
        Ok(())
    };
    let s = match scene::load(&path) {
        Err(e) => {
            check_message(&e.to_string())?;
            return Ok("refused");
        }
        Ok(s) => s,
    };
    match scene::run(&s) {
        Err(e) => {
            check_message(&e.to_string())?;
            Ok("run refused")
        }
        Ok(r) => {
            if let Some(f) = &r.failed {
                check_message(&f.to_string())?;
                return Ok("run failed");
            }
            for (name, c) in r.names.iter().zip(&r.columns) {
                if c.iter().any(|x| !x.is_finite()) {
                    return Err(format!("output {name} not finite in a run that succeeded"));
                }
            }
            if (r.t.last().copied().unwrap_or(0.0) - s.t_end).abs() > 1e-9 {
                return Err("a run that succeeded stopped early".into());
            }
            Ok("ran")
        }
    }
}

#[test]
fn mutated_fe_files_and_keys_are_refused_or_run() {
    let cases: usize = std::env::var("FFR_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_CASES);
    let seed: u64 = std::env::var("FFR_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(36);
    let mut seed_bytes = [0u8; 32];
    seed_bytes[..8].copy_from_slice(&seed.to_le_bytes());
    let mut rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes);
    let base = files();
    // The unmutated body loads and runs.
    let root = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz_fe");
    assert_eq!(case(&root.join("base"), &base), Ok("ran"));
    let mut counts = std::collections::BTreeMap::<&str, usize>::new();
    for i in 0..cases {
        let which = rng.random_range(0..base.len());
        let mut texts = base.clone();
        texts[which].1 = mutate(&mut rng, &base[which].1, which);
        let dir = root.join("case");
        let _ = std::fs::remove_dir_all(&dir);
        let d = dir.clone();
        let t = texts.clone();
        let heap = live_heap::mark();
        let outcome = std::thread::spawn(move || case(&d, &t))
            .join()
            .map(|r| (r, heap.peak()));
        let (r, peak) = match outcome {
            Ok(x) => x,
            Err(_) => panic!(
                "case {i} (seed {seed}) panicked; its files are in {}",
                dir.display()
            ),
        };
        match r {
            Ok(what) => *counts.entry(what).or_default() += 1,
            Err(e) => panic!(
                "case {i} (seed {seed}, {} mutated): {e}; files in {}",
                texts[which].0,
                dir.display()
            ),
        }
        assert!(
            peak <= MAX_LIVE_BYTES,
            "case {i} (seed {seed}): {peak} bytes live, more than {MAX_LIVE_BYTES}"
        );
    }
    println!("{cases} cases (seed {seed}): {counts:?}");
    assert!(counts.get("refused").copied().unwrap_or(0) > 0);
}
