//! `ffr report`: the benchmark scenes over their discretization choices, as
//! a work-precision report in the manner of DifferentialEquations.jl's
//! work-precision diagrams and the IVP test set's solver reports.
//!
//! Every run of a [`grid::Grid`] (scene, method family, elements, time
//! step; on every local core by default, through `ffr sweep`'s local
//! engine, [`crate::sweep::par_map`]) is set up with the library's scene modules ([`crate::benchmarks`]),
//! integrated under a CPU clock ([`measure::thread_cpu_seconds`]; the
//! minimum over repetitions) and measured against the best available
//! reference ([`grid::ErrorKind`]). The output directory receives
//! `report.md` (tables and their reading), `points.csv`
//! (`scene,method,elements,dt,cpu_s,error,error_kind`) and one SVG diagram
//! per scene, with the peers' points (`bench/peers/results/*.csv`) beside
//! ffr's. A run that fails is listed in `report.md` with its reason and
//! gives no point. How to run it and how long it takes: `docs/report.md`.

pub mod analysis;
pub mod data;
pub mod grid;
pub mod markdown;
pub mod measure;
pub mod plot;

use clap::Args;
use data::{FailedRun, Point};
use grid::{Grid, Scene};
use measure::Outcome;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Options of `ffr report`.
#[derive(Args, Debug, Clone)]
pub struct ReportArgs {
    /// A small grid (every scene and every kind of choice, one repetition
    /// per run; under a minute in a release build) instead of the full one.
    #[arg(long)]
    pub quick: bool,
    /// Directory for report.md, points.csv and the SVG diagrams.
    #[arg(long, default_value = "results/report")]
    pub out: PathBuf,
    /// Directory of peer results (`*.csv` with the columns of points.csv),
    /// relative to the current directory.
    #[arg(long, default_value = "bench/peers/results")]
    pub peers: PathBuf,
    /// Repetitions per run, the CPU time being their minimum (default: 3,
    /// with --quick 1; a run stops repeating once its repetitions used 3 s).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=100))]
    pub reps: Option<u16>,
    /// Only these scenes (comma-separated: spin-up-4, spin-up-10,
    /// spin-up-3d, slider-crank, pendulum, free-floating).
    #[arg(long, value_delimiter = ',')]
    pub scenes: Vec<String>,
    /// Runs at once, each on its own thread (default: every local core;
    /// CPU times are still per run, on the run's thread).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub workers: Option<u16>,
}

pub use crate::progress::Progress;
use crate::progress::Reporter;

/// Where the report goes and what it reads besides the runs.
#[derive(Clone, Debug)]
pub struct Options {
    /// Output directory.
    pub out: PathBuf,
    /// Peers' directory.
    pub peers: PathBuf,
    /// Progress display.
    pub progress: Progress,
    /// The command line that made the report (quoted in report.md).
    pub command: String,
    /// Runs at once (the local engine of `ffr sweep`; at least 1).
    pub workers: usize,
}

/// What a report run produced.
#[derive(Clone, Debug)]
pub struct ReportSummary {
    /// ffr's points (those in points.csv), in grid order.
    pub points: Vec<Point>,
    /// Runs that gave no point.
    pub failures: Vec<FailedRun>,
    /// Peers' points used (scenes of the grid).
    pub peer_points: Vec<Point>,
    /// Files written.
    pub files: Vec<PathBuf>,
    /// Wall time of the whole report (s).
    pub wall_s: f64,
    /// CPU time of the simulations (sum over every repetition, s).
    pub sim_cpu_s: f64,
}

/// The grid `args` asks for.
pub fn grid_for(args: &ReportArgs) -> Result<Grid, String> {
    let mut grid = if args.quick {
        Grid::quick()
    } else {
        Grid::full()
    };
    if let Some(r) = args.reps {
        grid.reps = r as usize;
        grid.rep_budget = grid.rep_budget.max(if r > 1 { 3.0 } else { 0.0 });
    }
    if !args.scenes.is_empty() {
        let mut scenes = Vec::new();
        for s in &args.scenes {
            let scene = Scene::from_name(s.trim()).ok_or_else(|| {
                format!(
                    "--scenes: unknown scene `{s}` (scenes: {})",
                    Scene::ALL.map(|s| s.name()).join(", ")
                )
            })?;
            scenes.push(scene);
        }
        grid = grid.only(&scenes);
    }
    Ok(grid)
}

/// Run `ffr report`: the grid, then report.md, points.csv and the diagrams
/// in `args.out`. Failed runs are reported, not errors; an error means the
/// report itself could not be made (bad options, an output not writable).
pub fn run(args: &ReportArgs) -> Result<ReportSummary, Box<dyn std::error::Error>> {
    let grid = grid_for(args)?;
    let mut command = String::from("ffr report");
    if args.quick {
        command.push_str(" --quick");
    }
    if let Some(r) = args.reps {
        command.push_str(&format!(" --reps {r}"));
    }
    if !args.scenes.is_empty() {
        command.push_str(&format!(" --scenes {}", args.scenes.join(",")));
    }
    let opts = Options {
        out: args.out.clone(),
        peers: args.peers.clone(),
        progress: Progress::Auto,
        command,
        workers: args
            .workers
            .map_or_else(crate::sweep::local_cores, |w| w as usize),
    };
    let s = run_grid(&grid, &opts)?;
    crate::outln!(
        "{} runs: {} points, {} failed; {:.1} s wall, {:.1} s CPU in the simulations",
        grid.cases.len(),
        s.points.len(),
        s.failures.len(),
        s.wall_s,
        s.sim_cpu_s
    )?;
    for f in &s.files {
        crate::outln!("wrote {}", f.display())?;
    }
    Ok(s)
}

/// Check that `out` can be a directory before spending time on the runs.
fn check_out_dir(out: &Path) -> Result<(), String> {
    if out.exists() && !out.is_dir() {
        return Err(format!(
            "{}: exists and is not a directory (--out names the report's directory)",
            out.display()
        ));
    }
    std::fs::create_dir_all(out)
        .map_err(|e| format!("{}: cannot create the directory: {e}", out.display()))
}

/// `/proc/loadavg`'s first three fields, where there is one.
fn load_average() -> Option<String> {
    let s = std::fs::read_to_string("/proc/loadavg").ok()?;
    Some(s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
}

/// Run `grid` and write the report to `opts.out`.
pub fn run_grid(grid: &Grid, opts: &Options) -> Result<ReportSummary, Box<dyn std::error::Error>> {
    check_out_dir(&opts.out)?;
    let scenes = grid.scenes();
    // Every file the report will write, checked before the runs.
    let csv_path = opts.out.join("points.csv");
    let svg_paths: Vec<PathBuf> = scenes
        .iter()
        .map(|s| opts.out.join(format!("{}.svg", s.name())))
        .collect();
    let md_path = opts.out.join("report.md");
    let mut outputs = vec![("a file of --out", csv_path.as_path())];
    outputs.extend(svg_paths.iter().map(|p| ("a file of --out", p.as_path())));
    outputs.push(("a file of --out", md_path.as_path()));
    crate::output::check_outputs(&outputs)?;
    let start = Instant::now();
    let load_before = load_average();
    let peers = data::read_peers(&opts.peers);
    let reporter = Reporter::new(opts.progress, grid.cases.len());
    // Every case on the local engine of `ffr sweep` (a pool of
    // `opts.workers` threads), in grid order; a case runs whole on one
    // thread, whose CPU clock times it.
    let n = grid.cases.len();
    let outcomes = crate::sweep::par_map(
        n,
        opts.workers,
        &reporter,
        |i| {
            let c0 = measure::thread_cpu_seconds();
            let outcome = measure::measure(&grid.cases[i], grid.reps, grid.rep_budget);
            (outcome, measure::thread_cpu_seconds() - c0)
        },
        |i, (outcome, _)| {
            let case = &grid.cases[i];
            let what = match outcome {
                Outcome::Point {
                    cpu_s, error, reps, ..
                } => format!("{cpu_s:.4} s CPU (min of {reps}), error {error:.3e}"),
                Outcome::Failed { reason, .. } => format!("FAILED: {reason}"),
            };
            let line = format!(
                "[{}/{n}] {} {} elements {} dt {}: {what}",
                i + 1,
                case.scene,
                case.method.name(),
                case.elements,
                case.dt
            );
            (line, matches!(outcome, Outcome::Failed { .. }))
        },
    )?;
    let mut points = Vec::new();
    let mut failures = Vec::new();
    let mut sim_cpu = 0.0;
    for (case, (outcome, cpu)) in grid.cases.iter().zip(outcomes) {
        sim_cpu += cpu;
        match outcome {
            Outcome::Point {
                cpu_s, error, reps, ..
            } => points.push(Point {
                scene: case.scene.name().into(),
                method: case.method.name(),
                elements: case.elements,
                dt: case.dt,
                cpu_s,
                error,
                error_kind: case.scene.error_kind().name().into(),
                tool: "ffr".into(),
                reps,
            }),
            Outcome::Failed { reason, t } => failures.push(FailedRun {
                scene: case.scene.name().into(),
                method: case.method.name(),
                elements: case.elements,
                dt: case.dt,
                reason,
                t,
            }),
        }
    }
    reporter.finish();
    let load_after = load_average();
    let peer_points: Vec<Point> = peers
        .points
        .iter()
        .filter(|p| scenes.iter().any(|s| s.name() == p.scene))
        .cloned()
        .collect();

    let mut texts = vec![data::csv(&points)];
    for scene in &scenes {
        let mut pts: Vec<Point> = points
            .iter()
            .filter(|p| p.scene == scene.name())
            .cloned()
            .collect();
        pts.extend(
            peer_points
                .iter()
                .filter(|p| p.scene == scene.name())
                .cloned(),
        );
        let svg = plot::diagram(
            scene.title(),
            &format!(
                "error ({}: {})",
                scene.error_kind(),
                markdown::error_short(*scene)
            ),
            &pts,
        )?;
        texts.push(svg);
    }
    let wall_s = start.elapsed().as_secs_f64();
    let md = markdown::report(&markdown::Input {
        grid,
        command: &opts.command,
        points: &points,
        failures: &failures,
        peers: &peers,
        peer_points: &peer_points,
        wall_s,
        sim_cpu_s: sim_cpu,
        load: (load_before, load_after),
        workers: opts.workers,
    });
    texts.push(md);
    // All files or none: every one staged, then all renamed.
    let mut files = vec![csv_path];
    files.extend(svg_paths);
    files.push(md_path);
    let writes: Vec<(&Path, &[u8])> = files
        .iter()
        .zip(&texts)
        .map(|(p, t)| (p.as_path(), t.as_bytes()))
        .collect();
    crate::output::write_all_atomic(&writes)?;
    Ok(ReportSummary {
        points,
        failures,
        peer_points,
        files,
        wall_s,
        sim_cpu_s: sim_cpu,
    })
}
