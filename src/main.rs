//! The `scm` binary: parse the command line, run the stage, turn errors into one line and an exit code.

mod cli;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = cli::args::Cli::parse();
    match cli::run(&cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("scm: error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
