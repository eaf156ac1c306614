//! MuJoCo: `<contact><exclude body1 body2/>` for the skipped pairs, in an MJCF file to `<include>`.
//!
//! MuJoCo's URDF import fuses every link attached by a fixed joint into its parent body
//! (`fusestatic`, on for URDF), the root chain into `world`, and already filters contacts between a
//! body and its parent (except the world). So links map to bodies first; a body pair is excluded only
//! when every link pair between the two bodies is skipped, and parent-child pairs are left out.

use super::xml_escape;
use crate::matrix::LinkPair;
use crate::robot::{JointKind, Robot};
use std::collections::{BTreeMap, BTreeSet};

/// The body a link ends up in after MuJoCo's URDF import: the nearest link at or above it whose joint
/// moves, or `world` for links fixed to the root.
pub fn mujoco_body(robot: &Robot, mut link: usize) -> String {
    loop {
        match robot.links[link].parent_joint.map(|j| &robot.joints[j]) {
            None => return "world".into(),
            Some(j) if j.kind != JointKind::Fixed => return robot.links[link].name.clone(),
            Some(j) => link = j.parent,
        }
    }
}

/// The parent body of a (non-world) body named after `link`.
fn parent_body(robot: &Robot, link: usize) -> String {
    match robot.links[link].parent_joint {
        Some(j) => mujoco_body(robot, robot.joints[j].parent),
        None => "world".into(),
    }
}

/// The excluded body pairs, in the order of their first link pair.
pub fn excluded_bodies(robot: &Robot, pairs: &[LinkPair]) -> Vec<(String, String)> {
    let mut order: Vec<(String, String)> = Vec::new();
    let mut all_skipped: BTreeMap<(String, String), bool> = BTreeMap::new();
    let mut parents: BTreeSet<(String, String)> = BTreeSet::new();
    for p in pairs {
        let (Some(la), Some(lb)) = (robot.link_index(&p.link1), robot.link_index(&p.link2)) else {
            continue;
        };
        let (ba, bb) = (mujoco_body(robot, la), mujoco_body(robot, lb));
        if ba == bb {
            continue;
        }
        for (body, link) in [(&ba, la), (&bb, lb)] {
            if body != "world" {
                let link = robot.link_index(body).unwrap_or(link);
                parents.insert((body.clone(), parent_body(robot, link)));
            }
        }
        // One key per unordered body pair: fused links can reach the same pair in either order.
        let key = if ba <= bb { (ba, bb) } else { (bb, ba) };
        match all_skipped.get_mut(&key) {
            Some(s) => *s &= p.entry.skip,
            None => {
                all_skipped.insert(key.clone(), p.entry.skip);
                order.push(key);
            }
        }
    }
    let filtered_by_mujoco = |a: &String, b: &String| {
        (a != "world" && parents.contains(&(b.clone(), a.clone())))
            || (b != "world" && parents.contains(&(a.clone(), b.clone())))
    };
    order
        .into_iter()
        .filter(|k| all_skipped[k] && !filtered_by_mujoco(&k.0, &k.1))
        .collect()
}

/// An MJCF file holding the contact excludes, to `<include file="..."/>` in a model of the robot.
pub fn write_mjcf(robot: &Robot, comment: &str, pairs: &[LinkPair]) -> String {
    let excludes: String = excluded_bodies(robot, pairs)
        .iter()
        .map(|(a, b)| {
            format!(
                "    <exclude body1=\"{}\" body2=\"{}\"/>\n",
                xml_escape(a),
                xml_escape(b)
            )
        })
        .collect();
    format!(
        "<!-- {} -->\n<mujoco model=\"{}\">\n  <contact>\n{excludes}  </contact>\n</mujoco>\n",
        comment.replace("--", "- -"),
        xml_escape(&robot.name)
    )
}
