//! Self-collision and self-proximity queries for planners: load a URDD once, then ask, for one shape
//! type and a joint configuration, whether the robot collides with itself (and which shape pairs) and
//! how far it is from doing so (the minimum signed distance, its pair and witness points), with the
//! skip matrix or over all pairs.
//!
//! Speed comes from three things, all exact: the skipped pairs are never looked at; every pair is first
//! bounded by its shapes' enclosing and inscribed spheres, and a GJK query runs only when the spheres
//! cannot decide; the minimum distance visits pairs in order of their sphere lower bound and stops as
//! soon as no remaining pair can beat the best distance found. The boolean query stops at the first
//! collision.
//!
//! ```no_run
//! use scm::query::{SelfChecker, SkipMode};
//! use scm::shapes::ShapeType;
//! use scm::urdd::Urdd;
//!
//! # fn main() -> scm::Result<()> {
//! let urdd = Urdd::open(std::path::Path::new("panda.urdd"))?; // after `scm run panda.urdf -o panda.urdd`
//! let checker = SelfChecker::load(&urdd, ShapeType::Hull, SkipMode::Skips)?;
//! let mut scratch = checker.scratch(); // one per thread; queries then allocate nothing
//! let q = checker.home(); // one value per DOF, in `checker.dofs()` order
//!
//! if checker.in_collision(&q, &mut scratch)? {
//!     for p in checker.collisions(&q, &mut scratch)?.pairs {
//!         println!("{} hits {}", p.link_a, p.link_b);
//!     }
//! }
//! if let Some(near) = checker.min_distance(&q, &mut scratch)? {
//!     println!(
//!         "closest: {} and {} at {:.4} m",
//!         near.pair.link_a, near.pair.link_b, near.distance
//!     );
//! }
//! # Ok(())
//! # }
//! ```

mod checker;
mod skips;

pub use checker::{CollisionReport, Proximity, Scratch, SelfChecker, ShapePair};
pub use skips::skip_reasons;

use serde::Serialize;

/// Whether a checker leaves out the pairs the skip matrix marks as skippable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SkipMode {
    /// Check only the pairs the skip matrix does not skip.
    Skips,
    /// Check every pair of shapes, including same-link and adjacent ones.
    NoSkips,
}
