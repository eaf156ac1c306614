//! Random shapes and poses for the collision tests: elongated boxes and hulls, as sampling meets them.

use super::CollisionShape;
use crate::math::{Pose, Rotation, Vec3};
use crate::shapes::{Geometry, Obb, convex_hull};

/// A small deterministic generator of values in [-0.5, 0.5).
pub fn values(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

/// Elongated boxes, and hulls of random points in elongated regions, alternately (40 shapes).
pub fn shapes(r: &mut impl FnMut() -> f64) -> Vec<CollisionShape> {
    let mut out = Vec::new();
    for k in 0..40 {
        let half = Vec3::new(0.2 + r(), 0.03 + 0.05 * r().abs(), 0.05 + 0.1 * r().abs());
        let geometry = if k % 2 == 0 {
            Geometry::Obb(Obb {
                center: Vec3::new(r(), r(), r()) * 0.1,
                rotation: Rotation::from_scaled_axis(Vec3::new(r(), r(), r()) * 3.0),
                half_extents: half,
            })
        } else {
            let points: Vec<Vec3> = (0..60)
                .map(|_| Vec3::new(r(), r(), r()) * half * 2.0)
                .collect();
            Geometry::Hull(convex_hull(&points).expect("60 random points span a volume"))
        };
        out.push(CollisionShape::new(&geometry).expect("not degenerate"));
    }
    out
}

/// A random index into [`shapes`].
pub fn pick(r: &mut dyn FnMut() -> f64) -> usize {
    ((r() + 0.5) * 40.0) as usize % 40
}

/// A random link pose within 0.4 m of the origin.
pub fn link(r: &mut dyn FnMut() -> f64) -> Pose {
    Pose::from_parts(
        Vec3::new(r(), r(), r()) * 0.8,
        Rotation::from_scaled_axis(Vec3::new(r(), r(), r()) * 6.0),
    )
}
