//! The `ffr` command line.

use crate::benchmarks::spin_up::{SpinUp, SpinUpResult, KRB};
use crate::output;
use clap::{Args, Parser, Subcommand};
use ffr::codegen::builder::KernelConfig;
use ffr::codegen::limits::{check_literals, check_params};
use ffr::codegen::sanitize::check_type_name;
use ffr::codegen::{generate_kernels, BodySpec, EmitOptions, Shape};
use ffr::invariants::check_invariants;
use ffr::kernels::BeamSpec;
use ffr::modal::ModalSettings;
use ffr::runtime::spec::{
    Formalism, FrameModel, KernelOptions, Params, Reference, SceneDim, Stiffening,
};
use ffr::runtime::{Body, GeneralizedAlpha, Integrator, Invariants, Rk4Baumgarte};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// Floating frame of reference (FFR) code generation and simulation.
#[derive(Parser, Debug)]
#[command(name = "ffr", version, about)]
pub struct Cli {
    /// What to do; without a command, the main job runs (`spin-up` with its defaults).
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// Subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Evaluate a body's invariants from its generated element kernels.
    Invariants {
        #[command(flatten)]
        body: BodyArgs,
        #[command(flatten)]
        params: ParamArgs,
        /// Print one JSON object (otherwise a short text summary).
        #[arg(long)]
        json: bool,
    },
    /// A body's natural frequencies by modal truncation of its exact m_ff,
    /// K_ff (clamped/pinned: eigenmodes; free: elastic modes, rigid motions
    /// removed), or Craig–Bampton with --boundary; see docs/modal.md.
    Modes {
        #[command(flatten)]
        body: BodyArgs,
        #[command(flatten)]
        params: ParamArgs,
        /// Number of modes, lowest first (default: every elastic mode; with
        /// --boundary, every fixed-interface mode).
        #[arg(long)]
        count: Option<usize>,
        /// Craig–Bampton instead of modal truncation: these body nodes
        /// (0 to N, comma-separated) are the boundary; --count fixed-interface
        /// modes plus one static constraint mode per boundary coordinate.
        #[arg(long, value_delimiter = ',')]
        boundary: Vec<usize>,
        /// Print one JSON object with the modal matrices (otherwise the
        /// frequencies in rad/s and Hz).
        #[arg(long)]
        json: bool,
    },
    /// Write a body reduced to its lowest modes in a format other engines
    /// read (MBDyn modal .fem, SID); see docs/export.md.
    Export {
        /// Output format.
        #[arg(long)]
        format: ExportFormat,
        #[command(flatten)]
        body: BodyArgs,
        #[command(flatten)]
        params: ParamArgs,
        /// Number of modes kept (default: every elastic mode; with
        /// --boundary, the number of fixed-interface modes, default all).
        #[arg(long)]
        modes: Option<usize>,
        /// Craig–Bampton with these boundary nodes (as for `modes`).
        #[arg(long, value_delimiter = ',')]
        boundary: Vec<usize>,
        /// The file to write (written to a temporary file, then renamed).
        #[arg(long)]
        out: PathBuf,
    },
    /// Run the spin-up beam benchmark (the main job).
    SpinUp(SpinUpArgs),
    /// Work-precision report of the benchmark scenes (report.md, points.csv,
    /// one SVG per scene; see docs/report.md).
    Report(crate::report::ReportArgs),
    /// Stiff and extreme cases, each with its check (stability.md; exits
    /// non-zero if a case fails; see docs/stability.md).
    Stability(crate::stability::StabilityArgs),
    /// Run a scene file.
    Run {
        /// The scene file (TOML; see the README's "Scene files").
        scene: PathBuf,
        /// Where to write the outputs (default: results/SCENE.csv, SCENE the file name).
        #[arg(long)]
        csv: Option<PathBuf>,
        /// Where to write the SVG plot (default: next to the CSV).
        #[arg(long)]
        svg: Option<PathBuf>,
        /// Run every flexible body on the general kernels (spatial scene,
        /// free frame) instead of those specialized for the scene
        /// (comparisons).
        #[arg(long)]
        general: bool,
    },
    /// Print the generated Rust: element kernels of a shape, a body with a
    /// fixed mesh (`--elements`), or every flexible body of a scene (`--scene`).
    Emit {
        #[command(flatten)]
        kernel: KernelArgs,
        /// Number of elements: emit a body type with this fixed mesh.
        #[arg(long, value_parser = clap::value_parser!(u16).range(1..=256))]
        elements: Option<u16>,
        /// Reference condition of a fixed-mesh body.
        #[arg(long, value_enum, default_value_t = Reference::Clamped)]
        reference: Reference,
        /// Emit the specialized kernels of this scene file's flexible bodies.
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Name of the generated type.
        #[arg(long, default_value = "Body")]
        type_name: String,
    },
}

/// Which element kernels: shape and model options.
#[derive(Args, Debug, Clone)]
pub struct KernelArgs {
    /// Built-in shape name (beam2, beam3) or path to a shape .toml file.
    #[arg(long, default_value = "beam3")]
    pub shape: String,
    /// Inertia formalism: consistent or lumped.
    #[arg(long, value_enum, default_value_t = Formalism::Consistent)]
    pub formalism: Formalism,
    /// Geometric stiffening: off, on (= fourth-order), second-order, fourth-order.
    #[arg(long, value_enum, default_value_t = Stiffening::Off)]
    pub stiffening: Stiffening,
    /// The scene the body moves in: planar or spatial (default: the shape's).
    #[arg(long = "scene-dim", value_enum)]
    pub scene_dim: Option<SceneDim>,
    /// Only prescribed frame motion (no reference rows).
    #[arg(long)]
    pub prescribed_frame: bool,
}

impl KernelArgs {
    /// The kernel options these arguments give.
    pub fn options(&self) -> KernelOptions {
        KernelOptions {
            formalism: self.formalism,
            stiffening: self.stiffening,
            scene: self.scene_dim,
            frame: if self.prescribed_frame {
                FrameModel::Prescribed
            } else {
                FrameModel::Free
            },
        }
    }

    fn config(&self, name: &str) -> KernelConfig {
        KernelConfig::new(name, &self.shape).options(self.options())
    }
}

/// Which body: shape, mesh, reference condition, formalism.
#[derive(Args, Debug, Clone)]
pub struct BodyArgs {
    /// Built-in shape name (beam2, beam3) or path to a shape .toml file.
    #[arg(long, default_value = "beam3")]
    pub shape: String,
    /// Number of equal elements (1 to 256).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..=256))]
    pub elements: u16,
    /// Reference condition: clamped, pinned or free.
    #[arg(long, value_enum, default_value_t = Reference::Clamped)]
    pub reference: Reference,
    /// Inertia formalism: consistent or lumped.
    #[arg(long, value_enum, default_value_t = Formalism::Consistent)]
    pub formalism: Formalism,
    /// Run the kernels on tapes even for a built-in shape (comparisons).
    #[arg(long)]
    pub tape: bool,
}

/// Parameter values (SI units); a shape that does not use one ignores it.
/// Defaults: a 1 m steel bar of 10 mm × 10 mm square section.
#[derive(Args, Debug, Clone)]
pub struct ParamArgs {
    /// Body length L (m).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub length: f64,
    /// Density ρ (kg/m³).
    #[arg(long, default_value_t = 7850.0, allow_hyphen_values = true)]
    pub rho: f64,
    /// Area A (m²).
    #[arg(long, default_value_t = 1e-4, allow_hyphen_values = true)]
    pub area: f64,
    /// I_y = ∫z² dA (m⁴).
    #[arg(long, default_value_t = 1e-8 / 12.0, allow_hyphen_values = true)]
    pub iy: f64,
    /// I_z = ∫y² dA (m⁴).
    #[arg(long, default_value_t = 1e-8 / 12.0, allow_hyphen_values = true)]
    pub iz: f64,
    /// Young's modulus E (Pa).
    #[arg(long, default_value_t = 2.1e11, allow_hyphen_values = true)]
    pub e: f64,
    /// Shear modulus G (Pa).
    #[arg(long, default_value_t = 8.1e10, allow_hyphen_values = true)]
    pub g: f64,
    /// Torsion constant J (m⁴).
    #[arg(long, default_value_t = 1.406e-8, allow_hyphen_values = true)]
    pub j: f64,
}

impl ParamArgs {
    /// As parameter values.
    pub fn values(&self) -> Params {
        Params {
            length: self.length,
            rho: self.rho,
            area: self.area,
            iy: self.iy,
            iz: self.iz,
            e: self.e,
            g: self.g,
            j: self.j,
        }
    }
}

impl BodyArgs {
    /// The body these arguments describe.
    pub fn beam(&self, params: Params) -> Result<BeamSpec, Box<dyn std::error::Error>> {
        Ok(BeamSpec {
            shape: self.shape.clone(),
            elements: self.elements as usize,
            reference: self.reference,
            options: KernelOptions::new().formalism(self.formalism),
            params,
            force_tape: self.tape,
        })
    }
}

/// The integrator of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum IntegratorKind {
    /// Implicit generalized-α (`--rho-inf`).
    GeneralizedAlpha,
    /// Explicit RK4 with Baumgarte stabilization.
    Rk4,
}

/// How `--modes` reduces the spin-up beam.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ReductionKind {
    /// The lowest clamped modes.
    Modal,
    /// Craig–Bampton with the tip node as boundary.
    CraigBampton,
}

/// The file format of `ffr export`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ExportFormat {
    /// MBDyn's modal element file (`.fem`).
    MbdynFem,
    /// The standard input data (SID) of flexible bodies.
    Sid,
}

/// Options of a spin-up run.
#[derive(Args, Debug, Clone)]
pub struct SpinUpArgs {
    /// Final spin rate ω_s (rad/s).
    #[arg(long, default_value_t = 4.0, allow_hyphen_values = true)]
    pub omega: f64,
    /// Number of elements of the 8 m beam (1 to 256).
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u16).range(1..=256))]
    pub elements: u16,
    /// Geometric stiffening: on (= fourth-order), off, second-order, fourth-order.
    #[arg(long, value_enum, default_value = "on")]
    pub stiffening: Stiffening,
    /// Inertia formalism: consistent or lumped.
    #[arg(long, value_enum, default_value_t = Formalism::Consistent)]
    pub formalism: Formalism,
    /// The spatial model: beam3 with Euler parameters (prescribed rotation
    /// about z) instead of the planar beam2.
    #[arg(long)]
    pub spatial: bool,
    /// End time (s).
    #[arg(long, default_value_t = 20.0, allow_hyphen_values = true)]
    pub t_end: f64,
    /// Time step (s).
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true)]
    pub dt: f64,
    /// Integrator: generalized-alpha or rk4.
    #[arg(long, value_enum, default_value_t = IntegratorKind::GeneralizedAlpha)]
    pub integrator: IntegratorKind,
    /// Generalized-α spectral radius at infinite frequency ρ∞ ∈ [0, 1].
    #[arg(long, default_value_t = 0.8, allow_hyphen_values = true)]
    pub rho_inf: f64,
    /// Multiply Young's and shear moduli by this factor (stiffness studies).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub e_scale: f64,
    /// Run the kernels on tapes instead of the compiled code (comparisons).
    #[arg(long)]
    pub tape: bool,
    /// Run the general body (kernels for a spatial scene and a free frame)
    /// instead of the one specialized for this scene (comparisons).
    #[arg(long)]
    pub general: bool,
    /// Reduce the beam to this many normal modes (a modal body; default:
    /// the full nodal body); see docs/modal.md.
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..))]
    pub modes: Option<u16>,
    /// With --modes: modal truncation (the lowest clamped modes) or
    /// Craig-Bampton with the tip node as boundary (fixed-interface modes
    /// plus its static constraint modes).
    #[arg(long, value_enum, default_value_t = ReductionKind::Modal, requires = "modes")]
    pub reduction: ReductionKind,
    /// With --modes: leave out the static modes (the inertia loads' static
    /// responses and, with stiffening, the modal derivatives).
    #[arg(long, requires = "modes")]
    pub no_static_modes: bool,
    /// With --modes: damping ratio ζ of every normal mode.
    #[arg(long, default_value_t = 0.0, requires = "modes")]
    pub modal_damping: f64,
    /// Where to write `t,tip_axial,tip_transverse` (default: results/spin_up_….csv).
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Where to write the SVG plot (default: next to the CSV).
    #[arg(long)]
    pub svg: Option<PathBuf>,
}

impl Default for SpinUpArgs {
    fn default() -> Self {
        SpinUpArgs::parse_from::<[&str; 0], &str>([])
    }
}

impl SpinUpArgs {
    fn parse_from<I: IntoIterator<Item = T>, T: Into<std::ffi::OsString> + Clone>(args: I) -> Self {
        #[derive(Parser)]
        struct Wrap {
            #[command(flatten)]
            a: SpinUpArgs,
        }
        let v: Vec<std::ffi::OsString> = std::iter::once("ffr".into())
            .chain(args.into_iter().map(Into::into))
            .collect();
        Wrap::parse_from(v).a
    }

    /// The scene settings these arguments ask for (checked).
    pub fn config(&self) -> Result<SpinUp, Box<dyn std::error::Error>> {
        for (name, v) in [
            ("--t-end", self.t_end),
            ("--dt", self.dt),
            ("--e-scale", self.e_scale),
        ] {
            if !v.is_finite() || v <= 0.0 {
                return Err(format!("{name} must be a positive number, found {v}").into());
            }
        }
        if !self.omega.is_finite() {
            return Err(format!("--omega must be a finite number, found {}", self.omega).into());
        }
        if self.dt > self.t_end {
            return Err(format!("--dt {} is longer than --t-end {}", self.dt, self.t_end).into());
        }
        if !(0.0..=1.0).contains(&self.rho_inf) {
            return Err(format!("--rho-inf must be in [0, 1], found {}", self.rho_inf).into());
        }
        let mut cfg = SpinUp::new(self.omega);
        cfg.elements = self.elements as usize;
        cfg.stiffening = self.stiffening;
        cfg.formalism = self.formalism;
        cfg.spatial = self.spatial;
        cfg.t_end = self.t_end;
        cfg.dt = self.dt;
        cfg.force_tape = self.tape;
        cfg.general = self.general;
        if let Some(k) = self.modes {
            if self.general {
                return Err("--general applies to the nodal body, not with --modes".into());
            }
            if !(self.modal_damping.is_finite() && self.modal_damping >= 0.0) {
                return Err(format!(
                    "--modal-damping must be a finite ratio ≥ 0, found {}",
                    self.modal_damping
                )
                .into());
            }
            cfg.modal = Some(ModalSettings {
                modes: k as usize,
                boundary: if self.reduction == ReductionKind::CraigBampton {
                    vec![cfg.elements]
                } else {
                    Vec::new()
                },
                static_modes: !self.no_static_modes,
                damping: vec![self.modal_damping],
            });
        }
        cfg.params = Params {
            e: KRB.e * self.e_scale,
            g: KRB.g * self.e_scale,
            ..KRB
        };
        cfg.integrator = match self.integrator {
            IntegratorKind::Rk4 => Integrator::Rk4(Rk4Baumgarte::default()),
            IntegratorKind::GeneralizedAlpha => {
                Integrator::GeneralizedAlpha(GeneralizedAlpha::with_rho_inf(self.rho_inf))
            }
        };
        Ok(cfg)
    }

    fn tag(&self) -> String {
        let s = match self.stiffening {
            Stiffening::Off => "linear",
            Stiffening::SecondOrder => "stiff2",
            Stiffening::FourthOrder => "stiff",
        };
        let modal = match self.modes {
            None => String::new(),
            Some(k) => format!(
                "_{}{k}{}",
                if self.reduction == ReductionKind::CraigBampton {
                    "cb"
                } else {
                    "modes"
                },
                if self.no_static_modes { "_pure" } else { "" }
            ),
        };
        format!(
            "spin_up_omega{}_n{}_{s}{}{modal}",
            self.omega,
            self.elements,
            if self.spatial { "_spatial" } else { "" }
        )
    }
}

/// The default output paths `results/<tag>.csv` and `.svg`, checked before
/// a run ([`output::check_outputs`]: regular files or new paths in a usable
/// directory, not the same file twice).
fn outputs(
    csv: &Option<PathBuf>,
    svg: &Option<PathBuf>,
    tag: &str,
) -> Result<(PathBuf, PathBuf), Box<dyn std::error::Error>> {
    let csv = csv
        .clone()
        .unwrap_or_else(|| PathBuf::from("results").join(format!("{tag}.csv")));
    let svg_given = svg.is_some();
    let svg = svg.clone().unwrap_or_else(|| csv.with_extension("svg"));
    let svg_flag = if svg_given {
        "--svg"
    } else {
        "the plot (by default the CSV path with extension .svg)"
    };
    output::check_outputs(&[("--csv", &csv), (svg_flag, &svg)])?;
    Ok((csv, svg))
}

/// Run the spin-up job: check, run, write the CSV and SVG, print a summary.
/// A run that diverged is reported and is an error (non-zero exit).
pub fn spin_up(args: &SpinUpArgs) -> Result<SpinUpResult, Box<dyn std::error::Error>> {
    let cfg = args.config()?;
    let (csv, svg) = outputs(&args.csv, &args.svg, &args.tag())?;
    let r = crate::benchmarks::spin_up::run(&cfg)?;
    let mut cols: Vec<(&str, &[f64])> = vec![
        ("tip_axial", &r.tip_axial),
        ("tip_transverse", &r.tip_transverse),
    ];
    if cfg.spatial {
        cols.push(("tip_lateral", &r.tip_lateral));
    }
    let names: Vec<&str> = cols.iter().map(|c| c.0).collect();
    let values: Vec<&[f64]> = cols.iter().map(|c| c.1).collect();
    check_finite_columns(&r.t, &names, &values)?;
    let plot = crate::plot::time_svg(
        &format!(
            "KRB spin-up, ω_s = {} rad/s, {} {} elements, stiffening {}",
            args.omega,
            args.elements,
            if cfg.spatial { "beam3" } else { "beam2" },
            cfg.stiffening
        ),
        "tip displacement, hub frame (m)",
        &r.t,
        &cols,
    )?;
    output::write_all_atomic(&[
        (&csv, crate::plot::csv(&r.t, &names, &values).as_bytes()),
        (&svg, plot.as_bytes()),
    ])?;
    crate::outln!(
        "spin-up beam (Kane, Ryan & Banerjee 1987): L = 8 m, ω_s = {} rad/s, T = 15 s, {} {} elements (kernels: {}), {} formalism, stiffening {}{}",
        args.omega,
        args.elements,
        if cfg.spatial { "beam3 (spatial, Euler parameters)" } else { "beam2 (planar)" },
        r.kernels,
        cfg.formalism,
        cfg.stiffening,
        if args.e_scale != 1.0 { format!(", E × {}", args.e_scale) } else { String::new() }
    )?;
    if cfg.modal.is_some() {
        crate::outln!("modal body: {}", r.body)?;
    }
    if let Some((t, y)) = r.min_transverse() {
        crate::outln!("peak tip deflection (hub frame): {y:.5} m at t = {t:.2} s")?;
    }
    if let Some(reference) = crate::reference::spin_up(args.omega).filter(|_| r.diverged.is_none())
    {
        if let Some((rel, abs)) = reference.error(
            "tip_transverse",
            &r.t,
            &r.tip_transverse,
            args.t_end.min(30.0),
        ) {
            let (_, yr) = reference.min("tip_transverse").unwrap_or((0.0, f64::NAN));
            crate::outln!(
                "against the geometrically exact reference (peak {yr:.5} m; {}): history error {rel:.2e} relative, {abs:.2e} m",
                reference.source
            )?;
        }
    }
    crate::outln!(
        "steps: {} of dt = {} s, {} Newton iterations, {} iteration matrices{}, wall time {:.3} s",
        r.steps,
        args.dt,
        r.newton_iterations,
        r.jacobians,
        retries(r.restarts, r.splits),
        r.wall
    )?;
    crate::outln!("wrote {} and {}", csv.display(), svg.display())?;
    if let Some(d) = &r.diverged {
        let hint = if cfg.stiffening == Stiffening::Off {
            " (the linear FFR model softens above its first bending frequency; try --stiffening on)"
        } else {
            ""
        };
        return Err(format!("the run diverged at t = {:.3} s: {}{hint}", d.t, d.reason).into());
    }
    Ok(r)
}

/// Run a scene file, write its outputs, print a summary; an integrator
/// failure is reported and is an error.
pub fn run_scene(
    path: &Path,
    csv: &Option<PathBuf>,
    svg: &Option<PathBuf>,
    general: bool,
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
    let r = ffr::scene::run(&scene)?;
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
        "steps: {} of dt = {} s, {} Newton iterations, {} iteration matrices{}, wall time {:.3} s",
        r.steps,
        scene.dt,
        r.newton_iterations,
        r.jacobians,
        retries(r.restarts, r.splits),
        r.wall
    )?;
    crate::outln!("wrote {} and {}", csv.display(), svg.display())?;
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
fn check_finite_columns(t: &[f64], names: &[&str], cols: &[&[f64]]) -> Result<(), String> {
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
fn retries(restarts: usize, splits: usize) -> String {
    match (restarts, splits) {
        (0, 0) => String::new(),
        (r, 0) => format!(", {r} steps restarted from rest"),
        (r, s) => format!(", {r} steps restarted from rest, {s} halved"),
    }
}

/// Run a parsed command line.
pub fn run(cli: Cli) -> Result<(), Box<dyn std::error::Error>> {
    match cli.command {
        Some(Command::Invariants { body, params, json }) => {
            let p = params.values();
            check_params(&p, &[])?;
            let beam = body.beam(p)?;
            let kernels = beam.kernels()?;
            let used = ffr::runtime::ElementKernels::info(&kernels)
                .params_used
                .to_vec();
            check_params(&p, &used)?;
            let b = beam.body()?;
            let inv = b.invariants();
            check_invariants(&inv, &b.layout().labels, beam.options.formalism)?;
            if json {
                crate::outln!(
                    "{}",
                    serde_json::to_string(&invariants_json(&inv, &b.layout().labels))?
                )?;
            } else {
                print_summary(&b.layout().description, &inv, &b.layout().labels)?;
            }
            Ok(())
        }
        Some(Command::Emit {
            kernel,
            elements,
            reference,
            scene,
            type_name,
        }) => {
            check_type_name(&type_name, "--type-name")?;
            let text = match (&scene, elements) {
                (Some(path), _) => ffr::scene::emit::scene_file(path, &type_name)?,
                (None, Some(n)) => {
                    let cfg = kernel.config(&type_name);
                    let model = cfg.model(Path::new("."))?;
                    let spec = BodySpec::new(model.shape.clone(), n as usize, reference)?
                        .with_formalism(model.options.formalism);
                    let set = generate_kernels(&model)?;
                    check_literals(&set)?;
                    ffr::codegen::emit_body_file(
                        &set,
                        &spec,
                        &EmitOptions {
                            type_name,
                            ..EmitOptions::default()
                        },
                    )
                }
                (None, None) => {
                    let cfg = kernel.config(&type_name);
                    let model = cfg.model(Path::new("."))?;
                    let set = generate_kernels(&model)?;
                    check_literals(&set)?;
                    ffr::codegen::emit_kernels_file(&set, &type_name, "::ffr::runtime")
                }
            };
            output::print(&text)?;
            Ok(())
        }
        Some(Command::Modes {
            body,
            params,
            count,
            boundary,
            json,
        }) => crate::modes::modes(&body, &params, count, &boundary, json),
        Some(Command::Export {
            format,
            body,
            params,
            modes,
            boundary,
            out,
        }) => crate::modes::export(format, &body, &params, modes, &boundary, &out),
        Some(Command::SpinUp(args)) => spin_up(&args).map(|_| ()),
        Some(Command::Report(args)) => crate::report::run(&args).map(|_| ()),
        Some(Command::Stability(args)) => crate::stability::run(&args).map(|_| ()),
        Some(Command::Run {
            scene,
            csv,
            svg,
            general,
        }) => run_scene(&scene, &csv, &svg, general).map(|_| ()),
        None => spin_up(&SpinUpArgs::default()).map(|_| ()),
    }
}

const AXES: [&str; 3] = ["x", "y", "z"];

/// The invariants as the JSON object of `ffr invariants --json`: `mass`,
/// `St0`, `Sbar`, `Skl`, `Ikl`, `theta` (keyed `"xx"`, `"xy"`, …; a planar
/// body has only x, y), `mff`, `Kff`, `dofs`.
pub fn invariants_json(inv: &Invariants, dofs: &[String]) -> Value {
    let d = inv.dim;
    let n = inv.nf();
    let mat = |m: &ffr::runtime::nalgebra::DMatrix<f64>| -> Vec<Vec<f64>> {
        (0..n)
            .map(|i| (0..n).map(|j| m[(i, j)]).collect())
            .collect()
    };
    let keyed = |f: &dyn Fn(usize, usize) -> Value| {
        let mut m = serde_json::Map::new();
        for k in 0..d {
            for l in 0..d {
                m.insert(format!("{}{}", AXES[k], AXES[l]), f(k, l));
            }
        }
        Value::Object(m)
    };
    json!({
        "mass": inv.mass,
        "St0": inv.s_t0.as_slice()[..d].to_vec(),
        "Sbar": (0..d).map(|k| (0..n).map(|a| inv.s_bar[(k, a)]).collect::<Vec<f64>>()).collect::<Vec<_>>(),
        "Skl": keyed(&|k, l| json!(mat(&inv.s_kl[k][l]))),
        "Ikl": keyed(&|k, l| json!(inv.i_kl[k][l].as_slice())),
        "theta": keyed(&|k, l| json!(inv.theta[(k, l)])),
        "mff": mat(&inv.m_ff),
        "Kff": mat(&inv.k_ff),
        "dofs": dofs,
    })
}

fn print_summary(
    description: &str,
    inv: &Invariants,
    dofs: &[String],
) -> Result<(), output::OutputError> {
    crate::outln!("{description}")?;
    crate::outln!("elastic coordinates ({}): {}", dofs.len(), dofs.join(" "))?;
    crate::outln!("mass m = {:e}", inv.mass)?;
    let d = inv.dim;
    crate::outln!("S_t0 = {:?}", &inv.s_t0.as_slice()[..d])?;
    for k in 0..d {
        crate::outln!(
            "Θ_{}· = {:?}",
            AXES[k],
            (0..d).map(|l| inv.theta[(k, l)]).collect::<Vec<_>>()
        )?;
    }
    let diag = |m: &ffr::runtime::nalgebra::DMatrix<f64>| {
        (0..m.nrows()).map(|i| m[(i, i)]).collect::<Vec<_>>()
    };
    crate::outln!("diag m_ff = {:?}", diag(&inv.m_ff))?;
    crate::outln!("diag K_ff = {:?}", diag(&inv.k_ff))
}

/// Whether `s` names a built-in shape.
pub fn is_builtin_shape(s: &str) -> bool {
    Shape::builtin(s).is_some()
}
