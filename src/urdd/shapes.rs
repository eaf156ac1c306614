//! Reading one shape type from a URDD as query-ready shapes: the one place sampling, the `mesh`
//! verdicts and the query API turn shape records into [`CollisionShape`]s (the geometry itself does no
//! I/O).

use super::{PREPROCESS, ShapeRecord, Urdd, shape_file_name};
use crate::collision::CollisionShape;
use crate::error::{Error, Result};
use crate::shapes::ShapeType;

/// The shapes of one type in matrix order, ready for queries, with the link each belongs to.
#[derive(Debug)]
pub struct TypeShapes {
    /// The shape type.
    pub shape_type: ShapeType,
    /// The records as stored (index, link, piece, geometry).
    pub records: Vec<ShapeRecord>,
    /// Query-ready shapes, in matrix order.
    pub shapes: Vec<CollisionShape>,
    /// Link index of each shape.
    pub links: Vec<usize>,
}

impl Urdd {
    /// The shapes of type `t`, ready for queries; `link_count` is the robot's number of links (every
    /// shape must name one of them). A degenerate hull or a dangling link index is bad input naming the
    /// shape.
    pub fn collision_shapes(&self, t: ShapeType, link_count: usize) -> Result<TypeShapes> {
        let urdd = self;
        let file = urdd.shapes(t)?;
        let mut shapes = Vec::with_capacity(file.shapes.len());
        let mut links = Vec::with_capacity(file.shapes.len());
        for s in &file.shapes {
            let geometry = urdd.geometry(&s.geometry)?;
            let shape = CollisionShape::new(&geometry).ok_or_else(|| {
                Error::input(
                    &urdd.dir().join(PREPROCESS).join(shape_file_name(t)),
                    format!("shape {} (link \"{}\")", s.index, s.link),
                    "degenerate hull",
                )
            })?;
            if s.link_index >= link_count {
                return Err(Error::input(
                    urdd.dir(),
                    format!("{t} shape {}", s.index),
                    "names a link that robot.json does not have",
                ));
            }
            shapes.push(shape);
            links.push(s.link_index);
        }
        Ok(TypeShapes {
            shape_type: t,
            records: file.shapes,
            shapes,
            links,
        })
    }
}
