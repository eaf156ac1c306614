//! A convex polyhedron whose support function climbs the vertex graph instead of scanning every vertex:
//! on a convex polytope the vertex graph has no local maxima of `v . dir` but the global one.

use crate::math::Vec3;
use crate::shapes::ConvexMesh;
use parry3d_f64::shape::SupportMap;

/// Cells per cube-face side of the table of climb starts.
const CELLS: usize = 4;

/// Vertices, their neighbours (compressed rows: vertex `v`'s are `neighbours[offsets[v]..offsets[v+1]]`),
/// and a table of climb starts: the directions are cut into cells by the faces of a cube, each face into
/// `CELLS` x `CELLS`, and each cell holds the extreme vertex along its centre direction, so a climb
/// from there takes a step or two.
#[derive(Debug, Clone)]
pub struct HullSupport {
    vertices: Vec<Vec3>,
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
    starts: Vec<u32>,
    /// Face planes `(n, d)`: `n . x <= d` inside, `n` a unit vector.
    planes: Vec<(Vec3, f64)>,
    /// The surface's triangles (indices into `vertices`).
    triangles: Vec<[u32; 3]>,
}

/// The cell of direction `dir` (any length, not zero) in the table of climb starts, and for a cell the
/// direction through its centre.
mod cells {
    use super::{CELLS, Vec3};

    /// The cube face (major axis and sign) and the two other coordinates over the major one.
    #[inline]
    fn face(dir: Vec3) -> (usize, f64, f64) {
        let a = dir.abs();
        let (axis, major, u, v) = if a.x >= a.y && a.x >= a.z {
            (0, dir.x, dir.y, dir.z)
        } else if a.y >= a.z {
            (1, dir.y, dir.z, dir.x)
        } else {
            (2, dir.z, dir.x, dir.y)
        };
        let m = major.abs();
        (2 * axis + usize::from(major < 0.0), u / m, v / m)
    }

    #[inline]
    fn slot(t: f64) -> usize {
        // t in [-1, 1] (NaN and rounding clamp to the ends).
        (((t + 1.0) * 0.5 * CELLS as f64) as usize).min(CELLS - 1)
    }

    /// The cell of `dir`.
    #[inline]
    pub fn of(dir: Vec3) -> usize {
        let (f, u, v) = face(dir);
        (f * CELLS + slot(u)) * CELLS + slot(v)
    }

    /// The direction through the centre of cell `c`.
    pub fn centre(c: usize) -> Vec3 {
        let (f, rest) = (c / (CELLS * CELLS), c % (CELLS * CELLS));
        let mid = |i: usize| (i as f64 + 0.5) / CELLS as f64 * 2.0 - 1.0;
        let (u, v) = (mid(rest / CELLS), mid(rest % CELLS));
        let major = if f % 2 == 0 { 1.0 } else { -1.0 };
        match f / 2 {
            0 => Vec3::new(major, u, v),
            1 => Vec3::new(v, major, u),
            _ => Vec3::new(u, v, major),
        }
    }

    /// Number of cells.
    pub const COUNT: usize = 6 * CELLS * CELLS;
}

impl HullSupport {
    /// Builds the vertex graph of a closed convex mesh.
    pub fn new(mesh: &ConvexMesh) -> HullSupport {
        let mut neighbours = vec![Vec::new(); mesh.vertices.len()];
        for f in &mesh.faces {
            for (a, b) in [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])] {
                for (x, y) in [(a, b), (b, a)] {
                    let list: &mut Vec<u32> = &mut neighbours[x as usize];
                    if !list.contains(&y) {
                        list.push(y);
                    }
                }
            }
        }
        let extreme = |dir: Vec3| {
            (0..mesh.vertices.len() as u32)
                .max_by(|&a, &b| {
                    mesh.vertices[a as usize]
                        .dot(dir)
                        .total_cmp(&mesh.vertices[b as usize].dot(dir))
                })
                .unwrap_or(0)
        };
        let starts = (0..cells::COUNT)
            .map(|c| extreme(cells::centre(c)))
            .collect();
        let mut offsets = vec![0u32];
        for list in &neighbours {
            offsets.push(offsets[offsets.len() - 1] + list.len() as u32);
        }
        HullSupport {
            vertices: mesh.vertices.clone(),
            offsets,
            neighbours: neighbours.concat(),
            starts,
            planes: mesh.planes(),
            triangles: mesh.faces.clone(),
        }
    }

    /// The vertices.
    pub fn vertices(&self) -> &[Vec3] {
        &self.vertices
    }

    /// The surface's triangles (indices into [`HullSupport::vertices`]).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// How deep `p` lies inside: its distance to the nearest face plane (negative outside).
    pub fn depth(&self, p: Vec3) -> f64 {
        self.planes
            .iter()
            .map(|(n, d)| d - n.dot(p))
            .fold(f64::INFINITY, f64::min)
    }
}

impl HullSupport {
    /// The index of the farthest vertex along `dir`, climbing from vertex `start` (any vertex gives the
    /// same answer; one near it gets there in fewer steps).
    #[inline]
    pub fn support_index_from(&self, dir: Vec3, start: u32) -> u32 {
        let mut at = start as usize;
        let mut best = self.vertices[at].dot(dir);
        loop {
            // The best neighbour (the first of equals), from two running maxima, over the even and
            // the odd neighbours, so that each comparison waits on half as many before it.
            let (from, to) = (self.offsets[at] as usize, self.offsets[at + 1] as usize);
            let around = &self.neighbours[from..to];
            // (value, vertex, position among the neighbours; none before any is higher)
            let mut even = (best, at, usize::MAX);
            let mut odd = even;
            let mut pairs = around.chunks_exact(2);
            for (k, pair) in (&mut pairs).enumerate() {
                let (n0, n1) = (pair[0] as usize, pair[1] as usize);
                let (d0, d1) = (self.vertices[n0].dot(dir), self.vertices[n1].dot(dir));
                if d0 > even.0 {
                    even = (d0, n0, 2 * k);
                }
                if d1 > odd.0 {
                    odd = (d1, n1, 2 * k + 1);
                }
            }
            if let [n] = pairs.remainder() {
                let d = self.vertices[*n as usize].dot(dir);
                if d > even.0 {
                    even = (d, *n as usize, around.len() - 1);
                }
            }
            // On a tie the earlier neighbour wins, as in one pass over them.
            let next = if odd.0 > even.0 || (odd.0 == even.0 && odd.2 < even.2) {
                odd
            } else {
                even
            };
            if next.1 == at {
                return at as u32;
            }
            (best, at) = (next.0, next.1);
        }
    }
}

impl HullSupport {
    /// The index of the farthest vertex along `dir`, climbing from the table's start for its cell.
    #[inline]
    pub fn support_index(&self, dir: Vec3) -> u32 {
        self.support_index_from(dir, self.starts[cells::of(dir)])
    }
}

impl SupportMap for HullSupport {
    fn local_support_point(&self, dir: Vec3) -> Vec3 {
        self.vertices[self.support_index(dir) as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::test_shapes::values;
    use crate::shapes::convex_hull;

    #[test]
    fn climbing_finds_the_scanned_support() {
        let mut r = values(7);
        let points: Vec<Vec3> = (0..400)
            .map(|_| Vec3::new(r(), r() * 0.3, r() * 2.0))
            .collect();
        let hull = convex_hull(&points).unwrap();
        let support = HullSupport::new(&hull);
        for _ in 0..2000 {
            let dir = Vec3::new(r(), r(), r());
            let climbed = support.local_support_point(dir).dot(dir);
            let scanned = hull
                .vertices
                .iter()
                .map(|v| v.dot(dir))
                .fold(f64::NEG_INFINITY, f64::max);
            assert_eq!(climbed, scanned);
        }
    }
}
