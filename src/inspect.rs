//! `scm inspect`: the collision geometry scm loaded for every link, placed at given configurations.
//!
//! For each link: where its geometry came from (`collision`, `visual` under `--visual-fallback`, or
//! none), each geometry element's kind, file and vertex and triangle counts, and per configuration the
//! world-frame axis-aligned box of every element and of the whole link. Boxes are exact: a mesh's are
//! the bounds of its placed vertices, a primitive's those of the true shape (not its tessellation), so
//! they can be compared with what another loader (Pinocchio, MoveIt) builds from the same URDF.

use crate::error::{Error, Result};
use crate::math::{Pose, Vec3};
use crate::mesh::primitive_bounds;
use crate::preprocess::{MeshCache, load_urdd_meshes};
use crate::robot::{GeometryOrigin, Kinematics, ShapeSource};
use crate::urdd::Urdd;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// Everything `scm inspect` reports.
#[derive(Debug, Clone, Serialize)]
pub struct InspectReport {
    /// Robot name.
    pub robot: String,
    /// The sampled degrees of freedom, in configuration order.
    pub dofs: Vec<String>,
    /// Per link (document order), its geometry.
    pub links: Vec<LinkGeometry>,
    /// The configurations asked for, with every link's placed boxes.
    pub configurations: Vec<PlacedConfiguration>,
}

/// One link's collision geometry as scm loaded it.
#[derive(Debug, Clone, Serialize)]
pub struct LinkGeometry {
    /// Link name.
    pub link: String,
    /// Which URDF elements the geometry came from.
    pub source: GeometryOrigin,
    /// The geometry elements, in URDF order.
    pub elements: Vec<ElementInfo>,
}

/// One `<collision>` (or fallback `<visual>`) element.
#[derive(Debug, Clone, Serialize)]
pub struct ElementInfo {
    /// `mesh`, `box`, `cylinder`, `sphere` or `capsule`.
    pub kind: &'static str,
    /// The mesh filename as the URDF writes it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub uri: Option<String>,
    /// The URDF line of the element.
    pub line: u32,
    /// Vertices of the loaded mesh (0 for primitives).
    pub vertices: usize,
    /// Triangles of the loaded mesh (0 for primitives).
    pub triangles: usize,
}

/// Axis-aligned bounds, metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Aabb {
    /// Lower corner.
    pub min: [f64; 3],
    /// Upper corner.
    pub max: [f64; 3],
}

impl Aabb {
    fn new((min, max): (Vec3, Vec3)) -> Aabb {
        Aabb {
            min: min.to_array(),
            max: max.to_array(),
        }
    }

    fn union(self, other: Aabb) -> Aabb {
        Aabb {
            min: std::array::from_fn(|i| self.min[i].min(other.min[i])),
            max: std::array::from_fn(|i| self.max[i].max(other.max[i])),
        }
    }
}

/// One configuration and what it places.
#[derive(Debug, Clone, Serialize)]
pub struct PlacedConfiguration {
    /// The DOF values.
    pub q: Vec<f64>,
    /// Every movable joint's value by name, mimic joints included.
    pub joints: BTreeMap<String, f64>,
    /// Per link with geometry, its world pose and boxes.
    pub links: Vec<PlacedLink>,
}

/// A link's geometry at one configuration.
#[derive(Debug, Clone, Serialize)]
pub struct PlacedLink {
    /// Link name.
    pub link: String,
    /// The link frame's position in the root frame.
    pub position: [f64; 3],
    /// The link frame's orientation, quaternion `[x, y, z, w]`.
    pub rotation: [f64; 4],
    /// The world box of each element, in element order.
    pub elements: Vec<Aabb>,
    /// The world box of all of them.
    pub bounds: Aabb,
}

/// Which configurations to place the geometry at.
#[derive(Debug, Clone)]
pub enum Configurations {
    /// The home configuration.
    Home,
    /// These, one value per DOF each.
    Given(Vec<Vec<f64>>),
    /// `count` configurations uniform within the limits, from `seed` (the bench's stream).
    Random {
        /// How many.
        count: usize,
        /// Seed.
        seed: u64,
    },
}

/// Loads a preprocessed URDD's robot and meshes and places every link's geometry.
pub fn inspect(dir: &Path, which: &Configurations) -> Result<InspectReport> {
    let urdd = Urdd::open(dir)?;
    urdd.fresh_stage(crate::urdd::PREPROCESS)?;
    let record = urdd.robot()?;
    let robot = &record.robot;
    let meshes = load_urdd_meshes(&urdd, robot)?;
    let kinematics = Kinematics::new(robot);
    let dofs = kinematics.dofs();
    let configs = match which {
        Configurations::Home => vec![kinematics.home()],
        Configurations::Given(list) => list.clone(),
        Configurations::Random { count, seed } => crate::bench::configurations(dofs, *seed, *count),
    };
    for q in &configs {
        if q.len() != dofs.len() || q.iter().any(|v| !v.is_finite()) {
            return Err(Error::input(
                Path::new("command line"),
                "--config",
                format!(
                    "expected {} finite joint values (one per DOF: {}), got {}",
                    dofs.len(),
                    dofs.iter()
                        .map(|d| d.name.as_str())
                        .collect::<Vec<_>>()
                        .join(" "),
                    q.len()
                ),
            ));
        }
    }
    let links = robot
        .links
        .iter()
        .map(|l| LinkGeometry {
            link: l.name.clone(),
            source: l.geometry_source,
            elements: l
                .geometry
                .iter()
                .map(|g| element_info(&g.shape, g.line, &meshes))
                .collect(),
        })
        .collect();
    let configurations = configs
        .iter()
        .map(|q| {
            let poses = kinematics.link_poses(q);
            let values = kinematics.joint_values(q);
            let joints = robot
                .joints
                .iter()
                .zip(values)
                .filter(|(j, _)| j.kind.is_actuated())
                .map(|(j, v)| (j.name.clone(), v))
                .collect();
            let links = robot
                .links
                .iter()
                .zip(&poses)
                .filter(|(l, _)| !l.geometry.is_empty())
                .map(|(l, pose)| {
                    let elements: Vec<Aabb> = l
                        .geometry
                        .iter()
                        .map(|g| element_bounds(&g.shape, &(*pose * g.origin), &meshes))
                        .collect();
                    let bounds = elements[1..]
                        .iter()
                        .fold(elements[0], |acc, b| acc.union(*b));
                    PlacedLink {
                        link: l.name.clone(),
                        position: pose.translation.to_array(),
                        rotation: pose.rotation.to_array(),
                        elements,
                        bounds,
                    }
                })
                .collect();
            PlacedConfiguration {
                q: q.clone(),
                joints,
                links,
            }
        })
        .collect();
    Ok(InspectReport {
        robot: robot.name.clone(),
        dofs: dofs.iter().map(|d| d.name.clone()).collect(),
        links,
        configurations,
    })
}

fn element_info(shape: &ShapeSource, line: u32, meshes: &MeshCache) -> ElementInfo {
    let (kind, uri, mesh) = match shape {
        ShapeSource::Mesh { uri, path, .. } => ("mesh", Some(uri.clone()), meshes.get(path)),
        ShapeSource::Box { .. } => ("box", None, None),
        ShapeSource::Cylinder { .. } => ("cylinder", None, None),
        ShapeSource::Sphere { .. } => ("sphere", None, None),
        ShapeSource::Capsule { .. } => ("capsule", None, None),
    };
    ElementInfo {
        kind,
        uri,
        line,
        vertices: mesh.map_or(0, |m| m.mesh.vertices.len()),
        triangles: mesh.map_or(0, |m| m.mesh.triangles.len()),
    }
}

/// The exact world box of one element placed by `pose` (the element's origin already applied).
fn element_bounds(shape: &ShapeSource, pose: &Pose, meshes: &MeshCache) -> Aabb {
    let point = (pose.translation, pose.translation);
    match shape {
        ShapeSource::Mesh { path, scale, .. } => {
            let placed: Vec<Vec3> = meshes
                .get(path)
                .map(|m| {
                    m.mesh
                        .vertices
                        .iter()
                        .map(|v| pose.transform_point(*v * *scale))
                        .collect()
                })
                .unwrap_or_default();
            Aabb::new(crate::math::bounds(&placed).unwrap_or(point))
        }
        primitive => Aabb::new(primitive_bounds(primitive, pose).unwrap_or(point)),
    }
}
