//! `scm sample`: its flags lowered into [`SampleOptions`], the stage (one shard, a merge or all), its
//! summary.

use super::args::{Cli, SampleArgs, SamplingArgs};
use super::common::{bad_flag, print_json};
use super::output::outln;
use super::progress;
use scm::error::Result;
use scm::sample::{SampleOptions, SampleReport, Shard, merge_shards, sample};
use std::path::Path;

/// `scm sample`: sample joint space, or one shard of it, or merge shards.
pub fn run_sample(cli: &Cli, args: &SampleArgs) -> Result<()> {
    let mut opts = sample_options(&args.urdd, &args.sampling, args.force)?;
    opts.shard = match &args.shard {
        Some(s) => Some(Shard::parse(s).ok_or_else(|| {
            bad_flag(
                "--shard",
                format!("expected K/N with 0 <= K < N, got \"{s}\""),
            )
        })?),
        None => None,
    };
    let bar = progress::Bar::new(cli.quiet);
    let report = match args.merge_shards {
        Some(n) if n > 0 => merge_shards(&opts, n, &bar)?,
        Some(_) => return Err(bad_flag("--merge-shards", "must be at least 1".into())),
        None => sample(&opts, &bar)?,
    };
    if cli.json {
        print_json(&report)
    } else {
        print_sample(cli, &report);
        Ok(())
    }
}

/// Lowers the sampling flags into library options.
pub fn sample_options(urdd: &Path, s: &SamplingArgs, force: bool) -> Result<SampleOptions> {
    if !(s.always_fraction > 0.0 && s.always_fraction <= 1.0) {
        return Err(bad_flag(
            "--always-fraction",
            format!("must be in (0, 1], got {}", s.always_fraction),
        ));
    }
    if !(s.search_margin.is_finite() && s.search_margin >= 0.0) {
        return Err(bad_flag(
            "--search-margin",
            format!("must be a distance >= 0, got {}", s.search_margin),
        ));
    }
    if !(s.tolerance.is_finite() && (0.0..=1e-4).contains(&s.tolerance)) {
        return Err(bad_flag(
            "--tolerance",
            format!("must be between 0 and 0.0001 m, got {}", s.tolerance),
        ));
    }
    let mut opts = SampleOptions::new(urdd);
    opts.samples = s.samples;
    opts.seed = s.seed;
    if !s.types.is_empty() {
        let mut types = s.types.clone();
        types.sort();
        types.dedup();
        opts.types = types;
    }
    opts.threads = s.threads.map(usize::from);
    opts.always_fraction = s.always_fraction;
    opts.mean_samples = if s.mean_samples == 0 {
        scm::sample::EXACT_MEAN
    } else {
        s.mean_samples
    };
    opts.tolerance = s.tolerance;
    opts.search.margin = s.search_margin;
    opts.certify.max_boxes_per_pair = s.certify_boxes;
    opts.certify.max_boxes = s.certify_total;
    opts.certify.max_exact_per_pair = s.certify_exact;
    opts.force = force;
    Ok(opts)
}

/// Prints the sampling summary, one line per type and one for the link pairs on the exact geometry
/// (notes on stderr); nothing with `--quiet`.
pub fn print_sample(cli: &Cli, r: &SampleReport) {
    if cli.quiet {
        return;
    }
    if r.up_to_date {
        outln!("{}: sampling up to date, nothing to do", r.urdd.display());
        return;
    }
    if let Some(f) = &r.shard_file {
        outln!("{}: wrote {f} in {:.1} s", r.urdd.display(), r.seconds);
        return;
    }
    for n in &r.notes {
        eprintln!("note: {n}");
    }
    let p = &r.phases;
    outln!(
        "{}: {} samples in {:.1} s (sampling {:.1}, search {:.1}, exact-geometry verdicts {:.1}; loading before them {:.1} s)",
        r.urdd.display(),
        r.samples,
        r.seconds,
        p.sampling,
        p.search,
        p.verdicts,
        p.load
    );
    for (t, s) in &r.types {
        let reasons: Vec<String> = s
            .reasons
            .iter()
            .map(|(reason, n)| format!("{} {n}", reason.id()))
            .collect();
        outln!(
            "  {:<13} {:>4} shapes: {}; search: {} pairs, {} never overturned",
            t.id(),
            s.shapes,
            reasons.join(", "),
            s.searched,
            s.overturned
        );
    }
    if let Some(m) = &r.mesh {
        let reasons: Vec<String> = m
            .reasons
            .iter()
            .map(|(reason, n)| format!("{} {n}", reason.id()))
            .collect();
        outln!(
            "  {:<13} {:>4} link pairs: {}; never: {} certified, {} sampled; {} overturned by the certificates ({} boxes)",
            "mesh",
            m.pairs,
            reasons.join(", "),
            m.certified,
            m.sampled,
            m.overturned,
            m.boxes
        );
    }
}
