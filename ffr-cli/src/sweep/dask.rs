//! The distributed engine: Dask. This process expands the cases; a Python
//! driver ([`DRIVER`], run as `PYTHON -c`) connects a
//! `dask.distributed.Client` to the scheduler and submits one task per case,
//! each running `FFR sweep STUDY --case I --json` on a worker (the same
//! binary and study by absolute path: a shared filesystem) and returning
//! its output; the rows come back here and the table is written as the
//! local engine writes it, so the results are the same bits.

use super::cases;
use super::results;
use super::run::CaseResult;
use super::study::Study;
use crate::progress::Reporter;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// The driver script.
pub const DRIVER: &str = include_str!("dask_driver.py");

/// The start of the driver's line for a finished case (then its JSON).
const CASE_LINE: &str = "FFR-CASE ";

/// The longest line of the driver's output read (a case line carries the
/// case's JSON and the last 4000 characters of its standard error).
const MAX_LINE: u64 = 16 << 20;

/// The driver's standard error kept for messages.
const MAX_STDERR: u64 = 1 << 20;

/// How to reach the cluster.
#[derive(Clone, Debug)]
pub struct DaskOptions {
    /// The scheduler's address (`tcp://HOST:PORT`).
    pub scheduler: String,
    /// The Python interpreter with `dask[distributed]`.
    pub python: String,
    /// The ffr binary the workers run (an absolute path they can reach).
    pub worker_ffr: PathBuf,
    /// Seconds to wait for the scheduler.
    pub connect_timeout: f64,
}

fn absolute(p: &Path) -> Result<PathBuf, String> {
    std::fs::canonicalize(p).map_err(|e| format!("{}: {e}", p.display()))
}

/// Every case of `study` on the Dask cluster at `opts.scheduler`.
pub fn run(
    study: &Study,
    opts: &DaskOptions,
    progress: &Reporter,
) -> Result<Vec<CaseResult>, String> {
    let n = cases::count(&study.axes);
    let study_abs = absolute(&study.path)?;
    let ffr = if opts.worker_ffr.is_absolute() {
        opts.worker_ffr.clone()
    } else {
        absolute(&opts.worker_ffr)?
    };
    let mut child = Command::new(&opts.python)
        .arg("-c")
        .arg(DRIVER)
        .arg(&opts.scheduler)
        .arg(&ffr)
        .arg(&study_abs)
        .arg(n.to_string())
        .arg(opts.connect_timeout.to_string())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| {
            format!(
                "cannot start Python `{}` for the Dask engine: {e} (give the interpreter with --python or FFR_PYTHON; it needs `pip install \"dask[distributed]\"`)",
                opts.python
            )
        })?;
    // Standard error is read on its own thread so that neither pipe fills.
    let mut stderr = child.stderr.take().expect("piped");
    let err_thread = std::thread::spawn(move || {
        use std::io::Read;
        // The first MAX_STDERR bytes are kept for the message; the rest is
        // read and dropped, so the pipe never fills.
        let mut kept = Vec::new();
        let _ = (&mut stderr).take(MAX_STDERR).read_to_end(&mut kept);
        let _ = std::io::copy(&mut stderr, &mut std::io::sink());
        String::from_utf8_lossy(&kept).into_owned()
    });
    let stdout = child.stdout.take().expect("piped");
    let mut rows: Vec<Option<CaseResult>> = vec![None; n];
    let mut bad: Option<String> = None;
    let mut reader = std::io::BufReader::new(stdout);
    let mut buf = Vec::new();
    loop {
        use std::io::{BufRead, Read};
        buf.clear();
        // One line, at most MAX_LINE bytes of it.
        match (&mut reader).take(MAX_LINE).read_until(b'\n', &mut buf) {
            Ok(0) => break,
            Ok(_) if buf.last() != Some(&b'\n') && buf.len() as u64 == MAX_LINE => {
                bad.get_or_insert(format!(
                    "a line of the Dask driver's output is longer than {MAX_LINE} bytes"
                ));
                let _ = std::io::copy(&mut reader, &mut std::io::sink());
                break;
            }
            Ok(_) => {}
            Err(e) => {
                bad.get_or_insert(format!("reading the Dask driver's output: {e}"));
                break;
            }
        }
        let line = String::from_utf8_lossy(&buf);
        let line = line.trim_end_matches(['\n', '\r']);
        // Only the driver's own lines; anything else a library printed is not ours.
        let Some(json) = line.strip_prefix(CASE_LINE) else {
            continue;
        };
        match task_result(study, n, json) {
            Ok(r) => {
                let i = r.case;
                progress.done(&super::run::summary_line(study, i, n, &r), !r.ok());
                rows[i] = Some(r);
            }
            Err(e) => {
                bad.get_or_insert(e);
            }
        }
    }
    let status = child
        .wait()
        .map_err(|e| format!("waiting for the Dask driver: {e}"))?;
    let err = err_thread.join().unwrap_or_default();
    let err = ffr::codegen::sanitize::snippet(err.trim(), 2000);
    match status.code() {
        Some(0) => {}
        Some(3) => {
            return Err(format!(
                "the Dask engine needs dask.distributed in Python `{}`: {err} (pip install \"dask[distributed]\", or give another interpreter with --python or FFR_PYTHON)",
                opts.python
            ))
        }
        Some(4) => {
            return Err(format!(
                "cannot reach the Dask scheduler at {} within {} s: {err}",
                opts.scheduler, opts.connect_timeout
            ))
        }
        Some(5) => return Err(format!("the Dask cluster failed during the sweep: {err}")),
        other => {
            return Err(format!(
                "the Dask driver (`{} -c …`) failed (exit {}): {err}",
                opts.python,
                other.map_or("by a signal".to_string(), |c| c.to_string())
            ))
        }
    }
    if let Some(e) = bad {
        return Err(e);
    }
    rows.into_iter()
        .enumerate()
        .map(|(i, r)| r.ok_or_else(|| format!("the Dask driver returned no result for case {i}")))
        .collect()
}

/// One line of the driver: `{"case", "returncode", "stdout", "stderr"}`.
fn task_result(study: &Study, n: usize, line: &str) -> Result<CaseResult, String> {
    let v: serde_json::Value = serde_json::from_str(line)
        .map_err(|e| format!("the Dask driver wrote a line that is not JSON ({e})"))?;
    let case = v
        .get("case")
        .and_then(|c| c.as_u64())
        .filter(|&c| (c as usize) < n)
        .ok_or("the Dask driver wrote a line without a valid case")? as usize;
    let rc = v.get("returncode").and_then(|c| c.as_i64()).unwrap_or(-1);
    let out = v.get("stdout").and_then(|c| c.as_str()).unwrap_or_default();
    let err = v.get("stderr").and_then(|c| c.as_str()).unwrap_or_default();
    if rc != 0 {
        // The worker could not run the case (a missing binary, a study it
        // cannot read): a failed row with its reason.
        return Ok(CaseResult {
            case,
            figures: Vec::new(),
            cpu_s: 0.0,
            failure: Some(format!(
                "on the Dask worker, ffr exited with {rc}: {}",
                ffr::codegen::sanitize::snippet(err.trim(), 500)
            )),
        });
    }
    results::from_json(study, case, out)
        .map_err(|e| format!("case {case} from the Dask worker: {e}"))
}
