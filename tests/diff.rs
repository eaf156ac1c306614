//! `scm diff` on Panda with MoveIt's shipped SRDF: the report's shape (counts first, grouped by kind,
//! witnesses on the path joints) and the JSON's evidence (every DOF, the path joints, the depth).

mod common;

use common::{robots_dir, sampled, scm_str};
use scm::query::{SelfChecker, SkipMode};
use scm::robot::Kinematics;
use scm::shapes::ShapeType;
use scm::urdd::Urdd;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The pair MoveIt's panda SRDF disables as `Never` whose meshes collide.
const COLLIDING: (&str, &str) = ("panda_link2", "panda_link6");

/// A sampled Panda URDD and its shipped SRDF.
fn panda(name: &str) -> Option<(PathBuf, PathBuf)> {
    let robots = robots_dir()?;
    let dir = sampled(&robots.join("panda/panda.urdf"), name, 2000);
    Some((dir, robots.join("panda/panda.srdf")))
}

/// `scm diff DIR --srdf SRDF` with `extra` flags: stdout, after checking it succeeded.
fn diff(dir: &Path, srdf: &Path, extra: &[&str]) -> String {
    let mut args = vec![
        "diff",
        dir.to_str().unwrap(),
        "--srdf",
        srdf.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let out = scm_str(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

fn diff_json(dir: &Path, srdf: &Path, extra: &[&str]) -> Value {
    let mut args = vec!["--json"];
    args.extend_from_slice(extra);
    serde_json::from_str(&diff(dir, srdf, &args)).unwrap()
}

/// Both lists of a comparison.
fn all(v: &Value) -> Vec<&Value> {
    v["moveit_skips_scm_checks"]
        .as_array()
        .unwrap()
        .iter()
        .chain(v["scm_skips_moveit_checks"].as_array().unwrap())
        .collect()
}

fn find<'a>(v: &'a Value, (a, b): (&str, &str)) -> &'a Value {
    all(v)
        .into_iter()
        .find(|d| d["link1"] == a && d["link2"] == b)
        .unwrap_or_else(|| panic!("{a} - {b} not listed: {v}"))
}

fn names(v: &Value) -> Vec<String> {
    serde_json::from_value(v.clone()).unwrap()
}

/// The report line of a pair and the witness line under it.
fn pair_lines<'a>(text: &'a str, (a, b): (&str, &str)) -> (&'a str, &'a str) {
    let lines: Vec<&str> = text.lines().collect();
    let i = lines
        .iter()
        .position(|l| l.trim_start().starts_with(&format!("{a} - {b}:")))
        .unwrap_or_else(|| panic!("{a} - {b} not in:\n{text}"));
    (lines[i], lines[i + 1])
}

#[test]
fn diff_json_keeps_every_dof_and_names_the_path_joints() {
    let Some((dir, srdf)) = panda("diff-json") else {
        return;
    };
    let v = diff_json(&dir, &srdf, &[]);
    let urdd = Urdd::open(&dir).unwrap();
    let robot = urdd.robot().unwrap().robot;
    let kinematics = Kinematics::new(&robot);
    let dofs: Vec<String> = kinematics.dofs().iter().map(|d| d.name.clone()).collect();
    assert!(!all(&v).is_empty());
    for d in all(&v) {
        let witness: Vec<(String, f64)> = serde_json::from_value(d["witness"].clone()).unwrap();
        let witness_names: Vec<String> = witness.iter().map(|(n, _)| n.clone()).collect();
        assert_eq!(witness_names, dofs, "{d}");
        // The path joints are the kinematics' own path DOFs, by name.
        let (a, b) = (d["link1"].as_str().unwrap(), d["link2"].as_str().unwrap());
        let path: Vec<String> = kinematics
            .path_dofs(robot.link_index(a).unwrap(), robot.link_index(b).unwrap())
            .into_iter()
            .map(|i| dofs[i].clone())
            .collect();
        assert_eq!(names(&d["path_joints"]), path, "{d}");
    }
    // The colliding pair: joints 3 to 6 move panda_link6 against panda_link2, and the convex pieces
    // penetrate at the configuration where the meshes overlap.
    let d = find(&v, COLLIDING);
    assert_eq!(d["witness_kind"], "exact geometry overlaps");
    assert_eq!(
        names(&d["path_joints"]),
        [
            "panda_joint3",
            "panda_joint4",
            "panda_joint5",
            "panda_joint6"
        ]
    );
    assert_eq!(d["witness_distance"]["geometry"], "decomp-hull", "{d}");
    let depth = d["witness_distance"]["distance"].as_f64().unwrap();
    assert!(depth < 0.0, "{d}");
    // The same number from the query API at the witness configuration.
    let q: Vec<f64> = serde_json::from_value::<Vec<(String, f64)>>(d["witness"].clone())
        .unwrap()
        .into_iter()
        .map(|(_, x)| x)
        .collect();
    let checker = SelfChecker::load(&urdd, ShapeType::DecompHull, SkipMode::NoSkips).unwrap();
    let mut scratch = checker.scratch();
    let pieces = |link: &str| -> Vec<usize> {
        (0..checker.shapes().len())
            .filter(|&i| checker.shapes()[i].link == link)
            .collect()
    };
    let mut deepest = f64::INFINITY;
    for i in pieces(COLLIDING.0) {
        for j in pieces(COLLIDING.1) {
            deepest = deepest.min(checker.pair_distance(&q, i, j, &mut scratch).unwrap().0);
        }
    }
    assert_eq!(depth, deepest);
}

#[test]
fn diff_report_counts_kinds_first_and_prints_only_path_joints() {
    let Some((dir, srdf)) = panda("diff-text") else {
        return;
    };
    let text = diff(&dir, &srdf, &[]);
    let v = diff_json(&dir, &srdf, &[]);
    let lines: Vec<&str> = text.lines().collect();
    // The summary: each list's count, then one count per kind, before any pair.
    let skips = v["moveit_skips_scm_checks"].as_array().unwrap().len();
    assert_eq!(
        lines[1],
        format!("MoveIt skips, scm checks: {skips}"),
        "{text}"
    );
    assert_eq!(
        lines[2], "  MoveIt Never -> scm checked on mesh (exact geometry overlaps): 1",
        "{text}"
    );
    let first_pair = lines.iter().position(|l| l.contains(" - panda_")).unwrap();
    let summary = lines
        .iter()
        .position(|l| l.starts_with("scm skips, MoveIt checks: "));
    assert!(summary.is_some_and(|i| i < first_pair), "{text}");
    // Every pair line is followed by its witness on the path joints only.
    for d in all(&v) {
        let pair = (d["link1"].as_str().unwrap(), d["link2"].as_str().unwrap());
        let (_, witness) = pair_lines(&text, pair);
        let printed: Vec<&str> = witness
            .split(": ")
            .nth(1)
            .unwrap_or_default()
            .split_whitespace()
            .map(|jv| jv.split('=').next().unwrap())
            .collect();
        assert_eq!(printed, names(&d["path_joints"]), "{witness}");
    }
    let (line, witness) = pair_lines(&text, COLLIDING);
    assert!(
        line.contains("at the witness decomp-hull penetrates"),
        "{line}"
    );
    assert!(witness.contains("panda_joint4="), "{witness}");
    assert!(!witness.contains("panda_joint1="), "{witness}");

    // --full-witness: every joint, the one off the path too.
    let full = diff(&dir, &srdf, &["--full-witness"]);
    let (_, witness) = pair_lines(&full, COLLIDING);
    assert!(
        witness.starts_with("      witness, all joints: "),
        "{witness}"
    );
    assert!(witness.contains("panda_joint1="), "{witness}");
    let dofs = find(&v, COLLIDING)["witness"].as_array().unwrap().len();
    assert_eq!(witness.matches('=').count(), dofs, "{witness}");
}

#[test]
fn diff_on_a_type_gives_the_sampled_penetration_on_that_type() {
    let Some((dir, srdf)) = panda("diff-type") else {
        return;
    };
    let v = diff_json(&dir, &srdf, &["--type", "hull"]);
    assert_eq!(v["statistics"], "hull");
    let d = find(&v, COLLIDING);
    assert_eq!(d["witness_kind"], "closest sampled");
    let d_min = d["d_min"].as_f64().unwrap();
    assert!(d_min < 0.0, "{d}");
    assert_eq!(d["witness_distance"]["distance"].as_f64(), Some(d_min));
    assert_eq!(d["witness_distance"]["geometry"], "hull");
    // A pair scm skips because it collides at home shows home and the hull's depth there.
    for d in v["scm_skips_moveit_checks"].as_array().unwrap() {
        if d["scm"] == "default" {
            assert_eq!(d["witness_kind"], "touches at home", "{d}");
            assert!(
                d["witness_distance"]["distance"].as_f64().unwrap() < 0.0,
                "{d}"
            );
        }
    }
}
