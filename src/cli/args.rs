//! Every command-line flag, defined in one place.

use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// scm: generate, inspect and refine robot self-collision matrices.
#[derive(Debug, Parser)]
#[command(name = "scm", version, about, propagate_version = true)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
    /// No progress bars or notes on stderr (errors are still printed).
    #[arg(long, short, global = true)]
    pub quiet: bool,
    /// Print a machine-readable JSON summary on stdout.
    #[arg(long, global = true)]
    pub json: bool,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Read a URDF and its meshes and build the six shape representations of every link into a URDD.
    Preprocess(PreprocessArgs),
    /// Open the interactive viewer on a URDD (needs the scm-viewer binary).
    View(ViewArgs),
}

/// `scm preprocess`.
#[derive(Debug, Args)]
pub struct PreprocessArgs {
    /// The robot's URDF file.
    pub urdf: PathBuf,
    /// The URDD directory to write (created if needed).
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    /// Where `package://NAME/...` points, as NAME=DIR (repeatable).
    #[arg(long = "package-path", value_name = "NAME=DIR")]
    pub package_paths: Vec<String>,
    /// Most vertices a link's simplified convex hull may keep.
    #[arg(long, default_value_t = 128, value_parser = clap::value_parser!(u32).range(8..=4096))]
    pub max_hull_vertices: u32,
    /// Most convex pieces per link in the decomposition.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub max_pieces: u32,
    /// Voxel resolution of the convex decomposition.
    #[arg(long, default_value_t = 40, value_parser = clap::value_parser!(u32).range(8..=256))]
    pub decomp_resolution: u32,
    /// Rebuild even if the URDD is up to date.
    #[arg(long)]
    pub force: bool,
}

/// `scm view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// The URDD directory.
    pub urdd: PathBuf,
}
