//! The URDD directory: a manifest plus one folder per stage, each written atomically.
//!
//! ```text
//! DIR/manifest.json                 format, robot, one StageRecord per stage (key, inputs, parameters)
//! DIR/preprocess/robot.json         robot model, DOFs, adjacency            (RobotRecord)
//! DIR/preprocess/links.json         per-link fit of the six types          (Vec<LinkRecord>)
//! DIR/preprocess/shapes/<type>.json ordered shape list of each type        (ShapeFile)
//! DIR/preprocess/meshes/*.obj       link hulls and decomposition pieces
//! ```

mod layout;
mod manifest;
mod obj;
mod records;
mod shapes;
mod write;

pub use layout::{
    BENCH, EXPORT, EXPORT_INDEX, IMPORT, IMPORTED_FILE, LAYERS, MANIFEST, MESH_FILE, PREPROCESS,
    SAMPLE, SHARDS, USER_FILE, compact_json, json_value, parameters, sample_file_name,
    shape_file_name, stage_key,
};
pub use manifest::{
    FORMAT_VERSION, InputFile, Manifest, StageRecord, Stamp, sha256_file, sha256_hex,
};
pub use obj::{from_obj, to_obj};
pub use records::{GeometryRecord, LinkRecord, RobotRecord, ShapeFile, ShapeRecord};
pub use shapes::TypeShapes;
pub use write::{StageDir, WriterLock, ensure_not_file, json_bytes, recover, write_atomic};

use crate::error::{Error, Result};
use crate::shapes::{Geometry, Obb, ShapeType, Sphere};
use rayon::prelude::*;
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};

/// An opened URDD directory.
#[derive(Debug, Clone)]
pub struct Urdd {
    dir: PathBuf,
    manifest: Manifest,
}

impl Urdd {
    /// Opens an existing URDD: the manifest must exist, parse, and not come from a newer format.
    pub fn open(dir: &Path) -> Result<Urdd> {
        let path = dir.join(MANIFEST);
        if !path.is_file() {
            return Err(Error::input(
                dir,
                "manifest.json",
                "not a URDD directory (no manifest.json); run `scm preprocess ROBOT.urdf -o DIR` first",
            ));
        }
        let manifest: Manifest = read_json_file(&path)?;
        if manifest.format != "urdd" {
            return Err(Error::input(
                &path,
                "format",
                format!("expected \"urdd\", found \"{}\"", manifest.format),
            ));
        }
        if manifest.format_version > FORMAT_VERSION {
            return Err(Error::input(
                &path,
                "format_version",
                format!(
                    "written by a newer scm (format {} > {FORMAT_VERSION}, scm {}); upgrade scm",
                    manifest.format_version, manifest.tool_version
                ),
            ));
        }
        // A stage folder a killed commit left set aside comes back before anything reads it.
        for record in manifest.stages.values() {
            recover(&dir.join(&record.folder))?;
        }
        Ok(Urdd {
            dir: dir.to_path_buf(),
            manifest,
        })
    }

    /// Takes the writer lock of the URDD at `dir` for a stage that writes it (the folder is created if
    /// needed; an existing file there is bad input); while another process holds it, `progress` shows
    /// that this one waits.
    pub fn lock_for_writing(
        dir: &Path,
        progress: &dyn crate::progress::Progress,
    ) -> Result<WriterLock> {
        write::ensure_not_file(dir)?;
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        WriterLock::take(dir, || {
            progress.note(&format!(
                "waiting: another scm is writing {} (it holds {})",
                dir.display(),
                dir.join(".lock").display()
            ))
        })
    }

    /// Opens an existing URDD for a stage that writes it: checked first (so a missing URDD is bad input,
    /// not a new empty folder), then locked, then read under the lock.
    pub fn open_for_writing(
        dir: &Path,
        progress: &dyn crate::progress::Progress,
    ) -> Result<(Urdd, WriterLock)> {
        Urdd::open(dir)?;
        let lock = Urdd::lock_for_writing(dir, progress)?;
        Ok((Urdd::open(dir)?, lock))
    }

    /// Opens `dir` if it holds a readable manifest, else starts a fresh one for `robot` (nothing is
    /// written until a stage is recorded). A manifest that exists but is broken is an error.
    pub fn open_or_new(dir: &Path, robot: &str) -> Result<Urdd> {
        if dir.join(MANIFEST).exists() {
            Urdd::open(dir)
        } else {
            Ok(Urdd {
                dir: dir.to_path_buf(),
                manifest: Manifest::new(robot),
            })
        }
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The manifest.
    pub fn manifest(&self) -> &Manifest {
        &self.manifest
    }

    /// The record of stage `name`, or a bad-input error saying which command produces it.
    pub fn stage(&self, name: &str) -> Result<&StageRecord> {
        self.manifest.stages.get(name).ok_or_else(|| {
            Error::input(
                &self.dir.join(MANIFEST),
                format!("stage \"{name}\""),
                format!("missing; run `scm {name}` first"),
            )
        })
    }

    /// The record of stage `name`, which must be current: every stage it read still has the key it
    /// had then. A missing or stale stage is bad input saying which command to rerun.
    pub fn fresh_stage(&self, name: &str) -> Result<&StageRecord> {
        let record = self.stage(name)?;
        for (dep, key) in &record.depends_on {
            if self.manifest.stages.get(dep).is_none_or(|d| &d.key != key) {
                return Err(Error::input(
                    &self.dir.join(MANIFEST),
                    format!("stage \"{name}\""),
                    format!(
                        "stale: stage \"{dep}\" changed since it ran; rerun `scm {name} {}`",
                        self.dir.display()
                    ),
                ));
            }
        }
        Ok(record)
    }

    /// Whether stage `name` ran with `key` and all its output files are present.
    pub fn is_up_to_date(&self, name: &str, key: &str) -> bool {
        self.manifest
            .stages
            .get(name)
            .is_some_and(|s| s.key == key && self.output_changes(name).is_empty())
    }

    /// How the outputs of stage `name` differ from what it wrote (missing, another size, other
    /// content), one sentence each; empty when they are intact or the stage never ran.
    pub fn output_changes(&self, name: &str) -> Vec<String> {
        let Some(record) = self.manifest.stages.get(name) else {
            return Vec::new();
        };
        let folder = self.dir.join(&record.folder);
        record
            .outputs
            .iter()
            .filter_map(|o| {
                let path = folder.join(o);
                let shown = Path::new(&record.folder).join(o);
                let shown = shown.display();
                let Some(meta) = std::fs::metadata(&path).ok().filter(|m| m.is_file()) else {
                    return Some(format!("{shown} is missing"));
                };
                let stamp = record.stamps.get(o)?;
                if meta.len() != stamp.bytes {
                    return Some(format!(
                        "{shown} has {} bytes, {} were written",
                        meta.len(),
                        stamp.bytes
                    ));
                }
                (sha256_file(&path).ok()?.1 != stamp.sha256)
                    .then(|| format!("{shown} changed since it was written"))
            })
            .collect()
    }

    /// The note a stage gives when its key is unchanged but its outputs are not: which files, and that
    /// it reruns.
    pub fn rerun_note(&self, name: &str, key: &str) -> Option<String> {
        let record = self.manifest.stages.get(name)?;
        let changes = self.output_changes(name);
        (record.key == key && !changes.is_empty())
            .then(|| format!("rerunning {name}: {}", changes.join("; ")))
    }

    /// Records a finished stage and writes the manifest atomically.
    pub fn record_stage(&mut self, name: &str, robot: &str, mut record: StageRecord) -> Result<()> {
        let folder = self.dir.join(&record.folder);
        record.stamps = record
            .outputs
            .par_iter()
            .map(|o| {
                let path = folder.join(o);
                let (bytes, sha256) = sha256_file(&path).map_err(|e| Error::io(&path, e))?;
                Ok((o.clone(), Stamp { bytes, sha256 }))
            })
            .collect::<Result<_>>()?;
        self.manifest.robot = robot.to_string();
        self.manifest.format_version = FORMAT_VERSION;
        self.manifest.tool_version = crate::VERSION.to_string();
        self.manifest.stages.insert(name.to_string(), record);
        write_atomic(
            &self.dir.join(MANIFEST),
            &json_bytes(MANIFEST, &self.manifest)?,
        )
    }

    /// The summary a stage recorded (`field` of it, or the whole), read as `T`; a hand-broken manifest
    /// is an error naming it, not empty counts.
    pub fn stage_summary<T: DeserializeOwned>(&self, name: &str, field: Option<&str>) -> Result<T> {
        let summary = &self.stage(name)?.summary;
        let value = match field {
            Some(f) => summary.get(f).cloned().unwrap_or_default(),
            None => summary.clone(),
        };
        serde_json::from_value(value).map_err(|e| {
            Error::input(
                &self.dir.join(MANIFEST),
                format!("stages.{name}.summary"),
                format!("cannot read: {e}"),
            )
        })
    }

    /// Reads a JSON file of a stage folder.
    pub fn read_json<T: DeserializeOwned>(&self, stage: &str, relative: &str) -> Result<T> {
        let folder = &self.stage(stage)?.folder;
        read_json_file(&self.dir.join(folder).join(relative))
    }

    /// The shape types the current sample stage wrote records for, in [`ShapeType::ALL`] order. A
    /// missing or stale sample stage is bad input.
    pub fn sampled_types(&self) -> Result<Vec<ShapeType>> {
        let outputs = &self.fresh_stage(SAMPLE)?.outputs;
        Ok(ShapeType::ALL
            .into_iter()
            .filter(|t| outputs.contains(&sample_file_name(*t)))
            .collect())
    }

    /// The file `name` of the current sample stage, or `None` when the stage did not write it: the
    /// one reader of the sample records (per type) and the `mesh` verdicts. A missing or stale
    /// sample stage is bad input; a truncated or corrupt file is bad input naming it.
    pub fn sample_output<T: DeserializeOwned>(&self, name: &str) -> Result<Option<T>> {
        if !self.fresh_stage(SAMPLE)?.outputs.iter().any(|o| o == name) {
            return Ok(None);
        }
        self.read_json(SAMPLE, name).map(Some)
    }

    /// The robot model written by preprocessing.
    pub fn robot(&self) -> Result<RobotRecord> {
        let record: RobotRecord = self.read_json(PREPROCESS, "robot.json")?;
        // A hand-broken record must not send forward kinematics round a cycle or out of bounds.
        let folder = &self.stage(PREPROCESS)?.folder;
        record.robot.check_tree().map_err(|message| {
            Error::input(&self.dir.join(folder).join("robot.json"), "robot", message)
        })?;
        Ok(record)
    }

    /// The per-link fit records written by preprocessing.
    pub fn links(&self) -> Result<Vec<LinkRecord>> {
        self.read_json(PREPROCESS, "links.json")
    }

    /// The shape list of one type.
    pub fn shapes(&self, shape_type: ShapeType) -> Result<ShapeFile> {
        self.read_json(PREPROCESS, &shape_file_name(shape_type))
    }

    /// The geometry of a shape record (reads the OBJ of hulls).
    pub fn geometry(&self, record: &GeometryRecord) -> Result<Geometry> {
        Ok(match record {
            GeometryRecord::Sphere { center, radius } => Geometry::Sphere(Sphere {
                center: *center,
                radius: *radius,
            }),
            GeometryRecord::Obb {
                center,
                rotation,
                half_extents,
            } => Geometry::Obb(Obb {
                center: *center,
                rotation: *rotation,
                half_extents: *half_extents,
            }),
            GeometryRecord::Hull { mesh, .. } => {
                let path = self.dir.join(&self.stage(PREPROCESS)?.folder).join(mesh);
                let text = std::fs::read_to_string(&path)
                    .map_err(|e| Error::input(&path, "file", format!("cannot read: {e}")))?;
                Geometry::Hull(from_obj(&text).map_err(|m| Error::input(&path, "OBJ", m))?)
            }
        })
    }

    /// One line saying what the directory holds.
    pub fn summary_line(&self) -> String {
        let stages: Vec<&str> = self.manifest.stages.keys().map(String::as_str).collect();
        format!(
            "{}: robot \"{}\", URDD format {}, stages: {}",
            self.dir.display(),
            self.manifest.robot,
            self.manifest.format_version,
            if stages.is_empty() {
                "none".to_string()
            } else {
                stages.join(", ")
            }
        )
    }
}

/// Reads and parses a JSON file; a missing, truncated or malformed file is bad input naming the position.
pub fn read_json_file<T: DeserializeOwned>(path: &Path) -> Result<T> {
    let bytes =
        std::fs::read(path).map_err(|e| Error::input(path, "file", format!("cannot read: {e}")))?;
    serde_json::from_slice(&bytes).map_err(|e| {
        Error::input(
            path,
            format!("line {}, column {}", e.line(), e.column()),
            format!("invalid JSON: {e}"),
        )
    })
}
