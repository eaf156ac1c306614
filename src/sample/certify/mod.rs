//! Certificates for `never`: a proof that two links' hulls cannot touch anywhere within the joint limits
//! of the joints on the path between them, by branch and bound over that box of joint values.
//!
//! The bound. Fix the links' common ancestor and move the path joints from a sub-box's centre `c` to
//! any `q` in it one joint at a time, each side's chain from the ancestor down. When joint `j` turns by
//! `t`, every point of the hull below it moves along an arc of chord `2 r sin(t / 2)`, `r` its distance
//! from the joint's axis; the joints above `j` have moved axis and point together and the joints below
//! still hold their centre values, so `r` is at most the hull's reach about `j`'s axis *at `c`*
//! (computed exactly, from the hull's vertices; it depends only on the joints below `j`, so a child box
//! keeps its parent's unless it was split along one of those). A prismatic joint moves points by the
//! slide itself.
//! Summing over both chains, no point of either hull moves farther than `D = sum_j disp_j`, so the
//! hulls' distance anywhere in the sub-box is at least `d(c) - D`. A sub-box with `d(c) - D` above a
//! small margin (the distance solver's tolerance) is cleared; otherwise it is split in two along the
//! DOF whose joints contribute most to `D`. The hulls contain the links' exact geometry, so a cleared
//! joint box proves the meshes never touch. A box centre where the hulls overlap is checked on the
//! exact geometry: a collision there is a witness against `never`; otherwise the hulls alone cannot
//! prove the pair, and the caller may search again with the exact geometry's distance standing in
//! where the hulls' bound falls short ([`PairGeometry::exact`]).

use crate::collision::{CollisionShape, signed_distance, signed_distance_points};
use crate::math::{Pose, Vec3};
use crate::robot::{Kinematics, PathJoint};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// The certificate search's budget; part of the sample stage's key.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CertifyParams {
    /// Most sub-boxes evaluated for one link pair.
    pub max_boxes_per_pair: u64,
    /// Most sub-boxes evaluated over all pairs of a run.
    pub max_boxes: u64,
    /// A sub-box is cleared when its lower bound exceeds this (m): the distance solver's tolerance.
    pub margin: f64,
    /// For a pair whose hulls overlap where its exact geometry does not, most exact-geometry distances
    /// its second search computes (each costs about a millisecond on meshes of thousands of
    /// triangles, a hull query about a microsecond).
    pub max_exact_per_pair: u64,
}

impl Default for CertifyParams {
    fn default() -> Self {
        CertifyParams {
            max_boxes_per_pair: 100_000,
            max_boxes: 20_000_000,
            margin: 1e-6,
            max_exact_per_pair: 500,
        }
    }
}

/// How a certificate search ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// Every sub-box was cleared: the hulls, so the meshes, never touch within the limits.
    Certified,
    /// The budget ran out before every sub-box was cleared.
    Budget,
    /// The hulls overlap at a box centre where the exact geometry does not, and no exact distance was
    /// given to go on with: hulls alone cannot prove it.
    HullsTouch,
    /// The exact geometry collides at a box centre: a witness against `never`.
    Collides,
}

/// What a certificate search established for one link pair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Certificate {
    /// How the search ended.
    pub status: Status,
    /// Sub-boxes evaluated.
    pub boxes: u64,
    /// The least lower bound over the sub-boxes of the hulls' distance (or, where the second search used
    /// it, the exact geometry's) (m): a proof that the pair stays this far apart over the cleared share
    /// of the box (for a certified pair, over all of it).
    pub lower_bound: f64,
    /// The share of the joint box (by volume, each DOF scaled to its range) that was cleared.
    pub cleared: f64,
    /// The least hull distance found at a box centre (m): the true minimum is between `lower_bound`
    /// and this.
    pub closest: f64,
    /// The configuration of `closest` (or of the collision, for [`Status::Collides`]).
    pub q: Vec<f64>,
    /// Sub-boxes where the hulls' bound fell short and the exact geometry's distance was computed.
    #[serde(default)]
    pub exact_queries: u64,
}

/// A lower bound on the distance between two links' exact geometry, given their poses, where it exceeds
/// the third argument; `None` where it is at most that (the search then has no use for its value, and
/// the query may stop sooner).
pub type ExactDistance<'a> = dyn Fn(&Pose, &Pose, f64) -> Option<f64> + Sync + 'a;

/// One link pair to certify: its links, their hulls and where the other DOFs rest.
pub struct PairGeometry<'a> {
    /// The robot's kinematics.
    pub kinematics: &'a Kinematics,
    /// First link and its hull.
    pub link_a: usize,
    /// The hull of `link_a`.
    pub hull_a: &'a CollisionShape,
    /// Second link.
    pub link_b: usize,
    /// The hull of `link_b`.
    pub hull_b: &'a CollisionShape,
    /// A full configuration; the path DOFs are overwritten, the others (which cannot change the pair's
    /// distance) stay.
    pub base: &'a [f64],
    /// A lower bound on the distance between the links' exact geometry (0 where it overlaps), given the
    /// links' poses in their common ancestor's frame, and how many times it may be called: where the
    /// hulls cannot clear a sub-box, the geometry inside them may. `None`: hulls only (a box centre
    /// where they overlap ends the search).
    pub exact: Option<(&'a ExactDistance<'a>, u64)>,
}

/// A sub-box of the path DOFs' joint values, with what its centre showed.
struct SubBox {
    center: Vec<f64>,
    half: Vec<f64>,
    volume: f64,
    lower: f64,
    /// The path DOF that contributes most to the bound at the centre: the one a split halves.
    split: usize,
    /// The hull's reach about each path joint at the centre (see [`Evaluation::reaches`]).
    reaches: Vec<f64>,
}

impl PartialEq for SubBox {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for SubBox {}
impl PartialOrd for SubBox {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for SubBox {
    /// The heap pops the least lower bound first (ties by centre, so the order is deterministic).
    fn cmp(&self, other: &Self) -> Ordering {
        other.lower.total_cmp(&self.lower).then_with(|| {
            other
                .center
                .iter()
                .zip(&self.center)
                .map(|(a, b)| a.total_cmp(b))
                .find(|o| o.is_ne())
                .unwrap_or(Ordering::Equal)
        })
    }
}

/// What one box centre showed: the hulls' distance, the bound's lower value, each path DOF's share.
struct Evaluation {
    distance: f64,
    lower: f64,
    weights: Vec<f64>,
    /// The hull's reach about each joint of side A's chain then side B's (0 for a prismatic joint).
    reaches: Vec<f64>,
    /// Where the hulls' bound fell short and the pair has exact geometry (and, once the allowance is
    /// counted, only where it lasts): the links' poses and each DOF's whole share, for
    /// [`Evaluation::finish`].
    ask: Option<(Pose, Pose, Vec<f64>)>,
    /// Where the hulls overlap: the configuration, and whether the exact geometry collides there.
    touching: Option<(Vec<f64>, bool)>,
}

impl Evaluation {
    /// Checks the exact geometry for a collision where the hulls overlap (`collides`), and consults
    /// its distance (`exact`) where the hulls' bound fell short and it was asked: the hulls contain
    /// the geometry, so its points move no farther than theirs.
    fn finish(&mut self, exact: Option<&ExactDistance>, collides: impl Fn(&[f64]) -> bool) {
        if let Some((q, hit)) = &mut self.touching {
            *hit = collides(q);
        }
        let (Some(exact), Some((pa, pb, whole))) = (exact, &self.ask) else {
            return;
        };
        // Only a distance whose bound beats the hulls' is taken: one at most `enough` could not (the
        // subtraction is monotone, and `enough` is stepped down until it rounds to the hulls' bound or
        // below), so the query need not find how far below `enough` it lies.
        let moved = whole.iter().sum::<f64>();
        let mut enough = self.lower + moved;
        while enough - moved > self.lower {
            enough = enough.next_down();
        }
        let Some(distance) = exact(pa, pb, enough) else {
            return;
        };
        let bound = distance - moved;
        if bound > self.lower {
            self.lower = bound;
            self.weights = whole.clone();
        }
    }
}

/// What a box's children take from it: its reaches, and the path DOF (index) it was split along.
/// A joint's reach depends only on the joints below it on its side, so it holds for a child unless
/// one of those is driven by the split DOF.
struct Inherited {
    reaches: Vec<f64>,
    split: usize,
}

/// Scratch for evaluations.
struct Evaluator<'a> {
    pair: &'a PairGeometry<'a>,
    /// The path DOFs (indices into the configuration).
    dofs: Vec<usize>,
    q: Vec<f64>,
    side_a: Vec<PathJoint>,
    side_b: Vec<PathJoint>,
    /// The clearing margin: the exact geometry is only consulted where the hulls' bound is below it.
    margin: f64,
    /// Exact-geometry distances computed so far.
    exact_queries: u64,
}

impl Evaluator<'_> {
    /// The configuration at `center` (the other DOFs at the pair's base).
    fn config(&mut self, center: &[f64]) -> &[f64] {
        for (&d, &c) in self.dofs.iter().zip(center) {
            self.q[d] = c;
        }
        &self.q
    }

    /// The hulls' bound over the box of `center` and `half`, and what the exact geometry would be
    /// asked where it falls short (see [`Evaluation::finish`]).
    fn evaluate(&mut self, center: &[f64], half: &[f64], from: Option<&Inherited>) -> Evaluation {
        self.config(center);
        let p = self.pair;
        let (pa, pb) = p.kinematics.pair_path(
            &self.q,
            p.link_a,
            p.link_b,
            &mut self.side_a,
            &mut self.side_b,
        );
        let (ha, hb) = (p.hull_a.pose(&pa), p.hull_b.pose(&pb));
        // The unit direction from the closest point of A to B's: every point's motion counts only along
        // it, since the gap between the hulls' extents along a fixed direction bounds their distance.
        let (distance, normal) = match signed_distance_points(p.hull_a, &ha, p.hull_b, &hb) {
            Some((d, x, y)) if d > 0.0 => (d, Some((y - x) / d)),
            Some((d, _, _)) => (d, None),
            None => (signed_distance(p.hull_a, &ha, p.hull_b, &hb), None),
        };
        // Each DOF's share of the bound: counted along `normal` (for the hulls' distance, convex sets)
        // and whole (for any sets: the exact geometry's distance).
        let mut weights = vec![0.0; self.dofs.len()];
        let mut whole = vec![0.0; self.dofs.len()];
        let mut reaches = Vec::with_capacity(self.side_a.len() + self.side_b.len());
        for (joints, hull, pose) in [(&self.side_a, p.hull_a, &pa), (&self.side_b, p.hull_b, &pb)] {
            // The joints of this side from `kept_from` down keep the parent's reach: the lowest joint
            // the split DOF drives and those below it (all of them, if it drives none here).
            let offset = reaches.len();
            let kept_from = from.map(|f| {
                let split = self.dofs[f.split];
                (f, joints.iter().rposition(|j| j.dof == split).unwrap_or(0))
            });
            // How far the joints above have turned the axes below, at most.
            let mut spread = 0.0;
            for (i, j) in joints.iter().enumerate() {
                let reach = match kept_from {
                    _ if j.prismatic => 0.0,
                    Some((f, m)) if i >= m => f.reaches[offset + i],
                    _ => hull.reach(pose, j.point, j.axis),
                };
                reaches.push(reach);
                let Some(k) = self.dofs.iter().position(|&d| d == j.dof) else {
                    continue;
                };
                let travel = j.rate * half[k];
                let (motion, share) = if j.prismatic {
                    (
                        travel,
                        normal.map_or(1.0, |n| along(n, j.axis, spread, false)),
                    )
                } else {
                    (
                        2.0 * reach * (0.5 * travel.min(std::f64::consts::PI)).sin(),
                        normal.map_or(1.0, |n| along(n, j.axis, spread, true)),
                    )
                };
                weights[k] += motion * share;
                whole[k] += motion;
                if !j.prismatic {
                    spread += travel;
                }
            }
        }
        let lower = distance - weights.iter().sum::<f64>();
        Evaluation {
            distance,
            lower,
            weights,
            reaches,
            ask: (lower <= self.margin && p.exact.is_some()).then_some((pa, pb, whole)),
            touching: (distance <= 0.0).then(|| (self.q.clone(), false)),
        }
    }
}

/// How much of a motion counts along the unit direction `n` when the joint's unit axis is `u` at the box
/// centre and may have turned by up to `spread` since: a turn about `u` moves a point at distance `r`
/// from it by at most `2 r sin(t / 2) |n x u|` along `n`, a slide along `u` by `t |n . u|`. Returns the
/// largest `|n x u|` (`turn`) or `|n . u|` over the axes within `spread` of `u`.
fn along(n: Vec3, u: Vec3, spread: f64, turn: bool) -> f64 {
    use std::f64::consts::{FRAC_PI_2, PI};
    let angle = n.dot(u).clamp(-1.0, 1.0).acos();
    let (lo, hi) = ((angle - spread).max(0.0), (angle + spread).min(PI));
    if turn {
        if lo <= FRAC_PI_2 && FRAC_PI_2 <= hi {
            1.0
        } else {
            lo.sin().max(hi.sin())
        }
    } else {
        lo.cos().abs().max(hi.cos().abs())
    }
}

/// Searches for a certificate that the pair's hulls never touch within the path DOFs' limits,
/// evaluating at most `budget` sub-boxes; `collides(q)` checks the exact geometry where the hulls
/// overlap at a box centre.
pub fn certify(
    pair: &PairGeometry,
    margin: f64,
    budget: u64,
    collides: impl Fn(&[f64]) -> bool + Sync,
) -> Certificate {
    let dofs = path_dofs(pair);
    let limits: Vec<(f64, f64)> = dofs
        .iter()
        .map(|&d| {
            let dof = &pair.kinematics.dofs()[d];
            (dof.lower, dof.upper)
        })
        .collect();
    let mut eval = Evaluator {
        pair,
        dofs,
        q: pair.base.to_vec(),
        side_a: Vec::new(),
        side_b: Vec::new(),
        margin,
        exact_queries: 0,
    };
    let center: Vec<f64> = limits.iter().map(|(lo, hi)| 0.5 * (lo + hi)).collect();
    let half: Vec<f64> = limits.iter().map(|(lo, hi)| 0.5 * (hi - lo)).collect();
    let mut out = Certificate {
        status: Status::Certified,
        boxes: 0,
        lower_bound: f64::INFINITY,
        cleared: 0.0,
        closest: f64::INFINITY,
        q: Vec::new(),
        exact_queries: 0,
    };
    let mut open = BinaryHeap::new();
    let mut pending = vec![(center, half, 1.0)];
    // What the boxes in `pending` take from their parent (none for the whole box).
    let mut inherited: Option<Inherited> = None;
    loop {
        // Evaluate the new boxes on the hulls; then, the boxes side by side (each exact query costs
        // up to milliseconds, and this pair may be the last one running), check the exact geometry
        // for a collision where the hulls overlap and consult its distance where their bound falls
        // short and the pair's allowance (counted in box order) lasts.
        let mut evaluations: Vec<Evaluation> = pending
            .iter()
            .map(|(center, half, _)| eval.evaluate(center, half, inherited.as_ref()))
            .collect();
        let mut allowed = eval.exact_queries;
        for e in &mut evaluations {
            match pair.exact {
                Some((_, most)) if e.ask.is_some() && allowed < most => allowed += 1,
                _ => e.ask = None,
            }
        }
        let exact = pair.exact.map(|(exact, _)| exact);
        let costly = |e: &Evaluation| e.touching.is_some() || e.ask.is_some();
        if evaluations.iter().filter(|e| costly(e)).count() > 1 {
            evaluations
                .par_iter_mut()
                .with_max_len(1)
                .for_each(|e| e.finish(exact, &collides));
        } else {
            evaluations
                .iter_mut()
                .for_each(|e| e.finish(exact, &collides));
        }
        // Take them in order: clear, keep open, or stop at an overlap (counting the exact queries
        // of the boxes taken only, as a search one box at a time would).
        for ((center, half, volume), e) in pending.drain(..).zip(evaluations) {
            eval.exact_queries += u64::from(e.ask.is_some());
            out.boxes += 1;
            if e.distance < out.closest {
                out.closest = e.distance;
                out.q = eval.config(&center).to_vec();
            }
            if let Some((q, hit)) = e.touching {
                let stop = if hit {
                    out.q = q;
                    Some(Status::Collides)
                } else {
                    pair.exact.is_none().then_some(Status::HullsTouch)
                };
                if let Some(status) = stop {
                    out.status = status;
                    out.lower_bound = out.lower_bound.min(e.lower);
                    out.exact_queries = eval.exact_queries;
                    return out;
                }
            }
            if e.lower > margin {
                out.cleared += volume;
                out.lower_bound = out.lower_bound.min(e.lower);
            } else {
                // Split along the DOF that contributes most to the bound.
                let split = (0..e.weights.len())
                    .max_by(|&x, &y| e.weights[x].total_cmp(&e.weights[y]).then(y.cmp(&x)))
                    .unwrap_or(0);
                open.push(SubBox {
                    center,
                    half,
                    volume,
                    lower: e.lower,
                    split,
                    reaches: e.reaches,
                });
            }
        }
        out.exact_queries = eval.exact_queries;
        // Every pop splits a box into two (both evaluated), so at most `pops` more boxes are ever
        // split, and a box behind `pops + 1` others in the heap's order is never popped: it stays
        // open with a lower bound at least the one the search ends with. Such boxes are dropped
        // (they hold four vectors of path DOFs; a 59-DOF path with 100,000 boxes took about
        // 100 MB), which changes nothing the certificate reports.
        let pops = budget.saturating_sub(out.boxes) / 2;
        let keep = usize::try_from(pops)
            .unwrap_or(usize::MAX)
            .saturating_add(1);
        if open.len() > keep.saturating_add(keep / 4).saturating_add(64) {
            keep_first(&mut open, keep);
        }
        let Some(b) = open.pop() else {
            return out;
        };
        if out.boxes + 2 > budget {
            out.status = Status::Budget;
            out.lower_bound = out.lower_bound.min(b.lower);
            return out;
        }
        let k = b.split;
        for sign in [-1.0, 1.0] {
            let (mut center, mut half) = (b.center.clone(), b.half.clone());
            half[k] *= 0.5;
            center[k] += sign * half[k];
            pending.push((center, half, 0.5 * b.volume));
        }
        inherited = Some(Inherited {
            reaches: b.reaches,
            split: k,
        });
    }
}

/// Keeps the `keep` boxes `open` would pop first, and drops the others.
fn keep_first(open: &mut BinaryHeap<SubBox>, keep: usize) {
    if open.len() <= keep {
        return;
    }
    let mut boxes = std::mem::take(open).into_vec();
    // The `keep` greatest under `SubBox`'s order (the heap pops the greatest: the least bound).
    boxes.select_nth_unstable_by(keep, |x, y| y.cmp(x));
    boxes.truncate(keep);
    *open = BinaryHeap::from(boxes);
}

/// The DOFs that move a joint on the pair's path, in ascending order.
fn path_dofs(pair: &PairGeometry) -> Vec<usize> {
    pair.kinematics.path_dofs(pair.link_a, pair.link_b)
}

#[cfg(test)]
mod tests;
