//! `ffr run SCENE.toml`: a scene file's run, its CSV, plot and summary.

use super::spin_up::outputs;
use crate::output;
use std::path::{Path, PathBuf};

/// Run a scene file, write its outputs, print a summary; an integrator
/// failure is reported and is an error.
pub fn run_scene(
    path: &Path,
    csv: &Option<PathBuf>,
    svg: &Option<PathBuf>,
    general: bool,
    vtk: Option<ffr::scene::vtk::VtkOptions>,
) -> Result<ffr::scene::SceneRun, Box<dyn std::error::Error>> {
    let scene = if general {
        ffr::scene::load_with(path, &ffr::scene::GeneralKernels)?
    } else {
        ffr::scene::load(path)?
    };
    let tag = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let (csv, svg) = outputs(csv, svg, &tag)?;
    let c0 = crate::clock::thread_cpu_seconds();
    let mut options = ffr::scene::RunOptions::default();
    options.vtk = vtk.clone();
    let r = ffr::scene::run_with(&scene, &options)?;
    let cpu = crate::clock::thread_cpu_seconds() - c0;
    let names: Vec<&str> = r.names.iter().map(String::as_str).collect();
    let cols: Vec<&[f64]> = r.columns.iter().map(Vec::as_slice).collect();
    if r.failed.is_none() {
        check_finite_columns(&r.t, &names, &cols)?;
    }
    let series: Vec<(&str, &[f64])> = names.iter().copied().zip(cols.iter().copied()).collect();
    let plot = crate::plot::time_svg(
        scene.description.as_deref().unwrap_or(&scene.origin),
        "outputs",
        &r.t,
        &series,
    )?;
    output::write_all_atomic(&[
        (&csv, crate::plot::csv(&r.t, &names, &cols).as_bytes()),
        (&svg, plot.as_bytes()),
    ])?;
    // User text (the file's path, its description, output names) is shown
    // escaped and shortened: it cannot move the cursor or change colours.
    let text = ffr::codegen::sanitize::snippet;
    crate::outln!(
        "scene {}{}",
        text(&scene.origin, MAX_ECHO_CHARS),
        scene
            .description
            .as_ref()
            .map_or(String::new(), |d| format!(": {}", text(d, MAX_ECHO_CHARS)))
    )?;
    for (b, k) in &scene.kernels {
        crate::outln!("  body `{}`: {k}", text(b, MAX_ECHO_CHARS))?;
    }
    for n in &scene.notes {
        crate::outln!("  {}", text(n, usize::MAX))?;
    }
    for (name, col) in names.iter().zip(&cols) {
        if let (Some(first), Some(last)) = (col.first(), col.last()) {
            let (lo, hi) = col
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                });
            crate::outln!(
                "  {}: {first:.6e} → {last:.6e} (min {lo:.6e}, max {hi:.6e})",
                text(name, crate::plot::MAX_LABEL_CHARS)
            )?;
        }
    }
    crate::outln!(
        "steps: {} of dt = {} s, {} Newton iterations, {} iteration matrices{}, wall time {:.3} s, CPU time {:.3} s",
        r.steps,
        scene.dt,
        r.newton_iterations,
        r.jacobians,
        retries(r.restarts, r.splits),
        r.wall,
        cpu
    )?;
    crate::outln!("wrote {} and {}", csv.display(), svg.display())?;
    if let Some(v) = &vtk {
        let files = r.t.len().div_ceil(v.every);
        crate::outln!(
            "wrote {} and {files} VTK step files (every {} of {} samples)",
            v.dir
                .join(format!(
                    "{}.pvd",
                    ffr::scene::vtk::scene_stem(&scene.origin)
                ))
                .display(),
            v.every,
            r.t.len()
        )?;
    }
    if let Some(f) = &r.failed {
        return Err(format!(
            "the run stopped at t = {:.6} s: {f}",
            r.t.last().copied().unwrap_or(0.0)
        )
        .into());
    }
    Ok(r)
}

/// Longest user text (a scene's description or path, a body name) echoed on
/// the terminal, in characters; longer text is cut with `…`.
pub const MAX_ECHO_CHARS: usize = 200;

/// Every time and output value finite, checked before anything is written
/// or printed; the error names the output and the time.
pub(crate) fn check_finite_columns(
    t: &[f64],
    names: &[&str],
    cols: &[&[f64]],
) -> Result<(), String> {
    if let Some((i, v)) = t.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(format!(
            "the time of sample {i} is {v}, not a finite number: the run is not valid (nothing written)"
        ));
    }
    for (n, c) in names.iter().zip(cols) {
        if let Some((i, v)) = c.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            let at = t.get(i).map_or(String::new(), |t| format!(" at t = {t} s"));
            return Err(format!(
                "output `{}` is {v}{at}, not a finite number: the run is not valid (nothing written)",
                ffr::codegen::sanitize::snippet(n, crate::plot::MAX_LABEL_CHARS)
            ));
        }
    }
    Ok(())
}

/// `, N steps restarted from rest, M halved` when there were any.
pub(super) fn retries(restarts: usize, splits: usize) -> String {
    match (restarts, splits) {
        (0, 0) => String::new(),
        (r, 0) => format!(", {r} steps restarted from rest"),
        (r, s) => format!(", {r} steps restarted from rest, {s} halved"),
    }
}
