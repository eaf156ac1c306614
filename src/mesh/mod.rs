//! Triangle meshes: loading mesh files and tessellating URDF primitives into one link-frame soup.

mod load;
mod primitive;

pub use load::load_mesh_file;
pub use primitive::tessellate;

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
