//! One output policy for every command (issue 36): an output never names
//! an input of the command (the scene file, a file the scene is read from,
//! a reference) or a file of the VTK series the command writes, and a
//! directory given to `linearize --out` holds only files ffr marked (a
//! foreign file is refused, a symbolic link is not followed). Each case was
//! a silent overwrite before.

mod common;
use common::cli::{ffr, s, scene, temp_dir};
use std::path::Path;

/// `path`'s bytes, to show that a refused command left a file alone.
fn bytes(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap()
}

#[test]
fn run_outputs_never_replace_the_scene_or_the_reference() {
    let dir = temp_dir("policy", "run");
    let sc = dir.join("S.toml");
    std::fs::copy(scene("pendulum.toml"), &sc).unwrap();
    let before = bytes(&sc);
    for flag in ["--svg", "--csv"] {
        let (ok, _, err) = ffr(&["run", s(&sc), flag, s(&sc)]);
        assert!(!ok);
        assert!(
            err.contains("would overwrite a file the scene is read from"),
            "{err}"
        );
        assert_eq!(bytes(&sc), before, "{flag}: the scene was replaced");
    }
    // A hard link to the scene is the same file.
    let link = dir.join("hard.svg");
    std::fs::hard_link(&sc, &link).unwrap();
    let (ok, _, err) = ffr(&["run", s(&sc), "--svg", s(&link)]);
    assert!(!ok && err.contains("would overwrite"), "{err}");
    assert_eq!(bytes(&sc), before);
    // A reference that the CSV would replace.
    let csv = dir.join("r.csv");
    let (ok, _, err) = ffr(&["run", s(&sc), "--csv", s(&csv)]);
    assert!(ok, "{err}");
    let reference = bytes(&csv);
    let (ok, _, err) = ffr(&["run", s(&sc), "--csv", s(&csv), "--reference", s(&csv)]);
    assert!(!ok);
    assert!(
        err.contains("would overwrite the --reference file"),
        "{err}"
    );
    assert_eq!(bytes(&csv), reference);
}

#[test]
fn run_and_campbell_outputs_never_replace_a_file_of_their_vtk_series() {
    let dir = temp_dir("policy", "vtk");
    let sc = dir.join("S.toml");
    std::fs::copy(scene("pendulum.toml"), &sc).unwrap();
    let vtk = dir.join("v");
    let (ok, _, err) = ffr(&[
        "run",
        s(&sc),
        "--vtk",
        s(&vtk),
        "--csv",
        s(&dir.join("a.csv")),
    ]);
    assert!(ok, "{err}");
    let step = vtk.join("S_0001.vtp");
    let before = bytes(&step);
    for flag in ["--csv", "--svg"] {
        let (ok, _, err) = ffr(&["run", s(&sc), "--vtk", s(&vtk), flag, s(&step)]);
        assert!(!ok);
        assert!(
            err.contains("would replace a file of the --vtk series"),
            "{err}"
        );
        assert_eq!(bytes(&step), before);
    }
    let spin = dir.join("spin.toml");
    std::fs::copy(scene("spin_up.toml"), &spin).unwrap();
    let svg = vtk.join("spin_speed01_mode01.pvd");
    let (ok, _, err) = ffr(&[
        "campbell",
        s(&spin),
        "--speeds",
        "0,1",
        "--count",
        "1",
        "--vtk",
        s(&vtk),
        "--svg",
        s(&svg),
    ]);
    assert!(!ok);
    assert!(
        err.contains("would replace a file of the --vtk series"),
        "{err}"
    );
    assert!(!svg.exists(), "nothing written");
    let (ok, _, err) = ffr(&["campbell", s(&spin), "--speeds", "0", "--svg", s(&spin)]);
    assert!(!ok && err.contains("would overwrite"), "{err}");
}

#[test]
fn static_and_export_outputs_never_replace_a_file_the_scene_is_read_from() {
    let dir = temp_dir("policy", "files");
    // A scene whose section table lies next to it.
    let blade = dir.join("blade.toml");
    let text = std::fs::read_to_string(scene("blade_5mw.toml")).unwrap();
    std::fs::write(&blade, text.replace("data/nrel5mw_blade.csv", "table.csv")).unwrap();
    let table = dir.join("table.csv");
    std::fs::copy(
        Path::new(&scene("blade_5mw.toml"))
            .parent()
            .unwrap()
            .join("data/nrel5mw_blade.csv"),
        &table,
    )
    .unwrap();
    let before = bytes(&table);
    let (ok, _, err) = ffr(&["static", s(&blade), "--csv", s(&table)]);
    assert!(!ok);
    assert!(
        err.contains("would overwrite a file the scene is read from"),
        "{err}"
    );
    assert_eq!(bytes(&table), before);
    // An FE body's matrix as the export's output.
    let fe = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/fe");
    for f in [
        "pendulum.toml",
        "cantilever_nodes.csv",
        "cantilever_mass.mtx",
        "cantilever_stiffness.mtx",
    ] {
        std::fs::copy(fe.join(f), dir.join(f)).unwrap();
    }
    let mass = dir.join("cantilever_mass.mtx");
    let before = bytes(&mass);
    let (ok, _, err) = ffr(&[
        "export",
        "--format",
        "sid",
        "--scene",
        s(&dir.join("pendulum.toml")),
        "--body",
        "bar",
        "--modes",
        "4",
        "--out",
        s(&mass),
    ]);
    assert!(!ok);
    assert!(
        err.contains("would overwrite a file the scene is read from"),
        "{err}"
    );
    assert_eq!(bytes(&mass), before);
}

#[test]
fn linearize_out_replaces_only_its_own_files_and_follows_no_link() {
    let dir = temp_dir("policy", "linearize");
    let sc = scene("pendulum.toml");
    let out = dir.join("lin");
    std::fs::create_dir_all(&out).unwrap();
    // A foreign file of one of the names.
    std::fs::write(out.join("A.mtx"), "mine\n").unwrap();
    let (ok, _, err) = ffr(&["linearize", &sc, "--out", s(&out)]);
    assert!(!ok);
    assert!(
        err.contains("A.mtx: exists and was not written by ffr"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("A.mtx")).unwrap(),
        "mine\n"
    );
    assert!(!out.join("linear.json").exists(), "nothing written");
    std::fs::remove_file(out.join("A.mtx")).unwrap();
    // A symbolic link inside the directory to a file outside it.
    let outside = dir.join("outside.json");
    std::fs::write(&outside, "{}").unwrap();
    std::os::unix::fs::symlink(&outside, out.join("linear.json")).unwrap();
    let (ok, _, err) = ffr(&["linearize", &sc, "--out", s(&out)]);
    assert!(!ok);
    assert!(err.contains("linear.json: is a symbolic link"), "{err}");
    assert_eq!(std::fs::read_to_string(&outside).unwrap(), "{}");
    std::fs::remove_file(out.join("linear.json")).unwrap();
    // Its own files: written, marked, and replaced by the next run.
    for _ in 0..2 {
        let (ok, _, err) = ffr(&["linearize", &sc, "--out", s(&out)]);
        assert!(ok, "{err}");
    }
    let a = std::fs::read_to_string(out.join("A.mtx")).unwrap();
    assert!(
        a.starts_with("%%MatrixMarket matrix coordinate real general\n% written by ffr linearize")
    );
    let js: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("linear.json")).unwrap()).unwrap();
    assert_eq!(js["written_by"], "ffr linearize");
    assert!(js["A"].is_array());
}

/// Paths in messages are cut in the middle (the file's name kept): a path
/// of 6 000 characters was printed whole (issue 36).
#[test]
fn long_paths_in_messages_are_cut() {
    let deep = format!("/nonexistent/{}x.csv", "p/".repeat(3000));
    let (ok, _, err) = ffr(&["run", &scene("pendulum.toml"), "--csv", &deep]);
    assert!(!ok);
    assert!(
        err.lines().count() == 1 && err.chars().count() < 400,
        "{err}"
    );
    assert!(err.contains("p/x.csv: "), "{err}");
    let missing = format!("/nonexistent/{}/scene.toml", "d".repeat(5000));
    let (ok, _, err) = ffr(&["run", &missing]);
    assert!(!ok);
    assert!(
        err.chars().count() < 400 && err.contains("ddd/scene.toml"),
        "{err}"
    );
}
