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
    /// Sample random joint configurations: per-pair distance statistics and skip reasons for every type.
    Sample(SampleArgs),
    /// Write the skip matrices (six JSON + YAML files) and the files MoveIt, MuJoCo, cuRobo, Drake load.
    Export(ExportArgs),
    /// Import a MoveIt SRDF's disabled collision pairs as the URDD's imported layer.
    ImportMoveit(ImportMoveitArgs),
    /// Compare scm's verdicts with a MoveIt SRDF's (the imported one by default), with evidence.
    Diff(DiffArgs),
    /// Preprocess, sample and export in one call; each stage is skipped when it is up to date.
    Run(RunArgs),
    /// Show the collision geometry scm loaded for every link, placed at configurations (world boxes).
    Inspect(InspectArgs),
    /// Open the interactive viewer on a URDD (needs the scm-viewer binary).
    View(ViewArgs),
    /// Measure queries with skips against without (time) and the skips' verdicts against the meshes.
    Bench(BenchArgs),
}

/// `scm preprocess`.
#[derive(Debug, Args)]
pub struct PreprocessArgs {
    /// The robot's URDF file.
    pub urdf: PathBuf,
    /// The URDD directory to write (created if needed).
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    /// Shape construction.
    #[command(flatten)]
    pub shapes: ShapeArgs,
    /// Rebuild even if the URDD is up to date.
    #[arg(long)]
    pub force: bool,
}

/// `scm run`: preprocess, sample and export, each skipped when up to date.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The robot's URDF file.
    pub urdf: PathBuf,
    /// The URDD directory to write (created if needed).
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    /// Shape construction.
    #[command(flatten)]
    pub shapes: ShapeArgs,
    /// Sampling.
    #[command(flatten)]
    pub sampling: SamplingArgs,
    /// Export.
    #[command(flatten)]
    pub export: ExportFlags,
    /// Recompute every stage even if up to date.
    #[arg(long)]
    pub force: bool,
}

/// Flags of shape construction (preprocess).
#[derive(Debug, Args)]
pub struct ShapeArgs {
    /// Where `package://NAME/...` (or `model://NAME/...`) points, as NAME=DIR (repeatable); searched
    /// before ROS_PACKAGE_PATH, AMENT_PREFIX_PATH (GZ_SIM_RESOURCE_PATH, GAZEBO_MODEL_PATH for
    /// model://) and the URDF's parent folders.
    #[arg(long = "package-path", value_name = "NAME=DIR")]
    pub package_paths: Vec<String>,
    /// Build shapes for links without <collision> from their <visual> geometry. MoveIt, Pinocchio,
    /// MuJoCo and Drake give such links no collision geometry, so their pairs are checked by no one.
    #[arg(long)]
    pub visual_fallback: bool,
    /// Most vertices a link's simplified convex hull may keep.
    #[arg(long, default_value_t = 128, value_parser = clap::value_parser!(u32).range(8..=4096))]
    pub max_hull_vertices: u32,
    /// Most convex pieces per link in the decomposition.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub max_pieces: u32,
    /// Voxel resolution of the convex decomposition.
    #[arg(long, default_value_t = 40, value_parser = clap::value_parser!(u32).range(8..=256))]
    pub decomp_resolution: u32,
}

/// `scm export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The URDD directory (after `scm sample`).
    pub urdd: PathBuf,
    /// Output folder (default DIR/export); replaced as a whole, atomically.
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// Export.
    #[command(flatten)]
    pub export: ExportFlags,
    /// Rewrite even if up to date.
    #[arg(long)]
    pub force: bool,
}

/// Flags of the export stage.
#[derive(Debug, Args)]
pub struct ExportFlags {
    /// Formats to write (comma-separated): matrices, srdf, mjcf, curobo, drake, svg, paper; default all.
    #[arg(long, value_delimiter = ',', value_parser = parse_format)]
    pub format: Vec<scm::export::Format>,
    /// The geometry the SRDF, MJCF, cuRobo and Drake files are decided on: mesh (the exact URDF
    /// collision geometry, safe for every consumer) or a shape type's link-level matrix.
    #[arg(long, default_value = "mesh", value_parser = parse_link_level)]
    pub link_type: scm::export::LinkLevel,
    /// Keep every `never` pair that is only sampled (not certified) checked in those files.
    #[arg(long)]
    pub require_certified: bool,
    /// The sphere type of cuRobo's collision_spheres.
    #[arg(long, default_value = "decomp-sphere", value_parser = parse_shape_type)]
    pub sphere_type: scm::shapes::ShapeType,
    /// Replace only the <disable_collisions> of this existing SRDF (groups, states, comments kept);
    /// the result is written to the export folder.
    #[arg(long, value_name = "SRDF")]
    pub merge_into: Option<PathBuf>,
}

/// `scm import-moveit`.
#[derive(Debug, Args)]
pub struct ImportMoveitArgs {
    /// The MoveIt SRDF.
    pub srdf: PathBuf,
    /// The URDD directory (after `scm preprocess`).
    pub urdd: PathBuf,
    /// Also print the comparison with scm's verdicts (as `scm diff`).
    #[arg(long)]
    pub compare: bool,
    /// The geometry standing for scm in the comparison: mesh or a shape type.
    #[arg(long = "type", default_value = "mesh", value_parser = parse_link_level)]
    pub link_level: scm::export::LinkLevel,
}

/// `scm diff`.
#[derive(Debug, Args)]
pub struct DiffArgs {
    /// The URDD directory (after `scm sample`).
    pub urdd: PathBuf,
    /// The SRDF to compare with (default: the imported one).
    #[arg(long)]
    pub srdf: Option<PathBuf>,
    /// The geometry standing for scm: mesh (the verdicts the exported files carry) or a shape type.
    #[arg(long = "type", default_value = "mesh", value_parser = parse_link_level)]
    pub link_level: scm::export::LinkLevel,
    /// Print every joint of each witness configuration, not only the joints between the two links
    /// (--json always has every joint).
    #[arg(long)]
    pub full_witness: bool,
}

/// `scm inspect`.
#[derive(Debug, Args)]
pub struct InspectArgs {
    /// The URDD directory (after `scm preprocess`).
    pub urdd: PathBuf,
    /// A configuration: one value per DOF in the URDD's order, space- or comma-separated
    /// (repeatable); default the home configuration.
    #[arg(long, value_name = "VALUES", conflicts_with = "random")]
    pub config: Vec<String>,
    /// N random configurations uniform within the joint limits instead.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub random: Option<u32>,
    /// Seed of --random.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// `scm view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// The URDD directory.
    pub urdd: PathBuf,
}

/// `scm bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// The URDD directory (after `scm sample`); with --scale, the robots: URDF files or preprocessed
    /// URDD directories (a URDD is sampled where it is: its sample stage is replaced).
    #[arg(required = true, value_name = "DIR")]
    pub urdd: Vec<PathBuf>,
    /// Fresh random configurations timed per type [default: 5000].
    #[arg(long, short = 'm', value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
    pub configs: Option<u64>,
    /// Timing repeats; the ratios are mean +- std over them [default: 5].
    #[arg(long, short = 'r', value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub repeats: Option<u32>,
    /// Fresh random configurations checked against the exact meshes (table 3) [default: 2000].
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
    pub truth_configs: Option<u64>,
    /// Random seed of the configurations, drawn from a stream sampling never uses [default: 1].
    #[arg(long)]
    pub seed: Option<u64>,
    /// Shape types to measure (comma-separated ids); default every sampled type.
    #[arg(long, value_delimiter = ',')]
    pub types: Vec<String>,
    /// Instead of tables 1-3, the scale table: per robot its links, DOFs, pieces and pairs against the
    /// time and peak memory of `scm sample --force` (a child process) and the work it recorded.
    #[arg(long, conflicts_with_all = ["configs", "repeats", "truth_configs", "seed", "types"])]
    pub scale: bool,
    /// With --scale: samples of each sample run [default: 100000].
    #[arg(long, short = 'n', requires = "scale", value_parser = clap::value_parser!(u64).range(1..=scm::sample::MAX_SAMPLES))]
    pub samples: Option<u64>,
    /// With --scale: sample runs per robot, alternating between robots; the table gives the medians
    /// [default: 1; 3 recommended].
    #[arg(long, requires = "scale", value_parser = clap::value_parser!(u32).range(1..=100))]
    pub runs: Option<u32>,
    /// With --scale: the folder URDF inputs are preprocessed into, one URDD per robot, kept
    /// [default: a temporary folder, removed afterwards].
    #[arg(long, short = 'o', value_name = "DIR", requires = "scale")]
    pub output: Option<PathBuf>,
}

/// `scm sample`.
#[derive(Debug, Args)]
pub struct SampleArgs {
    /// The URDD directory (after `scm preprocess`).
    pub urdd: PathBuf,
    /// Sampling.
    #[command(flatten)]
    pub sampling: SamplingArgs,
    /// Compute only shard K of N (0-based) and write its partial result into DIR/sample-shards/;
    /// shards take no lock and run side by side, on any machine with a copy of DIR.
    #[arg(long, value_name = "K/N", conflicts_with = "merge_shards")]
    pub shard: Option<String>,
    /// Merge the N shard results in DIR/sample-shards/ into the sample output; every shard must come
    /// from this URDD's preprocess output with the same sampling flags as the merge.
    #[arg(long, value_name = "N")]
    pub merge_shards: Option<u32>,
    /// Recompute even if the URDD is up to date.
    #[arg(long)]
    pub force: bool,
}

/// Flags of sampling.
#[derive(Debug, Args)]
pub struct SamplingArgs {
    /// Number of random joint configurations (1 to 1e9; memory does not grow with it).
    #[arg(long, short = 'n', default_value_t = 100_000, value_parser = clap::value_parser!(u64).range(1..=scm::sample::MAX_SAMPLES))]
    pub samples: u64,
    /// Random seed.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Shape types to sample (comma-separated ids); default all six.
    #[arg(long, value_delimiter = ',', value_parser = parse_shape_type)]
    pub types: Vec<scm::shapes::ShapeType>,
    /// Worker threads, 1 to 1024 (default: all cores); the result does not depend on it.
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=scm::sample::MAX_THREADS as i64))]
    pub threads: Option<u16>,
    /// A pair in collision in at least this fraction of the samples is skipped as `always`.
    #[arg(long, default_value_t = 0.95)]
    pub always_fraction: f64,
    /// Estimate each pair's d_mean from at most its first N samples (enough for 1%); 0: every
    /// sample, an exact mean.
    #[arg(long, value_name = "N", default_value_t = 25_000)]
    pub mean_samples: u64,
    /// d_min and d_max may differ from the exact extremes over the samples by at most this (m);
    /// 0 makes them exact. Collision counts and witnesses are always exact.
    #[arg(long, default_value_t = scm::sample::DEFAULT_TOLERANCE)]
    pub tolerance: f64,
    /// Pairs never in collision but closer than this (m) get a targeted collision search.
    #[arg(long, default_value_t = 0.02)]
    pub search_margin: f64,
    /// Most sub-boxes the certificate of one `never` link pair evaluates before it stays `sampled`.
    #[arg(long, default_value_t = 100_000, value_parser = clap::value_parser!(u64).range(1..=1_000_000_000))]
    pub certify_boxes: u64,
    /// Most sub-boxes the certificates of a run evaluate in all.
    #[arg(long, default_value_t = 20_000_000, value_parser = clap::value_parser!(u64).range(1..=100_000_000_000))]
    pub certify_total: u64,
    /// Most exact-geometry distances the certificate of one pair computes where its hulls overlap but
    /// its geometry does not (0: hulls only).
    #[arg(long, default_value_t = 500, value_parser = clap::value_parser!(u64).range(0..=1_000_000_000))]
    pub certify_exact: u64,
}

/// Parses a shape type id, naming the valid ones when it is unknown.
pub fn parse_shape_type(s: &str) -> Result<scm::shapes::ShapeType, String> {
    scm::shapes::ShapeType::from_id(s).ok_or_else(|| {
        let ids: Vec<&str> = scm::shapes::ShapeType::ALL.iter().map(|t| t.id()).collect();
        format!("unknown shape type \"{s}\" (one of {})", ids.join(", "))
    })
}

fn parse_format(s: &str) -> Result<scm::export::Format, String> {
    scm::export::Format::from_id(s).ok_or_else(|| {
        let ids: Vec<&str> = scm::export::Format::ALL.iter().map(|f| f.id()).collect();
        format!("unknown format \"{s}\" (one of {})", ids.join(", "))
    })
}

fn parse_link_level(s: &str) -> Result<scm::export::LinkLevel, String> {
    scm::export::LinkLevel::from_id(s).ok_or_else(|| {
        let ids: Vec<&str> = scm::shapes::ShapeType::ALL.iter().map(|t| t.id()).collect();
        format!(
            "unknown link level \"{s}\" (mesh, or a shape type: {})",
            ids.join(", ")
        )
    })
}
