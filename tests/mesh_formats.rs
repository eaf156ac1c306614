//! Mesh loading: COLLADA units, node transforms and up_axis; STL and OBJ; mesh scale and package:// URIs.

mod common;

use scm::math::Vec3;
use scm::mesh::load_mesh_file;
use scm::robot::{PackagePaths, ShapeSource, load_urdf};

/// A COLLADA file with one triangle (vertices in `unit` metres), instanced under a node with `matrix`.
fn dae(unit: f64, up: &str, matrix: &str) -> String {
    format!(
        r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="u" meter="{unit}"/><up_axis>{up}</up_axis></asset>
  <library_geometries>
    <geometry id="tri" name="tri"><mesh>
      <source id="tri-pos"><float_array id="tri-pos-array" count="9">0 0 0 100 0 0 0 100 0</float_array>
        <technique_common><accessor source="#tri-pos-array" count="3" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="tri-vtx"><input semantic="POSITION" source="#tri-pos"/></vertices>
      <triangles count="1"><input semantic="VERTEX" source="#tri-vtx" offset="0"/><p>0 1 2</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene">
      <node id="n"><matrix>{matrix}</matrix><instance_geometry url="#tri"/></node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>"##
    )
}

const IDENTITY: &str = "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1";

fn load(name: &str, text: &str) -> Vec<Vec3> {
    let dir = common::scratch("dae");
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    load_mesh_file(&path).unwrap().vertices
}

fn assert_points(got: &[Vec3], want: &[[f64; 3]]) {
    assert_eq!(got.len(), want.len());
    for (g, w) in got.iter().zip(want) {
        assert!(
            (*g - Vec3::from_array(*w)).length() < 1e-6,
            "got {got:?}, want {want:?}"
        );
    }
}

#[test]
fn collada_units_are_applied() {
    let v = load("mm.dae", &dae(0.001, "Z_UP", IDENTITY));
    assert_points(&v, &[[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.1, 0.0]]);
}

#[test]
fn collada_node_transforms_are_applied() {
    // Translate by (10, 20, 30) units and rotate 90 degrees about z (row-major COLLADA matrix).
    let m = "0 -1 0 10  1 0 0 20  0 0 1 30  0 0 0 1";
    let v = load("node.dae", &dae(0.01, "Z_UP", m));
    // (100,0,0) -> rotated (0,100,0) + (10,20,30) = (10,120,30) units of 1 cm.
    assert_points(&v, &[[0.1, 0.2, 0.3], [0.1, 1.2, 0.3], [-0.9, 0.2, 0.3]]);
}

#[test]
fn collada_y_up_becomes_z_up() {
    let v = load("yup.dae", &dae(1.0, "Y_UP", IDENTITY));
    // Y_UP: (x, y, z) -> (x, -z, y); the triangle in the XY plane stands up in XZ.
    assert_points(&v, &[[0.0, 0.0, 0.0], [100.0, 0.0, 0.0], [0.0, 0.0, 100.0]]);
}

#[test]
fn obj_and_ascii_stl() {
    let obj = load("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_points(&obj, &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let stl = load(
        "t.stl",
        "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 2 0 0\nvertex 0 2 0\nendloop\nendfacet\nendsolid t\n",
    );
    assert_points(&stl, &[[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]);
}

#[test]
fn package_uris_resolve_without_ros() {
    let root = common::scratch("pkg");
    let pkg = root.join("src/my_robot_description");
    std::fs::create_dir_all(pkg.join("meshes")).unwrap();
    std::fs::create_dir_all(pkg.join("urdf")).unwrap();
    std::fs::write(
        pkg.join("package.xml"),
        "<package><name>my_robot</name></package>",
    )
    .unwrap();
    std::fs::write(
        pkg.join("meshes/a.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .unwrap();
    let other = root.join("elsewhere");
    std::fs::create_dir_all(&other).unwrap();
    std::fs::write(
        other.join("b.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .unwrap();
    let urdf = pkg.join("urdf/r.urdf");
    std::fs::write(
        &urdf,
        r#"<robot name="r">
  <link name="a"><collision><geometry><mesh filename="package://my_robot/meshes/a.obj" scale="2 2 2"/></geometry></collision></link>
  <link name="b"><collision><geometry><mesh filename="package://other_pkg/b.obj"/></geometry></collision></link>
  <link name="c"><visual><geometry><mesh filename="file://../meshes/a.obj"/></geometry></visual></link>
  <joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
  <joint name="ac" type="fixed"><parent link="a"/><child link="c"/></joint>
</robot>"#,
    )
    .unwrap();
    // Without --package-path, other_pkg cannot be found: the message says how to fix it.
    let err = load_urdf(&urdf, &PackagePaths::new())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("other_pkg") && err.contains("--package-path"),
        "{err}"
    );
    let mut packages = PackagePaths::new();
    packages.insert("other_pkg", &other);
    let robot = load_urdf(&urdf, &packages).unwrap();
    let mesh_path = |link: usize| match &robot.links[link].geometry[0].shape {
        ShapeSource::Mesh { path, scale, .. } => (path.canonicalize().unwrap(), *scale),
        other => panic!("{other:?}"),
    };
    assert_eq!(
        mesh_path(0),
        (
            pkg.join("meshes/a.obj").canonicalize().unwrap(),
            Vec3::splat(2.0)
        )
    );
    assert_eq!(mesh_path(1).0, other.join("b.obj").canonicalize().unwrap());
    // A link with only visual geometry falls back to it and says so.
    assert_eq!(
        mesh_path(2).0,
        pkg.join("meshes/a.obj").canonicalize().unwrap()
    );
    assert!(
        robot
            .warnings
            .iter()
            .any(|w| w.contains("\"c\"") && w.contains("visual"))
    );
}
