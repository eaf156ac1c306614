//! The skip matrices: per shape type, which pairs a collision check may skip and why, resolved from
//! three layers. Sampling infers a verdict for every pair (`inferred`); `scm import-moveit` stores a
//! MoveIt SRDF's link pairs (`imported`); the viewer stores a person's marks (`user`). A higher layer
//! overrides a lower one for the pairs it names (user > imported > inferred), and sampling never
//! rewrites the imported or user layers.

mod heatmap;
mod imported;
mod links;
mod user;

pub use heatmap::{Cell, HeatMap, SHADE_RANGE, Verdict};
pub use imported::{IMPORTED_FILE, ImportedLayer, ImportedLookup, ImportedPair};
pub use links::{LinkPair, consumer_link_pairs};
pub use user::{USER_FILE, UserEdit, UserLayer};

use crate::error::{Error, Result};
use crate::sample::{PairRecord, SAMPLE, SampleFile, sample_file_name};
use crate::shapes::ShapeType;
use crate::urdd::{ShapeRecord, Urdd};
use serde::{Deserialize, Serialize};

pub use crate::urdd::LAYERS;

/// Which layer decided a pair's verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Layer {
    /// Inferred by sampling.
    Inferred,
    /// Imported from a MoveIt SRDF.
    Imported,
    /// Set by a person (the viewer).
    User,
}

impl Layer {
    /// The id used in files.
    pub fn id(self) -> &'static str {
        match self {
            Layer::Inferred => "inferred",
            Layer::Imported => "imported",
            Layer::User => "user",
        }
    }
}

/// A shape named stably by its link and decomposition piece, so edits survive re-preprocessing.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct ShapeKey {
    /// Link name.
    pub link: String,
    /// Decomposition piece (0 for whole-link types).
    pub piece: usize,
}

impl ShapeKey {
    /// The key of a shape record.
    pub fn of(shape: &ShapeRecord) -> ShapeKey {
        ShapeKey {
            link: shape.link.clone(),
            piece: shape.piece,
        }
    }
}

impl std::fmt::Display for ShapeKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}#{}", self.link, self.piece)
    }
}

/// The resolved verdict of one pair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Entry {
    /// Whether a collision check may skip the pair.
    pub skip: bool,
    /// Why: scm's reason id for `inferred` (`never`, `checked`, ...), MoveIt's reason for `imported`
    /// (`Never`, `Adjacent`, ..., `enabled` for `<enable_collisions>`), `user` for `user`.
    pub reason: String,
    /// The layer that decided.
    pub layer: Layer,
}

/// The effective skip matrix of one shape type, with the sampling statistics of every pair.
#[derive(Debug, Clone)]
pub struct SkipMatrix {
    /// The shape type.
    pub shape_type: ShapeType,
    /// Shapes in matrix order.
    pub shapes: Vec<ShapeRecord>,
    /// One entry per pair `a < b`, row-major (the order of [`SampleFile::pairs`]).
    pub entries: Vec<Entry>,
    /// The sampling statistics, in the same order.
    pub stats: Vec<PairRecord>,
    /// Samples drawn.
    pub samples: u64,
}

impl SkipMatrix {
    /// Loads the matrix of `shape_type`: the current sample output with the imported and user layers
    /// applied. A missing or stale sample stage, or a type that was not sampled, is bad input.
    pub fn load(urdd: &Urdd, shape_type: ShapeType) -> Result<SkipMatrix> {
        let sample = load_sample(urdd, shape_type)?;
        let shapes = urdd.shapes(shape_type)?.shapes;
        let imported = ImportedLayer::load(urdd)?;
        let user = UserLayer::load(urdd)?;
        SkipMatrix::resolve(shapes, sample, imported.as_ref(), &user)
    }

    /// Resolves the layers over a type's shapes and sample output (which must agree in size).
    pub fn resolve(
        shapes: Vec<ShapeRecord>,
        sample: SampleFile,
        imported: Option<&ImportedLayer>,
        user: &UserLayer,
    ) -> Result<SkipMatrix> {
        let n = shapes.len();
        if sample.pairs.len() != n * n.saturating_sub(1) / 2 {
            return Err(Error::Failed {
                context: format!("{} matrix", sample.shape_type),
                message: format!(
                    "the sample output has {} pairs but the shape list has {n} shapes; rerun `scm sample`",
                    sample.pairs.len()
                ),
            });
        }
        let imported = imported.map(ImportedLayer::lookup);
        let edits = user.lookup(sample.shape_type);
        let entries = sample
            .pairs
            .iter()
            .map(|p| {
                let (sa, sb) = (&shapes[p.a], &shapes[p.b]);
                let (ka, kb) = (ShapeKey::of(sa), ShapeKey::of(sb));
                if let Some(&skip) = edits.get(&ordered(ka, kb)) {
                    return Entry {
                        skip,
                        reason: "user".into(),
                        layer: Layer::User,
                    };
                }
                if let Some((skip, reason)) =
                    imported.as_ref().and_then(|m| m.get(&sa.link, &sb.link))
                {
                    return Entry {
                        skip,
                        reason: reason.into(),
                        layer: Layer::Imported,
                    };
                }
                Entry {
                    skip: p.reason.skips(),
                    reason: p.reason.id().into(),
                    layer: Layer::Inferred,
                }
            })
            .collect();
        Ok(SkipMatrix {
            shape_type: sample.shape_type,
            shapes,
            entries,
            stats: sample.pairs,
            samples: sample.samples,
        })
    }

    /// Number of shapes (rows).
    pub fn len(&self) -> usize {
        self.shapes.len()
    }

    /// Whether the type has no shapes.
    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }

    /// The position of pair `{a, b}` (`a != b`, any order) in `entries` and `stats`.
    pub fn pair_index(&self, a: usize, b: usize) -> usize {
        pair_index(self.len(), a.min(b), a.max(b))
    }

    /// The entry of pair `{a, b}` (`a != b`).
    pub fn entry(&self, a: usize, b: usize) -> &Entry {
        &self.entries[self.pair_index(a, b)]
    }

    /// Whether a check may skip pair `{a, b}`; a shape against itself is always skipped.
    pub fn skip(&self, a: usize, b: usize) -> bool {
        a == b || self.entry(a, b).skip
    }

    /// The stable key of shape `i`.
    pub fn key(&self, i: usize) -> ShapeKey {
        ShapeKey::of(&self.shapes[i])
    }

    /// The dense symmetric N x N skip matrix (the diagonal is `true`).
    pub fn dense(&self) -> Vec<Vec<bool>> {
        let n = self.len();
        (0..n)
            .map(|a| (0..n).map(|b| self.skip(a, b)).collect())
            .collect()
    }
}

/// Index of pair `a < b` among the `n (n - 1) / 2` pairs in row-major order.
pub fn pair_index(n: usize, a: usize, b: usize) -> usize {
    debug_assert!(a < b && b < n);
    a * (2 * n - a - 1) / 2 + (b - a - 1)
}

/// The sample output of one type; the stage must exist, be current and include the type.
pub fn load_sample(urdd: &Urdd, shape_type: ShapeType) -> Result<SampleFile> {
    let name = sample_file_name(shape_type);
    urdd.sample_output(&name)?.ok_or_else(|| {
        Error::input(
            &urdd.dir().join(SAMPLE),
            name,
            format!(
                "type {shape_type} was not sampled; rerun `scm sample {} --types ...` including it",
                urdd.dir().display()
            ),
        )
    })
}

/// The two keys in canonical order.
fn ordered(a: ShapeKey, b: ShapeKey) -> (ShapeKey, ShapeKey) {
    if a <= b { (a, b) } else { (b, a) }
}

#[cfg(test)]
mod tests {
    use super::pair_index;

    #[test]
    fn pair_index_is_row_major() {
        let n = 5;
        let mut k = 0;
        for a in 0..n {
            for b in a + 1..n {
                assert_eq!(pair_index(n, a, b), k);
                k += 1;
            }
        }
    }
}
