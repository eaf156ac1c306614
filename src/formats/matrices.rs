//! The six skip-matrix files (`<type>.json` and `<type>.yaml`): self-describing, one per shape type.

use super::JsonLines;
use crate::matrix::{Layer, SkipMatrix};
use crate::shapes::ShapeType;
use serde::{Deserialize, Serialize};
use serde_saphyr::{FlowMap, FlowSeq};

/// Identifies the file format.
pub const FORMAT: &str = "scm-skip-matrix";

/// One exported matrix: the shapes, the dense skip matrix and every pair's verdict and statistics.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MatrixFile {
    /// Always [`FORMAT`].
    pub format: String,
    /// Version of this format.
    pub format_version: u32,
    /// The robot name.
    pub robot: String,
    /// The shape type.
    pub shape_type: ShapeType,
    /// Samples behind the statistics.
    pub samples: u64,
    /// Shapes in matrix order.
    pub shapes: Vec<FlowMap<MatrixShape>>,
    /// Dense symmetric N x N matrix, `true` = a check may skip the pair (the diagonal is `true`).
    pub skip: Vec<FlowSeq<Vec<bool>>>,
    /// Every pair `a < b` in row-major order.
    pub pairs: Vec<FlowMap<MatrixPair>>,
}

/// A shape of the matrix.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MatrixShape {
    /// Row/column.
    pub index: usize,
    /// Link name.
    pub link: String,
    /// Decomposition piece (0 for whole-link types).
    pub piece: usize,
}

/// One pair's verdict and statistics (distances in metres, negative = penetration depth).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MatrixPair {
    /// Row.
    pub a: usize,
    /// Column.
    pub b: usize,
    /// Whether a check may skip the pair.
    pub skip: bool,
    /// Why (see the layer).
    pub reason: String,
    /// The layer that decided: inferred, imported or user.
    pub layer: Layer,
    /// Minimum signed distance over the samples.
    pub d_min: f64,
    /// Mean signed distance.
    pub d_mean: f64,
    /// Maximum signed distance.
    pub d_max: f64,
    /// Fraction of samples in collision.
    pub collision_fraction: f64,
}

impl MatrixFile {
    /// The file for one resolved matrix.
    pub fn new(robot: &str, m: &SkipMatrix) -> MatrixFile {
        MatrixFile {
            format: FORMAT.into(),
            format_version: crate::urdd::FORMAT_VERSION,
            robot: robot.into(),
            shape_type: m.shape_type,
            samples: m.samples,
            shapes: m
                .shapes
                .iter()
                .map(|s| {
                    FlowMap(MatrixShape {
                        index: s.index,
                        link: s.link.clone(),
                        piece: s.piece,
                    })
                })
                .collect(),
            skip: m.dense().into_iter().map(FlowSeq).collect(),
            pairs: m
                .stats
                .iter()
                .zip(&m.entries)
                .map(|(p, e)| {
                    FlowMap(MatrixPair {
                        a: p.a,
                        b: p.b,
                        skip: e.skip,
                        reason: e.reason.clone(),
                        layer: e.layer,
                        d_min: p.d_min,
                        d_mean: p.d_mean,
                        d_max: p.d_max,
                        collision_fraction: p.collision_fraction,
                    })
                })
                .collect(),
        }
    }

    /// JSON, one line per shape, row and pair.
    pub fn to_json(&self) -> Result<Vec<u8>, String> {
        let mut o = JsonLines::new();
        o.field("format", &self.format);
        o.field("format_version", &self.format_version);
        o.field("robot", &self.robot);
        o.field("shape_type", &self.shape_type);
        o.field("samples", &self.samples);
        o.list("shapes", &self.shapes);
        o.list("skip", &self.skip);
        o.list("pairs", &self.pairs);
        o.finish()
    }

    /// YAML (rows and pairs in flow style, one per line).
    pub fn to_yaml(&self) -> Result<Vec<u8>, String> {
        serde_saphyr::to_string(self)
            .map(String::into_bytes)
            .map_err(|e| e.to_string())
    }
}
