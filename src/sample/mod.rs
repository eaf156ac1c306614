//! The `sample` stage: N random joint configurations, per-pair distance statistics for every selected
//! shape type, skip inference with reasons, and a targeted search that overturns wrong "never" verdicts.
//!
//! Determinism: sample k is drawn from the random stream of its chunk (k / 1024) under the seed, and the
//! statistics merge exactly (fixed-point sums, smallest-index witnesses), so any thread count and any
//! sharding give the same bytes.

mod block;
mod certify;
mod engine;
mod finalize;
mod mesh;
mod prefetch;
mod reasons;
mod records;
mod search;
mod sets;
mod stats;
mod table;
mod work;

pub use certify::{Certificate, CertifyParams, PairGeometry, Status, certify};
pub use engine::{CHUNK, Engine};
pub use mesh::{LinkPairRecord, MESH_FILE, MeshFile, MeshSummary, NeverEvidence, load_mesh_file};
pub use reasons::{Evidence, Reason, infer, never_upper_bound};
pub use records::{PairRecord, SampleFile, TypeSummary, Witness};
pub use search::{SearchOutcome, SearchParams, SearchTarget, search_link_pair};
pub use sets::{PairSet, PlacedPair};
pub use stats::PairStats;
pub use table::Table;
use work::Laps;
pub use work::{Phases, Work};

use crate::error::{Error, Result};
use crate::progress::Progress;
use crate::shapes::ShapeType;
use crate::urdd::{PREPROCESS, StageDir, StageRecord, Urdd, json_bytes, write_atomic};
use crate::urdd::{compact_json, parameters};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub use crate::urdd::{SAMPLE, SHARDS, sample_file_name};

/// Which part of the samples a run computes: chunks `c` with `c % count == index`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// This shard, `0 <= index < count`.
    pub index: u32,
    /// Number of shards.
    pub count: u32,
}

impl Shard {
    /// Parses `K/N`.
    pub fn parse(s: &str) -> Option<Shard> {
        let (k, n) = s.split_once('/')?;
        let (index, count) = (k.trim().parse().ok()?, n.trim().parse().ok()?);
        (count > 0 && index < count).then_some(Shard { index, count })
    }

    fn file(count: u32, index: u32) -> String {
        format!("shard-{index}-of-{count}.json")
    }
}

/// `SampleOptions::mean_samples` for exact means over every sample.
pub const EXACT_MEAN: u64 = u64::MAX;

/// What to sample and how; everything but `threads`, `shard` and `force` enters the stage key.
#[derive(Debug, Clone, Serialize)]
pub struct SampleOptions {
    /// The URDD directory.
    pub urdd: PathBuf,
    /// Number of random configurations.
    pub samples: u64,
    /// Random seed.
    pub seed: u64,
    /// Shape types to sample.
    pub types: Vec<ShapeType>,
    /// A pair colliding in at least this fraction of samples is `always`.
    pub always_fraction: f64,
    /// At most this many leading samples per pair enter d_mean's estimate ([`EXACT_MEAN`]: every
    /// sample, an exact mean).
    pub mean_samples: u64,
    /// d_min and d_max are within this many metres of the exact extremes over the samples (0: exact).
    pub tolerance: f64,
    /// Targeted search.
    pub search: SearchParams,
    /// The budget of the `never` certificates on the exact geometry's link pairs.
    pub certify: CertifyParams,
    /// Worker threads (`None`: all cores). Does not change the result.
    #[serde(skip)]
    pub threads: Option<usize>,
    /// Compute only this shard and write its partial result.
    #[serde(skip)]
    pub shard: Option<Shard>,
    /// Recompute even when up to date.
    #[serde(skip)]
    pub force: bool,
}

impl SampleOptions {
    /// The defaults: 100,000 samples, seed 0, all six types, always at 95%, d_mean from the first 25,000
    /// samples, d_min/d_max within [`DEFAULT_TOLERANCE`].
    pub fn new(urdd: &Path) -> SampleOptions {
        SampleOptions {
            urdd: urdd.to_path_buf(),
            samples: 100_000,
            seed: 0,
            types: ShapeType::ALL.to_vec(),
            always_fraction: 0.95,
            mean_samples: 25_000,
            tolerance: DEFAULT_TOLERANCE,
            search: SearchParams::default(),
            certify: CertifyParams::default(),
            threads: None,
            shard: None,
            force: false,
        }
    }
}

/// What a sample run did.
#[derive(Debug, Clone, Serialize)]
pub struct SampleReport {
    /// The URDD directory.
    pub urdd: PathBuf,
    /// Nothing was done: the output was up to date.
    pub up_to_date: bool,
    /// Set when only a shard was computed (its file, relative to the URDD).
    pub shard_file: Option<String>,
    /// Samples drawn.
    pub samples: u64,
    /// Per type: pair counts per reason, and the search's work.
    pub types: BTreeMap<ShapeType, TypeSummary>,
    /// The link-level verdicts on the exact geometry (`mesh`): reasons, certified and sampled `never`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh: Option<MeshSummary>,
    /// Per type, what the sampling loop did (summed over the shards after a merge).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub work: BTreeMap<ShapeType, Work>,
    /// Seconds spent sampling (not counting loading and writing): `phases` without `load`.
    pub seconds: f64,
    /// Where the time went, phase by phase (all zero when nothing was done).
    pub phases: Phases,
    /// Why the stage reran although its key was unchanged (an output file changed or went missing).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
}

/// The `format` of a shard file.
const SHARD_FORMAT: &str = "scm-sample-shard";
/// The version of the shard file format, raised when a field changes meaning (2: the mean's control
/// sums are taken from 16-bit distance tables, so they do not merge with version 1's; 3: coaxial
/// pairs' tables span their relative turn, so their control sums differ from version 2's; 4: pairs of
/// spheres sum their control in four running sums, and their extremes are exact).
const SHARD_FORMAT_VERSION: u32 = 4;

/// A shard's partial result, self-contained so a scheduler can ship it: everything the merge checks it
/// against (no paths, nothing of the machine it ran on) and the exact accumulators of its chunks.
/// Every header field defaults, so a file that is something else fails on `format`, not on serde.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct ShardFile {
    /// [`SHARD_FORMAT`].
    #[serde(default)]
    format: String,
    /// [`SHARD_FORMAT_VERSION`] when written by this build.
    #[serde(default)]
    format_version: u32,
    /// The scm that sampled it.
    #[serde(default)]
    tool_version: String,
    /// The robot's name.
    #[serde(default)]
    robot: String,
    /// The key of the preprocess output it sampled.
    #[serde(default)]
    preprocess: String,
    /// The sampling options of the stage key: samples, seed, types and every other parameter.
    #[serde(default)]
    options: serde_json::Value,
    /// Which shard of how many.
    #[serde(default)]
    shard: Option<Shard>,
    /// The sample stage key of that preprocess output and those options.
    #[serde(default)]
    key: String,
    /// Per type, per pair: the exact accumulators of this shard's chunks.
    #[serde(default)]
    stats: BTreeMap<ShapeType, Vec<PairStats>>,
    /// Per type, what this shard's sampling loop did (the merge adds them up).
    #[serde(default)]
    work: BTreeMap<ShapeType, Work>,
}

impl ShardFile {
    /// What shard `shard` of `opts` on `urdd` records besides its statistics.
    fn header(urdd: &Urdd, opts: &SampleOptions, shard: Shard) -> Result<ShardFile> {
        Ok(ShardFile {
            format: SHARD_FORMAT.into(),
            format_version: SHARD_FORMAT_VERSION,
            tool_version: crate::VERSION.into(),
            robot: urdd.manifest().robot.clone(),
            preprocess: urdd.stage(PREPROCESS)?.key.clone(),
            options: parameters(SAMPLE, opts)?,
            shard: Some(shard),
            key: stage_key(urdd, opts)?,
            stats: BTreeMap::new(),
            work: BTreeMap::new(),
        })
    }

    /// Reads the shard file at `path`; an unreadable, truncated or malformed file is bad input naming
    /// it, never empty data.
    fn read(path: &Path) -> Result<ShardFile> {
        let bytes = std::fs::read(path)
            .map_err(|e| Error::input(path, "file", format!("cannot read: {e}")))?;
        serde_json::from_slice(&bytes).map_err(|e| {
            let what = if bytes.is_empty() {
                "empty".to_string()
            } else if e.is_eof() {
                format!("truncated after {} bytes", bytes.len())
            } else {
                format!("invalid JSON: {e}")
            };
            Error::input(
                path,
                format!("line {}, column {}", e.line(), e.column()),
                format!("{what}; copy it again or rerun this shard"),
            )
        })
    }

    /// Whether this shard (read from `path`) merges with `expected`: the first field that differs
    /// is bad input naming it and both values.
    fn check(&self, expected: &ShardFile, path: &Path) -> Result<()> {
        if self.format != SHARD_FORMAT {
            let message = format!("not a sample shard file (no \"format\": \"{SHARD_FORMAT}\")");
            return Err(Error::input(path, "format", message));
        }
        let found: BTreeMap<String, serde_json::Value> = self.fields().into_iter().collect();
        let Some((field, wanted)) = expected
            .fields()
            .into_iter()
            .find(|(field, wanted)| found.get(field) != Some(wanted))
        else {
            return Ok(());
        };
        let show = |v: Option<&serde_json::Value>| match v {
            Some(serde_json::Value::String(s)) if s.len() > 16 => {
                format!("{}...", s.chars().take(12).collect::<String>())
            }
            Some(v) => v.to_string(),
            None => "nothing".into(),
        };
        let hint = match field.as_str() {
            "format_version" | "tool_version" => "rerun this shard with this scm",
            "robot" | "preprocess" => "rerun this shard on a copy of this URDD",
            "shard" | "key" => "rerun this shard",
            _ => "give the shards and the merge the same sampling flags, or rerun this shard",
        };
        let message = format!(
            "this shard has {}, the merge expects {}; {hint}",
            show(found.get(&field)),
            show(Some(&wanted))
        );
        Err(Error::input(path, field, message))
    }

    /// The fields the merge compares, in the order it reports them: the header, then every sampling
    /// option by name (`seed`, `samples`, `search.margin` ...), then the stage key they give.
    fn fields(&self) -> Vec<(String, serde_json::Value)> {
        use serde_json::json;
        let mut fields = vec![
            ("format_version".into(), json!(self.format_version)),
            ("tool_version".into(), json!(self.tool_version)),
            (
                "shard".into(),
                json!(self.shard.map(|s| format!("{}/{}", s.index, s.count))),
            ),
            ("robot".into(), json!(self.robot)),
            ("preprocess".into(), json!(self.preprocess)),
        ];
        flatten("", &self.options, &mut fields);
        fields.push(("key".into(), json!(self.key)));
        fields
    }
}

/// The leaves of a JSON tree with their dotted names.
fn flatten(prefix: &str, value: &serde_json::Value, out: &mut Vec<(String, serde_json::Value)>) {
    match value {
        serde_json::Value::Object(map) => {
            for (k, v) in map {
                let name = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten(&name, v, out);
            }
        }
        leaf => out.push((prefix.into(), leaf.clone())),
    }
}

/// How far (m) d_min and d_max may lie from the exact extremes over the samples by default: 0.09 mm,
/// so that with the exact queries' own error (micrometres at worst, see docs/cli.md) they stay within
/// the 0.1 mm the extremes may carry.
pub const DEFAULT_TOLERANCE: f64 = 9e-5;

/// The most samples one run takes: memory stays flat in the count, time does not (about a day for
/// b1 on two cores).
pub const MAX_SAMPLES: u64 = 1_000_000_000;
/// The most worker threads one run starts.
pub const MAX_THREADS: usize = 1024;

/// Runs the sample stage (or one shard of it).
pub fn sample(opts: &SampleOptions, progress: &dyn Progress) -> Result<SampleReport> {
    let bad = |flag: &str, message: String| Error::input(Path::new("options"), flag, message);
    if !(1..=MAX_SAMPLES).contains(&opts.samples) {
        return Err(bad(
            "samples",
            format!("{} is outside 1..={MAX_SAMPLES}", opts.samples),
        ));
    }
    if let Some(t) = opts.threads.filter(|t| !(1..=MAX_THREADS).contains(t)) {
        return Err(bad("threads", format!("{t} is outside 1..={MAX_THREADS}")));
    }
    // Shards only write their own file, so a scheduler can run them side by side.
    let (mut urdd, _lock) = match opts.shard {
        None => {
            let (urdd, lock) = Urdd::open_for_writing(&opts.urdd, progress)?;
            (urdd, Some(lock))
        }
        Some(_) => (Urdd::open(&opts.urdd)?, None),
    };
    let key = stage_key(&urdd, opts)?;
    let notes: Vec<String> = urdd.rerun_note(SAMPLE, &key).into_iter().collect();
    let report = |up_to_date, shard_file, types, work, phases: Phases| SampleReport {
        urdd: opts.urdd.clone(),
        up_to_date,
        shard_file,
        samples: opts.samples,
        types,
        work,
        seconds: phases.after_load(),
        phases,
        mesh: None,
        notes: Vec::new(),
    };
    if opts.shard.is_none() && !opts.force && urdd.is_up_to_date(SAMPLE, &key) {
        let types = urdd.stage_summary(SAMPLE, Some("types"))?;
        let mesh = urdd.stage_summary(SAMPLE, Some("mesh"))?;
        // A stage written before the work was counted has none.
        let work: Option<_> = urdd.stage_summary(SAMPLE, Some("work"))?;
        return Ok(SampleReport {
            mesh,
            ..report(
                true,
                None,
                types,
                work.unwrap_or_default(),
                Phases::default(),
            )
        });
    }
    let mut laps = Laps::start();
    let mut phases = Phases::default();
    let engine = Engine::load(&urdd, &opts.types)?.with_tables();
    phases.load = laps.lap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.unwrap_or(0))
        .build()
        .map_err(|e| Error::Failed {
            context: "sample".into(),
            message: format!("cannot start threads: {e}"),
        })?;
    laps.lap();
    let chunks: Vec<u64> = (0..opts.samples.div_ceil(CHUNK))
        .filter(|c| {
            opts.shard
                .is_none_or(|s| c % u64::from(s.count) == u64::from(s.index))
        })
        .collect();
    progress.start("sampling", chunks.len() as u64 * CHUNK.min(opts.samples));
    let acc = pool.install(|| finalize::accumulate(&engine, opts, &chunks, progress));
    progress.finish();
    phases.sampling = laps.lap();
    let work: BTreeMap<ShapeType, Work> = engine
        .sets
        .iter()
        .map(|s| s.shape_type)
        .zip(engine.work())
        .collect();

    if let Some(shard) = opts.shard {
        let name = Shard::file(shard.count, shard.index);
        let file = ShardFile {
            stats: engine.sets.iter().map(|s| s.shape_type).zip(acc).collect(),
            work: work.clone(),
            ..ShardFile::header(&urdd, opts, shard)?
        };
        // Compact: a scheduler ships it between machines.
        let mut bytes = compact_json(&name, &file)?;
        bytes.push(b'\n');
        write_atomic(&opts.urdd.join(SHARDS).join(&name), &bytes)?;
        return Ok(report(
            false,
            Some(format!("{SHARDS}/{name}")),
            BTreeMap::new(),
            work,
            phases,
        ));
    }
    let files = pool.install(|| finalize::finalize(&engine, opts, acc));
    phases.search = laps.lap();
    let mesh = pool.install(|| mesh::mesh_verdicts(&urdd, &engine, opts, &files, progress))?;
    phases.verdicts = laps.lap();
    write_stage(&mut urdd, opts, key, &files, &mesh, &work)?;
    Ok(SampleReport {
        notes,
        mesh: Some(mesh.summary.clone()),
        ..report(
            false,
            None,
            files
                .iter()
                .map(|f| (f.shape_type, f.summary.clone()))
                .collect(),
            work,
            phases,
        )
    })
}

/// Merges the `count` shard files in the URDD into the sample stage output (identical to one run).
/// Every shard must be there and match this URDD's preprocess output and `opts`; a missing, foreign
/// or broken shard is bad input naming it, and nothing is written.
pub fn merge_shards(
    opts: &SampleOptions,
    count: u32,
    progress: &dyn Progress,
) -> Result<SampleReport> {
    let (mut urdd, _lock) = Urdd::open_for_writing(&opts.urdd, progress)?;
    let key = stage_key(&urdd, opts)?;
    let paths: Vec<PathBuf> = (0..count)
        .map(|index| opts.urdd.join(SHARDS).join(Shard::file(count, index)))
        .collect();
    // All present before any is read, so the one line names every shard still to run.
    let missing: Vec<u32> = (0..count)
        .filter(|&index| !paths[index as usize].is_file())
        .collect();
    if let Some(&first) = missing.first() {
        let others = match missing.len() {
            1 => String::new(),
            n => {
                let listed: Vec<String> = missing.iter().take(8).map(u32::to_string).collect();
                let more = if n > 8 { ", ..." } else { "" };
                format!(" (missing shards: {}{more})", listed.join(", "))
            }
        };
        return Err(Error::input(
            &paths[first as usize],
            format!("shard {first} of {count}"),
            format!(
                "missing{others}; run `scm sample {} --shard {first}/{count}` with the merge's sampling flags",
                opts.urdd.display()
            ),
        ));
    }
    let mut laps = Laps::start();
    let mut phases = Phases::default();
    // The merge samples nothing, so it builds no distance tables.
    let engine = Engine::load(&urdd, &opts.types)?;
    phases.load = laps.lap();
    let mut acc: Vec<Vec<PairStats>> = engine
        .sets
        .iter()
        .map(|s| vec![PairStats::default(); s.pairs.len()])
        .collect();
    let expected = ShardFile::header(&urdd, opts, Shard { index: 0, count })?;
    let mut work: BTreeMap<ShapeType, Work> = BTreeMap::new();
    progress.start("merging shards", u64::from(count));
    for (index, path) in (0..count).zip(&paths) {
        let shard = ShardFile::read(path)?;
        let expected = ShardFile {
            shard: Some(Shard { index, count }),
            ..expected.clone()
        };
        shard.check(&expected, path)?;
        for (set, stats) in engine.sets.iter().zip(acc.iter_mut()) {
            let part = shard
                .stats
                .get(&set.shape_type)
                .filter(|p| p.len() == stats.len())
                .ok_or_else(|| {
                    Error::input(
                        path,
                        format!("stats.{}", set.shape_type),
                        "missing or of the wrong length",
                    )
                })?;
            stats.iter_mut().zip(part).for_each(|(s, p)| s.merge(p));
        }
        for (t, w) in &shard.work {
            work.entry(*t).or_default().add(w);
        }
        progress.advance(1);
    }
    progress.finish();
    phases.sampling = laps.lap();
    let files = finalize::finalize(&engine, opts, acc);
    phases.search = laps.lap();
    let mesh = mesh::mesh_verdicts(&urdd, &engine, opts, &files, progress)?;
    phases.verdicts = laps.lap();
    write_stage(&mut urdd, opts, key, &files, &mesh, &work)?;
    Ok(SampleReport {
        mesh: Some(mesh.summary.clone()),
        work,
        urdd: opts.urdd.clone(),
        up_to_date: false,
        shard_file: None,
        samples: opts.samples,
        types: files
            .iter()
            .map(|f| (f.shape_type, f.summary.clone()))
            .collect(),
        seconds: phases.after_load(),
        phases,
        notes: Vec::new(),
    })
}

/// The key: the preprocess key it reads and the options.
fn stage_key(urdd: &Urdd, opts: &SampleOptions) -> Result<String> {
    let pre = urdd.stage(PREPROCESS)?;
    Ok(crate::urdd::stage_key(
        SAMPLE,
        serde_json::json!({ "preprocess": pre.key, "options": parameters(SAMPLE, opts)? }),
    ))
}

fn write_stage(
    urdd: &mut Urdd,
    opts: &SampleOptions,
    key: String,
    files: &[SampleFile],
    mesh: &MeshFile,
    work: &BTreeMap<ShapeType, Work>,
) -> Result<()> {
    let stage = StageDir::create(&opts.urdd.join(SAMPLE))?;
    let mut outputs = Vec::new();
    for f in files {
        let name = sample_file_name(f.shape_type);
        // Compact JSON: the pair lists of decomposition types are large.
        stage.write_json(&name, f)?;
        outputs.push(name);
    }
    stage.write(MESH_FILE, &json_bytes(MESH_FILE, mesh)?)?;
    outputs.push(MESH_FILE.to_string());
    stage.commit()?;
    let robot = urdd.manifest().robot.clone();
    let preprocess_key = urdd.stage(PREPROCESS)?.key.clone();
    let summary: BTreeMap<ShapeType, TypeSummary> = files
        .iter()
        .map(|f| (f.shape_type, f.summary.clone()))
        .collect();
    urdd.record_stage(
        SAMPLE,
        &robot,
        StageRecord {
            key,
            tool_version: crate::VERSION.into(),
            inputs: Vec::new(),
            parameters: parameters(SAMPLE, opts)?,
            folder: SAMPLE.into(),
            outputs,
            stamps: Default::default(),
            summary: serde_json::json!({ "types": summary, "mesh": &mesh.summary, "work": work }),
            depends_on: [(PREPROCESS.to_string(), preprocess_key)].into(),
        },
    )
}
