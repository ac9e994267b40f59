//! The spin-up beam of Kane, Ryan & Banerjee (1987): a cantilever clamped to
//! a hub whose angle is prescribed (theory sheet), run end to end with a
//! summary, a CSV and an SVG plot. The main job of `cargo run --release` and
//! the example `spin_up_beam`.

use crate::codegen::{BodySpec, Options, ParamValues, Reference, Shape};
use crate::evaluated::EvaluatedBody;
use crate::output;
use crate::runtime::scenes::{self, SpinUp, SpinUpResult};
use clap::{Args, ValueEnum};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Beam data of the benchmark (SI units).
pub const KRB: ParamValues = ParamValues {
    length: 8.0,
    rho: 2766.67,
    area: 7.2968e-5,
    iy: 8.2189e-9,
    iz: 8.2189e-9,
    e: 6.8952e10,
    g: 2.6e10,
    j: 1.6438e-8,
};

/// On or off.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Switch {
    /// On.
    On,
    /// Off.
    Off,
}

/// Options of a spin-up run.
#[derive(Args, Debug, Clone)]
pub struct SpinUpArgs {
    /// Final spin rate ω_s (rad/s).
    #[arg(long, default_value_t = 4.0)]
    pub omega: f64,
    /// Number of beam2 elements of the 8 m beam (1 to 256).
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u16).range(1..=256))]
    pub elements: u16,
    /// Geometric stiffening.
    #[arg(long, value_enum, default_value_t = Switch::On)]
    pub stiffening: Switch,
    /// End time (s).
    #[arg(long, default_value_t = 20.0)]
    pub t_end: f64,
    /// Time step (s).
    #[arg(long, default_value_t = 0.01)]
    pub dt: f64,
    /// Where to write `t,tip_axial,tip_transverse` (default: results/spin_up_….csv).
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Where to write the SVG plot (default: next to the CSV).
    #[arg(long)]
    pub svg: Option<PathBuf>,
}

impl Default for SpinUpArgs {
    fn default() -> Self {
        Self {
            omega: 4.0,
            elements: 8,
            stiffening: Switch::On,
            t_end: 20.0,
            dt: 0.01,
            csv: None,
            svg: None,
        }
    }
}

/// What a run produced.
pub struct Report {
    /// The trajectory of the tip.
    pub result: SpinUpResult,
    /// Steps taken.
    pub steps: usize,
    /// Wall time of the simulation (s).
    pub wall: f64,
    /// CSV written.
    pub csv: PathBuf,
    /// SVG written.
    pub svg: PathBuf,
}

/// Check the options, run, write the CSV and SVG, and print a summary.
pub fn run(args: &SpinUpArgs) -> Result<Report, Box<dyn std::error::Error>> {
    for (name, v) in [
        ("--omega", args.omega),
        ("--t-end", args.t_end),
        ("--dt", args.dt),
    ] {
        if !v.is_finite() || v <= 0.0 {
            return Err(format!("{name} must be a positive number, found {v}").into());
        }
    }
    if args.dt > args.t_end {
        return Err(format!("--dt {} is longer than --t-end {}", args.dt, args.t_end).into());
    }
    let stiff = args.stiffening == Switch::On;
    let tag = format!(
        "spin_up_omega{}_n{}_{}",
        args.omega,
        args.elements,
        if stiff { "stiff" } else { "linear" }
    );
    let csv = args
        .csv
        .clone()
        .unwrap_or_else(|| PathBuf::from("results").join(format!("{tag}.csv")));
    let svg = args
        .svg
        .clone()
        .unwrap_or_else(|| csv.with_extension("svg"));
    // Refuse unusable outputs before the run, not after it.
    output::check_file_path(&csv, "--csv")?;
    output::check_file_path(&svg, "--svg")?;
    let svg_flag = if args.svg.is_some() {
        "--svg"
    } else {
        "the plot (by default the CSV path with extension .svg)"
    };
    output::check_distinct(&[("--csv", &csv), (svg_flag, &svg)])?;

    let spec = BodySpec::new(
        Shape::resolve("beam2", None)?,
        args.elements as usize,
        Reference::Clamped,
    )?;
    let body = EvaluatedBody::new(&spec, Options { stiffening: stiff }, KRB)?;
    let mut cfg = SpinUp::new(args.omega);
    cfg.t_end = args.t_end;
    cfg.dt = args.dt;
    cfg.stiffening = stiff;
    let t0 = Instant::now();
    let result = scenes::spin_up(Box::new(body), None, &cfg)?;
    let wall = t0.elapsed().as_secs_f64();
    let steps = result.t.len().saturating_sub(1);

    write_csv(&csv, &result)?;
    crate::plot::tip_plot(
        &svg,
        &format!(
            "KRB spin-up, ω_s = {} rad/s, {} elements, stiffening {}",
            args.omega,
            args.elements,
            if stiff { "on" } else { "off" }
        ),
        &result,
    )?;

    println!(
        "spin-up beam (Kane, Ryan & Banerjee 1987): L = 8 m, ω_s = {} rad/s, T = 15 s, {} beam2 elements, stiffening {}",
        args.omega,
        args.elements,
        if stiff { "on" } else { "off" }
    );
    if let Some((t, y)) = result.min_transverse() {
        println!("peak tip deflection (hub frame): {y:.4} m at t = {t:.2} s");
    }
    if let Some(last) = result.tip_transverse.last() {
        println!(
            "final tip deflection: {last:.4} m at t = {:.2} s",
            result.t.last().copied().unwrap_or(0.0)
        );
    }
    if let Some(d) = &result.diverged {
        println!("DIVERGED at t = {:.2} s: {}", d.t, d.reason);
        if !stiff {
            println!("  (expected: the linear FFR model softens above its first bending frequency; try --stiffening on)");
        }
    }
    println!(
        "steps: {steps} of dt = {} s, wall time {wall:.3} s",
        args.dt
    );
    println!("wrote {} and {}", csv.display(), svg.display());
    Ok(Report {
        result,
        steps,
        wall,
        csv,
        svg,
    })
}

/// `t,tip_axial,tip_transverse`, numbers in shortest round-trip form,
/// written atomically.
fn write_csv(path: &Path, r: &SpinUpResult) -> Result<(), output::OutputError> {
    let mut s = String::from("t,tip_axial,tip_transverse\n");
    for i in 0..r.t.len() {
        s.push_str(&format!(
            "{},{},{}\n",
            output::number(r.t[i]),
            output::number(r.tip_axial[i]),
            output::number(r.tip_transverse[i])
        ));
    }
    output::write_atomic(path, s.as_bytes())
}
