//! `ffr run --vtk DIR [--every K]` and `ffr modes --vtk DIR`: the errors
//! (flags, a directory that is a file, files not ours, the bound on the
//! number of files), FE bodies' mode animations at the command line, and the
//! library's `run_with` (the `.pvd` lists the run's times; an FE body drawn
//! as its nodes). The files are read back by VTK itself in
//! python/tests/test_vtk.py.

mod common;
use common::cli::{ffr, s, scene, temp_dir};
use ffr::scene::vtk::{VtkOptions, MARK, MAX_VTK_FILES};
use std::path::Path;

fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn every_needs_vtk_and_is_at_least_one() {
    let dir = temp_dir("vtk", "flags");
    let csv = dir.join("o.csv");
    let (ok, _, err) = ffr(&[
        "run",
        &scene("spin_up.toml"),
        "--csv",
        s(&csv),
        "--every",
        "3",
    ]);
    assert!(!ok);
    assert!(err.contains("--vtk"), "{err}");
    let v = dir.join("v");
    let (ok, _, err) = ffr(&[
        "run",
        &scene("spin_up.toml"),
        "--csv",
        s(&csv),
        "--vtk",
        s(&v),
        "--every",
        "0",
    ]);
    assert!(!ok);
    assert!(err.contains("--every") && err.contains('0'), "{err}");
    assert!(!csv.exists() && !v.exists());
}

#[test]
fn a_directory_that_is_a_file_is_refused_before_the_run() {
    let dir = temp_dir("vtk", "file");
    let csv = dir.join("o.csv");
    let f = dir.join("f");
    std::fs::write(&f, "keep").unwrap();
    let (ok, _, err) = ffr(&[
        "run",
        &scene("spin_up.toml"),
        "--csv",
        s(&csv),
        "--vtk",
        s(&f),
    ]);
    assert!(!ok);
    assert!(err.contains("exists and is not a directory"), "{err}");
    assert_eq!(std::fs::read_to_string(&f).unwrap(), "keep");
    assert!(!csv.exists(), "nothing run, nothing written");
}

#[test]
fn files_not_written_by_ffr_are_not_replaced() {
    let dir = temp_dir("vtk", "foreign");
    let v = dir.join("v");
    std::fs::create_dir_all(&v).unwrap();
    std::fs::write(v.join("spin_up.pvd"), "mine").unwrap();
    let csv = dir.join("o.csv");
    let args = [
        "run",
        &scene("spin_up.toml"),
        "--csv",
        s(&csv),
        "--vtk",
        s(&v),
        "--every",
        "500",
    ];
    let (ok, _, err) = ffr(&args);
    assert!(!ok);
    assert!(
        err.contains("spin_up.pvd: exists and was not written by ffr: not replaced"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_to_string(v.join("spin_up.pvd")).unwrap(),
        "mine"
    );
    assert_eq!(listing(&v), ["spin_up.pvd"]);
    // A file ffr wrote (starting with its mark) is replaced.
    std::fs::write(v.join("spin_up.pvd"), MARK).unwrap();
    let (ok, out, err) = ffr(&args);
    assert!(ok, "{err}");
    assert!(out.contains("5 VTK step files"), "{out}");
    assert_eq!(
        listing(&v),
        [
            "spin_up.pvd",
            "spin_up_0000.vtp",
            "spin_up_0500.vtp",
            "spin_up_1000.vtp",
            "spin_up_1500.vtp",
            "spin_up_2000.vtp"
        ]
    );
    // The modes' animations refuse the same way, before writing any.
    std::fs::write(v.join("beam2_mode02_05.vtp"), "mine").unwrap();
    let (ok, _, err) = ffr(&[
        "modes",
        "--shape",
        "beam2",
        "--elements",
        "2",
        "--count",
        "2",
        "--vtk",
        s(&v),
    ]);
    assert!(!ok);
    assert!(
        err.contains("beam2_mode02_05.vtp: exists and was not written by ffr"),
        "{err}"
    );
    assert!(!listing(&v).iter().any(|f| f.starts_with("beam2_mode01")));
}

#[test]
fn the_number_of_files_is_bounded() {
    // dt = 1e-3 over 20 s: 20001 samples, more than MAX_VTK_FILES; refused
    // before the run, with the smallest --every that fits.
    let dir = temp_dir("vtk", "bound");
    let text = std::fs::read_to_string(scene("spin_up.toml"))
        .unwrap()
        .replace("dt = 0.01\n", "dt = 0.001\n");
    let path = dir.join("fine.toml");
    std::fs::write(&path, text).unwrap();
    let v = dir.join("v");
    let (ok, _, err) = ffr(&[
        "run",
        s(&path),
        "--csv",
        s(&dir.join("o.csv")),
        "--vtk",
        s(&v),
    ]);
    assert!(!ok);
    assert_eq!(MAX_VTK_FILES, 10_000);
    assert!(
        err.contains("20001 samples with every = 1 would write 20001 VTK files, more than the limit of 10000: use every ≥ 3 (--every 3)"),
        "{err}"
    );
    assert!(!v.exists());
}

#[test]
fn run_with_writes_one_file_per_every_samples_at_the_runs_times() {
    let dir = temp_dir("vtk", "lib");
    let scene = ffr::scene::load(Path::new(&scene("two_link_arm.toml"))).unwrap();
    let mut options = ffr::scene::RunOptions::default();
    options.vtk = Some(VtkOptions {
        dir: dir.clone(),
        every: 9,
    });
    let r = ffr::scene::run_with(&scene, &options).unwrap();
    assert!(r.failed.is_none());
    let plain = ffr::scene::run(&scene).unwrap();
    assert_eq!(r.t, plain.t);
    assert_eq!(
        r.columns, plain.columns,
        "writing the series changes no output"
    );
    let pvd = std::fs::read_to_string(dir.join("two_link_arm.pvd")).unwrap();
    let times: Vec<f64> = pvd
        .lines()
        .filter_map(|l| l.split("timestep=\"").nth(1))
        .map(|l| l.split('"').next().unwrap().parse().unwrap())
        .collect();
    let want: Vec<f64> = r.t.iter().step_by(9).copied().collect();
    assert_eq!(times, want);
    assert_eq!(listing(&dir).len(), want.len() + 1);
    // every = 0 is refused, naming the option.
    options.vtk = Some(VtkOptions {
        dir: dir.clone(),
        every: 0,
    });
    let e = ffr::scene::run_with(&scene, &options).unwrap_err();
    assert!(e.to_string().contains("every = 0"), "{e}");
}

/// The FE pendulum (tests/data/fe/pendulum.toml) at `path`, its files named
/// by absolute paths, run for `t_end`.
fn fe_pendulum(path: &Path, t_end: &str) {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/fe");
    let mut text = std::fs::read_to_string(data.join("pendulum.toml")).unwrap();
    assert!(text.contains("t_end = 1.0\n"));
    text = text.replace("t_end = 1.0\n", &format!("t_end = {t_end}\n"));
    for f in [
        "cantilever_nodes.csv",
        "cantilever_mass.mtx",
        "cantilever_stiffness.mtx",
    ] {
        let quoted = format!("\"{f}\"");
        assert!(text.contains(&quoted));
        text = text.replace(&quoted, &format!("{:?}", s(&data.join(f))));
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn fe_mode_animations_refuse_files_not_ours_and_keep_json_alone() {
    let dir = temp_dir("vtk", "fe-modes");
    let scene = dir.join("pendulum.toml");
    fe_pendulum(&scene, "1.0");
    let v = dir.join("v");
    std::fs::create_dir_all(&v).unwrap();
    std::fs::write(v.join("bar_mode02_05.vtp"), "mine").unwrap();
    let args = [
        "modes",
        "--scene",
        s(&scene),
        "--body",
        "bar",
        "--count",
        "2",
        "--json",
        "--vtk",
        s(&v),
    ];
    let (ok, _, err) = ffr(&args);
    assert!(!ok);
    assert!(
        err.contains("bar_mode02_05.vtp: exists and was not written by ffr"),
        "{err}"
    );
    assert_eq!(listing(&v), ["bar_mode02_05.vtp"], "nothing written");
    std::fs::remove_file(v.join("bar_mode02_05.vtp")).unwrap();
    // With --json, standard output is the JSON object alone.
    let (ok, out, err) = ffr(&args);
    assert!(ok, "{err}");
    let m: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(m["labels"].as_array().unwrap().len(), 2);
    let files = listing(&v);
    assert_eq!(files.len(), 2 * (1 + ffr::scene::vtk::FRAMES_PER_PERIOD));
    assert!(files.contains(&"bar_mode01.pvd".to_string()));
    assert!(files.contains(&"bar_mode02_23.vtp".to_string()));
    // Without --json, one line says what was written.
    let (ok, out, err) = ffr(&[
        "modes",
        "--scene",
        s(&scene),
        "--body",
        "bar",
        "--count",
        "2",
        "--vtk",
        s(&v),
    ]);
    assert!(ok, "{err}");
    assert!(
        out.contains("wrote 2 mode animations (24 frames each)") && out.contains("bar_mode*.pvd"),
        "{out}"
    );
}

#[test]
fn run_with_draws_an_fe_body_as_its_nodes() {
    let dir = temp_dir("vtk", "fe-run");
    let path = dir.join("pendulum.toml");
    fe_pendulum(&path, "0.002");
    let fe = ffr::scene::load(&path).unwrap();
    let v = dir.join("v");
    let mut options = ffr::scene::RunOptions::default();
    options.vtk = Some(VtkOptions::new(&v));
    let r = ffr::scene::run_with(&fe, &options).unwrap();
    assert!(r.failed.is_none());
    assert_eq!(
        listing(&v),
        [
            "pendulum.pvd",
            "pendulum_0000.vtp",
            "pendulum_0001.vtp",
            "pendulum_0002.vtp"
        ]
    );
    // 99 nodes and the joint, each a vertex; the array `node` only in a
    // file that draws an FE body.
    let text = std::fs::read_to_string(v.join("pendulum_0002.vtp")).unwrap();
    assert!(
        text.contains(r#"<Piece NumberOfPoints="100" NumberOfVerts="100">"#),
        "{}",
        &text[..400]
    );
    assert!(text.contains(r#"Name="node""#));
    let beams = dir.join("beams");
    options.vtk = Some(VtkOptions {
        dir: beams.clone(),
        every: 1000,
    });
    let arm = ffr::scene::load(Path::new(&scene("two_link_arm.toml"))).unwrap();
    ffr::scene::run_with(&arm, &options).unwrap();
    let text = std::fs::read_to_string(beams.join("two_link_arm_0000.vtp")).unwrap();
    assert!(text.contains(r#"Name="kind""#) && !text.contains(r#"Name="node""#));
}
