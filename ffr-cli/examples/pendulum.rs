//! A free flexible pendulum under gravity, pinned at one end, no damping:
//! energy drift and constraint violation (compiled beam kernels).
//!
//! `cargo run --release --example pendulum -- --beam beam3 --dt 5e-4 --rho-inf 0.9`

use clap::Parser;
use std::process::ExitCode;

/// Flexible pendulum (compiled beam2 or beam3 kernels).
#[derive(Parser)]
struct Cli {
    #[command(flatten)]
    args: ffr_cli::benchmarks::pendulum::PendulumArgs,
}

fn main() -> ExitCode {
    match ffr_cli::benchmarks::pendulum::run_and_print(&Cli::parse().args) {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
