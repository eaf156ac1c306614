//! `scm bench --scale`: how the sample stage grows with the robot. One row per robot: its size (links,
//! DOFs, decomposition pieces, link and piece pairs), the wall time and peak memory of `scm sample
//! --force` run as a child process (median of several runs, the runs alternating between robots), and
//! the work counts the sample stage records (targeted searches, certificate boxes).
//!
//! A URDF is preprocessed with the default shape parameters into a work folder; a URDD directory is
//! sampled where it is (its sample stage is replaced).

use super::child::{ChildRun, run_measured};
use crate::error::{Error, Result};
use crate::preprocess::{PreprocessOptions, preprocess};
use crate::progress::Progress;
use crate::robot::PackagePaths;
use crate::sample::{MeshSummary, Reason, SAMPLE, TypeSummary, Work};
use crate::shapes::{ShapeParams, ShapeType};
use crate::urdd::Urdd;
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

/// What to measure.
#[derive(Debug, Clone, Serialize)]
pub struct ScaleOptions {
    /// The robots: URDF files or preprocessed URDD directories.
    pub robots: Vec<PathBuf>,
    /// Samples of each sample run.
    pub samples: u64,
    /// Sample runs per robot; time and memory are their medians.
    pub runs: u32,
    /// The `scm` executable the sample runs start.
    pub scm: PathBuf,
    /// Where URDF inputs are preprocessed, one URDD per robot (kept); `None`: a temporary folder,
    /// removed at the end.
    pub work: Option<PathBuf>,
    /// `package://` resolution for URDF inputs.
    #[serde(skip)]
    pub packages: PackagePaths,
}

impl ScaleOptions {
    /// The defaults: 100,000 samples, one run, a temporary work folder, no package paths.
    pub fn new(robots: &[PathBuf], scm: &Path) -> ScaleOptions {
        ScaleOptions {
            robots: robots.to_vec(),
            samples: 100_000,
            runs: 1,
            scm: scm.to_path_buf(),
            work: None,
            packages: PackagePaths::default(),
        }
    }
}

/// What the sample stage did, as counted in its records.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct WorkCounts {
    /// Link pairs the exact geometry leaves `checked`.
    pub checked_link_pairs: usize,
    /// Link pairs the exact geometry calls `never`.
    pub never_link_pairs: usize,
    /// Of those, the ones with a certificate.
    pub certified: usize,
    /// Sub-boxes the certificates evaluated.
    pub certificate_boxes: u64,
    /// Decomposition piece pairs left `checked`.
    pub checked_piece_pairs: usize,
    /// Pairs the targeted search examined, over every type.
    pub searched_pairs: usize,
    /// What the sampling loop did, summed over the six types: pair-samples bounded, and how many
    /// needed a GJK run stopped early or an exact query.
    pub sampling: Work,
}

/// One robot's row.
#[derive(Debug, Clone, Serialize)]
pub struct ScaleRow {
    /// The input as given.
    pub input: PathBuf,
    /// The URDD that was sampled.
    pub urdd: PathBuf,
    /// Robot name.
    pub robot: String,
    /// Links with geometry.
    pub links: usize,
    /// Sampled degrees of freedom.
    pub dofs: usize,
    /// Convex decomposition pieces (decomp-hull shapes).
    pub pieces: usize,
    /// Pairs of links with geometry.
    pub link_pairs: usize,
    /// Pairs of pieces on different links.
    pub piece_pairs: usize,
    /// Every run, in order.
    pub runs: Vec<ChildRun>,
    /// Median wall time of the runs (s).
    pub seconds: f64,
    /// Median peak resident memory of the runs (bytes), when it could be read.
    pub peak_bytes: Option<u64>,
    /// What the last run's sample stage recorded.
    pub work: WorkCounts,
}

/// Everything `scm bench --scale` measured.
#[derive(Debug, Clone, Serialize)]
pub struct ScaleReport {
    /// The options used.
    pub options: ScaleOptions,
    /// Cores the machine offers (the sample runs use them all).
    pub cores: usize,
    /// One row per robot, in the order given.
    pub rows: Vec<ScaleRow>,
}

/// Measures every robot: preprocesses the URDFs, then runs `scm sample --force` `runs` times per
/// robot, alternating between robots, and reads the sizes and work counts back from each URDD.
pub fn scale(opts: &ScaleOptions, progress: &dyn Progress) -> Result<ScaleReport> {
    if opts.runs == 0 || opts.samples == 0 {
        return Err(Error::input(
            Path::new("command line"),
            "--scale",
            "needs at least one run of at least one sample",
        ));
    }
    let work = WorkFolder::new(opts.work.as_deref())?;
    let mut urdds = Vec::new();
    for (i, input) in opts.robots.iter().enumerate() {
        urdds.push(prepare(
            opts,
            input,
            &work.path.join(format!("{i:02}")),
            progress,
        )?);
    }
    let mut runs: Vec<Vec<ChildRun>> = vec![Vec::new(); urdds.len()];
    progress.start("sample runs", u64::from(opts.runs) * urdds.len() as u64);
    for _ in 0..opts.runs {
        for (urdd, row_runs) in urdds.iter().zip(&mut runs) {
            row_runs.push(run_measured(&mut sample_command(opts, urdd))?);
            progress.advance(1);
        }
    }
    progress.finish();
    let rows = opts
        .robots
        .iter()
        .zip(&urdds)
        .zip(runs)
        .map(|((input, urdd), runs)| row(input, urdd, runs))
        .collect::<Result<_>>()?;
    Ok(ScaleReport {
        options: opts.clone(),
        cores: std::thread::available_parallelism().map_or(1, usize::from),
        rows,
    })
}

/// The URDD to sample for `input`: a URDF preprocessed into `out` (nothing done when up to date), or
/// the URDD directory itself.
fn prepare(
    opts: &ScaleOptions,
    input: &Path,
    out: &Path,
    progress: &dyn Progress,
) -> Result<PathBuf> {
    if input.is_dir() {
        // Fails now, naming the folder, rather than in a child process later.
        Urdd::open(input)?.stage(crate::urdd::PREPROCESS)?;
        return Ok(input.to_path_buf());
    }
    preprocess(
        &PreprocessOptions {
            urdf: input.to_path_buf(),
            out: out.to_path_buf(),
            packages: opts.packages.clone(),
            visual_fallback: false,
            params: ShapeParams::default(),
            force: false,
        },
        progress,
    )?;
    Ok(out.to_path_buf())
}

/// `scm sample URDD --force -q -n SAMPLES`: every type, the other settings at their defaults.
fn sample_command(opts: &ScaleOptions, urdd: &Path) -> Command {
    let mut c = Command::new(&opts.scm);
    c.arg("sample")
        .arg(urdd)
        .args(["--force", "-q", "-n"])
        .arg(opts.samples.to_string());
    c
}

/// The row of one robot: its sizes and work counts from the URDD, the medians of its runs.
fn row(input: &Path, dir: &Path, runs: Vec<ChildRun>) -> Result<ScaleRow> {
    let urdd = Urdd::open(dir)?;
    let robot = urdd.robot()?;
    let links = urdd.shapes(ShapeType::Hull)?.shapes.len();
    let pieces = urdd.shapes(ShapeType::DecompHull)?.shapes;
    let mut per_link: BTreeMap<usize, usize> = BTreeMap::new();
    for p in &pieces {
        *per_link.entry(p.link_index).or_default() += 1;
    }
    let seconds = median(runs.iter().map(|r| r.seconds).collect()).unwrap_or(0.0);
    let peaks: Option<Vec<f64>> = runs
        .iter()
        .map(|r| r.peak_bytes.map(|b| b as f64))
        .collect();
    Ok(ScaleRow {
        input: input.to_path_buf(),
        urdd: dir.to_path_buf(),
        robot: urdd.manifest().robot.clone(),
        links,
        dofs: robot.dofs.len(),
        pieces: pieces.len(),
        link_pairs: links * links.saturating_sub(1) / 2,
        piece_pairs: cross_pairs(per_link.values().copied()),
        seconds,
        peak_bytes: peaks.and_then(median).map(|b| b.round() as u64),
        runs,
        work: work_counts(&urdd)?,
    })
}

/// Pairs of items from different groups, given the group sizes.
fn cross_pairs(sizes: impl Iterator<Item = usize>) -> usize {
    let (mut total, mut pairs) = (0, 0);
    for n in sizes {
        pairs += total * n;
        total += n;
    }
    pairs
}

/// The work counts the sample stage recorded in the manifest.
fn work_counts(urdd: &Urdd) -> Result<WorkCounts> {
    let types: BTreeMap<ShapeType, TypeSummary> = urdd.stage_summary(SAMPLE, Some("types"))?;
    let mesh: Option<MeshSummary> = urdd.stage_summary(SAMPLE, Some("mesh"))?;
    let mesh = mesh.unwrap_or_default();
    let reason = |r| mesh.reasons.get(&r).copied().unwrap_or(0);
    let work: Option<BTreeMap<ShapeType, Work>> = urdd.stage_summary(SAMPLE, Some("work"))?;
    let mut sampling = Work::default();
    work.unwrap_or_default()
        .values()
        .for_each(|w| sampling.add(w));
    Ok(WorkCounts {
        sampling,
        checked_link_pairs: reason(Reason::Checked),
        never_link_pairs: reason(Reason::Never),
        certified: mesh.certified,
        certificate_boxes: mesh.boxes,
        checked_piece_pairs: types
            .get(&ShapeType::DecompHull)
            .and_then(|t| t.reasons.get(&Reason::Checked).copied())
            .unwrap_or(0),
        searched_pairs: types.values().map(|t| t.searched).sum(),
    })
}

/// The median (the mean of the middle two of an even count); `None` when empty.
fn median(mut values: Vec<f64>) -> Option<f64> {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(values[n / 2]),
        _ => Some((values[n / 2 - 1] + values[n / 2]) / 2.0),
    }
}

/// The work folder: the given one (created, kept) or a temporary one removed when dropped.
struct WorkFolder {
    path: PathBuf,
    temporary: bool,
}

impl WorkFolder {
    fn new(given: Option<&Path>) -> Result<WorkFolder> {
        let (path, temporary) = match given {
            Some(p) => (p.to_path_buf(), false),
            None => (
                std::env::temp_dir().join(format!("scm-scale-{}", std::process::id())),
                true,
            ),
        };
        std::fs::create_dir_all(&path).map_err(|e| Error::io(&path, e))?;
        Ok(WorkFolder { path, temporary })
    }
}

impl Drop for WorkFolder {
    fn drop(&mut self) {
        if self.temporary {
            let _ = std::fs::remove_dir_all(&self.path);
        }
    }
}

/// How a row names its input: the file or folder name without its extension (`ur5e` for
/// `ur5e/ur5e.urdf`, `n60` for `/tmp/n60.urdd`), which tells apart robots that share a name.
fn input_name(input: &Path) -> String {
    input.file_stem().map_or_else(
        || input.display().to_string(),
        |s| s.to_string_lossy().into_owned(),
    )
}

/// The command that reproduces the table.
pub fn command(opts: &ScaleOptions) -> String {
    let mut c = String::from("scm bench --scale");
    for r in &opts.robots {
        let _ = write!(c, " {}", r.display());
    }
    let _ = write!(c, " -n {} --runs {}", opts.samples, opts.runs);
    c
}

/// The scale table as markdown, with the command and what each column counts.
pub fn render_scale(r: &ScaleReport) -> String {
    let o = &r.options;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "`{}` (scm {}, {} cores): `scm sample DIR --force` with {} samples, every type, the other \
         settings at their defaults, as a child process; time (wall) and peak resident memory are \
         the median of {} run{} per robot, the runs alternating between robots.\n",
        command(o),
        crate::VERSION,
        r.cores,
        o.samples,
        o.runs,
        if o.runs == 1 { "" } else { "s" }
    );
    s.push_str(
        "| input | robot | links | DOFs | pieces | link pairs | piece pairs | time (s) | peak MiB | pair-samples (M) | windows (M) | exact queries (M) | checked link pairs | never (certified) | certificate boxes | checked piece pairs | searched pairs |\n\
         |---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for row in &r.rows {
        let w = &row.work;
        let peak = row.peak_bytes.map_or("-".to_string(), |b| {
            format!("{:.0}", b as f64 / 1_048_576.0)
        });
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {:.2} | {} | {:.1} | {:.2} | {:.2} | {} | {} ({}) | {} | {} | {} |",
            input_name(&row.input),
            row.robot,
            row.links,
            row.dofs,
            row.pieces,
            row.link_pairs,
            row.piece_pairs,
            row.seconds,
            peak,
            w.sampling.pair_samples as f64 / 1e6,
            w.sampling.windows as f64 / 1e6,
            w.sampling.exact as f64 / 1e6,
            w.checked_link_pairs,
            w.never_link_pairs,
            w.certified,
            w.certificate_boxes,
            w.checked_piece_pairs,
            w.searched_pairs,
        );
    }
    s.push_str(
        "\n*input*: the file or folder name given, without its extension; *robot*: the URDF's robot \
         name; *links*: links with geometry; *pieces*: convex decomposition pieces (decomp-hull); *piece \
         pairs*: pairs of pieces on different links; *pair-samples*: samples times moving pairs, over the \
         six types, each bounded by its spheres; *windows*, *exact queries*: the pair-samples those \
         bounds (and the tighter ones after them) could not settle, decided by a GJK run stopped once \
         the distance lay inside the extremes, or by an exact distance; *checked*, *never*: the verdicts on the exact \
         geometry (link pairs) and on the pieces; *certificate boxes*: joint-space sub-boxes the \
         `never` certificates evaluated; *searched pairs*: pairs the targeted collision search \
         examined, over the six types.\n",
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(vec![]), None);
        assert_eq!(median(vec![3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(vec![4.0, 1.0, 2.0, 3.0]), Some(2.5));
    }

    #[test]
    fn cross_pairs_leave_out_pairs_within_a_group() {
        assert_eq!(cross_pairs([3, 3, 3].into_iter()), 27);
        assert_eq!(cross_pairs([1, 1, 1, 1].into_iter()), 6);
        assert_eq!(cross_pairs([5].into_iter()), 0);
    }
}
