//! `scm bench`: its flags lowered into [`BenchOptions`] (or [`ScaleOptions`] with `--scale`), the
//! measurement, its tables.

use super::args::{self, BenchArgs, Cli};
use super::common::{bad_flag, print_json};
use super::output::{out, outln};
use super::progress;
use scm::bench::{BenchOptions, BenchReport, ScaleOptions, bench, render_scale, scale};
use scm::error::{Error, Result};
use scm::robot::PackagePaths;

/// `scm bench`: time queries with and without skips, and check the skips against the meshes; with
/// `--scale`, the scale table instead.
pub fn run_bench(cli: &Cli, args: &BenchArgs) -> Result<()> {
    if args.scale {
        return run_scale(cli, args);
    }
    let opts = bench_options(args)?;
    let report = bench(&opts, &progress::Bar::new(cli.quiet))?;
    if cli.json {
        print_json(&report)
    } else {
        print_bench(&report);
        Ok(())
    }
}

/// `scm bench --scale`: sample every robot in child processes of this executable and print the scale
/// table.
fn run_scale(cli: &Cli, args: &BenchArgs) -> Result<()> {
    let exe = std::env::current_exe().map_err(|e| Error::Failed {
        context: "--scale".into(),
        message: format!("cannot find the scm executable to run: {e}"),
    })?;
    let mut opts = ScaleOptions::new(&args.urdd, &exe);
    if let Some(n) = args.samples {
        opts.samples = n;
    }
    if let Some(r) = args.runs {
        opts.runs = r;
    }
    opts.work = args.output.clone();
    opts.packages = PackagePaths::from_env();
    let report = scale(&opts, &progress::Bar::new(cli.quiet))?;
    if cli.json {
        print_json(&report)
    } else {
        out!("{}", render_scale(&report));
        Ok(())
    }
}

/// Lowers the bench flags into library options (library defaults where a flag is absent).
fn bench_options(args: &BenchArgs) -> Result<BenchOptions> {
    let [urdd] = args.urdd.as_slice() else {
        return Err(bad_flag(
            "DIR",
            format!(
                "one URDD directory expected, got {} (several robots need --scale)",
                args.urdd.len()
            ),
        ));
    };
    let mut opts = BenchOptions::new(urdd);
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
