//! scm: robot self-collision matrices. The library holds every stage (`preprocess`, ...) so the CLI,
//! the viewer, tests and benchmarks all call the same code.

pub mod bench;
pub mod collision;
pub mod diff;
pub mod error;
pub mod export;
pub mod formats;
pub mod import;
pub mod inspect;
pub mod math;
pub mod matrix;
pub mod mesh;
pub mod preprocess;
pub mod progress;
pub mod query;
pub mod rng;
pub mod robot;
pub mod sample;
pub mod shapes;
pub mod urdd;

pub use error::{Error, Result};

/// The scm version, recorded in every URDD.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
