//! Table 3: the verdict of each shape type with its skips against the exact triangle meshes.
//!
//! Per configuration, the ground truth is the set of non-adjacent link pairs whose meshes collide
//! ([`super::truth`]). A type *reports* a link pair when one of its checked (non-skipped) shape pairs
//! between those links collides. Then, per configuration:
//! - **false negative**: the meshes collide somewhere but the type reports nothing: a planner would
//!   accept a configuration in self-collision;
//! - **hidden by R**: some colliding link pair is not reported, and one of its shape pairs skipped for
//!   reason R does collide: the skip hid a real collision (a configuration may count for several R);
//! - **missed by the shapes**: some colliding link pair is not reported even with every shape pair
//!   checked (the type's shapes do not cover the geometry there, e.g. decomposition pieces);
//! - **false positive**: the type reports a collision but no meshes collide;
//! - **spurious pair**: the type reports a link pair whose meshes do not collide (the configuration may
//!   have other, real collisions).

use super::truth::MeshTruth;
use crate::math::Pose;
use crate::query::SelfChecker;
use crate::robot::Kinematics;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};

/// Counts of configurations for one shape type (divide by `configs` for fractions).
#[derive(Debug, Clone, Default, Serialize)]
pub struct Accuracy {
    /// Configurations examined.
    pub configs: usize,
    /// Configurations where the meshes of some non-adjacent link pair collide.
    pub mesh_collisions: usize,
    /// Configurations where the type with its skips reports a collision.
    pub reported: usize,
    /// Mesh collision, nothing reported.
    pub false_negatives: usize,
    /// Per skip reason: configurations where a pair skipped for it hides a real mesh collision.
    pub hidden: BTreeMap<String, usize>,
    /// Configurations with a mesh collision the type's shapes miss even without skips.
    pub missed_by_shapes: usize,
    /// Reported collision, no mesh collision.
    pub false_positives: usize,
    /// Configurations with a reported link pair whose meshes do not collide.
    pub spurious_pairs: usize,
}

/// What one configuration contributes.
#[derive(Default)]
struct Outcome {
    mesh: bool,
    reported: bool,
    hidden: BTreeSet<String>,
    missed: bool,
    spurious: bool,
}

/// The mesh ground truth at every configuration: colliding link pairs (in parallel).
pub fn ground_truth(
    truth: &MeshTruth,
    kinematics: &Kinematics,
    configs: &[Vec<f64>],
    tick: &(dyn Fn() + Sync),
) -> Vec<Vec<(usize, usize)>> {
    configs
        .par_iter()
        .map_init(Vec::<Pose>::new, |poses, q| {
            kinematics.link_poses_into(q, poses);
            let hits = truth.colliding(poses);
            tick();
            hits
        })
        .collect()
}

/// Compares a type's verdicts (with skips, and without for attribution) against the ground truth.
/// The reasons listed in `reasons` appear in the result even when they hide nothing.
pub fn against_meshes(
    skips: &SelfChecker,
    no_skips: &SelfChecker,
    configs: &[Vec<f64>],
    truth: &[Vec<(usize, usize)>],
    reasons: &[String],
) -> Accuracy {
    let links: Vec<usize> = skips.shapes().iter().map(|s| s.link_index).collect();
    let link_pair = |a: usize, b: usize| {
        let (x, y) = (links[a], links[b]);
        (x.min(y), x.max(y))
    };
    let outcomes: Vec<Outcome> = configs
        .par_iter()
        .zip(truth)
        .map_init(
            || skips.scratch(),
            |scratch, (q, mesh)| {
                // The configurations come from the checkers' own DOFs: the queries cannot fail.
                let reported: BTreeSet<(usize, usize)> = skips
                    .collisions(q, scratch)
                    .map(|r| r.pairs.iter().map(|p| link_pair(p.a, p.b)).collect())
                    .unwrap_or_default();
                let mut out = Outcome {
                    mesh: !mesh.is_empty(),
                    reported: !reported.is_empty(),
                    spurious: reported.iter().any(|p| !mesh.contains(p)),
                    ..Outcome::default()
                };
                let unreported: Vec<&(usize, usize)> =
                    mesh.iter().filter(|p| !reported.contains(p)).collect();
                if unreported.is_empty() {
                    return out;
                }
                let all = no_skips
                    .collisions(q, scratch)
                    .map(|r| r.pairs)
                    .unwrap_or_default();
                for lp in unreported {
                    let mut covered = false;
                    for p in all.iter().filter(|p| link_pair(p.a, p.b) == *lp) {
                        covered = true;
                        if let Some(r) = skips.skip_reason(p.a, p.b) {
                            out.hidden.insert(r.to_string());
                        }
                    }
                    out.missed |= !covered;
                }
                out
            },
        )
        .collect();
    let mut acc = Accuracy {
        configs: configs.len(),
        hidden: reasons.iter().map(|r| (r.clone(), 0)).collect(),
        ..Accuracy::default()
    };
    for o in outcomes {
        acc.mesh_collisions += usize::from(o.mesh);
        acc.reported += usize::from(o.reported);
        acc.false_negatives += usize::from(o.mesh && !o.reported);
        acc.false_positives += usize::from(o.reported && !o.mesh);
        acc.missed_by_shapes += usize::from(o.missed);
        acc.spurious_pairs += usize::from(o.spurious);
        for r in o.hidden {
            *acc.hidden.entry(r).or_default() += 1;
        }
    }
    acc
}
