//! `ffr sweep`: the spin-up over ω_s and elements gives the same table on 1
//! and 2 workers and through the workers' `--case I --json`; the CSV's
//! columns and numbers; failed cases are rows and the exit is non-zero;
//! bad study files are located errors; ranges and seeded samples are
//! reproducible; errors against a reference CSV; files not ours are kept.

use ffr::scene::SceneValue;
use ffr_cli::progress::Progress;
use ffr_cli::sweep::{self, Engine, SweepArgs};
use std::path::{Path, PathBuf};
use std::process::Command;

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ffr-sweep-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn spin_up_scene() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes/spin_up.toml")
        .canonicalize()
        .unwrap()
        .display()
        .to_string()
}

/// A study file in `dir` on the spin-up scene (by absolute path) with
/// `axes` and `collect` as given.
fn study(dir: &Path, name: &str, axes: &str, collect: &str) -> PathBuf {
    let p = dir.join(name);
    let text = format!(
        "scene = {:?}\n[axes]\n{axes}\n[collect]\n{collect}\n",
        spin_up_scene()
    );
    std::fs::write(&p, text).unwrap();
    p
}

const AXES: &str =
    "\"joints.0.drive.omega\" = [2.0, 4.0]\n\"bodies.beam.elements\" = [4, 8]\nt_end = [1.5]";
const COLLECT: &str = "tip_min = { output = \"tip_transverse\", stat = \"min\" }\ntip_final = { output = \"tip_transverse\", stat = \"final\" }\naxial_max = { output = \"tip_axial\", stat = \"absmax\" }";

fn args(study: &Path, out: &Path, workers: u16) -> SweepArgs {
    SweepArgs {
        study: study.to_path_buf(),
        out: Some(out.to_path_buf()),
        workers: Some(workers),
        engine: Engine::Local,
        scheduler: None,
        python: None,
        worker_ffr: None,
        connect_timeout: 20.0,
        stall_timeout: 60.0,
        case: None,
        json: false,
    }
}

/// The rows of a results.csv (header first), parsed with the csv crate.
fn read_csv(path: &Path) -> Vec<Vec<String>> {
    let mut rd = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_path(path)
        .unwrap();
    rd.records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect()
}

/// A table without its `cpu_s` column.
fn without_cpu(rows: &[Vec<String>]) -> Vec<Vec<String>> {
    let i = rows[0].iter().position(|c| c == "cpu_s").unwrap();
    rows.iter()
        .map(|r| {
            let mut r = r.clone();
            r.remove(i);
            r
        })
        .collect()
}

fn ffr(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_ffr"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn one_and_two_workers_give_the_same_table_and_the_workers_json_the_same_bits() {
    let dir = temp_dir("workers");
    let s = study(&dir, "study.toml", AXES, COLLECT);
    let study = sweep::read(&s).unwrap();
    let one = sweep::sweep(
        &study,
        &args(&s, &dir.join("w1"), 1),
        &dir.join("w1"),
        Progress::Silent,
    )
    .unwrap();
    let two = sweep::sweep(
        &study,
        &args(&s, &dir.join("w2"), 2),
        &dir.join("w2"),
        Progress::Silent,
    )
    .unwrap();
    // Same figures, bit for bit, in case order.
    assert_eq!(one.rows.len(), 4);
    for (a, b) in one.rows.iter().zip(&two.rows) {
        assert!(a.ok(), "{:?}", a.failure);
        assert_eq!(a.case, b.case);
        let bits =
            |r: &sweep::CaseResult| r.figures.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(a), bits(b));
    }
    let t1 = read_csv(&dir.join("w1/results.csv"));
    let t2 = read_csv(&dir.join("w2/results.csv"));
    assert_eq!(without_cpu(&t1), without_cpu(&t2));
    // The columns: case, the axes as written, the figures, cpu_s, status, message.
    assert_eq!(
        t1[0],
        [
            "case",
            "joints.0.drive.omega",
            "bodies.beam.elements",
            "t_end",
            "tip_min",
            "tip_final",
            "axial_max",
            "cpu_s",
            "status",
            "message"
        ]
    );
    // Rows in case order, the last axis fastest, values as written.
    let cells: Vec<(&str, &str, &str)> = t1[1..]
        .iter()
        .map(|r| (r[0].as_str(), r[1].as_str(), r[2].as_str()))
        .collect();
    assert_eq!(
        cells,
        [
            ("0", "2.0", "4"),
            ("1", "2.0", "8"),
            ("2", "4.0", "4"),
            ("3", "4.0", "8")
        ]
    );
    // Every number reads back to the same f64.
    for (row, r) in t1[1..].iter().zip(&one.rows) {
        for (cell, x) in row[4..7].iter().zip(&r.figures) {
            assert_eq!(
                cell.parse::<f64>().unwrap().to_bits(),
                x.to_bits(),
                "{cell}"
            );
        }
        assert_eq!(row[7].parse::<f64>().unwrap().to_bits(), r.cpu_s.to_bits());
        assert!(r.cpu_s > 0.0);
        assert_eq!((row[8].as_str(), row[9].as_str()), ("ok", ""));
    }
    // A faster spin deflects the tip more (the figures are the runs').
    assert!(one.rows[2].figures[0] < one.rows[0].figures[0]);
    // What a Dask worker runs: the same bits as the local engine's row.
    let (ok, out, err) = ffr(&["sweep", s.to_str().unwrap(), "--case", "3", "--json"]);
    assert!(ok, "{err}");
    let r = sweep::results::from_json(&study, 3, &out).unwrap();
    assert_eq!(
        r.figures.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        one.rows[3]
            .figures
            .iter()
            .map(|x| x.to_bits())
            .collect::<Vec<_>>()
    );
    // The plot is written, and is ours.
    let svg = std::fs::read_to_string(dir.join("w1/results.svg")).unwrap();
    assert!(svg.starts_with(sweep::plot::MARK) && svg.contains("<svg"));
}

#[test]
fn failed_cases_are_rows_and_the_command_exits_non_zero() {
    let dir = temp_dir("failed");
    let s = study(
        &dir,
        "study.toml",
        "\"bodies.beam.elements\" = [4, 0]\nintegrator = [{ kind = \"generalized-alpha\", rho_inf = 0.8 }, { kind = \"rk4\" }]\nt_end = [1.0]",
        "tip_min = { output = \"tip_transverse\", stat = \"min\" }",
    );
    let out = dir.join("out");
    let (ok, stdout, stderr) = ffr(&["sweep", s.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(!ok, "a failed case must fail the command");
    assert!(stdout.contains("4 cases: 1 ok, 3 failed"), "{stdout}");
    assert!(stderr.contains("3 of 4 cases failed"), "{stderr}");
    let t = read_csv(&out.join("results.csv"));
    assert_eq!(t.len(), 5);
    let status: Vec<&str> = t[1..].iter().map(|r| r[6].as_str()).collect();
    assert_eq!(status, ["ok", "failed", "failed", "failed"]);
    // The explicit integrator diverges: the runtime's message.
    assert!(t[2][7].contains("diverged"), "{}", t[2][7]);
    assert_eq!(t[2][4], "", "a failed case has no figure");
    // No elements: the loader's located message, naming the keys set.
    assert!(
        t[3][7].contains("spin_up.toml:12:12") && t[3][7].contains("with bodies.beam.elements = 0"),
        "{}",
        t[3][7]
    );
    assert!(!t[1][4].is_empty() && t[1][7].is_empty());
}

/// The error of reading a study with this text.
fn study_error(text: &str) -> String {
    // A directory per call: tests run in parallel.
    static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = N.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = temp_dir(&format!("bad{n}"));
    let p = dir.join("bad.toml");
    std::fs::write(&p, text.replace("SCENE", &spin_up_scene())).unwrap();
    let e = sweep::read(&p).unwrap_err().to_string();
    e.replace(&p.display().to_string(), "bad.toml")
}

#[test]
fn bad_study_files_are_located_errors() {
    let head = "scene = \"SCENE\"\n[axes]\n";
    let tip = "[collect]\ntip = { output = \"tip_transverse\", stat = \"min\" }\n";
    let cases: [(String, &str, &str); 12] = [
        (format!("{head}\"joints.3.drive.omega\" = [1.0]\n{tip}"), "bad.toml:3:1", "has no `3`"),
        (format!("{head}omega = {{ from = 1.0, to = 2.0, steps = 0 }}\n{tip}"), "bad.toml:3:41", "`steps` must be from 1"),
        (format!("{head}t_end = {{ from = 1.0, to = 2.0 }}\n{tip}"), "bad.toml:3:9", "exactly one of `steps`"),
        (format!("{head}t_end = {{ uniform = [1.0, 2.0], samples = 3 }}\n{tip}"), "bad.toml:3:9", "`seed = S`"),
        (format!("{head}t_end = {{ uniform = [2.0, 1.0], samples = 3, seed = 1 }}\n{tip}"), "bad.toml:3:21", "low < high"),
        (format!("{head}t_end = {{ form = 1.0 }}\n{tip}"), "bad.toml:3:11", "form"),
        (format!("{head}t_end = [1.0]\n[collect]\ntip = {{ output = \"tip\", stat = \"min\" }}\n"), "bad.toml:5:18", "no output `tip`"),
        (format!("{head}t_end = [1.0]\n[collect]\ntip = {{ output = \"tip_axial\", stat = \"median\" }}\n"), "bad.toml:5:38", "unknown statistic `median`"),
        (format!("{head}t_end = [1.0]\n[collect]\ntip = {{ output = \"tip_axial\", stat = \"max_error\" }}\n"), "bad.toml:5:7", "needs `reference"),
        (format!("{head}dt = {{ from = 1, to = 100000, step = 1 }}\nt_end = [1.0, 2.0]\n{tip}"), "bad.toml:4:1", "more than 100000 cases"),
        (format!("scene = \"nowhere.toml\"\n{tip}"), "bad.toml:1:9", "nowhere.toml"),
        (format!("{head}t_end = [1.0]\n[collect]\ncase = {{ output = \"tip_axial\", stat = \"min\" }}\n"), "bad.toml:5:1", "already a column"),
    ];
    for (text, at, what) in &cases {
        let e = study_error(text);
        assert!(e.starts_with(at), "expected {at}: {e}\n{text}");
        assert!(e.contains(what), "expected `{what}`: {e}\n{text}");
    }
}

#[test]
fn ranges_and_seeded_samples_are_reproducible() {
    let dir = temp_dir("ranges");
    let axes = "\"joints.0.drive.omega\" = { from = 1.0, to = 4.0, steps = 7 }\n\"bodies.beam.elements\" = { from = 4, to = 16, step = 4 }\n\"joints.0.drive.ramp\" = { uniform = [10.0, 20.0], samples = 5, seed = 1 }\n\"bodies.beam.params.e\" = { normal = [6.9e10, 1e9], samples = 3, seed = 42 }";
    let a = sweep::read(&study(&dir, "a.toml", axes, COLLECT)).unwrap();
    let b = sweep::read(&study(&dir, "b.toml", axes, COLLECT)).unwrap();
    assert_eq!(a.axes, b.axes);
    assert_eq!(sweep::cases::count(&a.axes), 7 * 4 * 5 * 3);
    let floats = |i: usize| -> Vec<f64> {
        a.axes[i]
            .values
            .iter()
            .map(|v| match v {
                SceneValue::Float(x) => *x,
                other => panic!("{other:?}"),
            })
            .collect()
    };
    assert_eq!(floats(0), [1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0]);
    assert_eq!(a.axes[1].values, [4, 8, 12, 16].map(SceneValue::Int));
    let ramp = floats(2);
    assert!(ramp.iter().all(|x| (10.0..20.0).contains(x)), "{ramp:?}");
    let mut distinct = ramp.clone();
    distinct.dedup();
    assert_eq!(distinct.len(), 5);
    assert!(floats(3).iter().all(|e| (6.4e10..7.4e10).contains(e)));
    // Another seed, other samples.
    let c = sweep::read(&study(
        &dir,
        "c.toml",
        &axes.replace("seed = 1", "seed = 2"),
        COLLECT,
    ))
    .unwrap();
    assert_ne!(c.axes[2], a.axes[2]);
    assert_eq!(c.axes[3], a.axes[3]);
    // The stream is ChaCha8 seeded from the seed (rand_chacha 0.9,
    // rand_distr 0.5): the same values on every platform. Pinned here, so
    // that a change of generator or of sampling shows as a failure.
    assert_eq!(
        ramp,
        [
            14.02485663664848,
            10.803837089297819,
            15.965601809348549,
            12.193245804838,
            12.836905913037375
        ]
    );
    assert_eq!(
        floats(3),
        [69477981238.35103, 70334070610.23181, 68789133316.72897]
    );
}

#[test]
fn errors_against_a_reference_csv() {
    let dir = temp_dir("reference");
    // The reference: the scene's own run at ω = 4 rad/s, 1 s, as `ffr run` writes it.
    let mut scene = ffr::scene::SceneText::read(Path::new(&spin_up_scene())).unwrap();
    scene.set("t_end", 1.0.into()).unwrap();
    let r = ffr::scene::run(&scene.load().unwrap()).unwrap();
    let names: Vec<&str> = r.names.iter().map(String::as_str).collect();
    let cols: Vec<&[f64]> = r.columns.iter().map(Vec::as_slice).collect();
    std::fs::write(dir.join("ref.csv"), ffr_cli::plot::csv(&r.t, &names, &cols)).unwrap();
    let s = study(
        &dir,
        "study.toml",
        "\"joints.0.drive.omega\" = [4.0, 3.0]\nt_end = [1.0]",
        "err = { output = \"tip_transverse\", stat = \"max_error\", reference = \"ref.csv\" }\nabs = { output = \"tip_axial\", stat = \"max_abs_error\", reference = \"ref.csv\", column = \"tip_axial\" }",
    );
    let study = sweep::read(&s).unwrap();
    let rows: Vec<_> = (0..2).map(|i| sweep::run_case(&study, i)).collect();
    assert!(rows.iter().all(|r| r.ok()), "{rows:?}");
    assert_eq!(rows[0].figures, [0.0, 0.0], "the reference's own run");
    assert!(
        rows[1].figures[0] > 0.05 && rows[1].figures[1] > 0.0,
        "{:?}",
        rows[1]
    );
    // A reference that does not have the column is a located error.
    std::fs::write(
        &s,
        std::fs::read_to_string(&s)
            .unwrap()
            .replace("column = \"tip_axial\"", "column = \"nope\""),
    )
    .unwrap();
    let e = sweep::read(&s).unwrap_err().to_string();
    assert!(
        e.contains("study.toml:7:") && e.contains("no column `nope`"),
        "{e}"
    );
    // A bad reference file: its line.
    std::fs::write(
        dir.join("ref.csv"),
        "t,tip_transverse,tip_axial\n0,0,0\n0.1,x,0\n",
    )
    .unwrap();
    let e = sweep::read(&s).unwrap_err().to_string();
    assert!(e.contains("ref.csv:3:") && e.contains("`x`"), "{e}");
}

#[test]
fn files_that_are_not_ours_are_kept() {
    let dir = temp_dir("ours");
    let s = study(&dir, "study.toml", "t_end = [0.5]", COLLECT);
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("results.csv"), "a,b\n1,2\n").unwrap();
    let (ok, _, err) = ffr(&["sweep", s.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(!ok && err.contains("not written by ffr sweep"), "{err}");
    assert_eq!(
        std::fs::read_to_string(out.join("results.csv")).unwrap(),
        "a,b\n1,2\n"
    );
    // Our own files are replaced.
    std::fs::remove_file(out.join("results.csv")).unwrap();
    for _ in 0..2 {
        let (ok, _, err) = ffr(&["sweep", s.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        assert!(ok, "{err}");
    }
    // --case checks its range; the Dask engine needs a scheduler.
    let (ok, _, err) = ffr(&["sweep", s.to_str().unwrap(), "--case", "1", "--json"]);
    assert!(!ok && err.contains("the study has 1 cases"), "{err}");
    let (ok, _, err) = ffr(&[
        "sweep",
        s.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--engine",
        "dask",
    ]);
    assert!(!ok && err.contains("needs --scheduler"), "{err}");
    // Each engine's flags are refused with the other.
    let o = out.to_str().unwrap();
    let study = s.to_str().unwrap();
    for (extra, needle) in [
        (
            vec!["--python", "python3"],
            "--python goes with --engine dask",
        ),
        (
            vec!["--scheduler", "tcp://127.0.0.1:9"],
            "--scheduler goes with --engine dask",
        ),
        (
            vec![
                "--engine",
                "dask",
                "--scheduler",
                "tcp://127.0.0.1:9",
                "--workers",
                "2",
            ],
            "--workers sets the local engine's threads",
        ),
    ] {
        let mut a = vec!["sweep", study, "--out", o];
        a.extend(extra);
        let (ok, _, err) = ffr(&a);
        assert!(!ok && err.contains(needle), "{err}");
    }
}

#[test]
fn the_dask_engine_without_python_or_scheduler_is_a_clear_error() {
    let dir = temp_dir("nodask");
    let s = study(&dir, "study.toml", "t_end = [0.5]", COLLECT);
    let out = dir.join("out");
    let (ok, _, err) = ffr(&[
        "sweep",
        s.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--engine",
        "dask",
        "--scheduler",
        "tcp://127.0.0.1:9",
        "--python",
        "/nonexistent/python3",
    ]);
    assert!(
        !ok && err.contains("cannot start Python `/nonexistent/python3`"),
        "{err}"
    );
    assert!(!out.join("results.csv").exists());
}

/// Issue 36: a range whose finite ends are more than `f64::MAX` apart.
/// Before, `uniform` panicked (exit 101) and `steps` gave NaN values whose
/// message blamed the scene ("NaN is not a finite number").
#[test]
fn ranges_whose_width_overflows_are_values_or_located_errors() {
    let head = "scene = \"SCENE\"\n[axes]\n";
    let tip = "[collect]\ntip = { output = \"tip_transverse\", stat = \"min\" }\n";
    // `steps`: the ends and the points between them, finite.
    let dir = temp_dir("overflow");
    let s = study(
        &dir,
        "study.toml",
        "\"bodies.beam.params.e\" = { from = -1e308, to = 1e308, steps = 5 }",
        "tip = { output = \"tip_transverse\", stat = \"min\" }",
    );
    let st = sweep::read(&s).unwrap();
    assert_eq!(
        st.axes[0].values,
        [-1e308, -5e307, 0.0, 5e307, 1e308].map(SceneValue::Float)
    );
    // Samples that cannot be drawn, or that overflow: located errors.
    for (axis, at, what) in [
        (
            "t_end = { uniform = [-1e308, 1e308], samples = 3, seed = 1 }",
            "bad.toml:3:21",
            "is not a finite number",
        ),
        (
            "t_end = { normal = [1e308, 1e308], samples = 20, seed = 1 }",
            "bad.toml:3:20",
            "is inf, not a finite number",
        ),
    ] {
        let e = study_error(&format!("{head}{axis}\n{tip}"));
        assert!(e.starts_with(at) && e.contains(what), "{e}");
        assert!(!e.contains("NaN"), "{e}");
    }
}

/// Issue 36: two axes reaching one place (the same key with another index
/// spelling, or one inside the other) made rows report values the run did
/// not use; they are refused at the second key.
#[test]
fn axes_on_one_place_are_refused() {
    let head = "scene = \"SCENE\"\n[axes]\n";
    let tip = "[collect]\ntip = { output = \"tip_transverse\", stat = \"min\" }\n";
    let drive = "{ kind = \"spin-up\", omega = 2.0, ramp = 15.0 }";
    for (axes, at, what) in [
        (
            "\"joints.0.drive.omega\" = [1.0, 2.0]\n\"joints.00.drive.omega\" = [3.0]".to_string(),
            "bad.toml:4:1",
            "axis `joints.00.drive.omega` sets the same place as axis `joints.0.drive.omega` (line 3)",
        ),
        (
            format!("\"joints.0.drive\" = [{drive}]\n\"joints.0.drive.omega\" = [3.0]"),
            "bad.toml:4:1",
            "axis `joints.0.drive.omega` sets a value inside the place of axis `joints.0.drive` (line 3)",
        ),
        (
            format!("\"joints.0.drive.omega\" = [3.0]\nt_end = [1.0]\n\"joints.000.drive\" = [{drive}]"),
            "bad.toml:5:1",
            "axis `joints.000.drive` sets the place holding axis `joints.0.drive.omega` (line 3)",
        ),
    ] {
        let e = study_error(&format!("{head}{axes}\n{tip}"));
        assert!(e.starts_with(at) && e.contains(what), "{e}");
    }
    // Places side by side are fine.
    let dir = temp_dir("places");
    let s = study(
        &dir,
        "study.toml",
        "\"joints.0.drive.omega\" = [1.0]\n\"joints.0.drive.ramp\" = [10.0]\n\"bodies.beam.params.e\" = [7e10]",
        "tip = { output = \"tip_transverse\", stat = \"min\" }",
    );
    assert_eq!(sweep::read(&s).unwrap().axes.len(), 3);
}

/// No control, bidi or other invisible character of `s` is raw.
fn assert_escaped(s: &str) {
    let raw = s
        .chars()
        .find(|&c| (c.is_control() && c != '\n') || ('\u{200b}'..='\u{202e}').contains(&c));
    assert!(raw.is_none(), "raw {raw:?} in {s:?}");
}

/// Issue 36: axis keys with escape sequences, bidi overrides and newlines
/// reached the terminal raw (in the study's errors and the failed rows).
#[test]
fn user_text_from_a_study_is_escaped() {
    let dir = temp_dir("escape");
    let hostile = [
        "joints\\u001b]0;X\\u0007.0.drive",
        "joints.0.dr\\u202eive.omega",
        "bodies.be\\nam.elements",
    ];
    for key in hostile {
        // A key that does not reach the scene: the study's error.
        let s = dir.join("study.toml");
        std::fs::write(
            &s,
            format!(
                "scene = {:?}\n[axes]\n\"{key}\" = [1.0]\n[collect]\ntip = {{ output = \"tip_transverse\", stat = \"min\" }}\n",
                spin_up_scene()
            ),
        )
        .unwrap();
        let (ok, out, err) = ffr(&[
            "sweep",
            s.to_str().unwrap(),
            "--out",
            dir.join("o").to_str().unwrap(),
        ]);
        assert!(!ok && err.contains("study.toml:3:1: axis `"), "{err}");
        assert_escaped(&out);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert_escaped(err.trim_end());
    }
    // A key the scene takes (a new field) whose cases fail: the progress
    // lines, the summary and the table's message and header.
    let s = dir.join("study2.toml");
    std::fs::write(
        &s,
        format!(
            "scene = {:?}\n[axes]\n\"joints.0.drive.om\\u001b[2J\\u202e\\nega\" = [1.0]\nt_end = [0.1]\n[collect]\ntip = {{ output = \"tip_transverse\", stat = \"min\" }}\n",
            spin_up_scene()
        ),
    )
    .unwrap();
    let out_dir = dir.join("o2");
    let (ok, out, err) = ffr(&[
        "sweep",
        s.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert!(!ok && err.contains("1 of 1 cases failed"), "{err}");
    assert_escaped(&out);
    assert_escaped(&err.replace('\n', " "));
    assert!(err.contains("om\\u{1b}[2J\\u{202e}\\nega"), "{err}");
    let t = read_csv(&out_dir.join("results.csv"));
    for cell in t[0].iter().chain(&t[1]) {
        assert_escaped(cell);
        assert!(!cell.contains('\n'), "{cell:?}");
    }
    assert_eq!(t[0][1], "joints.0.drive.om\\u{1b}[2J\\u{202e}\\nega");
}

/// Issue 36: a reference CSV with a column name twice was read silently
/// from the first; it is refused at its header, naming the column.
#[test]
fn a_reference_with_a_column_named_twice_is_refused() {
    let dir = temp_dir("dupref");
    std::fs::write(
        dir.join("ref.csv"),
        "t,tip_transverse,tip_axial,tip_transverse\n0,0,0,1\n1,0,0,1\n",
    )
    .unwrap();
    let s = study(
        &dir,
        "study.toml",
        "t_end = [1.0]",
        "err = { output = \"tip_transverse\", stat = \"max_error\", reference = \"ref.csv\" }",
    );
    let e = sweep::read(&s).unwrap_err().to_string();
    assert!(
        e.contains("study.toml:5:")
            && e.contains(
                "ref.csv:1: column `tip_transverse` appears twice (columns 2 and 4); name each column once"
            ),
        "{e}"
    );
    // `ffr run --reference` refuses it too.
    let (ok, _, err) = ffr(&[
        "run",
        &spin_up_scene(),
        "--csv",
        dir.join("o.csv").to_str().unwrap(),
        "--reference",
        dir.join("ref.csv").to_str().unwrap(),
    ]);
    assert!(!ok && err.contains("appears twice"), "{err}");
    assert!(!dir.join("o.csv").exists());
}

/// Issue 36: only the columns a study's figures name are stored (others are
/// only counted), and the numbers of all references are bounded together
/// (MAX_REFERENCE_VALUES) before they are stored.
#[test]
fn references_store_the_columns_named_within_a_bound() {
    use ffr_cli::reference::{Reference, MAX_REFERENCE_VALUES};
    let dir = temp_dir("refcols");
    let p = dir.join("ref.csv");
    std::fs::write(&p, "t,a,b,c\n0,1,x,3\n0.5,2,y,4\n1,3,z,5\n").unwrap();
    let r = Reference::read_columns(&p, Some(&["c", "a"]), 0).unwrap();
    assert_eq!(r.columns, ["a", "c"]);
    assert_eq!(r.header, ["a", "b", "c"]);
    assert_eq!(r.t, [0.0, 0.5, 1.0]);
    assert_eq!(r.values, [vec![1.0, 2.0, 3.0], vec![3.0, 4.0, 5.0]]);
    assert_eq!(r.numbers(), 9);
    // The column not read is not checked; read, it is an error at its line.
    let e = Reference::read(&p).unwrap_err();
    assert!(
        e.ends_with("ref.csv:2: `x` in column `b` is not a finite number"),
        "{e}"
    );
    // The bound counts the numbers other references hold.
    assert!(Reference::read_columns(&p, Some(&["a"]), MAX_REFERENCE_VALUES - 6).is_ok());
    let e = Reference::read_columns(&p, Some(&["a"]), MAX_REFERENCE_VALUES - 5).unwrap_err();
    assert!(
        e.contains("3 rows of t and 1 column(s) read are 6 numbers; with the 16777211 of the other references read that is more than MAX_REFERENCE_VALUES (16777216) together"),
        "{e}"
    );
    // A line longer than MAX_REFERENCE_LINE is refused at its line.
    let long = format!(
        "t,a\n0,1\n1,{}\n",
        "1".repeat(ffr_cli::reference::MAX_REFERENCE_LINE + 10)
    );
    std::fs::write(&p, long).unwrap();
    let e = Reference::read(&p).unwrap_err();
    assert!(
        e.contains("ref.csv:3: line 3 is longer than 1048576 bytes (MAX_REFERENCE_LINE)"),
        "{e}"
    );
}

/// Found by tests/fuzz_studies.rs: an integer range whose steps pass i64
/// (`from + i step` computed in i64) panicked in a debug build and wrapped
/// in a release build.
#[test]
fn integer_ranges_near_the_ends_of_i64_are_exact() {
    let dir = temp_dir("i64");
    let s = study(
        &dir,
        "study.toml",
        "\"bodies.beam.elements\" = { from = -9223372036854775808, to = 9223372036854775807, step = 9223372036854775807 }",
        "tip = { output = \"tip_transverse\", stat = \"min\" }",
    );
    let st = sweep::read(&s).unwrap();
    assert_eq!(
        st.axes[0].values,
        [i64::MIN, -1, i64::MAX - 1].map(SceneValue::Int)
    );
}

/// The Dask engine's timeouts are positive and at most MAX_TIMEOUT_S (a
/// year): the watchdog's deadlines are durations built from them.
#[test]
fn dask_timeouts_out_of_range_are_refused() {
    let dir = temp_dir("timeouts");
    let s = study(&dir, "study.toml", "t_end = [0.5]", COLLECT);
    let out = dir.join("out");
    for (flag, value) in [
        ("--connect-timeout", "1e300"),
        ("--connect-timeout", "0"),
        ("--stall-timeout", "-1"),
        ("--stall-timeout", "inf"),
    ] {
        let arg = format!("{flag}={value}");
        let (ok, _, err) = ffr(&[
            "sweep",
            s.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--engine",
            "dask",
            "--scheduler",
            "tcp://127.0.0.1:9",
            &arg,
        ]);
        assert!(
            !ok && err.contains(&format!(
                "{flag} must be a positive number of seconds, at most 3.2e7 (MAX_TIMEOUT_S)"
            )),
            "{flag} {value}: {err}"
        );
        assert!(!out.exists());
    }
}
