//! The sample stage's output records: one file per shape type with every pair's statistics and reason.

use super::reasons::Reason;
use super::search::SearchOutcome;
use crate::shapes::ShapeType;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

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
    /// Samples in `d_mean`: enough for a 3-sigma error under 1% (from a 256-sample pilot), capped by
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
