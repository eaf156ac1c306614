//! The human-readable `scm diff` report: the count of each kind of disagreement first, then the
//! pairs under each kind with their evidence and witness.

use super::{Comparison, Disagreement, WitnessJoints};
use std::path::Path;

/// The human-readable report, each witness on the joints between its two links.
pub fn format_comparison(c: &Comparison, urdd: &Path) -> String {
    format_comparison_with(c, urdd, WitnessJoints::Path)
}

/// The human-readable report: the count of each kind of disagreement first, then the pairs under
/// each kind, one line of evidence and one of witness `joints` per pair.
pub fn format_comparison_with(c: &Comparison, urdd: &Path, joints: WitnessJoints) -> String {
    let sections = [
        (
            "MoveIt skips, scm checks",
            by_kind(&c.moveit_skips_scm_checks),
        ),
        (
            "scm skips, MoveIt checks",
            by_kind(&c.scm_skips_moveit_checks),
        ),
    ];
    let mut s = format!(
        "{}: scm ({}) against MoveIt ({}): {} link pairs\n",
        urdd.display(),
        c.link_level,
        c.moveit_source,
        c.link_pairs
    );
    for (title, groups) in &sections {
        let count: usize = groups.iter().map(|(_, list)| list.len()).sum();
        s.push_str(&format!("{title}: {count}\n"));
        for (kind, list) in groups {
            s.push_str(&format!("  {kind}: {}\n", list.len()));
        }
    }
    for (title, groups) in &sections {
        if groups.is_empty() {
            continue;
        }
        s.push_str(&format!("\n{title}\n"));
        for (kind, list) in groups {
            s.push_str(&format!("  {kind}\n"));
            for d in list {
                s.push_str(&format!(
                    "    {}\n      {}\n",
                    evidence_line(d, &c.statistics),
                    witness_line(d, joints)
                ));
            }
        }
    }
    s
}

/// The disagreements of one list by kind (MoveIt's verdict, scm's, the geometry that decided it and
/// the witness's kind), the largest group first, pairs in list order within a group.
fn by_kind(list: &[Disagreement]) -> Vec<(String, Vec<&Disagreement>)> {
    let mut groups: Vec<(String, Vec<&Disagreement>)> = Vec::new();
    for d in list {
        let kind = format!(
            "MoveIt {} -> scm {} on {} ({})",
            d.moveit,
            d.scm,
            d.geometry,
            d.witness_kind.label()
        );
        match groups.iter_mut().find(|(k, _)| *k == kind) {
            Some((_, members)) => members.push(d),
            None => groups.push((kind, vec![d])),
        }
    }
    groups.sort_by(|a, b| b.1.len().cmp(&a.1.len()).then_with(|| a.0.cmp(&b.0)));
    groups
}

/// The pair, the evidence of a `never`, the sampling statistics and the collision at the witness.
fn evidence_line(d: &Disagreement, statistics: &str) -> String {
    let evidence = match (&d.evidence, d.lower_bound) {
        // A bound at or below zero proves no gap: not written as "proved".
        (Some(e), Some(lb)) if lb > 0.0 => format!("{e}, proved >= {lb:.4} m; "),
        (Some(e), Some(lb)) => format!("{e}, lower bound {lb:.4} m; "),
        (Some(e), None) => format!("{e}; "),
        _ => String::new(),
    };
    let depth = match &d.witness_distance {
        Some(w) if w.distance < 0.0 => {
            format!(
                "; at the witness {} penetrates {:.4} m",
                w.geometry, -w.distance
            )
        }
        Some(w) => format!(
            "; at the witness {} is {:.4} m apart",
            w.geometry, w.distance
        ),
        None => String::new(),
    };
    format!(
        "{} - {}: {evidence}{statistics} d_min {:.4} m, in collision {:.2}% of samples{depth}",
        d.link1,
        d.link2,
        d.d_min,
        100.0 * d.collision_fraction
    )
}

/// The witness configuration: the path joints' values, or every DOF's.
fn witness_line(d: &Disagreement, joints: WitnessJoints) -> String {
    let values: Vec<String> = match joints {
        WitnessJoints::All => d
            .witness
            .iter()
            .map(|(n, v)| format!("{n}={v:.4}"))
            .collect(),
        WitnessJoints::Path => d
            .witness
            .iter()
            .filter(|(n, _)| d.path_joints.contains(n))
            .map(|(n, v)| format!("{n}={v:.4}"))
            .collect(),
    };
    match (joints, values.is_empty()) {
        (WitnessJoints::Path, true) => "witness: no joint moves one link against the other".into(),
        (WitnessJoints::Path, false) => format!("witness, path joints: {}", values.join(" ")),
        (WitnessJoints::All, _) => format!("witness, all joints: {}", values.join(" ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diff::{WitnessDistance, WitnessKind};

    fn disagreement(scm: &str, path: &[&str], distance: Option<f64>) -> Disagreement {
        Disagreement {
            link1: "a".into(),
            link2: format!("b_{scm}"),
            moveit: "Never".into(),
            scm: scm.into(),
            d_min: -0.01,
            collision_fraction: 0.5,
            geometry: "mesh".into(),
            evidence: None,
            lower_bound: None,
            witness_kind: WitnessKind::ExactOverlap,
            witness: vec![("j1".into(), 1.0), ("j2".into(), 2.0), ("j3".into(), 3.0)],
            path_joints: path.iter().map(|s| s.to_string()).collect(),
            witness_distance: distance.map(|distance| WitnessDistance {
                distance,
                geometry: "decomp-hull".into(),
            }),
        }
    }

    #[test]
    fn report_counts_kinds_largest_first_then_lists_path_joints() {
        let c = Comparison {
            moveit_source: "x.srdf".into(),
            link_level: "mesh".into(),
            statistics: "hull".into(),
            link_pairs: 3,
            moveit_skips_scm_checks: vec![
                disagreement("always", &[], Some(0.002)),
                disagreement("checked", &["j2"], Some(-0.03)),
                disagreement("checked", &["j1", "j3"], None),
            ],
            scm_skips_moveit_checks: Vec::new(),
        };
        let text = format_comparison(&c, Path::new("d"));
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[1], "MoveIt skips, scm checks: 3");
        assert_eq!(
            lines[2],
            "  MoveIt Never -> scm checked on mesh (exact geometry overlaps): 2"
        );
        assert_eq!(
            lines[3],
            "  MoveIt Never -> scm always on mesh (exact geometry overlaps): 1"
        );
        assert_eq!(lines[4], "scm skips, MoveIt checks: 0");
        assert!(lines[8].ends_with("at the witness decomp-hull penetrates 0.0300 m"));
        assert_eq!(lines[9], "      witness, path joints: j2=2.0000");
        assert_eq!(lines[11], "      witness, path joints: j1=1.0000 j3=3.0000");
        assert!(lines[13].ends_with("at the witness decomp-hull is 0.0020 m apart"));
        assert_eq!(
            lines[14],
            "      witness: no joint moves one link against the other"
        );
        let full = format_comparison_with(&c, Path::new("d"), WitnessJoints::All);
        assert!(full.contains("      witness, all joints: j1=1.0000 j2=2.0000 j3=3.0000\n"));
    }
}
