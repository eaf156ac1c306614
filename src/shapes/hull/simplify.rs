//! Simplifying a convex hull to a bounded vertex count while still enclosing every vertex.

use super::{ConvexMesh, check_solid, convex_hull};
use crate::math::Vec3;
use crate::math::bounds;
use std::collections::HashSet;

/// A convex polyhedron with at most `max_vertices` vertices (at least 4) containing every
/// vertex of `hull`, as tight as the heuristics manage.
///
/// Two constructions compete and the smaller volume wins: the intersection of a greedy subset of
/// the hull's supporting planes, and the hull of a greedy vertex subset pushed out along rays from
/// an interior point just enough to cover the rest. A hull that already has few enough vertices,
/// or that is degenerate (flat), is returned unchanged.
pub fn simplify_hull(hull: &ConvexMesh, max_vertices: usize) -> ConvexMesh {
    if hull.vertices.len() <= max_vertices {
        return hull.clone();
    }
    let max_v = max_vertices.max(4);
    // A closed triangulated surface is trusted as the hull (the result's containment is verified
    // against the vertices anyway); anything else is rebuilt.
    let rebuilt;
    let full = if !hull.faces.is_empty() && hull.faces.len() + 4 == 2 * hull.vertices.len() {
        hull
    } else {
        match convex_hull(&hull.vertices) {
            Ok(h) if h.vertices.len() <= max_v => return h,
            Ok(h) => {
                rebuilt = h;
                &rebuilt
            }
            Err(_) => return hull.clone(),
        }
    };
    let pts = &full.vertices;
    let c = full.centroid();
    let scale = bounds(pts).map_or(0.0, |(lo, hi)| (hi - lo).length());
    let candidates = [
        by_planes(full, c, scale, max_v),
        by_vertices(full, scale, max_v),
        // Always-available fallbacks: the bounding box, the tetrahedron of supporting planes.
        bounds(pts).map(|(lo, hi)| (0..8).map(|i| lo + (hi - lo) * corner(i)).collect()),
        intersect(&support_planes(pts, &tetra()), c, scale),
    ];
    (candidates.into_iter().flatten())
        .filter(|v| v.len() <= max_v)
        .filter_map(|v| enclose(&v, pts, c, 1e-10 * scale))
        .min_by(|a, b| a.volume().total_cmp(&b.volume()))
        .unwrap_or_else(|| hull.clone())
}

/// Corner `i` of the unit cube (bit k of `i` set: coordinate k is 1).
pub(super) fn corner(i: usize) -> Vec3 {
    Vec3::new((i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2 & 1) as f64)
}

/// A half-space `n·x <= d` as (unit normal `n`, offset `d`).
type Plane = (Vec3, f64);

/// The 14 k-DOP directions: the six axes, then the eight diagonals.
fn kdop() -> [Vec3; 14] {
    let s = |bit: usize| if bit == 0 { 1.0 } else { -1.0 };
    std::array::from_fn(|i| match i {
        0..6 => Vec3::AXES[i / 2] * s(i % 2),
        _ => Vec3::new(s((i - 6) & 4), s((i - 6) & 2), s((i - 6) & 1)) / 3f64.sqrt(),
    })
}

/// Face normals of a regular tetrahedron (diagonals with an even number of minus signs).
fn tetra() -> [Vec3; 4] {
    let d = kdop();
    [d[6], d[9], d[11], d[12]]
}

/// The supporting planes of `pts` with the given unit normals.
fn support_planes(pts: &[Vec3], dirs: &[Vec3]) -> Vec<(Vec3, f64)> {
    let sup = |n: Vec3| pts.iter().map(|p| n.dot(*p)).fold(f64::MIN, f64::max);
    dirs.iter().map(|&n| (n, sup(n))).collect()
}

/// Pushes `x` unless a point within `tol` is already there.
fn push_unique(out: &mut Vec<Vec3>, x: Vec3, tol: f64) {
    if !out.iter().any(|y| y.distance_squared(x) <= tol * tol) {
        out.push(x);
    }
}

/// Vertices of the intersection of half-spaces `n·x <= d` that all strictly contain `c`, by
/// duality: each half-space maps to the dual point `n / (d - n·c)`, each dual hull face
/// `m·y = e` to the primal vertex `c + m / e`.
fn intersect(planes: &[(Vec3, f64)], c: Vec3, scale: f64) -> Option<Vec<Vec3>> {
    let dual: Vec<Vec3> = (planes
        .iter()
        .map(|&(n, d)| (d - n.dot(c) > 0.0).then(|| n / (d - n.dot(c)))))
    .collect::<Option<_>>()?;
    let mut out = Vec::new();
    for (m, e) in convex_hull(&dual).ok()?.planes() {
        if e.is_nan() || e <= 0.0 {
            return None;
        }
        push_unique(&mut out, c + m / e, 1e-7 * scale);
    }
    Some(out)
}

/// For each point, the (largest violation, plane index) over `planes`.
fn worst_plane(p: Vec3, planes: &[(Vec3, f64)]) -> (f64, usize) {
    (planes.iter().enumerate()).fold((f64::MIN, 0), |b, (i, (n, d))| {
        let v = n.dot(p) - d;
        if v > b.0 { (v, i) } else { b }
    })
}

/// Greedy supporting-plane intersection: start from the 14-DOP (or box, or tetrahedron) and keep
/// adding the hull face plane that cuts off the polytope vertex farthest outside the hull.
fn by_planes(full: &ConvexMesh, c: Vec3, scale: f64, max_v: usize) -> Option<Vec<Vec3>> {
    let pts = &full.vertices;
    let hull_planes = full.planes();
    // Seed: the smallest bounded k-DOP (14 planes, else box, else tetrahedron) fitting in
    // `max_v` vertices, in world axes, in the long/middle/thin frame of the vertices, or in a
    // frame on the largest face (exact for plates, whose thin axis the vertices only estimate).
    let thin = check_solid(pts, 0.0).unwrap_or([Vec3::X, Vec3::Y, Vec3::Z]);
    let largest = (full.faces.iter().filter_map(|f| full.triangle(f)))
        .map(|[a, b, c]| (b - a).cross(c - a))
        .max_by(|a, b| a.length_squared().total_cmp(&b.length_squared()))
        .and_then(|n| n.try_normalize())
        .unwrap_or(thin[2]);
    let along = (thin[0] - largest * largest.dot(thin[0]))
        .try_normalize()
        .unwrap_or(thin[1]);
    let frames = [
        [Vec3::X, Vec3::Y, Vec3::Z],
        thin,
        [along, largest.cross(along), largest],
    ];
    let mut seed: Option<(f64, Vec<Plane>, Vec<Vec3>)> = None;
    let (dop, tet) = (kdop(), tetra());
    for dirs in [&dop[..], &dop[..6], &tet[..]] {
        for axes in frames {
            let turned: Vec<Vec3> = dirs
                .iter()
                .map(|d| axes[0] * d.x + axes[1] * d.y + axes[2] * d.z)
                .collect();
            let planes = support_planes(pts, &turned);
            let Some(verts) = intersect(&planes, c, scale).filter(|v| v.len() <= max_v) else {
                continue;
            };
            let Ok(vol) = convex_hull(&verts).map(|m| m.volume()) else {
                continue;
            };
            if seed.as_ref().is_none_or(|s| vol < s.0) {
                seed = Some((vol, planes, verts));
            }
        }
        if seed.is_some() {
            break;
        }
    }
    let (_, mut planes, mut verts) = seed?;
    // Cache each vertex's worst violation: only new vertices need the full scan.
    let tol = 1e-9 * scale;
    let mut cache: Vec<(Vec3, (f64, usize))> = Vec::new();
    let mut used = HashSet::new();
    loop {
        let hit = |w: Vec3| {
            cache
                .iter()
                .find(|(x, _)| x.distance_squared(w) <= tol * tol)
        };
        let worst: Vec<(f64, usize)> = (verts.iter())
            .map(|&w| hit(w).map_or_else(|| worst_plane(w, &hull_planes), |h| h.1))
            .collect();
        cache = verts.iter().copied().zip(worst.iter().copied()).collect();
        let &(viol, plane) = worst.iter().max_by(|a, b| a.0.total_cmp(&b.0))?;
        // Stop when the polytope is the hull (to tolerance) or the cut would change nothing.
        if viol <= tol || !used.insert(plane) {
            break;
        }
        planes.push(hull_planes[plane]);
        match intersect(&planes, c, scale) {
            Some(v) if v.len() <= max_v => verts = v,
            _ => break,
        }
    }
    (verts.len() <= max_v).then_some(verts)
}

/// Greedy vertex subset, inflated: pick up to `max_v` hull vertices (farthest-outside first,
/// per face and round), then scale each chosen vertex about `c` by the largest factor its incident
/// faces need so that the cone of every face covers the hull vertices it contains.
fn by_vertices(full: &ConvexMesh, scale: f64, max_v: usize) -> Option<Vec<Vec3>> {
    let pts = &full.vertices;
    // Seed: the extreme vertices in the 14 k-DOP directions plus a large tetrahedron.
    let p0 = *pts.first()?;
    let i1 = argmax(pts, |p| p.distance_squared(p0));
    let u = (pts[i1] - p0).normalize_or_zero();
    let i2 = argmax(pts, |p| (p - p0).cross(u).length_squared());
    let n = u.cross(pts[i2] - p0).normalize_or_zero();
    let i3 = argmax(pts, |p| n.dot(p - p0).abs());
    let mut sel: Vec<usize> = Vec::new();
    for i in [0, i1, i2, i3]
        .into_iter()
        .chain(kdop().map(|n| argmax(pts, |p| n.dot(p))))
    {
        if !sel.contains(&i) && sel.len() < max_v {
            sel.push(i);
        }
    }
    let mut chosen: HashSet<usize> = sel.iter().copied().collect();
    let tol = 1e-9 * scale;
    while sel.len() < max_v {
        let sub: Vec<Vec3> = sel.iter().map(|&i| pts[i]).collect();
        let planes = convex_hull(&sub).ok()?.planes();
        let mut best = vec![(tol, usize::MAX); planes.len()];
        for (i, &p) in pts.iter().enumerate().filter(|(i, _)| !chosen.contains(i)) {
            let (v, f) = worst_plane(p, &planes);
            if v > best[f].0 {
                best[f] = (v, i);
            }
        }
        let mut add: Vec<(f64, usize)> = best.into_iter().filter(|b| b.1 != usize::MAX).collect();
        if add.is_empty() {
            break;
        }
        add.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        add.truncate(max_v - sel.len());
        sel.extend(add.iter().map(|a| a.1));
        chosen.extend(add.iter().map(|a| a.1));
    }
    let mut cur = convex_hull(&sel.iter().map(|&i| pts[i]).collect::<Vec<_>>()).ok()?;
    let c = cur.centroid();
    let mut best: Option<ConvexMesh> = None;
    for _ in 0..3 {
        let next = inflate(&cur, pts, c)?;
        let mesh = convex_hull(&next).ok()?;
        if best.as_ref().is_none_or(|b| mesh.volume() < b.volume()) {
            best = Some(mesh.clone());
        }
        cur = mesh;
    }
    best.map(|b| b.vertices)
}

/// Index of the point maximising `f` (0 for an empty slice).
pub(crate) fn argmax(pts: &[Vec3], f: impl Fn(Vec3) -> f64) -> usize {
    (pts.iter().enumerate())
        .fold(
            (0, f64::MIN),
            |b, (i, p)| if f(*p) > b.1 { (i, f(*p)) } else { b },
        )
        .0
}

/// One inflation step: moves every vertex `s_i` of `mesh` along its ray from the interior point
/// `c` to `c + t_i (s_i - c)` so that the union of the tetrahedra `(c, scaled face)` covers `pts`.
///
/// A point `v` in the cone of face `(i, j, k)` has cone coordinates `v - c = Σ α (s - c)`, `α >= 0`,
/// and lies in the scaled tetrahedron iff `Σ α / t <= 1`: linear in `u = 1 / t`. Starting from
/// the feasible `t_i` = the largest gauge over the incident faces' points, each `u_i` is then
/// raised as far as its constraints allow (coordinate ascent on that linear program).
fn inflate(mesh: &ConvexMesh, pts: &[Vec3], c: Vec3) -> Option<Vec<Vec3>> {
    let rel: Vec<Vec3> = mesh.vertices.iter().map(|v| *v - c).collect();
    // (face, unit normal, distance from c) of every non-sliver face; c must be strictly inside.
    let faces: Vec<([u32; 3], Vec3, f64)> = (mesh.faces.iter())
        .filter_map(|f| mesh.face_plane(f).map(|(n, d)| (*f, n, d - n.dot(c))))
        .collect();
    if faces.iter().any(|f| f.2.is_nan() || f.2 <= 0.0) {
        return None;
    }
    let mut rows: Vec<([usize; 3], [f64; 3])> = Vec::with_capacity(pts.len());
    let mut u = vec![1.0_f64; rel.len()];
    for p in pts {
        let r = *p - c;
        let (f, g) = (faces.iter())
            .map(|(f, n, h)| (f, n.dot(r) / h))
            .max_by(|a, b| a.1.total_cmp(&b.1))?;
        let idx = f.map(|i| i as usize);
        let [Some(a), Some(b), Some(d)] = idx.map(|i| rel.get(i).copied()) else {
            return None;
        };
        let det = a.dot(b.cross(d));
        if det.is_nan() || det == 0.0 {
            return None;
        }
        let alpha =
            [r.dot(b.cross(d)), a.dot(r.cross(d)), a.dot(b.cross(r))].map(|x| (x / det).max(0.0));
        for &i in &idx {
            u[i] = u[i].min(1.0 / g.max(1e-3));
        }
        rows.push((idx, alpha));
    }
    let mut by_vertex: Vec<Vec<usize>> = vec![Vec::new(); rel.len()];
    for (k, (idx, _)) in rows.iter().enumerate() {
        idx.iter().for_each(|&i| by_vertex[i].push(k));
    }
    for _ in 0..4 {
        for (i, ks) in by_vertex.iter().enumerate() {
            let bound = (ks.iter().map(|&k| &rows[k]))
                .filter_map(|(idx, al)| {
                    let (mine, rest) = (0..3).fold((0.0, 0.0), |(m, o), j| {
                        if idx[j] == i {
                            (m + al[j], o)
                        } else {
                            (m, o + al[j] * u[idx[j]])
                        }
                    });
                    (mine > 1e-12).then(|| (1.0 - rest) / mine)
                })
                .fold(f64::INFINITY, f64::min);
            if bound.is_finite() && bound > u[i] {
                u[i] = bound;
            }
        }
    }
    Some(rel.iter().zip(&u).map(|(r, u)| c + *r / *u).collect())
}

/// The hull of `verts`, scaled about `c` if needed so that every point of `pts` is inside: exactly
/// (`n·p <= d`) when a few growing scalings get there, else within the plane noise of `tol`.
fn enclose(verts: &[Vec3], pts: &[Vec3], c: Vec3, tol: f64) -> Option<ConvexMesh> {
    let mut mesh = convex_hull(verts).ok()?;
    for k in 0..5 {
        // (n, d, 1 / distance of c from the plane); c must be strictly inside.
        let planes: Vec<(Vec3, f64, f64)> = (mesh.planes().into_iter())
            .map(|(n, d)| (n, d, 1.0 / (d - n.dot(c))))
            .collect();
        if planes.iter().any(|p| p.2.is_nan() || p.2 <= 0.0) {
            return None;
        }
        // Largest violation `n·p - d`, and largest relative one (the gauge of p is 1 + that).
        let (mut worst, mut rel) = (f64::MIN, 0.0_f64);
        for p in pts {
            for (n, d, inv) in &planes {
                let v = n.dot(*p) - d;
                if v > worst {
                    worst = v;
                }
                if v * inv > rel {
                    rel = v * inv;
                }
            }
        }
        if worst <= 0.0 || (k == 4 && worst <= tol) {
            return Some(mesh);
        }
        let t = (1.0 + rel) * (1.0 + 1e-12 * 10f64.powi(k));
        mesh.vertices.iter_mut().for_each(|v| *v = c + (*v - c) * t);
    }
    None
}
