//! Every kind of bad input gets one clear line naming the file and the element, exit code 2, no panic,
//! and leaves an existing URDD untouched.

mod common;

use std::path::Path;

/// A robot with one box link and one mesh link; `{MESH}` is replaced by the mesh element.
fn robot_with(body: &str) -> String {
    format!(
        r#"<?xml version="1.0"?>
<robot name="bad">
  <link name="base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
{body}
</robot>"#
    )
}

const ARM: &str = r#"  <link name="arm"><collision><origin xyz="0 0 0.2"/><geometry><mesh filename="arm.stl"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/><limit lower="-1" upper="1"/></joint>"#;

/// Binary STL with the given triangles.
fn stl(triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut b = vec![0u8; 80];
    b.extend((triangles.len() as u32).to_le_bytes());
    for t in triangles {
        b.extend([0u8; 12]);
        for v in t {
            for c in v {
                b.extend(c.to_le_bytes());
            }
        }
        b.extend([0u8; 2]);
    }
    b
}

fn tetra() -> Vec<u8> {
    let p = [
        [0.0, 0.0, 0.0],
        [0.1, 0.0, 0.0],
        [0.0, 0.1, 0.0],
        [0.0, 0.0, 0.1],
    ];
    stl(&[
        [p[0], p[2], p[1]],
        [p[0], p[1], p[3]],
        [p[0], p[3], p[2]],
        [p[1], p[2], p[3]],
    ])
}

/// Runs preprocess on `urdf` (with `arm.stl` = `mesh`) and checks the error line.
fn check(name: &str, urdf: &str, mesh: Option<Vec<u8>>, expect: &[&str]) {
    let dir = common::scratch(name);
    let path = dir.join(format!("{name}.urdf"));
    std::fs::write(&path, urdf).unwrap();
    if let Some(m) = mesh {
        std::fs::write(dir.join("arm.stl"), m).unwrap();
    }
    let out = dir.join("out");
    let o = common::scm(&[
        "preprocess".as_ref(),
        path.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{name}: exit code; stderr: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{name}: panic: {stderr}");
    assert_eq!(
        stderr.trim_end().lines().count(),
        1,
        "{name}: one line expected, got: {stderr}"
    );
    assert!(
        stderr.contains(&format!("{name}.urdf")),
        "{name}: file not named: {stderr}"
    );
    for e in expect {
        assert!(stderr.contains(e), "{name}: expected `{e}` in: {stderr}");
    }
    assert!(
        !out.join("manifest.json").exists(),
        "{name}: nothing may be written"
    );
}

#[test]
fn malformed_xml() {
    check(
        "malformed",
        "<robot name=\"x\"><link name=\"a\"></robot>",
        None,
        &["line 1", "malformed XML"],
    );
}

#[test]
fn missing_mesh() {
    check(
        "missing_mesh",
        &robot_with(ARM),
        None,
        &["<link name=\"arm\">", "line 4", "arm.stl", "not found"],
    );
}

#[test]
fn unreadable_mesh() {
    check(
        "garbage_mesh",
        &robot_with(ARM),
        Some(b"solid nonsense that is not STL".to_vec()),
        &["<link name=\"arm\">", "arm.stl", "cannot parse"],
    );
}

#[test]
fn empty_mesh() {
    check(
        "empty_mesh",
        &robot_with(ARM),
        Some(stl(&[])),
        &["<link name=\"arm\">", "no triangles"],
    );
}

#[test]
fn flat_mesh() {
    let flat = stl(&[
        [[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.1, 0.0]],
        [[0.1, 0.0, 0.0], [0.1, 0.1, 0.0], [0.0, 0.1, 0.0]],
    ]);
    check(
        "flat_mesh",
        &robot_with(ARM),
        Some(flat),
        &["<link name=\"arm\">", "degenerate", "flat"],
    );
}

#[test]
fn single_point_mesh() {
    let point = stl(&[[[0.1, 0.1, 0.1]; 3], [[0.1, 0.1, 0.1]; 3]]);
    check(
        "point_mesh",
        &robot_with(ARM),
        Some(point),
        &["<link name=\"arm\">", "degenerate"],
    );
}

#[test]
fn nan_and_infinite_numbers() {
    let urdf = robot_with(ARM).replace("xyz=\"0 0 0.2\"", "xyz=\"0 NaN 0.2\"");
    check(
        "nan_origin",
        &urdf,
        Some(tetra()),
        &["<origin>", "not finite"],
    );
    let urdf = robot_with(ARM).replace("upper=\"1\"", "upper=\"inf\"");
    check(
        "inf_limit",
        &urdf,
        Some(tetra()),
        &["<limit>", "not finite"],
    );
}

#[test]
fn unknown_joint_type() {
    let urdf = robot_with(ARM).replace("type=\"revolute\"", "type=\"hinge\"");
    check(
        "joint_type",
        &urdf,
        Some(tetra()),
        &["<joint name=\"j1\">", "unknown joint type \"hinge\""],
    );
}

#[test]
fn duplicate_names() {
    let urdf = robot_with(&format!("{ARM}\n  <link name=\"arm\"/>"));
    check(
        "dup_link",
        &urdf,
        Some(tetra()),
        &["<link name=\"arm\">", "duplicate link name"],
    );
    let extra = r#"  <link name="other"/><joint name="j1" type="fixed"><parent link="base"/><child link="other"/></joint>"#;
    check(
        "dup_joint",
        &robot_with(&format!("{ARM}\n{extra}")),
        Some(tetra()),
        &["<joint name=\"j1\">", "duplicate joint name"],
    );
}

#[test]
fn joint_naming_missing_link() {
    let urdf = robot_with(&ARM.replace("<child link=\"arm\"/>", "<child link=\"ghost\"/>"));
    check(
        "ghost_link",
        &urdf,
        Some(tetra()),
        &["<joint name=\"j1\">", "\"ghost\"", "does not exist"],
    );
}

#[test]
fn several_roots() {
    let urdf = robot_with(&format!("{ARM}\n  <link name=\"floating_part\"/>"));
    check(
        "two_roots",
        &urdf,
        Some(tetra()),
        &["several root links", "base", "floating_part"],
    );
}

#[test]
fn cycle() {
    let back =
        r#"  <joint name="back" type="fixed"><parent link="arm"/><child link="base"/></joint>"#;
    check(
        "cycle",
        &robot_with(&format!("{ARM}\n{back}")),
        Some(tetra()),
        &["cycle"],
    );
}

#[test]
fn bad_input_keeps_existing_urdd() {
    let dir = common::scratch("keep");
    let good = dir.join("good.urdf");
    std::fs::write(&good, robot_with(ARM)).unwrap();
    std::fs::write(dir.join("arm.stl"), tetra()).unwrap();
    let out = dir.join("out");
    let o = common::scm(&[
        "preprocess".as_ref(),
        good.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "-q".as_ref(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let before = std::fs::read(out.join("manifest.json")).unwrap();
    std::fs::write(dir.join("arm.stl"), stl(&[])).unwrap();
    let o = common::scm(&[
        "preprocess".as_ref(),
        good.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(std::fs::read(out.join("manifest.json")).unwrap(), before);
    assert!(out.join("preprocess/shapes/hull.json").is_file());
    assert!(!Path::new(&out).join(".preprocess.tmp").exists());
}

#[test]
fn scm_view_of_a_missing_urdd_is_one_line_and_exit_2() {
    let dir = common::scratch("view-missing").join("nothing.urdd");
    let out = common::scm(&["view".as_ref(), dir.as_os_str()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("nothing.urdd"), "{err}");
}

#[test]
fn scm_view_without_the_viewer_says_how_to_build_it() {
    // A copy of scm alone in a folder, with nothing on PATH: no scm-viewer to be found.
    let work = common::scratch("view-no-viewer");
    let scm = work.join("scm");
    std::fs::copy(env!("CARGO_BIN_EXE_scm"), &scm).unwrap();
    let urdd = common::preprocessed(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/demo_arm/demo_arm.urdf"),
        "view-no-viewer-urdd",
    );
    let out = std::process::Command::new(&scm)
        .arg("view")
        .arg(&urdd)
        .env("PATH", "")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("`scm-viewer` was not found next to scm or on PATH")
            && err.contains("cargo build --release -p scm-viewer"),
        "{err}"
    );
}

#[test]
fn inspect_rejects_a_configuration_of_the_wrong_length_or_not_numbers() {
    let dir = common::scratch("inspect-bad");
    let urdf = dir.join("r.urdf");
    std::fs::write(&urdf, robot_with(ARM)).unwrap();
    std::fs::write(dir.join("arm.stl"), tetra()).unwrap();
    let urdd = dir.join("r.urdd");
    let o = common::scm_str(&[
        "preprocess",
        urdf.to_str().unwrap(),
        "-o",
        urdd.to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for (config, want) in [
        (
            "0.1 0.2",
            "expected 1 finite joint values (one per DOF: j1), got 2",
        ),
        ("abc", "`abc` is not a number"),
    ] {
        let o = common::scm_str(&["inspect", urdd.to_str().unwrap(), "--config", config]);
        assert_eq!(o.status.code(), Some(2), "{config}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains("--config") && err.contains(want), "{err}");
    }
    // A good one places the arm: its box moves with the joint.
    let o = common::scm_str(&[
        "inspect",
        urdd.to_str().unwrap(),
        "--config",
        "1.0",
        "--json",
    ]);
    assert!(o.status.success());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["configurations"][0]["joints"]["j1"], 1.0);
    let arm = &v["configurations"][0]["links"][1];
    assert_eq!(arm["link"], "arm");
    // The tetrahedron's x edge (0.1 m) turned by 1 rad about z reaches y = 0.1 sin 1.
    let max_y = arm["bounds"]["max"][1].as_f64().unwrap();
    assert!((max_y - 0.1 * 1f64.sin()).abs() < 1e-6, "{max_y}");
}
