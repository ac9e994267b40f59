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

/// `ffr export` of a scene's FE body: MBDyn's `.fem` with every FE node
/// (99), the four modes' nodal translations (node 64's are the rows of
/// `ffr modes --json`'s `phi` for its coordinates, to the JSON parser's
/// last digit), the lumped masses
/// (row sums of the mass matrix) summing to the box's 78.5 kg, the exact
/// rigid-body mass in record 12; SID written too.
#[test]
fn fe_body_export() {
    let s = scene();
    let dir = std::env::temp_dir().join(format!("ffr-fe-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fem = dir.join("bar.fem");
    let fem_s = fem.display().to_string();
    let (ok, _, err) = ffr(&[
        "export",
        "--format",
        "mbdyn-fem",
        "--scene",
        &s,
        "--body",
        "bar",
        "--modes",
        "4",
        "--out",
        &fem_s,
    ]);
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&fem).unwrap();
    assert!(text.contains("\nREV0 99 4 0 0 0\n"), "header");
    let group = |g: usize| -> Vec<Vec<f64>> {
        let start = text.find(&format!("** RECORD GROUP {g},")).unwrap();
        text[start..]
            .lines()
            .skip(1)
            .take_while(|l| !l.starts_with("**"))
            .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    let lumped: f64 = group(11).iter().map(|r| r[0]).sum();
    assert!((lumped / 78.5 - 1.0).abs() < 1e-12, "{lumped}");
    assert!((group(12)[0][0] / 78.5 - 1.0).abs() < 1e-13);
    // Record 8: per mode, 99 rows (ux uy uz rx ry rz of each node).
    let shapes: Vec<Vec<f64>> = {
        let start = text.find("** RECORD GROUP 8,").unwrap();
        let end = text.find("** RECORD GROUP 9,").unwrap();
        text[start..end]
            .lines()
            .filter(|l| !l.starts_with("**"))
            .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    assert_eq!(shapes.len(), 4 * 99);
    let modes = json_of(&[
        "modes", "--scene", &s, "--body", "bar", "--count", "4", "--json",
    ]);
    let dofs: Vec<&str> = modes["dofs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d.as_str().unwrap())
        .collect();
    for (k, dir) in ["ux", "uy", "uz"].iter().enumerate() {
        let a = dofs.iter().position(|d| *d == format!("{dir}_64")).unwrap();
        for m in 0..4 {
            let phi = modes["phi"][a][m].as_f64().unwrap();
            // serde_json's parser may be one unit in the last place off.
            let written = shapes[m * 99 + 64][k];
            assert!(
                (written - phi).abs() <= 4.0 * f64::EPSILON * phi.abs().max(1e-3),
                "mode {m} {dir}_64: {written} vs {phi}"
            );
        }
    }
    // The clamped interface nodes do not move.
    assert!(shapes[0].iter().all(|x| *x == 0.0));
    let sid = dir.join("bar.sid");
    let (ok, _, err) = ffr(&[
        "export",
        "--format",
        "sid",
        "--scene",
        &s,
        "--body",
        "bar",
        "--modes",
        "4",
        "--out",
        &sid.display().to_string(),
    ]);
    assert!(ok, "{err}");
    assert!(std::fs::metadata(&sid).unwrap().len() > 0);
    std::fs::remove_dir_all(&dir).unwrap();
}
