//! MoveIt SRDF: `<disable_collisions link1 link2 reason>` written from a link-level matrix, merged into
//! an existing SRDF, and read back for `scm import-moveit`.

use super::xml_escape;
use crate::error::{Error, Result};
use crate::matrix::{Entry, Layer, LinkPair};
use std::ops::Range;
use std::path::Path;

/// MoveIt's reason for a skipped link pair: Adjacent, Default, Always, Never or User.
pub fn moveit_reason(entry: &Entry) -> String {
    match entry.layer {
        Layer::User => "User".into(),
        Layer::Imported if entry.reason == "disable_default" => "User".into(),
        Layer::Imported => entry.reason.clone(),
        Layer::Inferred => match entry.reason.as_str() {
            "adjacent" => "Adjacent",
            "default" => "Default",
            "always" => "Always",
            "never" => "Never",
            _ => "User",
        }
        .into(),
    }
}

/// The `<disable_collisions>` lines of the skipped pairs, each prefixed by `indent`.
pub fn disable_lines(pairs: &[LinkPair], indent: &str) -> String {
    pairs
        .iter()
        .filter(|p| p.entry.skip)
        .map(|p| {
            format!(
                "{indent}<disable_collisions link1=\"{}\" link2=\"{}\" reason=\"{}\"/> <!-- {} -->\n",
                xml_escape(&p.link1),
                xml_escape(&p.link2),
                xml_escape(&moveit_reason(&p.entry)),
                decided_by(p).replace("--", "- -")
            )
        })
        .collect()
}

/// Which geometry decided a pair, for the comment after its line: `mesh, certified`, `mesh, sampled`,
/// `mesh`, a shape type's id, `imported` or `user`.
pub fn decided_by(p: &LinkPair) -> String {
    match p.evidence {
        Some(e) => format!("{}, {}", p.geometry, e.id()),
        None => p.geometry.clone(),
    }
}

/// A complete SRDF holding only the disabled pairs.
pub fn write_srdf(robot: &str, comment: &str, pairs: &[LinkPair]) -> String {
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!-- {} -->\n<robot name=\"{}\">\n{}</robot>\n",
        comment.replace("--", "- -"),
        xml_escape(robot),
        disable_lines(pairs, "    ")
    )
}

/// `existing` (the SRDF at `path`) with its `<disable_collisions>` replaced by `pairs`; everything
/// else (groups, states, end effectors, comments, formatting) is kept byte for byte.
pub fn merge_into(existing: &str, path: &Path, pairs: &[LinkPair]) -> Result<String> {
    let doc = parse(existing, path)?;
    let root = doc.root_element();
    let old: Vec<Range<usize>> = root
        .children()
        .filter(|n| n.has_tag_name("disable_collisions"))
        .map(|n| whole_lines(existing, n.range()))
        .collect();
    let (at, indent) = match old.first() {
        Some(r) => (r.start, leading_space(existing, r.start)),
        None => {
            let close = existing[..root.range().end]
                .rfind("</")
                .unwrap_or(root.range().end);
            let line = whole_lines(existing, close..close).start;
            let indent = root
                .children()
                .find(|n| n.is_element())
                .map(|n| leading_space(existing, whole_lines(existing, n.range()).start))
                .unwrap_or_else(|| "    ".into());
            (line, indent)
        }
    };
    let mut out = String::with_capacity(existing.len());
    let mut pos = 0;
    let mut inserted = false;
    for r in old.iter().cloned().chain(std::iter::once(at..at)) {
        if r.start < pos {
            continue;
        }
        out.push_str(&existing[pos..r.start]);
        if !inserted && r.start >= at {
            out.push_str(&disable_lines(pairs, &indent));
            inserted = true;
        }
        pos = r.end;
    }
    out.push_str(&existing[pos..]);
    Ok(out)
}

/// Extends `r` to whole lines when only whitespace surrounds it on its first and last line.
fn whole_lines(text: &str, r: Range<usize>) -> Range<usize> {
    let line_start = text[..r.start].rfind('\n').map_or(0, |i| i + 1);
    let start = if text[line_start..r.start].trim().is_empty() {
        line_start
    } else {
        r.start
    };
    let rest = &text[r.end..];
    let end = match rest.find('\n') {
        Some(i) if rest[..i].trim().is_empty() => r.end + i + 1,
        None if rest.trim().is_empty() => text.len(),
        _ => r.end,
    };
    start..end
}

/// The whitespace at the start of the line beginning at `line_start`.
fn leading_space(text: &str, line_start: usize) -> String {
    text[line_start..]
        .chars()
        .take_while(|c| *c == ' ' || *c == '\t')
        .collect()
}

/// A link pair named by an SRDF element.
#[derive(Debug, Clone, PartialEq)]
pub struct SrdfPair {
    /// `link1`.
    pub link1: String,
    /// `link2`.
    pub link2: String,
    /// `reason`, if given.
    pub reason: Option<String>,
    /// Line of the element.
    pub line: u32,
}

/// The collision settings of an SRDF.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Srdf {
    /// `<robot name>`.
    pub robot: String,
    /// `<disable_collisions>`.
    pub disabled: Vec<SrdfPair>,
    /// `<enable_collisions>`.
    pub enabled: Vec<SrdfPair>,
    /// `<disable_default_collisions link>` with its line.
    pub default_disabled: Vec<(String, u32)>,
}

/// Reads the collision settings of the SRDF text from `path`.
pub fn parse_srdf(text: &str, path: &Path) -> Result<Srdf> {
    let doc = parse(text, path)?;
    let root = doc.root_element();
    let line = |n: roxmltree::Node| doc.text_pos_at(n.range().start).row;
    if !root.has_tag_name("robot") {
        return Err(Error::input(
            path,
            format!("<{}>, line {}", root.tag_name().name(), line(root)),
            "the root element of an SRDF must be <robot>",
        ));
    }
    let mut srdf = Srdf {
        robot: root.attribute("name").unwrap_or_default().to_string(),
        ..Srdf::default()
    };
    for n in root.children().filter(|n| n.is_element()) {
        let attr = |name: &str| {
            n.attribute(name).map(str::to_string).ok_or_else(|| {
                Error::input(
                    path,
                    format!("<{}>, line {}", n.tag_name().name(), line(n)),
                    format!("missing attribute \"{name}\""),
                )
            })
        };
        match n.tag_name().name() {
            tag @ ("disable_collisions" | "enable_collisions") => {
                let pair = SrdfPair {
                    link1: attr("link1")?,
                    link2: attr("link2")?,
                    reason: n.attribute("reason").map(str::to_string),
                    line: line(n),
                };
                if tag == "disable_collisions" {
                    srdf.disabled.push(pair);
                } else {
                    srdf.enabled.push(pair);
                }
            }
            "disable_default_collisions" => srdf.default_disabled.push((attr("link")?, line(n))),
            _ => {}
        }
    }
    Ok(srdf)
}

/// Parses XML; malformed XML is bad input naming the line and column.
fn parse<'a>(text: &'a str, path: &Path) -> Result<roxmltree::Document<'a>> {
    roxmltree::Document::parse(text).map_err(|e| {
        // roxmltree places an unexpected end at 1:1; the end of the text is where it is.
        let pos = match e {
            roxmltree::Error::UnexpectedEndOfStream => roxmltree::TextPos::new(
                text.lines().count().max(1) as u32 + u32::from(text.ends_with('\n')),
                1,
            ),
            _ => e.pos(),
        };
        Error::input(
            path,
            format!("line {}, column {}", pos.row, pos.col),
            format!("malformed XML: {e}"),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pair(a: &str, b: &str, reason: &str) -> LinkPair {
        LinkPair {
            link1: a.into(),
            link2: b.into(),
            entry: Entry {
                skip: true,
                reason: reason.into(),
                layer: Layer::Inferred,
            },
            geometry: "mesh".into(),
            evidence: None,
        }
    }

    #[test]
    fn merge_replaces_only_disable_collisions() {
        let existing = "<?xml version=\"1.0\"?>\n<!-- keep me -->\n<robot name=\"r\">\n  <group name=\"arm\">\n    <chain base_link=\"a\" tip_link=\"c\"/>\n  </group>\n  <!--Disable collisions-->\n  <disable_collisions link1=\"a\" link2=\"b\" reason=\"Adjacent\"/>\n  <disable_collisions link1=\"a\" link2=\"c\" reason=\"Never\"/>\n  <end_effector name=\"e\" parent_link=\"c\" group=\"arm\"/>\n</robot>\n";
        let merged = merge_into(
            existing,
            Path::new("r.srdf"),
            &[pair("a", "b", "adjacent"), pair("b", "c", "always")],
        )
        .unwrap();
        assert_eq!(
            merged,
            "<?xml version=\"1.0\"?>\n<!-- keep me -->\n<robot name=\"r\">\n  <group name=\"arm\">\n    <chain base_link=\"a\" tip_link=\"c\"/>\n  </group>\n  <!--Disable collisions-->\n  <disable_collisions link1=\"a\" link2=\"b\" reason=\"Adjacent\"/> <!-- mesh -->\n  <disable_collisions link1=\"b\" link2=\"c\" reason=\"Always\"/> <!-- mesh -->\n  <end_effector name=\"e\" parent_link=\"c\" group=\"arm\"/>\n</robot>\n"
        );
    }

    #[test]
    fn merge_without_existing_pairs_appends_before_the_end_tag() {
        let existing = "<robot name=\"r\">\n    <group name=\"arm\"/>\n</robot>\n";
        let merged = merge_into(existing, Path::new("r.srdf"), &[pair("a", "b", "never")]).unwrap();
        assert_eq!(
            merged,
            "<robot name=\"r\">\n    <group name=\"arm\"/>\n    <disable_collisions link1=\"a\" link2=\"b\" reason=\"Never\"/> <!-- mesh -->\n</robot>\n"
        );
    }

    #[test]
    fn malformed_xml_names_the_line() {
        let err = parse_srdf(
            "<robot>\n<disable_collisions link1=\"a\"\n",
            Path::new("x.srdf"),
        )
        .unwrap_err()
        .to_string();
        assert!(err.starts_with("x.srdf: line 3"), "{err}");
    }
}
