//! Collision and distance queries between posed shapes, with the cheap sphere bounds that let callers
//! skip exact queries whose answer cannot matter.
//!
//! Sign convention: the signed distance is the separation in metres when two shapes are apart, and minus
//! the penetration depth (the shortest translation that separates them) when they overlap.

mod box_bound;
mod distance_window;
mod epa;
mod exact;
mod hull_support;
mod mesh_distance;
mod separated;
#[cfg(test)]
mod test_shapes;

pub use box_bound::{BoundingBox, PlacedBox, box_bounds};
pub use distance_window::{Hint, Last, Tether, Window, window};
pub use exact::{ExactError, ExactLink, ExactMesh, winding_number};
pub use hull_support::HullSupport;
pub use separated::{closest_on_segments, closest_on_triangle};

use crate::math::{Pose, Vec3, is_finite};
use crate::shapes::{ConvexMesh, Geometry};
use parry3d_f64::query::{self, gjk::CsoPoint};
use parry3d_f64::shape::{Ball, Cuboid, SupportMap};

/// A shape ready for queries: the parry shape, its pose in the link frame, and two spheres in the link
/// frame, one enclosing it and one inside it.
pub struct CollisionShape {
    kind: Kind,
    local: Pose,
    /// Centre of the enclosing sphere (link frame).
    pub outer_center: Vec3,
    /// Radius of the enclosing sphere.
    pub outer_radius: f64,
    /// Centre of the inscribed sphere (link frame).
    pub inner_center: Vec3,
    /// Radius of the inscribed sphere (0 when none is known).
    pub inner_radius: f64,
    /// An oriented box around the shape (link frame), for the box bounds; `None` for a sphere, whose
    /// sphere bounds are exact.
    pub bounding_box: Option<BoundingBox>,
}

impl std::fmt::Debug for CollisionShape {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CollisionShape")
            .field("outer_radius", &self.outer_radius)
            .field("inner_radius", &self.inner_radius)
            .finish_non_exhaustive()
    }
}

impl CollisionShape {
    /// Prepares a geometry for queries. `None` only for a hull parry cannot build (degenerate).
    pub fn new(geometry: &Geometry) -> Option<CollisionShape> {
        Some(match geometry {
            Geometry::Sphere(s) => CollisionShape {
                kind: Kind::Ball(Ball::new(s.radius)),
                local: Pose::from_translation(s.center),
                outer_center: s.center,
                outer_radius: s.radius,
                inner_center: s.center,
                inner_radius: s.radius,
                bounding_box: None,
            },
            Geometry::Obb(b) => CollisionShape {
                kind: Kind::Box(Cuboid::new(b.half_extents)),
                local: Pose::from_parts(b.center, b.rotation),
                outer_center: b.center,
                outer_radius: b.half_extents.length(),
                inner_center: b.center,
                inner_radius: b.half_extents.min_element(),
                bounding_box: Some(BoundingBox::of_box(b)),
            },
            Geometry::Hull(h) => {
                if h.vertices.len() < 4 || h.faces.len() < 4 {
                    return None;
                }
                let outer = crate::shapes::minimal_bounding_sphere(&h.vertices);
                let (inner_center, inner_radius) = inscribed(h);
                CollisionShape {
                    kind: Kind::Hull(HullSupport::new(h)),
                    local: Pose::IDENTITY,
                    outer_center: outer.center,
                    outer_radius: outer.radius,
                    inner_center,
                    inner_radius,
                    bounding_box: Some(BoundingBox::around(&crate::shapes::tight_obb(h))),
                }
            }
        })
    }

    /// Whether the shape is a sphere (its sphere bounds are then its exact distances).
    pub fn is_ball(&self) -> bool {
        matches!(self.kind, Kind::Ball(_))
    }

    /// The shape as a support map (for GJK and EPA), posed by [`CollisionShape::pose`].
    fn support_map(&self) -> &dyn SupportMap {
        match &self.kind {
            Kind::Ball(b) => b,
            Kind::Box(c) => c,
            Kind::Hull(h) => h,
        }
    }

    /// The shape's pose in the world given its link's pose.
    #[inline]
    pub fn pose(&self, link: &Pose) -> Pose {
        match self.kind {
            // A hull's vertices are in the link frame already (`local` is the identity).
            Kind::Hull(_) => *link,
            _ => *link * self.local,
        }
    }

    /// The shape's point numbered `anchor` (world frame), posed at `pose`: a hull vertex, or for a
    /// sphere or box its centre.
    #[inline]
    pub fn anchor(&self, pose: &Pose, anchor: u32) -> Vec3 {
        match &self.kind {
            Kind::Hull(h) => pose.transform_point(h.vertices()[anchor as usize]),
            _ => pose.translation,
        }
    }

    /// A hull's vertex numbered `anchor` in the shape's own frame (`None` for other shapes).
    #[inline]
    pub fn anchor_local(&self, anchor: u32) -> Option<Vec3> {
        match &self.kind {
            Kind::Hull(h) => h.vertices().get(anchor as usize).copied(),
            _ => None,
        }
    }

    /// The shape's farthest point along `dir` (world frame), posed at `pose`, and its anchor number
    /// (see [`CollisionShape::anchor`]): a hull's climb starts from its vertex numbered `from`, best
    /// the last support found for a nearby direction, a step or two from this one.
    #[inline]
    pub fn support_from(&self, pose: &Pose, dir: Vec3, from: u32) -> (Vec3, u32) {
        let (p, id) = self.local_support_from(pose.rotation.inverse() * dir, from);
        (pose.transform_point(p), id)
    }

    /// How deep the point `p` (shape frame) lies inside the shape: the radius of the largest ball
    /// around it that the shape contains (negative outside).
    pub fn depth(&self, p: Vec3) -> f64 {
        match &self.kind {
            Kind::Ball(b) => b.radius - p.length(),
            Kind::Box(c) => (c.half_extents - p.abs()).min_element(),
            Kind::Hull(h) => h.depth(p),
        }
    }

    /// The largest distance of any point of the shape, its link posed at `link`, from the line through
    /// `origin` along the unit vector `axis`: how fast its points move, per radian, when it turns about
    /// that line. The distance from a line is convex, so a hull's or box's largest is at a vertex.
    pub fn reach(&self, link: &Pose, origin: Vec3, axis: Vec3) -> f64 {
        // The line taken into the shape's own frame, so that a vertex costs a few products and no
        // rotation, and one square root for the largest.
        let pose = self.pose(link);
        let (o, u) = (
            pose.inverse_transform_point(origin),
            pose.rotation.inverse() * axis,
        );
        let from_line = |p: Vec3| {
            let v = p - o;
            (v - u * v.dot(u)).length_squared()
        };
        match &self.kind {
            Kind::Ball(b) => from_line(Vec3::ZERO).sqrt() + b.radius,
            Kind::Box(c) => separated::box_corners(c.half_extents)
                .into_iter()
                .map(from_line)
                .fold(0.0, f64::max)
                .sqrt(),
            Kind::Hull(h) => h
                .vertices()
                .iter()
                .map(|&v| from_line(v))
                .fold(0.0, f64::max)
                .sqrt(),
        }
    }

    /// `f` of the shape's surface (own frame), `None` for a sphere.
    fn with_surface<R>(&self, f: impl FnOnce(separated::Surface) -> R) -> Option<R> {
        match &self.kind {
            Kind::Ball(_) => None,
            Kind::Box(c) => Some(f(separated::Surface {
                vertices: &separated::box_corners(c.half_extents),
                triangles: &separated::BOX_TRIANGLES,
            })),
            Kind::Hull(h) => Some(f(separated::Surface {
                vertices: h.vertices(),
                triangles: h.triangles(),
            })),
        }
    }

    /// [`CollisionShape::support_from`] in the shape's own frame.
    #[inline]
    pub fn local_support_from(&self, dir: Vec3, from: u32) -> (Vec3, u32) {
        match &self.kind {
            Kind::Ball(b) => (dir.normalize_or_zero() * b.radius, 0),
            Kind::Box(c) => (c.local_support_point(dir), 0),
            Kind::Hull(h) => {
                let id = h.support_index_from(dir, from);
                (h.vertices()[id as usize], id)
            }
        }
    }
}

/// The query shape of each kind.
enum Kind {
    Ball(Ball),
    Box(Cuboid),
    Hull(HullSupport),
}

/// Bounds on the signed distance from the two shapes' extreme points along the unit axis `u` (pointing
/// from `a` towards `b`): `(lower, upper, next)`. With `pa` the farthest point of `a` along `u` and `pb`
/// the farthest of `b` along `-u`, the lower bound is their gap along `u` (a separating-axis test: if
/// negative, translating `b` by it along `u` separates the shapes, so the penetration depth is at most
/// that), and the upper bound is `|pa - pb|` (the distance between two points of the shapes, and
/// non-negative, so above any penetration too). `anchors` holds where the two searches start (the
/// pair's last support points: its next axis is seldom far from its last) and receives the anchor
/// numbers of `pa` and `pb` (see [`CollisionShape::anchor`]).
#[inline]
pub fn axis_bounds(
    a: &CollisionShape,
    pa: &Pose,
    b: &CollisionShape,
    pb: &Pose,
    u: Vec3,
    anchors: &mut [u32; 2],
) -> (f64, f64) {
    let (xa, ia) = a.support_from(pa, u, anchors[0]);
    let (xb, ib) = b.support_from(pb, -u, anchors[1]);
    *anchors = [ia, ib];
    ((xb - xa).dot(u), xa.distance(xb))
}

/// The lower bound on the signed distance of two shapes whose enclosing-sphere centres are at `outer_a`
/// and `outer_b` (world frame): the distance of those spheres, exact when both shapes are spheres.
#[inline]
pub fn outer_gap(a: &CollisionShape, outer_a: Vec3, b: &CollisionShape, outer_b: Vec3) -> f64 {
    outer_a.distance(outer_b) - a.outer_radius - b.outer_radius
}

/// Sphere bounds on the signed distance of two shapes whose enclosing-sphere centres are at `outer_a`,
/// `outer_b` and inscribed-sphere centres at `inner_a`, `inner_b` (world frame): `(lower, upper)`. The
/// lower bound holds because each shape lies inside its enclosing sphere; the upper bound because each
/// contains its inscribed sphere, so the spheres' overlap is at most the shapes' penetration depth.
pub fn sphere_bounds(
    a: &CollisionShape,
    outer_a: Vec3,
    inner_a: Vec3,
    b: &CollisionShape,
    outer_b: Vec3,
    inner_b: Vec3,
) -> (f64, f64) {
    (
        outer_gap(a, outer_a, b, outer_b),
        inner_a.distance(inner_b) - a.inner_radius - b.inner_radius,
    )
}

/// Whether two posed shapes overlap: the verdict of [`signed_distance`] `<= 0.0`, decided by one GJK
/// intersection test without computing a distance or penetration depth.
pub fn intersects(a: &CollisionShape, pa: &Pose, b: &CollisionShape, pb: &Pose) -> bool {
    if let (Kind::Ball(ba), Kind::Ball(bb)) = (&a.kind, &b.kind) {
        return pa.translation.distance(pb.translation) <= ba.radius + bb.radius;
    }
    let pos12 = pa.inv_mul(pb);
    query::details::intersection_test_support_map_support_map(
        &pos12,
        a.support_map(),
        b.support_map(),
    )
}

/// The witness points of [`signed_distance`] in the world frame: the closest points when the shapes are
/// apart, the deepest points of the penetration when they overlap. `None` only if GJK and EPA both fail.
pub fn witness_points(
    a: &CollisionShape,
    pa: &Pose,
    b: &CollisionShape,
    pb: &Pose,
) -> Option<(Vec3, Vec3)> {
    signed_distance_points(a, pa, b, pb).map(|(_, p1, p2)| (p1, p2))
}

/// [`signed_distance`] with its [`witness_points`]. `None` only if GJK and EPA both fail.
pub fn signed_distance_points(
    a: &CollisionShape,
    pa: &Pose,
    b: &CollisionShape,
    pb: &Pose,
) -> Option<(f64, Vec3, Vec3)> {
    if let (Kind::Ball(ba), Kind::Ball(bb)) = (&a.kind, &b.kind) {
        let (ca, cb) = (pa.translation, pb.translation);
        let dir = (cb - ca).normalize_or(Vec3::X);
        return Some((
            ca.distance(cb) - ba.radius - bb.radius,
            ca + dir * ba.radius,
            cb - dir * bb.radius,
        ));
    }
    let (d, p1, p2) = exact_query(a, b, &pa.inv_mul(pb), &mut Hint::default())?;
    Some((d, pa.transform_point(p1), pa.transform_point(p2)))
}

/// How far GJK's distance may lie above its lower bound before [`polished`] makes it exact, in metres.
const POLISH_GAP: f64 = 1e-7;

/// GJK's distance and closest points `found` (frame of `a`, `b` posed at `pos12`), made exact where its
/// bounds had not met within [`POLISH_GAP`] (it stalls on thin pieces): the gap along the direction
/// between the points bounds the distance from below, and the shapes' triangles near their support
/// planes along it hold the closest points (`separated`).
fn polished(
    a: &CollisionShape,
    b: &CollisionShape,
    pos12: &Pose,
    found: (f64, Vec3, Vec3),
    mut anchors: [u32; 2],
) -> (f64, Vec3, Vec3) {
    let (d, p1, p2) = found;
    let u = (p2 - p1) / d;
    let lower = -u.dot(distance_window::cso_support(a, b, pos12, u, &mut anchors).point);
    if d - lower <= POLISH_GAP {
        return found;
    }
    let exact = a
        .with_surface(|sa| b.with_surface(|sb| separated::exact_distance(sa, sb, pos12, u, d)))
        .flatten()
        .flatten();
    match exact {
        Some(e) if e.0 < d => e,
        _ => found,
    }
}

/// A sphere inside the hull: centred at the vertex mean, radius the distance to the nearest face plane.
fn inscribed(h: &ConvexMesh) -> (Vec3, f64) {
    let c = h.centroid();
    let r = h
        .planes()
        .iter()
        .map(|(n, d)| d - n.dot(c))
        .fold(f64::INFINITY, f64::min);
    (c, if r.is_finite() { r.max(0.0) } else { 0.0 })
}

/// Exact signed distance between two posed shapes (see the module doc for the sign). The shapes are in
/// collision exactly when the result is `<= 0.0`: one GJK decides, and only overlapping pairs pay for
/// the penetration depth (EPA, or the separating-axis test between two boxes).
pub fn signed_distance(a: &CollisionShape, pa: &Pose, b: &CollisionShape, pb: &Pose) -> f64 {
    signed_distance_hinted(a, pa, b, pb, &mut Hint::default())
}

/// [`signed_distance`], leaving in `hint` what it found: the closest points when the shapes are apart,
/// the direction of the penetration when they overlap.
pub fn signed_distance_hinted(
    a: &CollisionShape,
    pa: &Pose,
    b: &CollisionShape,
    pb: &Pose,
    hint: &mut Hint,
) -> f64 {
    if let (Kind::Ball(ba), Kind::Ball(bb)) = (&a.kind, &b.kind) {
        // Exact in closed form, and the most frequent query of the sphere types.
        return pa.translation.distance(pb.translation) - ba.radius - bb.radius;
    }
    exact_query(a, b, &pa.inv_mul(pb), hint).map_or(0.0, |(d, _, _)| d)
}

/// The exact signed distance of two shapes (not both spheres), `b` posed at `pos12` in the frame of
/// `a`, with a point of each in that frame: the closest points when apart, the deepest points when
/// overlapping. `hint` receives what the query found. `None` only if GJK and EPA both fail.
fn exact_query(
    a: &CollisionShape,
    b: &CollisionShape,
    pos12: &Pose,
    hint: &mut Hint,
) -> Option<(f64, Vec3, Vec3)> {
    // GJK on support maps for every pair, boxes too: parry's dedicated cuboid-cuboid distance derives
    // closest points from a separating axis and was measured off by up to 1.7 cm, and its cuboid
    // contact's depth by 0.18 mm (tests/exactness.rs). The same steps as parry's support-map
    // distance, keeping the points.
    let (g1, g2) = (a.support_map(), b.support_map());
    let mut simplex = distance_window::start_simplex(pos12, g1, g2);
    if let query::gjk::GJKResult::ClosestPoints(p1, p2, _) =
        query::gjk::closest_points(pos12, g1, g2, f64::MAX, true, &mut simplex)
    {
        let d = (p1 - p2).length();
        if d > 0.0 {
            let (d, p1, p2) = polished(a, b, pos12, (d, p1, p2), hint.anchors);
            hint.last = Last::apart(p1, p2, pos12);
            return Some((d, p1, p2));
        }
    }
    // Overlap (or touching): EPA from GJK's last simplex to the exact depth. parry's EPA, which stops
    // at a relative tolerance and was measured off by up to 1.0 mm, only where GJK ended on a single
    // point (touching) or ours degenerates.
    let n = simplex.dimension() + 1;
    let mut points = [CsoPoint::origin(); 4];
    for (i, p) in points[..n].iter_mut().enumerate() {
        *p = *simplex.point(i);
    }
    let mut anchors = hint.anchors;
    let exact = epa::penetration(&points[..n], |dir| {
        distance_window::cso_support(a, b, pos12, dir, &mut anchors)
    });
    let (dist, normal, p1, p2) = match exact {
        Some(p) => (-p.depth, p.normal, p.point_a, p.point_b),
        None => {
            let c = query::details::contact_support_map_support_map(pos12, g1, g2, 0.0)?;
            (c.dist, c.normal1, c.point1, pos12.transform_point(c.point2))
        }
    };
    if dist <= 0.0 && is_finite(normal) {
        // Between the two deepest points: inside both shapes, about half the depth into each.
        let deep = (p1 + p2) * 0.5;
        hint.last = Last::Overlap {
            normal,
            deep,
            depth: a.depth(deep),
        };
    }
    Some((dist.min(0.0), p1, p2))
}
