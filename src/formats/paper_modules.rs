//! The paper's original URDD modules (`link_shapes_skips_module`, `link_shapes_distance_statistics_module`),
//! so code written for the paper's tool reads scm's results: each a folder with `VERSION`,
//! `module.json` and `module.yaml`; N x N matrices in scm's shape order.

use crate::matrix::SkipMatrix;
use crate::shapes::ShapeType;
use serde::Serialize;
use serde_saphyr::FlowSeq;
use std::collections::BTreeMap;

/// Folder of the skips module.
pub const SKIPS_MODULE: &str = "link_shapes_skips_module";
/// Folder of the statistics module.
pub const STATISTICS_MODULE: &str = "link_shapes_distance_statistics_module";
/// The module version the paper's tool writes.
pub const VERSION: &str = "0.0.1";

/// The paper's name of a shape type (`full_convex_hulls`, `decomposition_obbs`, ...).
pub fn paper_name(t: ShapeType) -> &'static str {
    match t {
        ShapeType::Hull => "full_convex_hulls",
        ShapeType::Obb => "full_obbs",
        ShapeType::Sphere => "full_bounding_spheres",
        ShapeType::DecompHull => "decomposition_convex_hulls",
        ShapeType::DecompObb => "decomposition_obbs",
        ShapeType::DecompSphere => "decomposition_bounding_spheres",
    }
}

/// The paper's statistics of one type: `averages`, `maximums`, `minimums` (diagonal 0).
#[derive(Debug, Clone, Serialize)]
pub struct Statistics {
    /// Mean distances.
    pub averages: Vec<FlowSeq<Vec<f64>>>,
    /// Maximum distances.
    pub maximums: Vec<FlowSeq<Vec<f64>>>,
    /// Minimum distances.
    pub minimums: Vec<FlowSeq<Vec<f64>>>,
}

/// The skips module: `<paper_name>_skips` per type, ordered as the paper's struct.
pub fn skips_module(matrices: &[SkipMatrix]) -> BTreeMap<String, Vec<FlowSeq<Vec<bool>>>> {
    matrices
        .iter()
        .map(|m| {
            (
                format!("{}_skips", paper_name(m.shape_type)),
                m.dense().into_iter().map(FlowSeq).collect(),
            )
        })
        .collect()
}

/// The statistics module: `<paper_name>` per type.
pub fn statistics_module(matrices: &[SkipMatrix]) -> BTreeMap<String, Statistics> {
    matrices
        .iter()
        .map(|m| {
            let n = m.len();
            let grid = |f: &dyn Fn(&crate::sample::PairRecord) -> f64| {
                (0..n)
                    .map(|a| {
                        FlowSeq(
                            (0..n)
                                .map(|b| {
                                    if a == b {
                                        0.0
                                    } else {
                                        f(&m.stats[m.pair_index(a, b)])
                                    }
                                })
                                .collect(),
                        )
                    })
                    .collect()
            };
            (
                paper_name(m.shape_type).to_string(),
                Statistics {
                    averages: grid(&|p| p.d_mean),
                    maximums: grid(&|p| p.d_max),
                    minimums: grid(&|p| p.d_min),
                },
            )
        })
        .collect()
}
