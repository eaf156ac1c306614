//! The minimal enclosing sphere of a point set (Welzl's algorithm in Gärtner's move-to-front form).

use crate::math::{Vec3, bounds, is_finite};

/// A ball: every point within `radius` of `center`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    /// The centre.
    pub center: Vec3,
    /// The radius (zero for a single point or an empty set).
    pub radius: f64,
}

impl Sphere {
    /// The enclosed volume, `4/3 π r³`.
    pub fn volume(&self) -> f64 {
        4.0 / 3.0 * std::f64::consts::PI * self.radius.powi(3)
    }

    /// Whether `p` lies inside the ball or within `tol` of its surface.
    pub fn contains(&self, p: Vec3, tol: f64) -> bool {
        p.distance(self.center) <= self.radius + tol
    }
}

/// The smallest ball enclosing `points` (non-finite points are ignored; no points gives a zero
/// ball at the origin). Exact up to rounding, deterministic, and padded by ~1e-12 of the set's
/// size so that every point passes `contains(p, 0.0)`.
pub fn minimal_bounding_sphere(points: &[Vec3]) -> Sphere {
    let pts: Vec<Vec3> = points.iter().copied().filter(|p| is_finite(*p)).collect();
    let Some((lo, hi)) = bounds(&pts) else {
        return Sphere {
            center: Vec3::ZERO,
            radius: 0.0,
        };
    };
    // Work relative to the box centre, scaled to unit size: well-conditioned and overflow-free.
    let mid = lo * 0.5 + hi * 0.5;
    let s = (hi * 0.5 - lo * 0.5).max_element();
    if s.is_nan() || s <= 0.0 {
        return Sphere {
            center: mid,
            radius: 0.0,
        };
    }
    let mut q: Vec<Vec3> = pts.iter().map(|p| (*p - mid) / s).collect();
    // A fixed-seed shuffle makes the expected running time linear whatever the input order.
    let mut state = 0x853C_49E6_748F_EA9B_u64;
    for i in (1..q.len()).rev() {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        q.swap(i, ((state >> 33) % (i as u64 + 1)) as usize);
    }
    let mut mb = Miniball::new();
    let end = q.len();
    mb.mtf(&mut q, end);
    // Final radius: the true farthest point from the centre found, padded against rounding.
    let center = mid + mb.center * s;
    let far = pts.iter().map(|p| p.distance(center)).fold(0.0, f64::max);
    let radius = far + 1e-12 * s;
    Sphere { center, radius }
}

/// The support-set state of Gärtner's Miniball: the smallest ball with the pushed points (at most
/// four) on its boundary, built incrementally in an orthogonalised basis of their affine hull.
struct Miniball {
    /// How many support points are pushed.
    m: usize,
    /// The first support point.
    q0: Vec3,
    /// Orthogonalised directions `v[i]` (i >= 1) of the support points relative to `q0`.
    v: [Vec3; 4],
    /// `2 |v[i]|²`.
    z: [f64; 4],
    /// Centre after each push.
    centers: [Vec3; 4],
    /// Squared radius after each push.
    sqr_radii: [f64; 4],
    /// The current ball's centre.
    center: Vec3,
    /// The current ball's squared radius (negative: empty).
    sqr_radius: f64,
}

impl Miniball {
    fn new() -> Self {
        Miniball {
            m: 0,
            q0: Vec3::ZERO,
            v: [Vec3::ZERO; 4],
            z: [0.0; 4],
            centers: [Vec3::ZERO; 4],
            sqr_radii: [0.0; 4],
            center: Vec3::ZERO,
            sqr_radius: -1.0,
        }
    }

    /// How far `p` lies outside the current ball, in squared-distance units.
    fn excess(&self, p: Vec3) -> f64 {
        p.distance_squared(self.center) - self.sqr_radius
    }

    /// Adds `p` to the support set; refuses (returns false) when `p` is affinely dependent on it.
    fn push(&mut self, p: Vec3) -> bool {
        if self.m == 0 {
            self.q0 = p;
            self.centers[0] = p;
            self.sqr_radii[0] = 0.0;
        } else {
            let m = self.m;
            let mut vm = p - self.q0;
            for i in 1..m {
                let a = 2.0 * self.v[i].dot(p - self.q0) / self.z[i];
                vm -= self.v[i] * a;
            }
            let zm = 2.0 * vm.length_squared();
            if zm.is_nan() || zm == 0.0 || zm < 1e-16 * self.sqr_radius {
                return false;
            }
            let e = p.distance_squared(self.centers[m - 1]) - self.sqr_radii[m - 1];
            let f = e / zm;
            self.v[m] = vm;
            self.z[m] = zm;
            self.centers[m] = self.centers[m - 1] + vm * f;
            self.sqr_radii[m] = self.sqr_radii[m - 1] + e * f / 2.0;
        }
        self.center = self.centers[self.m];
        self.sqr_radius = self.sqr_radii[self.m];
        self.m += 1;
        true
    }

    /// Removes the last support point; the current ball stays (Gärtner's invariant: it now
    /// encloses the points seen so far).
    fn pop(&mut self) {
        self.m -= 1;
    }

    /// Move-to-front Welzl: the smallest ball of `pts[..end]` with the pushed points on its
    /// boundary. Recursion depth is bounded by the support size (at most 4).
    fn mtf(&mut self, pts: &mut [Vec3], end: usize) {
        if self.m == 4 {
            return;
        }
        for i in 0..end {
            let p = pts[i];
            // Points within ~1e-14 (relative) of the ball count as inside: the final radius is
            // taken as the true farthest distance, so they stay enclosed.
            if self.excess(p) > 1e-14 * self.sqr_radius.max(0.0) && self.push(p) {
                self.mtf(pts, i);
                self.pop();
                // Move p to the front: later passes meet the hard points first.
                pts[..=i].rotate_right(1);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::shapes::test_rng::Rng;

    fn assert_encloses(s: &Sphere, pts: &[Vec3]) {
        assert!(pts.iter().all(|p| s.contains(*p, 0.0)), "{s:?}");
    }

    fn check(pts: &[Vec3], center: Vec3, radius: f64) {
        let s = minimal_bounding_sphere(pts);
        assert_encloses(&s, pts);
        assert!(
            (s.radius - radius).abs() <= 0.01 * radius + 1e-12,
            "{s:?} vs {radius}"
        );
        assert!(
            s.center.distance(center) <= 0.01 * radius + 1e-12,
            "{s:?} vs {center}"
        );
        println!(
            "radius {} vs optimum {radius}: relative error {:e}",
            s.radius,
            s.radius / radius - 1.0
        );
    }

    #[test]
    fn known_optima() {
        let off = Vec3::new(3.0, -1.0, 2.0);
        let cube: Vec<Vec3> = (0..8)
            .map(|i| Vec3::new((i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2) as f64) + off)
            .collect();
        check(&cube, off + Vec3::splat(0.5), 3f64.sqrt() / 2.0);
        let k = 1.0 / 2f64.sqrt();
        let tet = [
            Vec3::new(1.0, 0.0, -k),
            Vec3::new(-1.0, 0.0, -k),
            Vec3::new(0.0, 1.0, k),
            Vec3::new(0.0, -1.0, k),
        ];
        check(&tet.map(|p| p + off), off, tet[0].length());
        check(&[off, off + Vec3::new(0.0, 2.0, 0.0)], off + Vec3::Y, 1.0);
        // Obtuse triangle: the ball is the diameter ball of the longest side.
        let tri = [
            Vec3::ZERO,
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(1.0, 0.5, 0.0),
        ];
        check(&tri, Vec3::new(2.0, 0.0, 0.0), 2.0);
        let mut r = Rng(5);
        let sphere: Vec<Vec3> = (0..3000).map(|_| r.unit() + off).collect();
        check(&sphere, off, 1.0);
        // Many points inside plus a few on the unit sphere.
        let mut inner: Vec<Vec3> = (0..2000).map(|_| r.unit() * r.f() * 0.9).collect();
        inner.extend([Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Z]);
        check(&inner, Vec3::ZERO, 1.0);
    }

    #[test]
    fn degenerate_inputs() {
        assert_eq!(
            minimal_bounding_sphere(&[]),
            Sphere {
                center: Vec3::ZERO,
                radius: 0.0
            }
        );
        let p = Vec3::new(1.0, 2.0, 3.0);
        assert_eq!(
            minimal_bounding_sphere(&[p]),
            Sphere {
                center: p,
                radius: 0.0
            }
        );
        assert_eq!(minimal_bounding_sphere(&[p; 5]).radius, 0.0);
        let line: Vec<Vec3> = (0..50)
            .map(|i| p + Vec3::new(1.0, 1.0, 0.0) * i as f64 * 0.1)
            .collect();
        check(&line, p + Vec3::new(2.45, 2.45, 0.0), 2.45 * 2f64.sqrt());
        let mut r = Rng(9);
        let disk: Vec<Vec3> = (0..500)
            .map(|_| {
                let u = r.unit();
                Vec3::new(u.x, u.y, 0.0).normalize() * 2.0
            })
            .collect();
        check(&disk, Vec3::ZERO, 2.0);
        let s = minimal_bounding_sphere(&[
            p,
            Vec3::splat(f64::NAN),
            p + Vec3::X,
            Vec3::splat(f64::INFINITY),
        ]);
        assert!(s.center.distance(p + Vec3::X * 0.5) < 1e-12 && (s.radius - 0.5).abs() < 1e-9);
        // Heavily repeated cospherical points (cube corners), a grid, and a circle (coplanar).
        let corners: Vec<Vec3> = (0..8000)
            .map(|i| Vec3::new((i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2 & 1) as f64))
            .collect();
        check(&corners, Vec3::splat(0.5), 3f64.sqrt() / 2.0);
        let grid: Vec<Vec3> = (0..8000)
            .map(|i| Vec3::new((i % 20) as f64, (i / 20 % 20) as f64, (i / 400) as f64))
            .collect();
        check(&grid, Vec3::splat(9.5), 9.5 * 3f64.sqrt());
        let circle: Vec<Vec3> = (0..360)
            .map(|i| {
                let a = (i as f64).to_radians();
                Vec3::new(a.cos(), 0.0, a.sin()) * 3.0
            })
            .collect();
        check(&circle, Vec3::ZERO, 3.0);
        // Duplicates and a huge offset.
        let far: Vec<Vec3> = (0..200)
            .map(|i| Vec3::splat(1e6) + r.unit() * 1e-3 * ((i % 3) as f64).min(1.0))
            .collect();
        check(&far, Vec3::splat(1e6), 1e-3);
    }

    #[test]
    fn clouds_are_enclosed_and_deterministic() {
        let clouds = crate::shapes::test_rng::test_clouds();
        for pts in &clouds {
            let s = minimal_bounding_sphere(pts);
            assert_encloses(&s, pts);
            assert_eq!(s, minimal_bounding_sphere(pts));
            // Optimality: the ball touches the set (some point within 1e-9 of the surface) and no
            // smaller ball around a nearby centre encloses it.
            let far = pts.iter().map(|p| p.distance(s.center)).fold(0.0, f64::max);
            assert!(s.radius - far < 1e-9);
            for d in [
                Vec3::X,
                Vec3::NEG_X,
                Vec3::Y,
                Vec3::NEG_Y,
                Vec3::Z,
                Vec3::NEG_Z,
            ] {
                let c = s.center + d * 1e-4;
                assert!(pts.iter().map(|p| p.distance(c)).fold(0.0, f64::max) > far);
            }
        }
    }
}
