//! The shapes of the sampled types, ready for queries: per type its shapes, their links and the pairs
//! to sample, and one pair placed at a configuration. What the block placement, the distance tables,
//! the targeted search and the engine all query, so none of them needs the engine itself.

use crate::collision::{
    CollisionShape, Hint, Window, intersects, outer_gap, signed_distance_hinted, window,
};
use crate::math::Pose;
use crate::robot::Kinematics;
use crate::shapes::ShapeType;

/// The shapes of one type, ready for queries, and the pairs to sample.
#[derive(Debug)]
pub struct PairSet {
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
}

impl PairSet {
    /// The link indices of pair `p`'s two shapes.
    pub fn pair_links(&self, p: usize) -> (usize, usize) {
        let (i, j) = self.pairs[p];
        (self.links[i as usize], self.links[j as usize])
    }

    /// Pair `p` placed at configuration `q` (forward kinematics of its two links only, from their
    /// common ancestor).
    pub fn pair_at(&self, kinematics: &Kinematics, p: usize, q: &[f64]) -> PlacedPair<'_> {
        let (la, lb) = self.pair_links(p);
        self.placed(p, kinematics.pair_poses(q, la, lb))
    }

    /// Pair `p` with its two links at poses `(link_a, link_b)` (of its first and second shape's link,
    /// in any one frame).
    pub fn placed(&self, p: usize, (link_a, link_b): (Pose, Pose)) -> PlacedPair<'_> {
        let (i, j) = self.pairs[p];
        PlacedPair {
            a: &self.shapes[i as usize],
            b: &self.shapes[j as usize],
            link_a,
            link_b,
        }
    }
}

/// Two shapes of a pair with their links' poses at some configuration.
#[derive(Debug, Clone, Copy)]
pub struct PlacedPair<'a> {
    pub(super) a: &'a CollisionShape,
    pub(super) b: &'a CollisionShape,
    pub(super) link_a: Pose,
    pub(super) link_b: Pose,
}

impl PlacedPair<'_> {
    /// A lower bound on the signed distance from the enclosing spheres (cheap).
    pub fn lower_bound(&self) -> f64 {
        let ca = self.link_a.transform_point(self.a.outer_center);
        let cb = self.link_b.transform_point(self.b.outer_center);
        outer_gap(self.a, ca, self.b, cb)
    }

    /// Whether the shapes overlap (signed distance `<= 0`): apart for the price of two points where
    /// their enclosing spheres are, else one GJK intersection test.
    pub fn overlaps(&self) -> bool {
        self.lower_bound() <= 0.0
            && intersects(
                self.a,
                &self.a.pose(&self.link_a),
                self.b,
                &self.b.pose(&self.link_b),
            )
    }

    /// Whether the signed distance may lie below `d`: `false` once the sphere bound, or else a GJK that
    /// stops as soon as it can tell (much cheaper than [`PlacedPair::distance`] when it does), shows it
    /// does not.
    pub fn may_be_below(&self, d: f64, hint: &mut Hint) -> bool {
        let lower = self.lower_bound();
        if lower >= d {
            return false;
        }
        let (pa, pb) = (self.a.pose(&self.link_a), self.b.pose(&self.link_b));
        let known = (lower, f64::INFINITY);
        let gjk = window(self.a, &pa, self.b, &pb, d, f64::INFINITY, known, hint);
        gjk == Window::Open
    }

    /// The exact signed distance.
    pub fn distance(&self) -> f64 {
        self.distance_hinted(&mut Hint::default())
    }

    /// The exact signed distance, starting from and leaving in `hint` what the last query found.
    pub fn distance_hinted(&self, hint: &mut Hint) -> f64 {
        signed_distance_hinted(
            self.a,
            &self.a.pose(&self.link_a),
            self.b,
            &self.b.pose(&self.link_b),
            hint,
        )
    }
}
