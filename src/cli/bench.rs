//! `scm bench`: its flags lowered into [`BenchOptions`], the measurement, its tables.

use super::args::{self, BenchArgs, Cli};
use super::common::{bad_flag, print_json};
use super::output::{out, outln};
use super::progress;
use scm::bench::{BenchOptions, BenchReport, bench};
use scm::error::Result;

/// `scm bench`: time queries with and without skips, and check the skips against the meshes.
pub fn run_bench(cli: &Cli, args: &BenchArgs) -> Result<()> {
    let opts = bench_options(args)?;
    let report = bench(&opts, &progress::Bar::new(cli.quiet))?;
    if cli.json {
        print_json(&report)
    } else {
        print_bench(&report);
        Ok(())
    }
}

/// Lowers the bench flags into library options (library defaults where a flag is absent).
fn bench_options(args: &BenchArgs) -> Result<BenchOptions> {
    let mut opts = BenchOptions::new(&args.urdd);
    if let Some(m) = args.configs {
        opts.configs = m as usize;
    }
    if let Some(r) = args.repeats {
        opts.repeats = r;
    }
    if let Some(m) = args.truth_configs {
        opts.truth_configs = m as usize;
    }
    if let Some(s) = args.seed {
        opts.seed = s;
    }
    for id in &args.types {
        let t = args::parse_shape_type(id.trim()).map_err(|m| bad_flag("--types", m))?;
        if !opts.types.contains(&t) {
            opts.types.push(t);
        }
    }
    opts.types.sort();
    Ok(opts)
}

/// Prints the tables and where they were written.
fn print_bench(r: &BenchReport) {
    out!("{}", scm::bench::render(r));
    outln!(
        "\nwrote {}",
        r.urdd.join(scm::bench::BENCH).join("bench.md").display()
    );
}
