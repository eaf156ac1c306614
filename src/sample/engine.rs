//! The sampling engine: shapes of the selected types prepared for queries, sample configurations drawn
//! per chunk, and the per-pair loop that runs exact queries only where the sphere bounds cannot decide.

use super::rng::Rng;
use super::stats::PairStats;
use super::table::{self, Table};
use crate::collision::{
    CollisionShape, ShapeSet, Versus, axis_bounds, signed_distance, sphere_bounds, versus,
};
use crate::error::Result;
use crate::math::{Pose, Vec3};
use crate::robot::{Kinematics, Robot};
use crate::shapes::ShapeType;
use crate::urdd::Urdd;
use rayon::prelude::*;

/// Samples per chunk; chunk c draws from its own random stream, so sample k is the same in any run.
pub const CHUNK: u64 = 1024;

/// The shapes of one type, ready for queries, and the pairs to sample.
#[derive(Debug)]
pub struct TypeSet {
    /// The shape type.
    pub shape_type: ShapeType,
    /// Shapes in matrix order.
    pub shapes: Vec<CollisionShape>,
    /// Link index of each shape.
    pub links: Vec<usize>,
    /// All pairs `(i, j)`, `i < j`, in row-major order: the order of every per-pair vector.
    pub pairs: Vec<(u32, u32)>,
    /// For each pair, whether any joint between its links moves (else it is rigid: computed once).
    pub moving: Vec<bool>,
    /// For each pair that depends on one DOF only, its distance table.
    pub tables: Vec<Option<Table>>,
}

/// Everything sampling needs, loaded from a URDD.
#[derive(Debug)]
pub struct Engine {
    /// The robot model.
    pub robot: Robot,
    /// Forward kinematics.
    pub kinematics: Kinematics,
    /// One set per selected type.
    pub sets: Vec<TypeSet>,
}

/// The parameters every chunk of a run shares.
#[derive(Debug, Clone, Copy)]
pub struct ChunkRun<'a> {
    /// Random seed.
    pub seed: u64,
    /// Total samples of the run.
    pub total: u64,
    /// Per set and pair: samples with a lower index enter the mean with exact distances.
    pub mean_budget: &'a [Vec<u64>],
    /// A sample is skipped for the extremes only when it cannot change them by more than this.
    pub tol: f64,
    /// Per set and pair, statistics over samples every run contains (the pilot, samples `0..PILOT`),
    /// or empty: the run's minimum and maximum are at least as extreme as theirs, so no chunk needs an
    /// exact query for a sample that could not beat them either.
    pub known: &'a [Vec<PairStats>],
}

/// What one pair's samples share within a run.
#[derive(Debug, Clone, Copy)]
struct PairRun<'a> {
    /// Samples with a lower index enter the mean with exact distances.
    mean_budget: u64,
    /// A sample is skipped for the extremes only when it cannot change them by more than this.
    tol: f64,
    /// Statistics over samples every run contains (see [`ChunkRun::known`]).
    known: Option<&'a PairStats>,
}

/// Samples per block: a chunk is placed a block at a time, and each pair then runs through the block
/// with its statistics in cache (the order of samples per pair, and so every result, is unchanged).
const BLOCK: usize = 128;

/// Consecutive samples placed together: their configurations, link poses and, per set, the world
/// centres of every shape's enclosing and inscribed spheres (a shape's over the block side by side).
#[derive(Debug, Default, Clone)]
pub struct Block {
    /// Index of the block's first sample.
    first: u64,
    /// Number of samples.
    len: usize,
    /// Configurations, `len` rows of one value per DOF.
    q: Vec<f64>,
    /// Link poses, `len` rows of one pose per link.
    links: Vec<Pose>,
    /// Per set, enclosing-sphere centres: `len` per shape, shape after shape.
    outer: Vec<Vec<Vec3>>,
    /// Per set, inscribed-sphere centres, laid out as `outer`.
    inner: Vec<Vec<Vec3>>,
}

/// Per-worker scratch space, reused across samples.
#[derive(Default)]
pub struct Scratch {
    block: Block,
    /// Per set and pair, the anchors (hull vertices) of the last bounds found in this chunk.
    anchors: Vec<Vec<[u32; 2]>>,
}

impl Engine {
    /// Loads the robot and the shapes of `types` from a preprocessed URDD.
    pub fn load(urdd: &Urdd, types: &[ShapeType]) -> Result<Engine> {
        let record = urdd.robot()?;
        let robot = record.robot;
        let kinematics = Kinematics::new(&robot);
        let mut sets = Vec::new();
        for &t in types {
            let ShapeSet { shapes, links, .. } = ShapeSet::load(urdd, t, robot.links.len())?;
            let n = shapes.len() as u32;
            let pairs: Vec<(u32, u32)> = (0..n)
                .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
                .collect();
            let moving = pairs
                .iter()
                .map(|&(i, j)| robot.moves_between(links[i as usize], links[j as usize]))
                .collect();
            sets.push(TypeSet {
                shape_type: t,
                shapes,
                links,
                pairs,
                moving,
                tables: Vec::new(),
            });
        }
        let mut engine = Engine {
            robot,
            kinematics,
            sets,
        };
        for s in 0..engine.sets.len() {
            let tables = (0..engine.sets[s].pairs.len())
                .into_par_iter()
                .map(|p| {
                    if engine.sets[s].moving[p] {
                        table::build(&engine, s, p)
                    } else {
                        None
                    }
                })
                .collect();
            engine.sets[s].tables = tables;
        }
        Ok(engine)
    }

    /// The configuration of sample `k` under `seed`.
    pub fn configuration(&self, seed: u64, k: u64) -> Vec<f64> {
        let mut rng = Rng::new(seed, k / CHUNK);
        let mut q = Vec::new();
        for _ in 0..=(k % CHUNK) {
            self.draw(&mut rng, &mut q);
        }
        q
    }

    fn draw(&self, rng: &mut Rng, q: &mut Vec<f64>) {
        q.clear();
        q.extend(
            self.kinematics
                .dofs()
                .iter()
                .map(|d| rng.range(d.lower, d.upper)),
        );
    }

    /// Signed distance of pair `p` of set `s` at configuration `q` (exact).
    pub fn pair_distance(&self, s: usize, p: usize, q: &[f64]) -> f64 {
        self.pair_at(s, p, q).distance()
    }

    /// Pair `p` of set `s` placed at configuration `q` (forward kinematics of its two links only, from
    /// their common ancestor).
    pub fn pair_at(&self, s: usize, p: usize, q: &[f64]) -> PlacedPair<'_> {
        let set = &self.sets[s];
        let (i, j) = set.pairs[p];
        let (a, b) = (&set.shapes[i as usize], &set.shapes[j as usize]);
        let (link_a, link_b) =
            self.kinematics
                .pair_poses(q, set.links[i as usize], set.links[j as usize]);
        PlacedPair {
            a,
            b,
            link_a,
            link_b,
        }
    }

    /// Draws the next `len` samples from `rng` (the first numbered `first`) and places them.
    fn place(&self, rng: &mut Rng, first: u64, len: usize, block: &mut Block) {
        let (dofs, links) = (self.kinematics.dofs().len(), self.robot.links.len());
        block.first = first;
        block.len = len;
        block.q.clear();
        block.links.clear();
        let (mut q, mut poses) = (Vec::with_capacity(dofs), Vec::with_capacity(links));
        for _ in 0..len {
            self.draw(rng, &mut q);
            self.kinematics.link_poses_into(&q, &mut poses);
            block.q.extend_from_slice(&q);
            block.links.extend_from_slice(&poses);
        }
        block.outer.resize(self.sets.len(), Vec::new());
        block.inner.resize(self.sets.len(), Vec::new());
        for (s, set) in self.sets.iter().enumerate() {
            let (outer, inner) = (&mut block.outer[s], &mut block.inner[s]);
            outer.clear();
            inner.clear();
            for (shape, &link) in set.shapes.iter().zip(&set.links) {
                for kk in 0..len {
                    let pose = &block.links[kk * links + link];
                    outer.push(pose.transform_point(shape.outer_center));
                    inner.push(pose.transform_point(shape.inner_center));
                }
            }
        }
    }

    /// Statistics of the first `n` samples (chunk 0's) with an exact distance for every moving pair at
    /// every sample: the same as [`Engine::run_chunk`] computes for them under a mean budget of at least
    /// `n`, but in parallel over pairs.
    pub fn pilot(&self, seed: u64, n: u64) -> Vec<Vec<PairStats>> {
        let mut block = Block::default();
        self.place(&mut Rng::new(seed, 0), 0, n.min(CHUNK) as usize, &mut block);
        self.sets
            .iter()
            .enumerate()
            .map(|(s, set)| {
                (0..set.pairs.len())
                    .into_par_iter()
                    .map(|p| {
                        let mut st = PairStats::default();
                        if set.moving[p] {
                            let run = PairRun {
                                mean_budget: n,
                                tol: 0.0,
                                known: None,
                            };
                            self.observe_block(set, s, p, &block, &run, &mut [0, 0], &mut st);
                        }
                        st
                    })
                    .collect()
            })
            .collect()
    }

    /// Samples chunk `chunk` (samples `chunk*CHUNK ..` up to `run.total`) into `acc[set][pair]`, which
    /// must hold the statistics of the chunk's first `done` samples (empty for `done == 0`): with
    /// `run.tol > 0` which samples get exact queries depends on what the chunk has seen, so each chunk
    /// is computed alone and merged, keeping results independent of threads and shards. Rigid pairs are
    /// skipped here (the caller computes them once).
    pub fn run_chunk(
        &self,
        run: &ChunkRun,
        chunk: u64,
        done: u64,
        acc: &mut [Vec<PairStats>],
        scratch: &mut Scratch,
    ) {
        let mut rng = Rng::new(run.seed, chunk);
        let first = chunk * CHUNK;
        let last = (first + CHUNK).min(run.total);
        // Anchors start afresh in every chunk, so a chunk's result does not depend on the worker.
        scratch.anchors.resize(self.sets.len(), Vec::new());
        for (anchors, set) in scratch.anchors.iter_mut().zip(&self.sets) {
            anchors.clear();
            anchors.resize(set.pairs.len(), [0, 0]);
        }
        let mut skipped = Vec::new();
        for _ in 0..done {
            self.draw(&mut rng, &mut skipped);
        }
        let block = &mut scratch.block;
        let mut start = first + done;
        while start < last {
            let len = (last - start).min(BLOCK as u64) as usize;
            self.place(&mut rng, start, len, block);
            let sets = self
                .sets
                .iter()
                .zip(acc.iter_mut())
                .zip(&mut scratch.anchors);
            for (s, ((set, stats), anchors)) in sets.enumerate() {
                let known = run.known.get(s);
                for (p, (st, anchor)) in stats.iter_mut().zip(anchors.iter_mut()).enumerate() {
                    if set.moving[p] {
                        let pair_run = PairRun {
                            mean_budget: run.mean_budget[s][p],
                            tol: run.tol,
                            known: known.map(|v| &v[p]),
                        };
                        self.observe_block(set, s, p, block, &pair_run, anchor, st);
                    }
                }
            }
            start += len as u64;
        }
    }

    /// Adds every sample of `block` of moving pair `p` of set `s` to `st`, in sample order.
    #[allow(clippy::too_many_arguments)]
    fn observe_block(
        &self,
        set: &TypeSet,
        s: usize,
        p: usize,
        block: &Block,
        run: &PairRun,
        anchors: &mut [u32; 2],
        st: &mut PairStats,
    ) {
        for kk in 0..block.len {
            self.observe(set, s, p, block, kk, run, anchors, st);
        }
    }

    /// Adds sample `kk` of `block` of moving pair `p` of set `s` to `st`, with an exact query only
    /// where the bounds cannot decide: the sample enters the mean (`k < run.mean_budget`), the
    /// collision verdict is open, or it could move the minimum or maximum by more than `run.tol`
    /// beyond both `st` and `run.known`.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn observe(
        &self,
        set: &TypeSet,
        s: usize,
        p: usize,
        block: &Block,
        kk: usize,
        run: &PairRun,
        anchors: &mut [u32; 2],
        st: &mut PairStats,
    ) {
        let PairRun {
            mean_budget,
            tol,
            known,
        } = *run;
        let k = block.first + kk as u64;
        let n = block.len;
        debug_assert_eq!(block.outer[s].len(), n * set.shapes.len());
        let (i, j) = set.pairs[p];
        let (i, j) = (i as usize, j as usize);
        let (a, b) = (&set.shapes[i], &set.shapes[j]);
        let (outer, inner) = (&block.outer[s], &block.inner[s]);
        let (oi, oj) = (outer[i * n + kk], outer[j * n + kk]);
        // Sphere bounds on the signed distance: lower from the enclosing spheres, upper from the
        // inscribed ones (see `collision` for why both hold with penetration too).
        let (mut lower, mut upper) =
            sphere_bounds(a, oi, inner[i * n + kk], b, oj, inner[j * n + kk]);
        if let Some(t) = &set.tables[p] {
            let (lo, hi) = t.bounds(block.q[kk * self.kinematics.dofs().len() + t.dof]);
            lower = lower.max(lo);
            upper = upper.min(hi);
        }
        // The control bound of the mean estimate: the same cheap bound for every sample.
        let control = if lower.is_finite() { lower } else { 0.0 };
        st.observe_bound(control);
        let exact_mean = k < mean_budget;
        let need_min = |lower: f64, st: &PairStats| {
            st.could_lower_min(lower, k, tol)
                && known.is_none_or(|n| n.could_lower_min(lower, k, tol))
        };
        let need_max = |upper: f64, st: &PairStats| {
            st.could_raise_max(upper, k, tol)
                && known.is_none_or(|n| n.could_raise_max(upper, k, tol))
        };
        let needs_exact = |lower: f64, upper: f64, st: &PairStats| {
            exact_mean
                || (lower <= 0.0 && upper >= 0.0)
                || need_min(lower, st)
                || need_max(upper, st)
        };
        if !needs_exact(lower, upper, st) {
            // The bounds decide: no new extreme, and the verdict is known.
            st.collisions += u64::from(upper < 0.0);
            return;
        }
        // Shape poses only for the pairs that get past the sphere bounds.
        let poses = &block.links[kk * self.robot.links.len()..];
        let (pa, pb) = (a.pose(&poses[set.links[i]]), b.pose(&poses[set.links[j]]));
        if !exact_mean {
            // The points that bounded this pair at its last sample are still two points of the
            // shapes: their distance is a cheap upper bound.
            let (xa, xb) = (a.anchor(&pa, anchors[0]), b.anchor(&pb, anchors[1]));
            upper = upper.min(xa.distance(xb));
            if !needs_exact(lower, upper, st) {
                st.collisions += u64::from(upper < 0.0);
                return;
            }
            // The shapes' extreme points along the line between the centres tighten both bounds.
            let axis = (oj - oi).normalize_or(Vec3::Z);
            let (lo, hi) = axis_bounds(a, &pa, b, &pb, axis, anchors);
            lower = lower.max(lo);
            upper = upper.min(hi);
            if !needs_exact(lower, upper, st) {
                st.collisions += u64::from(upper < 0.0);
                return;
            }
            // One side left open: a GJK that stops once it knows the side of a threshold.
            let (open_min, open_max) = (need_min(lower, st), need_max(upper, st));
            let min_threshold = st.min.min(known.map_or(f64::INFINITY, |n| n.min)) - tol;
            let max_threshold = st.max.max(known.map_or(f64::NEG_INFINITY, |n| n.max)) + tol;
            let decided = match (open_min, open_max) {
                // Only the verdict: any positive threshold tells overlap from separation.
                (false, false) => Some(versus(a, &pa, b, &pb, f64::MIN_POSITIVE)),
                // Beyond a positive threshold under the minimum: no new minimum, no collision.
                (true, false) if min_threshold > 0.0 => {
                    Some(versus(a, &pa, b, &pb, min_threshold)).filter(|v| *v == Versus::Beyond)
                }
                // Within the maximum (and its tolerance, so no tie can move the witness): no new
                // maximum; an overlap is a collision that cannot be a new minimum either.
                (false, true) if tol > 0.0 && max_threshold > 0.0 => {
                    Some(versus(a, &pa, b, &pb, max_threshold)).filter(|v| *v != Versus::Beyond)
                }
                _ => None,
            };
            if let Some(v) = decided {
                st.collisions += u64::from(v == Versus::Overlap);
                return;
            }
        }
        let d = signed_distance(a, &pa, b, &pb);
        st.observe_extremes(d, k);
        if exact_mean {
            st.observe_mean(d, control);
        }
        st.collisions += u64::from(d <= 0.0);
    }
}

/// Two shapes of a pair with their links' poses at some configuration.
#[derive(Debug, Clone, Copy)]
pub struct PlacedPair<'a> {
    a: &'a CollisionShape,
    b: &'a CollisionShape,
    link_a: Pose,
    link_b: Pose,
}

impl PlacedPair<'_> {
    /// A lower bound on the signed distance from the enclosing spheres (cheap).
    pub fn lower_bound(&self) -> f64 {
        let ca = self.link_a.transform_point(self.a.outer_center);
        let cb = self.link_b.transform_point(self.b.outer_center);
        ca.distance(cb) - self.a.outer_radius - self.b.outer_radius
    }

    /// The exact signed distance.
    pub fn distance(&self) -> f64 {
        signed_distance(
            self.a,
            &self.a.pose(&self.link_a),
            self.b,
            &self.b.pose(&self.link_b),
        )
    }
}
