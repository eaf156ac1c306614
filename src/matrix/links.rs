//! The link-level view of a skip matrix: what SRDF, MJCF, cuRobo and Drake files describe.

use super::{Entry, SkipMatrix};
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
                    entry: deciding.clone(),
                })
            })
            .collect()
    }
}
