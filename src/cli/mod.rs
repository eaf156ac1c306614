//! The thin command-line layer: parse flags, call one library stage per subcommand, print results.

pub mod args;
mod output;
mod progress;

use output::{out, outln};

use args::{
    BenchArgs, Cli, Command, DiffArgs, ExportArgs, ExportFlags, ImportMoveitArgs, InspectArgs,
    PreprocessArgs, RunArgs, SampleArgs, SamplingArgs, ShapeArgs, ViewArgs,
};
use scm::bench::{BenchOptions, BenchReport, bench};
use scm::compare::{
    CompareOptions, WitnessJoints, compare, format_comparison, format_comparison_with,
};
use scm::error::{Error, Result};
use scm::export::{ExportOptions, ExportReport, export};
use scm::import::{ImportOptions, import_moveit};
use scm::inspect::{Configurations, inspect};
use scm::preprocess::{PreprocessOptions, PreprocessReport, preprocess};
use scm::robot::PackagePaths;
use scm::sample::{SampleOptions, SampleReport, Shard, merge_shards, sample};
use scm::shapes::{DecompParams, ShapeParams};
use std::path::{Path, PathBuf};

/// Runs the parsed command line.
pub fn run(cli: &Cli) -> Result<()> {
    match &cli.command {
        Command::Preprocess(args) => run_preprocess(cli, args),
        Command::Sample(args) => run_sample(cli, args),
        Command::Export(args) => run_export(cli, args),
        Command::ImportMoveit(args) => run_import(cli, args),
        Command::Diff(args) => run_diff(cli, args),
        Command::Run(args) => run_all(cli, args),
        Command::Inspect(args) => run_inspect(cli, args),
        Command::View(args) => run_view(args),
        Command::Bench(args) => run_bench(cli, args),
    }
}

/// A bad command-line value.
fn bad_flag(flag: &str, message: String) -> Error {
    Error::input(Path::new("command line"), flag.to_string(), message)
}

/// Lowers the preprocess flags into library options.
fn preprocess_options(
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

/// Lowers the sampling flags into library options.
fn sample_options(urdd: &Path, s: &SamplingArgs, force: bool) -> Result<SampleOptions> {
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

/// Lowers the export flags into library options.
fn export_options(
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

/// `scm preprocess`: build the six shape representations into the URDD.
fn run_preprocess(cli: &Cli, args: &PreprocessArgs) -> Result<()> {
    let opts = preprocess_options(&args.urdf, &args.output, &args.shapes, args.force)?;
    let report = preprocess(&opts, &progress::Bar::new(cli.quiet))?;
    if cli.json {
        print_json(&report);
    } else {
        print_preprocess(cli, &report);
    }
    Ok(())
}

/// `scm sample`: sample joint space, or one shard of it, or merge shards.
fn run_sample(cli: &Cli, args: &SampleArgs) -> Result<()> {
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
        print_json(&report);
    } else {
        print_sample(cli, &report);
    }
    Ok(())
}

/// `scm run`: preprocess, sample, export; each stage does nothing when up to date.
fn run_all(cli: &Cli, args: &RunArgs) -> Result<()> {
    let pre = preprocess_options(&args.urdf, &args.output, &args.shapes, args.force)?;
    let sampling = sample_options(&args.output, &args.sampling, args.force)?;
    let exporting = export_options(&args.output, None, &args.export, args.force);
    let bar = progress::Bar::new(cli.quiet);
    let pre_report = preprocess(&pre, &bar)?;
    let sample_report = sample(&sampling, &bar)?;
    let export_report = export(&exporting, &bar)?;
    if cli.json {
        print_json(&serde_json::json!({
            "preprocess": pre_report,
            "sample": sample_report,
            "export": export_report,
        }));
    } else {
        print_preprocess(cli, &pre_report);
        print_sample(cli, &sample_report);
        print_export(cli, &export_report);
    }
    Ok(())
}

/// `scm export`: write the matrices and the consumer files.
fn run_export(cli: &Cli, args: &ExportArgs) -> Result<()> {
    let opts = export_options(&args.urdd, args.output.clone(), &args.export, args.force);
    let report = export(&opts, &progress::Bar::new(cli.quiet))?;
    if cli.json {
        print_json(&report);
    } else {
        print_export(cli, &report);
    }
    Ok(())
}

/// `scm import-moveit`: store an SRDF as the imported layer (and optionally compare).
fn run_import(cli: &Cli, args: &ImportMoveitArgs) -> Result<()> {
    let report = import_moveit(&ImportOptions {
        srdf: args.srdf.clone(),
        urdd: args.urdd.clone(),
    })?;
    let comparison = if args.compare {
        Some(compare(&CompareOptions {
            urdd: args.urdd.clone(),
            srdf: None,
            link_level: args.link_level,
        })?)
    } else {
        None
    };
    if cli.json {
        print_json(&serde_json::json!({ "import": report, "compare": comparison }));
        return Ok(());
    }
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
    if let Some(c) = comparison {
        out!("{}", format_comparison(&c, &args.urdd));
    }
    Ok(())
}

/// `scm diff`: scm's verdicts against MoveIt's.
fn run_diff(cli: &Cli, args: &DiffArgs) -> Result<()> {
    let c = compare(&CompareOptions {
        urdd: args.urdd.clone(),
        srdf: args.srdf.clone(),
        link_level: args.link_level,
    })?;
    let joints = if args.full_witness {
        WitnessJoints::All
    } else {
        WitnessJoints::Path
    };
    if cli.json {
        print_json(&c);
    } else {
        out!("{}", format_comparison_with(&c, &args.urdd, joints));
    }
    Ok(())
}

/// `scm inspect`: each link's loaded geometry and its world boxes at the configurations asked for.
fn run_inspect(cli: &Cli, args: &InspectArgs) -> Result<()> {
    let which = if let Some(count) = args.random {
        Configurations::Random {
            count: count as usize,
            seed: args.seed,
        }
    } else if args.config.is_empty() {
        Configurations::Home
    } else {
        let parse = |text: &String| -> Result<Vec<f64>> {
            text.split(|c: char| c == ',' || c.is_whitespace())
                .filter(|s| !s.is_empty())
                .map(|s| {
                    s.parse::<f64>().map_err(|_| {
                        bad_flag("--config", format!("`{s}` is not a number (in \"{text}\")"))
                    })
                })
                .collect()
        };
        Configurations::Given(args.config.iter().map(parse).collect::<Result<_>>()?)
    };
    let report = inspect(&args.urdd, &which)?;
    if cli.json {
        print_json(&report);
        return Ok(());
    }
    let mut out = String::new();
    for (i, placed) in report.configurations.iter().enumerate() {
        let q: Vec<String> = placed.q.iter().map(|v| format!("{v:.4}")).collect();
        out += &format!("configuration {i}: [{}]\n", q.join(" "));
        for link in &report.links {
            let counts: Vec<String> = link
                .elements
                .iter()
                .map(|e| match &e.uri {
                    Some(uri) => format!("{uri} ({} vertices)", e.vertices),
                    None => e.kind.to_string(),
                })
                .collect();
            let bounds = placed
                .links
                .iter()
                .find(|p| p.link == link.link)
                .map_or_else(
                    || "no collision geometry".to_string(),
                    |p| {
                        let f = |v: [f64; 3]| format!("({:.4}, {:.4}, {:.4})", v[0], v[1], v[2]);
                        format!("box {} .. {}", f(p.bounds.min), f(p.bounds.max))
                    },
                );
            let source = serde_json::to_value(link.source)
                .ok()
                .and_then(|v| v.as_str().map(str::to_string))
                .unwrap_or_default();
            out += &format!(
                "  {}: {source}, {} element(s){}{}; {bounds}\n",
                link.link,
                link.elements.len(),
                if counts.is_empty() { "" } else { ": " },
                counts.join(", ")
            );
        }
    }
    out!("{out}");
    Ok(())
}

fn print_json<T: serde::Serialize>(value: &T) {
    outln!(
        "{}",
        serde_json::to_string_pretty(value).unwrap_or_default()
    );
}

fn print_preprocess(cli: &Cli, r: &PreprocessReport) {
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

fn print_sample(cli: &Cli, r: &SampleReport) {
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
    outln!(
        "{}: {} samples in {:.1} s",
        r.urdd.display(),
        r.samples,
        r.seconds
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

/// `scm bench`: time queries with and without skips, and check the skips against the meshes.
fn run_bench(cli: &Cli, args: &BenchArgs) -> Result<()> {
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
    let report = bench(&opts, &progress::Bar::new(cli.quiet))?;
    if cli.json {
        print_json(&report);
    } else {
        print_bench(&report);
    }
    Ok(())
}

fn print_bench(r: &BenchReport) {
    out!("{}", scm::bench::render(r));
    outln!(
        "\nwrote {}",
        r.urdd.join(scm::bench::BENCH).join("bench.md").display()
    );
}

fn print_export(cli: &Cli, r: &ExportReport) {
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

/// `scm view`: launch the viewer binary found next to this executable or on PATH.
fn run_view(args: &ViewArgs) -> Result<()> {
    scm::urdd::Urdd::open(&args.urdd)?;
    let viewer = find_viewer().ok_or_else(|| Error::Failed {
        context: "scm view".into(),
        message:
            "the viewer binary `scm-viewer` was not found next to scm or on PATH; build it in the \
             scm source tree with `cargo build --release -p scm-viewer` (it needs Bevy) and put \
             target/release/scm-viewer beside scm or on PATH"
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
