//! The six shape representations of a link: one [`ShapeType`] enum that all code iterates over, and the
//! three geometric kinds ([`Sphere`], [`Obb`], [`ConvexMesh`]) they are made of.

mod decomp;
mod hull;
mod link_shapes;
mod obb;
mod per_type;
mod sphere;
#[cfg(test)]
mod test_rng;

pub use decomp::{DecompParams, convex_decomposition};
pub use hull::{ConvexMesh, HullError, convex_hull, simplify_hull};
pub use link_shapes::{LinkFit, LinkShapes, ShapeParams, build_link_shapes};
pub use obb::{Obb, tight_obb};
pub use per_type::PerType;
pub use sphere::{Sphere, minimal_bounding_sphere};

use serde::{Deserialize, Serialize};

/// The geometric kind of a shape: what a collision or distance query sees.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShapeKind {
    /// A bounding sphere.
    Sphere,
    /// An oriented bounding box.
    Obb,
    /// A convex hull.
    Hull,
}

/// Whether a shape type covers a whole link or each piece of its convex decomposition.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Scope {
    /// One shape for the whole link.
    Link,
    /// One shape per convex-decomposition piece.
    Pieces,
}

/// One of the six shape representations scm builds for every link.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum ShapeType {
    /// Minimal bounding sphere of the whole link.
    #[serde(rename = "sphere")]
    Sphere,
    /// Tight oriented bounding box of the whole link.
    #[serde(rename = "obb")]
    Obb,
    /// Simplified convex hull of the whole link.
    #[serde(rename = "hull")]
    Hull,
    /// Minimal bounding sphere of each decomposition piece.
    #[serde(rename = "decomp-sphere")]
    DecompSphere,
    /// Tight oriented bounding box of each decomposition piece.
    #[serde(rename = "decomp-obb")]
    DecompObb,
    /// Convex hull of each decomposition piece.
    #[serde(rename = "decomp-hull")]
    DecompHull,
}

impl ShapeType {
    /// All six types, in their canonical order.
    pub const ALL: [ShapeType; 6] = [
        ShapeType::Sphere,
        ShapeType::Obb,
        ShapeType::Hull,
        ShapeType::DecompSphere,
        ShapeType::DecompObb,
        ShapeType::DecompHull,
    ];

    /// The stable id used in file names, flags and JSON (`sphere`, `decomp-obb`, ...).
    pub fn id(self) -> &'static str {
        match self {
            ShapeType::Sphere => "sphere",
            ShapeType::Obb => "obb",
            ShapeType::Hull => "hull",
            ShapeType::DecompSphere => "decomp-sphere",
            ShapeType::DecompObb => "decomp-obb",
            ShapeType::DecompHull => "decomp-hull",
        }
    }

    /// The type with the given id.
    pub fn from_id(id: &str) -> Option<ShapeType> {
        ShapeType::ALL.into_iter().find(|t| t.id() == id)
    }

    /// The geometric kind of this type's shapes.
    pub fn kind(self) -> ShapeKind {
        match self {
            ShapeType::Sphere | ShapeType::DecompSphere => ShapeKind::Sphere,
            ShapeType::Obb | ShapeType::DecompObb => ShapeKind::Obb,
            ShapeType::Hull | ShapeType::DecompHull => ShapeKind::Hull,
        }
    }

    /// Whether this type has one shape per link or one per decomposition piece.
    pub fn scope(self) -> Scope {
        match self {
            ShapeType::Sphere | ShapeType::Obb | ShapeType::Hull => Scope::Link,
            _ => Scope::Pieces,
        }
    }
}

impl std::fmt::Display for ShapeType {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.id())
    }
}

/// The geometry of one shape, in its link's frame.
#[derive(Debug, Clone, PartialEq)]
pub enum Geometry {
    /// A sphere.
    Sphere(Sphere),
    /// An oriented box.
    Obb(Obb),
    /// A convex polyhedron.
    Hull(ConvexMesh),
}

impl Geometry {
    /// Fits a shape of `kind` around a convex polyhedron (the link hull or a decomposition piece).
    pub fn fit(kind: ShapeKind, hull: &ConvexMesh) -> Geometry {
        match kind {
            ShapeKind::Sphere => Geometry::Sphere(minimal_bounding_sphere(&hull.vertices)),
            ShapeKind::Obb => Geometry::Obb(tight_obb(hull)),
            ShapeKind::Hull => Geometry::Hull(hull.clone()),
        }
    }

    /// The enclosed volume in cubic metres.
    pub fn volume(&self) -> f64 {
        match self {
            Geometry::Sphere(s) => s.volume(),
            Geometry::Obb(b) => b.volume(),
            Geometry::Hull(h) => h.volume(),
        }
    }
}
