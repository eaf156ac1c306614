//! COLLADA (`.dae`) triangles as MoveIt and Pinocchio get them from Assimp.
//!
//! Assimp puts a COLLADA file's `<up_axis>` rotation and its `<unit meter>` scale on the scene's root
//! node; MoveIt (geometric_shapes), RViz's collision display and Pinocchio (Coal) reset or skip that
//! root transform, so neither reaches the geometry they check. Everything below the root is kept: the
//! nodes of the instanced `<visual_scene>` with their transforms (`<matrix>`, `<translate>`, `<rotate>`,
//! `<scale>`, `<lookat>`; `<skew>` is ignored, as Assimp does), nested `<node>`s, `<instance_node>`,
//! and every `<instance_geometry>`, a geometry instanced twice counting twice. Geometry that no node
//! instances is not part of the scene. `<triangles>`, `<polylist>`, `<polygons>` (holes dropped),
//! `<trifans>` and `<tristrips>` become triangles (polygons as fans); `<lines>` and `<linestrips>` are
//! ignored, as Coal drops line primitives.

use super::TriMesh;
use crate::math::{Mat3, Vec3};
use roxmltree::{Document, Node};
use std::collections::HashMap;

/// How deep `<node>` and `<instance_node>` may nest (a cycle of instance_nodes would never end).
const MAX_DEPTH: usize = 256;
/// Most nodes one file may place, counting every instance: nodes that instance each other twice over
/// multiply like XML entities in a "billion laughs" file.
const MAX_NODES: usize = 1_000_000;
/// Most triangle corners one file may place, for the same reason (240 MB of vertices; robot meshes
/// hold well under a million).
const MAX_CORNERS: usize = 10_000_000;

/// A COLLADA file's triangles in the file's own units, and notes on what was ignored.
pub struct Collada {
    /// The instanced triangles.
    pub mesh: TriMesh,
    /// What the consumers ignore and scm ignored with them (`<unit>`, `<up_axis>`, controllers).
    pub notes: Vec<String>,
}

/// Reads the triangles of the COLLADA document in `bytes`.
pub fn read_collada(bytes: &[u8]) -> Result<Collada, String> {
    let text = std::str::from_utf8(bytes).map_err(|e| format!("not UTF-8 text: {e}"))?;
    let doc = Document::parse(text).map_err(|e| format!("malformed XML: {e}"))?;
    let root = doc.root_element();
    if root.tag_name().name() != "COLLADA" {
        return Err(format!(
            "the root element is <{}>, not <COLLADA>",
            root.tag_name().name()
        ));
    }
    let mut reader = Reader {
        doc: &doc,
        ids: HashMap::new(),
        mesh: TriMesh::default(),
        notes: Vec::new(),
        visits: 0,
    };
    for node in root.descendants().filter(Node::is_element) {
        if let Some(id) = node.attribute("id") {
            reader.ids.entry(id).or_insert(node);
        }
    }
    reader.asset_notes(root);
    let scene = reader.visual_scene(root)?;
    for node in elements(scene, "node") {
        reader.node(node, Affine::IDENTITY, 0)?;
    }
    let Reader {
        mut mesh, notes, ..
    } = reader;
    mesh.compact();
    Ok(Collada { mesh, notes })
}

/// An affine map: `m * p + t`.
#[derive(Debug, Clone, Copy)]
struct Affine {
    m: Mat3,
    t: Vec3,
}

impl Affine {
    const IDENTITY: Affine = Affine {
        m: Mat3::IDENTITY,
        t: Vec3::ZERO,
    };

    /// `self` after `other`: first `other`, then `self`.
    fn then(self, other: Affine) -> Affine {
        Affine {
            m: self.m * other.m,
            t: self.m * other.t + self.t,
        }
    }

    fn apply(&self, p: Vec3) -> Vec3 {
        self.m * p + self.t
    }
}

struct Reader<'a, 'input> {
    doc: &'a Document<'input>,
    /// Every element with an `id`, for `url="#id"` and `source="#id"`.
    ids: HashMap<&'a str, Node<'a, 'input>>,
    mesh: TriMesh,
    notes: Vec<String>,
    /// Nodes placed so far.
    visits: usize,
}

/// The element children of `node` named `tag`.
fn elements<'a, 'input>(
    node: Node<'a, 'input>,
    tag: &'static str,
) -> impl Iterator<Item = Node<'a, 'input>> {
    node.children()
        .filter(move |c| c.is_element() && c.tag_name().name() == tag)
}

fn element<'a, 'input>(node: Node<'a, 'input>, tag: &'static str) -> Option<Node<'a, 'input>> {
    elements(node, tag).next()
}

/// The numbers of an element's text.
fn numbers<T: std::str::FromStr>(node: Node, what: &str) -> Result<Vec<T>, String> {
    node.text()
        .unwrap_or("")
        .split_ascii_whitespace()
        .map(|s| {
            s.parse::<T>()
                .map_err(|_| format!("<{what}>: `{s}` is not a valid number"))
        })
        .collect()
}

fn floats(node: Node, what: &str, count: usize) -> Result<Vec<f64>, String> {
    let v: Vec<f64> = numbers(node, what)?;
    if v.len() != count {
        return Err(format!("<{what}> needs {count} numbers, has {}", v.len()));
    }
    if v.iter().any(|x| !x.is_finite()) {
        return Err(format!("<{what}> holds a NaN or infinite number"));
    }
    Ok(v)
}

impl<'a, 'input> Reader<'a, 'input> {
    fn line(&self, node: Node) -> u32 {
        self.doc.text_pos_at(node.range().start).row
    }

    /// `<tag id="..."> (line N)` for messages.
    fn describe(&self, node: Node) -> String {
        match node.attribute("id") {
            Some(id) => format!(
                "<{} id=\"{id}\"> (line {})",
                node.tag_name().name(),
                self.line(node)
            ),
            None => format!("<{}> (line {})", node.tag_name().name(), self.line(node)),
        }
    }

    /// The element a `#id` reference names.
    fn target(&self, node: Node, attr: &str) -> Result<Node<'a, 'input>, String> {
        let url = node
            .attribute(attr)
            .ok_or_else(|| format!("{}: missing attribute `{attr}`", self.describe(node)))?;
        let id = url.strip_prefix('#').unwrap_or(url);
        self.ids.get(id).copied().ok_or_else(|| {
            format!(
                "{}: `{attr}=\"{url}\"` names no element of this file",
                self.describe(node)
            )
        })
    }

    /// Notes what the consumers ignore of `<asset>`: a unit other than metres, an up axis other than Z.
    fn asset_notes(&mut self, root: Node) {
        let Some(asset) = element(root, "asset") else {
            return;
        };
        if let Some(meter) = element(asset, "unit").and_then(|u| u.attribute("meter"))
            && meter.trim().parse::<f64>() != Ok(1.0)
        {
            self.notes.push(format!(
                "declares <unit meter=\"{meter}\">, which MoveIt and Pinocchio ignore (Assimp puts it \
                 on the root node they reset), so scm ignores it too; RViz's display applies it"
            ));
        }
        if let Some(up) = element(asset, "up_axis")
            .and_then(|u| u.text())
            .map(str::trim)
            && up != "Z_UP"
        {
            self.notes.push(format!(
                "declares <up_axis>{up}</up_axis>, which MoveIt, RViz and Pinocchio ignore, so scm \
                 ignores it too"
            ));
        }
    }

    /// The `<visual_scene>` that `<scene>` instances, or the first one.
    fn visual_scene(&self, root: Node<'a, 'input>) -> Result<Node<'a, 'input>, String> {
        if let Some(instance) =
            element(root, "scene").and_then(|s| element(s, "instance_visual_scene"))
        {
            return self.target(instance, "url");
        }
        element(root, "library_visual_scenes")
            .and_then(|l| element(l, "visual_scene"))
            .ok_or_else(|| "no <visual_scene>: the file places no geometry".to_string())
    }

    /// The transform elements of a `<node>`, composed in document order.
    fn local_transform(&self, node: Node) -> Result<Affine, String> {
        let mut out = Affine::IDENTITY;
        for child in node.children().filter(Node::is_element) {
            let name = child.tag_name().name();
            let step = match name {
                "matrix" => {
                    let v = floats(child, name, 16)?;
                    // Row-major; the last row is taken to be 0 0 0 1.
                    Affine {
                        m: Mat3::from_cols(
                            Vec3::new(v[0], v[4], v[8]),
                            Vec3::new(v[1], v[5], v[9]),
                            Vec3::new(v[2], v[6], v[10]),
                        ),
                        t: Vec3::new(v[3], v[7], v[11]),
                    }
                }
                "translate" => {
                    let v = floats(child, name, 3)?;
                    Affine {
                        m: Mat3::IDENTITY,
                        t: Vec3::new(v[0], v[1], v[2]),
                    }
                }
                "rotate" => {
                    let v = floats(child, name, 4)?;
                    let axis = Vec3::new(v[0], v[1], v[2]);
                    if axis.length() < 1e-12 {
                        Affine::IDENTITY
                    } else {
                        Affine {
                            m: Mat3::from_axis_angle(axis.normalize(), v[3].to_radians()),
                            t: Vec3::ZERO,
                        }
                    }
                }
                "scale" => {
                    let v = floats(child, name, 3)?;
                    Affine {
                        m: Mat3::from_diagonal(Vec3::new(v[0], v[1], v[2])),
                        t: Vec3::ZERO,
                    }
                }
                "lookat" => {
                    let v = floats(child, name, 9)?;
                    let eye = Vec3::new(v[0], v[1], v[2]);
                    let target = Vec3::new(v[3], v[4], v[5]);
                    let up = Vec3::new(v[6], v[7], v[8]);
                    let back = (eye - target).normalize_or_zero();
                    let right = up.cross(back).normalize_or_zero();
                    let up = back.cross(right);
                    Affine {
                        m: Mat3::from_cols(right, up, back),
                        t: eye,
                    }
                }
                _ => continue,
            };
            out = out.then(step);
        }
        Ok(out)
    }

    /// Places the geometry of `node` and its children under `parent`.
    fn node(&mut self, node: Node<'a, 'input>, parent: Affine, depth: usize) -> Result<(), String> {
        if depth > MAX_DEPTH {
            return Err(format!(
                "{}: nodes nest more than {MAX_DEPTH} deep (an <instance_node> cycle?)",
                self.describe(node)
            ));
        }
        self.visits += 1;
        if self.visits > MAX_NODES {
            return Err(format!(
                "{}: the scene places more than {MAX_NODES} nodes (instances that multiply?)",
                self.describe(node)
            ));
        }
        let transform = parent.then(self.local_transform(node)?);
        for child in node.children().filter(Node::is_element) {
            match child.tag_name().name() {
                "node" => self.node(child, transform, depth + 1)?,
                "instance_node" => {
                    let target = self.target(child, "url")?;
                    self.node(target, transform, depth + 1)?;
                }
                "instance_geometry" => {
                    let geometry = self.target(child, "url")?;
                    self.geometry(geometry, &transform)?;
                }
                "instance_controller" => self.notes.push(format!(
                    "{} is ignored (skinned geometry)",
                    self.describe(child)
                )),
                _ => {}
            }
        }
        Ok(())
    }

    /// Appends the triangles of a `<geometry>`'s `<mesh>`, placed by `transform`.
    fn geometry(&mut self, geometry: Node<'a, 'input>, transform: &Affine) -> Result<(), String> {
        let Some(mesh) = element(geometry, "mesh") else {
            return Ok(()); // <convex_mesh>, <spline>, <brep>: no triangles for the consumers either.
        };
        for prim in mesh.children().filter(Node::is_element) {
            let kind = prim.tag_name().name();
            if !matches!(
                kind,
                "triangles" | "polylist" | "polygons" | "trifans" | "tristrips"
            ) {
                continue;
            }
            let (positions, offset, stride) = self.primitive_inputs(prim)?;
            let Some(positions) = positions else {
                continue;
            };
            let mut corners: Vec<u32> = Vec::new();
            // Each polygon, fan or strip as a list of position indices.
            let mut polygons: Vec<Vec<u32>> = Vec::new();
            let tuples = |p: Node| -> Result<Vec<u32>, String> {
                let v: Vec<u32> = numbers(p, "p")?;
                Ok(v.chunks_exact(stride)
                    .map(|tuple| tuple[offset])
                    .collect::<Vec<u32>>())
            };
            match kind {
                "triangles" => {
                    for p in elements(prim, "p") {
                        polygons.extend(tuples(p)?.chunks_exact(3).map(<[u32]>::to_vec));
                    }
                }
                "polylist" => {
                    let counts: Vec<usize> = match element(prim, "vcount") {
                        Some(v) => numbers(v, "vcount")?,
                        None => Vec::new(),
                    };
                    let all = match element(prim, "p") {
                        Some(p) => tuples(p)?,
                        None => Vec::new(),
                    };
                    let mut at: usize = 0;
                    for n in counts {
                        let end = at.saturating_add(n);
                        if end > all.len() {
                            return Err(format!(
                                "{}: <vcount> asks for more vertices than <p> holds",
                                self.describe(prim)
                            ));
                        }
                        polygons.push(all[at..end].to_vec());
                        at = end;
                    }
                }
                "polygons" => {
                    for p in elements(prim, "p") {
                        polygons.push(tuples(p)?);
                    }
                    for ph in elements(prim, "ph") {
                        if let Some(p) = element(ph, "p") {
                            polygons.push(tuples(p)?);
                        }
                    }
                }
                "trifans" => {
                    for p in elements(prim, "p") {
                        polygons.push(tuples(p)?);
                    }
                }
                _ => {
                    // tristrips: triangle k is (k, k+1, k+2), every other one turned round.
                    for p in elements(prim, "p") {
                        let strip = tuples(p)?;
                        for (k, w) in strip.windows(3).enumerate() {
                            polygons.push(if k % 2 == 0 {
                                w.to_vec()
                            } else {
                                vec![w[1], w[0], w[2]]
                            });
                        }
                    }
                }
            }
            for polygon in &polygons {
                if polygon.len() < 3 {
                    continue;
                }
                if self.mesh.vertices.len() + polygon.len() > MAX_CORNERS {
                    return Err(format!(
                        "{}: the scene places more than {MAX_CORNERS} triangle corners",
                        self.describe(prim)
                    ));
                }
                corners.clear();
                for &index in polygon {
                    let p = positions.get(index as usize).ok_or_else(|| {
                        format!(
                            "{}: index {index} is out of range ({} positions)",
                            self.describe(prim),
                            positions.len()
                        )
                    })?;
                    corners.push(self.mesh.vertices.len() as u32);
                    self.mesh.vertices.push(transform.apply(*p));
                }
                for k in 1..corners.len() - 1 {
                    self.mesh
                        .triangles
                        .push([corners[0], corners[k], corners[k + 1]]);
                }
            }
        }
        Ok(())
    }

    /// A primitive's positions (from its `VERTEX` input's `<vertices>`, or a `POSITION` input), the
    /// offset of their index in each `<p>` tuple, and the tuple length.
    fn primitive_inputs(&self, prim: Node) -> Result<(Option<Vec<Vec3>>, usize, usize), String> {
        let mut stride = 1;
        let mut found = None;
        for input in elements(prim, "input") {
            let offset: usize = input
                .attribute("offset")
                .unwrap_or("0")
                .trim()
                .parse()
                .map_err(|_| format!("{}: `offset` is not a count", self.describe(input)))?;
            stride = stride.max(offset + 1);
            match input.attribute("semantic") {
                Some("VERTEX") => {
                    let vertices = self.target(input, "source")?;
                    let position = elements(vertices, "input")
                        .find(|i| i.attribute("semantic") == Some("POSITION"))
                        .ok_or_else(|| format!("{}: no POSITION input", self.describe(vertices)))?;
                    found = Some((self.target(position, "source")?, offset));
                }
                Some("POSITION") if found.is_none() => {
                    found = Some((self.target(input, "source")?, offset));
                }
                _ => {}
            }
        }
        match found {
            Some((source, offset)) => Ok((Some(self.source_points(source)?), offset, stride)),
            None => Ok((None, 0, stride)),
        }
    }

    /// The 3D points of a `<source>` through its accessor.
    fn source_points(&self, source: Node) -> Result<Vec<Vec3>, String> {
        let array = element(source, "float_array")
            .ok_or_else(|| format!("{}: no <float_array>", self.describe(source)))?;
        let values: Vec<f64> = numbers(array, "float_array")?;
        if values.iter().any(|v| !v.is_finite()) {
            return Err(format!(
                "{}: a NaN or infinite coordinate",
                self.describe(array)
            ));
        }
        let accessor = element(source, "technique_common").and_then(|t| element(t, "accessor"));
        let attr = |name: &str, default: usize| -> Result<usize, String> {
            match accessor.and_then(|a| a.attribute(name)) {
                Some(v) => v
                    .trim()
                    .parse()
                    .map_err(|_| format!("{}: `{name}` is not a count", self.describe(source))),
                None => Ok(default),
            }
        };
        let stride = attr("stride", 3)?.max(1);
        let offset = attr("offset", 0)?;
        let count = attr("count", values.len().saturating_sub(offset) / stride)?;
        // The last point read ends at offset + (count - 1) * stride + 3, which must lie in the array
        // (checked arithmetic: a hand-broken count must not wrap round and pass).
        let end = count
            .checked_sub(1)
            .map(|last| {
                last.checked_mul(stride)
                    .and_then(|x| x.checked_add(offset))
                    .and_then(|x| x.checked_add(3))
            })
            .unwrap_or(Some(0));
        if stride < 3 || end.is_none_or(|end| end > values.len()) {
            return Err(format!(
                "{}: the accessor reads past the {} numbers of its array",
                self.describe(source),
                values.len()
            ));
        }
        Ok((0..count)
            .map(|i| {
                let at = offset + i * stride;
                Vec3::new(values[at], values[at + 1], values[at + 2])
            })
            .collect())
    }
}
