//! `ffr sweep STUDY.toml --out DIR`: a scene over parameter axes, the
//! figures of every case in `DIR/results.csv` and a plot in
//! `DIR/results.svg`, on every local core or on a Dask cluster (format,
//! columns and cluster set-up: `docs/sweep.md`).
//!
//! - [`study`]: the study file, with located errors;
//! - [`cases`]: the product of the axes, ranges and seeded samples;
//! - [`collect`]: the figures of one run;
//! - [`run`](mod@run): one case, and the local engine (a rayon pool, also
//!   `ffr report`'s);
//! - [`results`]: the table and one case's JSON;
//! - [`plot`]: the SVG;
//! - [`dask`]: the distributed engine.

pub mod cases;
pub mod collect;
pub mod dask;
pub mod plot;
pub mod results;
pub mod run;
pub mod study;

pub use cases::{Axis, MAX_CASES};
pub use collect::{Figure, Stat};
pub use run::{local_cores, par_map, run_case, CaseResult};
pub use study::{read, Study, StudyError};

use crate::progress::{Progress, Reporter};
use clap::{Args, ValueEnum};
use std::path::PathBuf;
use std::time::Instant;

/// The longest `--connect-timeout` and `--stall-timeout`, in seconds (a
/// year).
pub const MAX_TIMEOUT_S: f64 = 3.2e7;

/// Where the cases run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Engine {
    /// Threads on this machine (`--workers`).
    Local,
    /// A Dask cluster (`--scheduler`).
    Dask,
}

/// Options of `ffr sweep`.
#[derive(Args, Debug, Clone)]
pub struct SweepArgs {
    /// The study file (TOML: `scene`, `[axes]`, `[collect]`; docs/sweep.md).
    pub study: PathBuf,
    /// Directory for results.csv and results.svg.
    #[arg(long, required_unless_present = "case")]
    pub out: Option<PathBuf>,
    /// Worker threads of the local engine (default: every local core).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub workers: Option<u16>,
    /// Where the cases run.
    #[arg(long, value_enum, default_value_t = Engine::Local)]
    pub engine: Engine,
    /// The Dask scheduler's address (`tcp://HOST:PORT`; --engine dask).
    #[arg(long)]
    pub scheduler: Option<String>,
    /// The Python interpreter with `dask[distributed]` (--engine dask;
    /// default: the environment variable FFR_PYTHON, else `python3`).
    #[arg(long)]
    pub python: Option<String>,
    /// The ffr binary the Dask workers run (default: this one; an absolute
    /// path every worker can reach).
    #[arg(long)]
    pub worker_ffr: Option<PathBuf>,
    /// Seconds to wait for the Dask scheduler.
    #[arg(long, default_value_t = 20.0)]
    pub connect_timeout: f64,
    /// Seconds without progress after which a Dask sweep stops (no case
    /// finished and none running on a worker: a scheduler without workers,
    /// or whose workers died); the finished rows are written, the others
    /// marked failed (--engine dask).
    #[arg(long, default_value_t = 60.0)]
    pub stall_timeout: f64,
    /// Run only this case and print its JSON (what a Dask worker runs).
    #[arg(long, hide = true, requires = "json")]
    pub case: Option<usize>,
    /// With --case: print the case as JSON.
    #[arg(long, hide = true, requires = "case")]
    pub json: bool,
}

/// What a sweep produced.
#[derive(Clone, Debug)]
pub struct SweepSummary {
    /// Rows in case order.
    pub rows: Vec<CaseResult>,
    /// Files written.
    pub files: Vec<PathBuf>,
    /// Wall time (s).
    pub wall_s: f64,
    /// Why the sweep stopped before every case ran (the Dask engine's
    /// watchdog, a cluster that failed); those cases are failed rows.
    pub stopped: Option<String>,
}

/// Run `ffr sweep`. The table is written whatever the cases gave; the
/// command fails (after writing) if any case failed.
pub fn run(args: &SweepArgs) -> Result<SweepSummary, Box<dyn std::error::Error>> {
    let study = study::read(&args.study)?;
    let n = cases::count(&study.axes);
    if let Some(i) = args.case {
        if i >= n {
            return Err(format!("--case {i}: the study has {n} cases (0 to {})", n - 1).into());
        }
        let r = run::run_case(&study, i);
        crate::outln!("{}", results::case_json(&study, &r))?;
        return Ok(SweepSummary {
            rows: vec![r],
            files: Vec::new(),
            wall_s: 0.0,
            stopped: None,
        });
    }
    let out = args
        .out
        .clone()
        .expect("clap requires --out without --case");
    let summary = sweep(&study, args, &out, Progress::Auto)?;
    let failed = summary.rows.iter().filter(|r| !r.ok()).count();
    let cpu: f64 = summary.rows.iter().map(|r| r.cpu_s).sum();
    crate::outln!(
        "{n} cases: {} ok, {failed} failed; {:.2} s wall, {:.2} s CPU in the simulations ({})",
        n - failed,
        summary.wall_s,
        cpu,
        match args.engine {
            Engine::Local => match workers(args) {
                1 => "local, 1 worker".to_string(),
                w => format!("local, {w} workers"),
            },
            Engine::Dask => format!(
                "dask at {}",
                ffr::codegen::sanitize::snippet(args.scheduler.as_deref().unwrap_or("?"), 200)
            ),
        }
    )?;
    for f in &summary.files {
        crate::outln!("wrote {}", f.display())?;
    }
    if let Some(why) = &summary.stopped {
        return Err(format!(
            "the sweep stopped: {why}; {failed} of {n} cases failed or did not run (status and message columns of {})",
            summary.files[0].display()
        )
        .into());
    }
    if failed > 0 {
        return Err(format!(
            "{failed} of {n} cases failed (status and message columns of {})",
            summary.files[0].display()
        )
        .into());
    }
    Ok(summary)
}

fn workers(args: &SweepArgs) -> usize {
    args.workers.map_or_else(local_cores, |w| w as usize)
}

/// Run every case of `study` on the engine `args` names and write
/// `out/results.csv` and `out/results.svg` (failed cases are rows).
pub fn sweep(
    study: &Study,
    args: &SweepArgs,
    out: &std::path::Path,
    progress: Progress,
) -> Result<SweepSummary, Box<dyn std::error::Error>> {
    if out.exists() && !out.is_dir() {
        return Err(format!(
            "{}: exists and is not a directory (--out names the sweep's directory)",
            out.display()
        )
        .into());
    }
    let csv_path = out.join("results.csv");
    let svg_path = out.join("results.svg");
    for p in [&csv_path, &svg_path] {
        results::check_ours(p)?;
    }
    crate::output::check_outputs(&[("--out", &csv_path), ("--out", &svg_path)])?;
    let dask = match args.engine {
        Engine::Local => {
            let dask_only = [
                ("--scheduler", args.scheduler.is_some()),
                ("--python", args.python.is_some()),
                ("--worker-ffr", args.worker_ffr.is_some()),
            ];
            if let Some((flag, _)) = dask_only.iter().find(|(_, given)| *given) {
                return Err(format!("{flag} goes with --engine dask").into());
            }
            None
        }
        Engine::Dask => {
            if args.workers.is_some() {
                return Err("--workers sets the local engine's threads; with --engine dask the Dask workers' threads (dask worker --nthreads) set how many cases run at once".into());
            }
            let scheduler = args
                .scheduler
                .clone()
                .ok_or("--engine dask needs --scheduler ADDRESS (e.g. tcp://10.0.0.1:8786)")?;
            for (flag, s) in [
                ("--connect-timeout", args.connect_timeout),
                ("--stall-timeout", args.stall_timeout),
            ] {
                if !(s.is_finite() && s > 0.0 && s <= MAX_TIMEOUT_S) {
                    return Err(format!(
                        "{flag} must be a positive number of seconds, at most {MAX_TIMEOUT_S:e} (MAX_TIMEOUT_S)"
                    )
                    .into());
                }
            }
            Some(dask::DaskOptions {
                scheduler,
                python: args
                    .python
                    .clone()
                    .or_else(|| std::env::var("FFR_PYTHON").ok().filter(|s| !s.is_empty()))
                    .unwrap_or_else(|| "python3".into()),
                worker_ffr: match &args.worker_ffr {
                    Some(p) => p.clone(),
                    None => std::env::current_exe().map_err(|e| {
                        format!(
                            "cannot find this ffr binary for the workers: {e} (give --worker-ffr)"
                        )
                    })?,
                },
                connect_timeout: args.connect_timeout,
                stall_timeout: args.stall_timeout,
            })
        }
    };
    let n = cases::count(&study.axes);
    let start = Instant::now();
    let reporter = Reporter::new(progress, n);
    let rows = match &dask {
        None => run::local(study, workers(args), &reporter).map(|rows| (rows, None)),
        Some(opts) => dask::run(study, opts, &reporter).map(|r| (r.rows, r.stopped)),
    };
    reporter.finish();
    let (rows, stopped) = rows?;
    let wall_s = start.elapsed().as_secs_f64();
    let table = results::csv(study, &rows)?;
    let svg = plot::svg(study, &rows)?;
    crate::output::write_all_atomic(&[(&csv_path, table.as_bytes()), (&svg_path, svg.as_bytes())])?;
    Ok(SweepSummary {
        rows,
        files: vec![csv_path, svg_path],
        wall_s,
        stopped,
    })
}
