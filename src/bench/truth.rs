//! The ground truth of table 3: the robot's original link geometry as triangle meshes, checked exactly
//! against each other at a configuration.
//!
//! What counts: two links collide when their meshes' surfaces intersect (parry's triangle-mesh
//! intersection test: a bounding-volume traversal, then a GJK test per pair of overlapping triangles,
//! with no approximating shape in between) or when one mesh lies entirely inside the other (a
//! vertex of one is inside the other by its generalized winding number, which stays meaningful for
//! meshes that are not watertight).
//!
//! Which link pairs count: pairs of different links with geometry that are not adjacent and whose
//! meshes do not collide at the home configuration. Adjacent links' meshes touch or overlap at their
//! joint, and links whose meshes already overlap at home are built into each other (a motor housing
//! inside a trunk box); these are design contacts, not self-collisions, which is why MoveIt's rules
//! skip them too (`Adjacent`, `Default`). Counting them would make nearly every configuration a
//! collision (on B1, every one).

use crate::error::{Error, Result};
use crate::math::{Pose, Vec3};
use crate::preprocess::{link_mesh, load_urdd_meshes};
use crate::robot::Kinematics;
use crate::shapes::minimal_bounding_sphere;
use crate::urdd::Urdd;
use parry3d_f64::bounding_volume::BoundingVolume;
use parry3d_f64::query;
use parry3d_f64::shape::TriMesh;

/// One link's original geometry, ready for exact tests.
struct LinkMesh {
    mesh: TriMesh,
    /// One vertex of each of the link's geometry elements (each is one connected part, as a rule).
    probes: Vec<Vec3>,
    /// Bounding sphere in the link frame.
    center: Vec3,
    radius: f64,
}

/// The meshes of every link with geometry and the link pairs the ground truth checks.
pub struct MeshTruth {
    links: Vec<Option<LinkMesh>>,
    /// Pairs `(a, b)`, `a < b`, of non-adjacent links that both have geometry and whose meshes do not
    /// collide at home.
    pairs: Vec<(usize, usize)>,
    /// Non-adjacent pairs whose meshes collide at home (left out).
    at_home: Vec<(usize, usize)>,
}

impl std::fmt::Debug for MeshTruth {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeshTruth")
            .field("pairs", &self.pairs.len())
            .finish_non_exhaustive()
    }
}

impl MeshTruth {
    /// Loads the original link geometry the way the preprocess stage does (mesh files as recorded in
    /// `robot.json`, primitives tessellated so they circumscribe the true shape).
    pub fn load(urdd: &Urdd) -> Result<MeshTruth> {
        let record = urdd.robot()?;
        let robot = &record.robot;
        let meshes = load_urdd_meshes(urdd, robot)?;
        let mut links = Vec::with_capacity(robot.links.len());
        for link in &robot.links {
            // The link's elements one by one, remembering where each starts: one probe vertex per
            // element for the containment test.
            let mut soup = crate::mesh::TriMesh::default();
            let mut probes = Vec::new();
            for g in &link.geometry {
                let single = crate::robot::Link {
                    geometry: vec![g.clone()],
                    ..link.clone()
                };
                let part = link_mesh(&single, &meshes);
                if let Some(&v) = part.vertices.first() {
                    probes.push(v);
                }
                soup.append_transformed(&part, &Pose::IDENTITY, Vec3::ONE);
            }
            if soup.triangles.is_empty() {
                links.push(None);
                continue;
            }
            let sphere = minimal_bounding_sphere(&soup.vertices);
            let mesh = TriMesh::new(soup.vertices, soup.triangles).map_err(|e| Error::Failed {
                context: format!("link \"{}\": triangle mesh", link.name),
                message: e.to_string(),
            })?;
            links.push(Some(LinkMesh {
                mesh,
                probes,
                center: sphere.center,
                radius: sphere.radius,
            }));
        }
        let adjacent: Vec<(usize, usize)> = robot.adjacent_pairs();
        let n = links.len();
        let pairs = (0..n)
            .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
            .filter(|&(a, b)| links[a].is_some() && links[b].is_some())
            .filter(|&(a, b)| !adjacent.contains(&(a, b)) && !adjacent.contains(&(b, a)))
            .collect();
        let mut truth = MeshTruth {
            links,
            pairs,
            at_home: Vec::new(),
        };
        let kinematics = Kinematics::new(robot);
        let home = kinematics.link_poses(&kinematics.home());
        truth.at_home = truth.colliding(&home);
        truth.pairs.retain(|p| !truth.at_home.contains(p));
        Ok(truth)
    }

    /// Non-adjacent link pairs left out because their meshes collide at the home configuration.
    pub fn at_home(&self) -> &[(usize, usize)] {
        &self.at_home
    }

    /// The link pairs the ground truth checks.
    pub fn pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }

    /// The checked link pairs whose meshes collide with link poses `poses`, in order.
    pub fn colliding(&self, poses: &[Pose]) -> Vec<(usize, usize)> {
        self.pairs
            .iter()
            .copied()
            .filter(|&(a, b)| self.collide(a, &poses[a], b, &poses[b]))
            .collect()
    }

    fn collide(&self, a: usize, pa: &Pose, b: usize, pb: &Pose) -> bool {
        let (Some(ma), Some(mb)) = (&self.links[a], &self.links[b]) else {
            return false;
        };
        let gap = pa
            .transform_point(ma.center)
            .distance(pb.transform_point(mb.center))
            - ma.radius
            - mb.radius;
        if gap > 0.0 || !ma.mesh.aabb(pa).intersects(&mb.mesh.aabb(pb)) {
            return false;
        }
        // Both shapes are triangle meshes, which the default dispatcher supports.
        let surfaces = query::intersection_test(pa, &ma.mesh, pb, &mb.mesh)
            .map(|r| r.intersecting)
            .unwrap_or(false);
        surfaces || inside(ma, pa, mb, pb) || inside(mb, pb, ma, pa)
    }
}

/// Whether some part of `a` (posed at `pa`) lies inside `b` (posed at `pb`), given that their surfaces
/// do not intersect: then each connected part of `a` is wholly inside `b` or wholly outside, so one
/// vertex per part decides (one per URDF geometry element).
fn inside(a: &LinkMesh, pa: &Pose, b: &LinkMesh, pb: &Pose) -> bool {
    a.probes.iter().any(|&v| {
        let p = pb.inverse_transform_point(pa.transform_point(v));
        b.mesh.local_aabb().contains_local_point(p) && winding_number(&b.mesh, p).abs() > 0.5
    })
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

    fn cube(half: f64) -> TriMesh {
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
        TriMesh::new(hull.vertices, hull.faces).unwrap()
    }

    #[test]
    fn winding_number_is_one_inside_and_zero_outside() {
        let m = cube(1.0);
        assert!((winding_number(&m, Vec3::new(0.2, -0.3, 0.5)) - 1.0).abs() < 1e-9);
        assert!(winding_number(&m, Vec3::new(2.5, 0.0, 0.0)).abs() < 1e-9);
    }

    #[test]
    fn containment_counts_as_collision() {
        let big = LinkMesh {
            probes: vec![Vec3::splat(-1.0)],
            mesh: cube(1.0),
            center: Vec3::ZERO,
            radius: 3f64.sqrt(),
        };
        let small = LinkMesh {
            probes: vec![Vec3::splat(-0.1)],
            mesh: cube(0.1),
            center: Vec3::ZERO,
            radius: 0.1 * 3f64.sqrt(),
        };
        let truth = MeshTruth {
            links: vec![Some(big), Some(small)],
            pairs: vec![(0, 1)],
            at_home: Vec::new(),
        };
        let at = |x: f64| {
            [
                Pose::IDENTITY,
                Pose::from_translation(Vec3::new(x, 0.0, 0.0)),
            ]
        };
        // Fully inside: no surface intersection, still a collision.
        assert_eq!(truth.colliding(&at(0.3)), vec![(0, 1)]);
        // Crossing the surface.
        assert_eq!(truth.colliding(&at(1.0)), vec![(0, 1)]);
        // Apart.
        assert!(truth.colliding(&at(1.2)).is_empty());
    }
}
