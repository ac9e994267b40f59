//! The `ffr` command line: the commands ([`Command`]) and their dispatch
//! ([`run`]); one file per command beside this one.

mod args;
mod emit;
mod fatigue;
mod fmu;
mod invariants;
mod linearize;
mod modes;
mod run;
mod spin_up;
mod statics;

pub use args::{
    BodyArgs, ExportFormat, IntegratorKind, KernelArgs, ParamArgs, ReductionKind, SceneBodyArgs,
};
pub use fatigue::{fatigue, FatigueArgs};
pub use fmu::{fmu, FmuArgs, FmuWritten};
pub use invariants::invariants_json;
pub use linearize::{
    campbell, campbell_json, campbell_svg, linear_json, linearize, matrix_market, CampbellArgs,
    LinearizeArgs,
};
pub use modes::{export, modes, modes_json, reducible};
pub(crate) use run::check_finite_columns;
pub use run::{run_scene, MAX_ECHO_CHARS};
pub use spin_up::{spin_up, SpinUpArgs};
pub use statics::{static_json, static_scene, StaticArgs};

use crate::output;
use clap::{Parser, Subcommand};
use ffr::codegen::limits::check_literals;
use ffr::codegen::sanitize::check_type_name;
use ffr::codegen::{generate_kernels, BodySpec, EmitOptions, Shape};
use ffr::runtime::spec::Reference;
use invariants::print_summary;
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
        #[command(flatten)]
        from_scene: SceneBodyArgs,
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
        #[command(flatten)]
        from_scene: SceneBodyArgs,
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
        /// Write each mode as a ParaView animation over one period into DIR
        /// (DIR/NAME_modeJ.pvd; largest node displacement 10 % of the body's
        /// length, an FE body's nodes' bounding box's longest side; see
        /// docs/vtk.md).
        #[arg(long, value_name = "DIR")]
        vtk: Option<PathBuf>,
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
        /// Take the body from a scene file (a beam, or an FE body: then
        /// `--boundary` names FE nodes).
        #[command(flatten)]
        from_scene: SceneBodyArgs,
    },
    /// Run the spin-up beam benchmark (the main job).
    SpinUp(SpinUpArgs),
    /// A scene's linear model `ẋ = A x + B u`, `y = C x + D u` about a state
    /// (independent coordinates on the constraint manifold), with its
    /// eigenvalues; see docs/linear.md.
    Linearize(LinearizeArgs),
    /// The static equilibrium under a scene's loads at t = 0 (gravity,
    /// forces, motor torques; drives held), by Newton with load increments,
    /// and its outputs there; see docs/static.md.
    Static(StaticArgs),
    /// A Campbell diagram: a scene's frequencies while its driven revolute
    /// joint turns at constant speeds (steady deformed state, gyroscopic
    /// terms); see docs/linear.md.
    Campbell(CampbellArgs),
    /// Work-precision report of the benchmark scenes (report.md, points.csv,
    /// one SVG per scene; see docs/report.md).
    Report(crate::report::ReportArgs),
    /// A scene over parameter axes (lists, ranges, seeded samples): the
    /// figures of every case in DIR/results.csv and a plot, on every local
    /// core or a Dask cluster (exits non-zero if a case failed; see
    /// docs/sweep.md).
    Sweep(crate::sweep::SweepArgs),
    /// Stiff and extreme cases, each with its check (stability.md; exits
    /// non-zero if a case fails; see docs/stability.md).
    Stability(crate::stability::StabilityArgs),
    /// Damage-equivalent loads of a column of a `ffr run --csv` file
    /// (rainflow counting, ASTM E1049-85; DEL_m = (Σ n_i S_i^m / N_eq)^(1/m),
    /// N_eq = T / t_eq), by the Python package's `ffr.fatigue` (needs
    /// Python with `ffr` and `rainflow`); see docs/fatigue.md.
    Fatigue(FatigueArgs),
    /// The scene as an FMI 2.0 Co-Simulation unit (NAME.fmu, Linux
    /// x86-64): its inputs, outputs and --parameter keys as variables, the
    /// scene's step per communication step; see docs/in-the-loop.md.
    Fmu(FmuArgs),
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
        /// Write a ParaView time series into DIR: DIR/SCENE.pvd and one VTK
        /// XML PolyData file (.vtp) per written step (see docs/vtk.md).
        #[arg(long, value_name = "DIR")]
        vtk: Option<PathBuf>,
        /// With --vtk: write every K-th step (the initial state always); at
        /// most 10000 step files.
        #[arg(long, value_name = "K", requires = "vtk", default_value_t = 1,
              value_parser = clap::value_parser!(u64).range(1..))]
        every: u64,
        /// A reference history (CSV: `t,NAME,…`): its columns named like
        /// the scene's outputs are drawn over them in the plot, and the
        /// largest difference of each is printed.
        #[arg(long, value_name = "FILE.csv")]
        reference: Option<PathBuf>,
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
        /// With --elements: also emit `<TYPE>Modal`, the body reduced to this
        /// many normal modes at the parameter flags' values (the basis and
        /// projected invariants baked in; docs/modal.md).
        #[arg(long, requires = "elements", conflicts_with = "scene")]
        modes: Option<usize>,
        /// With --modes: leave out the static modes (by default they are
        /// added, as in a scene file: inertia loads and, with stiffening, the
        /// modal derivatives).
        #[arg(long, requires = "modes")]
        no_static_modes: bool,
        /// With --modes: Craig–Bampton with these boundary nodes
        /// (comma-separated) instead of modal truncation.
        #[arg(long, value_delimiter = ',', requires = "modes")]
        boundary: Vec<usize>,
        /// The parameters of a modal body (--modes only).
        #[command(flatten)]
        params: ParamArgs,
    },
}

/// Run a parsed command line.
pub fn run(cli: Cli) -> Result<(), Box<dyn std::error::Error>> {
    match cli.command {
        Some(Command::Invariants {
            from_scene:
                SceneBodyArgs {
                    scene: Some(path),
                    body_name: Some(name),
                },
            json,
            ..
        }) => {
            let scene = ffr::scene::load(&path)?;
            let b = ffr::invariants::of_scene_body(&scene, &name)?;
            if json {
                crate::outln!(
                    "{}",
                    serde_json::to_string(&invariants_json(&b.invariants, &b.dofs))?
                )?;
            } else {
                print_summary(&b.description, &b.invariants, &b.dofs)?;
            }
            Ok(())
        }
        Some(Command::Invariants {
            body, params, json, ..
        }) => {
            let beam = body.beam(params.values())?;
            let b = ffr::invariants::of_beam(&beam)?;
            if json {
                crate::outln!(
                    "{}",
                    serde_json::to_string(&invariants_json(&b.invariants, &b.dofs))?
                )?;
            } else {
                print_summary(&b.description, &b.invariants, &b.dofs)?;
            }
            Ok(())
        }
        Some(Command::Emit {
            kernel,
            elements,
            reference,
            scene,
            type_name,
            modes,
            no_static_modes,
            boundary,
            params,
        }) => {
            check_type_name(&type_name, "--type-name")?;
            if modes.is_none() && params.values() != ParamArgs::parse_defaults().values() {
                return Err("the parameter flags of `ffr emit` set a modal body's parameters: give them with --modes".into());
            }
            let text = match (&scene, elements) {
                (None, Some(n)) if modes.is_some() => {
                    let settings = ffr::modal::ModalSettings {
                        modes: modes.unwrap_or_default(),
                        boundary,
                        static_modes: !no_static_modes,
                        damping: Vec::new(),
                    };
                    emit::modal_body(
                        &kernel, n as usize, reference, &params, &settings, &type_name,
                    )?
                }
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
            from_scene,
            count,
            boundary,
            json,
            vtk,
        }) => modes(
            &body,
            &params,
            &from_scene,
            count,
            &boundary,
            json,
            vtk.as_deref(),
        ),
        Some(Command::Export {
            format,
            body,
            params,
            modes,
            boundary,
            out,
            from_scene,
        }) => export(format, &body, &params, &from_scene, modes, &boundary, &out),
        Some(Command::SpinUp(args)) => spin_up(&args).map(|_| ()),
        Some(Command::Linearize(args)) => linearize(&args).map(|_| ()),
        Some(Command::Campbell(args)) => campbell(&args).map(|_| ()),
        Some(Command::Static(args)) => static_scene(&args).map(|_| ()),
        Some(Command::Fmu(args)) => fmu(&args).map(|_| ()),
        Some(Command::Report(args)) => crate::report::run(&args).map(|_| ()),
        Some(Command::Sweep(args)) => crate::sweep::run(&args).map(|_| ()),
        Some(Command::Stability(args)) => crate::stability::run(&args).map(|_| ()),
        Some(Command::Fatigue(args)) => fatigue(&args),
        Some(Command::Run {
            scene,
            csv,
            svg,
            general,
            vtk,
            every,
            reference,
        }) => {
            let vtk = vtk.map(|dir| ffr::scene::vtk::VtkOptions {
                dir,
                every: usize::try_from(every).unwrap_or(usize::MAX),
            });
            run_scene(&scene, &csv, &svg, general, vtk, reference.as_deref()).map(|_| ())
        }
        None => spin_up(&SpinUpArgs::default()).map(|_| ()),
    }
}

/// Whether `s` names a built-in shape.
pub fn is_builtin_shape(s: &str) -> bool {
    Shape::builtin(s).is_some()
}
