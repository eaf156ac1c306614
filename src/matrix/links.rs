//! The link-level view of a skip matrix: what SRDF, MJCF, cuRobo and Drake files describe.

use super::{Entry, Layer, SkipMatrix};
use crate::sample::{MeshFile, NeverEvidence, Reason};
use std::collections::BTreeMap;

/// The verdict of one link pair: skipped only when every shape pair between the two links is.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkPair {
    /// One link (earlier in the matrix order).
    pub link1: String,
    /// The other link.
    pub link2: String,
    /// The deciding entry: for a skipped pair, the one from the highest layer; for a checked pair,
    /// the first checked shape pair.
    pub entry: Entry,
    /// The geometry an inferred verdict was decided on: `mesh` (the exact URDF collision geometry), a
    /// shape type's id, or `tree` for `adjacent`; for imported and user verdicts, the layer's id.
    pub geometry: String,
    /// For a `never` decided on the exact geometry: certified or only sampled.
    pub evidence: Option<NeverEvidence>,
}

impl SkipMatrix {
    /// The links that have shapes, in matrix order.
    pub fn links(&self) -> Vec<String> {
        let mut links: Vec<String> = Vec::new();
        for s in &self.shapes {
            if links.last() != Some(&s.link) {
                links.push(s.link.clone());
            }
        }
        links
    }

    /// Every pair of distinct links with shapes, in matrix order, with its link-level verdict.
    pub fn link_pairs(&self) -> Vec<LinkPair> {
        let mut groups: BTreeMap<(usize, usize), Vec<&Entry>> = BTreeMap::new();
        for (p, entry) in self.stats.iter().zip(&self.entries) {
            let (la, lb) = (self.shapes[p.a].link_index, self.shapes[p.b].link_index);
            if la != lb {
                groups
                    .entry((la.min(lb), la.max(lb)))
                    .or_default()
                    .push(entry);
            }
        }
        let name = |link_index: usize| {
            self.shapes
                .iter()
                .find(|s| s.link_index == link_index)
                .map(|s| s.link.clone())
                .unwrap_or_default()
        };
        groups
            .into_iter()
            .filter_map(|((la, lb), entries)| {
                let deciding = if entries.iter().all(|e| e.skip) {
                    entries.iter().max_by_key(|e| e.layer).copied()
                } else {
                    entries.iter().find(|e| !e.skip).copied()
                }?;
                Some(LinkPair {
                    link1: name(la),
                    link2: name(lb),
                    geometry: match deciding.layer {
                        Layer::Inferred => self.shape_type.id().into(),
                        layer => layer.id().into(),
                    },
                    entry: deciding.clone(),
                    evidence: None,
                })
            })
            .collect()
    }
}

/// The link pairs the consumer files describe: `pairs` (a type's link-level view with the imported and
/// user layers applied) with every inferred verdict replaced by the exact geometry's (`mesh`). With
/// `require_certified`, a `never` that is only sampled stays checked.
pub fn consumer_link_pairs(
    pairs: Vec<LinkPair>,
    mesh: &MeshFile,
    require_certified: bool,
) -> Vec<LinkPair> {
    pairs
        .into_iter()
        .map(|p| {
            let record = mesh.pair(&p.link1, &p.link2);
            match record {
                Some(r) if p.entry.layer == Layer::Inferred => {
                    let uncertified =
                        require_certified && r.evidence == Some(NeverEvidence::Sampled);
                    LinkPair {
                        entry: Entry {
                            skip: r.reason.skips() && !uncertified,
                            reason: if uncertified {
                                Reason::Checked.id().into()
                            } else {
                                r.reason.id().into()
                            },
                            layer: Layer::Inferred,
                        },
                        // Adjacency is the kinematic tree's, not a geometric verdict.
                        geometry: if r.reason == Reason::Adjacent {
                            "tree".into()
                        } else {
                            "mesh".into()
                        },
                        evidence: r.evidence,
                        ..p
                    }
                }
                _ => p,
            }
        })
        .collect()
}
