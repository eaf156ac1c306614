//! The editor of the user layer: marks on one pair, the two bulk rules, undo and redo. Plain Rust over
//! the library's [`UserLayer`] and [`SkipMatrix`]; the editing plugin ([`super::EditingPlugin`]) only
//! calls into it.

use crate::pairs::list::ratio;
use scm::matrix::{SkipMatrix, UserLayer};

/// One edit a person (or an action script) asks for, on the pairs of one type.
#[derive(Debug, Clone, PartialEq)]
pub enum Edit {
    /// Mark pair `pair` (row-major index) skipped (`true`) or checked (`false`).
    Mark {
        /// Pair index.
        pair: usize,
        /// Skip or check.
        skip: bool,
    },
    /// Remove the mark of pair `pair`, so the lower layers decide again.
    Unmark {
        /// Pair index.
        pair: usize,
    },
    /// Skip every pair whose current distance is below `below` (or equal, when `inclusive`).
    SkipCloser {
        /// The threshold in metres.
        below: f64,
        /// Also skip pairs exactly at the threshold (the "below the selected pair's" rule, which
        /// includes the selected pair).
        inclusive: bool,
    },
    /// Skip every pair whose current distance over its mean distance is below `below`.
    SkipRatio {
        /// The threshold on `d / d_mean`.
        below: f64,
    },
}

/// The user layer being edited, with its undo and redo history.
#[derive(Debug, Clone)]
pub struct Editor {
    layer: UserLayer,
    saved: UserLayer,
    undo: Vec<(String, UserLayer)>,
    redo: Vec<(String, UserLayer)>,
}

impl Editor {
    /// Starts editing `layer` (as loaded from disk, so not dirty).
    pub fn new(layer: UserLayer) -> Editor {
        Editor {
            saved: layer.clone(),
            layer,
            undo: Vec::new(),
            redo: Vec::new(),
        }
    }

    /// The layer with every edit applied.
    pub fn layer(&self) -> &UserLayer {
        &self.layer
    }

    /// Whether the layer differs from what was last loaded or saved.
    pub fn is_dirty(&self) -> bool {
        self.layer.edits != self.saved.edits
    }

    /// Records that the current layer was saved.
    pub fn mark_saved(&mut self) {
        self.saved = self.layer.clone();
    }

    /// What undo would revert, if anything.
    pub fn undo_label(&self) -> Option<&str> {
        self.undo.last().map(|(l, _)| l.as_str())
    }

    /// What redo would reapply, if anything.
    pub fn redo_label(&self) -> Option<&str> {
        self.redo.last().map(|(l, _)| l.as_str())
    }

    /// Applies `edit` to the pairs of `m` given their current `distances` (row-major). Returns how
    /// many pairs it changed and a description; an edit that changes nothing leaves no history.
    pub fn apply(&mut self, edit: &Edit, m: &SkipMatrix, distances: &[f64]) -> (usize, String) {
        let t = m.shape_type;
        if let Edit::Mark { pair, .. } | Edit::Unmark { pair } = *edit
            && pair >= m.stats.len()
        {
            let n = m.stats.len();
            return (0, format!("no pair {pair} among the {n} pairs of {t}"));
        }
        let before = self.layer.clone();
        let key = |p: usize| {
            let s = &m.stats[p];
            (m.key(s.a), m.key(s.b))
        };
        let (changed, label) = match *edit {
            Edit::Mark { pair, skip } => {
                let (a, b) = key(pair);
                let label = format!(
                    "mark {a} - {b} {} ({t})",
                    if skip { "skip" } else { "check" }
                );
                let changed = self.layer.get(t, &a, &b) != Some(skip);
                self.layer.set(t, a, b, skip);
                (usize::from(changed), label)
            }
            Edit::Unmark { pair } => {
                let (a, b) = key(pair);
                let changed = self.layer.get(t, &a, &b).is_some();
                let label = format!("unmark {a} - {b} ({t})");
                self.layer.unset(t, &a, &b);
                (usize::from(changed), label)
            }
            Edit::SkipCloser { below, inclusive } => {
                let hit = |d: f64| d < below || (inclusive && d == below);
                let pairs = bulk(m, distances, |_, d| hit(d));
                let n = self.skip_all(m, &pairs);
                let op = if inclusive { "<=" } else { "<" };
                (n, format!("skip {n} pairs with d {op} {below:.4} m ({t})"))
            }
            Edit::SkipRatio { below } => {
                let pairs = bulk(m, distances, |p, d| ratio(d, &m.stats[p]) < below);
                let n = self.skip_all(m, &pairs);
                (
                    n,
                    format!("skip {n} pairs with d / d_mean < {below:.3} ({t})"),
                )
            }
        };
        if changed > 0 {
            self.undo.push((label.clone(), before));
            self.redo.clear();
        }
        (changed, label)
    }

    /// Reverts the last edit; returns its description.
    pub fn undo(&mut self) -> Option<String> {
        let (label, layer) = self.undo.pop()?;
        let current = std::mem::replace(&mut self.layer, layer);
        self.redo.push((label.clone(), current));
        Some(label)
    }

    /// Reapplies the last undone edit; returns its description.
    pub fn redo(&mut self) -> Option<String> {
        let (label, layer) = self.redo.pop()?;
        let current = std::mem::replace(&mut self.layer, layer);
        self.undo.push((label.clone(), current));
        Some(label)
    }

    /// Marks `pairs` skipped; returns how many were not skipped before.
    fn skip_all(&mut self, m: &SkipMatrix, pairs: &[usize]) -> usize {
        for &p in pairs {
            let s = &m.stats[p];
            self.layer.set(m.shape_type, m.key(s.a), m.key(s.b), true);
        }
        pairs.len()
    }
}

/// The pairs not skipped yet whose current distance passes `rule(pair, d)`.
fn bulk(m: &SkipMatrix, distances: &[f64], rule: impl Fn(usize, f64) -> bool) -> Vec<usize> {
    (0..m.entries.len())
        .filter(|&p| !m.entries[p].skip)
        .filter(|&p| distances.get(p).is_some_and(|&d| rule(p, d)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::matrix;

    /// Marks `pair` of `m`; returns how many pairs changed.
    fn mark(ed: &mut Editor, m: &SkipMatrix, pair: usize, skip: bool) -> usize {
        ed.apply(&Edit::Mark { pair, skip }, m, &[]).0
    }

    #[test]
    fn marks_undo_and_redo_restore_each_layer() {
        let m = matrix(4);
        let mut ed = Editor::new(UserLayer::default());
        assert_eq!(mark(&mut ed, &m, 1, true), 1);
        assert_eq!(mark(&mut ed, &m, 1, true), 0);
        assert_eq!(mark(&mut ed, &m, 2, false), 1);
        assert_eq!(ed.layer().edits.len(), 2);
        assert!(ed.is_dirty());
        assert!(ed.undo().is_some());
        assert_eq!(ed.layer().edits.len(), 1);
        assert!(ed.redo().is_some());
        assert_eq!(ed.layer().edits.len(), 2);
        assert!(ed.redo().is_none());
        assert_eq!(ed.apply(&Edit::Unmark { pair: 1 }, &m, &[]).0, 1);
        assert_eq!(ed.layer().edits.len(), 1);
        ed.undo();
        ed.undo();
        ed.undo();
        assert!(ed.layer().edits.is_empty());
        assert!(!ed.is_dirty());
        assert!(ed.undo().is_none());
        assert_eq!(ed.apply(&Edit::Unmark { pair: 99 }, &m, &[]).0, 0);
    }

    #[test]
    fn a_new_edit_clears_redo() {
        let m = matrix(3);
        let mut ed = Editor::new(UserLayer::default());
        mark(&mut ed, &m, 0, true);
        ed.undo();
        mark(&mut ed, &m, 1, true);
        assert!(ed.redo().is_none());
    }

    #[test]
    fn distance_rule_skips_only_closer_checked_pairs_in_one_undo_step() {
        // matrix(4): 6 pairs, all checked except pair 0 (adjacent), d_mean = 0.1 each.
        let m = matrix(4);
        let d = [0.0, 0.01, 0.02, 0.05, 0.2, -0.01];
        let mut ed = Editor::new(UserLayer::default());
        let rule = Edit::SkipCloser {
            below: 0.02,
            inclusive: false,
        };
        let (n, _) = ed.apply(&rule, &m, &d);
        // Pairs 1 (0.01) and 5 (-0.01); pair 0 is already skipped, pair 2 sits at the threshold.
        assert_eq!(n, 2);
        let marked: Vec<(usize, usize)> = (0..6)
            .filter(|&p| {
                let s = &m.stats[p];
                ed.layer().get(m.shape_type, &m.key(s.a), &m.key(s.b)) == Some(true)
            })
            .map(|p| (m.stats[p].a, m.stats[p].b))
            .collect();
        assert_eq!(marked, vec![(0, 2), (2, 3)]);
        let inclusive = Edit::SkipCloser {
            below: 0.02,
            inclusive: true,
        };
        let m2 = crate::fixtures::resolve(&m, ed.layer());
        assert_eq!(ed.apply(&inclusive, &m2, &d).0, 1);
        ed.undo();
        ed.undo();
        assert!(ed.layer().edits.is_empty());
    }

    #[test]
    fn ratio_rule_compares_current_over_mean_distance() {
        let m = matrix(3); // 3 pairs, d_mean 0.1, pair 0 skipped
        let d = [0.0, 0.04, 0.06];
        let mut ed = Editor::new(UserLayer::default());
        let (n, label) = ed.apply(&Edit::SkipRatio { below: 0.5 }, &m, &d);
        assert_eq!(n, 1, "{label}");
        let s = &m.stats[1];
        assert_eq!(
            ed.layer().get(m.shape_type, &m.key(s.a), &m.key(s.b)),
            Some(true)
        );
    }
}
