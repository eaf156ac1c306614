//! The imported layer: the link pairs of a MoveIt SRDF, with MoveIt's reasons, applied to every shape
//! pair between the two links.

use super::LAYERS;
use crate::error::Result;
use crate::urdd::{FORMAT_VERSION, Urdd, json_bytes, read_json_file, write_atomic};
use serde::{Deserialize, Serialize};
use std::collections::{HashMap, HashSet};

pub use crate::urdd::IMPORTED_FILE;

/// One link pair from the SRDF.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub struct ImportedPair {
    /// One link, as written in the SRDF.
    pub link1: String,
    /// The other link.
    pub link2: String,
    /// Disabled (`<disable_collisions>`: skip) or enabled (`<enable_collisions>`: check).
    pub skip: bool,
    /// MoveIt's reason (`Adjacent`, `Never`, ...); `enabled` for `<enable_collisions>`.
    pub reason: String,
}

/// `layers/imported.json`: what `scm import-moveit` read.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ImportedLayer {
    /// Format version.
    pub format_version: u32,
    /// The SRDF file as given.
    pub source: String,
    /// SHA-256 of the SRDF.
    pub sha256: String,
    /// The SRDF's robot name.
    pub robot: String,
    /// Link pairs, sorted, one per unordered pair.
    pub pairs: Vec<ImportedPair>,
    /// Links named by `<disable_default_collisions>`: every pair with them is skipped unless a pair
    /// entry says otherwise.
    pub default_disabled: Vec<String>,
}

/// An imported layer indexed for lookups.
#[derive(Debug)]
pub struct ImportedLookup<'a> {
    pairs: HashMap<(&'a str, &'a str), &'a ImportedPair>,
    default_disabled: HashSet<&'a str>,
}

impl ImportedLookup<'_> {
    /// The imported verdict of link pair `{a, b}` as (skip, reason), if the SRDF decides it.
    pub fn get(&self, a: &str, b: &str) -> Option<(bool, &str)> {
        let key = if a <= b { (a, b) } else { (b, a) };
        if let Some(p) = self.pairs.get(&key) {
            return Some((p.skip, p.reason.as_str()));
        }
        (a != b && (self.default_disabled.contains(a) || self.default_disabled.contains(b)))
            .then_some((true, "disable_default"))
    }
}

impl ImportedLayer {
    /// The imported layer of `urdd`, if one was imported.
    pub fn load(urdd: &Urdd) -> Result<Option<ImportedLayer>> {
        let path = urdd.dir().join(LAYERS).join(IMPORTED_FILE);
        if !path.exists() {
            return Ok(None);
        }
        read_json_file(&path).map(Some)
    }

    /// Writes the layer atomically into `urdd`, replacing an earlier import.
    pub fn save(&self, urdd: &Urdd) -> Result<()> {
        write_atomic(
            &urdd.dir().join(LAYERS).join(IMPORTED_FILE),
            &json_bytes(IMPORTED_FILE, self)?,
        )
    }

    /// An empty layer for the SRDF `source`.
    pub fn new(source: String, sha256: String, robot: String) -> ImportedLayer {
        ImportedLayer {
            format_version: FORMAT_VERSION,
            source,
            sha256,
            robot,
            pairs: Vec::new(),
            default_disabled: Vec::new(),
        }
    }

    /// The layer indexed by link pair.
    pub fn lookup(&self) -> ImportedLookup<'_> {
        ImportedLookup {
            pairs: self
                .pairs
                .iter()
                .map(|p| {
                    let (a, b) = (p.link1.as_str(), p.link2.as_str());
                    (if a <= b { (a, b) } else { (b, a) }, p)
                })
                .collect(),
            default_disabled: self.default_disabled.iter().map(String::as_str).collect(),
        }
    }
}
