//! Deciding where a pair's signed distance lies against a window `(lo, hi)` with only as many GJK
//! steps as that takes, and the hints one query leaves for the pair's next sample.
//!
//! Sampling needs an exact distance only where a sample could be a new minimum or maximum; elsewhere
//! it needs to know that the distance lies between them (and on which side of zero). GJK brackets the
//! distance from its first step: every simplex point is a point of the configuration-space obstacle, so
//! its distance from the origin bounds the distance from above, and every support point bounds it from
//! below. [`window`] stops as soon as the bracket lies inside the window, or proves it cannot.

use super::epa::depth_within;
use super::{CollisionShape, Kind, signed_distance_hinted};
use crate::math::{Pose, Vec3};
use parry3d_f64::query::gjk::{self, CsoPoint, VoronoiSimplex};
use parry3d_f64::shape::SupportMap;

/// What a pair's last queries leave behind for its next sample: the anchors its extreme-point searches
/// start from (see [`CollisionShape::anchor`]), and what the last exact query found.
#[derive(Debug, Clone, Copy, Default)]
pub struct Hint {
    /// Anchor numbers of the two shapes.
    pub anchors: [u32; 2],
    /// The last query's finding.
    pub last: Last,
}

/// What a pair's last query found, in the shapes' own frames, so that it holds in any pose.
#[derive(Debug, Clone, Copy, Default)]
pub enum Last {
    /// Nothing yet.
    #[default]
    None,
    /// The shapes were apart: a point of each (shape frames), the closest ones or, after a query that
    /// stopped early, the points its search had reached; and the direction from the first to the
    /// second then (frame of shape `a`).
    Apart {
        /// The points.
        points: [Vec3; 2],
        /// The direction between them.
        axis: Vec3,
    },
    /// The shapes overlapped: the direction of the penetration (towards `b`), a point between the
    /// deepest points and how deep it lies inside `a` (frame of shape `a`).
    Overlap {
        /// Direction of the penetration.
        normal: Vec3,
        /// A point between the deepest points.
        deep: Vec3,
        /// Its depth inside `a` ([`CollisionShape::depth`]).
        depth: f64,
    },
}

impl Last {
    /// The finding of a query that ended apart with point `p1` of `a` and `p2` of `b`, both in the
    /// frame of `a`, `b` posed at `pos12` in it.
    pub fn apart(p1: Vec3, p2: Vec3, pos12: &Pose) -> Last {
        Last::Apart {
            points: [p1, pos12.inverse_transform_point(p2)],
            axis: (p2 - p1).normalize_or(Vec3::Z),
        }
    }
}

/// Two points, one of each shape of a pair (each in its link's frame), and how deep they lie inside
/// their shapes together: in any configuration the distance between them less that depth bounds the
/// pair's signed distance from above (the balls of those radii around them lie in the shapes, and
/// cannot be separated by less). Taken where the pair was farthest apart, it is tight there, where the
/// maximum's samples lie.
#[derive(Debug, Clone, Copy)]
pub struct Tether {
    a: Vec3,
    b: Vec3,
    depth: f64,
}

impl Tether {
    /// The bound with the links posed at `link_a` and `link_b`.
    #[inline]
    pub fn upper(&self, link_a: &Pose, link_b: &Pose) -> f64 {
        link_a
            .transform_point(self.a)
            .distance(link_b.transform_point(self.b))
            - self.depth
    }
}

impl Hint {
    /// The tether of the points behind [`Hint::bounds`]' upper bound, the shapes posed at `pa` and
    /// `pb` (`None` before any query, or after an overlap whose deep point is not inside both shapes).
    pub fn tether(
        &self,
        a: &CollisionShape,
        pa: &Pose,
        b: &CollisionShape,
        pb: &Pose,
    ) -> Option<Tether> {
        let (p, q, depth) = match self.last {
            Last::None => return None,
            Last::Apart { points: [p, q], .. } => (p, q, 0.0),
            Last::Overlap { deep, depth, .. } => {
                let (q, both) = deep_in_both(deep, depth, pa, b, pb)?;
                (deep, q, both)
            }
        };
        Some(Tether {
            a: a.local.transform_point(p),
            b: b.local.transform_point(q),
            depth,
        })
    }

    /// With the shapes posed at `pa`, `pb` (`b` the second shape): an upper bound on the signed
    /// distance, and the axis (from `a` towards `b`, turned with `a`) along which the last query found
    /// the shapes apart or overlapping, a good axis for [`super::axis_bounds`] when the pair moved
    /// little. After a query that found them apart, the bound is the distance between its two points
    /// (points of the shapes in any pose); after an overlap, minus the depths of its deep point in both
    /// shapes where it lies inside both (the two balls of those radii around it lie in the shapes and
    /// cannot be separated by less).
    #[inline]
    pub fn bounds(&self, pa: &Pose, b: &CollisionShape, pb: &Pose) -> (f64, Option<Vec3>) {
        match self.last {
            Last::None => (f64::INFINITY, None),
            Last::Apart {
                points: [p, q],
                axis,
            } => {
                let (wa, wb) = (pa.transform_point(p), pb.transform_point(q));
                (wa.distance(wb), Some(pa.rotation * axis))
            }
            Last::Overlap {
                normal,
                deep,
                depth,
            } => {
                let upper = deep_in_both(deep, depth, pa, b, pb).map_or(f64::INFINITY, |(_, d)| -d);
                (upper, Some(pa.rotation * normal))
            }
        }
    }
}

/// An overlap's deep point `deep` (frame of `a`, posed at `pa`, lying `depth` inside it) in the frame
/// of `b` (posed at `pb`), and its depths in both shapes together, where it lies inside both.
#[inline]
fn deep_in_both(
    deep: Vec3,
    depth: f64,
    pa: &Pose,
    b: &CollisionShape,
    pb: &Pose,
) -> Option<(Vec3, f64)> {
    let q = pb.inverse_transform_point(pa.transform_point(deep));
    let in_b = b.depth(q);
    (depth > 0.0 && in_b > 0.0).then_some((q, depth + in_b))
}

/// What [`window`] decided.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Window {
    /// The signed distance lies strictly inside the window; `overlap` tells whether it is `<= 0`.
    Inside {
        /// Whether the shapes overlap.
        overlap: bool,
    },
    /// Not decided: the distance may lie outside the window (or GJK converged before telling), so an
    /// exact query has to.
    Open,
}

/// Most GJK steps before giving up (parry's GJK allows as many).
const MAX_STEPS: usize = 100;

/// Decides whether the signed distance of two posed shapes lies strictly inside `(lo, hi)` (either end
/// may be infinite) and, if so, whether they overlap. `bounds` are bounds on the distance already known
/// (lower, upper); they count as GJK's own. The search starts from the hint's points when it has them,
/// else as parry's distance query starts, and leaves its last points in `hint` when it ends apart.
#[allow(clippy::too_many_arguments)]
pub fn window(
    a: &CollisionShape,
    pa: &Pose,
    b: &CollisionShape,
    pb: &Pose,
    lo: f64,
    hi: f64,
    bounds: (f64, f64),
    hint: &mut Hint,
) -> Window {
    let inside = |d: f64| lo < d && d < hi;
    if let (Kind::Ball(_), Kind::Ball(_)) = (&a.kind, &b.kind) {
        let d = signed_distance_hinted(a, pa, b, pb, hint);
        return if inside(d) {
            Window::Inside { overlap: d <= 0.0 }
        } else {
            Window::Open
        };
    }
    let pos12 = pa.inv_mul(pb);
    let (g1, g2) = (a.support_map(), b.support_map());
    // Start from the closer of the last query's points and the anchors' (this sample's extreme points
    // along the centre line when the bounds before ran).
    let anchored = match (
        a.anchor_local(hint.anchors[0]),
        b.anchor_local(hint.anchors[1]),
    ) {
        (Some(p), Some(q)) => Some(CsoPoint::new(p, pos12.transform_point(q))),
        _ => None,
    };
    let last = match hint.last {
        Last::Apart { points: [p, q], .. } => Some(CsoPoint::new(p, pos12.transform_point(q))),
        _ => None,
    };
    let start = [anchored, last].into_iter().flatten().min_by(|x, y| {
        x.point
            .length_squared()
            .total_cmp(&y.point.length_squared())
    });
    let mut simplex = match start {
        Some(point) => {
            let mut simplex = VoronoiSimplex::new();
            simplex.reset(point);
            simplex
        }
        None => start_simplex(&pos12, g1, g2),
    };
    let (mut lower, mut upper) = bounds;
    let mut anchors = hint.anchors;
    let eps = gjk::eps_tol();
    let eps_rel = eps.sqrt();
    let mut last_dist = f64::INFINITY;
    // Whether the simplex's projection coordinates are those of its current points.
    let mut projected = false;
    for _ in 0..MAX_STEPS {
        let proj = simplex.project_origin_and_reduce();
        let dist = proj.length();
        projected = true;
        if dist <= eps || simplex.dimension() == 3 {
            // The origin is on or inside the simplex: the shapes overlap, and `lower` (a gap along
            // some axis, minus the depth along it) still bounds the signed distance from below.
            // Inside a tetrahedron, EPA steps bracket the depth until they settle the window.
            let inside = (lo < lower && 0.0 < hi)
                || (simplex.dimension() == 3 && {
                    let tetrahedron = [0, 1, 2, 3].map(|i| *simplex.point(i));
                    let support = |dir| cso_support(a, b, &pos12, dir, &mut anchors);
                    depth_within(&tetrahedron, support, lo, hi, lower)
                });
            hint.anchors = anchors;
            return if inside {
                Window::Inside { overlap: true }
            } else {
                Window::Open
            };
        }
        if dist >= last_dist {
            // No progress (rounding): an exact query decides.
            break;
        }
        last_dist = dist;
        upper = upper.min(dist);
        let dir = -proj / dist;
        let support = cso_support(a, b, &pos12, dir, &mut anchors);
        lower = lower.max(-dir.dot(support.point));
        // The support point is a point of the obstacle too.
        upper = upper.min(support.point.length());
        let verdict = if lower > 0.0 {
            Some(false)
        } else if upper <= 0.0 {
            Some(true)
        } else {
            None
        };
        if upper <= lo || lower >= hi {
            // Outside for sure: a new extreme, which needs its exact value.
            break;
        }
        if let (Some(overlap), true) = (verdict, lo < lower && upper < hi) {
            hint.anchors = anchors;
            hint.last = apart(&simplex, &pos12);
            return Window::Inside { overlap };
        }
        if upper - lower <= eps_rel * upper || !simplex.add_point(support) {
            // Converged, or stalled, without a decision.
            break;
        }
        projected = false;
    }
    hint.anchors = anchors;
    if projected {
        hint.last = apart(&simplex, &pos12);
    }
    Window::Open
}

/// The obstacle's (`a - b`, frame of `a`, `b` posed at `pos12`) farthest point along `dir`. The
/// searches climb from `anchors` and leave theirs there: the directions of successive GJK and EPA
/// steps change little.
#[inline]
pub(super) fn cso_support(
    a: &CollisionShape,
    b: &CollisionShape,
    pos12: &Pose,
    dir: Vec3,
    anchors: &mut [u32; 2],
) -> CsoPoint {
    let (sa, ia) = a.local_support_from(dir, anchors[0]);
    let (sb, ib) = b.local_support_from(pos12.rotation.inverse() * -dir, anchors[1]);
    *anchors = [ia, ib];
    CsoPoint::new(sa, pos12.transform_point(sb))
}

/// A GJK simplex started as parry's distance query starts it: one support point along the line
/// between the shapes' origins.
pub(super) fn start_simplex(
    pos12: &Pose,
    g1: &dyn SupportMap,
    g2: &dyn SupportMap,
) -> VoronoiSimplex {
    let dir = -pos12.translation;
    let eps = parry3d_f64::math::DEFAULT_EPSILON;
    let dir = if dir.length_squared() > eps * eps {
        dir.normalize()
    } else {
        Vec3::X
    };
    let mut simplex = VoronoiSimplex::new();
    simplex.reset(CsoPoint::from_shapes(pos12, g1, g2, dir));
    simplex
}

/// The points of each shape (in its own frame) that the simplex's last projection of the origin
/// combines: real points of the shapes, whatever the state of the search. The simplex must not be a
/// full tetrahedron (whose projection has no coordinates).
fn apart(simplex: &VoronoiSimplex, pos12: &Pose) -> Last {
    let (mut p1, mut p2) = (Vec3::ZERO, Vec3::ZERO);
    for i in 0..=simplex.dimension() {
        let (c, pt) = (simplex.proj_coord(i), simplex.point(i));
        p1 += pt.orig1 * c;
        p2 += pt.orig2 * c;
    }
    Last::apart(p1, p2, pos12)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::signed_distance;
    use crate::collision::test_shapes::{link, pick, shapes, values};

    /// A tether taken from a query at one pose bounds the signed distance from above at any other
    /// pose of the two links, overlapping or apart, and is the distance itself where it was taken.
    #[test]
    fn tethers_bound_the_distance_from_above_everywhere_and_tightly_where_taken() {
        let mut r = values(17);
        let shapes = shapes(&mut r);
        let (mut taken, mut overlapping) = (0, 0);
        for _ in 0..3000 {
            let (a, b) = (&shapes[pick(&mut r)], &shapes[pick(&mut r)]);
            let (la, lb) = (link(&mut r), link(&mut r));
            let (pa, pb) = (a.pose(&la), b.pose(&lb));
            let mut hint = Hint::default();
            let d = super::super::signed_distance_hinted(a, &pa, b, &pb, &mut hint);
            let Some(tether) = hint.tether(a, &pa, b, &pb) else {
                // Only an overlap whose deep point is not inside both shapes gives none.
                assert!(d <= 0.0, "no tether for a pair {d} m apart");
                continue;
            };
            taken += 1;
            overlapping += usize::from(d < 0.0);
            if d > 0.0 {
                let at = tether.upper(&la, &lb);
                assert!((at - d).abs() < 1e-9, "{at} where taken, distance {d}");
            }
            for _ in 0..5 {
                let (la, lb) = (link(&mut r), link(&mut r));
                let d = signed_distance(a, &a.pose(&la), b, &b.pose(&lb));
                let upper = tether.upper(&la, &lb);
                assert!(d <= upper + 1e-9, "tether {upper} below the distance {d}");
            }
        }
        assert!(
            taken > 2500 && overlapping > 100,
            "{taken} tethers, {overlapping} overlapping"
        );
    }

    /// Windows around random pairs' exact signed distances: an answer `Inside` is always right, and
    /// windows that hold an overlapping pair's distance with a millimetre to spare are mostly settled
    /// without the exact query (by the bracketing EPA steps: no other bound shows a depth).
    #[test]
    fn windows_are_settled_only_when_they_hold_the_distance() {
        let mut r = values(5);
        let shapes = shapes(&mut r);
        let (mut overlapping, mut settled) = (0, 0);
        for _ in 0..4000 {
            let (a, b) = (&shapes[pick(&mut r)], &shapes[pick(&mut r)]);
            let (pa, pb) = (a.pose(&link(&mut r)), b.pose(&link(&mut r)));
            let d = signed_distance(a, &pa, b, &pb);
            let margin = 1e-3;
            for (lo, hi) in [
                (d - margin, d + margin),
                (d - margin, f64::INFINITY),
                (f64::NEG_INFINITY, d + margin),
                (d + 1e-6, d + margin),
                (d - margin, d - 1e-6),
                (d - 1e-9, d + 1e-9),
            ] {
                let window = window(a, &pa, b, &pb, lo, hi, (-1e9, 1e9), &mut Hint::default());
                if let Window::Inside { overlap } = window {
                    // Exact queries carry micrometre errors (tests/exactness.rs).
                    assert!(lo - 1e-6 < d && d < hi + 1e-6, "{d} not in ({lo}, {hi})");
                    assert_eq!(overlap, d <= 0.0, "verdict at {d}");
                }
            }
            if d < -margin {
                overlapping += 1;
                let two_sided = window(
                    a,
                    &pa,
                    b,
                    &pb,
                    d - margin,
                    d + margin,
                    (-1e9, 1e9),
                    &mut Hint::default(),
                );
                settled += usize::from(two_sided != Window::Open);
            }
        }
        assert!(overlapping > 300, "{overlapping} overlapping pairs");
        assert!(
            settled * 10 > overlapping * 8,
            "{settled} of {overlapping} settled"
        );
    }
}
