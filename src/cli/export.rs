//! `scm export`: its flags lowered into [`ExportOptions`], the stage, its summary.

use super::args::{Cli, ExportArgs, ExportFlags};
use super::common::print_json;
use super::output::outln;
use super::progress;
use scm::error::Result;
use scm::export::{ExportOptions, ExportReport, export};
use std::path::{Path, PathBuf};

/// `scm export`: write the matrices and the consumer files.
pub fn run_export(cli: &Cli, args: &ExportArgs) -> Result<()> {
    let opts = export_options(&args.urdd, args.output.clone(), &args.export, args.force);
    let report = export(&opts, &progress::Bar::new(cli.quiet))?;
    if cli.json {
        print_json(&report)
    } else {
        print_export(cli, &report);
        Ok(())
    }
}

/// Lowers the export flags into library options.
pub fn export_options(
    urdd: &Path,
    out: Option<PathBuf>,
    e: &ExportFlags,
    force: bool,
) -> ExportOptions {
    let mut opts = ExportOptions::new(urdd);
    opts.out = out;
    if !e.format.is_empty() {
        let mut formats = e.format.clone();
        formats.sort();
        formats.dedup();
        opts.formats = formats;
    }
    opts.link_type = e.link_type;
    opts.require_certified = e.require_certified;
    opts.sphere_type = e.sphere_type;
    opts.merge_into = e.merge_into.clone();
    opts.force = force;
    opts
}

/// Prints the export summary: the link level, then one line per type (notes on stderr); nothing
/// with `--quiet`.
pub fn print_export(cli: &Cli, r: &ExportReport) {
    if cli.quiet {
        return;
    }
    if r.up_to_date {
        outln!("{}: export up to date, nothing to do", r.out.display());
        return;
    }
    for n in &r.notes {
        eprintln!("note: {n}");
    }
    let reasons: Vec<String> = r
        .link_reasons
        .iter()
        .map(|(reason, n)| format!("{reason} {n}"))
        .collect();
    outln!(
        "{}: {} files; link level ({}): {} of {} link pairs skipped ({})",
        r.out.display(),
        r.files.len(),
        r.link_level,
        r.link_pairs.0,
        r.link_pairs.1,
        reasons.join(", ")
    );
    for (t, c) in &r.types {
        let layers: Vec<String> = c.layers.iter().map(|(l, n)| format!("{l} {n}")).collect();
        outln!(
            "  {:<13} {:>4} shapes: {} skipped, {} checked ({})",
            t.id(),
            c.shapes,
            c.skipped,
            c.checked,
            layers.join(", ")
        );
    }
}
