//! EPA (the expanding polytope algorithm) over the configuration-space obstacle (CSO, `a - b`) of two
//! overlapping shapes: the exact penetration depth, and brackets on it with as few steps as a
//! question needs.
//!
//! EPA grows a polytope of CSO points around the origin. The polytope lies inside the CSO, so the
//! origin's distance to its nearest face is at most the penetration depth; the CSO's extent along any
//! unit direction is at least the depth (a separating-axis test). Each step adds the CSO's farthest
//! point along the nearest face's normal, and the two bounds close in: [`penetration`] runs until they
//! meet, [`depth_within`] only until they settle a window. Sampling asks only whether the signed
//! distance lies between the extremes seen so far, and the bracket usually answers that after a few
//! steps.

use crate::math::Vec3;
use parry3d_f64::query::gjk::CsoPoint;

/// Most vertices of the polytope that brackets a depth for a window: the start tetrahedron and one per
/// step.
const BRACKET_VERTICES: usize = 28;
/// Most vertices of the polytope of an exact depth.
const EXACT_VERTICES: usize = 160;
/// How far apart the bounds of an exact depth may be, in metres.
const EXACT_GAP: f64 = 1e-10;
/// How far (metres) from a face's plane a point counts as on it. GJK often stops with the origin on a
/// face of its tetrahedron, and such faces survive as EPA grows; a new point on the plane of a face
/// (the CSO of two boxes has large flat faces) must not replace it, or the fan over its horizon could
/// fold back.
const ON_FACE: f64 = 1e-12;

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
    const EMPTY: Face = Face {
        v: [0; 3],
        normal: Vec3::ZERO,
        dist: 0.0,
        alive: false,
    };

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

/// The polytope, with room for `V` vertices and `F` faces (a closed triangulation of `V` vertices has
/// `2V - 4`; the faces that see a new point are dropped before its fan is added). Each vertex keeps
/// the point of `a` it came from, for the witness points.
struct Polytope<const V: usize, const F: usize> {
    points: [Vec3; V],
    of_a: [Vec3; V],
    n_points: usize,
    faces: [Face; F],
    n_faces: usize,
}

impl<const V: usize, const F: usize> Polytope<V, F> {
    /// The tetrahedron of four CSO points around the origin, or `None` when it is degenerate.
    fn new(tetrahedron: &[CsoPoint; 4]) -> Option<Self> {
        let mut poly = Polytope {
            points: [Vec3::ZERO; V],
            of_a: [Vec3::ZERO; V],
            n_points: 4,
            faces: [Face::EMPTY; F],
            n_faces: 0,
        };
        for (k, p) in tetrahedron.iter().enumerate() {
            poly.points[k] = p.point;
            poly.of_a[k] = p.orig1;
        }
        for (tri, other) in [
            ([0, 1, 2], 3),
            ([0, 1, 3], 2),
            ([0, 2, 3], 1),
            ([1, 2, 3], 0),
        ] {
            let mut face = Face::new(&poly.points, tri)?;
            if face
                .normal
                .dot(poly.points[other] - poly.points[tri[0] as usize])
                > 0.0
            {
                face = Face::new(&poly.points, [tri[0], tri[2], tri[1]])?;
            }
            poly.faces[poly.n_faces] = face;
            poly.n_faces += 1;
        }
        Some(poly)
    }

    /// The face nearest the origin (all faces are alive between steps), or `None` when the origin
    /// lies outside the polytope by more than rounding, where its bounds would not hold. A face the
    /// origin lies on bounds nothing, but EPA grows past it like any other.
    fn nearest(&self) -> Option<Face> {
        let nearest = self.faces[..self.n_faces]
            .iter()
            .min_by(|x, y| x.dist.total_cmp(&y.dist))
            .copied()?;
        (nearest.dist >= -ON_FACE).then_some(nearest)
    }

    /// Adds the point `w`, replacing the faces that see it by a fan from it over their horizon; `false`
    /// when there is no room or a face degenerates.
    fn add(&mut self, w: &CsoPoint) -> bool {
        if self.n_points == V {
            return false;
        }
        let new = self.n_points as u8;
        self.points[self.n_points] = w.point;
        self.of_a[self.n_points] = w.orig1;
        self.n_points += 1;
        let mut horizon = [[0u8; 2]; V];
        let mut n_horizon = 0;
        for f in self.faces[..self.n_faces].iter_mut() {
            if f.alive && f.normal.dot(w.point) - f.dist > ON_FACE {
                f.alive = false;
                for e in [[f.v[0], f.v[1]], [f.v[1], f.v[2]], [f.v[2], f.v[0]]] {
                    // An edge shared by two removed faces appears once each way: both go.
                    if let Some(k) = horizon[..n_horizon].iter().position(|h| *h == [e[1], e[0]]) {
                        horizon[k] = horizon[n_horizon - 1];
                        n_horizon -= 1;
                    } else if n_horizon < V {
                        horizon[n_horizon] = e;
                        n_horizon += 1;
                    } else {
                        return false;
                    }
                }
            }
        }
        let mut kept = 0;
        for k in 0..self.n_faces {
            if self.faces[k].alive {
                self.faces[kept] = self.faces[k];
                kept += 1;
            }
        }
        self.n_faces = kept;
        if n_horizon < 3 || self.n_faces + n_horizon > F {
            return false;
        }
        for e in &horizon[..n_horizon] {
            let Some(face) = Face::new(&self.points, [e[0], e[1], new]) else {
                return false;
            };
            self.faces[self.n_faces] = face;
            self.n_faces += 1;
        }
        true
    }

    /// The point of `a` (frame of `a`) under the origin's projection onto `face`.
    fn point_of_a(&self, face: &Face) -> Vec3 {
        let [x, y, z] = face.v.map(|i| self.points[i as usize]);
        let p = face.normal * face.dist;
        // Barycentric coordinates (Ericson 3.4), clamped: the projection lies on the nearest face up
        // to rounding.
        let (v0, v1, v2) = (y - x, z - x, p - x);
        let (d00, d01, d11) = (v0.dot(v0), v0.dot(v1), v1.dot(v1));
        let (d20, d21) = (v2.dot(v0), v2.dot(v1));
        let denom = d00 * d11 - d01 * d01;
        let (v, w) = if denom > 0.0 {
            (
                ((d11 * d20 - d01 * d21) / denom).max(0.0),
                ((d00 * d21 - d01 * d20) / denom).max(0.0),
            )
        } else {
            (0.0, 0.0)
        };
        let u = (1.0 - v - w).max(0.0);
        let [ax, ay, az] = face.v.map(|i| self.of_a[i as usize]);
        (ax * u + ay * v + az * w) / (u + v + w)
    }
}

/// A tetrahedron of CSO points holding the origin (inside, or on its boundary), from GJK's last
/// simplex `simplex` (which holds the origin): that simplex when it is a tetrahedron; a triangle or
/// segment grows by the CSO's farthest points off its plane or line. `None` for a single point (the
/// origin is then a point of the CSO's boundary: the shapes touch) or a flat CSO.
fn tetrahedron(
    simplex: &[CsoPoint],
    support: &mut impl FnMut(Vec3) -> CsoPoint,
) -> Option<[CsoPoint; 4]> {
    // The farthest point along `dir` or `-dir`, whichever lies farther off the origin's plane.
    let mut off = |dir: Vec3| {
        let (p, q) = (support(dir), support(-dir));
        if dir.dot(p.point) >= -dir.dot(q.point) {
            p
        } else {
            q
        }
    };
    match *simplex {
        [p, q, r, s] => Some([p, q, r, s]),
        [p, q, r] => {
            let normal = (q.point - p.point)
                .cross(r.point - p.point)
                .try_normalize()?;
            Some([p, q, r, off(normal)])
        }
        [p, q] => {
            let line = (q.point - p.point).try_normalize()?;
            let across = line.any_orthonormal_vector();
            let r = off(across);
            let normal = line.cross(r.point - p.point).try_normalize()?;
            Some([p, q, r, off(normal)])
        }
        _ => None,
    }
}

/// Two overlapping shapes' penetration, in the frame of `a`.
#[derive(Debug, Clone, Copy)]
pub struct Penetration {
    /// The penetration depth (at most [`EXACT_GAP`] above the exact one).
    pub depth: f64,
    /// The direction, from `a` towards `b`, along which translating `b` by `depth` separates them.
    pub normal: Vec3,
    /// The deepest point of `a` inside `b`.
    pub point_a: Vec3,
    /// The deepest point of `b` inside `a` (`point_a` less `depth` along `normal`).
    pub point_b: Vec3,
}

/// The exact penetration of two overlapping shapes, given the CSO's support function `support(dir)`
/// (the point of `a - b` farthest along the unit vector `dir`) and GJK's last simplex, which holds the
/// origin: EPA steps until the CSO's least extent seen and the polytope's nearest face are within
/// [`EXACT_GAP`]. `None` when the simplex is a single point, or the polytope degenerates or outgrows
/// its room first.
pub fn penetration(
    simplex: &[CsoPoint],
    mut support: impl FnMut(Vec3) -> CsoPoint,
) -> Option<Penetration> {
    let start = tetrahedron(simplex, &mut support)?;
    let mut poly = Polytope::<EXACT_VERTICES, { 2 * EXACT_VERTICES - 4 }>::new(&start)?;
    // The least extent seen, and the face whose normal it was taken along.
    let mut best: Option<(f64, Face)> = None;
    loop {
        let nearest = poly.nearest()?;
        let w = support(nearest.normal);
        let extent = nearest.normal.dot(w.point);
        let (depth, face) = match best {
            Some((e, f)) if e <= extent => (e, f),
            _ => (extent, nearest),
        };
        best = Some((depth, face));
        if depth - nearest.dist <= EXACT_GAP {
            let point_a = poly.point_of_a(&face);
            return Some(Penetration {
                depth,
                normal: face.normal,
                point_a,
                point_b: point_a - face.normal * depth,
            });
        }
        if !poly.add(&w) {
            return None;
        }
    }
}

/// Brackets the signed distance of two overlapping shapes, given the CSO's support function
/// `support(dir)` (see [`penetration`]) and four CSO points whose tetrahedron holds the origin, until
/// the bracket lies strictly inside `(lo, hi)`: `true` when it does, `false` when it cannot (the
/// distance may lie outside, the polytope stopped growing, or it degenerated). `lower` is a lower
/// bound already known.
pub fn depth_within(
    tetrahedron: &[CsoPoint; 4],
    mut support: impl FnMut(Vec3) -> CsoPoint,
    lo: f64,
    hi: f64,
    mut lower: f64,
) -> bool {
    let Some(mut poly) =
        Polytope::<BRACKET_VERTICES, { 2 * BRACKET_VERTICES - 4 }>::new(tetrahedron)
    else {
        return false;
    };
    loop {
        let Some(nearest) = poly.nearest() else {
            return false;
        };
        // The shapes overlap (GJK found the origin in the tetrahedron), so the distance is at most 0.
        let upper = -nearest.dist.max(0.0);
        let w = support(nearest.normal);
        let extent = nearest.normal.dot(w.point);
        lower = lower.max(-extent);
        if lo < lower && upper < hi {
            return true;
        }
        if upper <= lo || lower >= hi || extent - nearest.dist <= 1e-12 * extent.abs().max(1e-3) {
            // Outside for sure, or converged without a decision: the exact query decides.
            return false;
        }
        if !poly.add(&w) {
            return false;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The CSO of two boxes (half extents `ha`, `hb`, axis-aligned, centres `ca`, `cb`): a box.
    fn box_support(c: Vec3, h: Vec3) -> impl Fn(Vec3) -> CsoPoint {
        move |d: Vec3| {
            CsoPoint::single_point(
                c + Vec3::new(h.x.copysign(d.x), h.y.copysign(d.y), h.z.copysign(d.z)),
            )
        }
    }

    /// Two axis-aligned boxes overlapping by 0.02 along x (less than along y and z): the CSO is the
    /// box of centre `ca - cb` and half extents `ha + hb`, and the signed distance is -0.02. Its
    /// support function, and a tetrahedron of its corners around the origin.
    fn two_boxes() -> (impl Fn(Vec3) -> CsoPoint, [CsoPoint; 4]) {
        let (ha, hb) = (Vec3::new(0.1, 0.2, 0.3), Vec3::new(0.05, 0.1, 0.1));
        let (ca, cb) = (Vec3::ZERO, Vec3::new(0.13, 0.01, -0.02));
        let (c, h) = (ca - cb, ha + hb);
        let corner = |x: f64, y: f64, z: f64| {
            CsoPoint::single_point(c + Vec3::new(x * h.x, y * h.y, z * h.z))
        };
        let tet = [
            corner(1.0, 1.0, 1.0),
            corner(1.0, -1.0, -1.0),
            corner(-1.0, 1.0, -1.0),
            corner(-1.0, -1.0, 1.0),
        ];
        (box_support(c, h), tet)
    }

    #[test]
    fn the_bracket_decides_only_windows_that_hold_the_depth() {
        let (support, tet) = two_boxes();
        // Windows around the exact value are decided; windows that miss it never are.
        for (lo, hi) in [
            (-0.03, -0.01),
            (-0.0201, -0.0199),
            (-1.0, 0.0),
            (-0.021, 1.0),
        ] {
            assert!(
                depth_within(&tet, &support, lo, hi, f64::NEG_INFINITY),
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
                !depth_within(&tet, &support, lo, hi, f64::NEG_INFINITY),
                "({lo}, {hi})"
            );
        }
    }

    /// The exact depth of the same two boxes: 0.02 along +x (from `a` towards `b`), from a GJK
    /// tetrahedron, triangle or segment through the origin, none of whose faces is the CSO's.
    #[test]
    fn the_exact_depth_of_two_boxes_is_their_least_overlap() {
        let (support, tet) = two_boxes();
        // A segment and a triangle of CSO points through the origin (every point within 0.02 of
        // the origin lies in the CSO).
        let (x, y) = (tet[0], tet[1]);
        let near = |p: Vec3| CsoPoint::single_point(-p.normalize() * 0.01);
        let segment = [x, near(x.point)];
        let triangle = [x, y, near(x.point + y.point)];
        for simplex in [&tet[..], &triangle[..], &segment[..]] {
            let p = penetration(simplex, &support).expect("a box CSO converges");
            assert!((p.depth - 0.02).abs() < 1e-12, "depth {}", p.depth);
            assert!(p.normal.distance(Vec3::X) < 1e-12, "normal {}", p.normal);
            assert!((p.point_a - p.point_b).length() - p.depth < 1e-12);
        }
    }
}
