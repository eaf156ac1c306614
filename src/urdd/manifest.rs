//! `manifest.json`: what a URDD holds, which inputs and parameters made each stage, and their hashes.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The URDD format version this build writes and reads.
pub const FORMAT_VERSION: u32 = 1;

/// The top-level manifest of a URDD directory.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Always `"urdd"`.
    pub format: String,
    /// The format version ([`FORMAT_VERSION`] when written by this build).
    pub format_version: u32,
    /// The robot name.
    pub robot: String,
    /// The scm version that last wrote the manifest.
    pub tool_version: String,
    /// One record per stage that has run, keyed by stage name (`preprocess`, `sample`, ...).
    pub stages: BTreeMap<String, StageRecord>,
}

/// What one stage consumed and produced.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StageRecord {
    /// Hash over everything the stage's output depends on; equal keys mean the stage is up to date.
    pub key: String,
    /// The scm version that ran the stage.
    pub tool_version: String,
    /// Input files with their SHA-256.
    pub inputs: Vec<InputFile>,
    /// The stage parameters, as given.
    pub parameters: serde_json::Value,
    /// The folder (relative to the URDD) holding the stage's files.
    pub folder: String,
    /// Files written, relative to `folder`.
    pub outputs: Vec<String>,
    /// Each output's size and hash as written, so a truncated, emptied or edited output is not taken
    /// for up to date (filled in by `Urdd::record_stage`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub stamps: BTreeMap<String, Stamp>,
    /// A small stage-specific summary (counts), for humans and scripts.
    pub summary: serde_json::Value,
    /// The keys of the stages this one read, as they were when it ran; a different key now means this
    /// stage's output is stale.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub depends_on: BTreeMap<String, String>,
}

/// An output file's size and content hash.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Stamp {
    /// Size in bytes.
    pub bytes: u64,
    /// Hex SHA-256 of the content.
    pub sha256: String,
}

/// An input file and its content hash.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct InputFile {
    /// The role of the file (`urdf`, `mesh`).
    pub role: String,
    /// The path as used by the run.
    pub path: String,
    /// Hex SHA-256 of the content.
    pub sha256: String,
}

impl Manifest {
    /// An empty manifest for `robot`.
    pub fn new(robot: &str) -> Manifest {
        Manifest {
            format: "urdd".into(),
            format_version: FORMAT_VERSION,
            robot: robot.into(),
            tool_version: crate::VERSION.into(),
            stages: BTreeMap::new(),
        }
    }
}

/// Hex SHA-256 of `bytes`.
pub fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::Digest;
    hex(&sha2::Sha256::digest(bytes))
}

/// The length and hex SHA-256 of the file at `path`, read a piece at a time: a stage's outputs can be
/// tens of MB.
pub fn sha256_file(path: &std::path::Path) -> std::io::Result<(u64, String)> {
    use sha2::Digest;
    use std::io::Read;
    let mut file = std::fs::File::open(path)?;
    let (mut hasher, mut buf, mut len) = (sha2::Sha256::new(), vec![0; 1 << 16], 0);
    loop {
        match file.read(&mut buf) {
            Ok(0) => return Ok((len, hex(&hasher.finalize()))),
            Ok(n) => {
                hasher.update(&buf[..n]);
                len += n as u64;
            }
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
}

fn hex(digest: &[u8]) -> String {
    digest.iter().map(|b| format!("{b:02x}")).collect()
}
