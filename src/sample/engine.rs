//! The sampling engine: shapes of the selected types prepared for queries, sample configurations drawn
//! per chunk, and the per-pair loop that runs exact queries only where the sphere bounds cannot decide.

use super::block::{BLOCK, Block};
use super::sets::PairSet;
use super::stats::PairStats;
use super::table::{self, Table};
use super::work::{Settled, SharedWork, Work};
use crate::collision::{
    Hint, Tether, Window, axis_bounds, box_bounds, outer_gap, signed_distance_hinted,
    sphere_bounds, window,
};
use crate::error::Result;
use crate::math::Vec3;
use crate::rng::Rng;
use crate::robot::{Kinematics, Robot, random_configuration};
use crate::shapes::ShapeType;
use crate::urdd::{TypeShapes, Urdd};
use rayon::prelude::*;

/// Samples per chunk; chunk c draws from its own random stream, so sample k is the same in any run.
pub const CHUNK: u64 = 1024;

/// Everything sampling needs, loaded from a URDD.
#[derive(Debug)]
pub struct Engine {
    /// The robot model.
    pub robot: Robot,
    /// Forward kinematics.
    pub kinematics: Kinematics,
    /// One set per selected type.
    pub sets: Vec<PairSet>,
    /// Per set and pair, the distance table of a pair that depends on one or two DOFs (or on two
    /// coaxial joints' relative turn): `None` for every pair until [`Engine::with_tables`] builds them.
    pub tables: Vec<Vec<Option<Table>>>,
    /// Per set, what the sampling loop has done so far.
    work: Vec<SharedWork>,
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
    /// Per set and pair, statistics over samples every run contains (the scout's, see
    /// [`Engine::scout`]), or empty: the run's minimum and maximum are at least as extreme as theirs,
    /// so no chunk needs an exact query for a sample that could not beat them either.
    pub known: &'a [Vec<PairStats>],
    /// Per set and pair, a tether taken where the pair was farthest apart (see [`Engine::tethers`]),
    /// or empty.
    pub tethers: &'a [Vec<Option<Tether>>],
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
    /// An upper bound for the samples the maximum could come from (see [`ChunkRun::tethers`]).
    tether: Option<&'a Tether>,
}

/// Per-worker scratch space, reused across samples.
#[derive(Default)]
pub struct ChunkScratch {
    block: Block,
    /// Per set and pair, what the pair's last queries in this chunk left for its next sample.
    hints: Vec<Vec<Hint>>,
}

impl Engine {
    /// Loads the robot and the shapes of `types` from a preprocessed URDD, without distance tables:
    /// enough for the exact queries, the search and the verdicts (merging shards); sampling wants
    /// [`Engine::with_tables`] too.
    pub fn load(urdd: &Urdd, types: &[ShapeType]) -> Result<Engine> {
        let record = urdd.robot()?;
        let robot = record.robot;
        let kinematics = Kinematics::new(&robot);
        let mut sets = Vec::new();
        for &t in types {
            let TypeShapes { shapes, links, .. } = urdd.collision_shapes(t, robot.links.len())?;
            let n = shapes.len() as u32;
            let pairs: Vec<(u32, u32)> = (0..n)
                .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
                .collect();
            let moving = pairs
                .iter()
                .map(|&(i, j)| robot.moves_between(links[i as usize], links[j as usize]))
                .collect();
            sets.push(PairSet {
                shape_type: t,
                shapes,
                links,
                pairs,
                moving,
            });
        }
        Ok(Engine {
            robot,
            kinematics,
            work: sets.iter().map(|_| SharedWork::default()).collect(),
            tables: sets.iter().map(|set| vec![None; set.pairs.len()]).collect(),
            sets,
        })
    }

    /// The engine with the distance tables of its moving pairs built (in parallel over pairs), which
    /// the sampling loop's cheap bounds read. Only bounds come from them: an engine without them
    /// computes the same results, with more exact queries.
    pub fn with_tables(mut self) -> Engine {
        let (robot, kinematics) = (&self.robot, &self.kinematics);
        self.tables = (self.sets.iter())
            .map(|set| {
                (0..set.pairs.len())
                    .into_par_iter()
                    .map(|p| {
                        if set.moving[p] {
                            table::build(robot, kinematics, set, p)
                        } else {
                            None
                        }
                    })
                    .collect()
            })
            .collect();
        self
    }

    /// Per set, what the sampling loop has done so far (pilot, scout and chunks).
    pub fn work(&self) -> Vec<Work> {
        self.work.iter().map(SharedWork::get).collect()
    }

    /// The configuration of sample `k` under `seed`.
    pub fn configuration(&self, seed: u64, k: u64) -> Vec<f64> {
        let mut rng = Rng::new(seed, k / CHUNK);
        let mut q = Vec::new();
        for _ in 0..=(k % CHUNK) {
            random_configuration(self.kinematics.dofs(), &mut rng, &mut q);
        }
        q
    }

    /// The configurations of samples `0..end` under `seed`, one row of DOF values after another.
    fn configurations(&self, seed: u64, end: u64) -> Vec<f64> {
        let mut all = Vec::new();
        let mut q = Vec::new();
        for chunk in 0..end.div_ceil(CHUNK) {
            let mut rng = Rng::new(seed, chunk);
            for _ in chunk * CHUNK..((chunk + 1) * CHUNK).min(end) {
                random_configuration(self.kinematics.dofs(), &mut rng, &mut q);
                all.extend_from_slice(&q);
            }
        }
        all
    }

    /// Per set and pair, the tether of the pair's closest points (or deep point) at the sample where
    /// `stats` (over samples `0..end` under `seed`) found it farthest apart: its distance bounds the
    /// pair's from above in every sample, tightly near the maximum, where the inscribed spheres'
    /// bound is loose for thin shapes. `None` for rigid pairs and pairs of spheres (whose sphere
    /// bounds are exact), in parallel over pairs.
    pub fn tethers(
        &self,
        seed: u64,
        end: u64,
        stats: &[Vec<PairStats>],
    ) -> Vec<Vec<Option<Tether>>> {
        let configurations = self.configurations(seed, end);
        let dofs = self.kinematics.dofs().len();
        (self.sets.iter().zip(stats))
            .map(|(set, stats)| {
                (0..set.pairs.len())
                    .into_par_iter()
                    .map(|p| {
                        let (i, j) = set.pairs[p];
                        let (a, b) = (&set.shapes[i as usize], &set.shapes[j as usize]);
                        let k = stats[p].max_sample;
                        if !set.moving[p] || (a.is_ball() && b.is_ball()) || k >= end {
                            return None;
                        }
                        let k = k as usize;
                        let pair = set.pair_at(
                            &self.kinematics,
                            p,
                            &configurations[k * dofs..(k + 1) * dofs],
                        );
                        let mut hint = Hint::default();
                        pair.distance_hinted(&mut hint);
                        hint.tether(a, &a.pose(&pair.link_a), b, &b.pose(&pair.link_b))
                    })
                    .collect()
            })
            .collect()
    }

    /// Signed distance of pair `p` of set `s` at configuration `q` (exact).
    pub fn pair_distance(&self, s: usize, p: usize, q: &[f64]) -> f64 {
        self.sets[s].pair_at(&self.kinematics, p, q).distance()
    }

    /// Empty statistics for every pair of every set.
    pub fn empty_stats(&self) -> Vec<Vec<PairStats>> {
        self.sets
            .iter()
            .map(|s| vec![PairStats::default(); s.pairs.len()])
            .collect()
    }

    /// Continues `stats` (statistics of samples `0..start` per set and pair) through samples
    /// `start..end`, every pair running through them in order with its own hint, in parallel over
    /// pairs: a chunk's work, but with the extremes and hints of all the samples before, so the
    /// extremes it ends with are close to the run's and prune every later chunk (see
    /// [`ChunkRun::known`]). `run.known` is not used; `run.tethers` is. Its blocks start at `start`
    /// (every run places the same ones: the caller's `start` is fixed).
    pub fn scout(&self, run: &ChunkRun, start: u64, end: u64, stats: &mut [Vec<PairStats>]) {
        let mut hints: Vec<Vec<Hint>> = self
            .sets
            .iter()
            .map(|set| vec![Hint::default(); set.pairs.len()])
            .collect();
        let (mut block, mut skipped) = (Block::default(), Vec::new());
        for chunk in 0..end.div_ceil(CHUNK) {
            let mut rng = Rng::new(run.seed, chunk);
            let (mut at, last) = (chunk * CHUNK, ((chunk + 1) * CHUNK).min(end));
            while at < last {
                let mut len = (last - at).min(BLOCK as u64) as usize;
                if at < start {
                    len = len.min((start - at) as usize);
                    (0..len).for_each(|_| {
                        random_configuration(self.kinematics.dofs(), &mut rng, &mut skipped)
                    });
                    at += len as u64;
                    continue;
                }
                block.place(&self.kinematics, &self.sets, &mut rng, at, len);
                for (s, (set, (stats, hints))) in self
                    .sets
                    .iter()
                    .zip(stats.iter_mut().zip(&mut hints))
                    .enumerate()
                {
                    let work = stats
                        .par_iter_mut()
                        .zip(hints.par_iter_mut())
                        .enumerate()
                        .filter(|(p, _)| set.moving[*p])
                        .map(|(p, (st, hint))| {
                            let pair_run = PairRun {
                                mean_budget: run.mean_budget[s][p],
                                tol: run.tol,
                                known: None,
                                tether: run.tethers.get(s).and_then(|v| v[p].as_ref()),
                            };
                            let mut work = Work::default();
                            self.observe_block(set, s, p, &block, &pair_run, hint, st, &mut work);
                            work
                        })
                        .reduce(Work::default, |mut a, b| {
                            a.add(&b);
                            a
                        });
                    self.work[s].add(&work);
                }
                at += len as u64;
            }
        }
    }

    /// Samples chunk `chunk` (samples `chunk*CHUNK ..` up to `run.total`) into `acc[set][pair]`, which
    /// must be empty: with `run.tol > 0` which samples get exact queries depends on what the chunk has
    /// seen, so each chunk is computed alone and merged, keeping results independent of threads and
    /// shards. Rigid pairs are skipped here (the caller computes them once).
    pub fn run_chunk(
        &self,
        run: &ChunkRun,
        chunk: u64,
        acc: &mut [Vec<PairStats>],
        scratch: &mut ChunkScratch,
    ) {
        let mut rng = Rng::new(run.seed, chunk);
        let first = chunk * CHUNK;
        let last = (first + CHUNK).min(run.total);
        // Hints start afresh in every chunk, so a chunk's result does not depend on the worker.
        scratch.hints.resize(self.sets.len(), Vec::new());
        for (hints, set) in scratch.hints.iter_mut().zip(&self.sets) {
            hints.clear();
            hints.resize(set.pairs.len(), Hint::default());
        }
        let block = &mut scratch.block;
        // The chunk's work per set, added to the shared counts once at its end.
        let mut work = vec![Work::default(); self.sets.len()];
        let mut start = first;
        while start < last {
            let len = (last - start).min(BLOCK as u64) as usize;
            block.place(&self.kinematics, &self.sets, &mut rng, start, len);
            let sets = self.sets.iter().zip(acc.iter_mut()).zip(&mut scratch.hints);
            for (s, (((set, stats), hints), work)) in sets.zip(&mut work).enumerate() {
                let known = run.known.get(s);
                for (p, (st, hint)) in stats.iter_mut().zip(hints.iter_mut()).enumerate() {
                    if set.moving[p] {
                        let pair_run = PairRun {
                            mean_budget: run.mean_budget[s][p],
                            tol: run.tol,
                            known: known.map(|v| &v[p]),
                            tether: run.tethers.get(s).and_then(|v| v[p].as_ref()),
                        };
                        self.observe_block(set, s, p, block, &pair_run, hint, st, work);
                    }
                }
            }
            start += len as u64;
        }
        for (shared, work) in self.work.iter().zip(&work) {
            shared.add(work);
        }
    }

    /// Adds every sample of `block` of moving pair `p` of set `s` to `st`, in sample order, and what
    /// that took to `work`.
    #[allow(clippy::too_many_arguments)]
    fn observe_block(
        &self,
        set: &PairSet,
        s: usize,
        p: usize,
        block: &Block,
        run: &PairRun,
        hint: &mut Hint,
        st: &mut PairStats,
        work: &mut Work,
    ) {
        // First the cheap bounds of every sample, in one pass of independent loads and arithmetic
        // (the table lookups miss the cache, and here the misses overlap), then the samples in order.
        debug_assert!(block.len <= BLOCK);
        // The block's first samples that enter the mean exactly.
        let exact_mean = run
            .mean_budget
            .saturating_sub(block.first)
            .min(block.len as u64) as usize;
        work.pair_samples += block.len as u64;
        let (i, j) = set.pairs[p];
        let (a, b) = (&set.shapes[i as usize], &set.shapes[j as usize]);
        if a.is_ball() && b.is_ball() {
            // Two spheres: the distance of their centres less their radii is exact.
            let n = block.len;
            let outer = &block.outer[s];
            let (oa, ob) = (&outer[i as usize * n..][..n], &outer[j as usize * n..][..n]);
            let mut d = [0.0; BLOCK];
            for ((d, a_), b_) in d.iter_mut().zip(oa).zip(ob) {
                *d = outer_gap(a, *a_, b, *b_);
            }
            work.cheap += n as u64;
            st.observe_exact_block(&d[..n], block.first, exact_mean);
            return;
        }
        let mut bounds = [(0.0, 0.0); BLOCK];
        let bounds = &mut bounds[..block.len];
        self.cheap_bounds(set, s, p, block, bounds);
        // The control bound of the mean estimate: the same cheap bound for every sample.
        st.observe_bounds(bounds.iter().map(|&b| control(b)));
        // A sample whose cheap bounds decide its verdict and lie strictly inside the extremes as they
        // stand at the block's start adds only its verdict: the extremes only tighten within the
        // block, so `observe` would decide it the same way. The others go to `observe`, in order.
        let known = run.known;
        let lo = st.min.min(known.map_or(f64::INFINITY, |n| n.min)) - run.tol;
        let hi = st.max.max(known.map_or(f64::NEG_INFINITY, |n| n.max)) + run.tol;
        let mut collisions = 0;
        for (kk, &(lower, upper)) in bounds.iter().enumerate() {
            if kk >= exact_mean && (lower > 0.0 || upper < 0.0) && lo < lower && upper < hi {
                collisions += u64::from(upper < 0.0);
                work.cheap += 1;
            } else {
                work.count(self.observe(set, s, p, block, kk, (lower, upper), run, hint, st));
            }
        }
        st.collisions += collisions;
    }

    /// Bounds `(lower, upper)` on the signed distance of moving pair `p` of set `s` at every sample of
    /// `block`, one per element of `out`: from the enclosing spheres (lower) and the inscribed ones
    /// (upper; see `collision` for why both hold with penetration too), and from the pair's table if
    /// it has one.
    fn cheap_bounds(
        &self,
        set: &PairSet,
        s: usize,
        p: usize,
        block: &Block,
        out: &mut [(f64, f64)],
    ) {
        let n = block.len;
        debug_assert_eq!(block.outer[s].len(), n * set.shapes.len());
        let (i, j) = set.pairs[p];
        let (i, j) = (i as usize, j as usize);
        let (a, b) = (&set.shapes[i], &set.shapes[j]);
        let (outer, inner) = (&block.outer[s], &block.inner[s]);
        let (oa, ob) = (&outer[i * n..(i + 1) * n], &outer[j * n..(j + 1) * n]);
        let (ia, ib) = (&inner[i * n..(i + 1) * n], &inner[j * n..(j + 1) * n]);
        // The table's lookups land anywhere in it, and a large robot's tables leave the cache between
        // blocks: its lines are asked for now and arrive while the sphere bounds are computed.
        let table = self.tables[s][p].as_ref();
        if let Some(t) = table {
            t.prefetch();
        }
        for (kk, out) in out.iter_mut().enumerate() {
            *out = sphere_bounds(a, oa[kk], ia[kk], b, ob[kk], ib[kk]);
        }
        if let Some(t) = table {
            t.tighten(&block.q, self.kinematics.dofs().len(), out);
        }
    }

    /// Adds sample `kk` of `block` of moving pair `p` of set `s` to `st`, with an exact query only
    /// where the bounds cannot decide: the sample enters the mean (`k < run.mean_budget`), the
    /// collision verdict is open, or it could move the minimum or maximum by more than `run.tol`
    /// beyond both `st` and `run.known`. Returns what settled it.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn observe(
        &self,
        set: &PairSet,
        s: usize,
        p: usize,
        block: &Block,
        kk: usize,
        (mut lower, mut upper): (f64, f64),
        run: &PairRun,
        hint: &mut Hint,
        st: &mut PairStats,
    ) -> Settled {
        let PairRun {
            mean_budget,
            tol,
            known,
            tether,
        } = *run;
        let k = block.first + kk as u64;
        let control = control((lower, upper));
        let (i, j) = set.pairs[p];
        let (i, j) = (i as usize, j as usize);
        let (a, b) = (&set.shapes[i], &set.shapes[j]);
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
        // Whether the bounds decide the sample (no new extreme, and the verdict known); if they do,
        // its verdict is counted.
        let settle = |lower: f64, upper: f64, st: &mut PairStats| {
            let decided = !needs_exact(lower, upper, st);
            st.collisions += u64::from(decided && upper < 0.0);
            decided
        };
        if settle(lower, upper, st) {
            return Settled::Cheap;
        }
        let n = block.len;
        let poses = &block.links[kk * self.robot.links.len()..];
        if let (Some(t), false) = (tether, exact_mean) {
            upper = upper.min(t.upper(&poses[set.links[i]], &poses[set.links[j]]));
            if settle(lower, upper, st) {
                return Settled::Bounds;
            }
        }
        // Whether both shapes are boxes: their box bounds are then their extreme points along the
        // centre line.
        let mut boxes_exact = false;
        if !exact_mean {
            // The bounding boxes along the line between their centres (placed with the block).
            if let (Some(box_a), Some(box_b)) = (&a.bounding_box, &b.bounding_box) {
                let boxes = &block.boxes[s];
                boxes_exact = box_a.is_exact() && box_b.is_exact();
                let (ba, bb) = (&boxes[i * n + kk], &boxes[j * n + kk]);
                if let Some((lo, hi)) = box_bounds(ba, bb, boxes_exact) {
                    lower = lower.max(lo);
                    upper = upper.min(hi);
                    if settle(lower, upper, st) {
                        return Settled::Bounds;
                    }
                }
            }
        }
        // Shape poses only for the pairs that get past the cheap bounds.
        let (pa, pb) = (a.pose(&poses[set.links[i]]), b.pose(&poses[set.links[j]]));
        if !exact_mean {
            // Cheap upper bounds from the pair's hint: the distance between the points that bounded
            // it at its last sample (still points of the shapes), and the last query's closest
            // points or, after an overlap, its deep point (see `Hint::bounds`).
            let (xa, xb) = (
                a.anchor(&pa, hint.anchors[0]),
                b.anchor(&pb, hint.anchors[1]),
            );
            let (near, last_axis) = hint.bounds(&pa, b, &pb);
            upper = upper.min(xa.distance(xb)).min(near);
            if settle(lower, upper, st) {
                return Settled::Bounds;
            }
            // The shapes' extreme points along an axis tighten both bounds: along the last query's
            // direction turned with the first shape (exact again where the pair turns about that
            // direction, as two coaxial motors facing each other do), then (unless the box bounds
            // did) along the line between the enclosing spheres' centres, far tighter than the
            // spheres for elongated shapes.
            let centre = (!boxes_exact).then(|| {
                let (oi, oj) = (block.outer[s][i * n + kk], block.outer[s][j * n + kk]);
                (oj - oi).normalize_or(Vec3::Z)
            });
            for axis in last_axis.into_iter().chain(centre) {
                let (lo, hi) = axis_bounds(a, &pa, b, &pb, axis, &mut hint.anchors);
                lower = lower.max(lo);
                upper = upper.min(hi);
                if settle(lower, upper, st) {
                    return Settled::Bounds;
                }
            }
            // Still open: a GJK that stops once it knows the distance lies between the extremes (and
            // on which side of zero).
            let lo = if need_min(lower, st) {
                st.min.min(known.map_or(f64::INFINITY, |n| n.min)) - tol
            } else {
                f64::NEG_INFINITY
            };
            let hi = if need_max(upper, st) {
                st.max.max(known.map_or(f64::NEG_INFINITY, |n| n.max)) + tol
            } else {
                f64::INFINITY
            };
            if let Window::Inside { overlap } = window(a, &pa, b, &pb, lo, hi, (lower, upper), hint)
            {
                st.collisions += u64::from(overlap);
                return Settled::Window;
            }
        }
        let d = signed_distance_hinted(a, &pa, b, &pb, hint);
        st.observe_extremes(d, k);
        if exact_mean {
            st.observe_mean(d, control);
        }
        st.collisions += u64::from(d <= 0.0);
        Settled::Exact
    }
}

/// The control bound of the mean estimate of a sample with cheap bounds `bound`: the lower one (0 where
/// it is not finite).
#[inline]
fn control((lower, _): (f64, f64)) -> f64 {
    if lower.is_finite() { lower } else { 0.0 }
}
