//! `scm bench`: the evidence for the skip matrices. Per shape type, over fresh random configurations
//! (a seed and stream that sampling never uses):
//! - tables 1 and 2: query time with skips / without skips for collision and proximity queries, mean
//!   and standard deviation over repeats, and the absolute time per query ([`timing`]);
//! - table 3: the verdict with skips against the robot's original triangle meshes checked exactly
//!   ([`accuracy`], [`truth`]).
//!
//! Writes `DIR/bench/bench.md` and `DIR/bench/bench.json` atomically and records a `bench` stage.
//!
//! `scm bench --scale` ([`scale`]) measures instead how sampling grows with the robot: time and peak
//! memory of `scm sample` child processes ([`child`]) against links, pieces and pairs.

pub mod accuracy;
pub mod child;
mod markdown;
pub mod scale;
pub mod timing;
pub mod truth;

pub use accuracy::Accuracy;
pub use markdown::render;
pub use scale::{ScaleOptions, ScaleReport, render_scale, scale};
pub use timing::{QueryKind, Timing};
pub use truth::MeshTruth;

use crate::error::Result;
use crate::progress::Progress;
use crate::query::{SelfChecker, SkipMode};
use crate::rng::Rng;
use crate::robot::{Dof, Kinematics, random_configuration};
use crate::sample::SAMPLE;
use crate::shapes::ShapeType;
use crate::urdd::{StageDir, StageRecord, Urdd, json_bytes};
use crate::urdd::{parameters, stage_key};
use serde::Serialize;
use std::path::{Path, PathBuf};

pub use crate::urdd::BENCH;

/// The random stream bench configurations come from. Sampling uses streams 0, 1, 2, ... (one per chunk
/// of 1,024 samples), so this one never repeats a sampled configuration, whatever the seed.
pub const BENCH_STREAM: u64 = 0xBE_4C00_0000_0000;

/// What to measure.
#[derive(Debug, Clone, Serialize)]
pub struct BenchOptions {
    /// The URDD directory (after `scm sample`).
    pub urdd: PathBuf,
    /// Configurations for the timing tables.
    pub configs: usize,
    /// Timing repeats (mean and standard deviation are over these).
    pub repeats: u32,
    /// Configurations for the mesh ground-truth table (the first ones of the same stream).
    pub truth_configs: usize,
    /// Seed of the configurations.
    pub seed: u64,
    /// Shape types (default: every sampled type).
    pub types: Vec<ShapeType>,
}

impl BenchOptions {
    /// The defaults: 5,000 configurations timed 5 times, 2,000 against the meshes, seed 1, every
    /// sampled type.
    pub fn new(urdd: &Path) -> BenchOptions {
        BenchOptions {
            urdd: urdd.to_path_buf(),
            configs: 5000,
            repeats: 5,
            truth_configs: 2000,
            seed: 1,
            types: Vec::new(),
        }
    }
}

/// The measurements of one shape type.
#[derive(Debug, Clone, Serialize)]
pub struct TypeBench {
    /// The shape type.
    pub shape_type: ShapeType,
    /// Number of shapes.
    pub shapes: usize,
    /// Number of shape pairs.
    pub pairs: usize,
    /// Pairs checked with skips.
    pub checked: usize,
    /// Every colliding pair: with / without skips.
    pub collisions: Timing,
    /// Is anything in collision, stopping at the first hit: with / without skips.
    pub first_hit: Timing,
    /// Minimum distance: with / without skips.
    pub proximity: Timing,
    /// Fraction of the timing configurations in collision with skips.
    pub collision_fraction: f64,
    /// The verdict with skips against the exact meshes.
    pub accuracy: Accuracy,
}

/// Everything `scm bench` measured.
#[derive(Debug, Clone, Serialize)]
pub struct BenchReport {
    /// The URDD directory.
    pub urdd: PathBuf,
    /// Robot name.
    pub robot: String,
    /// The options used.
    pub options: BenchOptions,
    /// Link pairs the mesh ground truth checks: with geometry, not adjacent, not colliding at home.
    pub truth_pairs: usize,
    /// Non-adjacent link pairs left out of the ground truth because their meshes collide at home.
    pub truth_at_home: Vec<[String; 2]>,
    /// Skip reasons that can hide a mesh collision (columns of table 3).
    pub reasons: Vec<String>,
    /// One entry per type.
    pub types: Vec<TypeBench>,
    /// Seconds spent.
    pub seconds: f64,
}

/// `count` configurations uniform within the joint limits from (`seed`, [`BENCH_STREAM`]).
pub fn configurations(dofs: &[Dof], seed: u64, count: usize) -> Vec<Vec<f64>> {
    let mut rng = Rng::new(seed, BENCH_STREAM);
    (0..count)
        .map(|_| {
            let mut q = Vec::new();
            random_configuration(dofs, &mut rng, &mut q);
            q
        })
        .collect()
}

/// The types to measure: the requested ones, or every type the sample stage has a file for.
fn selected_types(urdd: &Urdd, requested: &[ShapeType]) -> Result<Vec<ShapeType>> {
    Ok(if requested.is_empty() {
        urdd.sampled_types()?
    } else {
        requested.to_vec()
    })
}

/// Runs the benchmark and writes `DIR/bench/`.
pub fn bench(opts: &BenchOptions, progress: &dyn Progress) -> Result<BenchReport> {
    let start = std::time::Instant::now();
    let (mut urdd, _lock) = Urdd::open_for_writing(&opts.urdd, progress)?;
    let types = selected_types(&urdd, &opts.types)?;
    // Load every checker first, so bad input fails before any long work.
    let mut checkers = Vec::new();
    for &t in &types {
        checkers.push((
            SelfChecker::load(&urdd, t, SkipMode::Skips)?,
            SelfChecker::load(&urdd, t, SkipMode::NoSkips)?,
        ));
    }
    let robot = urdd.robot()?;
    let kinematics = Kinematics::new(&robot.robot);
    let truth = MeshTruth::load(&urdd)?;
    let configs = configurations(kinematics.dofs(), opts.seed, opts.configs);
    let truth_configs = configurations(kinematics.dofs(), opts.seed, opts.truth_configs);

    progress.start("mesh ground truth", truth_configs.len() as u64);
    let mesh = accuracy::ground_truth(&truth, &kinematics, &truth_configs, &|| progress.advance(1));
    progress.finish();

    let reasons = hiding_reasons(&checkers, &truth);
    let mut out = Vec::new();
    progress.start(
        "timing queries",
        u64::from(opts.repeats) * 3 * types.len() as u64,
    );
    for (skips, no_skips) in &checkers {
        let tick = || progress.advance(1);
        let time = |kind| timing::time_query(skips, no_skips, kind, &configs, opts.repeats, &tick);
        let collisions = time(QueryKind::Collisions);
        let first_hit = time(QueryKind::FirstHit);
        let proximity = time(QueryKind::Proximity);
        let mut scratch = skips.scratch();
        let colliding = configs
            .iter()
            .filter(|q| skips.in_collision(q, &mut scratch).unwrap_or(false))
            .count();
        let n = skips.shapes().len();
        out.push(TypeBench {
            shape_type: skips.shape_type(),
            shapes: n,
            pairs: n * n.saturating_sub(1) / 2,
            checked: skips.checked_pairs().len(),
            collisions,
            first_hit,
            proximity,
            collision_fraction: colliding as f64 / configs.len().max(1) as f64,
            accuracy: accuracy::against_meshes(skips, no_skips, &truth_configs, &mesh, &reasons),
        });
    }
    progress.finish();

    let report = BenchReport {
        urdd: opts.urdd.clone(),
        robot: urdd.manifest().robot.clone(),
        options: BenchOptions {
            types: types.clone(),
            ..opts.clone()
        },
        truth_pairs: truth.pairs().len(),
        truth_at_home: truth
            .at_home()
            .iter()
            .map(|&(a, b)| [link_name(&robot, a), link_name(&robot, b)])
            .collect(),
        reasons,
        types: out,
        seconds: start.elapsed().as_secs_f64(),
    };
    write(&mut urdd, &report)?;
    Ok(report)
}

fn link_name(robot: &crate::urdd::RobotRecord, i: usize) -> String {
    robot.robot.links[i].name.clone()
}

/// The skip reasons of shape pairs between different, non-adjacent links (the pairs the ground truth
/// checks), over every measured type: the reasons that could hide a mesh collision.
fn hiding_reasons(checkers: &[(SelfChecker, SelfChecker)], truth: &MeshTruth) -> Vec<String> {
    let mut reasons = std::collections::BTreeSet::new();
    for (skips, _) in checkers {
        let shapes = skips.shapes();
        for a in 0..shapes.len() {
            for b in a + 1..shapes.len() {
                let (x, y) = (shapes[a].link_index, shapes[b].link_index);
                if truth.pairs().contains(&(x.min(y), x.max(y)))
                    && let Some(r) = skips.skip_reason(a, b)
                {
                    reasons.insert(r.to_string());
                }
            }
        }
    }
    reasons.into_iter().collect()
}

/// Writes `bench.md` and `bench.json` into `DIR/bench/` (swapped in whole) and records the stage.
fn write(urdd: &mut Urdd, report: &BenchReport) -> Result<()> {
    let stage = StageDir::create(&urdd.dir().join(BENCH))?;
    stage.write("bench.md", render(report).as_bytes())?;
    stage.write("bench.json", &json_bytes("bench.json", report)?)?;
    stage.commit()?;
    let parameters = parameters(BENCH, &report.options)?;
    let sample_key = urdd.stage(SAMPLE)?.key.clone();
    // Timings differ between runs, so bench always runs; the key only identifies what it measured.
    let key = stage_key(
        BENCH,
        serde_json::json!({ "sample": sample_key, "parameters": parameters }),
    );
    let robot = report.robot.clone();
    urdd.record_stage(
        BENCH,
        &robot,
        StageRecord {
            key,
            tool_version: crate::VERSION.into(),
            inputs: Vec::new(),
            parameters,
            folder: BENCH.into(),
            outputs: vec!["bench.md".into(), "bench.json".into()],
            stamps: Default::default(),
            summary: serde_json::json!({ "types": report.types.len(), "seconds": report.seconds }),
            depends_on: [(SAMPLE.to_string(), sample_key)].into(),
        },
    )
}
