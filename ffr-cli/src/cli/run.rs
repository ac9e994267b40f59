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
    reference: Option<&Path>,
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
    // Outputs replace neither an input (the scene's files, the reference)
    // nor a file of the VTK series written in the same run.
    let written: [(&str, &Path); 2] = [("--csv", &csv), ("--svg", &svg)];
    output::check_not_scene_files(&written, &scene.input_files())?;
    if let Some(p) = reference {
        output::check_not_inputs(&written, &[("the --reference file", p)])?;
    }
    if let Some(v) = &vtk {
        output::check_not_in_series(
            &written,
            &v.dir,
            &ffr::scene::vtk::scene_stem(&scene.origin),
        )?;
    }
    // A reference is read and matched before the run.
    let reference = match reference {
        Some(p) => Some(read_reference(p, &scene)?),
        None => None,
    };
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
    let names_ref: Vec<String> = reference
        .as_ref()
        .map(|(rf, matched)| {
            matched
                .iter()
                .map(|c| format!("{c} ({})", reference_name(rf)))
                .collect()
        })
        .unwrap_or_default();
    let overlays: Vec<crate::plot::TimedSeries> = reference
        .as_ref()
        .map(|(rf, matched)| {
            matched
                .iter()
                .zip(&names_ref)
                .map(|(c, n)| {
                    (
                        n.as_str(),
                        rf.t.as_slice(),
                        rf.column(c).expect("a matched column"),
                    )
                })
                .collect()
        })
        .unwrap_or_default();
    let plot = crate::plot::time_svg_with(
        scene.description.as_deref().unwrap_or(&scene.origin),
        &y_label(&scene),
        &r.t,
        &series,
        &overlays,
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
    for b in &r.rotations {
        crate::outln!(
            "  elastic rotation of `{}`: at most {:.3} rad (t = {:.4} s, x = {:.4} m{})",
            text(&b.body, MAX_ECHO_CHARS),
            b.angle,
            b.t,
            b.x,
            if b.segment.1 > 1 {
                format!(", segment {} of {}", b.segment.0, b.segment.1)
            } else {
                String::new()
            }
        )?;
    }
    for w in &r.warnings {
        eprintln!("warning: {}", text(w, usize::MAX));
    }
    if let Some((rf, matched)) = &reference {
        crate::outln!(
            "reference {} (t from {} to {} s): max |run − reference| at the run's times in that span, the reference interpolated linearly:",
            text(&rf.source, MAX_ECHO_CHARS),
            rf.t[0],
            rf.t[rf.t.len() - 1]
        )?;
        for c in matched {
            let i = r
                .names
                .iter()
                .position(|n| n == c)
                .expect("a matched column");
            let label = text(c, crate::plot::MAX_LABEL_CHARS);
            match rf.max_abs_difference(c, &r.t, &r.columns[i]) {
                Some((d, n)) => crate::outln!("  {label}: {d:.6e} ({n} samples)")?,
                None => {
                    crate::outln!("  {label}: no sample of the run in the reference's time span")?
                }
            }
        }
        let unmatched: Vec<String> = rf
            .header
            .iter()
            .filter(|c| !matched.contains(c))
            .map(|c| text(c, crate::plot::MAX_LABEL_CHARS))
            .collect();
        if !unmatched.is_empty() {
            crate::outln!(
                "  not outputs of the scene (ignored): {}",
                unmatched.join(", ")
            )?;
        }
    }
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

/// The reference CSV at `path` ([`crate::reference::Reference::read`]) and
/// its columns that are outputs of `scene` (in the reference's order); an
/// error if none is.
fn read_reference(
    path: &Path,
    scene: &ffr::scene::Scene,
) -> Result<(crate::reference::Reference, Vec<String>), Box<dyn std::error::Error>> {
    // Only the columns named like the scene's outputs are read.
    let outputs: Vec<&str> = scene.outputs.iter().map(|o| o.name.as_str()).collect();
    let rf = crate::reference::Reference::read_columns(path, Some(&outputs), 0)?;
    let matched: Vec<String> = rf.columns.clone();
    if matched.is_empty() {
        let text = |v: Vec<&str>| {
            v.iter()
                .map(|c| ffr::codegen::sanitize::snippet(c, crate::plot::MAX_LABEL_CHARS))
                .collect::<Vec<_>>()
                .join(", ")
        };
        return Err(format!(
            "{}: --reference: no column is an output of the scene (its columns: {}; the scene's outputs: {})",
            rf.source,
            text(rf.header.iter().map(String::as_str).collect()),
            text(scene.outputs.iter().map(|o| o.name.as_str()).collect())
        )
        .into());
    }
    Ok((rf, matched))
}

/// How a reference's curves are named in the legend: `reference FILE`.
fn reference_name(rf: &crate::reference::Reference) -> String {
    let file = Path::new(&rf.source)
        .file_name()
        .map_or_else(|| rf.source.clone(), |f| f.to_string_lossy().into_owned());
    format!("reference {file}")
}

/// The unit of an output (SI, as scene files are written).
pub(crate) fn unit(kind: &ffr::scene::OutputKind) -> &'static str {
    use ffr::scene::OutputKind;
    match kind {
        OutputKind::Position(_) | OutputKind::Deflection(_) => "m",
        OutputKind::Velocity(_) => "m/s",
        OutputKind::Angle => "rad",
        OutputKind::Energy(_) => "J",
    }
}

/// The y axis label of a scene's plot: `outputs (UNITS)`, the outputs'
/// distinct units in their order.
fn y_label(scene: &ffr::scene::Scene) -> String {
    let mut units: Vec<&str> = Vec::new();
    for o in &scene.outputs {
        let u = unit(&o.kind);
        if !units.contains(&u) {
            units.push(u);
        }
    }
    if units.is_empty() {
        "outputs".into()
    } else {
        format!("outputs ({})", units.join(", "))
    }
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
