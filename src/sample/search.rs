//! Targeted search for collisions that random sampling missed: for a pair that was never in collision but
//! came close, sample densely the joints on the kinematic path between its two links (no other joint can
//! change its distance) and minimise the distance locally from the best starts.
//!
//! The dense samples are drawn once per link pair and shared by every searched shape pair between the
//! two links, of every type: the links are placed once per sample, and each shape pair only bounds (and,
//! where it could become a start, measures) its own distance there.

use super::sets::{PairSet, PlacedPair};
use crate::collision::Hint;
use crate::rng::Rng;
use crate::robot::Kinematics;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Parameters of the targeted search.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SearchParams {
    /// Pairs never in collision with d_min below this margin (m) are searched.
    pub margin: f64,
    /// Random configurations of the path joints per searched link pair.
    pub dense_samples: u32,
    /// Local minimisations per pair (from the sampling witness and the best dense samples).
    pub starts: usize,
    /// Most steps of one local minimisation.
    pub max_local_evaluations: u32,
}

impl Default for SearchParams {
    fn default() -> Self {
        SearchParams {
            margin: 0.02,
            dense_samples: 2000,
            starts: 4,
            max_local_evaluations: 600,
        }
    }
}

/// What the search found for one pair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SearchOutcome {
    /// Smallest signed distance found (m).
    pub d_min: f64,
    /// Whether a collision was found (`d_min <= 0`).
    pub collision: bool,
    /// The configuration of `d_min`.
    pub q: Vec<f64>,
    /// Exact distance queries spent (a configuration shown not to come below what it would have to
    /// beat, by the sphere bound or a GJK stopped early, needs none).
    pub evaluations: u64,
}

/// One shape pair to search.
#[derive(Debug, Clone, Copy)]
pub struct SearchTarget<'a> {
    /// The index of its set (type) in the run: `sets[set]`.
    pub set: usize,
    /// The pair's index in its set.
    pub pair: usize,
    /// The sampling witness: where the pair came closest.
    pub witness: &'a [f64],
}

/// The random stream of the dense samples of link pair `(la, lb)`, `la <= lb`: apart from the
/// sampling chunks' streams (below 2^40) and the benchmark's.
fn stream(la: usize, lb: usize) -> u64 {
    0x5EA4 << 48 | (la as u64) << 24 | lb as u64
}

/// A pair's search in progress: its best starts so far (the witness first) or the collision found.
struct Search<'a> {
    target: SearchTarget<'a>,
    /// Whether the pair's shapes hang from the link pair's links in reverse order.
    swapped: bool,
    starts: Vec<(f64, Vec<f64>)>,
    /// A configuration where the dense samples found a collision, and its distance.
    collision: Option<(f64, Vec<f64>)>,
    evaluations: u64,
    hint: Hint,
}

impl Search<'_> {
    /// The exact distance of `placed`, counted.
    fn eval(&mut self, placed: &PlacedPair) -> f64 {
        self.evaluations += 1;
        placed.distance_hinted(&mut self.hint)
    }

    /// What the search found: `d_min` at `q`, a collision where it is not positive.
    fn outcome(&self, d_min: f64, q: Vec<f64>) -> SearchOutcome {
        SearchOutcome {
            d_min,
            collision: d_min <= 0.0,
            q,
            evaluations: self.evaluations,
        }
    }

    /// The witness with the path DOFs `dofs` set to `x`.
    fn configuration(&self, dofs: &[usize], x: &[f64]) -> Vec<f64> {
        let mut q = self.target.witness.to_vec();
        dofs.iter().zip(x).for_each(|(&d, &v)| q[d] = v);
        q
    }
}

/// Searches `targets`, every one a moving pair between links `la` and `lb` (`la <= lb`, in either
/// order) of `sets`, starting from its sampling witness; one outcome per target, in order.
pub fn search_link_pair(
    kinematics: &Kinematics,
    sets: &[PairSet],
    (la, lb): (usize, usize),
    targets: &[SearchTarget],
    seed: u64,
    params: &SearchParams,
) -> Vec<SearchOutcome> {
    let dofs = kinematics.path_dofs(la, lb);
    let bounds: Vec<(f64, f64)> = dofs
        .iter()
        .map(|&d| (kinematics.dofs()[d].lower, kinematics.dofs()[d].upper))
        .collect();
    let keep = params.starts.max(1);
    let mut searches: Vec<Search> = targets
        .iter()
        .map(|&target| {
            let set = &sets[target.set];
            let mut search = Search {
                target,
                swapped: set.pair_links(target.pair) != (la, lb),
                starts: Vec::new(),
                collision: None,
                evaluations: 0,
                hint: Hint::default(),
            };
            let d = search.eval(&set.pair_at(kinematics, target.pair, target.witness));
            search.starts.push((d, target.witness.to_vec()));
            search
        })
        .collect();

    // Dense sampling of the path joints, the links placed once per sample; each pair keeps its best
    // starts. No collision so far, so every kept start is positive: a sample whose distance cannot lie
    // below a pair's worst kept start can neither collide nor become one of its starts.
    let mut rng = Rng::new(seed, stream(la, lb));
    let mut q = kinematics.home();
    let mut x = vec![0.0; dofs.len()];
    for _ in 0..params.dense_samples {
        for ((&d, &(lo, hi)), v) in dofs.iter().zip(&bounds).zip(&mut x) {
            *v = rng.range(lo, hi);
            q[d] = *v;
        }
        let (pose_a, pose_b) = kinematics.pair_poses(&q, la, lb);
        for search in searches.iter_mut().filter(|s| s.collision.is_none()) {
            let set = &sets[search.target.set];
            let poses = if search.swapped {
                (pose_b, pose_a)
            } else {
                (pose_a, pose_b)
            };
            let placed = set.placed(search.target.pair, poses);
            let full = search.starts.len() >= keep;
            // The witness is always a start, so there is a worst one.
            let worst = search.starts[search.starts.len() - 1].0;
            if full && !placed.may_be_below(worst, &mut search.hint) {
                continue;
            }
            let d = search.eval(&placed);
            if d <= 0.0 {
                search.collision = Some((d, search.configuration(&dofs, &x)));
            } else if !full || d < worst {
                // Behind the kept starts of equal distance, which come first.
                search.starts.push((d, search.configuration(&dofs, &x)));
                search.starts.sort_by(|a, b| a.0.total_cmp(&b.0));
                search.starts.truncate(keep);
            }
        }
    }
    searches
        .into_par_iter()
        .map(|mut search| match search.collision.take() {
            Some((d, q)) => search.outcome(d, q),
            None => local_search(kinematics, sets, &dofs, &bounds, search, params),
        })
        .collect()
}

/// Pattern search from each of `search`'s starts: try +-step on every path joint, halve the step when
/// stuck.
fn local_search(
    kinematics: &Kinematics,
    sets: &[PairSet],
    dofs: &[usize],
    bounds: &[(f64, f64)],
    mut search: Search,
    params: &SearchParams,
) -> SearchOutcome {
    let (set, pair) = (&sets[search.target.set], search.target.pair);
    let (la, lb) = set.pair_links(pair);
    // Each step moves one DOF from the current configuration: only what it moves is recomputed.
    let mut chains = kinematics.pair_chains(la, lb);
    let starts = std::mem::take(&mut search.starts);
    let mut best = starts[0].clone();
    for (mut d, mut q) in starts {
        chains.set_base(&q);
        let mut step: Vec<f64> = bounds.iter().map(|(lo, hi)| 0.05 * (hi - lo)).collect();
        let mut spent = 0;
        while spent < params.max_local_evaluations
            && step
                .iter()
                .zip(bounds)
                .any(|(s, (lo, hi))| *s > 1e-5 * (hi - lo))
        {
            let mut improved = false;
            for (k, &dof) in dofs.iter().enumerate() {
                for sign in [1.0, -1.0] {
                    let old = q[dof];
                    q[dof] = (old + sign * step[k]).clamp(bounds[k].0, bounds[k].1);
                    spent += 1;
                    // A step whose distance cannot lie below `d` cannot improve on it: no exact
                    // query (the search takes the same path either way).
                    let placed = set.placed(pair, chains.poses(&q, dof));
                    if placed.may_be_below(d, &mut search.hint) {
                        let trial = search.eval(&placed);
                        if trial < d {
                            d = trial;
                            improved = true;
                            chains.set_base(&q);
                            if d <= 0.0 {
                                return search.outcome(d, q);
                            }
                            break;
                        }
                    }
                    q[dof] = old;
                }
            }
            if !improved {
                step.iter_mut().for_each(|s| *s *= 0.5);
            }
        }
        if d < best.0 {
            best = (d, q);
        }
    }
    search.outcome(best.0, best.1)
}
