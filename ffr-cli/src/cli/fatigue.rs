//! `ffr fatigue RUN.csv --column NAME`: damage-equivalent loads of a column
//! of a `ffr run --csv` file, computed by the Python package's
//! `ffr.fatigue.main` (rainflow counting by the PyPI package `rainflow`),
//! so that the command line and `ffr.fatigue.equivalent_load` are the same
//! code; see docs/fatigue.md.

use std::ffi::OsString;
use std::io::Read;
use std::path::PathBuf;
use std::process::{Command, Stdio};

/// Arguments of `ffr fatigue` (checked by `ffr.fatigue`, which reads the file).
#[derive(clap::Args, Debug)]
pub struct FatigueArgs {
    /// The CSV (`ffr run --csv`: a header `t,NAME,…`, then rows).
    pub csv: PathBuf,
    /// The column whose damage-equivalent loads are computed.
    #[arg(long)]
    pub column: String,
    /// S-N (Wöhler) slopes, comma-separated.
    #[arg(long, default_value = "3,4,10", allow_hyphen_values = true)]
    pub m: String,
    /// The equivalent cycle's period in s: N_eq = T / t_eq, T the file's
    /// time span (1 s: the usual 1 Hz equivalent frequency).
    #[arg(long, default_value = "1", allow_hyphen_values = true)]
    pub t_eq: String,
    /// The number of equivalent cycles N_eq, instead of T / t_eq.
    #[arg(long, allow_hyphen_values = true)]
    pub n_eq: Option<String>,
    /// The ultimate load: with it, the Goodman mean-load correction of
    /// MLife, each range times (L_ult − |L_MF|) / (L_ult − |cycle mean|).
    #[arg(long, allow_hyphen_values = true)]
    pub ultimate: Option<String>,
    /// The Goodman correction's reference mean L_MF (default: the column's
    /// mean; with --ultimate).
    #[arg(long, allow_hyphen_values = true)]
    pub fixed_mean: Option<String>,
    /// Print one JSON object (`{"del": [{"m": …, "del": …}, …], …}`).
    #[arg(long)]
    pub json: bool,
    /// The Python interpreter with the `ffr` package and `rainflow`
    /// (default: the environment variable FFR_PYTHON, else `python3`).
    #[arg(long)]
    pub python: Option<String>,
}

/// The most bytes of the Python program's standard error kept for a message.
const MAX_STDERR: u64 = 1 << 16;

/// What the interpreter runs: `ffr.fatigue.main` with the arguments, the
/// current directory taken off the module path first (so that a directory
/// `ffr/` where the command runs does not stand in for the installed
/// package); exit 4 when the package cannot be imported.
const BOOTSTRAP: &str = r#"import sys
if sys.path and sys.path[0] == "":
    del sys.path[0]
try:
    from ffr import fatigue
except ImportError as e:
    sys.stderr.write("%s: %s\n" % (type(e).__name__, e))
    sys.exit(4)
sys.exit(fatigue.main(sys.argv[1:]))
"#;

const INSTALL: &str =
    "pip install ./python \"rainflow>=3\" from the ffr repository (or pip install \"ffr[fatigue]\")";

/// Run `ffr fatigue`: the DELs on standard output, as `ffr.fatigue` prints
/// them; its one-line error otherwise.
pub fn fatigue(args: &FatigueArgs) -> Result<(), Box<dyn std::error::Error>> {
    let python = args
        .python
        .clone()
        .or_else(|| std::env::var("FFR_PYTHON").ok().filter(|s| !s.is_empty()))
        .unwrap_or_else(|| "python3".into());
    let shown = ffr::codegen::sanitize::snippet(&python, 200);
    let mut argv: Vec<OsString> = vec![
        args.csv.clone().into_os_string(),
        "--column".into(),
        args.column.clone().into(),
        "--m".into(),
        args.m.clone().into(),
        "--t-eq".into(),
        args.t_eq.clone().into(),
    ];
    if let Some(n) = &args.n_eq {
        argv.push("--n-eq".into());
        argv.push(n.clone().into());
    }
    if let Some(u) = &args.ultimate {
        argv.push("--ultimate".into());
        argv.push(u.clone().into());
    }
    if let Some(f) = &args.fixed_mean {
        argv.push("--fixed-mean".into());
        argv.push(f.clone().into());
    }
    if args.json {
        argv.push("--json".into());
    }
    let mut child = Command::new(&python)
        .arg("-c")
        .arg(BOOTSTRAP)
        .args(&argv)
        .stdin(Stdio::null())
        .stdout(Stdio::inherit())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| {
            format!(
                "cannot start Python `{shown}` for `ffr fatigue`: {e} (install Python 3 and {INSTALL}, or give the interpreter with --python or FFR_PYTHON)"
            )
        })?;
    let mut stderr = child.stderr.take().expect("piped");
    let mut kept = Vec::new();
    let _ = (&mut stderr).take(MAX_STDERR).read_to_end(&mut kept);
    let _ = std::io::copy(&mut stderr, &mut std::io::sink());
    let status = child
        .wait()
        .map_err(|e| format!("waiting for Python `{shown}`: {e}"))?;
    let err = String::from_utf8_lossy(&kept);
    // The last line that says something (a traceback's last line is the
    // error; ffr.fatigue writes one line).
    let last = err
        .lines()
        .map(str::trim)
        .rfind(|l| !l.is_empty())
        .unwrap_or("");
    let last = ffr::codegen::sanitize::snippet(last.strip_prefix("error: ").unwrap_or(last), 2000);
    match status.code() {
        Some(0) => {
            if !err.trim().is_empty() {
                eprint!("{err}");
            }
            Ok(())
        }
        Some(2) if !last.is_empty() => Err(last.into()),
        Some(3) => Err(format!("{last} (in Python `{shown}`)").into()),
        Some(4) => Err(format!(
            "`ffr fatigue` runs the Python package ffr, which Python `{shown}` cannot import ({last}): {INSTALL}, or give another interpreter with --python or FFR_PYTHON"
        )
        .into()),
        other => Err(format!(
            "Python `{shown}` running ffr.fatigue failed ({}){}",
            other.map_or("killed by a signal".to_string(), |c| format!("exit {c}")),
            if last.is_empty() {
                String::new()
            } else {
                format!(": {last}")
            }
        )
        .into()),
    }
}
