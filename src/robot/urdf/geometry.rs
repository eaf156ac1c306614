//! The geometry half of the URDF reader: a link's `<collision>` (or, under `visual_fallback`, `<visual>`)
//! elements, each shape with its attributes checked and its mesh filename resolved.

use super::Reader;
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::robot::packages::PackagePaths;
use crate::robot::{GeometryElement, GeometryOrigin, Link, ShapeSource};
use roxmltree::Node;

impl<'a, 'input> Reader<'a, 'input> {
    pub(super) fn link(
        &self,
        node: Node,
        packages: &PackagePaths,
        warnings: &mut Vec<String>,
    ) -> Result<Link> {
        let name = self.required(node, "name")?.to_string();
        let collisions = self.geometry_elements(node, "collision", packages)?;
        let has_visual = self.children(node, "visual").next().is_some();
        let (geometry, geometry_source) = if !collisions.is_empty() {
            (collisions, GeometryOrigin::Collision)
        } else if has_visual && self.visual_fallback {
            warnings.push(format!(
                "link \"{name}\" has no <collision>; its <visual> geometry is used instead \
                 (--visual-fallback: no consumer checks it)"
            ));
            (
                self.geometry_elements(node, "visual", packages)?,
                GeometryOrigin::Visual,
            )
        } else {
            if has_visual {
                warnings.push(format!(
                    "link \"{name}\" has no <collision>: no collision shapes, as in MoveIt, \
                     Pinocchio, MuJoCo and Drake (--visual-fallback builds them from its <visual>)"
                ));
            }
            (Vec::new(), GeometryOrigin::None)
        };
        Ok(Link {
            name,
            geometry,
            geometry_source,
            parent_joint: None,
        })
    }

    fn geometry_elements(
        &self,
        link: Node,
        tag: &'static str,
        packages: &PackagePaths,
    ) -> Result<Vec<GeometryElement>> {
        let mut out = Vec::new();
        for element in self.children(link, tag) {
            let origin = self.origin(element)?;
            let geometry = self
                .child(element, "geometry")
                .ok_or_else(|| self.geometry_err(link, element, "has no <geometry>"))?;
            let shape_node = geometry
                .children()
                .find(|c| c.is_element())
                .ok_or_else(|| self.geometry_err(link, element, "<geometry> is empty"))?;
            let shape = self.shape(link, element, shape_node, packages)?;
            out.push(GeometryElement {
                origin,
                shape,
                line: self.line(element),
            });
        }
        Ok(out)
    }

    fn geometry_err(&self, link: Node, element: Node, message: &str) -> Error {
        Error::input(
            self.path,
            format!(
                "{} <{}> (line {})",
                self.describe(link),
                element.tag_name().name(),
                self.line(element)
            ),
            message.to_string(),
        )
    }

    fn positive(&self, link: Node, element: Node, shape: Node, attr: &str) -> Result<f64> {
        let v = self
            .required_number(shape, attr)
            .map_err(|e| self.nest(link, element, e))?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.geometry_err(
                link,
                element,
                &format!(
                    "<{}> {attr} must be positive, got {v}",
                    shape.tag_name().name()
                ),
            ))
        }
    }

    /// Re-labels an error raised on a geometry child so it names the link and the collision element.
    fn nest(&self, link: Node, element: Node, e: Error) -> Error {
        match e {
            Error::Input {
                message,
                element: inner,
                ..
            } => self.geometry_err(link, element, &format!("{inner}: {message}")),
            other => other,
        }
    }

    fn shape(
        &self,
        link: Node,
        element: Node,
        shape: Node,
        packages: &PackagePaths,
    ) -> Result<ShapeSource> {
        Ok(match shape.tag_name().name() {
            "box" => {
                let size = self
                    .vec3(shape, "size", Vec3::ZERO)
                    .map_err(|e| self.nest(link, element, e))?;
                if shape.attribute("size").is_none() || size.min_element() <= 0.0 {
                    return Err(self.geometry_err(link, element, "<box> needs a positive `size`"));
                }
                ShapeSource::Box { size }
            }
            "cylinder" => ShapeSource::Cylinder {
                radius: self.positive(link, element, shape, "radius")?,
                length: self.positive(link, element, shape, "length")?,
            },
            "capsule" => ShapeSource::Capsule {
                radius: self.positive(link, element, shape, "radius")?,
                length: self.positive(link, element, shape, "length")?,
            },
            "sphere" => ShapeSource::Sphere {
                radius: self.positive(link, element, shape, "radius")?,
            },
            "mesh" => {
                let uri = self
                    .required(shape, "filename")
                    .map_err(|e| self.nest(link, element, e))?;
                let scale = self
                    .vec3(shape, "scale", Vec3::ONE)
                    .map_err(|e| self.nest(link, element, e))?;
                let scale = match shape
                    .attribute("scale")
                    .map(|s| s.split_whitespace().count())
                {
                    // A single number scales uniformly (accepted by several ROS tools).
                    Some(1) => Vec3::splat(
                        self.optional_number(shape, "scale", 1.0)
                            .map_err(|e| self.nest(link, element, e))?,
                    ),
                    _ => scale,
                };
                if scale.abs().min_element() == 0.0 {
                    return Err(self.geometry_err(link, element, "<mesh> scale must not be zero"));
                }
                let path = packages.resolve(uri, self.path).map_err(|msg| {
                    self.geometry_err(link, element, &format!("mesh \"{uri}\": {msg}"))
                })?;
                ShapeSource::Mesh {
                    uri: uri.to_string(),
                    path,
                    scale,
                }
            }
            other => {
                return Err(self.geometry_err(
                    link,
                    element,
                    &format!("unknown geometry <{other}>"),
                ));
            }
        })
    }
}
