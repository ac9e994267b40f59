//! `ffr linearize` (a scene's linear model `A, B, C, D` and eigenvalues)
//! and `ffr campbell` (frequencies against rotor speed).

use crate::output;
use ffr::runtime::linear::{eigenvalues, LinearModel};
use ffr::runtime::nalgebra::DMatrix;
use ffr::scene::linear::{campbell_with, linearize_scene, At, Campbell};
use serde_json::{json, Value};
use std::error::Error;
use std::path::{Path, PathBuf};

/// Arguments of `ffr linearize`.
#[derive(clap::Args, Debug)]
pub struct LinearizeArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// Where: a time `T` in seconds (the scene is run to `T`; 0 is the
    /// consistent initial state) or `static` (the static equilibrium under
    /// the scene's loads).
    #[arg(long, default_value = "0")]
    pub at: String,
    /// Inputs, comma-separated: `jointN` (a torque in the N-th revolute
    /// joint, 1-based), `forceN` (the amplitude of the N-th force), `driveN`
    /// (the acceleration of the N-th joint's drive; its angle and rate
    /// become states); default: every motor joint and point force or
    /// torque; `--inputs ''` for none.
    #[arg(long, value_delimiter = ',')]
    pub inputs: Option<Vec<String>>,
    /// Outputs, comma-separated names of the scene's `[[outputs]]`; default:
    /// all but the energies; `--outputs ''` for none.
    #[arg(long, value_delimiter = ',')]
    pub outputs: Option<Vec<String>>,
    /// Print one JSON object `{states, inputs, outputs, A, B, C, D, eigenvalues}`.
    #[arg(long)]
    pub json: bool,
    /// Also write A.mtx, B.mtx, C.mtx, D.mtx (Matrix Market) and
    /// linear.json into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Arguments of `ffr campbell`.
#[derive(clap::Args, Debug)]
pub struct CampbellArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// Rotor speeds Ω (rad/s), comma-separated.
    #[arg(long, value_delimiter = ',', required = true)]
    pub speeds: Vec<f64>,
    /// The driven revolute joint (1-based in `[[joints]]`; default the first
    /// revolute joint with a drive).
    #[arg(long)]
    pub joint: Option<usize>,
    /// Modes per speed, lowest first.
    #[arg(long, default_value_t = 10)]
    pub count: usize,
    /// Print one JSON object `{speeds, modes}`.
    #[arg(long)]
    pub json: bool,
    /// Write the Campbell diagram (with the 1P, 3P, 6P lines) to this SVG.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Write each speed's modes as ParaView animations over one period into
    /// DIR (DIR/SCENE_speedI_modeJ.pvd, I and J from 1; see docs/vtk.md).
    #[arg(long, value_name = "DIR")]
    pub vtk: Option<PathBuf>,
}

/// An error of the library about the scene at `path`: a scene-file error
/// already says where; anything else gets the file's name in front.
fn located(path: &Path, e: ffr::Error) -> Box<dyn Error> {
    match e {
        ffr::Error::Scene(_) => e.into(),
        other => format!("{}: {other}", path.display()).into(),
    }
}

fn parse_at(s: &str) -> Result<At, String> {
    if s == "static" {
        return Ok(At::Static);
    }
    match s.parse::<f64>() {
        Ok(t) if t.is_finite() && t >= 0.0 => Ok(At::Time(t)),
        _ => Err(format!(
            "--at `{s}`: expected a time in seconds (finite, ≥ 0) or `static`"
        )),
    }
}

fn rows(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
        .collect()
}

/// The JSON of a linear model: `{states, inputs, outputs, A, B, C, D,
/// eigenvalues}` (matrices as nested row lists, eigenvalues `[re, im]`).
pub fn linear_json(m: &LinearModel) -> Result<Value, Box<dyn Error>> {
    let ev: Vec<[f64; 2]> = eigenvalues(&m.a)?.iter().map(|l| [l.re, l.im]).collect();
    Ok(json!({
        "states": m.states,
        "inputs": m.inputs,
        "outputs": m.outputs,
        "A": rows(&m.a),
        "B": rows(&m.b),
        "C": rows(&m.c),
        "D": rows(&m.d),
        "eigenvalues": ev,
    }))
}

/// The first line of the Matrix Market files `linearize --out` writes.
const MTX_HEADER: &str = "%%MatrixMarket matrix coordinate real general\n";

/// A matrix in Matrix Market coordinate format (`real general`, ffr's mark
/// line `MTX_MARK` after the header, 1-based,
/// the non-zero entries in column-major order, numbers in shortest
/// round-trip form).
pub fn matrix_market(m: &DMatrix<f64>, comment: &str) -> String {
    let mut entries = Vec::new();
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            let x = m[(i, j)];
            if x != 0.0 {
                entries.push((i + 1, j + 1, x));
            }
        }
    }
    let mut s = format!("{MTX_HEADER}{MTX_MARK}");
    for line in comment.lines() {
        s.push_str("% ");
        s.push_str(line);
        s.push('\n');
    }
    s.push_str(&format!("{} {} {}\n", m.nrows(), m.ncols(), entries.len()));
    for (i, j, x) in entries {
        s.push_str(&format!("{i} {j} {}\n", output::number(x)));
    }
    s
}

/// Run `ffr linearize`.
pub fn linearize(args: &LinearizeArgs) -> Result<LinearModel, Box<dyn Error>> {
    let at = parse_at(&args.at)?;
    if let Some(dir) = &args.out {
        if dir.exists() && !dir.is_dir() {
            return Err(format!("--out {}: not a directory", dir.display()).into());
        }
    }
    let spec = ffr::scene::load::load_spec(&args.scene)?;
    // `--inputs ''` asks for none.
    let names = |v: &Option<Vec<String>>| {
        v.as_ref().map(|v| {
            v.iter()
                .filter(|s| !s.is_empty())
                .cloned()
                .collect::<Vec<_>>()
        })
    };
    let (inputs, outputs) = (names(&args.inputs), names(&args.outputs));
    let model = linearize_scene(
        &spec,
        &ffr::scene::DefaultKernels,
        at,
        inputs.as_deref(),
        outputs.as_deref(),
    )
    .map_err(|e| located(&args.scene, e))?;
    let js = linear_json(&model).map_err(|e| format!("{}: {e}", args.scene.display()))?;
    if let Some(dir) = &args.out {
        write_dir(dir, &model, &js)?;
    }
    if args.json {
        crate::outln!("{}", serde_json::to_string(&js)?)?;
    } else {
        print_summary(&args.scene, &model)?;
    }
    Ok(model)
}

/// The line after the header of every Matrix Market file `linearize --out`
/// writes: `--out` replaces an existing `X.mtx` only if it has it.
pub const MTX_MARK: &str = "% written by ffr linearize; ffr may replace it\n";

/// How every `linear.json` that `linearize --out` writes starts (its first
/// key): `--out` replaces an existing one only if it starts so.
pub const JSON_MARK: &str = "{\"written_by\":\"ffr linearize\",";

/// `linear_json` as `linearize --out` writes it: [`JSON_MARK`] first, then
/// the object's keys.
fn marked_json(js: &Value) -> Result<String, Box<dyn Error>> {
    let body = serde_json::to_string(js)?;
    let rest = body.strip_prefix('{').ok_or("linear.json: not an object")?;
    Ok(if rest == "}" {
        format!("{}}}", JSON_MARK.trim_end_matches(','))
    } else {
        format!("{JSON_MARK}{rest}")
    })
}

/// Write the matrices and `linear.json` into `dir`. The directory holds
/// only files ffr marked: an existing file of these names is replaced only
/// if ffr wrote it ([`output::check_marked`]; a symbolic link is not
/// followed, a foreign file is refused before anything is written).
fn write_dir(dir: &Path, m: &LinearModel, js: &Value) -> Result<(), Box<dyn Error>> {
    let names = |v: &[String]| v.join(" ");
    let files = [
        (
            "A.mtx",
            matrix_market(
                &m.a,
                &format!("A: rows and columns the states: {}", names(&m.states)),
            ),
        ),
        (
            "B.mtx",
            matrix_market(
                &m.b,
                &format!(
                    "B: rows the states, columns the inputs: {}",
                    names(&m.inputs)
                ),
            ),
        ),
        (
            "C.mtx",
            matrix_market(&m.c, &format!("C: rows the outputs: {}", names(&m.outputs))),
        ),
        (
            "D.mtx",
            matrix_market(&m.d, "D: rows the outputs, columns the inputs"),
        ),
        ("linear.json", marked_json(js)?),
    ];
    let paths: Vec<(PathBuf, &str)> = files
        .iter()
        .map(|(n, s)| (dir.join(n), s.as_str()))
        .collect();
    for (p, _) in &paths {
        let mark = if p.extension().is_some_and(|e| e == "mtx") {
            format!("{MTX_HEADER}{MTX_MARK}")
        } else {
            JSON_MARK.to_string()
        };
        output::check_marked(p, mark.as_bytes(), "--out")?;
    }
    std::fs::create_dir_all(dir)
        .map_err(|e| format!("--out {}: cannot create the directory: {e}", dir.display()))?;
    let list: Vec<(&Path, &[u8])> = paths
        .iter()
        .map(|(p, s)| (p.as_path(), s.as_bytes()))
        .collect();
    output::write_all_atomic(&list)?;
    Ok(())
}

fn print_summary(scene: &Path, m: &LinearModel) -> Result<(), Box<dyn Error>> {
    let nz = m.independent.len();
    crate::outln!(
        "{}: linear model at t = {} with {} states ({} independent coordinates, {} drive perturbations, and their rates), {} inputs, {} outputs",
        scene.display(),
        m.state.t,
        m.states.len(),
        nz,
        m.drive_basis.ncols(),
        m.inputs.len(),
        m.outputs.len()
    )?;
    crate::outln!("inputs: {}", m.inputs.join(", "))?;
    crate::outln!("outputs: {}", m.outputs.join(", "))?;
    crate::outln!(
        "{:>5} {:>24} {:>24} {:>16} {:>10}",
        "k",
        "Re λ (1/s)",
        "Im λ (rad/s)",
        "|λ|/2π (Hz)",
        "ζ"
    )?;
    let ev = eigenvalues(&m.a)?;
    for (k, l) in ev.iter().enumerate() {
        let w = l.norm();
        let zeta = if w > 0.0 { -l.re / w } else { 0.0 };
        crate::outln!(
            "{:>5} {:>24.12e} {:>24.12e} {:>16.8} {:>10.3e}",
            k + 1,
            l.re,
            l.im,
            w / std::f64::consts::TAU,
            zeta
        )?;
    }
    if let Some(top) = ev.last().map(|l| l.norm()).filter(|w| *w > 0.0) {
        // RK4's stability region reaches 2√2 on the imaginary axis.
        crate::outln!(
            "stiffest mode: |λ| = {top:.6e} rad/s; an explicit RK4 step must stay below 2√2/|λ| = {:.3e} s",
            2.0 * std::f64::consts::SQRT_2 / top
        )?;
    }
    Ok(())
}

/// The JSON of a Campbell diagram: `{speeds, modes: [[{omega, hz, zeta,
/// label}, …] per speed], warnings: [text, …]}`.
pub fn campbell_json(c: &Campbell) -> Value {
    json!({
        "speeds": c.speeds,
        "warnings": c.warnings,
        "modes": c.modes.iter().map(|ms| ms.iter().map(|m| json!({
            "omega": m.omega,
            "hz": m.hz,
            "zeta": m.zeta,
            "label": m.label,
        })).collect::<Vec<_>>()).collect::<Vec<_>>(),
    })
}

/// Run `ffr campbell`.
pub fn campbell(args: &CampbellArgs) -> Result<Campbell, Box<dyn Error>> {
    if args.count == 0 {
        return Err("--count 0: ask for at least one mode".into());
    }
    if args.joint == Some(0) {
        return Err("--joint 0: joints are numbered from 1 in file order".into());
    }
    if let Some(p) = &args.svg {
        output::check_output(p, "--svg")?;
    }
    let spec = ffr::scene::load::load_spec(&args.scene)?;
    let stem = ffr::scene::vtk::scene_stem(&args.scene.display().to_string());
    if let Some(p) = &args.svg {
        let written: [(&str, &Path); 1] = [("--svg", p)];
        output::check_not_scene_files(&written, &ffr::scene::load::spec_input_files(&spec))?;
        if let Some(dir) = &args.vtk {
            output::check_not_in_series(&written, dir, &stem)?;
        }
    }
    // What the diagram may not show, once, before it is computed.
    let ji = ffr::scene::linear::campbell_joint(&spec, args.joint.map(|j| j - 1))
        .map_err(|e| located(&args.scene, e))?;
    for w in ffr::scene::linear::stiffening_warnings(&spec, ji) {
        eprintln!("warning: {w}");
    }
    let speed_name = |i: usize| {
        let w = args.speeds.len().to_string().len().max(2);
        format!("{stem}_speed{:0w$}", i + 1)
    };
    if let Some(dir) = &args.vtk {
        // Every file checked before anything is computed or written.
        let total = args
            .speeds
            .len()
            .saturating_mul(args.count)
            .saturating_mul(ffr::scene::vtk::FRAMES_PER_PERIOD + 1);
        if total > ffr::scene::vtk::MAX_VTK_FILES {
            return Err(format!(
                "--vtk: {} speeds × {} modes × {} files = {total} VTK files, more than the limit of {}: fewer speeds or a smaller --count",
                args.speeds.len(),
                args.count,
                ffr::scene::vtk::FRAMES_PER_PERIOD + 1,
                ffr::scene::vtk::MAX_VTK_FILES
            )
            .into());
        }
        for i in 0..args.speeds.len() {
            ffr::scene::vtk::check_mode_files(dir, &speed_name(i), args.count)?;
        }
    }
    let mut write = |i: usize,
                     scene: &ffr::scene::Scene,
                     state: &ffr::runtime::State,
                     modes: &[ffr::scene::linear::CampbellMode]|
     -> ffr::Result<()> {
        if let Some(dir) = &args.vtk {
            let m: Vec<(f64, &ffr::scene::vtk::ModeVector)> = modes
                .iter()
                .map(|m| (m.omega, m.vector.as_slice()))
                .collect();
            ffr::scene::vtk::write_linear_modes(dir, &speed_name(i), scene, &state.q, &m)?;
        }
        Ok(())
    };
    let c = campbell_with(
        &spec,
        &ffr::scene::DefaultKernels,
        &args.speeds,
        args.joint.map(|j| j - 1),
        args.count,
        &mut write,
    )
    .map_err(|e| located(&args.scene, e))?;
    // The warnings found while computing (growing modes at a speed), after
    // the stiffening warnings printed above.
    let before = ffr::scene::linear::stiffening_warnings(&spec, ji).len();
    for w in c.warnings.iter().skip(before) {
        eprintln!("warning: {}: {w}", args.scene.display());
    }
    if let Some(p) = &args.svg {
        let svg = campbell_svg(&c, &spec.description.clone().unwrap_or_default())?;
        output::write_atomic(p, svg.as_bytes())?;
    }
    if args.json {
        crate::outln!("{}", serde_json::to_string(&campbell_json(&c))?)?;
    } else {
        crate::outln!(
            "{}: Campbell diagram, joint {} turning at constant speed",
            args.scene.display(),
            c.joint + 1
        )?;
        for (w, ms) in c.speeds.iter().zip(&c.modes) {
            crate::outln!("Ω = {} rad/s", output::number(*w))?;
            for (k, m) in ms.iter().enumerate() {
                crate::outln!(
                    "{:>5} {:>20} rad/s {:>16} Hz  ζ = {:>10.3e}  {}",
                    k + 1,
                    fixed(m.omega, 10),
                    fixed(m.hz, 8),
                    m.zeta,
                    m.label
                )?;
            }
        }
    }
    Ok(c)
}

/// `x` with `digits` decimals below 1e6 in magnitude, else in exponent form
/// with as many significant digits (a frequency of 1e12 rad/s is not 23
/// characters of `1000000000000.0000000000`).
fn fixed(x: f64, digits: usize) -> String {
    if x.abs() < 1e6 || !x.is_finite() {
        format!("{x:.digits$}")
    } else {
        format!("{x:.digits$e}")
    }
}

/// The Campbell diagram as an SVG: each mode's frequency (Hz) against the
/// speed (rpm), and the 1P, 3P, 6P lines.
pub fn campbell_svg(c: &Campbell, title: &str) -> Result<String, Box<dyn Error>> {
    use plotters::prelude::*;
    let title = crate::plot::plot_text(
        &format!("Campbell diagram {title}"),
        crate::plot::MAX_TITLE_CHARS,
    );
    let rpm = |w: f64| w * 60.0 / std::f64::consts::TAU;
    let x_max = c
        .speeds
        .iter()
        .map(|&w| rpm(w))
        .fold(0.0f64, f64::max)
        .max(1e-9);
    let x_min = c
        .speeds
        .iter()
        .map(|&w| rpm(w))
        .fold(x_max, f64::min)
        .min(0.0);
    let f_max = c
        .modes
        .iter()
        .flatten()
        .map(|m| m.hz)
        .filter(|x| x.is_finite())
        .fold(0.0f64, f64::max)
        .max(1e-9)
        * 1.05;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 600)).into_drawing_area();
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(
                crate::plot::axis(x_min, x_max, 0.0),
                crate::plot::axis(0.0, f_max, 0.0),
            )?;
        chart
            .configure_mesh()
            .x_desc("rotor speed (rpm)")
            .y_desc("frequency (Hz)")
            .draw()?;
        for (p, color) in [
            (1.0, BLACK),
            (3.0, RGBColor(120, 120, 120)),
            (6.0, RGBColor(180, 180, 180)),
        ] {
            let pts = vec![(x_min, p * x_min / 60.0), (x_max, p * x_max / 60.0)];
            chart
                .draw_series(LineSeries::new(pts, color.stroke_width(1)))?
                .label(format!("{p}P"))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        }
        let colors = [BLUE, RED, GREEN, MAGENTA, CYAN, RGBColor(200, 120, 0)];
        let n = c.modes.iter().map(Vec::len).max().unwrap_or(0);
        for k in 0..n {
            let color = colors[k % colors.len()];
            let pts: Vec<(f64, f64)> = c
                .speeds
                .iter()
                .zip(&c.modes)
                .filter_map(|(&w, ms)| ms.get(k).map(|m| (rpm(w), m.hz)))
                .collect();
            let label = c
                .modes
                .first()
                .and_then(|ms| ms.get(k))
                .map(|m| format!("mode {} ({})", k + 1, m.label))
                .unwrap_or_default();
            chart
                .draw_series(LineSeries::new(pts.clone(), color))?
                .label(label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
            chart.draw_series(pts.into_iter().map(|p| Circle::new(p, 3, color.filled())))?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()?;
        root.present()?;
    }
    Ok(svg)
}
