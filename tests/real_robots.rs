//! Preprocessing every robot in the shared robots folder: shapes enclose the geometry, counts are
//! snapshotted, and reruns are no-ops that leave files untouched.

mod common;

use scm::preprocess::{PreprocessOptions, link_mesh, load_meshes, preprocess};
use scm::progress::NoProgress;
use scm::robot::{PackagePaths, UrdfOptions, load_urdf};
use scm::shapes::{Geometry, Scope, ShapeParams, ShapeType};
use scm::urdd::Urdd;
use std::collections::BTreeMap;
use std::path::Path;

/// Containment tolerance: 1 micrometre (meshes are stored in f32).
const TOL: f64 = 1e-6;

fn contains(g: &Geometry, p: scm::math::Vec3) -> bool {
    match g {
        Geometry::Sphere(s) => s.contains(p, TOL),
        Geometry::Obb(b) => b.contains(p, TOL),
        Geometry::Hull(h) => h.contains(p, TOL),
    }
}

fn run(urdf: &Path, out: &Path) -> scm::preprocess::PreprocessReport {
    let opts = PreprocessOptions {
        urdf: urdf.to_path_buf(),
        out: out.to_path_buf(),
        packages: PackagePaths::new(),
        visual_fallback: false,
        params: ShapeParams::default(),
        force: false,
    };
    preprocess(&opts, &NoProgress).unwrap_or_else(|e| panic!("{}: {e}", urdf.display()))
}

/// Every mesh vertex of every link lies inside its sphere, OBB and hull (and inside some piece).
fn check_containment(urdf: &Path, urdd: &Urdd) {
    let robot = load_urdf(urdf, &UrdfOptions::default()).unwrap();
    let meshes = load_meshes(&robot, urdf).unwrap();
    for t in ShapeType::ALL {
        let file = urdd.shapes(t).unwrap();
        let mut by_link: BTreeMap<usize, Vec<Geometry>> = BTreeMap::new();
        for s in &file.shapes {
            by_link
                .entry(s.link_index)
                .or_default()
                .push(urdd.geometry(&s.geometry).unwrap());
        }
        for (link, shapes) in by_link {
            let mesh = link_mesh(&robot.links[link], &meshes);
            let outside = mesh
                .vertices
                .iter()
                .filter(|&&v| match t.scope() {
                    Scope::Link => !contains(&shapes[0], v),
                    // VHACD pieces are hulls of the mesh clipped to voxel parts: together they cover it.
                    Scope::Pieces => !shapes.iter().any(|g| contains(g, v)),
                })
                .count();
            assert_eq!(
                outside,
                0,
                "{}: {t} of link {}: {outside} vertices outside",
                urdf.display(),
                robot.links[link].name
            );
        }
    }
}

#[test]
fn preprocess_every_shared_robot() {
    let Some(robots) = common::robots_dir() else {
        return;
    };
    for (folder, file) in common::ROBOTS {
        let urdf = robots.join(folder).join(file);
        let out = common::scratch(folder);
        let report = run(&urdf, &out);
        assert!(!report.up_to_date);
        let urdd = Urdd::open(&out).unwrap();
        check_containment(&urdf, &urdd);

        // Shape counts per type and link, snapshotted.
        let mut counts: BTreeMap<String, BTreeMap<&str, usize>> = BTreeMap::new();
        for t in ShapeType::ALL {
            for s in urdd.shapes(t).unwrap().shapes {
                *counts.entry(s.link).or_default().entry(t.id()).or_default() += 1;
            }
        }
        insta::assert_json_snapshot!(format!("shape_counts_{folder}"), counts);

        // Simplified hulls respect the vertex bound.
        for s in urdd.shapes(ShapeType::Hull).unwrap().shapes {
            if let scm::urdd::GeometryRecord::Hull { vertices, .. } = s.geometry {
                assert!(
                    vertices <= 128,
                    "{folder}: hull of {} has {vertices} vertices",
                    s.link
                );
            }
        }
    }
}

fn mtimes(dir: &Path) -> BTreeMap<String, std::time::SystemTime> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let e = e.unwrap();
            let m = e.metadata().unwrap();
            if m.is_dir() {
                stack.push(e.path());
            }
            out.insert(e.path().display().to_string(), m.modified().unwrap());
        }
    }
    out
}

#[test]
fn rerun_is_a_no_op_and_changes_rerun() {
    let Some(robots) = common::robots_dir() else {
        return;
    };
    let src = robots.join("fanuc");
    // A private copy so the test can edit the URDF.
    let dir = common::scratch("rerun");
    for sub in ["meshes/collision", "meshes/visual"] {
        std::fs::create_dir_all(dir.join(sub)).unwrap();
        for e in std::fs::read_dir(src.join(sub)).unwrap() {
            let e = e.unwrap();
            std::fs::copy(e.path(), dir.join(sub).join(e.file_name())).unwrap();
        }
    }
    let urdf = dir.join("fanuc.urdf");
    std::fs::copy(src.join("fanuc.urdf"), &urdf).unwrap();
    let out = dir.join("out.urdd");
    let first = common::scm(&[
        "preprocess".as_ref(),
        urdf.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--json".as_ref(),
    ]);
    assert!(first.status.success());
    let before = mtimes(&out);
    let bytes_before = std::fs::read(out.join("preprocess/shapes/obb.json")).unwrap();

    let again = common::scm(&[
        "preprocess".as_ref(),
        urdf.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--json".as_ref(),
    ]);
    assert!(again.status.success());
    let json: serde_json::Value = serde_json::from_slice(&again.stdout).unwrap();
    assert_eq!(json["up_to_date"], true);
    assert_eq!(
        mtimes(&out),
        before,
        "an up-to-date rerun must not touch any file"
    );

    // A changed parameter reruns; so does a changed mesh.
    let o = common::scm(&[
        "preprocess".as_ref(),
        urdf.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--json".as_ref(),
        "--max-hull-vertices".as_ref(),
        "32".as_ref(),
    ]);
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["up_to_date"], false);
    let mesh = dir.join("meshes/collision/link_6.stl");
    let mut m = std::fs::read(&mesh).unwrap();
    m[0] ^= 1; // the STL header: geometry unchanged, content changed
    std::fs::write(&mesh, m).unwrap();
    let o = common::scm(&[
        "preprocess".as_ref(),
        urdf.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--json".as_ref(),
        "--max-hull-vertices".as_ref(),
        "32".as_ref(),
    ]);
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["up_to_date"], false);
    // Same inputs and parameters as the first run: same bytes (determinism).
    std::fs::write(
        &mesh,
        std::fs::read(src.join("meshes/collision/link_6.stl")).unwrap(),
    )
    .unwrap();
    let o = common::scm(&[
        "preprocess".as_ref(),
        urdf.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "-q".as_ref(),
    ]);
    assert!(o.status.success());
    assert_eq!(
        std::fs::read(out.join("preprocess/shapes/obb.json")).unwrap(),
        bytes_before
    );
}
