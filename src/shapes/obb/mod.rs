//! Tight oriented bounding boxes: face-aligned minimum-area rectangles (rotating calipers) and PCA
//! frames as candidates, the best refined by a shrinking-step rotation search.

use std::collections::HashMap;

use super::hull::{ConvexMesh, convex_hull};
use crate::math::{Mat3, Rotation, Vec3, bounds, is_finite};

/// An oriented box: `center` plus up to `half_extents[k]` along each axis `k` (the columns of
/// `rotation`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Obb {
    /// The box centre.
    pub center: Vec3,
    /// The box orientation: its columns are the box axes.
    pub rotation: Rotation,
    /// Half the box size along each of its axes.
    pub half_extents: Vec3,
}

impl Obb {
    /// The enclosed volume.
    pub fn volume(&self) -> f64 {
        8.0 * self.half_extents.x * self.half_extents.y * self.half_extents.z
    }

    /// The three unit box axes (the columns of the rotation).
    pub fn axes(&self) -> [Vec3; 3] {
        [
            self.rotation * Vec3::X,
            self.rotation * Vec3::Y,
            self.rotation * Vec3::Z,
        ]
    }

    /// Whether `p` lies inside the box or within `tol` of it.
    pub fn contains(&self, p: Vec3, tol: f64) -> bool {
        let d = p - self.center;
        let h = self.half_extents.to_array();
        self.axes()
            .iter()
            .zip(h)
            .all(|(a, h)| a.dot(d).abs() <= h + tol)
    }

    /// The eight corners; corner `i` takes the + side of axis `k` when bit `k` of `i` is set.
    pub fn corners(&self) -> [Vec3; 8] {
        let [a, b, c] = self.axes();
        let h = self.half_extents;
        let sign = |i: usize, k: usize| if i >> k & 1 == 1 { 1.0 } else { -1.0 };
        std::array::from_fn(|i| {
            self.center + a * (h.x * sign(i, 0)) + b * (h.y * sign(i, 1)) + c * (h.z * sign(i, 2))
        })
    }
}

/// An orthonormal right-handed frame (the candidate box axes).
type Frame = [Vec3; 3];

/// How many face directions (by total area) get a minimum-area-rectangle candidate.
const MAX_FACE_DIRS: usize = 150;
/// How many of the best candidates get refined by the rotation search.
const REFINED: usize = 4;

/// A tight, near minimum-volume oriented box around the vertices of `hull`.
///
/// Candidates: the world axes, the PCA frames of the vertices and of the surface, and for each of
/// the (up to 150, by total area) distinct face directions the minimum-area rectangle of the
/// vertices projected along it. The best four are refined by a hill-climb over small rotations that
/// only accepts smaller volumes. The result contains every finite vertex, has a proper rotation and
/// among the box's 24 equivalent orientations the one closest to the identity.
pub fn tight_obb(hull: &ConvexMesh) -> Obb {
    let pts: Vec<Vec3> = hull
        .vertices
        .iter()
        .copied()
        .filter(|p| is_finite(*p))
        .collect();
    let Some((lo, hi)) = bounds(&pts) else {
        return Obb {
            center: Vec3::ZERO,
            rotation: Rotation::IDENTITY,
            half_extents: Vec3::ZERO,
        };
    };
    // A bare point list gets its hull built (its vertices then stand for all the points).
    let rebuilt = if hull.faces.is_empty() {
        convex_hull(&pts).ok()
    } else {
        None
    };
    let (mesh, pts) = match &rebuilt {
        Some(h) => (h, h.vertices.clone()),
        None => (hull, pts),
    };
    // Work relative to the bounding-box centre for precision.
    let origin = lo * 0.5 + hi * 0.5;
    let rel: Vec<Vec3> = pts.iter().map(|p| *p - origin).collect();
    let mut frames: Vec<Frame> = vec![[Vec3::X, Vec3::Y, Vec3::Z], pca_frame(&rel)];
    frames.extend(surface_frame(mesh, origin));
    let outline = Outline::new(mesh, pts.len());
    let dirs = face_directions(mesh);
    frames.extend(
        dirs.into_iter()
            .filter_map(|n| caliper_frame(&outline.points(&rel, n), n)),
    );
    let mut scored: Vec<(f64, Frame)> = frames
        .into_iter()
        .map(|f| (box_volume(&rel, &f), f))
        .collect();
    scored.sort_by(|a, b| a.0.total_cmp(&b.0));
    let size = (hi - lo).length();
    // Refine the best few distinct frames (same axes up to order and sign count as one).
    let same = |f: &Frame, g: &Frame| {
        f.iter()
            .all(|a| g.iter().any(|b| a.dot(*b).abs() > 1.0 - 1e-8))
    };
    let mut picked: Vec<(f64, Frame)> = Vec::new();
    for &(v, f) in &scored {
        if picked.len() < REFINED && !picked.iter().any(|(_, g)| same(&f, g)) {
            picked.push((v, f));
        }
    }
    let best = (picked.into_iter())
        .map(|(v, f)| refine(&rel, f, v, size))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map_or([Vec3::X, Vec3::Y, Vec3::Z], |b| b.1);
    fit(&pts, canonical(best), size)
}

/// The min and max of the points' coordinates along each axis of `f`.
fn extents(pts: &[Vec3], f: &Frame) -> (Vec3, Vec3) {
    let init = (Vec3::splat(f64::MAX), Vec3::splat(f64::MIN));
    pts.iter().fold(init, |(lo, hi), p| {
        let q = Vec3::new(f[0].dot(*p), f[1].dot(*p), f[2].dot(*p));
        (lo.min(q), hi.max(q))
    })
}

/// The volume of the box of `pts` aligned with `f`.
fn box_volume(pts: &[Vec3], f: &Frame) -> f64 {
    let (lo, hi) = extents(pts, f);
    (hi - lo).max(Vec3::ZERO).element_product()
}

/// The eigenvectors (as a right-handed frame) of a symmetric 3x3 matrix, by cyclic Jacobi.
fn eigen_frame(m: Mat3) -> Frame {
    let mut a = m.to_cols_array_2d();
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let scale: f64 = a.iter().flatten().map(|x| x * x).sum();
    for _ in 0..50 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        if off.is_nan() || off <= 1e-30 * scale {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let (c, s) = (1.0 / (t * t + 1.0).sqrt(), t / (t * t + 1.0).sqrt());
            // a <- Jᵀ a J and v <- v J, with J the rotation in the (p, q) plane.
            for row in &mut a {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            a[p] = std::array::from_fn(|k| c * rp[k] - s * rq[k]);
            a[q] = std::array::from_fn(|k| s * rp[k] + c * rq[k]);
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let col = |k: usize| Vec3::new(v[0][k], v[1][k], v[2][k]);
    orthonormal(col(0), col(1))
}

/// The right-handed orthonormal frame whose first axis is `a` and second lies in the `(a, b)`
/// plane (the world axes when that is undefined).
fn orthonormal(a: Vec3, b: Vec3) -> Frame {
    let Some(x) = a.try_normalize() else {
        return [Vec3::X, Vec3::Y, Vec3::Z];
    };
    let y = (b - x * x.dot(b))
        .try_normalize()
        .unwrap_or_else(|| x.any_orthonormal_vector());
    [x, y, x.cross(y)]
}

/// The PCA frame of the vertex cloud (relative coordinates).
fn pca_frame(rel: &[Vec3]) -> Frame {
    let n = rel.len().max(1) as f64;
    let mean = rel.iter().copied().sum::<Vec3>() / n;
    let mut cov = Mat3::ZERO;
    for p in rel {
        let d = *p - mean;
        cov += Mat3::from_cols(d * d.x, d * d.y, d * d.z);
    }
    eigen_frame(cov / n)
}

/// The PCA frame of the hull surface (area-weighted triangle covariance), if it has area.
fn surface_frame(mesh: &ConvexMesh, origin: Vec3) -> Option<Frame> {
    let (mut area, mut first, mut second) = (0.0, Vec3::ZERO, Mat3::ZERO);
    let outer = |a: Vec3, b: Vec3| Mat3::from_cols(a * b.x, a * b.y, a * b.z);
    for f in &mesh.faces {
        let v = f.map(|i| mesh.vertices.get(i as usize).map(|p| *p - origin));
        let [Some(a), Some(b), Some(c)] = v else {
            continue;
        };
        let w = (b - a).cross(c - a).length() / 2.0;
        if !w.is_finite() || w <= 0.0 {
            continue;
        }
        let m = (a + b + c) / 3.0;
        area += w;
        first += m * w;
        second += (outer(a, a) + outer(b, b) + outer(c, c) + outer(m, m) * 9.0) * (w / 12.0);
    }
    (area > 0.0).then(|| {
        let mean = first / area;
        eigen_frame(second / area - outer(mean, mean))
    })
}

/// Up to `MAX_FACE_DIRS` distinct face normals (sign-canonical), largest total area first.
fn face_directions(mesh: &ConvexMesh) -> Vec<Vec3> {
    // Bucket normals on a ~1e-3 grid; each bucket keeps its area-weighted normal sum.
    let mut buckets: HashMap<[i64; 3], (Vec3, f64, usize)> = HashMap::new();
    for (i, f) in mesh.faces.iter().enumerate() {
        let v = f.map(|i| mesh.vertices.get(i as usize).copied());
        let [Some(a), Some(b), Some(c)] = v else {
            continue;
        };
        let cr = (b - a).cross(c - a);
        let Some(n) = cr.try_normalize() else {
            continue;
        };
        let n = if n[n.abs().max_position()] < 0.0 {
            -n
        } else {
            n
        };
        let key = n.to_array().map(|x| (x * 1e3).round() as i64);
        let e = buckets.entry(key).or_insert((Vec3::ZERO, 0.0, i));
        e.0 += n * cr.length();
        e.1 += cr.length();
    }
    let mut dirs: Vec<(Vec3, f64, usize)> = buckets.into_values().collect();
    // Largest area first; ties by first face index, so the order is deterministic.
    dirs.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.2.cmp(&b.2)));
    let mut out: Vec<Vec3> = Vec::new();
    for (sum, _, _) in dirs {
        let Some(n) = sum.try_normalize() else {
            continue;
        };
        if out.len() < MAX_FACE_DIRS && out.iter().all(|m| m.dot(n).abs() < 1.0 - 1e-9) {
            out.push(n);
        }
    }
    out
}

/// Face normals and edge-adjacency of a hull, to find the vertices on the outline of its
/// projection along a direction (those on an edge between a front- and a back-facing face).
struct Outline {
    /// Unit normal per face (zero for slivers and bad faces).
    normals: Vec<Vec3>,
    /// Per edge: its two vertices and its faces (`usize::MAX` when it has only one).
    edges: Vec<(u32, u32, usize, usize)>,
    /// Whether the topology is usable (closed, every edge with two faces).
    ok: bool,
}

impl Outline {
    fn new(mesh: &ConvexMesh, n_points: usize) -> Outline {
        let normals: Vec<Vec3> = (mesh.faces.iter())
            .map(|f| {
                let v = f.map(|i| mesh.vertices.get(i as usize).copied());
                let [Some(a), Some(b), Some(c)] = v else {
                    return Vec3::ZERO;
                };
                (b - a).cross(c - a).normalize_or_zero()
            })
            .collect();
        let mut map: HashMap<(u32, u32), usize> = HashMap::new();
        let mut edges: Vec<(u32, u32, usize, usize)> = Vec::new();
        let mut ok = mesh.vertices.len() == n_points && !mesh.faces.is_empty();
        for (fi, f) in mesh.faces.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (f[k].min(f[(k + 1) % 3]), f[k].max(f[(k + 1) % 3]));
                match map.get(&(a, b)) {
                    Some(&e) if edges[e].3 == usize::MAX => edges[e].3 = fi,
                    Some(_) => ok = false,
                    None => {
                        map.insert((a, b), edges.len());
                        edges.push((a, b, fi, usize::MAX));
                    }
                }
            }
        }
        ok &= edges
            .iter()
            .all(|e| e.3 != usize::MAX && (e.0 as usize) < n_points && (e.1 as usize) < n_points);
        Outline { normals, edges, ok }
    }

    /// The 2-D-hull candidates of `rel` projected along `n`: the outline vertices, or all points
    /// when the topology is unusable.
    fn points<'a>(&self, rel: &'a [Vec3], n: Vec3) -> std::borrow::Cow<'a, [Vec3]> {
        if !self.ok {
            return rel.into();
        }
        let side: Vec<f64> = self.normals.iter().map(|m| m.dot(n)).collect();
        let mut keep = vec![false; rel.len()];
        for &(a, b, f, g) in &self.edges {
            // Faces within ~1e-9 of edge-on count as both front and back (a superset is harmless).
            // `ok` vouches for the indices: faces < normals.len(), vertices < rel.len().
            let (sf, sg) = (side[f], side[g]);
            if sf.min(sg) <= 1e-9 && sf.max(sg) >= -1e-9 {
                keep[a as usize] = true;
                keep[b as usize] = true;
            }
        }
        rel.iter()
            .zip(keep)
            .filter(|(_, k)| *k)
            .map(|(p, _)| *p)
            .collect::<Vec<_>>()
            .into()
    }
}

/// The frame of the minimum-area rectangle of the points projected along `n` (rotating calipers
/// over their 2-D convex hull), with `n` as third axis.
fn caliper_frame(rel: &[Vec3], n: Vec3) -> Option<Frame> {
    let (u, w) = n.any_orthonormal_pair();
    let poly = hull_2d(rel.iter().map(|p| [u.dot(*p), w.dot(*p)]).collect());
    let h = poly.len();
    if h < 3 {
        return None;
    }
    // Indices here stay below 2h: wrap them without a division.
    let at = |k: usize| poly[if k >= h { k - h } else { k }];
    let dot = |d: [f64; 2], k: usize| d[0] * at(k)[0] + d[1] * at(k)[1];
    let argmax = |d: [f64; 2]| {
        (0..h)
            .max_by(|&a, &b| dot(d, a).total_cmp(&dot(d, b)))
            .unwrap_or(0)
    };
    let (mut best, mut best_dir) = (f64::INFINITY, [1.0, 0.0]);
    let (mut hi, mut lo, mut top) = (0, 0, 0);
    for i in 0..h {
        let (p, q) = (poly[i], poly[(i + 1) % h]);
        let len = (q[0] - p[0]).hypot(q[1] - p[1]);
        if len.is_nan() || len <= 0.0 {
            continue;
        }
        let e = [(q[0] - p[0]) / len, (q[1] - p[1]) / len];
        let (ne, nn) = ([-e[0], -e[1]], [-e[1], e[0]]);
        if i == 0 || best.is_infinite() {
            (hi, lo, top) = (argmax(e), argmax(ne), argmax(nn));
        }
        // The extreme vertices only move forward (counter-clockwise) as the edge turns.
        for (ptr, d) in [(&mut hi, e), (&mut lo, ne), (&mut top, nn)] {
            for _ in 0..h {
                if dot(d, *ptr + 1) < dot(d, *ptr) {
                    break;
                }
                *ptr = (*ptr + 1) % h;
            }
        }
        let area = (dot(e, hi) + dot(ne, lo)) * (dot(nn, top) - dot(nn, i));
        if area < best {
            (best, best_dir) = (area, e);
        }
    }
    best.is_finite().then(|| {
        orthonormal(
            u * best_dir[0] + w * best_dir[1],
            n.cross(u * best_dir[0] + w * best_dir[1]),
        )
    })
}

/// The convex hull of 2-D points, counter-clockwise without collinear points (monotone chain).
fn hull_2d(mut p: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    p.sort_unstable_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let chain = |pts: &mut dyn Iterator<Item = [f64; 2]>| {
        let mut out: Vec<[f64; 2]> = Vec::new();
        for q in pts {
            while out.len() >= 2 && cross(out[out.len() - 2], out[out.len() - 1], q) <= 0.0 {
                out.pop();
            }
            out.push(q);
        }
        out.pop();
        out
    };
    let mut lower = chain(&mut p.iter().copied());
    lower.extend(chain(&mut p.iter().rev().copied()));
    lower
}

/// Hill-climbs over rotations of `f` about its own axes by a shrinking step, accepting only
/// smaller volumes. Evaluates on the points that can still become extreme within the next few
/// moves (refiltered as the frame turns), so each step is cheap; the returned volume is exact.
fn refine(rel: &[Vec3], mut f: Frame, mut vol: f64, size: f64) -> (f64, Frame) {
    const MOVES: usize = 6;
    let mut step = 0.02;
    // Hard cap on rounds: the search always ends, even on pathological volume plateaus.
    for _ in 0..500 {
        if step < 1e-7 {
            break;
        }
        // Any MOVES rotations of `step` move a point's coordinate by at most MOVES·step·size.
        let margin = 2.0 * MOVES as f64 * step * size;
        let (lo, hi) = extents(rel, &f);
        let near = |p: &&Vec3| {
            (0..3).any(|k| {
                let x = f[k].dot(**p);
                x - lo[k] <= margin || hi[k] - x <= margin
            })
        };
        let sub: Vec<Vec3> = rel.iter().filter(near).copied().collect();
        let mut moved = false;
        for _ in 0..MOVES {
            let turned = (0..6).map(|m| {
                let r = Rotation::from_axis_angle(f[m / 2], if m % 2 == 0 { step } else { -step });
                let g = orthonormal(r * f[0], r * f[1]);
                (box_volume(&sub, &g), g)
            });
            let Some((v, g)) = turned.min_by(|a, b| a.0.total_cmp(&b.0)) else {
                break;
            };
            if v < vol * (1.0 - 1e-12) {
                (vol, f, moved) = (v, g, true);
            } else {
                break;
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    (box_volume(rel, &f), f)
}

/// Among the 24 relabellings of the box axes (permutations and signs with determinant +1), the
/// one closest to the identity (largest trace); ties keep the first, so the result is deterministic.
fn canonical(f: Frame) -> Frame {
    let perms = [
        [0, 1, 2],
        [1, 2, 0],
        [2, 0, 1],
        [0, 2, 1],
        [2, 1, 0],
        [1, 0, 2],
    ];
    let mut best = (f64::MIN, f);
    for (pi, perm) in perms.iter().enumerate() {
        for signs in 0..8 {
            let s = |k: usize| if signs >> k & 1 == 1 { -1.0 } else { 1.0 };
            let parity = if pi < 3 { 1.0 } else { -1.0 };
            if parity * s(0) * s(1) * s(2) < 0.0 {
                continue;
            }
            let g: Frame = std::array::from_fn(|k| f[perm[k]] * s(k));
            let trace = g[0].x + g[1].y + g[2].z;
            if trace > best.0 + 1e-12 {
                best = (trace, g);
            }
        }
    }
    best.1
}

/// The box along frame `f` around `pts`, its rotation taken from the quaternion and its extents
/// padded (by ~1e-12 of `size`, more if rounding demands) so every point passes `contains(p, 0)`.
fn fit(pts: &[Vec3], f: Frame, size: f64) -> Obb {
    let f = orthonormal(f[0], f[1]);
    let rotation = Rotation::from_mat3(&Mat3::from_cols(f[0], f[1], f[2])).normalize();
    let mut obb = Obb {
        center: Vec3::ZERO,
        rotation,
        half_extents: Vec3::ZERO,
    };
    let axes = obb.axes();
    let (lo, hi) = extents(pts, &axes);
    let mid = (lo + hi) * 0.5;
    obb.center = axes[0] * mid.x + axes[1] * mid.y + axes[2] * mid.z;
    let reach = pts
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0, f64::max);
    let mut pad = 1e-12 * size + 4.0 * f64::EPSILON * reach;
    for _ in 0..8 {
        obb.half_extents = (hi - lo) * 0.5 + Vec3::splat(pad);
        if pts.iter().all(|p| obb.contains(*p, 0.0)) {
            break;
        }
        pad *= 4.0;
    }
    obb
}

#[cfg(test)]
mod tests;
