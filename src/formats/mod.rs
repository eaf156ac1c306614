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
}

impl JsonLines {
    /// An empty object.
    pub fn new() -> JsonLines {
        JsonLines::default()
    }

    fn key(&mut self, key: &str) {
        self.out
            .push_str(if self.out.is_empty() { "{\n" } else { ",\n" });
        self.out.push_str(&format!("  {}: ", compact(&key)));
    }

    /// A field written compactly on its line.
    pub fn field<T: Serialize + ?Sized>(&mut self, key: &str, value: &T) {
        self.key(key);
        self.out.push_str(&compact(value));
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
            self.out.push_str(&format!("    {}{sep}\n", compact(item)));
        }
        self.out.push_str("  ]");
    }

    /// The bytes, with a final newline.
    pub fn finish(mut self) -> Vec<u8> {
        if self.out.is_empty() {
            self.out.push('{');
        }
        self.out.push_str("\n}\n");
        self.out.into_bytes()
    }
}

/// Compact JSON of plain data (our own types with string keys cannot fail to serialise).
fn compact<T: Serialize + ?Sized>(value: &T) -> String {
    serde_json::to_string(value).unwrap_or_default()
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
