//! The spin-up beam benchmark (Kane, Ryan & Banerjee 1987).
//!
//! `cargo run --release --example spin_up_beam -- --omega 10 --stiffening off`
//!
//! Writes `t,tip_axial,tip_transverse` (tip displacement in the rotating hub
//! frame, metres) to `--csv` and an SVG plot next to it.

use clap::Parser;
use std::process::ExitCode;

/// Spin-up beam: prescribed hub angle, cantilever of 8 m.
#[derive(Parser)]
struct Cli {
    #[command(flatten)]
    args: ffr_cli::cli::SpinUpArgs,
}

fn main() -> ExitCode {
    match ffr_cli::cli::spin_up(&Cli::parse().args) {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
