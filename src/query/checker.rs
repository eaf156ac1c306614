//! [`SelfChecker`]: one shape type of a robot, its pairs to check, and the three queries.

use super::SkipMode;
use super::skips::skip_reasons;
use crate::collision::{intersects, signed_distance, sphere_bounds, witness_points};
use crate::error::{Error, Result};
use crate::math::{Pose, Vec3};
use crate::robot::{Dof, Kinematics};
use crate::shapes::ShapeType;
use crate::urdd::{ShapeRecord, TypeShapes, Urdd};
use serde::Serialize;
use std::path::Path;

/// A robot's self-collision and self-proximity checker for one shape type: the shapes posed by forward
/// kinematics, and the shape pairs to check (all pairs, or those the skip matrix does not skip).
///
/// Queries take a [`Scratch`] so that a planner calling them in a loop allocates nothing (a collision
/// report allocates only when it has pairs to report). The checker is immutable and `Sync`: threads
/// share one checker, each with its own scratch.
#[derive(Debug)]
pub struct SelfChecker {
    mode: SkipMode,
    kinematics: Kinematics,
    set: TypeShapes,
    /// The pairs to check, `a < b`.
    pairs: Vec<(u32, u32)>,
    /// Per pair of the whole matrix (row-major), the skip reason id, `None` when checked.
    reasons: Vec<Option<String>>,
}

/// Reusable per-thread working memory of the queries.
#[derive(Debug, Default, Clone)]
pub struct Scratch {
    links: Vec<Pose>,
    outer: Vec<Vec3>,
    inner: Vec<Vec3>,
    poses: Vec<Pose>,
    /// `stamp[i] == generation` when `poses[i]` is valid for the current query.
    stamp: Vec<u64>,
    generation: u64,
    order: Vec<(f64, u32)>,
}

/// Two shapes by matrix index, with their links' names.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ShapePair {
    /// First shape (the smaller index).
    pub a: usize,
    /// Second shape.
    pub b: usize,
    /// Link of `a`.
    pub link_a: String,
    /// Link of `b`.
    pub link_b: String,
}

/// The answer to "does the robot collide with itself?".
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct CollisionReport {
    /// Every checked pair in collision (signed distance <= 0), in row-major order.
    pub pairs: Vec<ShapePair>,
}

impl CollisionReport {
    /// Whether any checked pair collides.
    pub fn in_collision(&self) -> bool {
        !self.pairs.is_empty()
    }
}

/// The answer to "what is the minimum distance, and between which shapes?".
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Proximity {
    /// Signed distance of the closest checked pair: separation, or minus the penetration depth.
    pub distance: f64,
    /// The pair that attains it.
    pub pair: ShapePair,
    /// Witness points in the world (root link) frame, on `pair.a` and on `pair.b`: the closest points,
    /// or the deepest points of the penetration.
    pub points: [Vec3; 2],
}

impl SelfChecker {
    /// Loads the robot and the shapes of type `t` from a URDD. With [`SkipMode::Skips`] the pairs the
    /// effective skip matrix skips are left out (inferred by sampling, with the imported and user
    /// layers applied; the sample stage must be current and include `t`).
    pub fn load(urdd: &Urdd, t: ShapeType, mode: SkipMode) -> Result<SelfChecker> {
        let robot = urdd.robot()?.robot;
        let set = urdd.collision_shapes(t, robot.links.len())?;
        let n = set.shapes.len();
        let reasons = match mode {
            SkipMode::Skips => skip_reasons(urdd, t, n)?,
            SkipMode::NoSkips => vec![None; n * n.saturating_sub(1) / 2],
        };
        Ok(SelfChecker::new(
            Kinematics::new(&robot),
            set,
            mode,
            reasons,
        ))
    }

    /// A checker from loaded parts: `reasons` has one entry per pair of the whole matrix (row-major,
    /// `a < b`), the skip reason id or `None` for pairs to check.
    pub fn new(
        kinematics: Kinematics,
        set: TypeShapes,
        mode: SkipMode,
        reasons: Vec<Option<String>>,
    ) -> SelfChecker {
        let n = set.shapes.len() as u32;
        let pairs = (0..n)
            .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
            .zip(&reasons)
            .filter(|(_, r)| r.is_none())
            .map(|(p, _)| p)
            .collect();
        SelfChecker {
            mode,
            kinematics,
            set,
            pairs,
            reasons,
        }
    }

    /// The shape type.
    pub fn shape_type(&self) -> ShapeType {
        self.set.shape_type
    }

    /// Whether skipped pairs are left out.
    pub fn mode(&self) -> SkipMode {
        self.mode
    }

    /// The degrees of freedom a configuration gives values for, in order.
    pub fn dofs(&self) -> &[Dof] {
        self.kinematics.dofs()
    }

    /// The home configuration (every joint at 0, or mid-range where 0 is outside the limits).
    pub fn home(&self) -> Vec<f64> {
        self.kinematics.home()
    }

    /// The shapes in matrix order (link, piece, geometry).
    pub fn shapes(&self) -> &[ShapeRecord] {
        &self.set.records
    }

    /// The pairs the queries check, `a < b`, in row-major order.
    pub fn checked_pairs(&self) -> &[(u32, u32)] {
        &self.pairs
    }

    /// The skip reason id of the pair `(a, b)` (any order), `None` when the checker checks it or for
    /// `a == b`.
    pub fn skip_reason(&self, a: usize, b: usize) -> Option<&str> {
        let (a, b) = (a.min(b), a.max(b));
        let n = self.set.shapes.len();
        if a == b || b >= n {
            return None;
        }
        self.reasons[crate::matrix::pair_index(n, a, b)].as_deref()
    }

    /// Working memory sized for this checker.
    pub fn scratch(&self) -> Scratch {
        Scratch::default()
    }

    /// Whether the robot collides with itself at `q`: stops at the first colliding pair.
    pub fn in_collision(&self, q: &[f64], scratch: &mut Scratch) -> Result<bool> {
        self.prepare(q, scratch)?;
        for &(a, b) in &self.pairs {
            if self.pair_collides(a as usize, b as usize, scratch) {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Every checked pair in collision at `q`.
    pub fn collisions(&self, q: &[f64], scratch: &mut Scratch) -> Result<CollisionReport> {
        self.prepare(q, scratch)?;
        let mut report = CollisionReport::default();
        for &(a, b) in &self.pairs {
            if self.pair_collides(a as usize, b as usize, scratch) {
                report.pairs.push(self.shape_pair(a as usize, b as usize));
            }
        }
        Ok(report)
    }

    /// The minimum signed distance over the checked pairs at `q`, the pair attaining it and its witness
    /// points; `None` when there is no pair to check. Exact queries run only for pairs whose
    /// enclosing-sphere bound could beat the best distance found so far, in order of that bound.
    pub fn min_distance(&self, q: &[f64], scratch: &mut Scratch) -> Result<Option<Proximity>> {
        self.prepare(q, scratch)?;
        let shapes = &self.set.shapes;
        // Sphere bounds of every pair; only pairs whose lower bound is at most the smallest upper bound
        // can hold the minimum.
        let mut ceiling = f64::INFINITY;
        scratch.order.clear();
        for (p, &(a, b)) in self.pairs.iter().enumerate() {
            let (a, b) = (a as usize, b as usize);
            let (lower, upper) = sphere_bounds(
                &shapes[a],
                scratch.outer[a],
                scratch.inner[a],
                &shapes[b],
                scratch.outer[b],
                scratch.inner[b],
            );
            if lower <= ceiling {
                scratch.order.push((lower, p as u32));
                ceiling = ceiling.min(upper);
            }
        }
        let mut order = std::mem::take(&mut scratch.order);
        order.retain(|&(lower, _)| lower <= ceiling);
        order.sort_unstable_by(|x, y| x.0.total_cmp(&y.0));
        let mut best: Option<(f64, usize)> = None;
        for &(lower, p) in &order {
            if best.is_some_and(|(d, _)| lower >= d) {
                break;
            }
            let (a, b) = self.pairs[p as usize];
            let d = self.exact_distance(a as usize, b as usize, scratch);
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, p as usize));
            }
        }
        scratch.order = order;
        Ok(best.map(|(distance, p)| {
            let (a, b) = self.pairs[p];
            let (a, b) = (a as usize, b as usize);
            let (pa, pb) = (self.pose(a, scratch), self.pose(b, scratch));
            let points = witness_points(&shapes[a], &pa, &shapes[b], &pb)
                .map_or([pa.translation, pb.translation], |(x, y)| [x, y]);
            Proximity {
                distance,
                pair: self.shape_pair(a, b),
                points,
            }
        }))
    }

    /// Exact signed distance of every checked pair at `q`, no culling (reference and tests).
    pub fn all_distances(&self, q: &[f64], scratch: &mut Scratch) -> Result<Vec<f64>> {
        self.prepare(q, scratch)?;
        Ok(self
            .pairs
            .iter()
            .map(|&(a, b)| self.exact_distance(a as usize, b as usize, scratch))
            .collect())
    }

    /// The signed distance of one pair `{a, b}` (any order, skipped or not) at `q` and its witness
    /// points in the world (root link) frame, on `a` and on `b` (as in [`Proximity::points`]).
    pub fn pair_distance(
        &self,
        q: &[f64],
        a: usize,
        b: usize,
        scratch: &mut Scratch,
    ) -> Result<(f64, [Vec3; 2])> {
        let n = self.set.shapes.len();
        if a == b || a >= n || b >= n {
            return Err(Error::input(
                Path::new("pair"),
                format!("shapes {a} and {b}"),
                format!("not a pair of two of the {n} shapes"),
            ));
        }
        self.prepare(q, scratch)?;
        // Computed in matrix order, so either order gives the same distance bit for bit.
        let (lo, hi) = (a.min(b), a.max(b));
        let (pa, pb) = (self.pose(lo, scratch), self.pose(hi, scratch));
        let (sa, sb) = (&self.set.shapes[lo], &self.set.shapes[hi]);
        let d = signed_distance(sa, &pa, sb, &pb);
        let [x, y] = witness_points(sa, &pa, sb, &pb)
            .map_or([pa.translation, pb.translation], |(x, y)| [x, y]);
        Ok((d, if lo == a { [x, y] } else { [y, x] }))
    }

    fn shape_pair(&self, a: usize, b: usize) -> ShapePair {
        ShapePair {
            a,
            b,
            link_a: self.set.records[a].link.clone(),
            link_b: self.set.records[b].link.clone(),
        }
    }

    /// Forward kinematics and the world centres of every shape's bounding spheres.
    fn prepare(&self, q: &[f64], scratch: &mut Scratch) -> Result<()> {
        let dofs = self.kinematics.dofs().len();
        if q.len() != dofs {
            return Err(Error::input(
                Path::new("configuration"),
                "joint values",
                format!("expected {dofs} (one per DOF), got {}", q.len()),
            ));
        }
        if let Some(i) = q.iter().position(|v| !v.is_finite()) {
            return Err(Error::input(
                Path::new("configuration"),
                format!("joint \"{}\"", self.kinematics.dofs()[i].name),
                "not a finite number",
            ));
        }
        self.kinematics.link_poses_into(q, &mut scratch.links);
        let n = self.set.shapes.len();
        scratch.outer.clear();
        scratch.inner.clear();
        for (shape, &link) in self.set.shapes.iter().zip(&self.set.links) {
            let pose = &scratch.links[link];
            scratch.outer.push(pose.transform_point(shape.outer_center));
            scratch.inner.push(pose.transform_point(shape.inner_center));
        }
        if scratch.stamp.len() != n {
            scratch.stamp = vec![0; n];
            scratch.poses = vec![Pose::IDENTITY; n];
            scratch.generation = 0;
        }
        scratch.generation += 1;
        Ok(())
    }

    /// The world pose of shape `i`, computed once per query.
    fn pose(&self, i: usize, scratch: &mut Scratch) -> Pose {
        if scratch.stamp[i] != scratch.generation {
            scratch.poses[i] = self.set.shapes[i].pose(&scratch.links[self.set.links[i]]);
            scratch.stamp[i] = scratch.generation;
        }
        scratch.poses[i]
    }

    /// The collision verdict of one pair: the sphere bounds first, one GJK test when they cannot decide.
    fn pair_collides(&self, a: usize, b: usize, scratch: &mut Scratch) -> bool {
        let (sa, sb) = (&self.set.shapes[a], &self.set.shapes[b]);
        let (lower, upper) = sphere_bounds(
            sa,
            scratch.outer[a],
            scratch.inner[a],
            sb,
            scratch.outer[b],
            scratch.inner[b],
        );
        if lower > 0.0 {
            return false;
        }
        if upper < 0.0 {
            return true;
        }
        let (pa, pb) = (self.pose(a, scratch), self.pose(b, scratch));
        intersects(sa, &pa, sb, &pb)
    }

    fn exact_distance(&self, a: usize, b: usize, scratch: &mut Scratch) -> f64 {
        let (pa, pb) = (self.pose(a, scratch), self.pose(b, scratch));
        signed_distance(&self.set.shapes[a], &pa, &self.set.shapes[b], &pb)
    }
}
