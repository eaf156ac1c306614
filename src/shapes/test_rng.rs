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
