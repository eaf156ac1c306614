//! Triangle meshes: loading mesh files and tessellating URDF primitives into one link-frame soup.

mod collada;
mod load;
mod obj;
mod primitive;
mod stl;

pub use load::{MeshFile, load_mesh_file, read_mesh};
pub use primitive::{primitive_bounds, tessellate};

use crate::math::{Pose, Vec3};

/// An indexed triangle mesh.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub vertices: Vec<Vec3>,
    /// Triangles as vertex indices.
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// Appends `other`, transformed by `pose` after scaling each axis by `scale`.
    pub fn append_transformed(&mut self, other: &TriMesh, pose: &Pose, scale: Vec3) {
        let base = self.vertices.len() as u32;
        self.vertices.extend(
            other
                .vertices
                .iter()
                .map(|v| pose.transform_point(*v * scale)),
        );
        // A mirroring scale flips the winding; keep triangles outward-facing.
        let flip = scale.x * scale.y * scale.z < 0.0;
        self.triangles.extend(other.triangles.iter().map(|t| {
            if flip {
                [t[0] + base, t[2] + base, t[1] + base]
            } else {
                [t[0] + base, t[1] + base, t[2] + base]
            }
        }));
    }

    /// Drops the vertices no triangle uses (Assimp's meshes hold only those), keeping the order of the
    /// rest.
    pub fn compact(&mut self) {
        let mut used = vec![false; self.vertices.len()];
        for t in &self.triangles {
            for &i in t {
                used[i as usize] = true;
            }
        }
        if used.iter().all(|&u| u) {
            return;
        }
        let mut new_index = vec![0u32; self.vertices.len()];
        let mut kept = Vec::with_capacity(self.vertices.len());
        for (i, v) in self.vertices.iter().enumerate() {
            if used[i] {
                new_index[i] = kept.len() as u32;
                kept.push(*v);
            }
        }
        for t in &mut self.triangles {
            *t = t.map(|i| new_index[i as usize]);
        }
        self.vertices = kept;
    }

    /// Signed volume enclosed by the triangles (meaningful for closed, outward-oriented meshes).
    pub fn signed_volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }
}
