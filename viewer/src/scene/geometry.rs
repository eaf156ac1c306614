//! What the scene plugin ([`super::ScenePlugin`]) draws, prepared in plain Rust before the window opens: every shape of every sampled
//! type and every link's original mesh as flat-shaded triangles in the link frame, with outline edges.

use crate::model::Model;
use scm::error::Result;
use scm::math::Vec3;
use scm::mesh::TriMesh;
use scm::preprocess::{link_mesh, load_urdd_meshes};
use scm::shapes::{Geometry, ShapeType};

/// A triangle list in the link frame, ready to become a render mesh.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Triangles {
    /// Corner positions, three per triangle (flat shading needs unshared corners).
    pub positions: Vec<[f32; 3]>,
    /// One normal per corner (the face normal).
    pub normals: Vec<[f32; 3]>,
}

/// One shape to draw.
#[derive(Debug, Clone)]
pub struct ShapeGeometry {
    /// Matrix index.
    pub index: usize,
    /// Link index.
    pub link: usize,
    /// The shape in the link frame.
    pub geometry: Geometry,
    /// Outline segments in the link frame.
    pub outline: Vec<[Vec3; 2]>,
}

/// Everything the scene draws.
#[derive(Debug, Clone, Default)]
pub struct SceneGeometry {
    /// Per sampled type, its shapes.
    pub shapes: Vec<(ShapeType, Vec<ShapeGeometry>)>,
    /// Per link, its original geometry (empty for links without).
    pub originals: Vec<Triangles>,
    /// Centre and radius of a sphere around the robot at home (root frame).
    pub bounds: (Vec3, f64),
}

impl SceneGeometry {
    /// Loads the shapes of every sampled type and the original link meshes of `model`.
    pub fn load(model: &Model) -> Result<SceneGeometry> {
        let mut shapes = Vec::new();
        for data in &model.types {
            let mut list = Vec::with_capacity(data.matrix.shapes.len());
            for s in &data.matrix.shapes {
                let geometry = model.urdd.geometry(&s.geometry)?;
                list.push(ShapeGeometry {
                    index: s.index,
                    link: s.link_index,
                    outline: outline(&geometry),
                    geometry,
                });
            }
            shapes.push((data.shape_type, list));
        }
        let meshes = load_urdd_meshes(&model.urdd, &model.robot)?;
        let originals: Vec<Triangles> = model
            .robot
            .links
            .iter()
            .map(|l| triangles(&link_mesh(l, &meshes)))
            .collect();
        let home = model.kinematics.link_poses(&model.kinematics.home());
        let points: Vec<Vec3> = shapes
            .first()
            .map(|(_, list)| {
                list.iter()
                    .flat_map(|s| {
                        s.outline
                            .iter()
                            .flatten()
                            .map(|p| home[s.link].transform_point(*p))
                    })
                    .collect()
            })
            .unwrap_or_default();
        let bounds = match scm::math::bounds(&points) {
            Some((lo, hi)) => ((lo + hi) * 0.5, ((hi - lo).length() * 0.5).max(0.1)),
            None => (Vec3::ZERO, 1.0),
        };
        Ok(SceneGeometry {
            shapes,
            originals,
            bounds,
        })
    }
}

/// Flat-shaded triangles of a mesh.
pub fn triangles(mesh: &TriMesh) -> Triangles {
    let corners = mesh
        .triangles
        .iter()
        .map(|t| t.map(|i| mesh.vertices[i as usize]));
    flat(corners)
}

/// Flat-shaded triangles of a hull's faces.
pub fn hull_triangles(vertices: &[Vec3], faces: &[[u32; 3]]) -> Triangles {
    flat(faces.iter().map(|f| f.map(|i| vertices[i as usize])))
}

fn flat(corners: impl Iterator<Item = [Vec3; 3]>) -> Triangles {
    let mut out = Triangles::default();
    for [a, b, c] in corners {
        let n = (b - a).cross(c - a);
        let len = n.length();
        if len <= 0.0 || !len.is_finite() {
            continue;
        }
        let n = (n / len).as_vec3().to_array();
        for p in [a, b, c] {
            out.positions.push(p.as_vec3().to_array());
            out.normals.push(n);
        }
    }
    out
}

/// Outline segments of a shape in the link frame: three great circles of a sphere, the twelve edges of
/// a box, the edges of a hull (each once).
pub fn outline(geometry: &Geometry) -> Vec<[Vec3; 2]> {
    match geometry {
        Geometry::Sphere(s) => {
            const N: usize = 48;
            let mut out = Vec::with_capacity(3 * N);
            for axis in 0..3 {
                let point = |k: usize| {
                    let a = std::f64::consts::TAU * k as f64 / N as f64;
                    let (u, v) = (a.cos() * s.radius, a.sin() * s.radius);
                    s.center
                        + match axis {
                            0 => Vec3::new(0.0, u, v),
                            1 => Vec3::new(u, 0.0, v),
                            _ => Vec3::new(u, v, 0.0),
                        }
                };
                out.extend((0..N).map(|k| [point(k), point(k + 1)]));
            }
            out
        }
        Geometry::Obb(b) => {
            let corner = |i: usize| {
                let sign = |bit: usize| if i & bit == 0 { -1.0 } else { 1.0 };
                let local = Vec3::new(
                    sign(1) * b.half_extents.x,
                    sign(2) * b.half_extents.y,
                    sign(4) * b.half_extents.z,
                );
                b.center + b.rotation * local
            };
            let mut out = Vec::with_capacity(12);
            for i in 0..8 {
                for bit in [1, 2, 4] {
                    if i & bit == 0 {
                        out.push([corner(i), corner(i | bit)]);
                    }
                }
            }
            out
        }
        Geometry::Hull(h) => h.edges().into_iter().map(|(a, b)| [a, b]).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use scm::shapes::{Sphere, convex_hull};

    fn cube() -> scm::shapes::ConvexMesh {
        let v: Vec<Vec3> = (0..8)
            .map(|i| Vec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
            .collect();
        convex_hull(&v).expect("a cube has a hull")
    }

    #[test]
    fn a_box_has_twelve_edges_of_its_extents() {
        let obb = scm::shapes::tight_obb(&cube());
        let edges = outline(&Geometry::Obb(obb));
        assert_eq!(edges.len(), 12);
        for [a, b] in edges {
            assert!((a.distance(b) - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn hull_edges_are_unique_and_faces_flat_shaded() {
        let hull = cube();
        let edges = outline(&Geometry::Hull(hull.clone()));
        // 12 cube edges plus one diagonal per square face (triangulated).
        assert_eq!(edges.len(), 18);
        let t = hull_triangles(&hull.vertices, &hull.faces);
        assert_eq!(t.positions.len(), 3 * hull.faces.len());
        assert!(t.normals.iter().all(|n| {
            let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            (l - 1.0).abs() < 1e-5
        }));
    }

    #[test]
    fn a_sphere_outline_lies_on_the_sphere() {
        let s = Sphere {
            center: Vec3::new(1.0, 2.0, 3.0),
            radius: 0.5,
        };
        let edges = outline(&Geometry::Sphere(s));
        assert_eq!(edges.len(), 3 * 48);
        assert!(
            edges
                .iter()
                .flatten()
                .all(|p| (p.distance(s.center) - 0.5).abs() < 1e-9)
        );
    }
}
