//! The URDD directory: a manifest plus one folder per stage, each written atomically.
//!
//! ```text
//! DIR/manifest.json                 format, robot, one StageRecord per stage (key, inputs, parameters)
//! DIR/preprocess/robot.json         robot model, DOFs, adjacency            (RobotRecord)
//! DIR/preprocess/links.json         per-link fit of the six types          (Vec<LinkRecord>)
//! DIR/preprocess/shapes/<type>.json ordered shape list of each type        (ShapeFile)
//! DIR/preprocess/meshes/*.obj       link hulls and decomposition pieces
//! ```

mod manifest;
mod obj;
mod records;
mod write;

pub use manifest::{FORMAT_VERSION, InputFile, Manifest, StageRecord, sha256_hex};
pub use obj::{from_obj, to_obj};
pub use records::{GeometryRecord, LinkRecord, RobotRecord, ShapeFile, ShapeRecord};
pub use write::{StageDir, json_bytes, write_atomic};

use crate::error::{Error, Result};
use crate::shapes::{Geometry, Obb, ShapeType, Sphere};
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};

/// File name of the manifest.
pub const MANIFEST: &str = "manifest.json";
/// Folder of the preprocess stage.
pub const PREPROCESS: &str = "preprocess";

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
        Ok(Urdd {
            dir: dir.to_path_buf(),
            manifest,
        })
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
        self.manifest.stages.get(name).is_some_and(|s| {
            s.key == key
                && s.outputs
                    .iter()
                    .all(|o| self.dir.join(&s.folder).join(o).is_file())
        })
    }

    /// Records a finished stage and writes the manifest atomically.
    pub fn record_stage(&mut self, name: &str, robot: &str, record: StageRecord) -> Result<()> {
        self.manifest.robot = robot.to_string();
        self.manifest.format_version = FORMAT_VERSION;
        self.manifest.tool_version = crate::VERSION.to_string();
        self.manifest.stages.insert(name.to_string(), record);
        write_atomic(&self.dir.join(MANIFEST), &json_bytes(&self.manifest))
    }

    /// Reads a JSON file of a stage folder.
    pub fn read_json<T: DeserializeOwned>(&self, stage: &str, relative: &str) -> Result<T> {
        let folder = &self.stage(stage)?.folder;
        read_json_file(&self.dir.join(folder).join(relative))
    }

    /// The robot model written by preprocessing.
    pub fn robot(&self) -> Result<RobotRecord> {
        self.read_json(PREPROCESS, "robot.json")
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

/// The path of a type's shape list inside the preprocess folder.
pub fn shape_file_name(shape_type: ShapeType) -> String {
    format!("shapes/{}.json", shape_type.id())
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
