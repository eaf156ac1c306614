//! Bracketing the penetration depth of two overlapping shapes with as few EPA steps as a question needs.
//!
//! EPA grows a polytope of points of the configuration-space obstacle (CSO, `a - b`) around the origin.
//! The polytope lies inside the CSO, so the origin's distance to its nearest face is at most the
//! penetration depth: minus it bounds the signed distance from above. The CSO's extent along any unit
//! direction is at least the depth (a separating-axis test): minus the extent along the nearest face's
//! normal bounds the signed distance from below. Sampling asks only whether the signed distance lies
//! between the extremes seen so far, and the bracket usually answers that after a few steps, where
//! the exact depth (parry's EPA) runs to convergence.

use crate::math::Vec3;

/// Most vertices of the polytope: the start tetrahedron and one per step.
const MAX_VERTICES: usize = 28;
/// Most faces: a closed triangulation of `V` vertices has `2V - 4` (the faces that see a new point
/// are dropped before its fan is added).
const MAX_FACES: usize = 2 * MAX_VERTICES - 4;

/// A face of the polytope: vertex indices counter-clockwise seen from outside, the outward unit normal,
/// and the origin's distance to its plane.
#[derive(Clone, Copy)]
struct Face {
    v: [u8; 3],
    normal: Vec3,
    dist: f64,
    alive: bool,
}

impl Face {
    /// The face through `v` of the points `p`, or `None` when it is degenerate.
    fn new(p: &[Vec3], v: [u8; 3]) -> Option<Face> {
        let (a, b, c) = (p[v[0] as usize], p[v[1] as usize], p[v[2] as usize]);
        let normal = (b - a).cross(c - a).try_normalize()?;
        Some(Face {
            v,
            normal,
            dist: normal.dot(a),
            alive: true,
        })
    }
}

/// Brackets the signed distance of two overlapping shapes, given the CSO's support function
/// `support(dir)` (the point of `a - b` farthest along the unit vector `dir`) and four CSO points
/// whose tetrahedron contains the origin, until the bracket lies strictly inside `(lo, hi)`: `true`
/// when it does, `false` when it cannot (the distance may lie outside, the polytope stopped growing,
/// or it degenerated). `lower` is a lower bound already known.
pub fn depth_within(
    tetrahedron: [Vec3; 4],
    mut support: impl FnMut(Vec3) -> Vec3,
    lo: f64,
    hi: f64,
    mut lower: f64,
) -> bool {
    let mut points = [Vec3::ZERO; MAX_VERTICES];
    points[..4].copy_from_slice(&tetrahedron);
    let mut n_points = 4;
    let mut faces = [Face {
        v: [0; 3],
        normal: Vec3::ZERO,
        dist: 0.0,
        alive: false,
    }; MAX_FACES];
    let mut n_faces = 0;
    for (tri, other) in [
        ([0, 1, 2], 3),
        ([0, 1, 3], 2),
        ([0, 2, 3], 1),
        ([1, 2, 3], 0),
    ] {
        let Some(mut face) = Face::new(&points, tri) else {
            return false;
        };
        if face.normal.dot(points[other] - points[tri[0] as usize]) > 0.0 {
            face = Face::new(&points, [tri[0], tri[2], tri[1]]).expect("the same three points");
        }
        faces[n_faces] = face;
        n_faces += 1;
    }
    loop {
        // The nearest face (all are alive here): the origin lies inside every face's plane, so the
        // depth is at least its distance.
        let Some(nearest) = faces[..n_faces]
            .iter()
            .min_by(|x, y| x.dist.total_cmp(&y.dist))
            .copied()
        else {
            return false;
        };
        if nearest.dist < 0.0 {
            // Rounding put the origin outside: the bound would not hold.
            return false;
        }
        let upper = -nearest.dist;
        let w = support(nearest.normal);
        let extent = nearest.normal.dot(w);
        lower = lower.max(-extent);
        if lo < lower && upper < hi {
            return true;
        }
        if upper <= lo || lower >= hi || extent - nearest.dist <= 1e-12 * extent.abs().max(1e-3) {
            // Outside for sure, or converged without a decision: the exact query decides.
            return false;
        }
        if n_points == MAX_VERTICES {
            return false;
        }
        // Replace the faces that see the new point by a fan from it over their horizon.
        let new = n_points as u8;
        points[n_points] = w;
        n_points += 1;
        let mut horizon = [[0u8; 2]; 64];
        let mut n_horizon = 0;
        for f in faces[..n_faces].iter_mut() {
            if f.alive && f.normal.dot(w) - f.dist > 0.0 {
                f.alive = false;
                for e in [[f.v[0], f.v[1]], [f.v[1], f.v[2]], [f.v[2], f.v[0]]] {
                    // An edge shared by two removed faces appears once each way: both go.
                    if let Some(k) = horizon[..n_horizon].iter().position(|h| *h == [e[1], e[0]]) {
                        horizon[k] = horizon[n_horizon - 1];
                        n_horizon -= 1;
                    } else if n_horizon < horizon.len() {
                        horizon[n_horizon] = e;
                        n_horizon += 1;
                    } else {
                        return false;
                    }
                }
            }
        }
        // Compact the faces, then add the fan.
        let mut kept = 0;
        for k in 0..n_faces {
            if faces[k].alive {
                faces[kept] = faces[k];
                kept += 1;
            }
        }
        n_faces = kept;
        if n_horizon < 3 || n_faces + n_horizon > MAX_FACES {
            return false;
        }
        for e in &horizon[..n_horizon] {
            let Some(face) = Face::new(&points, [e[0], e[1], new]) else {
                return false;
            };
            faces[n_faces] = face;
            n_faces += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The CSO of two boxes (half extents `ha`, `hb`, axis-aligned, centres `ca`, `cb`): a box.
    fn box_support(c: Vec3, h: Vec3) -> impl Fn(Vec3) -> Vec3 {
        move |d: Vec3| c + Vec3::new(h.x.copysign(d.x), h.y.copysign(d.y), h.z.copysign(d.z))
    }

    #[test]
    fn the_bracket_decides_only_windows_that_hold_the_depth() {
        // Two axis-aligned boxes overlapping by 0.02 along x (less than along y and z): the CSO is
        // the box of centre ca - cb and half extents ha + hb, and the signed distance is -0.02.
        let (ha, hb) = (Vec3::new(0.1, 0.2, 0.3), Vec3::new(0.05, 0.1, 0.1));
        let (ca, cb) = (Vec3::ZERO, Vec3::new(0.13, 0.01, -0.02));
        let (c, h) = (ca - cb, ha + hb);
        let support = box_support(c, h);
        // A tetrahedron of CSO corners around the origin.
        let corner = |x: f64, y: f64, z: f64| c + Vec3::new(x * h.x, y * h.y, z * h.z);
        let tet = [
            corner(1.0, 1.0, 1.0),
            corner(1.0, -1.0, -1.0),
            corner(-1.0, 1.0, -1.0),
            corner(-1.0, -1.0, 1.0),
        ];
        // Windows around the exact value are decided; windows that miss it never are.
        for (lo, hi) in [
            (-0.03, -0.01),
            (-0.0201, -0.0199),
            (-1.0, 0.0),
            (-0.021, 1.0),
        ] {
            assert!(
                depth_within(tet, &support, lo, hi, f64::NEG_INFINITY),
                "({lo}, {hi})"
            );
        }
        // (-0.02 is not representable: these windows miss the computed depth by at least 1e-9.)
        for (lo, hi) in [
            (-0.019, 0.0),
            (-0.5, -0.021),
            (-0.02 + 1e-9, -0.01),
            (-0.03, -0.02 - 1e-9),
        ] {
            assert!(
                !depth_within(tet, &support, lo, hi, f64::NEG_INFINITY),
                "({lo}, {hi})"
            );
        }
    }
}
