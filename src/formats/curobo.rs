//! cuRobo: the `self_collision_ignore` map and `collision_spheres` of a robot configuration, as the
//! `robot_cfg.kinematics` fragment of a cuRobo robot YAML.

use crate::matrix::LinkPair;
use crate::urdd::{GeometryRecord, ShapeRecord};

/// A YAML double-quoted scalar (JSON string syntax is valid YAML).
fn quoted(s: &str) -> String {
    // A JSON string's text cannot fail to be written.
    serde_json::Value::from(s).to_string()
}

/// Formats a number for YAML with enough digits to round-trip a metre value to 1e-9.
fn num(x: f64) -> String {
    let s = format!("{x:.9}");
    let s = s.trim_end_matches('0');
    let s = s
        .strip_suffix('.')
        .map_or_else(|| s.to_string(), |t| format!("{t}.0"));
    if s == "-0.0" { "0.0".into() } else { s }
}

/// The fragment: `collision_link_names`, `collision_spheres` (from `spheres`, one list per link, in the
/// link frame) and `self_collision_ignore` (each skipped link pair once, under its first link).
pub fn write_curobo(
    comment: &str,
    links: &[String],
    pairs: &[LinkPair],
    spheres: &[ShapeRecord],
) -> String {
    let mut out = format!("# {comment}\nrobot_cfg:\n  kinematics:\n");
    out.push_str("    collision_link_names:\n");
    for l in links {
        out.push_str(&format!("      - {}\n", quoted(l)));
    }
    out.push_str("    collision_spheres:\n");
    for l in links {
        let own: Vec<&ShapeRecord> = spheres.iter().filter(|s| &s.link == l).collect();
        if own.is_empty() {
            continue;
        }
        out.push_str(&format!("      {}:\n", quoted(l)));
        for s in own {
            if let GeometryRecord::Sphere { center, radius } = &s.geometry {
                out.push_str(&format!(
                    "        - {{center: [{}, {}, {}], radius: {}}}\n",
                    num(center.x),
                    num(center.y),
                    num(center.z),
                    num(*radius)
                ));
            }
        }
    }
    out.push_str("    self_collision_ignore:\n");
    for l in links {
        let ignored: Vec<String> = pairs
            .iter()
            .filter(|p| p.entry.skip && &p.link1 == l)
            .map(|p| quoted(&p.link2))
            .collect();
        if !ignored.is_empty() {
            out.push_str(&format!("      {}: [{}]\n", quoted(l), ignored.join(", ")));
        }
    }
    out
}
