//! The `mesh` type: link-level verdicts decided on the exact URDF collision geometry, the reasons the
//! SRDF, MJCF, cuRobo and Drake files carry.
//!
//! - `default`: the links' geometry touches at home, as MoveIt and Pinocchio see it
//!   ([`ExactLink::touch`], inside what every consumer checks);
//! - `always`: it touches in every sample;
//! - `never`: it never overlaps as solids ([`ExactLink::overlap`]) in any sample, with its evidence: a
//!   [`Certificate`] over the link hulls (which contain it), `certified` when every sub-box of the path
//!   joints' limits was cleared, else `sampled`;
//! - `checked` otherwise.
//!
//! The exact geometry is only examined on samples where the link hulls overlap: elsewhere it is apart
//! for free. A pair whose hulls never overlapped in sampling (the `hull` type's statistics) is apart
//! in every sample; others run through the samples in order until their verdict is settled (an
//! overlap and a non-touching sample: neither `always` nor `never`).

use super::SampleOptions;
use super::certify::{Certificate, CertifyParams, PairGeometry, Status, certify};
use super::engine::{CHUNK, Engine};
use super::reasons::{Reason, never_upper_bound};
use super::records::{SampleFile, Witness};
use super::sets::PlacedPair;
use crate::collision::ExactLink;
use crate::error::{Error, Result};
use crate::math::Pose;
use crate::preprocess::{exact_links, load_meshes, urdd_urdf};
use crate::progress::Progress;
use crate::rng::Rng;
use crate::robot::random_configuration;
use crate::shapes::ShapeType;
use crate::urdd::{FORMAT_VERSION, TypeShapes, Urdd};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};

pub use crate::urdd::MESH_FILE;

/// Pairs certified side by side when the run's box budget could run out: each batch shares what is
/// left of it equally, so the result does not depend on the thread count. When every pair can have its
/// whole per-pair budget, all pairs form one batch (no batch waits for its slowest pair).
const BATCH: usize = 64;

/// Whether a `never` verdict is proved or only sampled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum NeverEvidence {
    /// The link hulls provably never touch within the joint limits (or the pair is rigid and apart).
    Certified,
    /// Never in collision in the samples, not proved: see the pair's certificate for how far it got.
    Sampled,
}

impl NeverEvidence {
    /// The id used in files and messages.
    pub fn id(self) -> &'static str {
        match self {
            NeverEvidence::Certified => "certified",
            NeverEvidence::Sampled => "sampled",
        }
    }
}

/// The `mesh` verdict of one link pair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinkPairRecord {
    /// The link earlier in the robot's link order.
    pub link1: String,
    /// The other link.
    pub link2: String,
    /// Why the pair may be skipped, or `checked`.
    pub reason: Reason,
    /// Whether the geometry touches at home.
    pub home_touch: bool,
    /// Samples whose exact verdict is known: every sample, or (for `checked` pairs) those up to the one
    /// that settled the verdict.
    pub examined: u64,
    /// Of those, samples where the geometry touches.
    pub touches: u64,
    /// Of those, samples where it overlaps as solids (touching, or one inside the other).
    pub overlaps: u64,
    /// The first configuration where the geometry overlaps (a sample, or a certificate's box centre).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub witness: Option<Witness>,
    /// For `never` pairs: certified or sampled.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub evidence: Option<NeverEvidence>,
    /// The certificate search, for pairs that had one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub certificate: Option<Certificate>,
}

/// Counts of the `mesh` verdicts.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct MeshSummary {
    /// Link pairs (of distinct links with geometry).
    pub pairs: usize,
    /// Pairs per reason.
    pub reasons: BTreeMap<Reason, usize>,
    /// `never` pairs with a certificate.
    pub certified: usize,
    /// `never` pairs only sampled.
    pub sampled: usize,
    /// Pairs never in collision in the samples that the certificate search found colliding.
    pub overturned: usize,
    /// Sub-boxes the certificate searches evaluated.
    pub boxes: u64,
}

/// `sample/mesh.json`: the link-level verdicts on the exact geometry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeshFile {
    /// Format version.
    pub format_version: u32,
    /// Samples drawn.
    pub samples: u64,
    /// Seed.
    pub seed: u64,
    /// 95% upper bound on the collision probability of a `sampled` never pair (about 3 / samples).
    pub never_upper_bound: f64,
    /// The certificate budget.
    pub certify: CertifyParams,
    /// Counts.
    pub summary: MeshSummary,
    /// One record per pair of distinct links with geometry, in link order.
    pub pairs: Vec<LinkPairRecord>,
}

impl MeshFile {
    /// The record of links `a` and `b` (either order).
    pub fn pair(&self, a: &str, b: &str) -> Option<&LinkPairRecord> {
        self.pairs
            .iter()
            .find(|p| (p.link1 == a && p.link2 == b) || (p.link1 == b && p.link2 == a))
    }
}

/// Decides every link pair's `mesh` verdict. `files` are this run's per-type outputs: the `hull` type's,
/// when sampled, spares the pairs whose hulls never overlapped a pass over the samples.
pub(super) fn mesh_verdicts(
    urdd: &Urdd,
    engine: &Engine,
    opts: &SampleOptions,
    files: &[SampleFile],
    progress: &dyn Progress,
) -> Result<MeshFile> {
    let robot = &engine.robot;
    let urdf = urdd_urdf(urdd)?;
    let exact = exact_links(robot, &load_meshes(robot, &urdf)?, &urdf)?;
    let hulls = urdd.collision_shapes(ShapeType::Hull, robot.links.len())?;
    let mut hull_of: Vec<Option<usize>> = vec![None; robot.links.len()];
    for (i, &link) in hulls.links.iter().enumerate() {
        hull_of[link] = Some(i);
    }
    // Hull collisions per link pair, where the hull type was sampled in this run.
    let hull_collisions: HashMap<(usize, usize), u64> = files
        .iter()
        .find(|f| f.shape_type == ShapeType::Hull)
        .map(|f| {
            f.pairs
                .iter()
                .map(|p| {
                    let (a, b) = (hulls.links[p.a], hulls.links[p.b]);
                    ((a.min(b), a.max(b)), p.collisions)
                })
                .collect()
        })
        .unwrap_or_default();
    let adjacent: Vec<(usize, usize)> = robot.adjacent_pairs();
    let n = robot.links.len();
    let pairs: Vec<(usize, usize)> = (0..n)
        .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
        .filter(|&(a, b)| exact[a].is_some() && exact[b].is_some())
        .collect();
    let missing_hull = pairs
        .iter()
        .flat_map(|&(a, b)| [a, b])
        .find(|&l| hull_of[l].is_none());
    if let Some(link) = missing_hull {
        return Err(Error::Failed {
            context: "mesh verdicts".into(),
            message: format!(
                "link \"{}\" has geometry but no hull in the preprocess output; rerun `scm preprocess`",
                robot.links[link].name
            ),
        });
    }
    let home = engine.kinematics.home();
    let ctx = Context {
        engine,
        opts,
        exact: &exact,
        hulls: &hulls,
        hull_of: &hull_of,
        home: &home,
    };

    progress.start("exact geometry", pairs.len() as u64);
    let mut records: Vec<LinkPairRecord> = pairs
        .par_iter()
        .map(|&(a, b)| {
            let adjacent = adjacent.contains(&(a, b)) || adjacent.contains(&(b, a));
            let r = ctx.sampled_verdict(a, b, adjacent, hull_collisions.get(&(a, b)).copied());
            progress.advance(1);
            r
        })
        .collect();
    progress.finish();

    // Certificates for the moving `never` pairs, in batches sharing the run's budget.
    let todo: Vec<usize> = (0..records.len())
        .filter(|&i| records[i].reason == Reason::Never && records[i].evidence.is_none())
        .collect();
    progress.start("certifying never", todo.len() as u64);
    let mut spent = 0u64;
    let binding = opts.certify.max_boxes
        < (todo.len() as u64).saturating_mul(opts.certify.max_boxes_per_pair);
    let batch_len = if binding { BATCH } else { todo.len().max(1) };
    for batch in todo.chunks(batch_len) {
        let left = opts.certify.max_boxes.saturating_sub(spent);
        let budget = opts
            .certify
            .max_boxes_per_pair
            .min(left / batch.len() as u64);
        // The costly pairs first, one pair per task, so that no core is left with a long one at the
        // end: a pair whose hulls collided in more samples more likely needs the exact geometry's
        // second search. Each certificate depends only on its pair and the batch's budget, so the
        // order changes no result.
        let mut order = batch.to_vec();
        order.sort_by_key(|&i| {
            std::cmp::Reverse(hull_collisions.get(&pairs[i]).copied().unwrap_or(0))
        });
        let mut results: Vec<(usize, Certificate)> = order
            .par_iter()
            .with_max_len(1)
            .map(|&i| {
                let c = ctx.certificate(pairs[i], budget);
                progress.advance(1);
                (i, c)
            })
            .collect();
        results.sort_by_key(|&(i, _)| i);
        for (i, c) in results {
            spent += c.boxes;
            let r = &mut records[i];
            match c.status {
                Status::Certified => r.evidence = Some(NeverEvidence::Certified),
                Status::Collides => {
                    r.reason = Reason::Checked;
                    r.witness = Some(Witness {
                        sample: None,
                        q: c.q.clone(),
                    });
                }
                Status::Budget | Status::HullsTouch => r.evidence = Some(NeverEvidence::Sampled),
            }
            r.certificate = Some(c);
        }
    }
    progress.finish();

    let mut summary = MeshSummary {
        pairs: records.len(),
        ..MeshSummary::default()
    };
    for r in &records {
        *summary.reasons.entry(r.reason).or_default() += 1;
        match r.evidence {
            Some(NeverEvidence::Certified) => summary.certified += 1,
            Some(NeverEvidence::Sampled) => summary.sampled += 1,
            None => {}
        }
        if let Some(c) = &r.certificate {
            summary.boxes += c.boxes;
            summary.overturned += usize::from(c.status == Status::Collides);
        }
    }
    Ok(MeshFile {
        format_version: FORMAT_VERSION,
        samples: opts.samples,
        seed: opts.seed,
        never_upper_bound: never_upper_bound(opts.samples),
        certify: opts.certify.clone(),
        summary,
        pairs: records,
    })
}

/// What the verdicts of all pairs share.
struct Context<'a> {
    engine: &'a Engine,
    opts: &'a SampleOptions,
    exact: &'a [Option<ExactLink>],
    hulls: &'a TypeShapes,
    hull_of: &'a [Option<usize>],
    home: &'a [f64],
}

/// One sample's verdict on the exact geometry.
#[derive(Clone, Copy, PartialEq)]
enum Contact {
    Apart,
    /// One lies inside the other without their surfaces meeting.
    Inside,
    Touch,
}

impl Context<'_> {
    fn links(&self, a: usize, b: usize) -> (&ExactLink, &ExactLink) {
        match (&self.exact[a], &self.exact[b]) {
            (Some(x), Some(y)) => (x, y),
            // Only pairs of links with geometry are examined.
            _ => unreachable!("pairs of links with geometry"),
        }
    }

    /// The exact verdict at `q`, examining the geometry only when the link hulls overlap.
    fn contact(&self, a: usize, b: usize, q: &[f64], gate: bool) -> Contact {
        let (pa, pb) = self.engine.kinematics.pair_poses(q, a, b);
        if gate {
            let (ha, hb) = self.hull_pair(a, b);
            let hulls = PlacedPair {
                a: ha,
                b: hb,
                link_a: pa,
                link_b: pb,
            };
            if !hulls.overlaps() {
                return Contact::Apart;
            }
        }
        let (la, lb) = self.links(a, b);
        if la.touch(&pa, lb, &pb) {
            Contact::Touch
        } else if la.encloses(&pa, lb, &pb) {
            Contact::Inside
        } else {
            Contact::Apart
        }
    }

    fn hull_pair(
        &self,
        a: usize,
        b: usize,
    ) -> (
        &crate::collision::CollisionShape,
        &crate::collision::CollisionShape,
    ) {
        // `mesh_verdicts` checked that every link with geometry has a hull.
        let index = |l: usize| self.hull_of[l].unwrap_or_default();
        (&self.hulls.shapes[index(a)], &self.hulls.shapes[index(b)])
    }

    /// The verdict from home and the samples (before any certificate).
    fn sampled_verdict(
        &self,
        a: usize,
        b: usize,
        adjacent: bool,
        hull_collisions: Option<u64>,
    ) -> LinkPairRecord {
        let robot = &self.engine.robot;
        let n = self.opts.samples;
        let mut r = LinkPairRecord {
            link1: robot.links[a].name.clone(),
            link2: robot.links[b].name.clone(),
            reason: Reason::Checked,
            home_touch: false,
            examined: 0,
            touches: 0,
            overlaps: 0,
            witness: None,
            evidence: None,
            certificate: None,
        };
        if adjacent {
            r.reason = Reason::Adjacent;
            return r;
        }
        let at_home = self.contact(a, b, self.home, false);
        r.home_touch = at_home == Contact::Touch;
        if r.home_touch {
            r.reason = Reason::Default;
            return r;
        }
        if !robot.moves_between(a, b) {
            // Rigid: home is every sample, and exact.
            r.examined = n;
            if at_home == Contact::Inside {
                r.overlaps = n;
                r.witness = Some(Witness {
                    sample: None,
                    q: self.home.to_vec(),
                });
            } else {
                r.reason = Reason::Never;
                r.evidence = Some(NeverEvidence::Certified);
            }
            return r;
        }
        if hull_collisions == Some(0) {
            // The hulls never overlapped, so neither did the geometry inside them.
            r.examined = n;
            r.reason = Reason::Never;
            return r;
        }
        let mut q = Vec::new();
        'chunks: for chunk in 0..n.div_ceil(CHUNK) {
            let mut rng = Rng::new(self.opts.seed, chunk);
            for k in chunk * CHUNK..((chunk + 1) * CHUNK).min(n) {
                random_configuration(self.engine.kinematics.dofs(), &mut rng, &mut q);
                let c = self.contact(a, b, &q, true);
                r.examined += 1;
                r.touches += u64::from(c == Contact::Touch);
                if c != Contact::Apart {
                    r.overlaps += 1;
                    if r.witness.is_none() {
                        r.witness = Some(Witness {
                            sample: Some(k),
                            q: q.clone(),
                        });
                    }
                }
                // Settled: neither always (a sample without touch) nor never (an overlap).
                if r.overlaps > 0 && r.touches < r.examined {
                    break 'chunks;
                }
            }
        }
        r.reason = if r.touches == n {
            Reason::Always
        } else if r.overlaps == 0 {
            Reason::Never
        } else {
            Reason::Checked
        };
        r
    }

    /// The certificate search for a moving `never` pair: on the link hulls, and where they overlap
    /// at a box centre without the exact geometry colliding there, again with the exact geometry's
    /// distance where the hulls' bound falls short (the box budget counts both searches).
    fn certificate(&self, (a, b): (usize, usize), budget: u64) -> Certificate {
        let (hull_a, hull_b) = self.hull_pair(a, b);
        let (la, lb) = self.links(a, b);
        let exact = |pa: &Pose, pb: &Pose, enough: f64| la.distance_above(pa, lb, pb, enough);
        let mut pair = PairGeometry {
            kinematics: &self.engine.kinematics,
            link_a: a,
            hull_a,
            link_b: b,
            hull_b,
            base: self.home,
            exact: None,
        };
        let params = &self.opts.certify;
        let collides = |q: &[f64]| self.contact(a, b, q, false) != Contact::Apart;
        let first = certify(&pair, params.margin, budget, collides);
        if first.status != Status::HullsTouch || params.max_exact_per_pair == 0 {
            return first;
        }
        pair.exact = Some((&exact, params.max_exact_per_pair));
        let mut second = certify(
            &pair,
            params.margin,
            budget.saturating_sub(first.boxes),
            collides,
        );
        second.boxes += first.boxes;
        second
    }
}

/// The `mesh` file of a URDD's current sample stage, or `None` when it has none (sampled without the
/// exact geometry).
pub fn load_mesh_file(urdd: &Urdd) -> Result<Option<MeshFile>> {
    urdd.sample_output(MESH_FILE)
}
