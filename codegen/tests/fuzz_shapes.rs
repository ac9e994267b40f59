//! Fuzzing of shape files on stable Rust (proptest): generated shape files,
//! valid and near-valid, through the whole generator.
//!
//! Inputs: polynomial strings over the grammar of [`ffr_codegen::expr`]
//! (valid entries, random expressions, deep nesting, long sign runs, big
//! exponents and numbers, odd Unicode, control characters), mutated entries,
//! shape structures (dimension, coordinates, rows; valid and near-valid),
//! random TOML values and byte-level mutations of the whole text.
//!
//! Each shape is taken as a body (1–3 elements, any reference condition,
//! one in five lumped) and as element kernels (`generate_kernels`: one in
//! four with geometric stiffening, second or fourth order; a planar shape
//! in a spatial scene one time in four; frame free three times in four;
//! `ā ≡ 0` one time in four).
//!
//! For every input, in a thread with the default test stack (2 MiB):
//! - no panic and no stack overflow;
//! - the generator's work (parsing, exact invariants, kernel programs,
//!   literal check, emission) done within [`CASE_LIMIT`] (2 s of the case
//!   thread's CPU time; wall time on other systems than Linux), and the
//!   whole case within 30 s of wall time;
//! - either a clear error (non-empty, one line, `fuzz.toml:line:col: …` for
//!   a shape file that is refused; the same error from
//!   `BodySpec::exact_invariants` and `generate_kernels` for a body that is
//!   refused), or a body such that, at the command line's default
//!   parameters (accepted by `check_params`):
//!   - its exact invariants (`BodySpec::exact_invariants`, evaluated) are
//!     all finite, the mass positive, the `m_ff` diagonal positive
//!     (non-negative for the lumped formalism);
//!   - the kernels' coefficients are finite (what the runtime checks), the
//!     `element_invariants` program on a tape gives its exact polynomials
//!     (within 1e-12 of the sum of the magnitudes of their terms) for every
//!     element, and assembled, the same finiteness and `m_ff` diagonal;
//!   - every kernel (`mass`, `residual_elastic`, `tangent_elastic`,
//!     `energy`, `point_shape`, and `residual`, `tangent` for a free frame)
//!     is finite at a deformed, moving state in a rotating, accelerating
//!     frame;
//!   - its literals are finite (`check_literals`) and the emitted body file
//!     (`emit_body_file`) has a header of comment lines and parses
//!     (`syn::parse_file`).
//!
//! `cargo test -p ffr-codegen --test fuzz_shapes` runs [`DEFAULT_CASES`]
//! cases with a fixed seed. More:
//!
//! ```sh
//! FFR_FUZZ_CASES=100000 cargo test -p ffr-codegen --release --test fuzz_shapes -- --nocapture
//! FFR_FUZZ_CASES=100000 FFR_FUZZ_SEED=7 cargo test -p ffr-codegen --test fuzz_shapes -- --nocapture
//! ```
//!
//! The input of the case in progress is written to
//! `target/tmp/fuzz_current_case.toml` when `FFR_FUZZ_CASES` is set, so that
//! even an abort leaves its reproducer. `corpus` runs the reproducers of
//! issue 8 through the same checks.

mod common;

use common::{coefficient_values, eval_element, thread_cpu_time, Dense, Run, TapeBody};
use ffr_codegen::eom::OutArr;
use ffr_codegen::limits::{check_literals, check_params};
use ffr_codegen::program::Inputs;
use ffr_codegen::{
    emit_body_file, generate_kernels, BodySpec, EmitOptions, Error, Formalism, FrameModel,
    KernelModel, KernelOptions, KernelSet, Params, Reference, SceneDim, Shape, Stiffening,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Cases per run without `FFR_FUZZ_CASES`.
const DEFAULT_CASES: u32 = 600;

/// Longest the generator's work on a case may take (CPU time of its
/// thread), with or without geometric stiffening: the stiffening energy is
/// written in element scalars and its derivatives go through the chain
/// rule, so it no longer dominates. Measured in the test profile (5000 cases,
/// seed 8): the slowest case 0.64 s without stiffening, 0.74 s with
/// (12-coordinate spatial shapes, free frame), a third of the limit.
const CASE_LIMIT: Duration = Duration::from_secs(2);

/// A case still running after this is reported as a hang.
const HANG_LIMIT: Duration = Duration::from_secs(30);

/// The command line's default parameters (a 1 m steel bar, 10 mm square).
const DEFAULTS: Params = Params {
    length: 1.0,
    rho: 7850.0,
    area: 1e-4,
    iy: 1e-8 / 12.0,
    iz: 1e-8 / 12.0,
    e: 2.1e11,
    g: 8.1e10,
    j: 1.406e-8,
};

/// One generated input: the shape text, the body built from it and the
/// options of its kernels.
#[derive(Clone, Debug)]
struct Case {
    text: String,
    elements: usize,
    reference: Reference,
    formalism: Formalism,
    stiffening: Stiffening,
    /// Kernels for a spatial scene even if the shape is planar.
    spatial_scene: bool,
    free_frame: bool,
    zero_frame_acceleration: bool,
}

/// How a case ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Outcome {
    /// The shape file was refused.
    ShapeError,
    /// The shape was read; the body was refused (e.g. torsion not constant
    /// over the section).
    BodyError,
    /// Invariants computed, checked and emitted.
    Body,
}

// ---------------------------------------------------------------- strategies

fn select(items: &[&'static str]) -> BoxedStrategy<String> {
    prop::sample::select(items.to_vec())
        .prop_map(String::from)
        .boxed()
}

/// A small rational coefficient as a shape author writes it.
fn coefficient() -> BoxedStrategy<String> {
    prop_oneof![
        4 => (1i32..13).prop_map(|n| n.to_string()),
        2 => (1i32..13, 1i32..9).prop_map(|(a, b)| format!("{a}/{b}")),
        1 => (0i32..100, 0u32..100).prop_map(|(a, b)| format!("{a}.{b}")),
        1 => (1i32..10, -20i32..20).prop_map(|(a, e)| format!("{a}e{e}")),
    ]
    .boxed()
}

/// A valid-looking entry: a sum of terms `c · xi^a · (eta | zeta | 1)`, times
/// `l` for a rotation coordinate (the units of `S`), possibly in Hermite
/// style with parentheses. (Wrong powers of `l` come from [`mutate`] and
/// [`expression`].)
fn good_entry(spatial: bool, rotation: bool) -> BoxedStrategy<String> {
    let section = if spatial {
        select(&["", "", "", "*eta", "*zeta"])
    } else {
        select(&["", "", "", "*eta"])
    };
    let term = (
        coefficient(),
        0u32..5,
        Just(if rotation { "*l" } else { "" }),
        section,
        any::<bool>(),
    )
        .prop_map(|(c, a, l, s, neg)| {
            let x = match a {
                0 => String::new(),
                1 => "*xi".into(),
                a => format!("*xi^{a}"),
            };
            format!("{}{c}{x}{l}{s}", if neg { "-" } else { "" })
        });
    let mut hermite = if rotation {
        vec![
            "l*(xi - 2*xi^2 + xi^3)",
            "(1 - 4*xi + 3*xi^2)*l*eta",
            "l*xi^2*(xi - 1)",
            "-l*(-xi^2 + xi^3)",
            "(2*xi - 3*xi^2)*l*eta",
        ]
    } else {
        vec![
            "1 - 3*xi^2 + 2*xi^3",
            "6*(xi - xi^2)*eta",
            "(1 - xi)^2*(1 + 2*xi)",
            "xi^2*(3 - 2*xi)",
            "1 - xi",
            "xi",
        ]
    };
    if spatial {
        hermite.extend(if rotation {
            ["(1 - 4*xi + 3*xi^2)*l*zeta", "-(1 - xi)*l*zeta"]
        } else {
            ["6*(xi^2 - xi)*zeta", "6*(xi - xi^2)*zeta"]
        });
    }
    prop_oneof![
        1 => Just("0".to_string()),
        6 => prop::collection::vec(term, 1..5).prop_map(|t| t.join(" + ").replace("+ -", "- ")),
        2 => prop::sample::select(hermite).prop_map(String::from),
    ]
    .boxed()
}

/// Near-valid and hostile leaves.
fn leaf() -> BoxedStrategy<String> {
    prop_oneof![
        6 => select(&["xi", "eta", "zeta", "l"]),
        4 => (0u32..20).prop_map(|n| n.to_string()),
        1 => (0u32..1000, 0u32..100_000).prop_map(|(a, b)| format!("{a}.{b}")),
        1 => (1u32..10, -400i32..400).prop_map(|(a, e)| format!("{a}e{e}")),
        1 => (1usize..400).prop_map(|n| "9".repeat(n)),
        1 => (1usize..2000).prop_map(|n| format!("0.{}1", "0".repeat(n))),
        2 => select(&[
            "x", "Xi", "XI", "ξ", "sin(xi)", "exp(l)", "π", "1e", "1e+", "1.2.3", ".", "e5", "xi_",
            "l2", "ｘｉ", "\u{202e}xi", "\\n", "\"", "'", " ", "\u{0}", "\r", "\n", "NaN", "inf",
            "_", "()", "(", ")", "**", "^", "xi^", "1/0", "0/0", "1/xi", "xi/(1-1)", "--xi",
            "+-+xi", "1e999", "1e-999", "٣", "①", "\u{feff}", "\t", "xi xi", "2xi", "xi2",
            "0x10", "1_000", "∞", "√xi", "xi²",
        ]),
    ]
    .boxed()
}

/// An exponent after `^`: mostly small, sometimes hostile.
fn exponent() -> BoxedStrategy<String> {
    prop_oneof![
        6 => (0u32..5).prop_map(|n| n.to_string()),
        2 => (0u32..70).prop_map(|n| n.to_string()),
        1 => select(&[
            "64", "65", "2147483647", "2147483648", "4294967297", "-1", "0.5", "(2^31)", "",
            "999999999999999999999999", "0000000000000000000000002", "1e3", "xi", "-0",
        ]),
    ]
    .boxed()
}

/// Random expressions over the grammar, with hostile constructions.
fn expression() -> BoxedStrategy<String> {
    leaf()
        .prop_recursive(6, 48, 4, |inner| {
            prop_oneof![
                4 => (inner.clone(), select(&[" + ", " - ", "*", " * ", "-", "+"]), inner.clone())
                    .prop_map(|(a, o, b)| format!("{a}{o}{b}")),
                1 => (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("{a}/{b}")),
                2 => inner.clone().prop_map(|a| format!("({a})")),
                2 => (inner.clone(), exponent()).prop_map(|(a, e)| format!("({a})^{e}")),
                2 => (inner.clone(), exponent()).prop_map(|(a, e)| format!("{a}^{e}")),
                1 => inner.clone().prop_map(|a| format!("-{a}")),
                1 => (inner.clone(), 1usize..6, exponent()).prop_map(|(a, k, e)| {
                    let mut s = a;
                    for _ in 0..k {
                        s = format!("({s})^{e}");
                    }
                    s
                }),
                1 => (inner.clone(), 0usize..10_000)
                    .prop_map(|(a, n)| format!("{}{a}{}", "(".repeat(n), ")".repeat(n))),
                1 => (inner.clone(), 0usize..10_000).prop_map(|(a, n)| format!("{}{a}", "(".repeat(n))),
                1 => (inner.clone(), 0usize..60_000).prop_map(|(a, n)| format!("{}{a}", "-".repeat(n))),
                1 => (inner.clone(), 0usize..200)
                    .prop_map(|(a, n)| vec![a; n.max(1)].join("+")),
            ]
        })
        .boxed()
}

/// A character that may break things.
fn odd_char() -> BoxedStrategy<char> {
    prop_oneof![
        3 => select(&["(", ")", "^", "*", "/", "+", "-", ".", "e", "\"", "\\", "'", "[", "]",
                      "{", "}", "=", ",", "#", " ", "0", "9", "x", "l"])
            .prop_map(|s| s.chars().next().unwrap()),
        1 => any::<char>(),
        1 => prop::sample::select(vec!['\n', '\r', '\t', '\0', '\u{202e}', '\u{2028}', '\u{feff}', 'ξ', '\u{10ffff}']),
    ]
    .boxed()
}

/// `s` with a few random edits (delete, insert, duplicate, truncate).
fn mutate(s: BoxedStrategy<String>) -> BoxedStrategy<String> {
    (
        s,
        prop::collection::vec(
            (0u8..4, any::<prop::sample::Index>(), odd_char(), 0usize..8),
            1..4,
        ),
    )
        .prop_map(|(s, edits)| {
            let mut c: Vec<char> = s.chars().collect();
            for (kind, at, ch, n) in edits {
                let i = if c.is_empty() {
                    0
                } else {
                    at.index(c.len() + 1)
                };
                match kind {
                    0 if i < c.len() => {
                        c.remove(i);
                    }
                    1 => c.insert(i.min(c.len()), ch),
                    2 if i < c.len() => {
                        let end = (i + n).min(c.len());
                        let piece: Vec<char> = c[i..end].to_vec();
                        for (k, x) in piece.into_iter().enumerate() {
                            c.insert(end + k, x);
                        }
                    }
                    _ => c.truncate(i),
                }
            }
            c.into_iter().collect()
        })
        .boxed()
}

/// An entry of `S`.
fn entry(spatial: bool, rotation: bool) -> BoxedStrategy<String> {
    prop_oneof![
        10 => good_entry(spatial, rotation),
        3 => expression(),
        2 => mutate(good_entry(spatial, rotation)),
    ]
    .boxed()
}

/// A TOML basic string holding exactly `s`.
fn toml_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => out.push_str(&format!("\\u{:04X}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A random TOML value (for fields that expect something else).
fn toml_value() -> BoxedStrategy<String> {
    let atom = prop_oneof![
        any::<i64>().prop_map(|n| n.to_string()),
        any::<f64>().prop_map(|x| format!("{x:?}").replace("inf", "inf").replace("NaN", "nan")),
        any::<bool>().prop_map(|b| b.to_string()),
        Just("1979-05-27T07:32:00Z".to_string()),
        ".*".prop_map(|s: String| toml_string(&s)),
    ];
    prop_oneof![
        4 => atom.boxed(),
        1 => (1usize..3000).prop_map(|n| format!("{}1{}", "[".repeat(n), "]".repeat(n))),
        1 => (1usize..3000).prop_map(|n| format!("{}1{}", "{a=".repeat(n), "}".repeat(n))),
        1 => prop::collection::vec(any::<u8>(), 0..5).prop_map(|v| format!("{v:?}")),
    ]
    .boxed()
}

const PLANAR_KINDS: [&str; 3] = ["ux", "uy", "rz"];
const SPATIAL_KINDS: [&str; 6] = ["ux", "uy", "uz", "rx", "ry", "rz"];

/// How hostile a generated shape file is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    /// Valid structure and valid-looking entries: exercises the generator.
    Clean,
    /// Valid structure, entries from the whole grammar and mutations.
    Entries,
    /// Near-valid structure, random TOML values, damaged text.
    Structure,
}

/// A whole shape file: valid structure and entries, or hostile entries, or
/// near-valid structure with random values and byte-level damage.
fn shape_text() -> BoxedStrategy<String> {
    let mode = prop_oneof![
        5 => Just(Mode::Clean),
        3 => Just(Mode::Entries),
        2 => Just(Mode::Structure),
    ];
    let structure = (
        mode,
        any::<bool>(),
        prop::collection::vec(any::<bool>(), 6),
        any::<prop::sample::Index>(),
        prop_oneof![
            8 => Just("\"fuzzed\"".to_string()),
            1 => ".{0,80}".prop_map(|s: String| toml_string(&s)),
            1 => toml_value(),
        ],
        prop::collection::vec(0u8..8, 8),
    );
    structure
        .prop_flat_map(|(mode, spatial, pick, order, name, flaws)| {
            let kinds: Vec<&'static str> = if spatial {
                SPATIAL_KINDS
                    .iter()
                    .zip(&pick)
                    .filter(|(_, &p)| p)
                    .map(|(k, _)| *k)
                    .collect()
            } else {
                PLANAR_KINDS
                    .iter()
                    .zip(&pick)
                    .filter(|(_, &p)| p)
                    .map(|(k, _)| *k)
                    .collect()
            };
            let kinds = if kinds.is_empty() { vec!["uy"] } else { kinds };
            let mut coords: Vec<(String, i64, String)> = Vec::new();
            for node in 0..2 {
                for k in &kinds {
                    coords.push((format!("{k}{node}"), node, k.to_string()));
                }
            }
            let hostile = mode == Mode::Structure;
            let name = if hostile {
                name
            } else {
                "\"fuzzed\"".to_string()
            };
            // Near-valid structure, each flaw with probability 1/8.
            let flaw = |i: usize| hostile && flaws[i] == 0;
            if flaw(0) {
                coords[0].1 = 2;
            }
            if flaw(1) && coords.len() > 1 {
                coords[1].0 = coords[0].0.clone();
            }
            if flaw(2) {
                coords[0].2 = "uw".into();
            }
            if flaw(3) {
                coords.pop();
            }
            if flaw(4) {
                for i in 0..14 {
                    coords.push((format!("extra{i}"), (i % 2) as i64, "ux".into()));
                }
            }
            if flaw(7) {
                coords[0].0 = "a\nfn main() {}".into();
            }
            let n = coords.len();
            let rot = order.index(n.max(1));
            coords.rotate_left(rot);
            let dim: i64 = match flaws[5] {
                0 if hostile => 4,
                1 if hostile => 1 << 40,
                _ if spatial => 3,
                _ => 2,
            };
            let rows = if spatial { 3 } else { 2 };
            let width = if flaw(6) { n + 1 } else { n };
            // One strategy per entry: the power of `l` depends on the column.
            let column = |j: usize| {
                let rotation = coords.get(j).is_some_and(|c| c.2.starts_with('r'));
                if mode == Mode::Clean {
                    good_entry(spatial, rotation)
                } else {
                    entry(spatial, rotation)
                }
            };
            let entries: Vec<Vec<BoxedStrategy<String>>> = (0..rows)
                .map(|_| (0..width).map(column).collect())
                .collect();
            let field = if hostile {
                (0u8..8).boxed()
            } else {
                Just(99u8).boxed()
            };
            let text_flaw = if hostile {
                (0u8..5).boxed()
            } else {
                Just(99u8).boxed()
            };
            (
                Just((name, dim, coords)),
                entries,
                field,
                toml_value(),
                text_flaw,
            )
        })
        .prop_map(|((name, dim, coords), entries, field, value, text_flaw)| {
            let mut t = String::new();
            t.push_str(&format!("name = {name}\n"));
            t.push_str(&format!(
                "dimension = {}\n",
                if field == 0 {
                    value.clone()
                } else {
                    dim.to_string()
                }
            ));
            if field == 1 {
                t.push_str(&format!("description = {value}\n"));
            } else {
                t.push_str("description = \"fuzzed shape\"\n");
            }
            t.push_str("coordinates = [\n");
            for (i, (n, node, kind)) in coords.iter().enumerate() {
                let node = if field == 2 && i == 0 {
                    value.clone()
                } else {
                    node.to_string()
                };
                t.push_str(&format!(
                    "  {{ name = {}, node = {node}, kind = {} }},\n",
                    toml_string(n),
                    toml_string(kind)
                ));
            }
            t.push_str("]\n[S]\n");
            for (r, row) in ["x", "y", "z"].iter().zip(&entries) {
                let items: Vec<String> = row.iter().map(|e| toml_string(e)).collect();
                if field == 3 && *r == "y" {
                    t.push_str(&format!("y = {value}\n"));
                } else {
                    t.push_str(&format!("{r} = [{}]\n", items.join(", ")));
                }
            }
            if field == 4 {
                t.push_str(&format!("extra = {value}\n"));
            }
            (t, text_flaw)
        })
        .prop_flat_map(|(t, text_flaw)| {
            // Byte-level damage to the text: truncation, insertions, deletions.
            let n = t.len();
            (Just(t), Just(text_flaw), 0..=n, odd_char(), 0usize..50)
        })
        .prop_map(|(t, flaw, at, ch, len)| {
            let at = (0..=at).rev().find(|&i| t.is_char_boundary(i)).unwrap_or(0);
            match flaw {
                0 => t[..at].to_string(),
                1 => format!("{}{ch}{}", &t[..at], &t[at..]),
                2 => {
                    let end = (at + len..=t.len())
                        .find(|&i| t.is_char_boundary(i))
                        .unwrap_or(t.len());
                    format!("{}{}", &t[..at], &t[end..])
                }
                3 => format!("{}{}", t, &t[at..]),
                _ => t,
            }
        })
        .boxed()
}

fn case() -> BoxedStrategy<Case> {
    (
        shape_text(),
        1usize..4,
        0u8..3,
        0u8..5,
        0u8..8,
        (0u8..4, 0u8..4, 0u8..4),
    )
        .prop_map(|(text, elements, r, f, s, (scene, free, zero_a))| Case {
            text,
            elements,
            reference: [Reference::Clamped, Reference::Pinned, Reference::Free][r as usize],
            formalism: if f == 0 {
                Formalism::Lumped
            } else {
                Formalism::Consistent
            },
            stiffening: match s {
                0 => Stiffening::SecondOrder,
                1 => Stiffening::FourthOrder,
                _ => Stiffening::Off,
            },
            spatial_scene: scene == 0,
            free_frame: free != 0,
            zero_frame_acceleration: zero_a == 0,
        })
        .boxed()
}

// ------------------------------------------------------------------- oracle

/// An error must be a clear message: non-empty, one line; a refused shape
/// file names `fuzz.toml:line:col`.
fn clear(e: &Error) -> Result<(), String> {
    let m = e.to_string();
    if m.trim().is_empty() || m.contains('\n') || m.contains('\r') {
        return Err(format!("unclear error message: {m:?}"));
    }
    if let Error::Shape { location, message } = e {
        if location.file != "fuzz.toml" || location.line == 0 || location.column == 0 {
            return Err(format!("bad location in {m:?}"));
        }
        if message.trim().is_empty() {
            return Err(format!("empty message: {m:?}"));
        }
    }
    Ok(())
}

/// The generator's work in a case (CPU time of the case thread), counted
/// step by step: the oracle's own evaluations and its re-parse of the output
/// are not the generator's work.
#[derive(Default)]
struct Work(Duration);

impl Work {
    fn time<T>(&mut self, f: impl FnOnce() -> T) -> T {
        let start = thread_cpu_time();
        let r = f();
        self.0 += thread_cpu_time() - start;
        r
    }
}

/// Frame motion `ā, α, ω`, `β'`, `γ'` and the body's coordinates, velocities
/// and accelerations at which the kernels are run.
const FRAME: [f64; 9] = [0.3, -9.81, 0.2, 0.5, -0.4, 2.0, 1.5, -0.7, 3.0];
const BP: f64 = 4.0e4;
const GP: f64 = 2.0e2;

fn state(nf: usize, scale: f64) -> Vec<f64> {
    (0..nf).map(|i| scale * (i as f64 + 1.0)).collect()
}

/// The `element_invariants` program of `set` on a tape against its exact
/// polynomials, evaluated term by term, for every element of the body:
/// the same outputs, each within 1e-12 of the sum of the magnitudes of its
/// terms (a few hundred roundings of either evaluation order).
fn programs_match_polynomials(set: &KernelSet, body: &TapeBody) -> Result<(), String> {
    let polys = &set.polys.element_invariants;
    let targets: Vec<_> = polys.iter().map(|(t, _)| *t).collect();
    let program_targets: Vec<_> = set
        .element_invariants
        .outputs
        .iter()
        .map(|(t, _)| *t)
        .collect();
    if targets != program_targets {
        return Err("element_invariants: the program's outputs are not the polynomials'".into());
    }
    let mut run = Run::new(&set.element_invariants);
    for e in 0..body.elements() {
        let mut got = Vec::with_capacity(polys.len());
        run.run(
            &Inputs {
                coef: &body.coef,
                x0: body.x0(e),
                ..Inputs::default()
            },
            |_, _, v| got.push(v),
        );
        for (((arr, i), p), g) in polys.iter().zip(got) {
            let (v, scale) = eval_element(p, &body.params, body.l, body.x0(e));
            // Also fails on NaN.
            let close = (g - v).abs() <= 1e-12 * scale;
            if !close {
                return Err(format!(
                    "element_invariants {arr:?}[{i}] of element {e}: the program gives {g:e}, the polynomial {v:e} (terms up to {scale:e})"
                ));
            }
        }
    }
    Ok(())
}

/// Every entry finite.
fn finite<'a>(what: &str, v: impl IntoIterator<Item = &'a f64>) -> Result<(), String> {
    match v.into_iter().find(|x| !x.is_finite()) {
        Some(x) => Err(format!("{what}: {x} at the defaults")),
        None => Ok(()),
    }
}

/// The `m_ff` diagonal positive (non-negative for the lumped formalism).
fn diagonal(what: &str, m: &nalgebra::DMatrix<f64>, f: Formalism) -> Result<(), String> {
    for a in 0..m.nrows() {
        let d = m[(a, a)];
        let ok = match f {
            Formalism::Consistent => d > 0.0,
            Formalism::Lumped => d >= 0.0,
        };
        if !ok {
            return Err(format!("{what} m_ff[{a}][{a}] = {d} ({f:?})"));
        }
    }
    Ok(())
}

/// Run one case through the generator and check the result.
fn check_case(c: &Case, work: &mut Work) -> Result<Outcome, String> {
    let shape = match work.time(|| Shape::parse(&c.text, "fuzz.toml")) {
        Ok(s) => s,
        Err(e) => {
            clear(&e)?;
            tally(&e);
            return Ok(Outcome::ShapeError);
        }
    };
    let spec = BodySpec::new(shape.clone(), c.elements, c.reference)
        .map_err(|e| format!("BodySpec::new: {e}"))?
        .with_formalism(c.formalism);
    // A free frame keeps its `ā` terms whatever `zero_frame_acceleration` says.
    let mut options = KernelOptions::new()
        .formalism(c.formalism)
        .stiffening(c.stiffening)
        .frame(FrameModel::from_flags(
            c.free_frame,
            c.zero_frame_acceleration,
        ));
    if c.spatial_scene {
        options = options.scene(SceneDim::Spatial);
    }
    let model = KernelModel::new(shape, options);
    // The body's exact invariants and the kernels both start from the
    // element invariants: both succeed, or both fail with the same error.
    let exact = work.time(|| spec.exact_invariants());
    let set = work.time(|| generate_kernels(&model));
    let (exact, set) = match (exact, set) {
        (Ok(x), Ok(s)) => (x, s),
        (Err(e), Err(f)) => {
            clear(&e)?;
            if e != f {
                return Err(format!(
                    "exact_invariants and generate_kernels refuse differently: {e} / {f}"
                ));
            }
            tally(&e);
            return Ok(Outcome::BodyError);
        }
        (Ok(_), Err(e)) => {
            return Err(format!(
                "generate_kernels failed after exact_invariants succeeded: {e}"
            ))
        }
        (Err(e), Ok(_)) => {
            return Err(format!(
                "exact_invariants failed, generate_kernels succeeded: {e}"
            ))
        }
    };
    work.time(|| check_literals(&set))
        .map_err(|e| format!("non-finite literal: {e}"))?;
    check_params(&DEFAULTS, &set.params_used()).map_err(|e| format!("defaults refused: {e}"))?;

    // The exact body invariants at the defaults.
    let inv = Dense::from_exact(&exact, &DEFAULTS);
    if let Some((q, x)) = inv.first_not_finite() {
        return Err(format!("exact invariant {q} = {x} at the defaults"));
    }
    diagonal("exact", &inv.m_ff, c.formalism)?;
    if inv.mass.is_nan() || inv.mass <= 0.0 {
        return Err(format!("mass {}", inv.mass));
    }

    // The programs at the defaults, as the runtime runs them: the
    // coefficients (which `KernelBody::new` checks), the invariants program
    // against its polynomials and assembled, and every kernel at a state.
    let coef = coefficient_values(&set, &DEFAULTS, DEFAULTS.elem_length(c.elements));
    if let Some(i) = coef.iter().position(|x| !x.is_finite()) {
        return Err(format!("coefficient c[{i}] = {} at the defaults", coef[i]));
    }
    let body = TapeBody::new(&set, c.elements, c.reference, DEFAULTS);
    programs_match_polynomials(&set, &body)?;
    let assembled = body.invariants();
    if let Some((q, x)) = assembled.first_not_finite() {
        return Err(format!(
            "element_invariants program: {q} = {x} at the defaults"
        ));
    }
    diagonal("element_invariants program", &assembled.m_ff, c.formalism)?;
    let nf = body.nf();
    let (q, qd, qdd) = (state(nf, 1e-3), state(nf, 1e-2), state(nf, 1e-1));
    let mass = body.mass(&q);
    finite("mass kernel S_t", &mass.s_t)?;
    finite("mass kernel m_ff", mass.m_ff.iter())?;
    finite("mass kernel m_f_frame", mass.m_f_frame.iter())?;
    finite("mass kernel m_ref_f", mass.m_ref_f.iter())?;
    finite("mass kernel m_ref_frame", mass.m_ref_frame.iter())?;
    let (f, k) = body.tangent_elastic(&q, &qd, &qdd, &FRAME, BP, GP);
    finite("tangent_elastic f", &f)?;
    finite("tangent_elastic K", k.iter())?;
    finite(
        "residual_elastic",
        &body.residual_elastic(&q, &qd, &qdd, &FRAME),
    )?;
    finite("energy", [body.energy(&q)].iter())?;
    if c.free_frame {
        let r = body.residual(&q, &qd, &qdd, &FRAME);
        finite("residual", r.f_r.iter().chain(&r.f_th).chain(&r.f_f))?;
        let t = body.tangent(&q, &qd, &qdd, &FRAME, BP, GP);
        finite("tangent", t.f_r.iter().chain(&t.f_th).chain(&t.f_f))?;
        finite("tangent k_ff", t.k_ff.iter())?;
        finite("tangent d_f_frame", t.d_f_frame.iter())?;
        finite("tangent k_ref_f", t.k_ref_f.iter())?;
        finite("tangent d_ref_frame", t.d_ref_frame.iter())?;
    }
    let mut run = Run::new(&set.point_shape);
    for xi in [0.0, 0.5, 1.0] {
        let mut v = Vec::new();
        run.run(
            &Inputs {
                coef: &body.coef,
                xi,
                ..Inputs::default()
            },
            |arr, _, x| {
                assert!(matches!(arr, OutArr::S | OutArr::Psi));
                v.push(x)
            },
        );
        finite("point_shape", &v)?;
    }

    // The emitted file: a header of comments, Rust that parses.
    let code = work.time(|| emit_body_file(&set, &spec, &EmitOptions::default()));
    if !code.starts_with("// @generated by ffr-codegen") {
        return Err("emitted code has no header".into());
    }
    let header_end = code.find("\n\n").unwrap_or(code.len());
    if code[..header_end]
        .lines()
        .any(|l| !l.starts_with("//") || l.chars().any(char::is_control))
    {
        return Err("the header has a line that is not a comment".into());
    }
    syn::parse_file(&code).map_err(|e| format!("emitted code does not parse: {e}"))?;
    Ok(Outcome::Body)
}

/// Kinds of refusal (the message without location, numbers and quoted
/// text), for the summary of long runs.
static KINDS: std::sync::Mutex<std::collections::BTreeMap<String, usize>> =
    std::sync::Mutex::new(std::collections::BTreeMap::new());

fn tally(e: &Error) {
    let m = match e {
        Error::Shape { message, .. } => message.clone(),
        other => other.to_string(),
    };
    // Drop what is quoted and the digits: `S[x][c0] (`…`): unknown symbol `x`` → `S[x][c] (): unknown symbol`.
    let mut kind = String::new();
    let mut quoted = false;
    for ch in m.chars() {
        if ch == '`' {
            quoted = !quoted;
        } else if !quoted && !ch.is_ascii_digit() {
            kind.push(ch);
        }
    }
    let kind: String = kind.chars().take(70).collect();
    *KINDS.lock().unwrap().entry(kind).or_default() += 1;
}

/// Counts of outcomes, for the summary.
static COUNTS: [AtomicUsize; 3] = [
    AtomicUsize::new(0),
    AtomicUsize::new(0),
    AtomicUsize::new(0),
];
/// The slowest case without and with stiffening.
type Slowest = [Option<(Duration, Case)>; 2];
static SLOWEST: std::sync::Mutex<Slowest> = std::sync::Mutex::new([None, None]);

/// Run a case on a thread with the default test stack, bounded in time:
/// [`CASE_LIMIT`] of the thread's CPU time for
/// the generator's work (parsing, exact invariants, kernel programs, literal
/// check, emission; not the oracle's evaluations nor its re-parse of the
/// output), [`HANG_LIMIT`] of wall time in all.
fn run_case(c: &Case) -> Result<Outcome, String> {
    let (tx, rx) = mpsc::channel();
    let case = c.clone();
    std::thread::Builder::new()
        .name("fuzz-case".into())
        .stack_size(2 << 20)
        .spawn(move || {
            let mut work = Work::default();
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                check_case(&case, &mut work)
            }));
            let took = work.0;
            let r = match r {
                Ok(r) => r,
                Err(p) => Err(format!(
                    "panic: {}",
                    p.downcast_ref::<String>()
                        .cloned()
                        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                        .unwrap_or_default()
                )),
            };
            let _ = tx.send((r, took));
        })
        .expect("spawn a case thread");
    match rx.recv_timeout(HANG_LIMIT) {
        Ok((r, took)) => {
            {
                let slowest = &mut SLOWEST.lock().unwrap()[c.stiffening.is_on() as usize];
                if slowest.as_ref().is_none_or(|(t, _)| took > *t) {
                    *slowest = Some((took, c.clone()));
                }
            }
            if took > CASE_LIMIT {
                return Err(format!("took {took:?}, more than {CASE_LIMIT:?}"));
            }
            let outcome = r?;
            COUNTS[outcome as usize].fetch_add(1, Ordering::Relaxed);
            Ok(outcome)
        }
        Err(_) => Err(format!("no result after {HANG_LIMIT:?}: a hang")),
    }
}

fn env_u64(name: &str) -> Option<u64> {
    std::env::var(name).ok().and_then(|v| v.trim().parse().ok())
}

#[test]
fn fuzz_shapes() {
    let cases = env_u64("FFR_FUZZ_CASES").map_or(DEFAULT_CASES, |n| n as u32);
    let seed = env_u64("FFR_FUZZ_SEED").unwrap_or(8);
    let save = std::env::var_os("FFR_FUZZ_CASES").is_some();
    let current = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz_current_case.toml");
    let mut seed_bytes = [0u8; 32];
    seed_bytes[..8].copy_from_slice(&seed.to_le_bytes());
    let config = Config {
        cases,
        failure_persistence: None,
        max_shrink_iters: 2000,
        ..Config::default()
    };
    let mut runner = TestRunner::new_with_rng(
        config,
        TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes),
    );
    let start = Instant::now();
    let result = runner.run(&case(), |c| {
        if save {
            let _ = std::fs::write(&current, &c.text);
        }
        run_case(&c).map(|_| ()).map_err(TestCaseError::fail)
    });
    let counts: Vec<usize> = COUNTS.iter().map(|c| c.load(Ordering::Relaxed)).collect();
    println!(
        "fuzz_shapes: {cases} cases (seed {seed}) in {:.1} s: {} shape files refused, {} bodies refused, {} bodies checked and emitted (counts include shrinking)",
        start.elapsed().as_secs_f64(),
        counts[0],
        counts[1],
        counts[2],
    );
    for (k, slowest) in SLOWEST.lock().unwrap().iter().enumerate() {
        let Some((t, c)) = slowest else { continue };
        let path = current.with_file_name(format!("fuzz_slowest_case_{k}.toml"));
        if save {
            let _ = std::fs::write(&path, &c.text);
        }
        println!(
            "slowest case {} stiffening: {t:?} CPU, {} elements, {:?}, {:?}, stiffening {}, {} scene, free frame {}, ā ≡ 0 {}{}",
            if c.stiffening.is_on() { "with" } else { "without" },
            c.elements,
            c.reference,
            c.formalism,
            c.stiffening,
            if c.spatial_scene { "spatial" } else { "own" },
            c.free_frame,
            c.zero_frame_acceleration,
            if save {
                format!(" (text in {})", path.display())
            } else {
                String::new()
            }
        );
    }
    if save {
        let mut kinds: Vec<(String, usize)> = KINDS.lock().unwrap().clone().into_iter().collect();
        kinds.sort_by_key(|k| std::cmp::Reverse(k.1));
        println!("most frequent refusals:");
        for (k, n) in kinds.iter().take(40) {
            println!("  {n:7}  {k}");
        }
    }
    if let Err(e) = result {
        panic!("{e}");
    }
    assert!(
        counts[2] * 10 >= counts.iter().sum::<usize>(),
        "too few valid shapes to exercise the generator: {counts:?}"
    );
}

// ------------------------------------------------------------------- corpus

/// A planar bar with entry `S[x][u2]` replaced (as in issue 8's reproducers).
fn bar(entry: &str) -> String {
    format!(
        "name = \"bar2\"\ndimension = 2\ncoordinates = [\n  {{ name = \"u1\", node = 0, kind = \"ux\" }},\n  {{ name = \"v1\", node = 0, kind = \"uy\" }},\n  {{ name = \"u2\", node = 1, kind = \"ux\" }},\n  {{ name = \"v2\", node = 1, kind = \"uy\" }},\n]\n[S]\nx = [\"1 - xi\", \"0\", {}, \"0\"]\ny = [\"0\", \"1 - xi\", \"0\", \"xi\"]\n",
        toml_string(entry)
    )
}

/// Every shape-file reproducer of issue 8, through the fuzzing oracle.
#[test]
fn corpus() {
    let deep = format!("{}xi{}", "(".repeat(8000), ")".repeat(8000));
    let minus = format!("{}xi", "-".repeat(50_000));
    let inject = bar("xi").replace(
        "name = \"bar2\"",
        "name = \"x\\nfn main() { std::process::exit(3) }\\n//\"",
    );
    let inject_cr = bar("xi").replace("name = \"bar2\"", "name = \"x\\rfn main() {}\"");
    let corpus: Vec<(&str, String, Outcome)> = vec![
        (
            "wrapping exponents",
            bar("((((xi^64)^64)^64)^64)^64"),
            Outcome::ShapeError,
        ),
        (
            "one more ^64",
            bar("(((((xi^64)^64)^64)^64)^64)^64"),
            Outcome::ShapeError,
        ),
        ("xi^(2^31)", bar("xi^(2^31)"), Outcome::ShapeError),
        ("8000 parentheses", bar(&deep), Outcome::ShapeError),
        ("50000 unary minus", bar(&minus), Outcome::Body),
        ("l^32768", bar("xi*((l^64)^64)^8"), Outcome::ShapeError),
        (
            "nested power hang",
            bar("((1+xi)^8)^64"),
            Outcome::ShapeError,
        ),
        (
            "coefficient 1e300*1e300",
            bar("1e300*1e300*xi"),
            Outcome::ShapeError,
        ),
        ("name with newline", inject, Outcome::ShapeError),
        ("name with carriage return", inject_cr, Outcome::ShapeError),
        (
            "truncated file",
            bar("xi")[..150].to_string(),
            Outcome::ShapeError,
        ),
        ("the bar itself", bar("xi"), Outcome::Body),
    ];
    for (name, text, expect) in corpus {
        for formalism in [Formalism::Consistent, Formalism::Lumped] {
            for stiffening in [
                Stiffening::Off,
                Stiffening::SecondOrder,
                Stiffening::FourthOrder,
            ] {
                let c = Case {
                    text: text.clone(),
                    elements: 2,
                    reference: Reference::Clamped,
                    formalism,
                    stiffening,
                    spatial_scene: false,
                    free_frame: true,
                    zero_frame_acceleration: false,
                };
                let got = run_case(&c).unwrap_or_else(|e| panic!("{name}: {e}"));
                assert_eq!(got, expect, "{name}");
            }
        }
    }
}
