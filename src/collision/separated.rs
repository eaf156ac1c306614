//! The exact distance of two separated polytopes once GJK has nearly converged.
//!
//! parry's GJK can stall on thin pieces a few micrometres before its bounds meet (tests/exactness.rs).
//! Its closest points and the shapes' extents along the direction between them still pin the answer
//! down: with `u` that unit direction (from `a` towards `b`), `upper` the distance GJK found and `lower`
//! the gap between `a`'s farthest point along `u` and `b`'s farthest along `-u`, the true closest points
//! lie within `band = upper - lower` of those support planes. (With `x`, `y` the closest points and `D`
//! their distance, `y . u >= min_b` and `(y - x) . u <= D <= upper`, so `x . u >= max_a - band`; the
//! same for `y`.) Every triangle of a shape's surface that reaches into its slab has a vertex there, so
//! the least distance between those triangles of the two shapes is the exact distance, found among a
//! handful of them.

use crate::math::{Pose, Vec3};

/// The triangles of a box's surface, its corners numbered by sign bits (x: 1, y: 2, z: 4).
pub(super) const BOX_TRIANGLES: [[u32; 3]; 12] = [
    [0, 2, 6],
    [0, 6, 4],
    [1, 3, 7],
    [1, 7, 5],
    [0, 1, 5],
    [0, 5, 4],
    [2, 3, 7],
    [2, 7, 6],
    [0, 1, 3],
    [0, 3, 2],
    [4, 5, 7],
    [4, 7, 6],
];

/// A box's corners (its own frame), numbered as in [`BOX_TRIANGLES`].
pub(super) fn box_corners(half: Vec3) -> [Vec3; 8] {
    std::array::from_fn(|k| {
        let sign = |bit: usize| if k & (1 << bit) == 0 { -1.0 } else { 1.0 };
        Vec3::new(sign(0) * half.x, sign(1) * half.y, sign(2) * half.z)
    })
}

/// A polytope's surface: vertices and triangles (indices into them), in its own frame.
#[derive(Clone, Copy)]
pub(super) struct Surface<'a> {
    pub vertices: &'a [Vec3],
    pub triangles: &'a [[u32; 3]],
}

/// The exact distance of two separated polytopes `a` and `b` (`b` posed at `pos12` in the frame of
/// `a`) and their closest points (frame of `a`), given a unit direction `u` from `a` towards `b` and
/// an upper bound `upper` on the distance (module doc). `None` when the two slabs hold no triangle
/// pair (only if the inputs are inconsistent).
pub(super) fn exact_distance(
    a: Surface,
    b: Surface,
    pos12: &Pose,
    u: Vec3,
    upper: f64,
) -> Option<(f64, Vec3, Vec3)> {
    let b_vertices: Vec<Vec3> = b
        .vertices
        .iter()
        .map(|v| pos12.transform_point(*v))
        .collect();
    let along = |vs: &[Vec3]| vs.iter().map(|v| v.dot(u)).collect::<Vec<f64>>();
    let (ta, tb) = (along(a.vertices), along(&b_vertices));
    let max_a = ta.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min_b = tb.iter().copied().fold(f64::INFINITY, f64::min);
    // A little more than the band: rounding must not drop the triangle that holds a closest point.
    let band = (upper - (min_b - max_a)).max(0.0) * (1.0 + 1e-6) + 1e-12;
    let slab_a = slab(a.triangles, a.vertices, &ta, |t| t >= max_a - band);
    let slab_b = slab(b.triangles, &b_vertices, &tb, |t| t <= min_b + band);
    let mut best: Option<(f64, Vec3, Vec3)> = None;
    for ta in &slab_a {
        for tb in &slab_b {
            let (p, q) = closest_between_triangles(ta, tb);
            let d = p.distance(q);
            if best.is_none_or(|(e, _, _)| d < e) {
                best = Some((d, p, q));
            }
        }
    }
    best
}

/// The triangles with a corner whose position `t` (along the direction) passes `keep`, as their corner
/// points.
fn slab(
    triangles: &[[u32; 3]],
    vertices: &[Vec3],
    t: &[f64],
    keep: impl Fn(f64) -> bool,
) -> Vec<[Vec3; 3]> {
    triangles
        .iter()
        .filter(|tri| tri.iter().any(|&i| keep(t[i as usize])))
        .map(|tri| tri.map(|i| vertices[i as usize]))
        .collect()
}

/// The closest points of two triangles (apart): the nearer of every corner against the other
/// triangle and every edge against every edge.
fn closest_between_triangles(a: &[Vec3; 3], b: &[Vec3; 3]) -> (Vec3, Vec3) {
    let mut best = (f64::INFINITY, a[0], b[0]);
    let mut consider = |p: Vec3, q: Vec3| {
        let d = p.distance_squared(q);
        if d < best.0 {
            best = (d, p, q);
        }
    };
    for k in 0..3 {
        consider(a[k], closest_on_triangle(a[k], b[0], b[1], b[2]));
        consider(closest_on_triangle(b[k], a[0], a[1], a[2]), b[k]);
    }
    for i in 0..3 {
        for j in 0..3 {
            let (p, q) = closest_on_segments(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]);
            consider(p, q);
        }
    }
    (best.1, best.2)
}

/// The point of triangle `abc` closest to `p` (Ericson, Real-Time Collision Detection, 5.1.5).
pub fn closest_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// The closest points of segments `p1 q1` and `p2 q2` (Ericson 5.1.9).
pub fn closest_on_segments(p1: Vec3, q1: Vec3, p2: Vec3, q2: Vec3) -> (Vec3, Vec3) {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.dot(d1), d2.dot(d2), d2.dot(r));
    if a <= 1e-30 && e <= 1e-30 {
        return (p1, p2);
    }
    if a <= 1e-30 {
        return (p1, p2 + d2 * (f / e).clamp(0.0, 1.0));
    }
    let c = d1.dot(r);
    if e <= 1e-30 {
        return (p1 + d1 * (-c / a).clamp(0.0, 1.0), p2);
    }
    let b = d1.dot(d2);
    let denom = a * e - b * b;
    let mut s = if denom > 0.0 {
        ((b * f - c * e) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = (b * s + f) / e;
    if t < 0.0 {
        t = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    (p1 + d1 * s, p2 + d2 * t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::test_shapes::values;

    /// The closest points found are at least as close as any of a dense grid of points on the
    /// triangle and segments, and lie on them.
    #[test]
    fn closest_points_beat_a_dense_grid() {
        let mut r = values(3);
        let mut point = || Vec3::new(r(), r(), r()) * 2.0;
        for _ in 0..200 {
            let (p, a, b, c) = (point(), point(), point(), point());
            let x = closest_on_triangle(p, a, b, c);
            let n = (b - a).cross(c - a).normalize();
            assert!((x - a).dot(n).abs() < 1e-12, "off the triangle's plane");
            let steps = 60;
            for i in 0..=steps {
                for j in 0..=steps - i {
                    let (s, t) = (i as f64 / steps as f64, j as f64 / steps as f64);
                    let y = a + (b - a) * s + (c - a) * t;
                    assert!(p.distance(x) <= p.distance(y) + 1e-12);
                }
            }
            let (p2, q2) = (point(), point());
            let (x, y) = closest_on_segments(a, b, p2, q2);
            for i in 0..=steps {
                for j in 0..=steps {
                    let (s, t) = (i as f64 / steps as f64, j as f64 / steps as f64);
                    let (u, v) = (a + (b - a) * s, p2 + (q2 - p2) * t);
                    assert!(x.distance(y) <= u.distance(v) + 1e-12);
                }
            }
        }
    }

    /// Two boxes apart, face to face but tilted a hair, with a loose upper bound: the distance
    /// between their triangles near the support planes is the exact distance.
    #[test]
    fn the_slab_triangles_give_the_exact_distance() {
        let half = Vec3::new(0.1, 0.02, 0.3);
        let corners = box_corners(half);
        let surface = Surface {
            vertices: &corners,
            triangles: &BOX_TRIANGLES,
        };
        // b 0.05 above a along y, turned 1e-4 rad about z: its lowest corner, (-0.1, -0.02) in its
        // frame, lies above a's top face.
        let angle = 1e-4f64;
        let pos12 = Pose::from_parts(
            Vec3::new(0.0, 0.09, 0.0),
            crate::math::Rotation::from_rotation_z(angle),
        );
        let exact = 0.07 - 0.02 * angle.cos() - 0.1 * angle.sin();
        let (d, p, q) = exact_distance(surface, surface, &pos12, Vec3::Y, exact + 3e-6)
            .expect("the slabs hold the closest triangles");
        assert!((d - exact).abs() < 1e-12, "{d} vs {exact}");
        assert!((p.distance(q) - d).abs() < 1e-15);
    }
}
