//! The user layer: skip marks a person set (in the viewer), per shape type and shape pair.

use super::{LAYERS, ShapeKey, ordered};
use crate::error::Result;
use crate::shapes::ShapeType;
use crate::urdd::{FORMAT_VERSION, Urdd, json_bytes, read_json_file, write_atomic};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

pub use crate::urdd::USER_FILE;

/// One mark: the pair `{a, b}` of `shape_type` is skipped (`skip`) or checked (`!skip`).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub struct UserEdit {
    /// The shape type.
    pub shape_type: ShapeType,
    /// One shape (`a <= b` in the file).
    pub a: ShapeKey,
    /// The other shape.
    pub b: ShapeKey,
    /// Skip (`true`) or check (`false`).
    pub skip: bool,
}

/// `layers/user.json`: every mark, in canonical order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct UserLayer {
    /// Format version.
    pub format_version: u32,
    /// The marks, sorted, at most one per pair and type.
    pub edits: Vec<UserEdit>,
}

impl Default for UserLayer {
    fn default() -> Self {
        UserLayer {
            format_version: FORMAT_VERSION,
            edits: Vec::new(),
        }
    }
}

impl UserLayer {
    /// The user layer of `urdd` (empty when there is none).
    pub fn load(urdd: &Urdd) -> Result<UserLayer> {
        let path = urdd.dir().join(LAYERS).join(USER_FILE);
        if !path.exists() {
            return Ok(UserLayer::default());
        }
        let mut layer: UserLayer = read_json_file(&path)?;
        layer.normalise();
        Ok(layer)
    }

    /// Writes the layer atomically into `urdd`.
    pub fn save(&self, urdd: &Urdd) -> Result<()> {
        let mut layer = self.clone();
        layer.normalise();
        write_atomic(
            &urdd.dir().join(LAYERS).join(USER_FILE),
            &json_bytes(USER_FILE, &layer)?,
        )
    }

    /// Marks pair `{a, b}` of `shape_type` as skipped or checked, replacing an earlier mark.
    pub fn set(&mut self, shape_type: ShapeType, a: ShapeKey, b: ShapeKey, skip: bool) {
        let (a, b) = ordered(a, b);
        self.unset(shape_type, &a, &b);
        self.edits.push(UserEdit {
            shape_type,
            a,
            b,
            skip,
        });
        self.edits.sort();
    }

    /// Removes the mark of pair `{a, b}`, so the lower layers decide again.
    pub fn unset(&mut self, shape_type: ShapeType, a: &ShapeKey, b: &ShapeKey) {
        let (a, b) = ordered(a.clone(), b.clone());
        self.edits
            .retain(|e| !(e.shape_type == shape_type && e.a == a && e.b == b));
    }

    /// The mark of pair `{a, b}`, if any.
    pub fn get(&self, shape_type: ShapeType, a: &ShapeKey, b: &ShapeKey) -> Option<bool> {
        let (a, b) = ordered(a.clone(), b.clone());
        self.edits
            .iter()
            .find(|e| e.shape_type == shape_type && e.a == a && e.b == b)
            .map(|e| e.skip)
    }

    /// The marks of one type, keyed by their ordered pair.
    pub(super) fn lookup(&self, shape_type: ShapeType) -> HashMap<(ShapeKey, ShapeKey), bool> {
        self.edits
            .iter()
            .filter(|e| e.shape_type == shape_type)
            .map(|e| (ordered(e.a.clone(), e.b.clone()), e.skip))
            .collect()
    }

    /// Orders each pair and the list; a later duplicate of a pair wins.
    fn normalise(&mut self) {
        let mut seen = std::collections::BTreeMap::new();
        for e in self.edits.drain(..) {
            let (a, b) = ordered(e.a, e.b);
            seen.insert((e.shape_type, a, b), e.skip);
        }
        self.edits = seen
            .into_iter()
            .map(|((shape_type, a, b), skip)| UserEdit {
                shape_type,
                a,
                b,
                skip,
            })
            .collect();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(link: &str) -> ShapeKey {
        ShapeKey {
            link: link.into(),
            piece: 0,
        }
    }

    #[test]
    fn set_replaces_and_unset_removes_in_any_order() {
        let mut layer = UserLayer::default();
        layer.set(ShapeType::Hull, key("b"), key("a"), true);
        layer.set(ShapeType::Hull, key("a"), key("b"), false);
        assert_eq!(layer.edits.len(), 1);
        assert_eq!(
            layer.get(ShapeType::Hull, &key("b"), &key("a")),
            Some(false)
        );
        assert_eq!(layer.get(ShapeType::Obb, &key("a"), &key("b")), None);
        layer.unset(ShapeType::Hull, &key("b"), &key("a"));
        assert!(layer.edits.is_empty());
    }
}
