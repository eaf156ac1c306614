//! A convex polyhedron whose support function climbs the vertex graph instead of scanning every vertex:
//! on a convex polytope the vertex graph has no local maxima of `v . dir` but the global one.

use crate::math::Vec3;
use crate::shapes::ConvexMesh;
use parry3d_f64::shape::SupportMap;

/// Vertices, their neighbours (compressed rows: vertex `v`'s are `neighbours[offsets[v]..offsets[v+1]]`),
/// and the extreme vertices along the six axis directions (climb starts).
#[derive(Debug, Clone)]
pub struct HullSupport {
    vertices: Vec<Vec3>,
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
    starts: [u32; 6],
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
        let starts = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z].map(extreme);
        let mut offsets = vec![0u32];
        for list in &neighbours {
            offsets.push(offsets[offsets.len() - 1] + list.len() as u32);
        }
        HullSupport {
            vertices: mesh.vertices.clone(),
            offsets,
            neighbours: neighbours.concat(),
            starts,
        }
    }

    /// The vertices.
    pub fn vertices(&self) -> &[Vec3] {
        &self.vertices
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
            let mut moved = false;
            let (from, to) = (self.offsets[at] as usize, self.offsets[at + 1] as usize);
            for &n in &self.neighbours[from..to] {
                let d = self.vertices[n as usize].dot(dir);
                if d > best {
                    best = d;
                    at = n as usize;
                    moved = true;
                }
            }
            if !moved {
                return at as u32;
            }
        }
    }
}

impl SupportMap for HullSupport {
    fn local_support_point(&self, dir: Vec3) -> Vec3 {
        let at = self.starts[match (
            dir.x.abs() >= dir.y.abs(),
            dir.y.abs() >= dir.z.abs(),
            dir.x.abs() >= dir.z.abs(),
        ) {
            (true, _, true) => usize::from(dir.x < 0.0),
            (false, true, _) => 2 + usize::from(dir.y < 0.0),
            _ => 4 + usize::from(dir.z < 0.0),
        }];
        self.vertices[self.support_index_from(dir, at) as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::convex_hull;

    #[test]
    fn climbing_finds_the_scanned_support() {
        let mut s = 7u64;
        let mut r = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
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
