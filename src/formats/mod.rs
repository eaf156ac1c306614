//! File formats scm writes and reads, one module per format: the six matrix files, MoveIt SRDF,
//! MuJoCo MJCF excludes, cuRobo, Drake, SVG heat maps, and the paper's URDD modules.

pub mod curobo;
pub mod drake;
pub mod matrices;
pub mod mjcf;
pub mod paper_modules;
pub mod srdf;
pub mod svg;

use serde::Serialize;

/// A JSON object written one field per line and one list item per line: readable and diffable, and
/// small for large matrices. Field order is the order of the calls.
#[derive(Debug, Default)]
pub struct JsonLines {
    out: String,
    /// The first value that could not be written (reported by [`JsonLines::finish`]).
    error: Option<String>,
}

impl JsonLines {
    /// An empty object.
    pub fn new() -> JsonLines {
        JsonLines::default()
    }

    fn key(&mut self, key: &str) {
        self.out
            .push_str(if self.out.is_empty() { "{\n" } else { ",\n" });
        self.out
            .push_str(&format!("  {}: ", serde_json::Value::from(key)));
    }

    /// Compact JSON of `value`; a value JSON cannot hold is kept as the object's error.
    fn compact<T: Serialize + ?Sized>(&mut self, value: &T) -> String {
        serde_json::to_string(value).unwrap_or_else(|e| {
            self.error.get_or_insert(e.to_string());
            String::new()
        })
    }

    /// A field written compactly on its line.
    pub fn field<T: Serialize + ?Sized>(&mut self, key: &str, value: &T) {
        self.key(key);
        let text = self.compact(value);
        self.out.push_str(&text);
    }

    /// A list with one compact item per line.
    pub fn list<T: Serialize>(&mut self, key: &str, items: &[T]) {
        self.key(key);
        if items.is_empty() {
            self.out.push_str("[]");
            return;
        }
        self.out.push_str("[\n");
        for (i, item) in items.iter().enumerate() {
            let sep = if i + 1 < items.len() { "," } else { "" };
            let text = self.compact(item);
            self.out.push_str(&format!("    {text}{sep}\n"));
        }
        self.out.push_str("  ]");
    }

    /// The bytes, with a final newline; or the error of the first value JSON could not hold, never
    /// an object with a value missing.
    pub fn finish(mut self) -> Result<Vec<u8>, String> {
        if let Some(e) = self.error {
            return Err(format!("cannot be written as JSON: {e}"));
        }
        if self.out.is_empty() {
            self.out.push('{');
        }
        self.out.push_str("\n}\n");
        Ok(self.out.into_bytes())
    }
}

/// Escapes text for an XML attribute value or text node.
pub fn xml_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::JsonLines;
    use std::collections::BTreeMap;

    #[test]
    fn a_value_json_cannot_hold_is_an_error_not_a_missing_field() {
        let mut o = JsonLines::new();
        o.field("robot", "arm");
        // JSON object keys are strings: a map keyed by pairs cannot be written.
        let bad: BTreeMap<(u8, u8), u8> = [((1, 2), 3)].into();
        o.field("pairs", &bad);
        let err = o.finish().unwrap_err();
        assert!(err.contains("cannot be written as JSON"), "{err}");

        let mut o = JsonLines::new();
        o.field("robot", "arm");
        o.list("skip", &[1, 2]);
        let text = String::from_utf8(o.finish().unwrap()).unwrap();
        assert_eq!(
            text,
            "{\n  \"robot\": \"arm\",\n  \"skip\": [\n    1,\n    2\n  ]\n}\n"
        );
    }
}
