//! The flexible slider-crank of Simeon's IVP test-set problem: midpoint
//! deflection of the connecting rod (compiled beam2 kernels), slider on a
//! prismatic joint, against the published solution at t = 0.1 s.
//!
//! `cargo run --release --example slider_crank -- --elements 8 --dt 5e-5 --csv results/slider_crank.csv`

use clap::Parser;
use ffr_cli::benchmarks::slider_crank::{self, SliderCrankArgs};

#[derive(Parser, Debug)]
#[command(about = "Flexible slider-crank (Simeon) with a compiled beam2 rod")]
struct Cli {
    #[command(flatten)]
    args: SliderCrankArgs,
}

fn main() {
    let cli = Cli::parse();
    if let Err(e) = slider_crank::run(&cli.args) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
