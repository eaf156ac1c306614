//! `scm import-moveit` and `scm diff`: store a MoveIt SRDF, compare scm's verdicts with it, and the
//! comparison printing both share.

use super::args::{Cli, DiffArgs, ImportMoveitArgs};
use super::common::{print_json, to_json};
use super::output::{out, outln};
use scm::diff::{Comparison, DiffOptions, WitnessJoints, diff, format_comparison_with};
use scm::error::Result;
use scm::import::{ImportOptions, ImportReport, import_moveit};
use std::path::Path;

/// `scm import-moveit`: store an SRDF as the imported layer (and optionally compare).
pub fn run_import(cli: &Cli, args: &ImportMoveitArgs) -> Result<()> {
    let report = import_moveit(&ImportOptions {
        srdf: args.srdf.clone(),
        urdd: args.urdd.clone(),
    })?;
    let comparison = if args.compare {
        Some(diff(&DiffOptions {
            urdd: args.urdd.clone(),
            srdf: None,
            link_level: args.link_level,
        })?)
    } else {
        None
    };
    if cli.json {
        // One object, keys sorted by serde_json's Map, the reports' fields included.
        let mut both = serde_json::Map::new();
        both.insert("import".into(), to_json(&report)?);
        both.insert("compare".into(), to_json(&comparison)?);
        return print_json(&both);
    }
    print_import(cli, &report);
    if let Some(c) = comparison {
        print_comparison(&c, &args.urdd, WitnessJoints::Path);
    }
    Ok(())
}

/// `scm diff`: scm's verdicts against MoveIt's.
pub fn run_diff(cli: &Cli, args: &DiffArgs) -> Result<()> {
    let c = diff(&DiffOptions {
        urdd: args.urdd.clone(),
        srdf: args.srdf.clone(),
        link_level: args.link_level,
    })?;
    if cli.json {
        return print_json(&c);
    }
    let joints = if args.full_witness {
        WitnessJoints::All
    } else {
        WitnessJoints::Path
    };
    print_comparison(&c, &args.urdd, joints);
    Ok(())
}

/// Prints what the import read and stored (its warnings on stderr unless `--quiet`).
fn print_import(cli: &Cli, report: &ImportReport) {
    if !cli.quiet {
        for w in &report.warnings {
            eprintln!("warning: {w}");
        }
    }
    let reasons: Vec<String> = report
        .reasons
        .iter()
        .map(|(r, n)| format!("{} {n}", if r.is_empty() { "(none)" } else { r }))
        .collect();
    let read: usize = report.reasons.values().sum();
    outln!(
        "{}: read {read} <disable_collisions> from {} ({}), {} <enable_collisions>, {} \
         <disable_default_collisions>; stored {} distinct link pairs{}",
        report.urdd.display(),
        report.srdf.display(),
        reasons.join(", "),
        report.enabled,
        report.default_disabled,
        report.stored,
        match report.warnings.len() {
            0 => String::new(),
            n => format!(" ({n} warnings: unknown links, links without geometry or repeats)"),
        }
    );
}

/// Prints the comparison report, each witness on the given `joints`.
fn print_comparison(c: &Comparison, urdd: &Path, joints: WitnessJoints) {
    out!("{}", format_comparison_with(c, urdd, joints));
}
