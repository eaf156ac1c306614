//! The JSON records a URDD holds besides the manifest: the robot model and the per-type shape lists.

use crate::math::{Rotation, Vec3};
use crate::robot::{Dof, Robot};
use crate::shapes::{LinkFit, ShapeType};
use serde::{Deserialize, Serialize};

/// `preprocess/robot.json`: the robot model, its degrees of freedom and link adjacency.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RobotRecord {
    /// Format version of this file.
    pub format_version: u32,
    /// Links, joints, limits and geometry sources.
    pub robot: Robot,
    /// The sampled degrees of freedom.
    pub dofs: Vec<Dof>,
    /// Adjacent link pairs by name (MoveIt's rule), sorted.
    pub adjacent: Vec<[String; 2]>,
}

/// `preprocess/links.json`: per link, how many shapes it has and how well each type fits.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LinkRecord {
    /// Link name.
    pub link: String,
    /// Link index in the robot.
    pub link_index: usize,
    /// Where the geometry came from (`collision` or `visual`).
    pub geometry: crate::robot::GeometryOrigin,
    /// Fit statistics of the six types.
    pub fit: LinkFit,
}

/// `preprocess/shapes/<type>.json`: the ordered shape list of one type.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ShapeFile {
    /// Format version of this file.
    pub format_version: u32,
    /// The shape type.
    pub shape_type: ShapeType,
    /// Shapes in matrix order (sorted by link index, then piece).
    pub shapes: Vec<ShapeRecord>,
}

/// One shape: its place in the matrix, its link and piece, and its geometry in the link frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShapeRecord {
    /// Row/column of this shape in the type's matrices.
    pub index: usize,
    /// Link name.
    pub link: String,
    /// Link index in the robot.
    pub link_index: usize,
    /// Decomposition piece (0 for whole-link types).
    pub piece: usize,
    /// Geometry parameters in the link frame.
    pub geometry: GeometryRecord,
}

/// Geometry parameters as stored on disk; hulls live in OBJ files beside the JSON.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum GeometryRecord {
    /// A sphere.
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius.
        radius: f64,
    },
    /// An oriented box; `rotation` is a unit quaternion `[x, y, z, w]` whose columns are the box axes.
    Obb {
        /// Centre.
        center: Vec3,
        /// Orientation.
        rotation: Rotation,
        /// Half extents along the box axes.
        half_extents: Vec3,
    },
    /// A convex polyhedron stored as an OBJ file.
    Hull {
        /// OBJ path relative to the stage folder.
        mesh: String,
        /// Vertex count.
        vertices: usize,
        /// Triangle count.
        faces: usize,
        /// Enclosed volume (m^3).
        volume: f64,
    },
}
