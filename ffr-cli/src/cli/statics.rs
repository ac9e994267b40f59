//! `ffr static SCENE.toml`: the static equilibrium under the scene's loads
//! and its outputs there.

use crate::output;
use ffr::scene::statics::{SceneStatic, StaticOptions, MAX_STEPS};
use serde_json::{json, Map, Value};
use std::error::Error;
use std::path::{Path, PathBuf};

/// Arguments of `ffr static`.
#[derive(clap::Args, Debug)]
pub struct StaticArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// Load increments: K equal steps of the loads from 0 to their full
    /// value (1 to 10000); default: automatic (the whole load, the
    /// increment halved on failure).
    #[arg(long, value_name = "K", allow_hyphen_values = true, value_parser = parse_steps)]
    pub steps: Option<usize>,
    /// Write one CSV row: t = 0 and the outputs (the columns of `ffr run`'s CSV).
    #[arg(long, value_name = "PATH")]
    pub csv: Option<PathBuf>,
    /// Print one JSON object `{"outputs": {NAME: value, …}, "steps": K,
    /// "iterations": n}`.
    #[arg(long)]
    pub json: bool,
}

/// `--steps K`: a whole number from 1 to [`MAX_STEPS`].
fn parse_steps(s: &str) -> Result<usize, String> {
    let expected = format!("expected a whole number of load increments from 1 to {MAX_STEPS}");
    let t = s.trim();
    if t.is_empty() {
        return Err(format!("an empty value: {expected}"));
    }
    if t.starts_with('-') && t[1..].chars().all(|c| c.is_ascii_digit()) && t.len() > 1 {
        return Err(format!("{t} is negative: {expected}"));
    }
    if !t.chars().all(|c| c.is_ascii_digit()) {
        return Err(format!("`{t}` is not a whole number: {expected}"));
    }
    match t.parse::<usize>() {
        Ok(0) => Err(format!("0 load increments: {expected}")),
        Ok(k) if k <= MAX_STEPS => Ok(k),
        _ => Err(format!("{t} is too many: {expected}")),
    }
}

/// The JSON of a static solution: `{"outputs": {NAME: value, …}, "steps":
/// K, "iterations": n}`, and `"warnings": [TEXT, …]` only when a body
/// turned past what one floating frame describes (the contract's three
/// keys otherwise).
pub fn static_json(s: &SceneStatic) -> Value {
    let mut outputs = Map::new();
    for (n, v) in s.names.iter().zip(&s.values) {
        outputs.insert(n.clone(), json!(v));
    }
    let mut out = json!({
        "outputs": Value::Object(outputs),
        "steps": s.steps,
        "iterations": s.iterations,
    });
    if !s.warnings.is_empty() {
        out["warnings"] = json!(s.warnings);
    }
    out
}

/// Run `ffr static`: solve, write the CSV row, print the outputs (or the
/// JSON). No equilibrium is an error (non-zero exit), nothing written.
pub fn static_scene(args: &StaticArgs) -> Result<SceneStatic, Box<dyn Error>> {
    if let Some(p) = &args.csv {
        output::check_output(p, "--csv")?;
        output::check_not_inputs(&[("--csv", p)], &[("the scene file", &args.scene)])?;
    }
    let scene = ffr::scene::load(&args.scene)?;
    if let Some(p) = &args.csv {
        output::check_not_scene_files(&[("--csv", p)], &scene.input_files())?;
    }
    let options = StaticOptions { steps: args.steps };
    let s = ffr::scene::statics::solve(&scene, &options).map_err(|e| located(&args.scene, e))?;
    for w in &s.warnings {
        eprintln!("warning: {w}");
    }
    if let Some(p) = &args.csv {
        let names: Vec<&str> = s.names.iter().map(String::as_str).collect();
        let cols: Vec<&[f64]> = s.values.iter().map(std::slice::from_ref).collect();
        output::write_atomic(p, crate::plot::csv(&[0.0], &names, &cols).as_bytes())?;
    }
    if args.json {
        crate::outln!("{}", serde_json::to_string(&static_json(&s))?)?;
        return Ok(s);
    }
    let text = ffr::codegen::sanitize::snippet;
    crate::outln!(
        "scene {}{}: static equilibrium at t = 0",
        text(&scene.origin, super::MAX_ECHO_CHARS),
        scene
            .description
            .as_ref()
            .map_or(String::new(), |d| format!(
                " ({})",
                text(d, super::MAX_ECHO_CHARS)
            ))
    )?;
    for (name, (v, o)) in s.names.iter().zip(s.values.iter().zip(&scene.outputs)) {
        crate::outln!(
            "  {}: {v:.9e} {}",
            text(name, crate::plot::MAX_LABEL_CHARS),
            super::run::unit(&o.kind)
        )?;
    }
    crate::outln!(
        "{} load increment{}, {} Newton iterations",
        s.steps,
        if s.steps == 1 { "" } else { "s" },
        s.iterations
    )?;
    if let Some(p) = &args.csv {
        crate::outln!("wrote {}", p.display())?;
    }
    Ok(s)
}

/// An error of the library about the scene at `path`: a scene-file error
/// already says where; anything else gets the file's name in front.
fn located(path: &Path, e: ffr::Error) -> Box<dyn Error> {
    match e {
        ffr::Error::Scene(_) => e.into(),
        other => format!("{}: {other}", path.display()).into(),
    }
}

#[cfg(test)]
mod tests {
    use super::parse_steps;

    #[test]
    fn steps_are_whole_numbers_in_range() {
        assert_eq!(parse_steps("1"), Ok(1));
        assert_eq!(parse_steps("10000"), Ok(10000));
        for (bad, says) in [
            ("0", "0 load increments"),
            ("-3", "-3 is negative"),
            ("10001", "10001 is too many"),
            ("99999999999999999999999", "is too many"),
            ("2.5", "`2.5` is not a whole number"),
            ("1e3", "`1e3` is not a whole number"),
            ("abc", "`abc` is not a whole number"),
            ("", "an empty value"),
            ("-", "`-` is not a whole number"),
        ] {
            let e = parse_steps(bad).unwrap_err();
            assert!(
                e.contains(says) && e.contains("from 1 to 10000"),
                "{bad}: {e}"
            );
        }
    }
}
