//! A tiny deterministic PRNG (SplitMix64) for the point clouds of the shape tests.

use crate::math::{Rotation, Vec3};
use std::f64::consts::TAU;

/// SplitMix64 with helpers for points, directions and rotations.
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    /// Uniform in [0, 1).
    pub(crate) fn f(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A point uniform in the cube [lo, hi]^3.
    pub(crate) fn v(&mut self, lo: f64, hi: f64) -> Vec3 {
        Vec3::new(self.f(), self.f(), self.f()) * (hi - lo) + Vec3::splat(lo)
    }

    /// A uniformly random unit vector.
    pub(crate) fn unit(&mut self) -> Vec3 {
        loop {
            let v = self.v(-1.0, 1.0);
            if (0.01..1.0).contains(&v.length_squared()) {
                return v.normalize();
            }
        }
    }

    /// A random rotation.
    pub(crate) fn rotation(&mut self) -> Rotation {
        Rotation::from_axis_angle(self.unit(), TAU * self.f())
    }
}

/// Test point clouds: a flat box, a sphere shell, a thin cylinder, an L shape.
pub(crate) fn test_clouds() -> Vec<Vec<Vec3>> {
    let mut r = Rng(7);
    let axis = Vec3::new(1.0, 2.0, 0.5).normalize();
    let (u, w) = axis.any_orthonormal_pair();
    vec![
        (0..500)
            .map(|_| r.v(-1.0, 1.0) * Vec3::new(0.5, 0.3, 0.1) + Vec3::X)
            .collect(),
        (0..2000)
            .map(|_| r.unit() * 0.2 + Vec3::new(0.1, -2.0, 0.3))
            .collect(),
        (0..1500)
            .map(|_| {
                (u * (TAU * r.f()).cos() + w * (TAU * r.f()).sin()).normalize() * 0.02
                    + axis * r.f()
            })
            .collect(),
        (0..800)
            .map(|i| {
                r.v(0.0, 1.0)
                    * if i % 2 == 0 {
                        Vec3::new(1.0, 0.2, 0.2)
                    } else {
                        Vec3::new(0.2, 1.0, 0.2)
                    }
            })
            .collect(),
    ]
}
