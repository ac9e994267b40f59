//! The results table `DIR/results.csv` (one row per case, in case order)
//! and the JSON of one case that the distributed engine's workers print.

use super::cases;
use super::run::CaseResult;
use super::study::Study;
use std::path::Path;

/// The header of `results.csv`: `case`, the axes' keys as written (control,
/// bidi and other invisible characters escaped, as in messages), the
/// figures' names, `cpu_s`, `status`, `message`.
pub fn header(study: &Study) -> Vec<String> {
    let mut h = vec!["case".to_string()];
    h.extend(
        study
            .axes
            .iter()
            .map(|a| ffr::codegen::sanitize::snippet(&a.key, usize::MAX)),
    );
    h.extend(study.figures.iter().map(|f| f.name.clone()));
    h.extend(["cpu_s", "status", "message"].map(String::from));
    h
}

/// `results.csv`: a row per case (numbers in the shortest form that reads
/// back to the same `f64`; a failed case has empty figures, `failed` and
/// its message).
pub fn csv(study: &Study, rows: &[CaseResult]) -> Result<String, String> {
    let mut w = csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    let e = |e: csv::Error| format!("cannot write the results table: {e}");
    w.write_record(header(study)).map_err(e)?;
    for r in rows {
        let mut rec = vec![r.case.to_string()];
        rec.extend(
            cases::values(&study.axes, r.case)
                .into_iter()
                .map(cases::cell),
        );
        if r.ok() {
            rec.extend(r.figures.iter().map(|x| crate::output::number(*x)));
        } else {
            rec.extend(study.figures.iter().map(|_| String::new()));
        }
        rec.push(crate::output::number(r.cpu_s));
        rec.push(if r.ok() { "ok" } else { "failed" }.to_string());
        rec.push(r.failure.clone().unwrap_or_default());
        w.write_record(&rec).map_err(e)?;
    }
    let bytes = w.into_inner().map_err(|e| e.to_string())?;
    String::from_utf8(bytes).map_err(|e| e.to_string())
}

/// Bytes of an existing file read to tell whether it is ours.
const HEAD_BYTES: u64 = 64 << 10;

/// A file in the output directory that `ffr sweep` may replace: one that
/// does not exist, or one it wrote (`results.csv` whose header starts with
/// `case,` and ends with `,cpu_s,status,message`; an SVG with the
/// [`super::plot::MARK`] comment). Anything else is refused.
pub fn check_ours(path: &Path) -> Result<(), String> {
    let Ok(meta) = std::fs::symlink_metadata(path) else {
        return Ok(());
    };
    let refuse = || {
        format!(
            "{}: exists and was not written by ffr sweep: not replaced (remove it or give another --out)",
            path.display()
        )
    };
    if !meta.is_file() {
        return Err(refuse());
    }
    // The first line of a table of MAX_AXES keys and MAX_FIGURES names fits.
    let mut head = Vec::new();
    {
        use std::io::Read;
        let f = std::fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
        f.take(HEAD_BYTES)
            .read_to_end(&mut head)
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    let head = String::from_utf8_lossy(&head);
    let ours = if path.extension().is_some_and(|e| e == "csv") {
        head.lines()
            .next()
            .is_some_and(|l| l.starts_with("case,") && l.ends_with(",cpu_s,status,message"))
    } else {
        head.starts_with(super::plot::MARK)
    };
    if ours {
        Ok(())
    } else {
        Err(refuse())
    }
}

/// One case as the hidden `ffr sweep STUDY --case I --json` prints it:
/// numbers as strings in the shortest form that reads back to the same
/// `f64` (JSON readers may round), the case's values as the table writes
/// them (the engine checks them against its own expansion).
pub fn case_json(study: &Study, r: &CaseResult) -> serde_json::Value {
    serde_json::json!({
        "case": r.case,
        "values": cases::values(&study.axes, r.case).into_iter().map(cases::cell).collect::<Vec<_>>(),
        "figures": r.figures.iter().map(|x| crate::output::number(*x)).collect::<Vec<_>>(),
        "cpu_s": crate::output::number(r.cpu_s),
        "status": if r.ok() { "ok" } else { "failed" },
        "message": r.failure.clone().unwrap_or_default(),
    })
}

/// A case back from its JSON, checked against `study`: the same case
/// values, one finite figure per figure for an ok case.
pub fn from_json(study: &Study, case: usize, text: &str) -> Result<CaseResult, String> {
    let v: serde_json::Value =
        serde_json::from_str(text.trim()).map_err(|e| format!("not a case's JSON ({e})"))?;
    let field = |k: &str| {
        v.get(k)
            .ok_or_else(|| format!("no `{k}` in the case's JSON"))
    };
    let num = |s: &serde_json::Value| -> Result<f64, String> {
        s.as_str()
            .and_then(|s| s.parse::<f64>().ok())
            .ok_or_else(|| format!("`{s}` is not a number written as a string"))
    };
    if field("case")?.as_u64() != Some(case as u64) {
        return Err(format!(
            "the JSON is of case {}, not {case}",
            field("case")?
        ));
    }
    let values: Vec<String> = cases::values(&study.axes, case)
        .into_iter()
        .map(cases::cell)
        .collect();
    let got: Vec<&str> = field("values")?
        .as_array()
        .ok_or("`values` is not an array")?
        .iter()
        .map(|x| x.as_str().unwrap_or("?"))
        .collect();
    if got != values {
        return Err(format!(
            "the worker's case {case} has the values [{}], this study's [{}]: did the study change?",
            got.join(", "),
            values.join(", ")
        ));
    }
    let cpu_s = num(field("cpu_s")?)?;
    let message = field("message")?.as_str().unwrap_or_default().to_string();
    match field("status")?.as_str() {
        Some("ok") => {
            let figures = field("figures")?
                .as_array()
                .ok_or("`figures` is not an array")?
                .iter()
                .map(num)
                .collect::<Result<Vec<f64>, String>>()?;
            if figures.len() != study.figures.len() || figures.iter().any(|x| !x.is_finite()) {
                return Err(format!(
                    "{} figures, not {} finite ones",
                    figures.len(),
                    study.figures.len()
                ));
            }
            Ok(CaseResult {
                case,
                figures,
                cpu_s,
                failure: None,
            })
        }
        Some("failed") => Ok(CaseResult {
            case,
            figures: Vec::new(),
            cpu_s,
            failure: Some(message),
        }),
        other => Err(format!("status {other:?} is neither ok nor failed")),
    }
}
