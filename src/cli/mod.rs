//! The thin command-line layer: parse flags, call one library stage per subcommand, print results.

pub mod args;
mod progress;

use args::{Cli, Command, PreprocessArgs, ViewArgs};
use scm::error::{Error, Result};
use scm::preprocess::{PreprocessOptions, PreprocessReport, preprocess};
use scm::robot::PackagePaths;
use scm::shapes::{DecompParams, ShapeParams};
use std::path::{Path, PathBuf};

/// Runs the parsed command line.
pub fn run(cli: &Cli) -> Result<()> {
    match &cli.command {
        Command::Preprocess(args) => run_preprocess(cli, args),
        Command::View(args) => run_view(args),
    }
}

/// `scm preprocess`: build the six shape representations into the URDD.
fn run_preprocess(cli: &Cli, args: &PreprocessArgs) -> Result<()> {
    let mut packages = PackagePaths::new();
    for entry in &args.package_paths {
        let (name, dir) = PackagePaths::parse_entry(entry).ok_or_else(|| {
            Error::input(
                Path::new("command line"),
                "--package-path",
                format!("expected NAME=DIR, got \"{entry}\""),
            )
        })?;
        packages.insert(name, dir);
    }
    let opts = PreprocessOptions {
        urdf: args.urdf.clone(),
        out: args.output.clone(),
        packages,
        params: ShapeParams {
            max_hull_vertices: args.max_hull_vertices as usize,
            decomposition: DecompParams {
                resolution: args.decomp_resolution,
                max_pieces: args.max_pieces,
                ..DecompParams::default()
            },
        },
        force: args.force,
    };
    let bar = progress::Bar::new(cli.quiet);
    let report = preprocess(&opts, &bar)?;
    if !cli.quiet {
        for w in &report.warnings {
            eprintln!("note: {w}");
        }
    }
    print_report(cli, &report);
    Ok(())
}

fn print_report(cli: &Cli, r: &PreprocessReport) {
    if cli.json {
        println!("{}", serde_json::to_string_pretty(r).unwrap_or_default());
        return;
    }
    if cli.quiet {
        return;
    }
    if r.up_to_date {
        println!(
            "{}: up to date (robot \"{}\"), nothing to do",
            r.urdd.display(),
            r.robot
        );
        return;
    }
    let counts: Vec<String> = r.shapes.iter().map(|(t, n)| format!("{t} {n}")).collect();
    println!(
        "{}: robot \"{}\", {} links ({} with geometry), {} DOFs; shapes: {}",
        r.urdd.display(),
        r.robot,
        r.links,
        r.links_with_geometry,
        r.dofs,
        counts.join(", ")
    );
}

/// `scm view`: launch the viewer binary found next to this executable or on PATH.
fn run_view(args: &ViewArgs) -> Result<()> {
    scm::urdd::Urdd::open(&args.urdd)?;
    let viewer = find_viewer().ok_or_else(|| Error::Failed {
        context: "scm view".into(),
        message:
            "the viewer binary `scm-viewer` was not found next to scm or on PATH; build it with \
                  `cargo build --release -p scm-viewer` (it needs Bevy) and put it beside scm"
                .into(),
    })?;
    let status = std::process::Command::new(&viewer)
        .arg(&args.urdd)
        .status()
        .map_err(|e| Error::io(&viewer, e))?;
    if status.success() {
        Ok(())
    } else {
        Err(Error::Failed {
            context: "scm view".into(),
            message: format!("the viewer exited with {status}"),
        })
    }
}

fn find_viewer() -> Option<PathBuf> {
    let name = format!("scm-viewer{}", std::env::consts::EXE_SUFFIX);
    let beside = std::env::current_exe().ok()?.parent()?.join(&name);
    if beside.is_file() {
        return Some(beside);
    }
    std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|p| p.join(&name))
            .find(|p| p.is_file())
    })
}
