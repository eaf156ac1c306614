//! The one math vocabulary of the core: parry's f64 glam types, re-exported under short names.

pub use parry3d_f64::math::{Pose, Rotation, Vector as Vec3};

/// A 3x3 matrix (parry's f64 glam matrix).
pub use parry3d_f64::math::Matrix as Mat3;

/// True when every coordinate of `v` is finite.
pub fn is_finite(v: Vec3) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

/// Axis-aligned bounds of a point set: `(min, max)`, or `None` for an empty set.
pub fn bounds(points: &[Vec3]) -> Option<(Vec3, Vec3)> {
    let first = *points.first()?;
    Some(
        points
            .iter()
            .fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p))),
    )
}
