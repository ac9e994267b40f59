//! A free flexible pendulum under gravity, pinned at one end, no damping:
//! energy drift and constraint violation.
//!
//! `cargo run --release --example pendulum -- --beam beam3 --dt 5e-4`

use clap::Parser;
use std::process::ExitCode;

/// Flexible pendulum (generated beam2 or beam3 body).
#[derive(Parser)]
struct Cli {
    #[command(flatten)]
    args: ffr::pendulum::PendulumArgs,
}

fn main() -> ExitCode {
    match ffr::pendulum::run_and_print(&Cli::parse().args) {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
