//! A quickhull with exact orientation predicates: the fallback when parry's quickhull fails.

use super::{FastMap, HullError, argmax};
use crate::math::Vec3;

/// Quickhull with exact orientation tests on the distinct input points `w` (not the rounded
/// unit-extent copy: exactly coplanar input stays coplanar), so coplanar and nearly coplanar points
/// cannot make it inconsistent. Returns the outward faces over indices into `w`.
pub(super) fn exact_hull(w: &[Vec3]) -> Result<Vec<[u32; 3]>, HullError> {
    let fail = || HullError::Failed("exact quickhull found no initial tetrahedron".into());
    // A large initial tetrahedron.
    let i0 = argmax(w, |p| -p.x);
    let i1 = argmax(w, |p| p.distance_squared(w[i0]));
    let u = (w[i1] - w[i0]).normalize_or_zero();
    let i2 = argmax(w, |p| (p - w[i0]).cross(u).length_squared());
    let n = (w[i1] - w[i0]).cross(w[i2] - w[i0]);
    let i3 = argmax(w, |p| n.dot(p - w[i0]).abs());
    if side(w[i0], w[i1], w[i2], w[i3]) == 0.0 {
        return Err(fail());
    }
    let mut hull = Quickhull {
        w,
        faces: Vec::new(),
        alive: Vec::new(),
        outside: Vec::new(),
        edge: FastMap::default(),
    };
    let simplex = [i0, i1, i2, i3].map(|i| i as u32);
    let mut todo = Vec::new();
    for k in 0..4 {
        let mut f = [0, 1, 2, 3].map(|j| simplex[(k + j) % 4]);
        if hull.side(&[f[0], f[1], f[2]], f[3]) > 0.0 {
            f.swap(1, 2);
        }
        todo.push(hull.add([f[0], f[1], f[2]]));
    }
    let rest = (0..w.len() as u32)
        .filter(|i| !simplex.contains(i))
        .collect();
    hull.assign(rest, &todo);
    while let Some(f) = todo.pop() {
        if !hull.alive[f] || hull.outside[f].is_empty() {
            continue;
        }
        // The farthest outside point of f joins the hull; faces it sees are replaced by a cone.
        let [a, b, c] = hull.faces[f].map(|i| w[i as usize]);
        let n = (b - a).cross(c - a);
        let far = |i: &&u32| n.dot(w[**i as usize] - a);
        let Some(&p) = hull.outside[f]
            .iter()
            .max_by(|x, y| far(x).total_cmp(&far(y)))
        else {
            continue;
        };
        let mut visible = vec![f];
        hull.alive[f] = false;
        let mut k = 0;
        while k < visible.len() {
            let g = hull.faces[visible[k]];
            for e in 0..3 {
                if let Some(&h) = hull.edge.get(&(g[(e + 1) % 3], g[e])) {
                    // Faces whose plane holds p go too, so no flat face or
                    // non-extreme vertex is left behind.
                    if hull.alive[h] && hull.side(&hull.faces[h], p) >= 0.0 {
                        hull.alive[h] = false;
                        visible.push(h);
                    }
                }
            }
            k += 1;
        }
        // Horizon: edges of visible faces whose twin belongs to a face that stays.
        let mut horizon = Vec::new();
        let mut orphans = Vec::new();
        for &g in &visible {
            let fg = hull.faces[g];
            for e in 0..3 {
                let (u, v) = (fg[e], fg[(e + 1) % 3]);
                if hull.edge.get(&(v, u)).is_some_and(|&h| hull.alive[h]) {
                    horizon.push((u, v));
                }
            }
            orphans.extend(
                std::mem::take(&mut hull.outside[g])
                    .into_iter()
                    .filter(|&i| i != p),
            );
        }
        for &g in &visible {
            let fg = hull.faces[g];
            (0..3).for_each(|e| _ = hull.edge.remove(&(fg[e], fg[(e + 1) % 3])));
        }
        let cone: Vec<usize> = horizon.iter().map(|&(u, v)| hull.add([u, v, p])).collect();
        hull.assign(orphans, &cone);
        todo.extend(cone);
    }
    Ok((hull.faces.iter().zip(&hull.alive))
        .filter(|f| *f.1)
        .map(|f| *f.0)
        .collect())
}

/// The state of `exact_hull`: faces (counter-clockwise from outside), which are alive, the points
/// strictly outside each, and the face on the left of each directed edge. Every point index it
/// holds comes from `0..w.len()`, so indexing `w` with them cannot fail.
struct Quickhull<'a> {
    w: &'a [Vec3],
    faces: Vec<[u32; 3]>,
    alive: Vec<bool>,
    outside: Vec<Vec<u32>>,
    edge: FastMap<(u32, u32), usize>,
}

impl Quickhull<'_> {
    /// Which side of face `f` point `p` lies on: positive outside, zero on its plane.
    fn side(&self, f: &[u32; 3], p: u32) -> f64 {
        let at = |i: u32| self.w[i as usize];
        side(at(f[0]), at(f[1]), at(f[2]), at(p))
    }

    /// Adds face `f`, returning its index.
    fn add(&mut self, f: [u32; 3]) -> usize {
        let i = self.faces.len();
        (0..3).for_each(|e| _ = self.edge.insert((f[e], f[(e + 1) % 3]), i));
        self.faces.push(f);
        self.alive.push(true);
        self.outside.push(Vec::new());
        i
    }

    /// Gives each point to the first of `faces` it lies strictly outside of (none: it is inside).
    fn assign(&mut self, points: Vec<u32>, faces: &[usize]) {
        for p in points {
            if let Some(&f) = faces.iter().find(|&&f| self.side(&self.faces[f], p) > 0.0) {
                self.outside[f].push(p);
            }
        }
    }
}

/// The sign (-1, 0 or 1) of `((b - a) × (c - a)) · (d - a)`, exactly: positive when `d` lies on
/// the side the counter-clockwise triangle `a, b, c` faces. A floating-point filter with
/// Shewchuk's error bound decides almost every case; the rest use exact expansion arithmetic.
pub(super) fn side(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> f64 {
    let (u, v, x) = (b - a, c - a, d - a);
    let det = u.cross(v).dot(x);
    let permanent = x.x.abs() * ((u.y * v.z).abs() + (u.z * v.y).abs())
        + x.y.abs() * ((u.z * v.x).abs() + (u.x * v.z).abs())
        + x.z.abs() * ((u.x * v.y).abs() + (u.y * v.x).abs());
    if det.abs() > 7.771_561_172_376_103e-16 * permanent {
        return det.signum();
    }
    // Exact: differences as two-term expansions, then the triple product.
    let diff = |p: Vec3, q: Vec3| [0, 1, 2].map(|k| grow(&[p[k]], -q[k]));
    let (u, v, x) = (diff(b, a), diff(c, a), diff(d, a));
    let minor = |i: usize, j: usize| add(&mul(&u[i], &v[j]), &neg(&mul(&u[j], &v[i])));
    let det = add(
        &add(&mul(&minor(1, 2), &x[0]), &mul(&minor(2, 0), &x[1])),
        &mul(&minor(0, 1), &x[2]),
    );
    det.last().map_or(0.0, |t| t.signum())
}

/// `e + b` for a nonoverlapping expansion `e` (increasing magnitude, no zeros), exactly.
fn grow(e: &[f64], b: f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(e.len() + 1);
    let mut q = b;
    for &x in e {
        let s = q + x;
        let (bv, av) = (s - q, s - (s - q));
        let err = (q - av) + (x - bv);
        if err != 0.0 {
            out.push(err);
        }
        q = s;
    }
    if q != 0.0 {
        out.push(q);
    }
    out
}

/// The exact sum of two expansions.
fn add(e: &[f64], f: &[f64]) -> Vec<f64> {
    f.iter().fold(e.to_vec(), |acc, &x| grow(&acc, x))
}

/// The exact negation of an expansion.
fn neg(e: &[f64]) -> Vec<f64> {
    e.iter().map(|x| -x).collect()
}

/// The exact product of two expansions (each term product split exactly with a fused multiply-add).
fn mul(e: &[f64], f: &[f64]) -> Vec<f64> {
    let mut out = Vec::new();
    for &x in e {
        for &y in f {
            let p = x * y;
            out = add(&out, &[x.mul_add(y, -p), p]);
        }
    }
    out
}
