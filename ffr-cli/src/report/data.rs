//! Work-precision points: ffr's, written to `points.csv`, and peers', read
//! from CSV files with the same columns.

use std::path::{Path, PathBuf};

/// The header of `points.csv` and of every peer file.
pub const HEADER: &str = "scene,method,elements,dt,cpu_s,error,error_kind";

/// One work-precision point.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// Scene name (`spin-up-4`, …).
    pub scene: String,
    /// Method family.
    pub method: String,
    /// Elements (or modes).
    pub elements: usize,
    /// Time step (s).
    pub dt: f64,
    /// CPU seconds of the simulation.
    pub cpu_s: f64,
    /// Error.
    pub error: f64,
    /// `reference`, `published`, `energy` or `momentum`.
    pub error_kind: String,
    /// Who made it: `ffr`, or the peer file's stem (`exudyn`).
    pub tool: String,
    /// Repetitions behind `cpu_s` (ffr's points; 0 if not known).
    pub reps: usize,
}

/// A run of the grid that gave no point.
#[derive(Clone, Debug, PartialEq)]
pub struct FailedRun {
    /// Scene name.
    pub scene: String,
    /// Method family.
    pub method: String,
    /// Elements.
    pub elements: usize,
    /// Time step (s).
    pub dt: f64,
    /// Why.
    pub reason: String,
    /// Simulated time reached (s), if known.
    pub t: Option<f64>,
}

/// `points` as CSV text with [`HEADER`]; numbers in their shortest
/// round-trip form.
pub fn csv(points: &[Point]) -> String {
    let mut s = String::from(HEADER);
    s.push('\n');
    for p in points {
        s.push_str(&format!(
            "{},{},{},{},{},{},{}\n",
            p.scene,
            p.method,
            p.elements,
            crate::output::number(p.dt),
            crate::output::number(p.cpu_s),
            crate::output::number(p.error),
            p.error_kind
        ));
    }
    s
}

/// What was found in the peers' directory.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Peers {
    /// The directory looked in.
    pub dir: PathBuf,
    /// The files read (sorted).
    pub files: Vec<PathBuf>,
    /// Their points (tool = the file's stem).
    pub points: Vec<Point>,
    /// Lines or files that were skipped, and why.
    pub problems: Vec<String>,
}

/// Parse one peer file's text; `tool` names its points. Lines that do not
/// parse (wrong number of fields, a number that is not finite, a CPU time
/// that is not positive) are skipped with a message.
pub fn parse_peer(text: &str, tool: &str, origin: &str) -> (Vec<Point>, Vec<String>) {
    let (mut points, mut problems) = (Vec::new(), Vec::new());
    let mut lines = text.lines();
    match lines.next().map(str::trim) {
        Some(h) if h == HEADER => {}
        h => {
            problems.push(format!(
                "{origin}: skipped, its header is {:?}, not `{HEADER}`",
                h.unwrap_or("")
            ));
            return (points, problems);
        }
    }
    for (i, line) in lines.enumerate() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let lno = i + 2;
        let f: Vec<&str> = line.split(',').collect();
        let parsed = (|| -> Result<Point, String> {
            if f.len() != 7 {
                return Err(format!("{} fields, not 7", f.len()));
            }
            let num = |s: &str, what: &str| -> Result<f64, String> {
                let v: f64 = s
                    .trim()
                    .parse()
                    .map_err(|_| format!("{what} `{s}` is not a number"))?;
                if v.is_finite() {
                    Ok(v)
                } else {
                    Err(format!("{what} `{s}` is not finite"))
                }
            };
            let p = Point {
                scene: f[0].trim().into(),
                method: f[1].trim().into(),
                elements: f[2]
                    .trim()
                    .parse()
                    .map_err(|_| format!("elements `{}` is not a count", f[2]))?,
                dt: num(f[3], "dt")?,
                cpu_s: num(f[4], "cpu_s")?,
                error: num(f[5], "error")?,
                error_kind: f[6].trim().into(),
                tool: tool.into(),
                reps: 0,
            };
            if !(p.cpu_s > 0.0) || !(p.error >= 0.0) || !(p.dt > 0.0) {
                return Err("cpu_s and dt must be positive, error not negative".into());
            }
            Ok(p)
        })();
        match parsed {
            Ok(p) => points.push(p),
            Err(e) => problems.push(format!("{origin}:{lno}: skipped ({e})")),
        }
    }
    (points, problems)
}

/// Largest peer file read, in bytes (16 MiB; a peer's file has one line per
/// run, a few hundred lines).
pub const MAX_PEER_BYTES: u64 = 16 << 20;

/// Read every `*.csv` in `dir` (a missing directory is no error: the
/// report then says that no peer file was found).
pub fn read_peers(dir: &Path) -> Peers {
    let mut out = Peers {
        dir: dir.to_path_buf(),
        ..Peers::default()
    };
    let Ok(entries) = std::fs::read_dir(dir) else {
        return out;
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|x| x == "csv"))
        .collect();
    files.sort();
    for f in files {
        let tool = f
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let text =
            ffr_codegen::limits::read_input(&f, MAX_PEER_BYTES, "peer file", "MAX_PEER_BYTES")
                .and_then(|b| String::from_utf8(b).map_err(|_| "is not UTF-8 text".to_string()));
        match text {
            Ok(text) => {
                let (p, pr) = parse_peer(&text, &tool, &f.display().to_string());
                out.points.extend(p);
                out.problems.extend(pr);
                out.files.push(f);
            }
            Err(e) => out
                .problems
                .push(format!("{}: cannot be read: {e}", f.display())),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peer_lines_that_do_not_parse_are_skipped_with_a_reason() {
        let text = format!(
            "{HEADER}\nspin-up-4,x,2,0.01,0.5,1e-3,reference\nspin-up-4,x,2,0.01,nan,1e-3,reference\nspin-up-4,x,2,0.01\n\n"
        );
        let (p, pr) = parse_peer(&text, "peer", "f.csv");
        assert_eq!(p.len(), 1);
        assert_eq!(p[0].cpu_s, 0.5);
        assert_eq!(p[0].tool, "peer");
        assert_eq!(pr.len(), 2, "{pr:?}");
        assert!(pr[0].starts_with("f.csv:3:"), "{pr:?}");
        let (p, pr) = parse_peer("a,b\n1,2\n", "peer", "g.csv");
        assert!(p.is_empty() && pr[0].contains("header"), "{pr:?}");
    }

    #[test]
    fn csv_round_trips_through_the_peer_parser() {
        let p = Point {
            scene: "pendulum".into(),
            method: "ffr-ga1-consistent-linear".into(),
            elements: 4,
            dt: 2.5e-4,
            cpu_s: 0.012345678901234,
            error: 3.3e-7,
            error_kind: "energy".into(),
            tool: "ffr".into(),
            reps: 3,
        };
        let (back, pr) = parse_peer(&csv(std::slice::from_ref(&p)), "ffr", "x");
        assert!(pr.is_empty());
        assert_eq!(back, vec![Point { reps: 0, ..p }]);
    }
}
