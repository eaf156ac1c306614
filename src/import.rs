//! The `import-moveit` stage: a MoveIt SRDF's `<disable_collisions>`, `<enable_collisions>` and
//! `<disable_default_collisions>` stored as the URDD's imported layer, keeping MoveIt's reasons.

use crate::error::{Error, Result};
use crate::formats::srdf::{SrdfPair, parse_srdf};
use crate::matrix::{ImportedLayer, ImportedPair};
use crate::robot::GeometryOrigin;
use crate::urdd::{
    IMPORT, IMPORTED_FILE, InputFile, LAYERS, PREPROCESS, StageRecord, Urdd, sha256_hex, stage_key,
};
use serde::Serialize;
use std::collections::{BTreeMap, HashMap};
use std::path::PathBuf;

/// What to import.
#[derive(Debug, Clone)]
pub struct ImportOptions {
    /// The SRDF file.
    pub srdf: PathBuf,
    /// The URDD directory (after `scm preprocess`).
    pub urdd: PathBuf,
}

/// What an import stored and what it warned about.
#[derive(Debug, Clone, Serialize)]
pub struct ImportReport {
    /// The URDD directory.
    pub urdd: PathBuf,
    /// The SRDF.
    pub srdf: PathBuf,
    /// `<disable_collisions>` elements read, per MoveIt reason (as written in the SRDF).
    pub reasons: BTreeMap<String, usize>,
    /// `<enable_collisions>` elements read.
    pub enabled: usize,
    /// Links named by `<disable_default_collisions>`.
    pub default_disabled: usize,
    /// Distinct link pairs stored in the imported layer.
    pub stored: usize,
    /// Problems that did not stop the import (unknown links, links without geometry, duplicates).
    pub warnings: Vec<String>,
}

/// Reads the SRDF and replaces the URDD's imported layer with it, recorded in the manifest as the
/// `import-moveit` stage (the SRDF's hash as its input, the layer file stamped).
pub fn import_moveit(opts: &ImportOptions) -> Result<ImportReport> {
    let text = std::fs::read_to_string(&opts.srdf)
        .map_err(|e| Error::input(&opts.srdf, "file", format!("cannot read: {e}")))?;
    let srdf = parse_srdf(&text, &opts.srdf)?;
    let (mut urdd, _lock) = Urdd::open_for_writing(&opts.urdd, &crate::progress::NoProgress)?;
    let robot = urdd.robot()?.robot;
    let file = opts.srdf.display().to_string();
    let mut warnings = Vec::new();
    if !srdf.robot.is_empty() && srdf.robot != robot.name {
        warnings.push(format!(
            "{file}: <robot name=\"{}\"> differs from the URDD's robot \"{}\"",
            srdf.robot, robot.name
        ));
    }
    // A link the pair can apply to: it exists and has geometry. Otherwise warn.
    let usable = |link: &str, line: u32, warnings: &mut Vec<String>| match robot.link_index(link) {
        None => {
            warnings.push(format!(
                "{file}: line {line}: link \"{link}\" does not exist in robot \"{}\"; ignored",
                robot.name
            ));
            false
        }
        Some(i) if robot.links[i].geometry_source == GeometryOrigin::None => {
            warnings.push(format!(
                "{file}: line {line}: link \"{link}\" has no geometry; the pair affects no shape"
            ));
            false
        }
        Some(_) => true,
    };

    let mut reasons = BTreeMap::new();
    let mut stored: HashMap<(String, String), (ImportedPair, u32)> = HashMap::new();
    let entries = srdf
        .disabled
        .iter()
        .map(|p| (p, true))
        .chain(srdf.enabled.iter().map(|p| (p, false)));
    for (pair, skip) in entries {
        if skip {
            let reason = pair.reason.clone().unwrap_or_default();
            *reasons.entry(reason).or_insert(0) += 1;
        }
        store(pair, skip, &file, &mut stored, &mut warnings, &usable);
    }
    let mut default_disabled = Vec::new();
    for (link, line) in &srdf.default_disabled {
        if usable(link, *line, &mut warnings) {
            default_disabled.push(link.clone());
        }
    }
    default_disabled.sort();
    default_disabled.dedup();

    let mut layer = ImportedLayer::new(
        file.clone(),
        sha256_hex(text.as_bytes()),
        srdf.robot.clone(),
    );
    layer.pairs = stored.into_values().map(|(p, _)| p).collect();
    layer.pairs.sort();
    layer.default_disabled = default_disabled;
    layer.save(&urdd)?;
    let report = ImportReport {
        urdd: opts.urdd.clone(),
        srdf: opts.srdf.clone(),
        reasons,
        enabled: srdf.enabled.len(),
        default_disabled: layer.default_disabled.len(),
        stored: layer.pairs.len(),
        warnings,
    };
    let preprocess_key = urdd.stage(PREPROCESS)?.key.clone();
    let srdf_hash = sha256_hex(text.as_bytes());
    urdd.record_stage(
        IMPORT,
        &robot.name,
        StageRecord {
            key: stage_key(
                IMPORT,
                serde_json::json!({ "srdf": srdf_hash, "preprocess": preprocess_key }),
            ),
            tool_version: crate::VERSION.into(),
            inputs: vec![InputFile {
                role: "srdf".into(),
                path: file,
                sha256: srdf_hash,
            }],
            parameters: serde_json::Value::Null,
            folder: LAYERS.into(),
            outputs: vec![IMPORTED_FILE.into()],
            stamps: Default::default(),
            summary: serde_json::json!({
                "reasons": &report.reasons,
                "enabled": report.enabled,
                "default_disabled": report.default_disabled,
                "stored": report.stored,
            }),
            depends_on: [(PREPROCESS.to_string(), preprocess_key)].into(),
        },
    )?;
    Ok(report)
}

/// Stores one SRDF pair, warning about self pairs, unusable links, duplicates and reversals.
fn store(
    pair: &SrdfPair,
    skip: bool,
    file: &str,
    stored: &mut HashMap<(String, String), (ImportedPair, u32)>,
    warnings: &mut Vec<String>,
    usable: &dyn Fn(&str, u32, &mut Vec<String>) -> bool,
) {
    let line = pair.line;
    if pair.link1 == pair.link2 {
        warnings.push(format!(
            "{file}: line {line}: pair names link \"{}\" twice; ignored",
            pair.link1
        ));
        return;
    }
    let ok1 = usable(&pair.link1, line, warnings);
    let ok2 = usable(&pair.link2, line, warnings);
    if !(ok1 && ok2) {
        return;
    }
    let (a, b) = if pair.link1 <= pair.link2 {
        (pair.link1.clone(), pair.link2.clone())
    } else {
        (pair.link2.clone(), pair.link1.clone())
    };
    let reason = if skip {
        pair.reason.clone().unwrap_or_default()
    } else {
        "enabled".into()
    };
    if let Some((previous, previous_line)) = stored.get(&(a.clone(), b.clone())) {
        let how = if previous.link1 == pair.link1 {
            "duplicates"
        } else {
            "repeats (reversed)"
        };
        warnings.push(format!(
            "{file}: line {line}: pair \"{}\" - \"{}\" {how} the pair on line {previous_line}; the later one is kept",
            pair.link1, pair.link2
        ));
    }
    stored.insert(
        (a, b),
        (
            ImportedPair {
                link1: pair.link1.clone(),
                link2: pair.link2.clone(),
                skip,
                reason,
            },
            line,
        ),
    );
}
