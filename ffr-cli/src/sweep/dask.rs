//! The distributed engine: Dask. This process expands the cases; a Python
//! driver ([`DRIVER`], run as `PYTHON -c`) connects a
//! `dask.distributed.Client` to the scheduler and submits one task per case,
//! each running `FFR sweep STUDY --case I --json` on a worker (the same
//! binary by absolute path, the study by the path given, in this process's
//! working directory: a shared filesystem) and returning its output; the
//! rows come back here and the table is written as the local engine writes
//! it, so the results are the same bits, messages included. A watchdog in
//! the driver (`--stall-timeout`) and one here on the driver
//! ([`DRIVER_SILENCE_S`]) stop a sweep that makes no progress; the finished
//! rows are written and the others are failed rows saying why.

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

/// The start of the driver's line when it stopped the sweep (then a JSON
/// object with the reason).
const STOP_LINE: &str = "FFR-STOP ";

/// Seconds the driver may stay silent (it writes a line about once a
/// second) before this process stops it: after the connection, longer than
/// the Dask client's own network timeouts; before it, this plus
/// `--connect-timeout` (Python's imports included).
pub const DRIVER_SILENCE_S: f64 = 120.0;

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
    /// Seconds without progress (no case finished, none running on a
    /// worker) after which the sweep stops.
    pub stall_timeout: f64,
}

/// What the cluster gave: a row per case (those that did not finish are
/// failed rows saying why), and why the sweep stopped early, if it did.
#[derive(Clone, Debug)]
pub struct DaskRun {
    /// Every case, in case order.
    pub rows: Vec<CaseResult>,
    /// Why the sweep stopped before every case finished.
    pub stopped: Option<String>,
}

fn absolute(p: &Path) -> Result<PathBuf, String> {
    std::fs::canonicalize(p).map_err(|e| format!("{}: {e}", p.display()))
}

fn text(s: &str) -> String {
    ffr::codegen::sanitize::snippet(s, 200)
}

/// What the reader thread passes on.
enum Line {
    /// A line of the driver's standard output.
    Text(String),
    /// A line longer than [`MAX_LINE`], or a read error; the reader stops.
    Bad(String),
}

/// Every case of `study` on the Dask cluster at `opts.scheduler`. Errors
/// before any case ran (no Python, no dask.distributed, no scheduler) are
/// `Err`; a cluster that fails or stalls during the sweep gives the
/// finished rows and the others failed, with the reason in
/// [`DaskRun::stopped`].
pub fn run(study: &Study, opts: &DaskOptions, progress: &Reporter) -> Result<DaskRun, String> {
    let n = cases::count(&study.axes);
    // The workers run in this directory, with the study's path as given,
    // so that their messages name files as the local engine's do.
    let cwd = std::env::current_dir()
        .map_err(|e| format!("cannot tell the working directory for the Dask workers: {e}"))?;
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
        .arg(&study.path)
        .arg(n.to_string())
        .arg(opts.connect_timeout.to_string())
        .arg(opts.stall_timeout.to_string())
        .arg(&cwd)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| {
            format!(
                "cannot start Python `{}` for the Dask engine: {e} (give the interpreter with --python or FFR_PYTHON; it needs `pip install \"dask[distributed]\"`)",
                text(&opts.python)
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
    // Standard output too, line by line to this thread, which waits on
    // the lines with a deadline (the watchdog on the driver itself).
    let stdout = child.stdout.take().expect("piped");
    let (tx, rx) = std::sync::mpsc::channel::<Line>();
    let out_thread = std::thread::spawn(move || {
        use std::io::{BufRead, Read};
        let mut reader = std::io::BufReader::new(stdout);
        let mut buf = Vec::new();
        loop {
            buf.clear();
            // One line, at most MAX_LINE bytes of it.
            let line = match (&mut reader).take(MAX_LINE).read_until(b'\n', &mut buf) {
                Ok(0) => return,
                Ok(_) if buf.last() != Some(&b'\n') && buf.len() as u64 == MAX_LINE => Line::Bad(
                    format!("a line of the Dask driver's output is longer than {MAX_LINE} bytes"),
                ),
                Ok(_) => Line::Text(
                    String::from_utf8_lossy(&buf)
                        .trim_end_matches(['\n', '\r'])
                        .to_string(),
                ),
                Err(e) => Line::Bad(format!("reading the Dask driver's output: {e}")),
            };
            let last = matches!(line, Line::Bad(_));
            if tx.send(line).is_err() || last {
                let _ = std::io::copy(&mut reader, &mut std::io::sink());
                return;
            }
        }
    });
    let mut rows: Vec<Option<CaseResult>> = vec![None; n];
    let mut bad: Option<String> = None;
    let mut stopped: Option<String> = None;
    let mut heard = false;
    loop {
        let silence = DRIVER_SILENCE_S + if heard { 0.0 } else { opts.connect_timeout };
        let line = match rx.recv_timeout(std::time::Duration::from_secs_f64(silence)) {
            Ok(Line::Text(l)) => l,
            Ok(Line::Bad(e)) => {
                bad.get_or_insert(e);
                break;
            }
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => break,
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
                stopped = Some(format!(
                    "the Dask driver wrote nothing for {silence} s (DRIVER_SILENCE_S): stopped"
                ));
                // Ours to stop: the child this function started.
                let _ = child.kill();
                break;
            }
        };
        heard = true;
        if let Some(json) = line.strip_prefix(STOP_LINE) {
            let reason = serde_json::from_str::<serde_json::Value>(json)
                .ok()
                .and_then(|v| v.get("reason").and_then(|r| r.as_str()).map(String::from))
                .unwrap_or_else(|| "the Dask driver stopped".into());
            stopped = Some(ffr::codegen::sanitize::snippet(&reason, 2000));
            continue;
        }
        // Only the driver's case lines count; anything else a library
        // printed is not ours (the FFR-ALIVE lines only show it is alive).
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
    let _ = out_thread.join();
    let err = ffr::codegen::sanitize::snippet(err.trim(), 2000);
    match status.code() {
        _ if stopped.is_some() => {}
        Some(0) => {}
        Some(3) => {
            return Err(format!(
                "the Dask engine needs dask.distributed in Python `{}`: {err} (pip install \"dask[distributed]\", or give another interpreter with --python or FFR_PYTHON)",
                text(&opts.python)
            ))
        }
        Some(4) => {
            return Err(format!(
                "cannot reach the Dask scheduler at {} within {} s: {err}",
                text(&opts.scheduler),
                opts.connect_timeout
            ))
        }
        Some(5) => stopped = Some(format!("the Dask cluster failed during the sweep: {err}")),
        other if heard => {
            stopped = Some(format!(
                "the Dask driver (`{} -c …`) failed (exit {}): {err}",
                text(&opts.python),
                other.map_or("by a signal".to_string(), |c| c.to_string())
            ))
        }
        other => {
            return Err(format!(
                "the Dask driver (`{} -c …`) failed (exit {}): {err}",
                text(&opts.python),
                other.map_or("by a signal".to_string(), |c| c.to_string())
            ))
        }
    }
    if let Some(e) = bad {
        return Err(e);
    }
    if stopped.is_none() && rows.iter().any(Option::is_none) {
        stopped = Some("the Dask driver ended before every case finished".into());
    }
    let rows = rows
        .into_iter()
        .enumerate()
        .map(|(i, r)| {
            r.unwrap_or_else(|| CaseResult {
                case: i,
                figures: Vec::new(),
                cpu_s: 0.0,
                failure: Some(format!(
                    "not run: {}",
                    stopped
                        .as_deref()
                        .unwrap_or("the Dask driver returned nothing for it")
                )),
            })
        })
        .collect();
    Ok(DaskRun { rows, stopped })
}

/// One line of the driver: `{"case", "returncode", "stdout", "stderr"}`,
/// or `{"case", "error"}` for a task the cluster could not run.
fn task_result(study: &Study, n: usize, line: &str) -> Result<CaseResult, String> {
    let v: serde_json::Value = serde_json::from_str(line)
        .map_err(|e| format!("the Dask driver wrote a line that is not JSON ({e})"))?;
    let case = v
        .get("case")
        .and_then(|c| c.as_u64())
        .filter(|&c| (c as usize) < n)
        .ok_or("the Dask driver wrote a line without a valid case")? as usize;
    if let Some(e) = v.get("error") {
        return Ok(CaseResult {
            case,
            figures: Vec::new(),
            cpu_s: 0.0,
            failure: Some(format!(
                "the Dask cluster could not run the case: {}",
                ffr::codegen::sanitize::snippet(e.as_str().unwrap_or("?").trim(), 500)
            )),
        });
    }
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
