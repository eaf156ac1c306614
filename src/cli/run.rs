//! `scm run`: the three stages in one call, lowered and printed by their own modules.

use super::args::{Cli, RunArgs};
use super::common::{print_json, to_json};
use super::export::{export_options, print_export};
use super::preprocess::{preprocess_options, print_preprocess};
use super::progress;
use super::sample::{print_sample, sample_options};
use scm::error::Result;
use scm::export::export;
use scm::preprocess::preprocess;
use scm::sample::sample;

/// `scm run`: preprocess, sample, export; each stage does nothing when up to date.
pub fn run_all(cli: &Cli, args: &RunArgs) -> Result<()> {
    let pre = preprocess_options(&args.urdf, &args.output, &args.shapes, args.force)?;
    let sampling = sample_options(&args.output, &args.sampling, args.force)?;
    let exporting = export_options(&args.output, None, &args.export, args.force);
    let bar = progress::Bar::new(cli.quiet);
    let pre_report = preprocess(&pre, &bar)?;
    let sample_report = sample(&sampling, &bar)?;
    let export_report = export(&exporting, &bar)?;
    if cli.json {
        // One object keyed by stage; serde_json's Map sorts its keys, the reports' fields included.
        let mut all = serde_json::Map::new();
        all.insert("preprocess".into(), to_json(&pre_report)?);
        all.insert("sample".into(), to_json(&sample_report)?);
        all.insert("export".into(), to_json(&export_report)?);
        print_json(&all)
    } else {
        print_preprocess(cli, &pre_report);
        print_sample(cli, &sample_report);
        print_export(cli, &export_report);
        Ok(())
    }
}
