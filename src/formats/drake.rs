//! Drake: `<drake:collision_filter_group>` elements to paste into the robot's URDF (inside `<robot>`).
//! One group per link that takes part in a skipped pair; each group ignores the groups of the later
//! links it is skipped with.

use super::xml_escape;
use crate::matrix::LinkPair;

/// The group name of a link.
pub fn group_name(link: &str) -> String {
    format!("scm_{link}")
}

/// The `<drake:collision_filter_group>` elements, in link order.
pub fn write_drake(comment: &str, links: &[String], pairs: &[LinkPair]) -> String {
    let skipped: Vec<&LinkPair> = pairs.iter().filter(|p| p.entry.skip).collect();
    let mut out = format!(
        "<!-- {} -->\n<!-- Paste inside <robot> of a URDF that declares xmlns:drake=\"http://drake.mit.edu\". -->\n",
        comment.replace("--", "- -")
    );
    for l in links {
        if !skipped.iter().any(|p| &p.link1 == l || &p.link2 == l) {
            continue;
        }
        out.push_str(&format!(
            "<drake:collision_filter_group name=\"{}\">\n  <drake:member link=\"{}\"/>\n",
            xml_escape(&group_name(l)),
            xml_escape(l)
        ));
        for p in skipped.iter().filter(|p| &p.link1 == l) {
            out.push_str(&format!(
                "  <drake:ignored_collision_filter_group name=\"{}\"/>\n",
                xml_escape(&group_name(&p.link2))
            ));
        }
        out.push_str("</drake:collision_filter_group>\n");
    }
    out
}
