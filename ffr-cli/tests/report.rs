//! `ffr report`: the quick grid end to end (the command as CI runs it), and
//! the report's handling of failed runs and peer files on a two-run grid
//! through the library API.

use ffr::runtime::spec::Stiffening;
use ffr_cli::report::data::HEADER;
use ffr_cli::report::grid::{Case, ErrorKind, Grid, Method, Scene, Scheme};
use ffr_cli::report::{run_grid, Options, Progress};
use std::path::{Path, PathBuf};
use std::process::Command;

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ffr-report-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `(scene, method, elements, dt, cpu_s, error, error_kind)` of points.csv,
/// checking the header and that every row has seven fields.
fn read_points(path: &Path) -> Vec<(String, String, usize, f64, f64, f64, String)> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(HEADER));
    assert_eq!(HEADER, "scene,method,elements,dt,cpu_s,error,error_kind");
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), 7, "{l}");
            (
                f[0].to_string(),
                f[1].to_string(),
                f[2].parse().unwrap(),
                f[3].parse().unwrap(),
                f[4].parse().unwrap(),
                f[5].parse().unwrap(),
                f[6].to_string(),
            )
        })
        .collect()
}

/// Rows of the "Failed runs" tables of report.md.
fn failed_rows(md: &str) -> usize {
    md.split("### Failed runs")
        .skip(1)
        .map(|sec| {
            let sec = sec.split("\n## ").next().unwrap();
            sec.lines().filter(|l| l.starts_with("| `")).count()
        })
        .sum()
}

#[test]
fn quick_report_writes_every_file_with_valid_points() {
    let out = temp_dir("quick");
    let peers = Path::new(env!("CARGO_MANIFEST_DIR")).join("../bench/peers/results");
    let run = Command::new(env!("CARGO_BIN_EXE_ffr"))
        .args(["report", "--quick", "--out"])
        .arg(&out)
        .arg("--peers")
        .arg(&peers)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    // Not a terminal: one plain progress line per run.
    let grid = Grid::quick();
    assert_eq!(
        stderr.lines().filter(|l| l.starts_with('[')).count(),
        grid.cases.len(),
        "{stderr}"
    );

    let points = read_points(&out.join("points.csv"));
    for (scene, method, n, dt, cpu, err, kind) in &points {
        let sc = Scene::from_name(scene).unwrap_or_else(|| panic!("scene {scene}"));
        assert_eq!(kind, sc.error_kind().name(), "{scene} {method}");
        assert!(
            cpu.is_finite() && *cpu > 0.0,
            "{method} {n} {dt}: cpu {cpu}"
        );
        assert!(
            err.is_finite() && *err >= 0.0,
            "{method} {n} {dt}: error {err}"
        );
        assert!(method.starts_with("ffr-"), "{method}");
    }
    for sc in Scene::ALL {
        assert!(points.iter().any(|p| p.0 == sc.name()), "no point for {sc}");
        let svg = std::fs::read_to_string(out.join(format!("{}.svg", sc.name()))).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("<circle"), "{sc}");
        assert!(svg.contains("Pareto front"), "{sc}");
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    for k in ErrorKind::ALL {
        assert!(md.contains(&format!("`{}`", k.name())), "error kind {k}");
    }
    for sc in Scene::ALL {
        assert!(md.contains(&format!("## {}: ", sc.name())), "{sc}");
        assert!(md.contains(&format!("({}.svg)", sc.name())), "{sc}");
    }
    // Every run is a point or a failure with its reason.
    assert_eq!(points.len() + failed_rows(&md), grid.cases.len());
    // The Exudyn peer file is read and compared.
    assert!(md.contains("bench/peers/results/exudyn.csv"), "peers");
    assert!(
        md.contains("ffr against Exudyn at equal error"),
        "ratio table"
    );
    assert!(md.contains("Modal bodies"), "modal hook");
    std::fs::remove_dir_all(&out).unwrap();
}

/// Two pendulum runs: one that runs, and RK4 far above its stability limit
/// (8 elements of the aluminium bar: axial `ω_max` about 1.4e5 rad/s, so
/// `ω_max dt` ≈ 140 ≫ 2.8 at dt = 1e-3), which must fail and be reported;
/// a peer file with one point is compared at equal error.
#[test]
fn failed_runs_are_reported_and_peers_compared() {
    let out = temp_dir("small");
    let peers = out.join("peers");
    std::fs::create_dir_all(&peers).unwrap();
    std::fs::write(
        peers.join("other.csv"),
        format!("{HEADER}\npendulum,other-method,4,0.001,2.0,5e-3,energy\nnot,a,valid,line\n"),
    )
    .unwrap();
    let ok = Method::new(Scheme::Alpha(1.0), Stiffening::Off);
    let bad = Method::new(Scheme::Rk4, Stiffening::Off);
    let grid = Grid {
        name: "test".into(),
        cases: vec![
            Case {
                scene: Scene::Pendulum,
                method: ok,
                elements: 2,
                dt: 2e-3,
            },
            Case {
                scene: Scene::Pendulum,
                method: bad,
                elements: 8,
                dt: 1e-3,
            },
        ],
        reps: 2,
        rep_budget: 10.0,
    };
    let opts = Options {
        out: out.join("report"),
        peers: peers.clone(),
        progress: Progress::Silent,
        command: "test".into(),
        workers: 2,
    };
    let s = run_grid(&grid, &opts).unwrap();
    // One worker gives the same points and failures (the runs on a pool
    // of two threads), timing aside.
    let one = run_grid(
        &grid,
        &Options {
            out: out.join("report1"),
            workers: 1,
            ..opts.clone()
        },
    )
    .unwrap();
    let key = |s: &ffr_cli::report::ReportSummary| {
        (
            s.points
                .iter()
                .map(|p| {
                    (
                        p.scene.clone(),
                        p.method.clone(),
                        p.elements,
                        p.dt.to_bits(),
                        p.error.to_bits(),
                    )
                })
                .collect::<Vec<_>>(),
            s.failures
                .iter()
                .map(|f| (f.method.clone(), f.reason.clone()))
                .collect::<Vec<_>>(),
        )
    };
    assert_eq!(key(&one), key(&s));
    assert_eq!(s.points.len(), 1);
    assert_eq!(s.points[0].reps, 2);
    assert_eq!(s.failures.len(), 1);
    let f = &s.failures[0];
    assert_eq!(f.method, bad.name());
    assert!(
        f.reason.contains("diverged") || f.reason.contains("non-finite"),
        "{}",
        f.reason
    );
    let points = read_points(&out.join("report/points.csv"));
    assert_eq!(points.len(), 1);
    assert_eq!(points[0].1, ok.name());
    let md = std::fs::read_to_string(out.join("report/report.md")).unwrap();
    assert_eq!(failed_rows(&md), 1);
    assert!(
        md.contains(&format!("| `{}` | 8 | 0.001 |", bad.name())),
        "{md}"
    );
    // The peer's bad line is named, its point compared: at 1e-2 the peer's
    // front costs its one point (error 5e-3 ≤ 1e-2), ffr's its one point.
    assert!(md.contains("other.csv:3: skipped"), "{md}");
    let ffr_cpu = s.points[0].cpu_s;
    assert!(s.points[0].error <= 1e-2);
    assert!(md.contains("ffr against Other at equal error"), "{md}");
    let row = md
        .split("ffr against Other at equal error")
        .nth(1)
        .unwrap()
        .lines()
        .find(|l| l.starts_with("| pendulum | "))
        .unwrap_or_else(|| panic!("{md}"));
    let first = row.split(" | ").nth(1).unwrap();
    let shown: f64 = first.split('×').next().unwrap().parse().unwrap();
    let expected = ffr_cpu / 2.0;
    assert!(
        (shown - expected).abs() <= 0.01 * expected.abs() + 1e-12,
        "{row} vs {expected}"
    );
    // No peer directory: said so.
    let opts2 = Options {
        peers: out.join("nowhere"),
        out: out.join("report2"),
        ..opts
    };
    let grid2 = Grid {
        cases: grid.cases[..1].to_vec(),
        ..grid
    };
    run_grid(&grid2, &opts2).unwrap();
    let md2 = std::fs::read_to_string(out.join("report2/report.md")).unwrap();
    assert!(md2.contains("no peer file was found"), "{md2}");
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn bad_options_are_errors_before_any_run() {
    let out = temp_dir("bad");
    let file = out.join("file");
    std::fs::write(&file, "x").unwrap();
    for (args, needle) in [
        (vec!["--scenes", "nope"], "unknown scene `nope`"),
        (vec!["--out", file.to_str().unwrap()], "is not a directory"),
    ] {
        let r = Command::new(env!("CARGO_BIN_EXE_ffr"))
            .arg("report")
            .arg("--quick")
            .args(&args)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(!stderr.contains("[1/"), "ran before failing: {stderr}");
    }
    std::fs::remove_dir_all(&out).unwrap();
}

/// The quick grid runs every spin-up also with a segmented beam (issue 35),
/// beside the one-body run of the same elements and step; in space the
/// segmented beam's error is below the one body's (whose error stalls at
/// 0.14 from 4 elements on, the one floating frame's limit).
#[test]
fn quick_grid_has_segmented_spin_ups_below_the_one_body() {
    use ffr_cli::report::measure::run_once;
    let grid = Grid::quick();
    for sc in [Scene::SpinUp4, Scene::SpinUp10, Scene::SpinUp3d] {
        let seg: Vec<&Case> = grid
            .cases
            .iter()
            .filter(|c| c.scene == sc && c.method.segments > 1)
            .collect();
        assert!(!seg.is_empty(), "{sc}: no segmented case");
        for c in seg {
            assert_eq!(c.elements % c.method.segments, 0, "{c:?}");
            assert!(
                c.method
                    .name()
                    .ends_with(&format!("-seg{}", c.method.segments)),
                "{}",
                c.method.name()
            );
            let one = Case {
                method: c.method.segments(1),
                ..c.clone()
            };
            assert!(grid.cases.contains(&one), "{sc}: no one-body run of {c:?}");
            if sc != Scene::SpinUp3d {
                continue;
            }
            let (a, b) = (run_once(c).unwrap(), run_once(&one).unwrap());
            println!(
                "{sc} {} el dt {}: {} segments {:e}, one body {:e}",
                c.elements, c.dt, c.method.segments, a.error, b.error
            );
            assert!(a.error < b.error, "{} vs {}", a.error, b.error);
        }
    }
}

/// The segmented runs go through a scene file's text
/// (`spin_up::scene_text`); with one segment that scene is the report's
/// one-body model, built in code: the same tip histories, planar and in
/// space under gravity.
#[test]
fn the_segments_scene_is_the_spin_up_model() {
    use ffr_cli::benchmarks::spin_up::{self, SpinUp};
    use ffr_cli::report::measure::{spin_up_3d_params, SPIN_UP_3D_GRAVITY};
    for spatial in [false, true] {
        let mut cfg = SpinUp::new(10.0);
        if spatial {
            cfg = SpinUp::new(4.0);
            cfg.spatial = true;
            cfg.gravity = SPIN_UP_3D_GRAVITY;
            cfg.params = spin_up_3d_params();
        }
        cfg.elements = 4;
        cfg.dt = 1e-2;
        cfg.t_end = 3.0;
        let direct = spin_up::run(&cfg).unwrap();
        let scene = spin_up::run_segmented(&cfg).unwrap();
        assert!(direct.diverged.is_none() && scene.diverged.is_none());
        assert_eq!(direct.t.len(), scene.t.len());
        let mut diff = 0.0f64;
        let mut peak = 0.0f64;
        for (a, b) in [
            (&direct.tip_axial, &scene.tip_axial),
            (&direct.tip_transverse, &scene.tip_transverse),
            (&direct.tip_lateral, &scene.tip_lateral),
        ] {
            assert_eq!(a.len(), b.len());
            for (x, y) in a.iter().zip(b) {
                diff = diff.max((x - y).abs());
                peak = peak.max(x.abs());
            }
        }
        println!("spatial {spatial}: max |Δ tip| = {diff:e} m (peak {peak:e} m)");
        assert!(peak > 1e-3, "{peak}");
        assert!(diff < 1e-9, "{diff:e}");
    }
}
