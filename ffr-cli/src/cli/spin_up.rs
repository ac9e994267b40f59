//! `ffr spin-up` (and `ffr` alone): the spin-up beam of Kane, Ryan and
//! Banerjee from the command line.

use super::args::{IntegratorKind, ReductionKind};
use super::run::{check_finite_columns, retries};
use crate::benchmarks::spin_up::{SpinUp, SpinUpResult, KRB};
use crate::output;
use clap::{Args, Parser};
use ffr::modal::ModalSettings;
use ffr::runtime::spec::{Formalism, Params, Stiffening};
use ffr::runtime::{GeneralizedAlpha, Integrator, Rk4Baumgarte};
use std::path::PathBuf;

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
    /// Run the kernels on tapes instead of the compiled code (comparisons);
    /// with --modes, the modal body's generated inertia kernels on tapes.
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
pub(super) fn outputs(
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
    // The geometrically exact reference the error is reported against, where
    // there is one for this spin rate: its transverse tip history over the
    // run's.
    let reference = crate::reference::spin_up(args.omega);
    let overlay: Vec<crate::plot::TimedSeries> = reference
        .as_ref()
        .and_then(|r| {
            Some((
                "reference tip_transverse",
                &r.t[..],
                r.column("tip_transverse")?,
            ))
        })
        .into_iter()
        .collect();
    let plot = crate::plot::time_svg_with(
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
        &overlay,
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
    if let Some(reference) = reference.filter(|_| r.diverged.is_none()) {
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
        "steps: {} of dt = {} s, {} Newton iterations, {} iteration matrices{}, wall time {:.3} s, CPU time {:.3} s",
        r.steps,
        args.dt,
        r.newton_iterations,
        r.jacobians,
        retries(r.restarts, r.splits),
        r.wall,
        r.cpu
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
