//! The `sample` stage: N random joint configurations, per-pair distance statistics for every selected
//! shape type, skip inference with reasons, and a targeted search that overturns wrong "never" verdicts.
//!
//! Determinism: sample k is drawn from the random stream of its chunk (k / 1024) under the seed, and the
//! statistics merge exactly (fixed-point sums, smallest-index witnesses), so any thread count and any
//! sharding give the same bytes.

mod engine;
mod reasons;
mod rng;
mod search;
mod stats;
mod table;

pub use engine::{CHUNK, Engine};
pub use reasons::{Evidence, Reason, infer, never_upper_bound};
pub use search::{SearchOutcome, SearchParams, path_dofs, search_pair};
pub use stats::PairStats;

use crate::error::{Error, Result};
use crate::progress::Progress;
use crate::shapes::ShapeType;
use crate::urdd::{
    FORMAT_VERSION, PREPROCESS, StageDir, StageRecord, Urdd, json_bytes, read_json_file,
    sha256_hex, write_atomic,
};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};

/// Folder of the sample stage.
pub const SAMPLE: &str = "sample";
/// Folder of shard partial results.
pub const SHARDS: &str = "sample-shards";

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
    /// The first this many samples enter d_mean exactly (all samples when >= `samples`).
    pub mean_samples: u64,
    /// d_min and d_max are within this many metres of the exact extremes over the samples (0: exact).
    pub tolerance: f64,
    /// Targeted search.
    pub search: SearchParams,
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
    /// samples, d_min/d_max within 0.05 mm.
    pub fn new(urdd: &Path) -> SampleOptions {
        SampleOptions {
            urdd: urdd.to_path_buf(),
            samples: 100_000,
            seed: 0,
            types: ShapeType::ALL.to_vec(),
            always_fraction: 0.95,
            mean_samples: 25_000,
            tolerance: 5e-5,
            search: SearchParams::default(),
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
    /// Seconds spent sampling (not counting loading and writing).
    pub seconds: f64,
}

/// Per-type counts.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TypeSummary {
    /// Shapes of this type.
    pub shapes: usize,
    /// Pairs per reason.
    pub reasons: BTreeMap<Reason, usize>,
    /// Pairs the targeted search examined.
    pub searched: usize,
    /// `never` verdicts the search overturned (a collision was found).
    pub overturned: usize,
}

/// `sample/<type>.json`: statistics and reasons of every pair of one type.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SampleFile {
    /// Format version.
    pub format_version: u32,
    /// The shape type.
    pub shape_type: ShapeType,
    /// Samples drawn.
    pub samples: u64,
    /// Seed.
    pub seed: u64,
    /// Most samples whose exact distance entered a pair's d_mean (each pair records its own count).
    pub mean_samples: u64,
    /// The `always` threshold.
    pub always_fraction: f64,
    /// 95% upper bound on the collision probability of a `never` pair (about 3 / samples).
    pub never_upper_bound: f64,
    /// Counts.
    pub summary: TypeSummary,
    /// One record per pair `a < b` in row-major order.
    pub pairs: Vec<PairRecord>,
}

/// The statistics and verdict of one shape pair. Distances are signed: negative is penetration depth.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairRecord {
    /// Row shape index.
    pub a: usize,
    /// Column shape index.
    pub b: usize,
    /// Why the pair may be skipped, or `checked`.
    pub reason: Reason,
    /// Minimum signed distance over the samples (m).
    pub d_min: f64,
    /// Mean signed distance (m) over the first `mean_samples` samples (exact distances).
    pub d_mean: f64,
    /// Samples in `d_mean`: enough for a 3-sigma error under 1% (from a 512-sample pilot), capped by
    /// the file's `mean_samples`.
    pub mean_samples: u64,
    /// Maximum signed distance (m).
    pub d_max: f64,
    /// Samples in collision.
    pub collisions: u64,
    /// `collisions / samples`.
    pub collision_fraction: f64,
    /// Signed distance at the home configuration.
    pub home_distance: f64,
    /// Where `d_min` was reached: sample index (absent for rigid pairs) and configuration.
    pub witness: Witness,
    /// The targeted search's result, for pairs it examined.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub search: Option<SearchOutcome>,
}

/// A configuration where something was observed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Witness {
    /// The sample index, when it came from sampling.
    pub sample: Option<u64>,
    /// Joint values, one per DOF.
    pub q: Vec<f64>,
}

/// A shard's partial result: exact accumulators of its chunks.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct ShardFile {
    key: String,
    shard: Shard,
    stats: BTreeMap<ShapeType, Vec<PairStats>>,
}

/// The sample stage's output path for a type, relative to the URDD.
pub fn sample_file_name(t: ShapeType) -> String {
    format!("{}.json", t.id())
}

/// Runs the sample stage (or one shard of it).
pub fn sample(opts: &SampleOptions, progress: &dyn Progress) -> Result<SampleReport> {
    let mut urdd = Urdd::open(&opts.urdd)?;
    let key = stage_key(&urdd, opts)?;
    let report = |up_to_date, shard_file, types, seconds| SampleReport {
        urdd: opts.urdd.clone(),
        up_to_date,
        shard_file,
        samples: opts.samples,
        types,
        seconds,
    };
    if opts.shard.is_none() && !opts.force && urdd.is_up_to_date(SAMPLE, &key) {
        let types = serde_json::from_value(urdd.stage(SAMPLE)?.summary.clone()).unwrap_or_default();
        return Ok(report(true, None, types, 0.0));
    }
    let engine = Engine::load(&urdd, &opts.types)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.unwrap_or(0))
        .build()
        .map_err(|e| Error::Failed {
            context: "sample".into(),
            message: format!("cannot start threads: {e}"),
        })?;
    let started = std::time::Instant::now();
    let chunks: Vec<u64> = (0..opts.samples.div_ceil(CHUNK))
        .filter(|c| {
            opts.shard
                .is_none_or(|s| c % u64::from(s.count) == u64::from(s.index))
        })
        .collect();
    progress.start("sampling", chunks.len() as u64 * CHUNK.min(opts.samples));
    let acc = pool.install(|| accumulate(&engine, opts, &chunks, progress));
    progress.finish();

    if let Some(shard) = opts.shard {
        let name = Shard::file(shard.count, shard.index);
        let file = ShardFile {
            key,
            shard,
            stats: engine.sets.iter().map(|s| s.shape_type).zip(acc).collect(),
        };
        write_atomic(&opts.urdd.join(SHARDS).join(&name), &json_bytes(&file))?;
        return Ok(report(
            false,
            Some(format!("{SHARDS}/{name}")),
            BTreeMap::new(),
            started.elapsed().as_secs_f64(),
        ));
    }
    let files = pool.install(|| finalize(&engine, opts, acc, progress));
    let seconds = started.elapsed().as_secs_f64();
    write_stage(&mut urdd, opts, key, &files)?;
    Ok(report(
        false,
        None,
        files
            .iter()
            .map(|f| (f.shape_type, f.summary.clone()))
            .collect(),
        seconds,
    ))
}

/// Merges the `count` shard files in the URDD into the sample stage output (identical to one run).
pub fn merge_shards(
    opts: &SampleOptions,
    count: u32,
    progress: &dyn Progress,
) -> Result<SampleReport> {
    let mut urdd = Urdd::open(&opts.urdd)?;
    let key = stage_key(&urdd, opts)?;
    let engine = Engine::load(&urdd, &opts.types)?;
    let mut acc: Vec<Vec<PairStats>> = engine
        .sets
        .iter()
        .map(|s| vec![PairStats::default(); s.pairs.len()])
        .collect();
    for index in 0..count {
        let path = opts.urdd.join(SHARDS).join(Shard::file(count, index));
        if !path.is_file() {
            return Err(Error::input(
                &path,
                "shard",
                format!(
                    "missing; run `scm sample {} --shard {index}/{count}`",
                    opts.urdd.display()
                ),
            ));
        }
        let shard: ShardFile = read_json_file(&path)?;
        if shard.key != key {
            return Err(Error::input(
                &path,
                "key",
                "computed with other parameters or another preprocess output; rerun this shard",
            ));
        }
        for (set, stats) in engine.sets.iter().zip(acc.iter_mut()) {
            let part = shard
                .stats
                .get(&set.shape_type)
                .filter(|p| p.len() == stats.len())
                .ok_or_else(|| {
                    Error::input(
                        &path,
                        format!("stats.{}", set.shape_type),
                        "missing or of the wrong length",
                    )
                })?;
            stats.iter_mut().zip(part).for_each(|(s, p)| s.merge(p));
        }
    }
    let started = std::time::Instant::now();
    let files = finalize(&engine, opts, acc, progress);
    write_stage(&mut urdd, opts, key, &files)?;
    Ok(SampleReport {
        urdd: opts.urdd.clone(),
        up_to_date: false,
        shard_file: None,
        samples: opts.samples,
        types: files
            .iter()
            .map(|f| (f.shape_type, f.summary.clone()))
            .collect(),
        seconds: started.elapsed().as_secs_f64(),
    })
}

fn stage_key(urdd: &Urdd, opts: &SampleOptions) -> Result<String> {
    let pre = urdd.stage(PREPROCESS)?;
    let material = serde_json::json!({
        "stage": SAMPLE,
        "format_version": FORMAT_VERSION,
        "tool_version": crate::VERSION,
        "preprocess": pre.key,
        "options": parameters(opts),
    });
    Ok(sha256_hex(&json_bytes(&material)))
}

fn parameters(opts: &SampleOptions) -> serde_json::Value {
    let mut v = serde_json::to_value(opts).unwrap_or_default();
    if let Some(m) = v.as_object_mut() {
        m.remove("urdd");
    }
    v
}

/// Samples of the pilot run that sizes each pair's exact-mean budget.
const PILOT: u64 = 512;

/// How many leading samples enter each pair's mean exactly: enough for a 3-sigma error under 1% of the
/// mean, judged from a pilot of the first [`PILOT`] samples, between `2 * PILOT` and `opts.mean_samples`.
/// Depends only on the seed and the robot, so every thread count and shard gets the same budgets.
fn mean_budgets(engine: &Engine, opts: &SampleOptions) -> Vec<Vec<u64>> {
    let cap = opts.mean_samples.min(opts.samples);
    if cap <= 2 * PILOT {
        return engine
            .sets
            .iter()
            .map(|s| vec![cap; s.pairs.len()])
            .collect();
    }
    let pilot_budget: Vec<Vec<u64>> = engine
        .sets
        .iter()
        .map(|s| vec![PILOT; s.pairs.len()])
        .collect();
    let run = engine::ChunkRun {
        seed: opts.seed,
        total: PILOT,
        mean_budget: &pilot_budget,
        tol: opts.tolerance,
    };
    let mut pilot: Vec<Vec<PairStats>> = engine
        .sets
        .iter()
        .map(|s| vec![PairStats::default(); s.pairs.len()])
        .collect();
    engine.run_chunk(&run, 0, &mut pilot, &mut engine::Scratch::default());
    pilot
        .iter()
        .map(|stats| {
            stats
                .iter()
                .map(|st| {
                    let (mean, std) = (st.mean().abs(), st.std());
                    let needed = if mean > 0.0 {
                        (3.0 * std / (0.01 * mean)).powi(2).ceil()
                    } else {
                        f64::INFINITY
                    };
                    (needed.min(cap as f64) as u64).max(2 * PILOT).min(cap)
                })
                .collect()
        })
        .collect()
}

/// Runs the chunks in parallel. Each chunk starts from empty accumulators (see [`Engine::run_chunk`]);
/// chunk results merge exactly in any order.
fn accumulate(
    engine: &Engine,
    opts: &SampleOptions,
    chunks: &[u64],
    progress: &dyn Progress,
) -> Vec<Vec<PairStats>> {
    let empty = || -> Vec<Vec<PairStats>> {
        engine
            .sets
            .iter()
            .map(|s| vec![PairStats::default(); s.pairs.len()])
            .collect()
    };
    let budgets = mean_budgets(engine, opts);
    let run = engine::ChunkRun {
        seed: opts.seed,
        total: opts.samples,
        mean_budget: &budgets,
        tol: opts.tolerance,
    };
    let merge = |mut a: Vec<Vec<PairStats>>, b: &[Vec<PairStats>]| {
        for (x, y) in a.iter_mut().zip(b) {
            x.iter_mut().zip(y).for_each(|(s, o)| s.merge(o));
        }
        a
    };
    chunks
        .par_iter()
        .fold(
            || (empty(), empty(), engine::Scratch::default()),
            |(total, mut chunk, mut scratch), &c| {
                chunk.iter_mut().for_each(|v| v.fill(PairStats::default()));
                engine.run_chunk(&run, c, &mut chunk, &mut scratch);
                progress.advance(CHUNK.min(opts.samples - c * CHUNK));
                (merge(total, &chunk), chunk, scratch)
            },
        )
        .map(|(total, _, _)| total)
        .reduce(empty, |a, b| merge(a, &b))
}

/// Rigid pairs, home distances, reasons, witnesses and the targeted search: from exact accumulators to files.
fn finalize(
    engine: &Engine,
    opts: &SampleOptions,
    acc: Vec<Vec<PairStats>>,
    progress: &dyn Progress,
) -> Vec<SampleFile> {
    let home = engine.kinematics.home();
    let adjacent: BTreeSet<(usize, usize)> = engine.robot.adjacent_pairs().into_iter().collect();
    // Witness configurations, generated once per distinct sample index.
    let witness_samples: BTreeSet<u64> = acc
        .iter()
        .flatten()
        .filter(|s| s.min_sample != u64::MAX)
        .map(|s| s.min_sample)
        .collect();
    let configs: HashMap<u64, Vec<f64>> = witness_samples
        .into_par_iter()
        .map(|k| (k, engine.configuration(opts.seed, k)))
        .collect();
    let n = opts.samples;
    let mean_samples = opts.mean_samples.min(n);

    let mut files = Vec::new();
    for (s, (set, stats)) in engine.sets.iter().zip(acc).enumerate() {
        let mut pairs: Vec<PairRecord> = set
            .pairs
            .par_iter()
            .enumerate()
            .map(|(p, &(i, j))| {
                let (la, lb) = (set.links[i as usize], set.links[j as usize]);
                let home_distance = engine.pair_distance(s, p, &home);
                let (st, witness) = if set.moving[p] {
                    let st = stats[p];
                    (
                        st,
                        Witness {
                            sample: Some(st.min_sample),
                            q: configs.get(&st.min_sample).cloned().unwrap_or_default(),
                        },
                    )
                } else {
                    // Rigid: the distance is the same in every sample.
                    let c = u64::from(home_distance <= 0.0) * n;
                    let mut st = PairStats {
                        collisions: c,
                        ..PairStats::default()
                    };
                    st.observe_extremes(home_distance, 0);
                    st.sum = (home_distance * 1e12).round() as i128 * i128::from(mean_samples);
                    st.mean_count = mean_samples;
                    (
                        st,
                        Witness {
                            sample: None,
                            q: home.clone(),
                        },
                    )
                };
                let collision_fraction = if n == 0 {
                    0.0
                } else {
                    st.collisions as f64 / n as f64
                };
                let evidence = Evidence {
                    same_link: la == lb,
                    adjacent: adjacent.contains(&(la.min(lb), la.max(lb))),
                    home_collision: home_distance <= 0.0,
                    collision_fraction,
                    search_collision: false,
                };
                let mut record = PairRecord {
                    a: i as usize,
                    b: j as usize,
                    reason: infer(&evidence, opts.always_fraction),
                    d_min: st.min,
                    d_mean: st.mean(),
                    mean_samples: st.mean_count,
                    d_max: st.max,
                    collisions: st.collisions,
                    collision_fraction,
                    home_distance,
                    witness,
                    search: None,
                };
                if record.reason == Reason::Never
                    && set.moving[p]
                    && record.d_min < opts.search.margin
                {
                    let outcome =
                        search_pair(engine, s, p, &record.witness.q, opts.seed, &opts.search);
                    if outcome.collision {
                        record.reason = infer(
                            &Evidence {
                                search_collision: true,
                                ..evidence
                            },
                            opts.always_fraction,
                        );
                    }
                    record.search = Some(outcome);
                }
                record
            })
            .collect();
        pairs.sort_by_key(|r| (r.a, r.b));
        let mut summary = TypeSummary {
            shapes: set.shapes.len(),
            ..TypeSummary::default()
        };
        for r in &pairs {
            *summary.reasons.entry(r.reason).or_default() += 1;
            if let Some(o) = &r.search {
                summary.searched += 1;
                summary.overturned += usize::from(o.collision);
            }
        }
        progress.advance(0);
        files.push(SampleFile {
            format_version: FORMAT_VERSION,
            shape_type: set.shape_type,
            samples: n,
            seed: opts.seed,
            mean_samples,
            always_fraction: opts.always_fraction,
            never_upper_bound: never_upper_bound(n),
            summary,
            pairs,
        });
    }
    files
}

fn write_stage(
    urdd: &mut Urdd,
    opts: &SampleOptions,
    key: String,
    files: &[SampleFile],
) -> Result<()> {
    let stage = StageDir::create(&opts.urdd.join(SAMPLE))?;
    let mut outputs = Vec::new();
    for f in files {
        let name = sample_file_name(f.shape_type);
        // Compact JSON: the pair lists of decomposition types are large.
        let mut bytes = serde_json::to_vec(f).unwrap_or_default();
        bytes.push(b'\n');
        stage.write(&name, &bytes)?;
        outputs.push(name);
    }
    stage.commit()?;
    let robot = urdd.manifest().robot.clone();
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
            parameters: parameters(opts),
            folder: SAMPLE.into(),
            outputs,
            summary: serde_json::to_value(summary).unwrap_or_default(),
        },
    )
}
