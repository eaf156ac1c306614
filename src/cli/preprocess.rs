//! `scm preprocess`: its flags lowered into [`PreprocessOptions`], the stage, its summary.

use super::args::{Cli, PreprocessArgs, ShapeArgs};
use super::common::{bad_flag, print_json};
use super::output::outln;
use super::progress;
use scm::error::Result;
use scm::preprocess::{PreprocessOptions, PreprocessReport, preprocess};
use scm::robot::PackagePaths;
use scm::shapes::{DecompParams, ShapeParams};
use std::path::Path;

/// `scm preprocess`: build the six shape representations into the URDD.
pub fn run_preprocess(cli: &Cli, args: &PreprocessArgs) -> Result<()> {
    let opts = preprocess_options(&args.urdf, &args.output, &args.shapes, args.force)?;
    let report = preprocess(&opts, &progress::Bar::new(cli.quiet))?;
    if cli.json {
        print_json(&report)
    } else {
        print_preprocess(cli, &report);
        Ok(())
    }
}

/// Lowers the preprocess flags into library options.
pub fn preprocess_options(
    urdf: &Path,
    out: &Path,
    shapes: &ShapeArgs,
    force: bool,
) -> Result<PreprocessOptions> {
    let mut packages = PackagePaths::from_env();
    for entry in &shapes.package_paths {
        let (name, dir) = PackagePaths::parse_entry(entry).ok_or_else(|| {
            bad_flag(
                "--package-path",
                format!("expected NAME=DIR, got \"{entry}\""),
            )
        })?;
        packages.insert(name, dir);
    }
    Ok(PreprocessOptions {
        urdf: urdf.to_path_buf(),
        out: out.to_path_buf(),
        packages,
        visual_fallback: shapes.visual_fallback,
        params: ShapeParams {
            max_hull_vertices: shapes.max_hull_vertices as usize,
            decomposition: DecompParams {
                resolution: shapes.decomp_resolution,
                max_pieces: shapes.max_pieces,
                ..DecompParams::default()
            },
        },
        force,
    })
}

/// Prints the preprocess summary (notes on stderr); nothing with `--quiet`.
pub fn print_preprocess(cli: &Cli, r: &PreprocessReport) {
    if cli.quiet {
        return;
    }
    for w in &r.warnings {
        eprintln!("note: {w}");
    }
    if r.up_to_date {
        outln!(
            "{}: preprocess up to date (robot \"{}\"), nothing to do",
            r.urdd.display(),
            r.robot
        );
        return;
    }
    let counts: Vec<String> = r.shapes.iter().map(|(t, n)| format!("{t} {n}")).collect();
    outln!(
        "{}: robot \"{}\", {} links ({} with geometry), {} DOFs; shapes: {}",
        r.urdd.display(),
        r.robot,
        r.links,
        r.links_with_geometry,
        r.dofs,
        counts.join(", ")
    );
}
