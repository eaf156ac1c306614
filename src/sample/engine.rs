//! The sampling engine: shapes of the selected types prepared for queries, sample configurations drawn
//! per chunk, and the per-pair loop that runs exact queries only where the sphere bounds cannot decide.

use super::rng::Rng;
use super::stats::PairStats;
use super::table::{self, Table};
use crate::collision::{
    CollisionShape, ShapeSet, axis_lower_bound, signed_distance, sphere_bounds,
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
}

/// Per-worker scratch space, reused across samples.
#[derive(Default)]
pub struct Scratch {
    q: Vec<f64>,
    links: Vec<Pose>,
    outer: Vec<Vec3>,
    inner: Vec<Vec3>,
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

    /// Pair `p` of set `s` placed at configuration `q` (forward kinematics of its two links only).
    pub fn pair_at(&self, s: usize, p: usize, q: &[f64]) -> PlacedPair<'_> {
        let set = &self.sets[s];
        let (i, j) = set.pairs[p];
        let (a, b) = (&set.shapes[i as usize], &set.shapes[j as usize]);
        let link_a = self.kinematics.link_pose(q, set.links[i as usize]);
        let link_b = self.kinematics.link_pose(q, set.links[j as usize]);
        PlacedPair {
            a,
            b,
            link_a,
            link_b,
        }
    }

    /// Samples chunk `chunk` (samples `chunk*CHUNK ..` up to `run.total`) into `acc[set][pair]`, which
    /// must start empty: with `run.tol > 0` which samples get exact queries depends on what the chunk has
    /// seen, so each chunk is computed alone and merged, keeping results independent of threads and
    /// shards. Rigid pairs are skipped here (the caller computes them once).
    pub fn run_chunk(
        &self,
        run: &ChunkRun,
        chunk: u64,
        acc: &mut [Vec<PairStats>],
        scratch: &mut Scratch,
    ) {
        let ChunkRun {
            seed,
            total,
            mean_budget,
            tol,
        } = *run;
        let mut rng = Rng::new(seed, chunk);
        let first = chunk * CHUNK;
        let last = (first + CHUNK).min(total);
        for k in first..last {
            self.draw(&mut rng, &mut scratch.q);
            self.kinematics
                .link_poses_into(&scratch.q, &mut scratch.links);
            for ((set, stats), budget) in self.sets.iter().zip(acc.iter_mut()).zip(mean_budget) {
                self.sample_set(set, k, budget, tol, stats, scratch);
            }
        }
    }

    fn sample_set(
        &self,
        set: &TypeSet,
        k: u64,
        mean_budget: &[u64],
        tol: f64,
        stats: &mut [PairStats],
        scratch: &mut Scratch,
    ) {
        let poses = &scratch.links;
        scratch.outer.clear();
        scratch.inner.clear();
        for (shape, &link) in set.shapes.iter().zip(&set.links) {
            scratch
                .outer
                .push(poses[link].transform_point(shape.outer_center));
            scratch
                .inner
                .push(poses[link].transform_point(shape.inner_center));
        }
        for (p, &(i, j)) in set.pairs.iter().enumerate() {
            if !set.moving[p] {
                continue;
            }
            let (i, j) = (i as usize, j as usize);
            let (a, b) = (&set.shapes[i], &set.shapes[j]);
            // Sphere bounds on the signed distance: lower from the enclosing spheres, upper from the
            // inscribed ones (see `collision` for why both hold with penetration too).
            let (mut lower, mut upper) = sphere_bounds(
                a,
                scratch.outer[i],
                scratch.inner[i],
                b,
                scratch.outer[j],
                scratch.inner[j],
            );
            if let Some(t) = &set.tables[p] {
                let (lo, hi) = t.bounds(scratch.q[t.dof]);
                lower = lower.max(lo);
                upper = upper.min(hi);
            }
            let st = &mut stats[p];
            // The control bound of the mean estimate: the same cheap bound for every sample.
            let control = if lower.is_finite() { lower } else { 0.0 };
            st.observe_bound(control);
            let exact_mean = k < mean_budget[p];
            let needs_exact = |lower: f64, st: &PairStats| {
                exact_mean
                    || (lower <= 0.0 && upper >= 0.0)
                    || st.could_lower_min(lower, k, tol)
                    || st.could_raise_max(upper, k, tol)
            };
            if !needs_exact(lower, st) {
                // The bounds decide: no new extreme, and the verdict is known.
                st.collisions += u64::from(upper < 0.0);
                continue;
            }
            // Shape poses only for the pairs that get past the sphere bounds.
            let (pa, pb) = (a.pose(&poses[set.links[i]]), b.pose(&poses[set.links[j]]));
            if !exact_mean {
                // A separating-axis test along the line between the centres tightens the lower bound.
                let axis = (scratch.outer[j] - scratch.outer[i]).normalize_or(Vec3::Z);
                lower = lower.max(axis_lower_bound(a, &pa, b, &pb, axis));
                if !needs_exact(lower, st) {
                    st.collisions += u64::from(upper < 0.0);
                    continue;
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
