//! The URDD's layout and stage bookkeeping in one place: every folder and file name a stage writes or
//! reads, and the one recipe for a stage's key (what makes a stage's output current).
//!
//! ```text
//! DIR/manifest.json                      one StageRecord per stage
//! DIR/preprocess/shapes/<type>.json      shape lists          DIR/preprocess/meshes/*.obj
//! DIR/sample/<type>.json, mesh.json      sample records       DIR/sample-shards/  shard partials
//! DIR/layers/imported.json, user.json    imported and user layers
//! DIR/export/export.json + files         the export           DIR/bench/          bench tables
//! ```

use super::manifest::{FORMAT_VERSION, sha256_hex};
use crate::error::{Error, Result};
use crate::shapes::ShapeType;
use serde::Serialize;

/// File name of the manifest.
pub const MANIFEST: &str = "manifest.json";
/// Folder of the preprocess stage.
pub const PREPROCESS: &str = "preprocess";
/// Folder of the sample stage.
pub const SAMPLE: &str = "sample";
/// Folder of shard partial results.
pub const SHARDS: &str = "sample-shards";
/// The sample stage's link-level verdicts on the exact geometry.
pub const MESH_FILE: &str = "mesh.json";
/// Name of the import stage's manifest record (its output is [`IMPORTED_FILE`] in [`LAYERS`]).
pub const IMPORT: &str = "import-moveit";
/// Folder of the imported and user layers.
pub const LAYERS: &str = "layers";
/// The imported layer's file in [`LAYERS`].
pub const IMPORTED_FILE: &str = "imported.json";
/// The user layer's file in [`LAYERS`].
pub const USER_FILE: &str = "user.json";
/// Default folder of the export stage.
pub const EXPORT: &str = "export";
/// The export's index of what it wrote, inside its folder.
pub const EXPORT_INDEX: &str = "export.json";
/// Folder of the bench stage.
pub const BENCH: &str = "bench";

/// The path of a type's shape list inside the preprocess folder.
pub fn shape_file_name(shape_type: ShapeType) -> String {
    format!("shapes/{}.json", shape_type.id())
}

/// The file of a type's sample records inside the sample folder.
pub fn sample_file_name(t: ShapeType) -> String {
    format!("{}.json", t.id())
}

/// The one stage-key recipe: the SHA-256 of the canonical JSON of the stage's name, the URDD format
/// and tool versions, and `reads` (an object of what the stage read: input hashes, the keys of the
/// stages it depends on, parameters). Paths never count, so a moved URDD stays current.
pub fn stage_key(stage: &str, reads: serde_json::Value) -> String {
    let mut material = match reads {
        serde_json::Value::Object(m) => m,
        other => {
            let mut m = serde_json::Map::new();
            m.insert("reads".into(), other);
            m
        }
    };
    material.insert("stage".into(), stage.into());
    material.insert("format_version".into(), FORMAT_VERSION.into());
    material.insert("tool_version".into(), crate::VERSION.into());
    // A JSON value's pretty text (`{:#}`) is the pretty serialisation, and it cannot fail: its keys are
    // strings.
    sha256_hex(format!("{:#}\n", serde_json::Value::Object(material)).as_bytes())
}

/// `value` as JSON: as a value, or as compact bytes with a final newline. A value JSON cannot hold
/// (a map with non-string keys, a failing serialiser) is an error naming `what`, never empty data.
pub fn json_value<T: Serialize>(what: &str, value: &T) -> Result<serde_json::Value> {
    serde_json::to_value(value).map_err(|e| json_error(what, e))
}

/// `value` as compact JSON bytes (see [`json_value`]).
pub fn compact_json<T: Serialize>(what: &str, value: &T) -> Result<Vec<u8>> {
    serde_json::to_vec(value).map_err(|e| json_error(what, e))
}

/// The error of `what` JSON could not hold.
pub(super) fn json_error(what: &str, e: serde_json::Error) -> Error {
    Error::Failed {
        context: what.to_string(),
        message: format!("cannot be written as JSON: {e}"),
    }
}

/// A stage's options as recorded in the manifest and its key: every field but the URDD's own path
/// (`urdd`). A value that cannot be written as JSON is an error naming `stage`.
pub fn parameters<T: Serialize>(stage: &str, options: &T) -> Result<serde_json::Value> {
    let mut v = json_value(&format!("{stage} parameters"), options)?;
    if let Some(m) = v.as_object_mut() {
        m.remove("urdd");
    }
    Ok(v)
}
