//! A lenient URDF reader on roxmltree, as forgiving as ROS's own parser and precise in its error messages.
//!
//! Only direct `<robot>` children count as links and joints, so `<joint>` inside `<transmission>` or
//! `<gazebo>` is ignored. `<limit>` needs no `velocity`/`effort`, `<axis>` without `xyz` means 1 0 0, and
//! `<material>` elements are ignored wherever they are.
//!
//! A link's collision geometry is its `<collision>` elements, as MoveIt, Pinocchio, MuJoCo and Drake
//! read it: a link without one has none, unless [`UrdfOptions::visual_fallback`] asks for its `<visual>`
//! elements instead. A file that still needs xacro is refused with the command that expands it.

mod geometry;

use super::packages::PackagePaths;
use super::{Joint, JointKind, Limits, Link, Mimic, Robot};
use crate::error::{Error, Result};
use crate::math::{Pose, Rotation, Vec3};
use roxmltree::{Document, Node};
use std::collections::HashMap;
use std::path::Path;

/// How a URDF is read.
#[derive(Debug, Clone, Default)]
pub struct UrdfOptions {
    /// Where `package://` and `model://` point.
    pub packages: PackagePaths,
    /// Give a link without `<collision>` its `<visual>` geometry (no consumer does; off by default).
    pub visual_fallback: bool,
}

/// Reads and validates the URDF at `path`.
pub fn load_urdf(path: &Path, options: &UrdfOptions) -> Result<Robot> {
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xacro"))
    {
        return Err(xacro_error(path, "file", "is a xacro file"));
    }
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error::input(path, "file", format!("cannot read: {e}")))?;
    parse_urdf(&text, path, options)
}

/// Parses URDF `text` read from `path` (used for error messages and relative mesh paths).
pub fn parse_urdf(text: &str, path: &Path, options: &UrdfOptions) -> Result<Robot> {
    let doc = Document::parse(text).map_err(|e| {
        let pos = e.pos();
        let element = format!("line {}, column {}", pos.row, pos.col);
        match e {
            roxmltree::Error::UnknownNamespace(prefix, _) if prefix == "xacro" => {
                xacro_error(path, element, "uses xacro: elements")
            }
            e => Error::input(path, element, format!("malformed XML: {e}")),
        }
    })?;
    if let Some(node) = doc
        .descendants()
        .find(|n| n.is_element() && n.tag_name().namespace().is_some_and(is_xacro_ns))
    {
        let line = doc.text_pos_at(node.range().start).row;
        return Err(xacro_error(
            path,
            format!("<xacro:{}> (line {line})", node.tag_name().name()),
            "uses xacro: elements",
        ));
    }
    let reader = Reader {
        doc: &doc,
        path,
        visual_fallback: options.visual_fallback,
    };
    reader.robot(&options.packages)
}

/// Whether a namespace URI is xacro's (`http://www.ros.org/wiki/xacro` and its spellings).
fn is_xacro_ns(uri: &str) -> bool {
    uri.trim_end_matches('/').ends_with("/xacro")
}

/// The one line that says a file needs xacro first, and how.
fn xacro_error(path: &Path, element: impl Into<String>, what: &str) -> Error {
    Error::input(
        path,
        element,
        format!(
            "the file {what}: expand it to plain URDF first, for example `xacro {} > robot.urdf` \
             (xacro comes with ROS, or `pip install xacro`), then give scm robot.urdf",
            path.display()
        ),
    )
}

/// The largest magnitude any URDF number may have (metres, radians, scale factors): a bound far past
/// any robot, under which every distance and its square stay exact enough in f64.
pub const MAX_MAGNITUDE: f64 = 1e6;

struct Reader<'a, 'input> {
    doc: &'a Document<'input>,
    path: &'a Path,
    visual_fallback: bool,
}

impl<'a, 'input> Reader<'a, 'input> {
    fn line(&self, node: Node) -> u32 {
        self.doc.text_pos_at(node.range().start).row
    }

    /// `<tag name="...">` (line N)
    fn describe(&self, node: Node) -> String {
        match node.attribute("name") {
            Some(name) => format!(
                "<{} name=\"{}\"> (line {})",
                node.tag_name().name(),
                name,
                self.line(node)
            ),
            None => format!("<{}> (line {})", node.tag_name().name(), self.line(node)),
        }
    }

    fn err(&self, node: Node, message: impl Into<String>) -> Error {
        Error::input(self.path, self.describe(node), message)
    }

    fn child<'n>(&self, node: Node<'n, 'input>, tag: &str) -> Option<Node<'n, 'input>> {
        node.children()
            .find(|c| c.is_element() && c.tag_name().name() == tag)
    }

    fn children<'n>(
        &self,
        node: Node<'n, 'input>,
        tag: &'static str,
    ) -> impl Iterator<Item = Node<'n, 'input>> {
        node.children()
            .filter(move |c| c.is_element() && c.tag_name().name() == tag)
    }

    fn required<'n>(&self, node: Node<'n, 'input>, attr: &str) -> Result<&'n str> {
        node.attribute(attr)
            .ok_or_else(|| self.err(node, format!("missing attribute `{attr}`")))
    }

    fn number(&self, node: Node, attr: &str, text: &str) -> Result<f64> {
        let v: f64 = text.trim().parse().map_err(|_| {
            self.err(
                node,
                format!("attribute `{attr}`: `{text}` is not a number"),
            )
        })?;
        if !v.is_finite() {
            Err(self.err(node, format!("attribute `{attr}`: `{text}` is not finite")))
        } else if v.abs() > MAX_MAGNITUDE {
            Err(self.err(
                node,
                format!(
                    "attribute `{attr}`: `{text}` is beyond ±{MAX_MAGNITUDE:e} (no robot measures \
                     that in metres or radians; scm cannot compute with it)"
                ),
            ))
        } else {
            Ok(v)
        }
    }

    fn optional_number(&self, node: Node, attr: &str, default: f64) -> Result<f64> {
        match node.attribute(attr) {
            Some(text) => self.number(node, attr, text),
            None => Ok(default),
        }
    }

    fn required_number(&self, node: Node, attr: &str) -> Result<f64> {
        let text = self.required(node, attr)?;
        self.number(node, attr, text)
    }

    fn vec3(&self, node: Node, attr: &str, default: Vec3) -> Result<Vec3> {
        let Some(text) = node.attribute(attr) else {
            return Ok(default);
        };
        let parts: Vec<&str> = text.split_whitespace().collect();
        if parts.len() != 3 {
            return Err(self.err(
                node,
                format!("attribute `{attr}`: expected 3 numbers, got `{text}`"),
            ));
        }
        Ok(Vec3::new(
            self.number(node, attr, parts[0])?,
            self.number(node, attr, parts[1])?,
            self.number(node, attr, parts[2])?,
        ))
    }

    /// `<origin xyz rpy>` child of `node`, identity when absent.
    fn origin(&self, node: Node) -> Result<Pose> {
        let Some(o) = self.child(node, "origin") else {
            return Ok(Pose::IDENTITY);
        };
        let xyz = self.vec3(o, "xyz", Vec3::ZERO)?;
        let rpy = self.vec3(o, "rpy", Vec3::ZERO)?;
        Ok(Pose::from_parts(xyz, rpy_to_rotation(rpy)))
    }

    fn robot(&self, packages: &PackagePaths) -> Result<Robot> {
        let root = self.doc.root_element();
        if root.tag_name().name() != "robot" {
            return Err(self.err(root, "the root element must be <robot>"));
        }
        let name = root.attribute("name").unwrap_or("robot").to_string();
        let mut warnings = Vec::new();

        let mut links: Vec<Link> = Vec::new();
        let mut link_index: HashMap<&str, usize> = HashMap::new();
        for node in self.children(root, "link") {
            let link_name = self.required(node, "name")?;
            if link_index.insert(link_name, links.len()).is_some() {
                return Err(self.err(node, "duplicate link name"));
            }
            links.push(self.link(node, packages, &mut warnings)?);
        }
        if links.is_empty() {
            return Err(self.err(root, "the robot has no <link>"));
        }

        let joint_nodes: Vec<Node> = self.children(root, "joint").collect();
        let mut joint_index: HashMap<&str, usize> = HashMap::new();
        for (i, node) in joint_nodes.iter().enumerate() {
            let joint_name = self.required(*node, "name")?;
            if joint_index.insert(joint_name, i).is_some() {
                return Err(self.err(*node, "duplicate joint name"));
            }
        }
        let mut joints = Vec::with_capacity(joint_nodes.len());
        for node in &joint_nodes {
            joints.push(self.joint(*node, &link_index, &joint_index)?);
        }
        for (i, joint) in joints.iter().enumerate() {
            let child = &mut links[joint.child];
            if let Some(other) = child.parent_joint {
                return Err(self.err(
                    joint_nodes[i],
                    format!(
                        "link \"{}\" is already the child of joint \"{}\" (a link has one parent; \
                         this closes a cycle)",
                        child.name, joints[other].name
                    ),
                ));
            }
            child.parent_joint = Some(i);
        }
        let roots: Vec<usize> = (0..links.len())
            .filter(|&i| links[i].parent_joint.is_none())
            .collect();
        let root_link = match roots.as_slice() {
            [r] => *r,
            [] => {
                return Err(self.err(
                    root,
                    "every link is a joint's child: the joints form a cycle",
                ));
            }
            many => {
                let names: Vec<&str> = many.iter().map(|&i| links[i].name.as_str()).collect();
                return Err(self.err(
                    root,
                    format!(
                        "several root links (links that are no joint's child): {}",
                        names.join(", ")
                    ),
                ));
            }
        };
        // Every link must hang from the root: walking up from any link has to end there without a loop.
        for start in 0..links.len() {
            let mut at = start;
            let mut steps = 0;
            while let Some(j) = links[at].parent_joint {
                at = joints[j].parent;
                steps += 1;
                if steps > joints.len() {
                    let node = joint_nodes[j];
                    return Err(self.err(node, "the joints form a cycle"));
                }
            }
        }
        resolve_mimic_chains(&mut joints).map_err(|j| {
            self.err(
                joint_nodes[j],
                "<mimic> joints follow each other in a cycle",
            )
        })?;

        Ok(Robot {
            name,
            links,
            joints,
            root: root_link,
            warnings,
        })
    }

    fn joint(
        &self,
        node: Node,
        links: &HashMap<&str, usize>,
        joints: &HashMap<&str, usize>,
    ) -> Result<Joint> {
        let name = self.required(node, "name")?.to_string();
        let type_name = self.required(node, "type")?;
        let kind = match type_name {
            "revolute" => JointKind::Revolute,
            "continuous" => JointKind::Continuous,
            "prismatic" => JointKind::Prismatic,
            "fixed" => JointKind::Fixed,
            "floating" => JointKind::Floating,
            "planar" => JointKind::Planar,
            other => return Err(self.err(node, format!("unknown joint type \"{other}\""))),
        };
        let link_ref = |tag: &str| -> Result<usize> {
            let child = self
                .child(node, tag)
                .ok_or_else(|| self.err(node, format!("missing <{tag} link=\"...\">")))?;
            let link = self
                .required(child, "link")
                .map_err(|_| self.err(node, format!("<{tag}> has no `link` attribute")))?;
            links.get(link).copied().ok_or_else(|| {
                self.err(
                    node,
                    format!("<{tag}> names link \"{link}\", which does not exist"),
                )
            })
        };
        let parent = link_ref("parent")?;
        let child = link_ref("child")?;
        if parent == child {
            return Err(self.err(node, "parent and child are the same link"));
        }
        let origin = self.origin(node)?;
        let axis = match self.child(node, "axis") {
            Some(a) => self.vec3(a, "xyz", Vec3::X)?,
            None => Vec3::X,
        };
        let axis = if kind.is_actuated() || kind == JointKind::Planar {
            let len = axis.length();
            if len < 1e-12 {
                return Err(self.err(node, "<axis xyz> must not be the zero vector"));
            }
            axis / len
        } else {
            axis.normalize_or(Vec3::X)
        };
        let limits = match kind {
            JointKind::Revolute | JointKind::Prismatic => {
                let limit = self.child(node, "limit").ok_or_else(|| {
                    self.err(
                        node,
                        format!("a {type_name} joint needs <limit lower upper>"),
                    )
                })?;
                let lower = self.optional_number(limit, "lower", 0.0)?;
                let upper = self.optional_number(limit, "upper", 0.0)?;
                if lower > upper {
                    return Err(self.err(
                        node,
                        format!("<limit> lower {lower} is above upper {upper}"),
                    ));
                }
                Some(Limits { lower, upper })
            }
            _ => None,
        };
        let mimic = match self.child(node, "mimic") {
            Some(m) => {
                let leader = self.required(m, "joint")?;
                let joint = joints.get(leader).copied().ok_or_else(|| {
                    self.err(
                        node,
                        format!("<mimic> names joint \"{leader}\", which does not exist"),
                    )
                })?;
                Some(Mimic {
                    joint,
                    multiplier: self.optional_number(m, "multiplier", 1.0)?,
                    offset: self.optional_number(m, "offset", 0.0)?,
                })
            }
            None => None,
        };
        Ok(Joint {
            name,
            kind,
            parent,
            child,
            origin,
            axis,
            limits,
            mimic,
        })
    }
}

/// URDF roll-pitch-yaw (fixed axes X, then Y, then Z) as a rotation.
pub fn rpy_to_rotation(rpy: Vec3) -> Rotation {
    Rotation::from_rotation_z(rpy.z)
        * Rotation::from_rotation_y(rpy.y)
        * Rotation::from_rotation_x(rpy.x)
}

/// Rewrites mimic-of-mimic chains so every mimic names an actuated leader directly. Returns the index of a
/// joint in a cycle on failure.
fn resolve_mimic_chains(joints: &mut [Joint]) -> std::result::Result<(), usize> {
    for i in 0..joints.len() {
        let Some(mut m) = joints[i].mimic else {
            continue;
        };
        let mut steps = 0;
        while let Some(next) = joints[m.joint].mimic {
            m = Mimic {
                joint: next.joint,
                multiplier: m.multiplier * next.multiplier,
                offset: m.multiplier * next.offset + m.offset,
            };
            steps += 1;
            if steps > joints.len() {
                return Err(i);
            }
        }
        if m.joint == i {
            return Err(i);
        }
        joints[i].mimic = Some(m);
    }
    Ok(())
}
