use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = ffr::cli::Cli::parse();
    match ffr::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
