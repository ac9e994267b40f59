//! A free-floating flexible body with no forces: round-off check of the
//! momentum rates of the equations of motion at random states, and the drift
//! of linear and angular momentum along a trajectory (integrator accuracy).
//!
//! `cargo run --release --example free_floating -- --beam beam3 --method rk4 --dt 1e-4 --study`

use clap::Parser;
use ffr_cli::benchmarks::free_floating::{
    check_rates, describe, drift_study, FreeFloatingArgs, StateScales,
};
use std::process::ExitCode;

/// Free-floating flexible beam (compiled beam2 or beam3 kernels).
#[derive(Parser)]
struct Cli {
    #[command(flatten)]
    args: FreeFloatingArgs,
    /// Random states for the round-off check of ṗ and Ḣ.
    #[arg(long, default_value_t = 20)]
    states: usize,
    /// Also run dt/2 and dt/4 and print the observed orders of the drift.
    #[arg(long)]
    study: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let a = &cli.args;
    println!("{}", describe(a));
    let run = || -> Result<(), Box<dyn std::error::Error>> {
        for stiff in [false, true] {
            let c = check_rates(
                a.beam,
                a.elements as usize,
                stiff,
                &if stiff {
                    StateScales::elastic()
                } else {
                    StateScales::default()
                },
                cli.states,
                1,
            )?;
            println!(
                "equations of motion ({}): {} random states, max |ṗ|/scale = {:.2e}, max |Ḣ|/scale = {:.2e} (round-off); without the velocity terms: {:.2e}, {:.2e}",
                if stiff { "E, G of the bar" } else { "K_ff ≈ 0" },
                c.states,
                c.worst_p,
                c.worst_h,
                c.without_qv.0,
                c.without_qv.1
            );
            println!(
                "  rate formulas vs central differences of the runtime's momenta: {:.1e}, {:.1e}",
                c.formula_vs_differences.0, c.formula_vs_differences.1
            );
        }
        let steps: Vec<f64> = if cli.study {
            vec![a.dt, a.dt / 2.0, a.dt / 4.0]
        } else {
            vec![a.dt]
        };
        let study = drift_study(a, &steps)?;
        for d in &study.runs {
            println!(
                "trajectory ({:?}, dt = {} s, ω_max·dt = {:.2}, {} steps, {:.3} s wall): max |Δp|/|p₀| = {:.2e}, max |ΔH|/|H₀| = {:.2e}, max |ΔE|/E₀ = {:.2e} (integration error, O(dt^{}))",
                a.method,
                d.dt,
                d.omega_max_dt.1,
                d.steps,
                d.wall,
                d.dp,
                d.dh,
                d.de,
                a.method.order()
            );
        }
        if cli.study {
            println!(
                "observed orders of the drift of (p, H): {:.2?}",
                study.orders
            );
        }
        Ok(())
    };
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
