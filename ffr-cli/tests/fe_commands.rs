//! `ffr invariants` and `ffr modes` on a scene's FE body (issue 23): the same
//! JSON keys as for beams; the solid cantilever's clamped frequencies equal
//! scikit-fem's (`tests/data/fe/cantilever_eigen.csv`, scipy's `eigh` of the
//! same matrices) and its mass the box's; errors exit 1, never a panic.

mod common;

use common::cli::ffr;
use serde_json::Value;
use std::collections::BTreeSet;
use std::path::PathBuf;

fn scene() -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/fe/pendulum.toml")
        .display()
        .to_string()
}

fn json_of(args: &[&str]) -> Value {
    let (ok, out, err) = ffr(args);
    assert!(ok, "{args:?}: {err}");
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"))
}

fn keys(v: &Value) -> BTreeSet<String> {
    v.as_object().unwrap().keys().cloned().collect()
}

#[test]
fn fe_body_invariants_and_modes_from_a_scene() {
    let s = scene();
    let inv = json_of(&["invariants", "--scene", &s, "--body", "bar", "--json"]);
    let beam_inv = json_of(&[
        "invariants",
        "--shape",
        "beam3",
        "--elements",
        "2",
        "--json",
    ]);
    assert_eq!(keys(&inv), keys(&beam_inv));
    // The box: ρ L B² = 78.5 kg (consistent hexahedra: exact to round-off).
    let m = inv["mass"].as_f64().unwrap();
    assert!((m / 78.5 - 1.0).abs() < 1e-13, "{m}");
    assert_eq!(inv["dofs"].as_array().unwrap().len(), 270);

    let modes = json_of(&[
        "modes", "--scene", &s, "--body", "bar", "--count", "12", "--json",
    ]);
    let beam_modes = json_of(&[
        "modes",
        "--shape",
        "beam3",
        "--elements",
        "2",
        "--count",
        "2",
        "--json",
    ]);
    assert_eq!(keys(&modes), keys(&beam_modes));
    assert_eq!(keys(&modes["invariants"]), keys(&beam_modes["invariants"]));
    let eigen = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/data/fe/cantilever_eigen.csv"),
    )
    .unwrap();
    let reference: Vec<f64> = eigen
        .lines()
        .skip(1)
        .take(12)
        .map(|l| l.split(',').nth(2).unwrap().parse().unwrap())
        .collect();
    let omega: Vec<f64> = modes["omega"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_f64().unwrap())
        .collect();
    assert_eq!(omega.len(), 12);
    for (w, r) in omega.iter().zip(&reference) {
        assert!((w / r - 1.0).abs() < 1e-9, "{w} vs scikit-fem {r}");
    }
    assert_eq!(modes["phi"].as_array().unwrap().len(), 270);

    // Craig–Bampton on the tip's centre node: two normal modes, three
    // constraint modes.
    let cb = json_of(&[
        "modes",
        "--scene",
        &s,
        "--body",
        "bar",
        "--count",
        "2",
        "--boundary",
        "64",
        "--json",
    ]);
    let labels: Vec<&str> = cb["labels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l.as_str().unwrap())
        .collect();
    assert_eq!(
        labels,
        [
            "mode_1",
            "mode_2",
            "constraint_ux_64",
            "constraint_uy_64",
            "constraint_uz_64"
        ]
    );
}

#[test]
fn fe_body_command_errors() {
    let s = scene();
    for (args, message) in [
        (
            vec!["modes", "--scene", &s, "--body", "bar", "--count", "271"],
            "--count must be between 1 and 270",
        ),
        (
            vec!["modes", "--scene", &s, "--body", "bar", "--boundary", "0"],
            "interface node",
        ),
        (
            vec!["modes", "--scene", &s, "--body", "bar", "--boundary", "99"],
            "out of range",
        ),
        (
            vec!["invariants", "--scene", &s, "--body", "nothing"],
            "no flexible body `nothing`",
        ),
    ] {
        let (ok, _, err) = ffr(&args);
        assert!(!ok && err.contains(message), "{args:?}: {err}");
    }
}
