//! All six representations of one link, built from its collision geometry in the link frame.

use super::decomp::{DecompParams, convex_decomposition};
use super::hull::{HullError, convex_hull, simplify_hull};
use super::{Geometry, PerType, Scope, ShapeKind};
use crate::mesh::TriMesh;
use serde::{Deserialize, Serialize};

/// Parameters of shape construction (recorded in the URDD; a change reruns preprocessing).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShapeParams {
    /// Upper bound on the vertex count of a link's simplified hull.
    pub max_hull_vertices: usize,
    /// Convex decomposition parameters.
    pub decomposition: DecompParams,
}

impl Default for ShapeParams {
    fn default() -> Self {
        ShapeParams {
            max_hull_vertices: 128,
            decomposition: DecompParams::default(),
        }
    }
}

/// How well each representation fits a link.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinkFit {
    /// Volume of the exact convex hull of the link's geometry (m^3): the reference.
    pub mesh_hull_volume: f64,
    /// Vertices of the exact hull before simplification.
    pub mesh_hull_vertices: usize,
    /// Vertices of the triangle geometry the shapes were built from.
    pub mesh_vertices: usize,
    /// Each type's total volume divided by `mesh_hull_volume`.
    pub relative_volume: PerType<f64>,
    /// Number of convex decomposition pieces.
    pub pieces: usize,
}

/// The six representations of one link.
#[derive(Debug, Clone)]
pub struct LinkShapes {
    /// The shapes of each type (one for link types, one per piece for decomposition types).
    pub shapes: PerType<Vec<Geometry>>,
    /// Fit statistics.
    pub fit: LinkFit,
}

/// Builds the six representations of a link from its triangle geometry in the link frame.
pub fn build_link_shapes(mesh: &TriMesh, params: &ShapeParams) -> Result<LinkShapes, HullError> {
    let exact = convex_hull(&mesh.vertices)?;
    let hull = simplify_hull(&exact, params.max_hull_vertices);
    let pieces = convex_decomposition(mesh, &exact, &params.decomposition);
    let shapes = PerType::from_fn(|t| match t.scope() {
        // The link's sphere and box enclose the exact hull; its hull type is the simplified hull.
        Scope::Link => vec![match t.kind() {
            ShapeKind::Hull => Geometry::Hull(hull.clone()),
            kind => Geometry::fit(kind, &exact),
        }],
        Scope::Pieces => pieces.iter().map(|p| Geometry::fit(t.kind(), p)).collect(),
    });
    let reference = exact.volume();
    let fit = LinkFit {
        mesh_hull_volume: reference,
        mesh_hull_vertices: exact.vertices.len(),
        mesh_vertices: mesh.vertices.len(),
        relative_volume: shapes.map(|_, g| g.iter().map(Geometry::volume).sum::<f64>() / reference),
        pieces: pieces.len(),
    };
    Ok(LinkShapes { shapes, fit })
}
