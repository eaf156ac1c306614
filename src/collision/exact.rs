//! The `mesh` geometry: a link's URDF collision geometry exactly as the consumers check it (triangle
//! meshes as loaded, primitives as exact parry primitives), and the two collision tests on it.
//!
//! - [`ExactLink::touch`]: what MoveIt and Pinocchio (FCL / Coal) report: a primitive is a solid, a
//!   mesh is its triangles, so a mesh wholly inside another mesh does not touch it. This is the
//!   geometry *inside* what every consumer checks (MuJoCo and Drake check the meshes' convex hulls,
//!   which contain it), so `default` and `always` are decided on it.
//! - [`ExactLink::overlap`]: solid bodies: `touch`, or a part of one link wholly inside a mesh of the
//!   other (one probe point per part, by the generalized winding number, which stays meaningful for
//!   meshes that are not watertight). The ground truth of `scm bench` and of `never`.
//!
//! Geometry only: callers build links from a robot's loaded meshes ([`ExactLink::new`]), each mesh
//! file at each scale indexed once ([`ExactMesh`]) and shared by every element that uses it.

use super::mesh_distance::mesh_distance;
use crate::math::{Pose, Rotation, Vec3};
use crate::mesh::TriMesh as SoupMesh;
use crate::robot::{GeometryElement, ShapeSource};
use crate::shapes::minimal_bounding_sphere;
use parry3d_f64::bounding_volume::BoundingVolume;
use parry3d_f64::query;
use parry3d_f64::shape::{Ball, Capsule, Cuboid, Cylinder, Shape, TriMesh};
use std::sync::Arc;

/// One geometry element of a link.
struct Part {
    /// The element's pose in the link frame (its URDF origin).
    pose: Pose,
    /// The element in its own frame (shared between links for meshes, see [`ExactMesh`]).
    shape: Arc<dyn Shape>,
    /// Whether the part is a triangle mesh (a surface, not a solid).
    is_mesh: bool,
    /// A point of the part (link frame), for the containment test.
    probe: Vec3,
    /// Bounding sphere (link frame).
    center: Vec3,
    radius: f64,
}

/// A mesh element's triangles indexed for the exact tests, in the element's frame (its scale applied,
/// its origin not). Clones share the triangles and their bounding-volume tree: a robot whose four legs
/// use the same mesh files holds each of them once.
#[derive(Clone)]
pub struct ExactMesh {
    mesh: Arc<TriMesh>,
    /// A vertex, for the containment test (element frame).
    probe: Vec3,
    /// Bounding sphere (element frame).
    center: Vec3,
    radius: f64,
}

impl std::fmt::Debug for ExactMesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ExactMesh")
            .field("triangles", &self.mesh.indices().len())
            .field("radius", &self.radius)
            .finish_non_exhaustive()
    }
}

impl ExactMesh {
    /// Indexes `soup` (element frame); `None` for a mesh without vertices, an error (parry's, for the
    /// caller to place) when parry cannot index its triangles.
    pub fn new(soup: SoupMesh) -> Result<Option<ExactMesh>, String> {
        let Some(&probe) = soup.vertices.first() else {
            return Ok(None);
        };
        let sphere = minimal_bounding_sphere(&soup.vertices);
        let mesh = TriMesh::new(soup.vertices, soup.triangles)
            .map_err(|e| format!("triangle mesh: {e}"))?;
        Ok(Some(ExactMesh {
            mesh: Arc::new(mesh),
            probe,
            center: sphere.center,
            radius: sphere.radius,
        }))
    }
}

/// A link's exact collision geometry, ready for collision tests.
pub struct ExactLink {
    parts: Vec<Part>,
    /// Bounding sphere of all parts (link frame).
    center: Vec3,
    radius: f64,
}

impl std::fmt::Debug for ExactLink {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ExactLink")
            .field("parts", &self.parts.len())
            .field("radius", &self.radius)
            .finish_non_exhaustive()
    }
}

/// Why a link's geometry could not be prepared.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("element at line {line}: {message}")]
pub struct ExactError {
    /// The URDF line of the element.
    pub line: u32,
    /// What parry said.
    pub message: String,
}

impl ExactLink {
    /// Prepares a link's elements; `mesh_of` gives a mesh element's indexed triangles in the element
    /// frame (see [`ExactMesh`]; `None` for an empty mesh, which is left out). `None` for a link
    /// without geometry.
    pub fn new(
        elements: &[GeometryElement],
        mesh_of: impl Fn(&GeometryElement) -> Result<Option<ExactMesh>, String>,
    ) -> Result<Option<ExactLink>, ExactError> {
        let mut parts = Vec::new();
        for g in elements {
            let fail = |message: String| ExactError {
                line: g.line,
                message,
            };
            let primitive = |shape: Arc<dyn Shape>, local: Pose, radius: f64| Part {
                pose: g.origin * local,
                shape,
                is_mesh: false,
                probe: g.origin.translation,
                center: g.origin.translation,
                radius,
            };
            // URDF cylinders and capsules run along z; parry's cylinder along y.
            let y_to_z =
                Pose::from_rotation(Rotation::from_rotation_x(std::f64::consts::FRAC_PI_2));
            let part = match &g.shape {
                ShapeSource::Box { size } => primitive(
                    Arc::new(Cuboid::new(*size * 0.5)),
                    Pose::IDENTITY,
                    (*size * 0.5).length(),
                ),
                ShapeSource::Sphere { radius } => {
                    primitive(Arc::new(Ball::new(*radius)), Pose::IDENTITY, *radius)
                }
                ShapeSource::Cylinder { radius, length } => primitive(
                    Arc::new(Cylinder::new(0.5 * length, *radius)),
                    y_to_z,
                    radius.hypot(0.5 * length),
                ),
                ShapeSource::Capsule { radius, length } => primitive(
                    Arc::new(Capsule::new_z(0.5 * length, *radius)),
                    Pose::IDENTITY,
                    0.5 * length + radius,
                ),
                ShapeSource::Mesh { .. } => {
                    let Some(mesh) = mesh_of(g).map_err(fail)? else {
                        continue;
                    };
                    Part {
                        pose: g.origin,
                        shape: mesh.mesh,
                        is_mesh: true,
                        probe: g.origin.transform_point(mesh.probe),
                        center: g.origin.transform_point(mesh.center),
                        radius: mesh.radius,
                    }
                }
            };
            parts.push(part);
        }
        if parts.is_empty() {
            return Ok(None);
        }
        // A sphere around the parts' spheres: their extreme points in six directions are enough for a
        // minimal sphere of points that encloses every part (each part's sphere lies within the
        // enclosing sphere of its centre plus its radius).
        let points: Vec<Vec3> = parts.iter().map(|p| p.center).collect();
        let around = minimal_bounding_sphere(&points);
        let radius = parts
            .iter()
            .map(|p| p.center.distance(around.center) + p.radius)
            .fold(0.0, f64::max);
        Ok(Some(ExactLink {
            parts,
            center: around.center,
            radius,
        }))
    }

    /// Bounding sphere in the link frame: centre and radius.
    pub fn bounding_sphere(&self) -> (Vec3, f64) {
        (self.center, self.radius)
    }

    /// Whether the links (posed at `pa` and `pb`) collide as MoveIt and Pinocchio report it: a
    /// primitive's solid or a mesh's triangles meet the other link's.
    pub fn touch(&self, pa: &Pose, other: &ExactLink, pb: &Pose) -> bool {
        if spheres_apart(pa, self.center, self.radius, pb, other.center, other.radius) {
            return false;
        }
        self.parts.iter().any(|a| {
            other.parts.iter().any(|b| {
                let (qa, qb) = (*pa * a.pose, *pb * b.pose);
                !spheres_apart(pa, a.center, a.radius, pb, b.center, b.radius)
                    && a.shape
                        .compute_aabb(&qa)
                        .intersects(&b.shape.compute_aabb(&qb))
                    // Every pairing of parry primitives and triangle meshes is supported; an
                    // unsupported one would be a collision we cannot rule out.
                    && query::intersection_test(&qa, a.shape.as_ref(), &qb, b.shape.as_ref())
                        .map(|r| r.intersecting)
                        .unwrap_or(true)
            })
        })
    }

    /// Whether the links overlap as solid bodies: they [`touch`](ExactLink::touch), or some part of
    /// one lies wholly inside a mesh of the other.
    pub fn overlap(&self, pa: &Pose, other: &ExactLink, pb: &Pose) -> bool {
        self.touch(pa, other, pb) || self.encloses(pa, other, pb)
    }

    /// Whether some part of one link lies wholly inside a mesh of the other, exact where they do not
    /// [`touch`](ExactLink::touch) (each part's probe point decides): what
    /// [`overlap`](ExactLink::overlap) adds to touch, for a caller that has tested touch already.
    pub fn encloses(&self, pa: &Pose, other: &ExactLink, pb: &Pose) -> bool {
        self.inside(pa, other, pb) || other.inside(pb, self, pa)
    }

    /// A lower bound on the distance between the links (0 where they overlap): the least distance between
    /// their parts (parry's, exact for primitives, between triangles for meshes).
    pub fn distance(&self, pa: &Pose, other: &ExactLink, pb: &Pose) -> f64 {
        self.distance_above(pa, other, pb, f64::NEG_INFINITY)
            .unwrap_or(0.0)
    }

    /// [`ExactLink::distance`] where it exceeds `enough`; `None` (sooner) where it is at most `enough`,
    /// for a caller with no use for such a distance.
    pub fn distance_above(
        &self,
        pa: &Pose,
        other: &ExactLink,
        pb: &Pose,
        enough: f64,
    ) -> Option<f64> {
        if self.encloses(pa, other, pb) {
            return (0.0 > enough).then_some(0.0);
        }
        let mut best = f64::INFINITY;
        for a in &self.parts {
            for b in &other.parts {
                let gap = pa
                    .transform_point(a.center)
                    .distance(pb.transform_point(b.center))
                    - a.radius
                    - b.radius;
                if gap >= best {
                    continue;
                }
                let (qa, qb) = (*pa * a.pose, *pb * b.pose);
                let meshes = (a.shape.as_trimesh(), b.shape.as_trimesh());
                let d = if let (Some(ma), Some(mb)) = meshes {
                    mesh_distance(ma, &qa, mb, &qb, enough)
                } else {
                    // An unsupported pairing could be touching: 0 is the safe bound.
                    query::distance(&qa, a.shape.as_ref(), &qb, b.shape.as_ref())
                        .map_or(0.0, |r| r.distance)
                };
                best = best.min(d.max(0.0));
                if best <= enough {
                    return None;
                }
            }
        }
        Some(best)
    }

    /// Whether a part of `self` lies inside a mesh part of `other`, given that they do not touch: then
    /// each part of `self` is wholly inside or wholly outside, so its probe point decides.
    fn inside(&self, pa: &Pose, other: &ExactLink, pb: &Pose) -> bool {
        self.parts.iter().any(|a| {
            let world = pa.transform_point(a.probe);
            other.parts.iter().filter(|b| b.is_mesh).any(|b| {
                let p = (*pb * b.pose).inverse_transform_point(world);
                let mesh = b.shape.as_trimesh();
                mesh.is_some_and(|m| {
                    m.local_aabb().contains_local_point(p) && winding_number(m, p).abs() > 0.5
                })
            })
        })
    }
}

/// Whether two posed spheres are strictly apart.
fn spheres_apart(pa: &Pose, ca: Vec3, ra: f64, pb: &Pose, cb: Vec3, rb: f64) -> bool {
    pa.transform_point(ca).distance(pb.transform_point(cb)) > ra + rb
}

/// The generalized winding number of `mesh` at `p`: 1 inside a closed outward mesh, 0 outside, and a
/// graceful value in between for meshes with holes (Jacobson et al. 2013; solid angles by Van Oosterom
/// and Strackee 1983).
pub fn winding_number(mesh: &TriMesh, p: Vec3) -> f64 {
    let v = mesh.vertices();
    let total: f64 = mesh
        .indices()
        .iter()
        .map(|t| {
            let (a, b, c) = (
                v[t[0] as usize] - p,
                v[t[1] as usize] - p,
                v[t[2] as usize] - p,
            );
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let det = a.dot(b.cross(c));
            let div = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
            2.0 * det.atan2(div)
        })
        .sum();
    total / (4.0 * std::f64::consts::PI)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robot::ShapeSource;

    fn element(shape: ShapeSource, at: Vec3) -> GeometryElement {
        GeometryElement {
            origin: Pose::from_translation(at),
            shape,
            line: 1,
        }
    }

    fn cube_mesh(half: f64) -> SoupMesh {
        let v: Vec<Vec3> = (0..8)
            .map(|i| {
                Vec3::new(
                    if i & 1 == 0 { -half } else { half },
                    if i & 2 == 0 { -half } else { half },
                    if i & 4 == 0 { -half } else { half },
                )
            })
            .collect();
        let hull = crate::shapes::convex_hull(&v).unwrap();
        SoupMesh {
            vertices: hull.vertices,
            triangles: hull.faces,
        }
    }

    /// A link made of one cube mesh of half-size `half`.
    fn mesh_link(half: f64) -> ExactLink {
        let e = element(
            ShapeSource::Mesh {
                uri: "cube.stl".into(),
                path: "cube.stl".into(),
                scale: Vec3::ONE,
            },
            Vec3::ZERO,
        );
        ExactLink::new(&[e], |_| ExactMesh::new(cube_mesh(half)))
            .unwrap()
            .unwrap()
    }

    fn at(x: f64) -> Pose {
        Pose::from_translation(Vec3::new(x, 0.0, 0.0))
    }

    #[test]
    fn winding_number_is_one_inside_and_zero_outside() {
        let c = cube_mesh(1.0);
        let m = TriMesh::new(c.vertices, c.triangles).unwrap();
        assert!((winding_number(&m, Vec3::new(0.2, -0.3, 0.5)) - 1.0).abs() < 1e-9);
        assert!(winding_number(&m, Vec3::new(2.5, 0.0, 0.0)).abs() < 1e-9);
    }

    #[test]
    fn a_mesh_inside_a_mesh_overlaps_but_does_not_touch() {
        let (big, small) = (mesh_link(1.0), mesh_link(0.1));
        let home = Pose::IDENTITY;
        // Fully inside: no triangle meets, as FCL and Coal see it; solid bodies overlap.
        assert!(!big.touch(&home, &small, &at(0.3)));
        assert!(big.overlap(&home, &small, &at(0.3)));
        assert!(small.overlap(&at(0.3), &big, &home));
        // Crossing the surface.
        assert!(big.touch(&home, &small, &at(1.0)));
        // Apart.
        assert!(!big.overlap(&home, &small, &at(1.2)));
        // Distances: 0 inside and crossing, the gap between the faces apart.
        assert_eq!(big.distance(&home, &small, &at(0.3)), 0.0);
        assert_eq!(big.distance(&home, &small, &at(1.0)), 0.0);
        assert!((big.distance(&home, &small, &at(1.2)) - 0.1).abs() < 1e-9);
        // Above a caller's `enough`, the same distance; at or below it, none.
        let d = big.distance(&home, &small, &at(1.2));
        assert_eq!(big.distance_above(&home, &small, &at(1.2), 0.05), Some(d));
        assert_eq!(
            big.distance_above(&home, &small, &at(1.2), 0.1 + 1e-6),
            None
        );
        assert_eq!(big.distance_above(&home, &small, &at(0.3), -1.0), Some(0.0));
        assert_eq!(big.distance_above(&home, &small, &at(0.3), 0.0), None);
    }

    #[test]
    fn a_shared_mesh_is_placed_by_each_element_origin() {
        // One cube (half-size 0.1) held by two links: turned 45 degrees about z at x = 0.5, its
        // corner reaches x = 0.5 + 0.1 * sqrt(2); at z = 1, unturned.
        let cube = ExactMesh::new(cube_mesh(0.1)).unwrap().unwrap();
        let link_at = |origin: Pose| {
            let e = GeometryElement {
                origin,
                shape: ShapeSource::Mesh {
                    uri: "cube.stl".into(),
                    path: "cube.stl".into(),
                    scale: Vec3::ONE,
                },
                line: 1,
            };
            ExactLink::new(&[e], |_| Ok(Some(cube.clone())))
                .unwrap()
                .unwrap()
        };
        let turned = Pose::from_translation(Vec3::new(0.5, 0.0, 0.0))
            * Pose::from_rotation(Rotation::from_rotation_z(std::f64::consts::FRAC_PI_4));
        let (a, b) = (link_at(turned), link_at(Pose::from_translation(Vec3::Z)));
        let ball = |p: Vec3| {
            ExactLink::new(&[element(ShapeSource::Sphere { radius: 0.001 }, p)], |_| {
                Ok(None)
            })
            .unwrap()
            .unwrap()
        };
        let home = Pose::IDENTITY;
        // Past the unturned cube's face (x = 0.6), inside the turned one's corner: inside, no touch.
        let inside = ball(Vec3::new(0.63, 0.0, 0.0));
        assert!(a.overlap(&home, &inside, &home));
        assert!(!a.touch(&home, &inside, &home));
        assert!(!b.overlap(&home, &inside, &home));
        let corner = 0.5 + 0.1 * std::f64::consts::SQRT_2;
        let d = a.distance(&home, &ball(Vec3::new(0.7, 0.0, 0.0)), &home);
        assert!((d - (0.7 - corner - 0.001)).abs() < 1e-9, "{d}");
        assert!(b.overlap(&home, &ball(Vec3::new(0.05, 0.0, 1.05)), &home));
        assert!(!b.overlap(&home, &ball(Vec3::new(0.0, 0.0, 1.15)), &home));
    }

    #[test]
    fn primitives_are_exact_not_tessellated() {
        // Two unit spheres 2.001 apart: a circumscribing tessellation would touch, the spheres do not.
        let s = |x| {
            ExactLink::new(
                &[element(
                    ShapeSource::Sphere { radius: 1.0 },
                    Vec3::new(x, 0.0, 0.0),
                )],
                |_| Ok(None),
            )
            .unwrap()
            .unwrap()
        };
        let home = Pose::IDENTITY;
        assert!(!s(0.0).touch(&home, &s(2.001), &home));
        assert!(s(0.0).touch(&home, &s(1.999), &home));
        // A cylinder runs along z: radius 0.1, length 2 reaches z = 1 but not x = 0.5.
        let cyl = ExactLink::new(
            &[element(
                ShapeSource::Cylinder {
                    radius: 0.1,
                    length: 2.0,
                },
                Vec3::ZERO,
            )],
            |_| Ok(None),
        )
        .unwrap()
        .unwrap();
        let ball = |p: Vec3| {
            ExactLink::new(&[element(ShapeSource::Sphere { radius: 0.05 }, p)], |_| {
                Ok(None)
            })
            .unwrap()
            .unwrap()
        };
        assert!(cyl.touch(&home, &ball(Vec3::new(0.0, 0.0, 1.0)), &home));
        assert!(!cyl.touch(&home, &ball(Vec3::new(0.5, 0.0, 0.0)), &home));
        // A primitive wholly inside a mesh overlaps it.
        assert!(mesh_link(1.0).overlap(&home, &ball(Vec3::new(0.2, 0.0, 0.0)), &home));
        assert!(!mesh_link(1.0).touch(&home, &ball(Vec3::new(0.2, 0.0, 0.0)), &home));
    }
}
