//! Mesh files as real exporters write them, read as the consumers' Assimp reads them (COLLADA
//! `<up_axis>` and `<unit>` ignored, node transforms kept, lines dropped), and the URDF rules around
//! them: mirrored scale, links without `<collision>`, `package://` and `model://` lookup, xacro.
//!
//! The files are authored (`scripts/make_mesh_variants.py` writes `tests/data/mesh_variants/`);
//! `tests/consumer_geometry.rs` checks the same robot against Pinocchio.

mod common;

use scm::math::{Vec3, bounds};
use scm::mesh::{MeshFile, load_mesh_file};
use scm::robot::{PackagePaths, ShapeSource, UrdfOptions, load_urdf};
use std::path::{Path, PathBuf};

fn variants() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mesh_variants")
}

fn variant(name: &str) -> MeshFile {
    let path = variants().join("meshes").join(name);
    load_mesh_file(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn assert_bounds(file: &MeshFile, lo: [f64; 3], hi: [f64; 3]) {
    let (min, max) = bounds(&file.mesh.vertices).expect("vertices");
    let close = |a: Vec3, b: [f64; 3]| (a - Vec3::from_array(b)).abs().max_element() < 1e-6;
    assert!(
        close(min, lo) && close(max, hi),
        "bounds {min:?}..{max:?}, want {lo:?}..{hi:?}"
    );
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(&path, text).unwrap();
    path
}

const TETRA_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

#[test]
fn binary_stl_whose_header_begins_with_solid_is_binary() {
    let file = variant("solid_header.stl");
    assert_eq!(file.mesh.triangles.len(), 12);
    assert_bounds(&file, [-0.04, -0.04, 0.0], [0.04, 0.04, 0.06]);
    assert!(file.notes.is_empty(), "{:?}", file.notes);
}

#[test]
fn binary_stl_with_a_wrong_triangle_count_is_read_by_its_size_and_says_so() {
    let file = variant("wrong_count.stl");
    assert_eq!(file.mesh.triangles.len(), 12);
    assert_bounds(&file, [0.0, 0.0, 0.0], [0.01, 0.02, 0.03]);
    assert!(
        file.notes.iter().any(|n| n.contains("says 0 triangles")),
        "{:?}",
        file.notes
    );
}

#[test]
fn ascii_stl_with_tabs_crlf_and_blank_lines() {
    let file = variant("irregular.stl");
    assert_eq!(file.mesh.triangles.len(), 12);
    assert_bounds(&file, [-0.03, -0.02, 0.0], [0.03, 0.02, 0.07]);
}

#[test]
fn obj_polygons_negative_indices_and_several_objects() {
    let file = variant("polygons.obj");
    // Two pentagons (3 triangles each) and five quads (2 each) of the prism, 12 cube triangles; the
    // point, the line and the missing mtllib add nothing.
    assert_eq!(file.mesh.triangles.len(), 6 + 10 + 12);
    assert_eq!(file.mesh.vertices.len(), 10 + 8);
    let (min, max) = bounds(&file.mesh.vertices).unwrap();
    assert!((max.z - 0.08).abs() < 1e-9 && min.z.abs() < 1e-9);
    // Relative indices reached the cube's own vertices: its top face is at z 0.08, x in [-0.02, 0.02].
    let top: Vec<_> = file
        .mesh
        .triangles
        .iter()
        .filter(|t| t.iter().all(|&i| file.mesh.vertices[i as usize].z > 0.079))
        .collect();
    assert_eq!(top.len(), 2);
}

#[test]
fn obj_errors_name_the_line() {
    let dir = common::scratch("obj-err");
    let path = write(&dir, "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
    let err = load_mesh_file(&path).unwrap_err();
    assert!(
        err.contains("line 4") && err.contains("out of range"),
        "{err}"
    );
}

#[test]
fn collada_polylist_ignores_up_axis_and_unit_as_the_consumers_do() {
    let file = variant("polylist_yup_inch.dae");
    assert_eq!(file.mesh.triangles.len(), 12);
    // Neither rotated to Z-up nor scaled by 0.0254: the numbers of the file, as Pinocchio reads them.
    assert_bounds(&file, [-0.02, -0.02, 0.0], [0.02, 0.02, 0.04]);
    let notes = file.notes.join("\n");
    assert!(
        notes.contains("unit meter=\"0.0254\"") && notes.contains("Y_UP"),
        "{notes}"
    );
}

#[test]
fn collada_nested_node_transforms_apply_and_lines_are_dropped() {
    let file = variant("nested_nodes.dae");
    // Three <polygons> quads and six <triangles>; the <lines> and its two far positions are gone.
    assert_eq!(file.mesh.triangles.len(), 12);
    assert_eq!(file.mesh.vertices.len(), 3 * 4 + 6 * 3);
    let (min, max) = bounds(&file.mesh.vertices).unwrap();
    assert!(
        min.min_element() > -0.1 && max.max_element() < 0.1,
        "{min:?} {max:?}"
    );
    // inner: matrix (x, y, z) -> (x, -z + 0.01, y) after scale (1, 0.5, 2); outer: rotate 30 degrees
    // about z, then translate (0.01, 0, 0.02). The cube corner (0.03, 0.03, 0.03) lands here:
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let inner = Vec3::new(0.03, -0.06 + 0.01, 0.015);
    let want = Vec3::new(
        c * inner.x - s * inner.y + 0.01,
        s * inner.x + c * inner.y,
        inner.z + 0.02,
    );
    assert!(
        file.mesh
            .vertices
            .iter()
            .any(|v| (*v - want).length() < 1e-6),
        "no vertex at {want:?}"
    );
}

#[test]
fn collada_instance_nodes_repeated_instances_strips_and_fans() {
    let file = variant("instances.dae");
    // Each instance: a strip of 8 triangles round the sides and two fans of 2; instanced twice (once
    // directly, once through <instance_node>). The geometry no node instances (at 5 m) is not there.
    assert_eq!(file.mesh.triangles.len(), 2 * (8 + 4));
    let (_, max) = bounds(&file.mesh.vertices).unwrap();
    assert!(max.max_element() < 1.0, "{max:?}");
    // The second instance: translate z 0.03 under a 90-degree turn about x, so it rises along -y.
    assert!(
        file.mesh
            .vertices
            .iter()
            .any(|v| (*v - Vec3::new(0.025, -0.055, 0.025)).length() < 1e-6)
    );
}

#[test]
fn collada_instance_node_cycle_is_an_error_not_a_hang() {
    let dir = common::scratch("dae-cycle");
    let path = write(
        &dir,
        "cycle.dae",
        r##"<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <library_nodes><node id="a"><instance_node url="#a"/></node></library_nodes>
  <library_visual_scenes><visual_scene id="s"><node id="n"><instance_node url="#a"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>"##,
    );
    let err = load_mesh_file(&path).unwrap_err();
    assert!(err.contains("nest more than"), "{err}");
}

#[test]
fn mirrored_scale_gives_an_outward_hull_of_the_mirrored_shape() {
    let urdf = variants().join("mesh_variants.urdf");
    let dir = common::preprocessed(&urdf, "mirror");
    let urdd = scm::urdd::Urdd::open(&dir).unwrap();
    let hulls = urdd.shapes(scm::shapes::ShapeType::Hull).unwrap();
    let record = hulls.shapes.iter().find(|s| s.link == "l6").unwrap();
    let scm::shapes::Geometry::Hull(hull) = urdd.geometry(&record.geometry).unwrap() else {
        panic!("not a hull");
    };
    assert!(hull.volume() > 0.0, "inside-out hull: {}", hull.volume());
    // The wedge alone: its y vertex (0, 0.03, 0) is mirrored to -0.03, its triangles still face out.
    let robot = load_urdf(&urdf, &UrdfOptions::default()).unwrap();
    let meshes = scm::preprocess::load_meshes(&robot, &urdf).unwrap();
    let wedge = scm::preprocess::element_mesh(&robot.links[6].geometry[0], &meshes);
    assert!(wedge.vertices.iter().all(|v| v.y <= 0.0));
    assert!(hull.contains(Vec3::new(0.0, -0.03, 0.0), 1e-9));
    let want = 0.06 * 0.03 * 0.04 / 6.0;
    assert!(
        (wedge.signed_volume() - want).abs() < 1e-12,
        "mirrored wedge volume {} (want +{want})",
        wedge.signed_volume()
    );
    let wedge_hull = scm::shapes::convex_hull(&wedge.vertices).unwrap();
    assert!((wedge_hull.volume() - want).abs() < 1e-12);
}

#[test]
fn links_without_collision_get_no_shapes_unless_visual_fallback() {
    let urdf = variants().join("mesh_variants.urdf");
    // Default: "tool" has only a <visual>, so no consumer checks it and scm builds nothing for it.
    let out = common::scratch("fallback-off");
    let o = common::scm_str(&[
        "preprocess",
        urdf.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("\"tool\" has no <collision>") && stderr.contains("--visual-fallback"),
        "{stderr}"
    );
    let urdd = scm::urdd::Urdd::open(&out).unwrap();
    assert!(urdd.links().unwrap().iter().all(|l| l.link != "tool"));
    let params = &urdd.stage("preprocess").unwrap().parameters;
    assert_eq!(params["visual_fallback"], false);

    // --visual-fallback: shapes from the visual, recorded in the parameters and per link.
    let out = common::scratch("fallback-on");
    let o = common::scm_str(&[
        "preprocess",
        urdf.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--visual-fallback",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let urdd = scm::urdd::Urdd::open(&out).unwrap();
    let tool = urdd.links().unwrap().into_iter().find(|l| l.link == "tool");
    assert_eq!(
        tool.map(|l| l.geometry),
        Some(scm::robot::GeometryOrigin::Visual)
    );
    assert_eq!(
        urdd.stage("preprocess").unwrap().parameters["visual_fallback"],
        true
    );
    let robot = urdd.robot().unwrap().robot;
    let tool = robot.links.iter().find(|l| l.name == "tool").unwrap();
    assert_eq!(tool.geometry_source, scm::robot::GeometryOrigin::Visual);
}

/// A package folder `root/NAME` with a package.xml and `meshes/a.obj`, and a URDF elsewhere that uses
/// `SCHEME://NAME/meshes/a.obj` in its link "a".
fn package_fixture(root: &Path, scheme: &str, name: &str) -> PathBuf {
    write(
        root,
        &format!("{name}/package.xml"),
        &format!("<package><name>{name}</name></package>"),
    );
    write(root, &format!("{name}/meshes/a.obj"), TETRA_OBJ);
    write(
        &root.join("robot"),
        "r.urdf",
        &format!(
            r#"<robot name="r"><link name="a"><collision><geometry><mesh filename="{scheme}://{name}/meshes/a.obj"/></geometry></collision></link></robot>"#
        ),
    )
}

/// The URDF read with these package paths (no visual fallback).
fn load_with(urdf: &Path, packages: PackagePaths) -> scm::robot::Robot {
    let options = UrdfOptions {
        packages,
        ..UrdfOptions::default()
    };
    load_urdf(urdf, &options).unwrap_or_else(|e| panic!("{e}"))
}

fn resolved(robot: &scm::robot::Robot) -> PathBuf {
    match &robot.links[0].geometry[0].shape {
        ShapeSource::Mesh { path, .. } => path.canonicalize().unwrap(),
        other => panic!("{other:?}"),
    }
}

#[test]
fn package_uris_through_ros_package_path_and_ament_prefix_path() {
    let root = common::scratch("ros-paths");
    let ws = root.join("ws/src/deep");
    let urdf = package_fixture(&ws, "package", "arm_description");
    // The URDF is in ws/src/deep/robot, so the parent-folder search would find ws/src/deep/arm_description;
    // move the package away so only the environment can find it.
    let ros1 = root.join("ros1/src/group");
    std::fs::create_dir_all(&ros1).unwrap();
    std::fs::rename(ws.join("arm_description"), ros1.join("arm_description")).unwrap();

    let mut packages = PackagePaths::new();
    packages.set_env("ROS_PACKAGE_PATH", vec![root.join("ros1")]);
    let robot = load_with(&urdf, packages);
    assert_eq!(
        resolved(&robot),
        ros1.join("arm_description/meshes/a.obj")
            .canonicalize()
            .unwrap()
    );

    // ROS 2: PREFIX/share/NAME.
    let prefix = root.join("install");
    std::fs::create_dir_all(prefix.join("share")).unwrap();
    std::fs::rename(
        ros1.join("arm_description"),
        prefix.join("share/arm_description"),
    )
    .unwrap();
    let mut packages = PackagePaths::new();
    packages.set_env("ROS_PACKAGE_PATH", vec![]);
    packages.set_env(
        "AMENT_PREFIX_PATH",
        vec![root.join("elsewhere"), prefix.clone()],
    );
    let robot = load_with(&urdf, packages);
    assert!(resolved(&robot).starts_with(prefix.canonicalize().unwrap()));

    // The binary reads the environment.
    let out = common::scratch("ros-paths-cli");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_scm"))
        .args([
            "preprocess",
            urdf.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-q",
        ])
        .env("AMENT_PREFIX_PATH", &prefix)
        .env_remove("ROS_PACKAGE_PATH")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn model_uris_through_gazebo_paths() {
    let root = common::scratch("model-paths");
    let urdf = package_fixture(&root.join("models"), "model", "table");
    std::fs::rename(root.join("models/table"), root.join("gz_table")).unwrap();
    std::fs::create_dir_all(root.join("gz")).unwrap();
    std::fs::rename(root.join("gz_table"), root.join("gz/table")).unwrap();
    let mut packages = PackagePaths::new();
    packages.set_env("GZ_SIM_RESOURCE_PATH", vec![root.join("gz")]);
    let robot = load_with(&urdf, packages);
    assert_eq!(
        resolved(&robot),
        root.join("gz/table/meshes/a.obj").canonicalize().unwrap()
    );
}

#[test]
fn a_missing_package_names_the_package_the_link_and_every_place_searched() {
    let root = common::scratch("missing-pkg");
    let urdf = package_fixture(&root, "package", "present");
    let text = std::fs::read_to_string(&urdf)
        .unwrap()
        .replace("present", "absent_pkg");
    std::fs::write(&urdf, text).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_scm"))
        .args(["preprocess", urdf.to_str().unwrap(), "-o"])
        .arg(root.join("out"))
        .env("ROS_PACKAGE_PATH", root.join("nowhere"))
        .env_remove("AMENT_PREFIX_PATH")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    for part in [
        "package \"absent_pkg\" not found",
        "<link name=\"a\">",
        "ROS_PACKAGE_PATH (",
        "nowhere",
        "AMENT_PREFIX_PATH (unset)",
        "parent folders",
        "--package-path absent_pkg=DIR",
    ] {
        assert!(err.contains(part), "missing {part:?} in: {err}");
    }
}

#[test]
fn explicit_package_path_and_relative_file_uris() {
    let root = common::scratch("pkg");
    let other = root.join("elsewhere");
    write(&other, "b.obj", TETRA_OBJ);
    write(&root, "robot/meshes/c.obj", TETRA_OBJ);
    let urdf = write(
        &root.join("robot/urdf"),
        "r.urdf",
        r#"<robot name="r">
  <link name="b"><collision><geometry><mesh filename="package://other_pkg/b.obj"/></geometry></collision></link>
  <link name="c"><collision><geometry><mesh filename="file://../meshes/c.obj"/></geometry></collision></link>
  <joint name="bc" type="fixed"><parent link="b"/><child link="c"/></joint>
</robot>"#,
    );
    let mut packages = PackagePaths::new();
    packages.insert("other_pkg", &other);
    let robot = load_with(&urdf, packages);
    assert_eq!(
        resolved(&robot),
        other.join("b.obj").canonicalize().unwrap()
    );
}

#[test]
fn a_mesh_path_that_is_a_folder_or_a_device_says_so() {
    let root = common::scratch("mesh-dir");
    std::fs::create_dir_all(root.join("meshes/folder.stl")).unwrap();
    let urdf = write(
        &root,
        "r.urdf",
        r#"<robot name="r"><link name="a"><collision><geometry><mesh filename="meshes/folder.stl"/></geometry></collision></link></robot>"#,
    );
    let err = load_urdf(&urdf, &UrdfOptions::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("is a folder"), "{err}");
    let urdf = write(
        &root,
        "dev.urdf",
        r#"<robot name="r"><link name="a"><collision><geometry><mesh filename="/dev/zero"/></geometry></collision></link></robot>"#,
    );
    let err = load_urdf(&urdf, &UrdfOptions::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("not a regular file"), "{err}");
}

#[test]
fn xacro_files_are_refused_with_the_command_that_expands_them() {
    let root = common::scratch("xacro");
    let by_name = write(&root, "robot.urdf.xacro", "<robot name=\"r\"/>");
    let by_content = write(
        &root,
        "robot.urdf",
        r#"<?xml version="1.0"?>
<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="w" value="0.1"/>
  <link name="a"/>
</robot>"#,
    );
    let undeclared = write(
        &root,
        "undeclared.urdf",
        "<robot name=\"r\"><xacro:include filename=\"x.xacro\"/><link name=\"a\"/></robot>",
    );
    for urdf in [&by_name, &by_content, &undeclared] {
        let o = common::scm_str(&[
            "preprocess",
            urdf.to_str().unwrap(),
            "-o",
            "/nonexistent/out",
        ]);
        assert_eq!(o.status.code(), Some(2), "{}", urdf.display());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            err.contains(&format!("xacro {} > robot.urdf", urdf.display())),
            "{err}"
        );
    }
    let err = String::from_utf8_lossy(
        &common::scm_str(&[
            "preprocess",
            by_content.to_str().unwrap(),
            "-o",
            "/nonexistent/o",
        ])
        .stderr,
    )
    .to_string();
    assert!(err.contains("<xacro:property> (line 3)"), "{err}");
}

#[test]
fn collada_instances_that_multiply_are_an_error_not_an_explosion() {
    // Each level instances the one below twice: 2^40 nodes if nothing stopped it.
    let mut nodes = String::from(r#"<node id="n0"/>"#);
    for k in 1..=40 {
        nodes += &format!(
            r##"<node id="n{k}"><instance_node url="#n{p}"/><instance_node url="#n{p}"/></node>"##,
            p = k - 1
        );
    }
    let text = format!(
        r##"<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <library_nodes>{nodes}</library_nodes>
  <library_visual_scenes><visual_scene id="s"><node id="top"><instance_node url="#n40"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>"##
    );
    let dir = common::scratch("dae-laughs");
    let path = write(&dir, "laughs.dae", &text);
    let err = load_mesh_file(&path).unwrap_err();
    assert!(err.contains("more than 1000000 nodes"), "{err}");
}
