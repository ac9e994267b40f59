//! `ffr stability`: a suite of stiff and extreme cases, each run under a CPU
//! limit and `catch_unwind`, written to `stability.md` (one row per case:
//! what it stresses, its check and bound, the outcome, the figures). The
//! command exits non-zero if any case fails.
//!
//! A case passes when its run is bounded and its check holds, or when the
//! program refuses it with an error naming the cause (the case says which
//! refusal it expects). It fails on a panic, a non-finite figure, a run
//! stopped by its CPU limit, an unexpected error, or a check that does not
//! hold. The cases are in [`cases`]; how to run the suite and what each case
//! checks: `docs/stability.md`.

pub mod cases;

use crate::clock::thread_cpu_seconds;
use clap::Args;
use std::cell::Cell;
use std::fmt::Write as _;
use std::ops::ControlFlow;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::Instant;

pub use crate::progress::Progress;
use crate::progress::Reporter;

/// Options of `ffr stability`.
#[derive(Args, Debug, Clone)]
pub struct StabilityArgs {
    /// The quick subset (what CI runs; a few seconds in a release build)
    /// instead of the full suite.
    #[arg(long)]
    pub quick: bool,
    /// Directory for stability.md.
    #[arg(long, default_value = "results/stability")]
    pub out: PathBuf,
}

/// How a case ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// Bounded and its check holds.
    Pass,
    /// Refused by the program with the expected error (quoted).
    Refused(String),
    /// Failed, with the reason.
    Fail(String),
}

impl Verdict {
    /// Whether the case passed (a run that held its check, or an expected refusal).
    pub fn passed(&self) -> bool {
        !matches!(self, Verdict::Fail(_))
    }
}

/// What a case's run gives back: its verdict and the figures that show it.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The verdict of the case's own check.
    pub verdict: Verdict,
    /// `(name, value)` figures (errors, drifts, iterations…), in table order.
    pub figures: Vec<(String, f64)>,
}

impl Outcome {
    /// A passing outcome with these figures.
    pub fn pass(figures: Vec<(String, f64)>) -> Self {
        Self {
            verdict: Verdict::Pass,
            figures,
        }
    }
}

/// A CPU-time limit, asked after every step of a case's runs.
pub struct Budget {
    start: f64,
    limit: f64,
    stopped_at: Cell<Option<f64>>,
}

impl Budget {
    /// A limit of `limit` CPU seconds of this thread, from now.
    pub fn new(limit: f64) -> Self {
        Self {
            start: thread_cpu_seconds(),
            limit,
            stopped_at: Cell::new(None),
        }
    }

    /// Go on while the CPU time used is within the limit; otherwise record
    /// the simulation time `t` and stop.
    pub fn tick(&self, t: f64) -> ControlFlow<()> {
        if thread_cpu_seconds() - self.start > self.limit {
            if self.stopped_at.get().is_none() {
                self.stopped_at.set(Some(t));
            }
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }

    /// `Err` naming the limit if a run was stopped by it.
    pub fn check(&self) -> Result<(), String> {
        match self.stopped_at.get() {
            Some(t) => Err(format!(
                "stopped by the CPU limit of {} s at t = {t:.6} s (a hang or a far too slow run)",
                self.limit
            )),
            None => Ok(()),
        }
    }
}

/// The closure that runs a case.
pub type CaseFn = Box<dyn Fn(&Budget) -> Result<Outcome, String> + Send + Sync>;

/// One case of the suite.
pub struct Case {
    /// Short name (unique in a suite).
    pub name: String,
    /// What it stresses.
    pub stresses: String,
    /// Its check and bound, as stated in the report.
    pub check: String,
    /// CPU limit of the case (s).
    pub cpu_limit: f64,
    /// The run: its figures and the verdict of its check; `Err` is a failure.
    pub run: CaseFn,
}

impl Case {
    /// A case.
    pub fn new(
        name: impl Into<String>,
        stresses: impl Into<String>,
        check: impl Into<String>,
        cpu_limit: f64,
        run: impl Fn(&Budget) -> Result<Outcome, String> + Send + Sync + 'static,
    ) -> Self {
        Self {
            name: name.into(),
            stresses: stresses.into(),
            check: check.into(),
            cpu_limit,
            run: Box::new(run),
        }
    }
}

/// The result of one case.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseResult {
    /// Case name.
    pub name: String,
    /// What it stresses.
    pub stresses: String,
    /// Check and bound.
    pub check: String,
    /// Final verdict (after the runner's own checks).
    pub verdict: Verdict,
    /// Figures.
    pub figures: Vec<(String, f64)>,
    /// CPU time of the case (s).
    pub cpu_s: f64,
}

/// Run one case: under `catch_unwind`, its CPU measured, its budget
/// checked, and any non-finite figure turned into a failure.
pub fn run_case(case: &Case) -> CaseResult {
    let c0 = thread_cpu_seconds();
    let budget = Budget::new(case.cpu_limit);
    let r = catch_unwind(AssertUnwindSafe(|| (case.run)(&budget)));
    let cpu_s = thread_cpu_seconds() - c0;
    let (verdict, figures) = match r {
        Err(p) => {
            let msg = p
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| p.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "(no message)".into());
            (Verdict::Fail(format!("panic: {msg}")), Vec::new())
        }
        Ok(Err(e)) => (Verdict::Fail(e), Vec::new()),
        Ok(Ok(o)) => {
            let mut v = o.verdict;
            if let Err(e) = budget.check() {
                v = Verdict::Fail(e);
            } else if let Some((n, x)) = o.figures.iter().find(|(_, x)| !x.is_finite()) {
                if v.passed() {
                    v = Verdict::Fail(format!("figure `{n}` is {x}: a silent non-finite result"));
                }
            }
            (v, o.figures)
        }
    };
    CaseResult {
        name: case.name.clone(),
        stresses: case.stresses.clone(),
        check: case.check.clone(),
        verdict,
        figures,
        cpu_s,
    }
}

/// What a suite produced.
#[derive(Clone, Debug)]
pub struct Summary {
    /// One result per case, in order.
    pub results: Vec<CaseResult>,
    /// Path of stability.md.
    pub file: PathBuf,
    /// Wall time (s).
    pub wall_s: f64,
}

impl Summary {
    /// Cases that failed.
    pub fn failed(&self) -> Vec<&CaseResult> {
        self.results
            .iter()
            .filter(|r| !r.verdict.passed())
            .collect()
    }
}

/// Run `cases` and write `out/stability.md`; `title` names the suite.
pub fn run_cases(
    cases: &[Case],
    out: &Path,
    title: &str,
    progress: Progress,
) -> Result<Summary, Box<dyn std::error::Error>> {
    if out.exists() && !out.is_dir() {
        return Err(format!(
            "{}: exists and is not a directory (--out names the directory of stability.md)",
            out.display()
        )
        .into());
    }
    std::fs::create_dir_all(out)
        .map_err(|e| format!("{}: cannot create the directory: {e}", out.display()))?;
    let file = out.join("stability.md");
    crate::output::check_outputs(&[("the file of --out", &file)])?;
    let start = Instant::now();
    let reporter = Reporter::new(progress, cases.len());
    let mut results = Vec::new();
    for (i, case) in cases.iter().enumerate() {
        reporter.start(case.name.clone());
        let r = run_case(case);
        let line = format!(
            "[{}/{}] {}: {} ({:.2} s CPU)",
            i + 1,
            cases.len(),
            r.name,
            verdict_text(&r.verdict),
            r.cpu_s
        );
        reporter.done(&line, !r.verdict.passed());
        results.push(r);
    }
    reporter.finish();
    let wall_s = start.elapsed().as_secs_f64();
    let md = markdown(title, &results, wall_s);
    crate::output::write_atomic(&file, md.as_bytes())?;
    Ok(Summary {
        results,
        file,
        wall_s,
    })
}

fn verdict_text(v: &Verdict) -> String {
    match v {
        Verdict::Pass => "pass".into(),
        Verdict::Refused(m) => format!("pass (refused: {m})"),
        Verdict::Fail(m) => format!("FAIL: {m}"),
    }
}

/// A figure as the table prints it: integers as integers, others with 3
/// significant digits.
pub fn format_value(x: f64) -> String {
    if x.is_finite() && x.fract() == 0.0 && x.abs() < 1e9 {
        format!("{x:.0}")
    } else {
        format!("{x:.3e}")
    }
}

fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// The markdown of a suite's results.
pub fn markdown(title: &str, results: &[CaseResult], wall_s: f64) -> String {
    let failed = results.iter().filter(|r| !r.verdict.passed()).count();
    let cpu: f64 = results.iter().map(|r| r.cpu_s).sum();
    let mut s = String::new();
    let _ = writeln!(s, "# ffr stability: {title}\n");
    let _ = writeln!(
        s,
        "{} cases, {} passed, {failed} failed; {wall_s:.1} s wall, {cpu:.1} s CPU (thread CPU time of each case, one run).\n",
        results.len(),
        results.len() - failed
    );
    let _ = writeln!(
        s,
        "A case passes if its run is bounded and its check holds, or if the program refuses it with an error naming the cause; it fails on a panic, a non-finite figure, its CPU limit, an unexpected error or a check that does not hold. What each case checks and why: docs/stability.md.\n"
    );
    let _ = writeln!(
        s,
        "| case | stresses | check (bound) | outcome | figures | CPU s |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    for r in results {
        let figs = r
            .figures
            .iter()
            .map(|(n, x)| format!("{n} {}", format_value(*x)))
            .collect::<Vec<_>>()
            .join("; ");
        let outcome = match &r.verdict {
            Verdict::Pass => "pass".to_string(),
            Verdict::Refused(m) => format!("pass, refused: “{m}”"),
            Verdict::Fail(m) => format!("**FAIL**: {m}"),
        };
        let _ = writeln!(
            s,
            "| `{}` | {} | {} | {} | {} | {:.3} |",
            r.name,
            cell(&r.stresses),
            cell(&r.check),
            cell(&outcome),
            cell(&figs),
            r.cpu_s
        );
    }
    s
}

/// Run `ffr stability`: the quick or full suite, stability.md in
/// `args.out`; an `Err` if a case failed (the command exits non-zero).
pub fn run(args: &StabilityArgs) -> Result<Summary, Box<dyn std::error::Error>> {
    let cases = if args.quick {
        cases::quick()
    } else {
        cases::full()
    };
    let title = if args.quick {
        "quick suite (`ffr stability --quick`)"
    } else {
        "full suite (`ffr stability`)"
    };
    run_suite(&cases, &args.out, title, Progress::Auto)
}

/// [`run_cases`], a summary printed, and an `Err` naming the failed cases
/// if any failed (the command's exit status).
pub fn run_suite(
    cases: &[Case],
    out: &Path,
    title: &str,
    progress: Progress,
) -> Result<Summary, Box<dyn std::error::Error>> {
    let s = run_cases(cases, out, title, progress)?;
    let failed = s.failed();
    crate::outln!(
        "{} cases: {} passed, {} failed; {:.1} s wall",
        s.results.len(),
        s.results.len() - failed.len(),
        failed.len(),
        s.wall_s
    )?;
    crate::outln!("wrote {}", s.file.display())?;
    if !failed.is_empty() {
        let names: Vec<&str> = failed.iter().map(|r| r.name.as_str()).collect();
        return Err(format!(
            "{} case(s) failed: {} (see {})",
            failed.len(),
            names.join(", "),
            s.file.display()
        )
        .into());
    }
    Ok(s)
}
