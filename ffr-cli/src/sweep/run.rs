//! Running cases: one case (its axes set on the scene, loaded, run under
//! the thread CPU clock, its figures collected), and the local engine, a
//! rayon pool over the cases that `ffr report` uses too.

use super::cases;
use super::study::Study;
use crate::progress::Reporter;
use rayon::prelude::*;

/// What one case gave: a row of `results.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseResult {
    /// The case's number (from 0).
    pub case: usize,
    /// One value per figure (empty when the case failed).
    pub figures: Vec<f64>,
    /// Thread CPU time of the simulation (s; of loading and running when
    /// the scene did not load).
    pub cpu_s: f64,
    /// Why it failed (`None`: ok).
    pub failure: Option<String>,
}

impl CaseResult {
    /// Whether the case gave its figures.
    pub fn ok(&self) -> bool {
        self.failure.is_none()
    }
}

/// Run case `case` of `study` on the calling thread. Nothing here panics:
/// a scene error, a simulation that stops early, a non-finite output or
/// figure, and a panic inside the library are a failed case.
pub fn run_case(study: &Study, case: usize) -> CaseResult {
    let c0 = crate::clock::thread_cpu_seconds();
    let mut cpu = None;
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        case_figures(study, case, &mut cpu)
    }))
    .unwrap_or_else(|p| {
        let msg = p
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "unknown panic".into());
        Err(format!("panicked: {msg}"))
    });
    let cpu_s = cpu.unwrap_or_else(|| crate::clock::thread_cpu_seconds() - c0);
    match r {
        Ok(figures) => CaseResult {
            case,
            figures,
            cpu_s,
            failure: None,
        },
        // The message quotes user text (keys, values, names): escaped
        // and cut, in the table and on the terminal alike.
        Err(m) => CaseResult {
            case,
            figures: Vec::new(),
            cpu_s,
            failure: Some(ffr::codegen::sanitize::snippet(
                &m,
                super::study::MAX_MESSAGE_CHARS,
            )),
        },
    }
}

fn case_figures(study: &Study, case: usize, cpu: &mut Option<f64>) -> Result<Vec<f64>, String> {
    let mut scene = study.scene.clone();
    for (axis, v) in study.axes.iter().zip(cases::values(&study.axes, case)) {
        scene.set(&axis.key, v.clone()).map_err(|e| e.to_string())?;
    }
    let loaded = scene.load().map_err(|e| e.to_string())?;
    let c0 = crate::clock::thread_cpu_seconds();
    let r = ffr::scene::run(&loaded);
    *cpu = Some(crate::clock::thread_cpu_seconds() - c0);
    let r = r.map_err(|e| e.to_string())?;
    if let Some(f) = &r.failed {
        return Err(format!(
            "the run stopped at t = {} s: {f}",
            r.t.last().copied().unwrap_or(0.0)
        ));
    }
    let names: Vec<&str> = r.names.iter().map(String::as_str).collect();
    let cols: Vec<&[f64]> = r.columns.iter().map(Vec::as_slice).collect();
    crate::cli::check_finite_columns(&r.t, &names, &cols)
        .map_err(|e| e.replace(": the run is not valid (nothing written)", ""))?;
    study.figures.iter().map(|f| f.of(&r)).collect()
}

/// The number of local cores (1 if it cannot be known).
pub fn local_cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The local engine: `f(i)` for every `i < n` on a pool of `workers`
/// threads, results in the order of `i` whatever the pool size (each `f(i)`
/// runs whole on one thread, so the thread CPU clock times it).
/// `line(i, &result)` is the progress line of a finished run and whether
/// it failed.
pub fn par_map<T: Send>(
    n: usize,
    workers: usize,
    progress: &Reporter,
    f: impl Fn(usize) -> T + Sync,
    line: impl Fn(usize, &T) -> (String, bool) + Sync,
) -> Result<Vec<T>, String> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(workers.max(1))
        .thread_name(|i| format!("ffr-worker-{i}"))
        .build()
        .map_err(|e| format!("cannot start {workers} worker threads: {e}"))?;
    Ok(pool.install(|| {
        (0..n)
            .into_par_iter()
            .with_max_len(1)
            .map(|i| {
                let r = f(i);
                let (text, failed) = line(i, &r);
                progress.done(&text, failed);
                r
            })
            .collect()
    }))
}

/// Every case of `study` on the local engine.
pub fn local(
    study: &Study,
    workers: usize,
    progress: &Reporter,
) -> Result<Vec<CaseResult>, String> {
    let n = cases::count(&study.axes);
    par_map(
        n,
        workers,
        progress,
        |i| run_case(study, i),
        |i, r| (summary_line(study, i, n, r), !r.ok()),
    )
}

/// A progress line: `[3/8] key=value …: ok, 0.12 s CPU` or `FAILED: …`.
pub fn summary_line(study: &Study, i: usize, n: usize, r: &CaseResult) -> String {
    let params: Vec<String> = study
        .axes
        .iter()
        .zip(cases::values(&study.axes, i))
        .map(|(a, v)| {
            format!(
                "{}={}",
                ffr::codegen::sanitize::snippet(&a.key, 40),
                ffr::codegen::sanitize::snippet(&cases::cell(v), 40)
            )
        })
        .collect();
    let what = match &r.failure {
        None => format!("ok, {:.3} s CPU", r.cpu_s),
        Some(m) => format!("FAILED: {}", ffr::codegen::sanitize::snippet(m, 300)),
    };
    format!("[case {i} of {n}] {}: {what}", params.join(" "))
}
