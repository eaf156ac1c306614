//! Convex polyhedra: the exact convex hull of a point set and its simplification to a bounded
//! vertex count that still encloses it.
//!
//! The hull is parry's quickhull behind our own degeneracy checks, with its output validated;
//! when parry trips (it does on nearly coplanar points, e.g. f32 meshes with subdivided flat
//! sides) a quickhull with exact orientation predicates takes over.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use crate::math::{Vec3, bounds, is_finite};

mod exact;
mod simplify;

use exact::exact_hull;
pub(crate) use simplify::argmax;
pub use simplify::simplify_hull;

/// A closed convex triangle mesh whose faces wind counter-clockwise seen from outside.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvexMesh {
    /// The hull's vertices (every one is a corner of the hull).
    pub vertices: Vec<Vec3>,
    /// Triangles as indices into `vertices`, counter-clockwise seen from outside.
    pub faces: Vec<[u32; 3]>,
}

impl ConvexMesh {
    /// The three corners of face `f`, or `None` when one of its indices is out of range.
    fn triangle(&self, f: &[u32; 3]) -> Option<[Vec3; 3]> {
        let v = |i: u32| self.vertices.get(i as usize).copied();
        Some([v(f[0])?, v(f[1])?, v(f[2])?])
    }

    /// The plane of face `f` as (unit outward normal, offset), `None` for a sliver face.
    fn face_plane(&self, f: &[u32; 3]) -> Option<(Vec3, f64)> {
        let [a, b, c] = self.triangle(f)?;
        // Cross the two edges at the corner opposite the longest edge: the best-conditioned pair.
        let (la, lb, lc) = (
            (c - b).length_squared(),
            (a - c).length_squared(),
            (b - a).length_squared(),
        );
        let (o, e1, e2) = if la >= lb && la >= lc {
            (a, b - a, c - a)
        } else if lb >= lc {
            (b, c - b, a - b)
        } else {
            (c, a - c, b - c)
        };
        let n = e1.cross(e2);
        let len = n.length();
        // A sliver (angle below ~1e-12 rad) has no trustworthy normal; its neighbours bound it.
        if len.is_nan() || len <= 1e-12 * e1.length() * e2.length() {
            return None;
        }
        let n = n / len;
        Some((n, n.dot(o).max(n.dot(a)).max(n.dot(b)).max(n.dot(c))))
    }

    /// The enclosed volume (zero for an empty mesh).
    pub fn volume(&self) -> f64 {
        let o = self.centroid();
        let sum: f64 = (self.faces.iter().filter_map(|f| self.triangle(f)))
            .map(|[a, b, c]| (a - o).dot((b - o).cross(c - o)))
            .sum();
        sum / 6.0
    }

    /// The face planes as (unit outward normal `n`, offset `d`): inside means `n·x <= d`.
    pub fn planes(&self) -> Vec<(Vec3, f64)> {
        self.faces
            .iter()
            .filter_map(|f| self.face_plane(f))
            .collect()
    }

    /// Whether `p` lies inside the mesh or within `tol` of it (false for a mesh without faces).
    pub fn contains(&self, p: Vec3, tol: f64) -> bool {
        let planes = self.planes();
        !planes.is_empty() && planes.iter().all(|(n, d)| n.dot(p) <= d + tol)
    }

    /// The mean of the vertices (origin for an empty mesh), an interior point of a proper hull.
    pub fn centroid(&self) -> Vec3 {
        if self.vertices.is_empty() {
            return Vec3::ZERO;
        }
        self.vertices.iter().copied().sum::<Vec3>() / self.vertices.len() as f64
    }

    /// Every edge of the faces once, as its two corners (for outlines and edge-edge tests).
    pub fn edges(&self) -> Vec<(Vec3, Vec3)> {
        let mut e: Vec<(u32, u32)> = self
            .faces
            .iter()
            .flat_map(|f| [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])])
            .map(|(a, b)| (a.min(b), a.max(b)))
            .collect();
        e.sort_unstable();
        e.dedup();
        e.into_iter()
            .map(|(a, b)| (self.vertices[a as usize], self.vertices[b as usize]))
            .collect()
    }
}

/// Why a convex hull could not be built.
#[derive(Debug, thiserror::Error)]
pub enum HullError {
    /// Fewer than the four points a solid needs.
    #[error("a convex hull needs at least 4 points, got {0}")]
    TooFewPoints(usize),
    /// A coordinate is NaN or infinite.
    #[error("points contain NaN or infinite coordinates")]
    NonFinite,
    /// The points span no volume.
    #[error("degenerate point set: {0}")]
    Degenerate(&'static str),
    /// The hull algorithm itself failed.
    #[error("convex hull computation failed: {0}")]
    Failed(String),
}

/// Exact-bit key of a point (with `-0.0` folded onto `0.0`).
fn key(p: Vec3) -> [u64; 3] {
    p.to_array().map(|x| (x + 0.0).to_bits())
}

/// A small fast hasher for the integer keys used here (SipHash dominates otherwise).
#[derive(Default)]
struct KeyHasher(u64);

impl Hasher for KeyHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.0 = (self.0.rotate_left(23) ^ u64::from_le_bytes(word))
                .wrapping_mul(0x9E37_79B9_7F4A_7C15);
        }
    }
    fn finish(&self) -> u64 {
        let z = (self.0 ^ (self.0 >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z ^ (z >> 31)
    }
}

type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<KeyHasher>>;

/// The exact convex hull of `points`, with outward (counter-clockwise) faces and its vertices in
/// input order.
///
/// Fails on fewer than four points, non-finite coordinates, or points that are coincident,
/// collinear or coplanar within 1e-9 of the point set's size. Output is deterministic.
pub fn convex_hull(points: &[Vec3]) -> Result<ConvexMesh, HullError> {
    if !points.iter().all(|p| is_finite(*p)) {
        return Err(HullError::NonFinite);
    }
    let Some((lo, hi)) = bounds(points).filter(|_| points.len() >= 4) else {
        return Err(HullError::TooFewPoints(points.len()));
    };
    // Work in normalised coordinates (every |coordinate| <= 1): scale-free tests, no overflow.
    let (mid, half) = (lo * 0.5 + hi * 0.5, hi * 0.5 - lo * 0.5);
    let s = half.max_element();
    if s.is_nan() || s <= 0.0 {
        return Err(HullError::Degenerate("all points coincide"));
    }
    let q: Vec<Vec3> = points.iter().map(|p| (*p - mid) / s).collect();
    let axes = check_solid(&q, 1e-9 * (2.0 * half / s).length())?;
    // Parry's quickhull uses absolute tolerances that break on thin sets (a 1 mm plate of 1 m):
    // hand it an affine image stretched to unit extent along the thin axes found above. The
    // map has positive determinant, so hull vertices, faces and their winding carry over.
    let lo = axes.map(|e| q.iter().map(|p| e.dot(*p)).fold(f64::MAX, f64::min));
    let ext = axes.map(|e| q.iter().map(|p| e.dot(*p)).fold(f64::MIN, f64::max));
    let ext = [0, 1, 2].map(|i| ext[i] - lo[i]);
    let white = |p: Vec3| Vec3::from_array([0, 1, 2].map(|i| (axes[i].dot(p) - lo[i]) / ext[i]));
    let mut index: FastMap<[u64; 3], usize> = FastMap::default();
    let (mut w, mut src) = (Vec::new(), Vec::new());
    for (i, p) in q.iter().enumerate() {
        let x = white(*p);
        if let std::collections::hash_map::Entry::Vacant(slot) = index.entry(key(x)) {
            slot.insert(w.len());
            w.push(x);
            src.push(i);
        }
    }
    // Parry's quickhull still trips over nearly coplanar points (f32 meshes whose flat sides are
    // subdivided): its output is validated, and on failure the exact-predicate quickhull runs.
    let parry = parry_hull(&w).and_then(|f| checked(&w, f, 1e-9));
    let (ids, faces) = parry.or_else(|e| {
        let distinct: Vec<Vec3> = src.iter().map(|&i| points[i]).collect();
        exact_hull(&distinct)
            .and_then(|f| checked(&w, f, 1e-7))
            .map_err(|_| e)
    })?;
    let vertices = ids.iter().map(|&i| points[src[i]]).collect();
    Ok(ConvexMesh { vertices, faces })
}

/// Parry's quickhull of the distinct, unit-extent points `w`: its faces over indices into `w`.
fn parry_hull(w: &[Vec3]) -> Result<Vec<[u32; 3]>, HullError> {
    let index: FastMap<[u64; 3], u32> = (w.iter().enumerate())
        .map(|(i, p)| (key(*p), i as u32))
        .collect();
    let run = || parry3d_f64::transformation::try_convex_hull(w);
    let (hv, hf) = std::panic::catch_unwind(run)
        .map_err(|_| HullError::Failed("quickhull panicked".into()))?
        .map_err(|e| HullError::Failed(e.to_string()))?;
    let ids: Vec<u32> = (hv.iter().map(|v| index.get(&key(*v)).copied()))
        .collect::<Option<_>>()
        .ok_or_else(|| HullError::Failed("hull vertex not among the input".into()))?;
    (hf.iter().map(|f| f.map(|k| ids.get(k as usize).copied())))
        .map(|[a, b, c]| Some([a?, b?, c?]))
        .collect::<Option<_>>()
        .ok_or_else(|| HullError::Failed("bad face index".into()))
}

/// Validates `faces` (over indices into `w`, wound outward) to within `tol` and compacts them:
/// (the sorted vertex indices, the faces over positions in that list).
fn checked(
    w: &[Vec3],
    faces: Vec<[u32; 3]>,
    tol: f64,
) -> Result<(Vec<usize>, Vec<[u32; 3]>), HullError> {
    let mut ids: Vec<usize> = faces.iter().flatten().map(|&i| i as usize).collect();
    ids.sort_unstable();
    ids.dedup();
    let mut remap = vec![0_u32; w.len()];
    for (k, &i) in ids.iter().enumerate() {
        *remap
            .get_mut(i)
            .ok_or_else(|| HullError::Failed("bad vertex index".into()))? = k as u32;
    }
    // Every face index is in `ids`, each checked against `remap` (and `w`) just above.
    let faces = faces.iter().map(|f| f.map(|i| remap[i as usize])).collect();
    let mesh = ConvexMesh {
        vertices: ids.iter().map(|&i| w[i]).collect(),
        faces,
    };
    validate(&mesh, w, &ids, tol)?;
    Ok((ids, mesh.faces))
}

/// Checks (in the unit-extent frame) that `mesh` bounds a convex polyhedron: a closed, consistently
/// oriented sphere-like surface (F = 2V - 4, every edge once each way) that is convex at every
/// edge to within `tol`. Then spot-checks that it contains the input points (all of them unless
/// that would cost more than ~4e6 plane tests; vertices `ids` need no check).
fn validate(mesh: &ConvexMesh, w: &[Vec3], ids: &[usize], tol: f64) -> Result<(), HullError> {
    let fail = |m: &str| Err(HullError::Failed(format!("quickhull produced {m}")));
    let mut edges: FastMap<(u32, u32), usize> = FastMap::default();
    for (i, f) in mesh.faces.iter().enumerate() {
        if mesh.triangle(f).is_none() {
            return fail("a bad face index");
        }
        for k in 0..3 {
            if edges.insert((f[k], f[(k + 1) % 3]), i).is_some() {
                return fail("a non-manifold surface");
            }
        }
    }
    if mesh.faces.len() + 4 != 2 * mesh.vertices.len() {
        return fail("a surface that is not a closed sphere");
    }
    for f in &mesh.faces {
        let Some((n, d)) = mesh.face_plane(f) else {
            continue;
        };
        for k in 0..3 {
            let Some(&g) = edges.get(&(f[(k + 1) % 3], f[k])) else {
                return fail("an open surface");
            };
            // `edges` only holds indices of faces whose indices were all checked above.
            let apex = mesh.faces[g].iter().map(|&i| mesh.vertices[i as usize]);
            if apex.map(|v| n.dot(v) - d).fold(f64::MIN, f64::max) > tol {
                return fail("a non-convex surface");
            }
        }
    }
    let planes = mesh.planes();
    let mut on_hull = vec![false; w.len()];
    ids.iter().for_each(|&i| on_hull[i] = true);
    let rest: Vec<Vec3> = (w.iter().zip(on_hull))
        .filter(|(_, h)| !h)
        .map(|(p, _)| *p)
        .collect();
    let step = (rest.len() * planes.len() / 4_000_000).max(1);
    if !rest
        .iter()
        .step_by(step)
        .all(|p| planes.iter().all(|(n, d)| n.dot(*p) <= d + tol))
    {
        return fail("a hull that misses input points");
    }
    Ok(())
}

/// Rejects point sets (normalised) that are collinear or coplanar within `tol`; otherwise returns
/// a right-handed orthonormal frame whose axes follow the set's long, middle and thin directions.
fn check_solid(q: &[Vec3], tol: f64) -> Result<[Vec3; 3], HullError> {
    let far = |f: &dyn Fn(Vec3) -> f64| q.get(argmax(q, f)).copied().unwrap_or(Vec3::ZERO);
    let axis = Vec3::from_array([0, 1, 2].map(|k| far(&|p| p[k])[k] - far(&|p| -p[k])[k]));
    let axis = Vec3::AXES[axis.max_position()];
    let (a, b) = (far(&|p| -p.dot(axis)), far(&|p| p.dot(axis)));
    let u = (b - a).normalize_or_zero();
    let dist = |p: Vec3| (p - a).cross(u).length();
    let c = far(&dist);
    if dist(c) <= tol {
        return Err(HullError::Degenerate("points are collinear"));
    }
    let n = (b - a).cross(c - a).normalize_or_zero();
    let d = far(&|p| n.dot(p - a).abs());
    if n.dot(d - a).abs() <= tol {
        return Err(HullError::Degenerate("points are coplanar (flat mesh)"));
    }
    Ok([u, n.cross(u), n])
}
#[cfg(test)]
mod tests {
    use super::exact::side;
    use super::simplify::corner;
    use super::*;
    use std::f64::consts::TAU;

    use crate::shapes::test_rng::Rng;

    fn clouds() -> Vec<(&'static str, Vec<Vec3>)> {
        let mut r = Rng(7);
        let boxy = (0..500)
            .map(|_| r.v(-1.0, 1.0) * Vec3::new(0.5, 0.3, 0.1) + Vec3::X)
            .collect();
        let sphere = (0..2000)
            .map(|_| r.unit() * 0.2 + Vec3::new(0.1, -2.0, 0.3))
            .collect();
        let axis = Vec3::new(1.0, 2.0, 0.5).normalize();
        let (u, w) = axis.any_orthonormal_pair();
        let cyl = (0..1500)
            .map(|i| {
                let (a, t) = (TAU * r.f(), if i % 3 == 0 { (i % 2) as f64 } else { r.f() });
                (u * a.cos() + w * a.sin()) * 0.02 + axis * t
            })
            .collect();
        let ell = (0..800)
            .map(|i| match i % 2 {
                0 => r.v(0.0, 1.0) * Vec3::new(1.0, 0.2, 0.2),
                _ => r.v(0.0, 1.0) * Vec3::new(0.2, 1.0, 0.2),
            })
            .collect();
        vec![
            ("box", boxy),
            ("sphere", sphere),
            ("cylinder", cyl),
            ("L", ell),
        ]
    }

    #[test]
    fn errors() {
        let e = |pts: &[Vec3]| convex_hull(pts).unwrap_err();
        assert!(matches!(e(&[]), HullError::TooFewPoints(0)));
        assert!(matches!(e(&[Vec3::X]), HullError::TooFewPoints(1)));
        assert!(matches!(e(&[Vec3::X, Vec3::Y]), HullError::TooFewPoints(2)));
        assert!(matches!(
            e(&[Vec3::ONE; 6]),
            HullError::Degenerate("all points coincide")
        ));
        let line: Vec<Vec3> = (0..10)
            .map(|i| Vec3::new(1.0, 2.0, 3.0) * i as f64)
            .collect();
        assert!(matches!(
            e(&line),
            HullError::Degenerate("points are collinear")
        ));
        let mut r = Rng(1);
        let (u, w) = Vec3::new(1.0, -1.0, 0.3).normalize().any_orthonormal_pair();
        let plane: Vec<Vec3> = (0..50).map(|_| u * r.f() + w * r.f() + Vec3::Z).collect();
        assert!(matches!(
            e(&plane),
            HullError::Degenerate("points are coplanar (flat mesh)")
        ));
        let mut nan = plane.clone();
        nan[3].y = f64::NAN;
        assert!(matches!(e(&nan), HullError::NonFinite));
        assert!(e(&nan).to_string().contains("NaN"));
        // A thin but solid slab is not degenerate.
        let slab: Vec<Vec3> = (0..50)
            .map(|i| u * r.f() + w * r.f() + u.cross(w) * 1e-6 * (i % 2) as f64)
            .collect();
        assert!(convex_hull(&slab).is_ok());
    }

    #[test]
    fn cube_hull() {
        let mut pts: Vec<Vec3> = (0..8)
            .map(|i| Vec3::new((i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2) as f64))
            .collect();
        let mut r = Rng(3);
        pts.extend((0..100).map(|_| r.v(0.0, 1.0)));
        pts.extend((0..100).map(|_| Vec3::new(r.f(), r.f(), 1.0))); // coplanar with a face
        let h = convex_hull(&pts).unwrap();
        assert_eq!(h.vertices.len(), 8);
        assert_eq!(h.faces.len(), 12);
        assert!((h.volume() - 1.0).abs() < 1e-12);
        assert!(pts.iter().all(|p| h.contains(*p, 1e-12)));
        assert!(!h.contains(Vec3::new(0.5, 0.5, 1.01), 1e-3));
        assert!(h.planes().iter().all(|(n, d)| n.dot(h.centroid()) < *d));
        // A triangulated cube: 12 edges and one diagonal per face, each once.
        let edges = h.edges();
        assert_eq!(edges.len(), 18);
        assert!(edges.iter().all(|(a, b)| a.distance(*b) >= 1.0 - 1e-12));
    }

    #[test]
    fn clouds_hull_contains_and_is_deterministic() {
        for (name, pts) in clouds() {
            let h = convex_hull(&pts).unwrap();
            // Tiny faces' planes carry ~1e-10 of rounding at 1 m, hence the 1e-9 tolerance.
            assert!(pts.iter().all(|p| h.contains(*p, 1e-9)), "{name}");
            assert!(
                h.planes().iter().all(|(n, d)| n.dot(h.centroid()) < *d),
                "{name}"
            );
            assert!(h.volume() > 0.0);
            assert_eq!(h, convex_hull(&pts).unwrap());
        }
        // A grid has many coplanar points: a classic quickhull trap.
        let grid: Vec<Vec3> = (0..1000)
            .map(|i| Vec3::new((i % 10) as f64, (i / 10 % 10) as f64, (i / 100) as f64))
            .collect();
        let h = convex_hull(&grid).unwrap();
        assert!((h.volume() - 729.0).abs() < 1e-9);
        assert!(grid.iter().all(|p| h.contains(*p, 1e-9)));
    }

    #[test]
    fn exact_predicate() {
        let (a, b, c) = (
            Vec3::new(0.1, 0.2, 0.5),
            Vec3::new(0.7, 0.3, 0.5),
            Vec3::new(0.3, 0.9, 0.5),
        );
        let d = Vec3::new(1e3 + 0.1, -7.3, 0.5);
        assert_eq!(side(a, b, c, d), 0.0);
        assert_eq!(side(a, b, c, d + Vec3::Z * 1e-13), 1.0);
        assert_eq!(side(a, b, c, Vec3::new(d.x, d.y, 0.5f64.next_down())), -1.0);
        // Nearly collinear far-off points, where the floating-point value has the wrong sign.
        let e = Vec3::new(0.5, 0.5, 0.5);
        let f = Vec3::new(12.0, 12.0, 12.0);
        assert_eq!(side(e, f, Vec3::new(24.0, 24.0, 24.0), Vec3::X), 0.0);
    }

    #[test]
    fn exact_hull_keeps_only_corners() {
        let mut pts: Vec<Vec3> = (0..8)
            .map(|i| corner(i) * Vec3::new(0.6, 0.2, 0.1))
            .collect();
        let mut r = Rng(4);
        pts.extend((0..300).map(|i| corner(i % 8) * Vec3::new(0.6, 0.2, 0.1) * r.f()));
        pts.extend((0..200).map(|i| Vec3::new(r.f() * 0.6, r.f() * 0.2, (i % 2) as f64 * 0.1)));
        let (ids, faces) = checked(&pts, exact_hull(&pts).unwrap(), 1e-12).unwrap();
        assert_eq!((ids, faces.len()), ((0..8).collect(), 12));
    }

    #[test]
    fn f32_subdivided_boxes() {
        // Flat sides tessellated into many nearly coplanar f32-rounded points: parry's quickhull
        // fails on some of these; the exact fallback must always deliver.
        let f32r = |p: Vec3| Vec3::from_array(p.to_array().map(|x| x as f32 as f64));
        let turn =
            crate::math::Rotation::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        for (scale, off) in [
            (0.01, Vec3::ZERO),
            (0.05, Vec3::new(0.3, -0.2, 0.5)),
            (1.0, Vec3::new(10.0, 0.0, 0.0)),
        ] {
            for k in [3, 5, 10, 20] {
                let grid = (0..=k)
                    .flat_map(|i| (0..=k).flat_map(move |j| (0..=k).map(move |l| [i, j, l])));
                let pts: Vec<Vec3> = grid
                    .filter(|c| c.iter().any(|&x| x == 0 || x == k))
                    .map(|c| {
                        Vec3::from_array(c.map(|x| x as f64 / k as f64)) * Vec3::new(0.6, 0.2, 0.1)
                    })
                    .map(|p| f32r(turn * p * scale + off))
                    .collect();
                let h = convex_hull(&pts).unwrap();
                assert!(
                    pts.iter().all(|p| h.contains(*p, 1e-9 * scale)),
                    "{scale} {k}"
                );
                assert!(
                    (h.volume() / (0.012 * scale.powi(3)) - 1.0).abs() < 1e-4,
                    "{scale} {k}"
                );
            }
        }
    }

    #[test]
    fn simplify_contains_everything() {
        for (name, pts) in clouds() {
            let h = convex_hull(&pts).unwrap();
            for max in [4, 8, 20, 64, 128] {
                let t = std::time::Instant::now();
                let s = simplify_hull(&h, max);
                let ratio = s.volume() / h.volume();
                println!(
                    "{name} max {max}: {} -> {} vertices, ratio {ratio:.4}, {:?}",
                    h.vertices.len(),
                    s.vertices.len(),
                    t.elapsed()
                );
                assert!(s.vertices.len() <= max, "{name} {max}");
                assert!(pts.iter().all(|p| s.contains(*p, 1e-9)), "{name} {max}");
                assert!(ratio >= 1.0 - 1e-9);
            }
        }
    }

    #[test]
    fn simplify_sphere_is_tight() {
        let mut r = Rng(11);
        let pts: Vec<Vec3> = (0..2000).map(|_| r.unit()).collect();
        let h = convex_hull(&pts).unwrap();
        let t = std::time::Instant::now();
        let s = simplify_hull(&h, 128);
        let ratio = s.volume() / h.volume();
        println!(
            "sphere 2000: {} vertices, volume ratio {ratio:.4}, {:?}",
            s.vertices.len(),
            t.elapsed()
        );
        assert!(s.vertices.len() <= 128);
        assert!(pts.iter().all(|p| s.contains(*p, 0.0)));
        assert!(ratio < 1.05, "ratio {ratio}");
        assert_eq!(s, simplify_hull(&h, 128));
        assert_eq!(simplify_hull(&s, 128), s);
    }
}
