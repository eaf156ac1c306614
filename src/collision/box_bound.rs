//! Bounds on a pair's signed distance from oriented boxes along the line between their centres:
//! for elongated shapes far tighter than the enclosing spheres, and nearly as cheap once each box is
//! placed (per shape and sample, not per pair).

use crate::math::{Pose, Rotation, Vec3};
use crate::shapes::Obb;

/// An oriented box around a shape, in its link's frame.
#[derive(Debug, Clone, Copy)]
pub struct BoundingBox {
    center: Vec3,
    rotation: Rotation,
    half_extents: Vec3,
    /// Whether the box is the shape itself (its corners are then points of the shape).
    exact: bool,
}

/// A bounding box placed in the world: its centre and its three axes scaled by the half extents.
#[derive(Debug, Clone, Copy, Default)]
pub struct PlacedBox {
    center: Vec3,
    axes: [Vec3; 3],
}

/// Slack added to a box around another shape, so rounding in the box fit cannot leave a vertex out.
const SLACK: f64 = 1e-9;

impl BoundingBox {
    /// The box shape `b` itself.
    pub fn of_box(b: &Obb) -> BoundingBox {
        BoundingBox {
            center: b.center,
            rotation: b.rotation,
            half_extents: b.half_extents,
            exact: true,
        }
    }

    /// A box `b` fitted around a shape (every point of the shape inside it).
    pub fn around(b: &Obb) -> BoundingBox {
        BoundingBox {
            center: b.center,
            rotation: b.rotation,
            half_extents: b.half_extents + Vec3::splat(SLACK),
            exact: false,
        }
    }

    /// Whether the box is the shape itself.
    pub fn is_exact(&self) -> bool {
        self.exact
    }

    /// The box placed by its link's pose.
    #[inline]
    pub fn place(&self, link: &Pose) -> PlacedBox {
        let r = link.rotation * self.rotation;
        let h = self.half_extents;
        PlacedBox {
            center: link.transform_point(self.center),
            axes: [r * Vec3::X * h.x, r * Vec3::Y * h.y, r * Vec3::Z * h.z],
        }
    }
}

impl PlacedBox {
    /// Half the box's extent along the unit vector `u`.
    #[inline]
    fn reach(&self, u: Vec3) -> f64 {
        let [x, y, z] = self.axes;
        x.dot(u).abs() + y.dot(u).abs() + z.dot(u).abs()
    }

    /// The box's corner farthest along `u`.
    #[inline]
    fn corner(&self, u: Vec3) -> Vec3 {
        let [x, y, z] = self.axes;
        self.center + pick(x, u) + pick(y, u) + pick(z, u)
    }
}

/// The axis `v` or `-v`, whichever points along `u`.
#[inline]
fn pick(v: Vec3, u: Vec3) -> Vec3 {
    if v.dot(u) >= 0.0 { v } else { -v }
}

/// Bounds `(lower, upper)` on the signed distance of two shapes inside the placed boxes `a` and `b`,
/// along the unit axis `u` between the box centres. The lower bound is the gap between the boxes'
/// extents along `u` (a separating-axis test: with a negative gap, translating `b` by it along `u`
/// separates the boxes, and so the shapes inside them); it holds for overlapping shapes too. The
/// upper bound, only where both boxes are the shapes themselves (`exact`), is the distance between
/// their corners nearest each other along `u` (two points of the shapes); else infinite. `None` when
/// the centres coincide (no axis).
#[inline]
pub fn box_bounds(a: &PlacedBox, b: &PlacedBox, exact: bool) -> Option<(f64, f64)> {
    let d = b.center - a.center;
    let len = d.length();
    if len <= f64::MIN_POSITIVE.sqrt() {
        return None;
    }
    let u = d / len;
    let lower = len - a.reach(u) - b.reach(u);
    let upper = if exact {
        a.corner(u).distance(b.corner(-u))
    } else {
        f64::INFINITY
    };
    Some((lower, upper))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::test_shapes::{link, pick, shapes, values};
    use crate::collision::{signed_distance, sphere_bounds};

    #[test]
    fn box_bounds_bracket_the_signed_distance_and_beat_the_spheres() {
        let mut r = values(11);
        let shapes = shapes(&mut r);
        let (mut checked, mut tighter, mut overlapping) = (0, 0, 0);
        for _ in 0..4000 {
            let (a, b) = (&shapes[pick(&mut r)], &shapes[pick(&mut r)]);
            let (la, lb) = (link(&mut r), link(&mut r));
            let d = signed_distance(a, &a.pose(&la), b, &b.pose(&lb));
            let (box_a, box_b) = (a.bounding_box.unwrap(), b.bounding_box.unwrap());
            let exact = box_a.is_exact() && box_b.is_exact();
            let Some((lower, upper)) = box_bounds(&box_a.place(&la), &box_b.place(&lb), exact)
            else {
                continue;
            };
            assert!(lower <= d + 1e-9, "lower {lower} above the distance {d}");
            assert!(d <= upper + 1e-9, "upper {upper} below the distance {d}");
            assert_eq!(
                upper.is_finite(),
                exact,
                "an upper bound only for two boxes"
            );
            let (sphere_lower, _) = sphere_bounds(
                a,
                la.transform_point(a.outer_center),
                la.transform_point(a.inner_center),
                b,
                lb.transform_point(b.outer_center),
                lb.transform_point(b.inner_center),
            );
            checked += 1;
            tighter += usize::from(lower > sphere_lower + 1e-3);
            overlapping += usize::from(d < 0.0);
        }
        assert!(
            checked > 3900 && overlapping > 200,
            "{checked} pairs, {overlapping} overlapping"
        );
        // For elongated shapes the box gap is far tighter than the enclosing spheres' most of the time.
        assert!(
            tighter * 2 > checked,
            "tighter than the spheres in {tighter} of {checked}"
        );
    }
}
