//! The robot model: links, joints, their collision geometry sources, and the kinematic tree.

mod adjacency;
mod kinematics;
mod packages;
mod tree;
mod urdf;

pub use kinematics::{Configuration, Dof, Kinematics, PairChains, PathJoint, random_configuration};
pub use packages::PackagePaths;
pub use urdf::{MAX_MAGNITUDE, UrdfOptions, load_urdf, parse_urdf, rpy_to_rotation};

use crate::math::{Pose, Vec3};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// A robot read from a URDF: links, joints and the tree between them.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Robot {
    /// The `<robot name>`.
    pub name: String,
    /// Links in document order.
    pub links: Vec<Link>,
    /// Joints in document order.
    pub joints: Vec<Joint>,
    /// Index of the root link (the one link that is no joint's child).
    pub root: usize,
    /// Notes about leniencies applied while reading (e.g. visual geometry used for collision).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// One `<link>` and the geometry used for its collision shapes.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Link {
    /// The link name.
    pub name: String,
    /// The geometry elements the shapes are built from (collision, or visual as a fallback).
    pub geometry: Vec<GeometryElement>,
    /// Where `geometry` came from.
    pub geometry_source: GeometryOrigin,
    /// The joint whose child this link is (`None` for the root).
    pub parent_joint: Option<usize>,
}

/// Which URDF elements a link's geometry was taken from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GeometryOrigin {
    /// The link's `<collision>` elements.
    Collision,
    /// The link had no `<collision>`; its `<visual>` elements were used instead.
    Visual,
    /// The link has no geometry at all.
    None,
}

/// One `<collision>` (or `<visual>`) element: a shape placed in the link frame.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct GeometryElement {
    /// Pose of the shape in the link frame.
    pub origin: Pose,
    /// The shape.
    pub shape: ShapeSource,
    /// Line of the element in the URDF, for error messages.
    pub line: u32,
}

/// A URDF `<geometry>`: a primitive or a mesh file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case")]
pub enum ShapeSource {
    /// `<box size>`: full edge lengths.
    Box {
        /// Edge lengths along x, y, z.
        size: Vec3,
    },
    /// `<cylinder radius length>` along z.
    Cylinder {
        /// Radius.
        radius: f64,
        /// Length along z.
        length: f64,
    },
    /// `<sphere radius>`.
    Sphere {
        /// Radius.
        radius: f64,
    },
    /// `<capsule radius length>` along z (length of the cylindrical part).
    Capsule {
        /// Radius.
        radius: f64,
        /// Length of the cylinder between the two hemispheres.
        length: f64,
    },
    /// `<mesh filename scale>`.
    Mesh {
        /// The filename as written in the URDF.
        uri: String,
        /// The resolved path on disk.
        path: PathBuf,
        /// Per-axis scale.
        scale: Vec3,
    },
}

/// One `<joint>`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Joint {
    /// The joint name.
    pub name: String,
    /// The joint type.
    pub kind: JointKind,
    /// Parent link index.
    pub parent: usize,
    /// Child link index.
    pub child: usize,
    /// Pose of the joint frame in the parent link frame.
    pub origin: Pose,
    /// Unit axis in the joint frame.
    pub axis: Vec3,
    /// Position limits (revolute, prismatic); `None` for joints without a range.
    pub limits: Option<Limits>,
    /// Set when this joint follows another.
    pub mimic: Option<Mimic>,
}

/// Joint types of URDF.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum JointKind {
    /// Rotation about the axis within limits.
    Revolute,
    /// Rotation about the axis without limits (sampled over a full turn).
    Continuous,
    /// Translation along the axis within limits.
    Prismatic,
    /// No motion.
    Fixed,
    /// Six degrees of freedom; held at identity for self-collision.
    Floating,
    /// Motion in a plane; held at identity for self-collision.
    Planar,
}

impl JointKind {
    /// Whether the joint contributes a sampled degree of freedom (unless it is a mimic).
    pub fn is_actuated(self) -> bool {
        matches!(
            self,
            JointKind::Revolute | JointKind::Continuous | JointKind::Prismatic
        )
    }
}

/// Lower and upper position limits.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Limits {
    /// Lower limit (rad or m).
    pub lower: f64,
    /// Upper limit (rad or m).
    pub upper: f64,
}

/// `<mimic>`: value = multiplier * leader + offset.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Mimic {
    /// Index of the leader joint.
    pub joint: usize,
    /// Multiplier.
    pub multiplier: f64,
    /// Offset.
    pub offset: f64,
}

impl Robot {
    /// Index of the link with this name.
    pub fn link_index(&self, name: &str) -> Option<usize> {
        self.links.iter().position(|l| l.name == name)
    }

    /// Index of the joint with this name.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// Checks that the links and joints form one tree rooted at `root` with every index in range, as
    /// the URDF reader guarantees; for records read back from disk. The error says what is wrong.
    pub fn check_tree(&self) -> std::result::Result<(), String> {
        let (links, joints) = (self.links.len(), self.joints.len());
        if self.root >= links {
            return Err(format!("root link {} of {links} does not exist", self.root));
        }
        for (i, j) in self.joints.iter().enumerate() {
            if j.parent >= links || j.child >= links || j.parent == j.child {
                return Err(format!("joint \"{}\" names links out of range", j.name));
            }
            if self.links[j.child].parent_joint != Some(i) {
                return Err(format!(
                    "joint \"{}\" is not its child link's parent joint",
                    j.name
                ));
            }
            if j.mimic
                .is_some_and(|m| m.joint >= joints || self.joints[m.joint].mimic.is_some())
            {
                return Err(format!("joint \"{}\" mimics a joint out of range", j.name));
            }
        }
        for (i, link) in self.links.iter().enumerate() {
            match link.parent_joint {
                None if i != self.root => {
                    return Err(format!(
                        "link \"{}\" has no parent but is not the root",
                        link.name
                    ));
                }
                Some(j) if j >= joints || self.joints[j].child != i => {
                    return Err(format!("link \"{}\" names a wrong parent joint", link.name));
                }
                _ => {}
            }
            let mut at = i;
            for _ in 0..=joints {
                match self.links[at].parent_joint {
                    Some(j) => at = self.joints[j].parent,
                    None => break,
                }
            }
            if at != self.root {
                return Err(format!(
                    "link \"{}\" does not hang from the root (a cycle)",
                    link.name
                ));
            }
        }
        Ok(())
    }

    /// Pairs of links (index order, `a < b`) that a collision check treats as adjacent: joined by a joint,
    /// possibly bridged through links that have no geometry (MoveIt's rule). Only links with geometry appear.
    pub fn adjacent_pairs(&self) -> Vec<(usize, usize)> {
        adjacency::adjacent_pairs(self)
    }
}
