//! The `export` stage: the resolved skip matrices (sampling + imported + user layers) written as the
//! six matrix files and as the files MoveIt, MuJoCo, cuRobo, Drake and the paper's tool load.

use crate::error::{Error, Result};
use crate::formats::{curobo, drake, matrices::MatrixFile, mjcf, paper_modules, srdf, svg};
use crate::matrix::{
    HeatMap, IMPORTED_FILE, LAYERS, LinkPair, SkipMatrix, USER_FILE, consumer_link_pairs,
};
use crate::progress::Progress;
use crate::sample::{NeverEvidence, SAMPLE, load_mesh_file};
use crate::shapes::ShapeType;
use crate::urdd::{StageDir, StageRecord, Urdd, json_bytes, sha256_hex};
use crate::urdd::{compact_json, json_value, parameters};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub use crate::urdd::EXPORT;
pub use crate::urdd::EXPORT_INDEX;

/// An output format of `scm export`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Format {
    /// The six matrix files, JSON and YAML.
    Matrices,
    /// MoveIt SRDF `<disable_collisions>`.
    Srdf,
    /// MuJoCo `<contact><exclude>`.
    Mjcf,
    /// cuRobo `self_collision_ignore` and `collision_spheres`.
    Curobo,
    /// Drake collision filter groups.
    Drake,
    /// SVG heat maps: one per sampled type and one of the exported link pairs.
    Svg,
    /// The paper's URDD modules.
    Paper,
}

impl Format {
    /// Every format, in output order.
    pub const ALL: [Format; 7] = [
        Format::Matrices,
        Format::Srdf,
        Format::Mjcf,
        Format::Curobo,
        Format::Drake,
        Format::Svg,
        Format::Paper,
    ];

    /// The id used by `--format`.
    pub fn id(self) -> &'static str {
        match self {
            Format::Matrices => "matrices",
            Format::Srdf => "srdf",
            Format::Mjcf => "mjcf",
            Format::Curobo => "curobo",
            Format::Drake => "drake",
            Format::Svg => "svg",
            Format::Paper => "paper",
        }
    }

    /// The format with this id.
    pub fn from_id(id: &str) -> Option<Format> {
        Format::ALL.into_iter().find(|f| f.id() == id)
    }
}

/// The geometry the link-level files (SRDF, MJCF, cuRobo, Drake) are decided on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinkLevel {
    /// The exact URDF collision geometry (the sample stage's `mesh` verdicts): the default, and the
    /// only one whose skips are safe for every consumer.
    Mesh,
    /// A shape type's link-level matrix (a pair is skipped when every shape pair between the links is).
    Type(ShapeType),
}

impl LinkLevel {
    /// The id used by `--link-type`: `mesh` or a shape type's.
    pub fn id(self) -> &'static str {
        match self {
            LinkLevel::Mesh => "mesh",
            LinkLevel::Type(t) => t.id(),
        }
    }

    /// The level with this id.
    pub fn from_id(id: &str) -> Option<LinkLevel> {
        match id {
            "mesh" => Some(LinkLevel::Mesh),
            _ => ShapeType::from_id(id).map(LinkLevel::Type),
        }
    }
}

impl Serialize for LinkLevel {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.id())
    }
}

impl<'de> Deserialize<'de> for LinkLevel {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let id = String::deserialize(d)?;
        LinkLevel::from_id(&id)
            .ok_or_else(|| serde::de::Error::custom(format!("unknown link level `{id}`")))
    }
}

/// What to export and where; everything but `force` enters the stage key.
#[derive(Debug, Clone, Serialize)]
pub struct ExportOptions {
    /// The URDD directory.
    pub urdd: PathBuf,
    /// The output folder (default `DIR/export`).
    pub out: Option<PathBuf>,
    /// Formats to write.
    pub formats: Vec<Format>,
    /// The geometry the SRDF, MJCF, cuRobo and Drake files are decided on.
    pub link_type: LinkLevel,
    /// Keep every `never` pair that is only sampled (not certified) checked in those files.
    pub require_certified: bool,
    /// The sphere type cuRobo's `collision_spheres` come from.
    pub sphere_type: ShapeType,
    /// An existing SRDF whose `<disable_collisions>` the SRDF output replaces (everything else kept).
    pub merge_into: Option<PathBuf>,
    /// Rewrite even if up to date.
    #[serde(skip)]
    pub force: bool,
}

impl ExportOptions {
    /// Every format into `DIR/export`, link level from the exact geometry (`mesh`), cuRobo spheres from
    /// `decomp-sphere`.
    pub fn new(urdd: &Path) -> ExportOptions {
        ExportOptions {
            urdd: urdd.to_path_buf(),
            out: None,
            formats: Format::ALL.to_vec(),
            link_type: LinkLevel::Mesh,
            require_certified: false,
            sphere_type: ShapeType::DecompSphere,
            merge_into: None,
            force: false,
        }
    }

    /// The output folder.
    pub fn out_dir(&self) -> PathBuf {
        self.out.clone().unwrap_or_else(|| self.urdd.join(EXPORT))
    }
}

/// Per type: how many pairs are skipped and checked, and which layer decided.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ExportCounts {
    /// Shapes.
    pub shapes: usize,
    /// Pairs a check may skip.
    pub skipped: usize,
    /// Pairs that must be checked.
    pub checked: usize,
    /// Pairs per deciding layer.
    pub layers: BTreeMap<String, usize>,
}

/// What an export did.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ExportReport {
    /// The URDD directory.
    pub urdd: PathBuf,
    /// The output folder.
    pub out: PathBuf,
    /// Nothing was done: the output was up to date.
    pub up_to_date: bool,
    /// Files written, relative to `out`.
    pub files: Vec<String>,
    /// What was left out and why.
    #[serde(default)]
    pub notes: Vec<String>,
    /// Per type counts.
    pub types: BTreeMap<ShapeType, ExportCounts>,
    /// Link pairs of the link-level files that are skipped, and in all.
    pub link_pairs: (usize, usize),
    /// The geometry the link-level files were decided on (`mesh` or a shape type).
    #[serde(default)]
    pub link_level: String,
    /// Skipped link pairs per reason (MoveIt's names), and `never` split by evidence
    /// (`never-certified`, `never-sampled`), plus `never-kept-checked` under `--require-certified`.
    #[serde(default)]
    pub link_reasons: BTreeMap<String, usize>,
}

/// Runs the export stage.
pub fn export(opts: &ExportOptions, progress: &dyn Progress) -> Result<ExportReport> {
    let (mut urdd, _lock) = Urdd::open_for_writing(&opts.urdd, progress)?;
    let sample_key = urdd.fresh_stage(SAMPLE)?.key.clone();
    let out = opts.out_dir();
    let key = stage_key(&urdd, opts, &sample_key)?;
    if !opts.force
        && urdd.is_up_to_date(EXPORT, &key)
        && let Some(previous) = read_index(&out)
    {
        return Ok(ExportReport {
            up_to_date: true,
            ..previous
        });
    }
    guard_foreign_folder(&out)?;
    let rerun = urdd.rerun_note(EXPORT, &key);

    let robot = urdd.robot()?;
    let robot_name = robot.robot.name.clone();
    let sampled = urdd.sampled_types()?;
    progress.start("exporting", sampled.len() as u64 + 1);
    let mut matrices = Vec::new();
    for t in &sampled {
        matrices.push(SkipMatrix::load(&urdd, *t)?);
        progress.advance(1);
    }
    // The layers (imported, user) are read from a type's link-level view: the chosen type, or for
    // `mesh` the link hull (the first whole-link type sampled where it was not).
    let layer_type = match opts.link_type {
        LinkLevel::Type(t) => t,
        LinkLevel::Mesh => [ShapeType::Hull, ShapeType::Obb, ShapeType::Sphere]
            .into_iter()
            .chain(sampled.iter().copied())
            .find(|t| sampled.contains(t))
            .unwrap_or(ShapeType::Hull),
    };
    let link_matrix = matrices
        .iter()
        .find(|m| m.shape_type == layer_type)
        .ok_or_else(|| {
            Error::input(
                &opts.urdd.join(SAMPLE),
                layer_type.id(),
                "the link-level type was not sampled; choose another with --link-type",
            )
        })?;
    let links = link_matrix.links();
    let link_pairs = match opts.link_type {
        LinkLevel::Type(_) => link_matrix.link_pairs(),
        LinkLevel::Mesh => {
            let mesh = load_mesh_file(&urdd)?.ok_or_else(|| {
                Error::input(
                    &opts.urdd.join(SAMPLE),
                    crate::sample::MESH_FILE,
                    "missing: the sample output has no verdicts on the exact geometry; rerun `scm sample`",
                )
            })?;
            consumer_link_pairs(link_matrix.link_pairs(), &mesh, opts.require_certified)
        }
    };
    let link_reasons = link_reason_counts(&link_pairs);
    let comment = format!(
        "Written by scm {} for robot \"{robot_name}\" ({} samples). Skips decided on {}{}.",
        crate::VERSION,
        link_matrix.samples,
        match opts.link_type {
            LinkLevel::Mesh => "the exact URDF collision geometry (mesh)".to_string(),
            LinkLevel::Type(t) => format!("the {t} matrix"),
        },
        never_note(&link_reasons),
    );

    let stage = StageDir::create(&out)?;
    let mut files = Vec::new();
    let mut notes: Vec<String> = rerun.into_iter().collect();
    let mut write = |name: String, bytes: Vec<u8>| -> Result<()> {
        stage.write(&name, &bytes)?;
        files.push(name);
        Ok(())
    };
    for format in &opts.formats {
        match format {
            Format::Matrices => {
                for m in &matrices {
                    let file = MatrixFile::new(&robot_name, m);
                    let json = file.to_json().map_err(|message| Error::Failed {
                        context: format!("matrices/{}.json", m.shape_type),
                        message,
                    })?;
                    write(format!("matrices/{}.json", m.shape_type), json)?;
                    let yaml = file.to_yaml().map_err(|e| Error::Failed {
                        context: format!("{} matrix YAML", m.shape_type),
                        message: e,
                    })?;
                    write(format!("matrices/{}.yaml", m.shape_type), yaml)?;
                }
            }
            Format::Srdf => {
                let text = match &opts.merge_into {
                    Some(path) => srdf::merge_into(&read_text(path)?, path, &link_pairs)?,
                    None => srdf::write_srdf(&robot_name, &comment, &link_pairs),
                };
                write(format!("{robot_name}.srdf"), text.into_bytes())?;
            }
            Format::Mjcf => write(
                format!("{robot_name}.mjcf-excludes.xml"),
                mjcf::write_mjcf(&robot.robot, &comment, &link_pairs).into_bytes(),
            )?,
            Format::Curobo => {
                let spheres = urdd.shapes(opts.sphere_type)?.shapes;
                write(
                    format!("{robot_name}.curobo.yml"),
                    curobo::write_curobo(&comment, &links, &link_pairs, &spheres).into_bytes(),
                )?;
            }
            Format::Drake => write(
                format!("{robot_name}.drake-filters.xml"),
                drake::write_drake(&comment, &links, &link_pairs).into_bytes(),
            )?,
            Format::Svg => {
                let order = robot.robot.kinematic_link_names();
                for m in &matrices {
                    let map = HeatMap::of_type(m, &order);
                    write(
                        format!("heatmaps/{}.svg", m.shape_type),
                        svg::write_svg(&map).into_bytes(),
                    )?;
                }
                let title = match opts.link_type {
                    LinkLevel::Mesh => "link pairs in the exported files (decided on mesh)".into(),
                    LinkLevel::Type(t) => {
                        format!("link pairs in the exported files (decided on {t})")
                    }
                };
                let map = HeatMap::of_link_pairs(title, &link_pairs, link_matrix, &order);
                write(
                    "heatmaps/links.svg".into(),
                    svg::write_svg(&map).into_bytes(),
                )?;
            }
            Format::Paper if matrices.len() == ShapeType::ALL.len() => {
                write_paper_modules(&matrices, &mut write)?
            }
            Format::Paper => notes.push(
                "the paper's URDD modules were not written: they need all six shape types sampled"
                    .into(),
            ),
        }
    }
    let report = ExportReport {
        urdd: opts.urdd.clone(),
        out: out.clone(),
        up_to_date: false,
        files,
        notes,
        types: matrices.iter().map(|m| (m.shape_type, counts(m))).collect(),
        link_pairs: (
            link_pairs.iter().filter(|p| p.entry.skip).count(),
            link_pairs.len(),
        ),
        link_level: opts.link_type.id().into(),
        link_reasons,
    };
    stage.write(EXPORT_INDEX, &json_bytes(EXPORT_INDEX, &report)?)?;
    stage.commit()?;
    progress.advance(1);
    progress.finish();

    let robot_manifest = urdd.manifest().robot.clone();
    urdd.record_stage(
        EXPORT,
        &robot_manifest,
        StageRecord {
            key,
            tool_version: crate::VERSION.into(),
            inputs: Vec::new(),
            parameters: json_value("export parameters", opts)?,
            folder: folder_in(&opts.urdd, &out),
            outputs: report
                .files
                .iter()
                .cloned()
                .chain([EXPORT_INDEX.to_string()])
                .collect(),
            stamps: Default::default(),
            summary: json_value("export summary", &report.types)?,
            depends_on: [(SAMPLE.to_string(), sample_key)].into(),
        },
    )?;
    Ok(report)
}

/// The paper's two modules (all six types).
fn write_paper_modules(
    matrices: &[SkipMatrix],
    write: &mut dyn FnMut(String, Vec<u8>) -> Result<()>,
) -> Result<()> {
    let yaml_error = |e: serde_saphyr::SerializeError| Error::Failed {
        context: "paper module YAML".into(),
        message: e.to_string(),
    };
    let skips = paper_modules::skips_module(matrices);
    let stats = paper_modules::statistics_module(matrices);
    for (folder, json, yaml) in [
        (
            paper_modules::SKIPS_MODULE,
            compact_json(paper_modules::SKIPS_MODULE, &skips)?,
            serde_saphyr::to_string(&skips).map_err(yaml_error)?,
        ),
        (
            paper_modules::STATISTICS_MODULE,
            compact_json(paper_modules::STATISTICS_MODULE, &stats)?,
            serde_saphyr::to_string(&stats).map_err(yaml_error)?,
        ),
    ] {
        write(
            format!("{folder}/VERSION"),
            paper_modules::VERSION.as_bytes().to_vec(),
        )?;
        write(format!("{folder}/module.json"), json)?;
        write(format!("{folder}/module.yaml"), yaml.into_bytes())?;
    }
    Ok(())
}

/// Skipped link pairs per MoveIt reason; `never` also split by its evidence.
fn link_reason_counts(pairs: &[LinkPair]) -> BTreeMap<String, usize> {
    let mut counts = BTreeMap::new();
    for p in pairs {
        if p.entry.skip {
            *counts.entry(srdf::moveit_reason(&p.entry)).or_default() += 1;
        }
        let key = match (p.evidence, p.entry.skip) {
            (Some(NeverEvidence::Certified), true) => "never-certified",
            (Some(NeverEvidence::Sampled), true) => "never-sampled",
            (Some(NeverEvidence::Sampled), false) => "never-kept-checked",
            _ => continue,
        };
        *counts.entry(key.to_string()).or_default() += 1;
    }
    counts
}

/// `; never: N certified, M sampled (...)` for the files' header comment.
fn never_note(counts: &BTreeMap<String, usize>) -> String {
    let n = |k: &str| counts.get(k).copied().unwrap_or(0);
    if n("never-certified") + n("never-sampled") + n("never-kept-checked") == 0 {
        return String::new();
    }
    let mut note = format!(
        "; never: {} certified, {} only sampled",
        n("never-certified"),
        n("never-sampled")
    );
    if n("never-kept-checked") > 0 {
        note.push_str(&format!(
            ", {} sampled kept checked (--require-certified)",
            n("never-kept-checked")
        ));
    }
    note
}

fn counts(m: &SkipMatrix) -> ExportCounts {
    let mut c = ExportCounts {
        shapes: m.len(),
        ..ExportCounts::default()
    };
    for e in &m.entries {
        if e.skip {
            c.skipped += 1;
        } else {
            c.checked += 1;
        }
        *c.layers.entry(e.layer.id().to_string()).or_default() += 1;
    }
    c
}

/// The key: the sample output it reads, the imported and user layers, a merged SRDF, the options.
fn stage_key(urdd: &Urdd, opts: &ExportOptions, sample_key: &str) -> Result<String> {
    let hash_of = |path: &Path| -> Result<Option<String>> {
        match std::fs::read(path) {
            Ok(bytes) => Ok(Some(sha256_hex(&bytes))),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(Error::io(path, e)),
        }
    };
    let layers = urdd.dir().join(LAYERS);
    let merge = match &opts.merge_into {
        Some(p) => Some(hash_of(p)?.ok_or_else(|| {
            Error::input(p, "file", "cannot read the SRDF to merge into: not found")
        })?),
        None => None,
    };
    Ok(crate::urdd::stage_key(
        EXPORT,
        serde_json::json!({
            "sample": sample_key,
            "imported": hash_of(&layers.join(IMPORTED_FILE))?,
            "user": hash_of(&layers.join(USER_FILE))?,
            "merge_into": merge,
            "options": parameters(EXPORT, opts)?,
        }),
    ))
}

/// Refuses to replace a folder that exists, is not empty and was not written by `scm export`.
fn guard_foreign_folder(out: &Path) -> Result<()> {
    crate::urdd::ensure_not_file(out)?;
    let non_empty = std::fs::read_dir(out).is_ok_and(|mut d| d.next().is_some());
    if non_empty && !out.join(EXPORT_INDEX).is_file() {
        return Err(Error::input(
            out,
            "output folder",
            "exists, is not empty and was not written by `scm export`; choose a new or empty folder",
        ));
    }
    Ok(())
}

fn read_index(out: &Path) -> Option<ExportReport> {
    serde_json::from_slice(&std::fs::read(out.join(EXPORT_INDEX)).ok()?).ok()
}

fn read_text(path: &Path) -> Result<String> {
    std::fs::read_to_string(path)
        .map_err(|e| Error::input(path, "file", format!("cannot read: {e}")))
}

/// `out` relative to the URDD when inside it, else as given.
fn folder_in(urdd: &Path, out: &Path) -> String {
    out.strip_prefix(urdd)
        .unwrap_or(out)
        .to_string_lossy()
        .into_owned()
}
