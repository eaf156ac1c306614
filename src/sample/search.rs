//! Targeted search for collisions that random sampling missed: for a pair that was never in collision but
//! came close, sample densely the joints on the kinematic path between its two links (no other joint can
//! change its distance) and minimise the distance locally from the best starts.

use super::sets::PairSet;
use crate::rng::Rng;
use crate::robot::Kinematics;
use serde::{Deserialize, Serialize};

/// Parameters of the targeted search.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SearchParams {
    /// Pairs never in collision with d_min below this margin (m) are searched.
    pub margin: f64,
    /// Random configurations of the path joints per searched pair.
    pub dense_samples: u32,
    /// Local minimisations per pair (from the sampling witness and the best dense samples).
    pub starts: usize,
    /// Most distance evaluations of one local minimisation.
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
    /// Distance evaluations spent.
    pub evaluations: u64,
}

/// Searches pair `pair` of `set` (set number `set_index` of the run, which picks its random
/// stream), starting from the sampling witness `witness`.
pub fn search_pair(
    kinematics: &Kinematics,
    set: &PairSet,
    set_index: usize,
    pair: usize,
    witness: &[f64],
    seed: u64,
    params: &SearchParams,
) -> SearchOutcome {
    let (la, lb) = set.pair_links(pair);
    let dofs = kinematics.path_dofs(la, lb);
    let bounds: Vec<(f64, f64)> = dofs
        .iter()
        .map(|&d| (kinematics.dofs()[d].lower, kinematics.dofs()[d].upper))
        .collect();
    let mut evaluations = 0u64;
    let mut eval = |q: &[f64]| {
        evaluations += 1;
        set.pair_at(kinematics, pair, q).distance()
    };

    // Dense sampling of the path joints; keep the best starts (the witness first).
    let mut starts: Vec<(f64, Vec<f64>)> = vec![(eval(witness), witness.to_vec())];
    let mut rng = Rng::new(seed, (set_index as u64) << 40 | pair as u64);
    let mut q = witness.to_vec();
    let keep = params.starts.max(1);
    for _ in 0..params.dense_samples {
        for (&d, &(lo, hi)) in dofs.iter().zip(&bounds) {
            q[d] = rng.range(lo, hi);
        }
        // No collision so far, so every kept start is positive: a sample whose sphere lower bound
        // exceeds the worst kept start can neither collide nor become a start.
        let placed = set.pair_at(kinematics, pair, &q);
        if starts.len() >= keep && placed.lower_bound() > starts[starts.len() - 1].0 {
            continue;
        }
        let d = eval(&q);
        if d <= 0.0 {
            return SearchOutcome {
                d_min: d,
                collision: true,
                q,
                evaluations,
            };
        }
        starts.push((d, q.clone()));
        starts.sort_by(|a, b| a.0.total_cmp(&b.0));
        starts.truncate(keep);
    }

    // Pattern search from each start: try +-step on every path joint, halve the step when stuck.
    let mut best = starts[0].clone();
    for (mut d, mut q) in starts {
        let mut step: Vec<f64> = bounds.iter().map(|(lo, hi)| 0.05 * (hi - lo)).collect();
        let mut spent = 0;
        while spent < params.max_local_evaluations
            && step
                .iter()
                .zip(&bounds)
                .any(|(s, (lo, hi))| *s > 1e-5 * (hi - lo))
        {
            let mut improved = false;
            for (k, &dof) in dofs.iter().enumerate() {
                for sign in [1.0, -1.0] {
                    let old = q[dof];
                    q[dof] = (old + sign * step[k]).clamp(bounds[k].0, bounds[k].1);
                    let trial = eval(&q);
                    spent += 1;
                    if trial < d {
                        d = trial;
                        improved = true;
                        if d <= 0.0 {
                            return SearchOutcome {
                                d_min: d,
                                collision: true,
                                q,
                                evaluations,
                            };
                        }
                        break;
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
    SearchOutcome {
        d_min: best.0,
        collision: false,
        q: best.1,
        evaluations,
    }
}
