//! `ffr run SCENE --reference FILE.csv`: the reference's columns named like
//! the scene's outputs are drawn over them, the largest difference of each
//! is printed; the plot's axes carry units; a reference without a matching
//! column or with a bad row is an error naming the file.

mod common;
use common::cli::{ffr, s, scene, temp_dir};

#[test]
fn a_reference_is_overlaid_and_its_difference_printed() {
    let dir = temp_dir("ref", "overlay");
    let csv = dir.join("o.csv");
    let (ok, _, err) = ffr(&["run", &scene("spin_up.toml"), "--csv", s(&csv)]);
    assert!(ok, "{err}");
    // The run's own tip_transverse plus 1e-3, up to t = 10 s (1001 of the
    // run's samples), and a column the scene does not have.
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut reference = String::from("t,tip_transverse,other\n");
    let mut rows = 0;
    for line in text.lines().skip(1) {
        let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        if f[0] <= 10.0 {
            reference.push_str(&format!("{:?},{:?},0\n", f[0], f[2] + 1e-3));
            rows += 1;
        }
    }
    assert_eq!(rows, 1001);
    let rf = dir.join("ref.csv");
    std::fs::write(&rf, reference).unwrap();
    let svg = dir.join("o2.svg");
    let (ok, out, err) = ffr(&[
        "run",
        &scene("spin_up.toml"),
        "--csv",
        s(&dir.join("o2.csv")),
        "--svg",
        s(&svg),
        "--reference",
        s(&rf),
    ]);
    assert!(ok, "{err}");
    assert!(
        out.contains("  tip_transverse: 1.000000e-3 (1001 samples)"),
        "{out}"
    );
    assert!(
        out.contains("not outputs of the scene (ignored): other"),
        "{out}"
    );
    let plot = std::fs::read_to_string(&svg).unwrap();
    assert!(
        plot.contains("tip_transverse (reference ref.csv)"),
        "the overlay's legend"
    );
    assert!(
        plot.contains("outputs (m)") && plot.contains("t (s)"),
        "axes with units"
    );
}

#[test]
fn a_reference_without_a_matching_column_or_with_a_bad_row_is_refused() {
    let dir = temp_dir("ref", "bad");
    let rf = dir.join("ref.csv");
    std::fs::write(&rf, "t,nothing\n0,1\n").unwrap();
    let csv = dir.join("o.csv");
    let (ok, _, err) = ffr(&[
        "run",
        &scene("spin_up.toml"),
        "--csv",
        s(&csv),
        "--reference",
        s(&rf),
    ]);
    assert!(!ok);
    assert!(
        err.contains("--reference: no column is an output of the scene (its columns: nothing; the scene's outputs: tip_axial, tip_transverse)"),
        "{err}"
    );
    assert!(!csv.exists(), "refused before the run");
    std::fs::write(&rf, "t,tip_transverse\n0,1\n0.5,nan\n").unwrap();
    let (ok, _, err) = ffr(&[
        "run",
        &scene("spin_up.toml"),
        "--csv",
        s(&csv),
        "--reference",
        s(&rf),
    ]);
    assert!(!ok);
    assert!(
        err.contains("ref.csv:3: `nan` in column `tip_transverse` is not a finite number"),
        "{err}"
    );
}

#[test]
fn the_plot_names_the_units_of_mixed_outputs() {
    // pendulum.toml records an angle, positions and deflections, energies.
    let dir = temp_dir("ref", "units");
    let svg = dir.join("p.svg");
    let (ok, _, err) = ffr(&[
        "run",
        &scene("pendulum.toml"),
        "--csv",
        s(&dir.join("p.csv")),
        "--svg",
        s(&svg),
    ]);
    assert!(ok, "{err}");
    let plot = std::fs::read_to_string(&svg).unwrap();
    assert!(
        plot.contains("outputs (rad, m, J)"),
        "y axis with the units"
    );
}
