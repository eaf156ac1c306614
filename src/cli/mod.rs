//! The thin command-line layer: one module per subcommand, each lowering its flags (defined in
//! [`args`]) into the library stage's options, calling the stage and printing its result; this file
//! only dispatches.

pub mod args;
mod bench;
mod common;
mod export;
mod import;
mod inspect;
mod output;
mod preprocess;
mod progress;
mod run;
mod sample;
mod view;

use args::{Cli, Command};
use scm::error::Result;

/// Runs the parsed command line.
pub fn run(cli: &Cli) -> Result<()> {
    match &cli.command {
        Command::Preprocess(args) => preprocess::run_preprocess(cli, args),
        Command::Sample(args) => sample::run_sample(cli, args),
        Command::Export(args) => export::run_export(cli, args),
        Command::ImportMoveit(args) => import::run_import(cli, args),
        Command::Diff(args) => import::run_diff(cli, args),
        Command::Run(args) => run::run_all(cli, args),
        Command::Inspect(args) => inspect::run_inspect(cli, args),
        Command::View(args) => view::run_view(args),
        Command::Bench(args) => bench::run_bench(cli, args),
    }
}
