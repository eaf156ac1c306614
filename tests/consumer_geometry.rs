//! Geometry parity with the consumers: scm's collision geometry is the geometry Pinocchio + Coal (and so
//! MoveIt, which loads meshes through the same Assimp rules) builds from the same URDF.
//!
//! For every shared robot and the authored mesh-variants robot: at 20 random
//! configurations, per link, the number of collision geometries and the world-frame box of all of them
//! (`scm inspect --json` against `tests/consumers/geometry_pinocchio.py`) agree to 1e-6 m, and every
//! vertex of the consumer's geometry (points on the surface of its primitives) lies inside scm's link
//! hull, which is what makes a hull-level `never` safe for that consumer.
//!
//! The demo arm is not among them: it was written to exercise scm's leniency (a `<capsule>`, a `<limit>`
//! without `velocity`), which urdfdom, and so Pinocchio and MoveIt, refuse.

mod common;

use common::{python_with, robots_dir, run_consumer, scm_str};
use scm::shapes::{Geometry, ShapeType};
use scm::urdd::Urdd;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Largest difference between scm's and the consumer's world boxes.
const BOX_TOLERANCE: f64 = 1e-6;
/// How far outside scm's hull a consumer vertex may lie (hull planes are f64 from f32 mesh data).
const HULL_TOLERANCE: f64 = 1e-7;
const CONFIGURATIONS: &str = "20";

fn mesh_variants() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mesh_variants/mesh_variants.urdf")
}

fn corner(v: &Value) -> [f64; 3] {
    std::array::from_fn(|i| v[i].as_f64().expect("a number"))
}

/// Compares scm's loaded geometry of `urdf` with Pinocchio's; `packages` is Pinocchio's package dir.
fn assert_parity(urdf: &Path, packages: &Path, name: &str) {
    let Some(python) = python_with(&["pinocchio", "coal"]) else {
        return;
    };
    let dir = common::preprocessed(urdf, name);
    let out = scm_str(&[
        "inspect",
        dir.to_str().unwrap(),
        "--json",
        "--random",
        CONFIGURATIONS,
    ]);
    assert!(
        out.status.success(),
        "scm inspect: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let scm: Value = serde_json::from_slice(&out.stdout).expect("inspect JSON");
    let configs = dir.join("configs.json");
    let joints: Vec<&Value> = scm["configurations"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| &c["joints"])
        .collect();
    std::fs::write(&configs, serde_json::to_vec(&joints).unwrap()).unwrap();
    let consumer = run_consumer(python, "geometry_pinocchio.py", &[urdf, packages, &configs]);

    let mut worst = 0.0f64;
    let scm_configs = scm["configurations"].as_array().unwrap();
    let consumer_configs = consumer["configurations"].as_array().unwrap();
    assert_eq!(scm_configs.len(), consumer_configs.len());
    for (k, (ours, theirs)) in scm_configs.iter().zip(consumer_configs).enumerate() {
        let theirs = theirs.as_object().unwrap();
        let ours: BTreeMap<&str, &Value> = ours["links"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| (l["link"].as_str().unwrap(), l))
            .collect();
        assert_eq!(
            ours.keys().copied().collect::<Vec<_>>(),
            theirs.keys().map(String::as_str).collect::<Vec<_>>(),
            "{name}: the links with collision geometry differ"
        );
        for (link, l) in &ours {
            let t = &theirs[*link];
            assert_eq!(
                l["elements"].as_array().unwrap().len() as u64,
                t["count"].as_u64().unwrap(),
                "{name}: link \"{link}\": number of collision geometries"
            );
            for (ours, theirs) in [
                (&l["bounds"]["min"], &t["min"]),
                (&l["bounds"]["max"], &t["max"]),
            ] {
                let (a, b) = (corner(ours), corner(theirs));
                for i in 0..3 {
                    let d = (a[i] - b[i]).abs();
                    worst = worst.max(d);
                    assert!(
                        d <= BOX_TOLERANCE,
                        "{name}: link \"{link}\", configuration {k}: world box {a:?} vs Pinocchio's \
                         {b:?} (off by {d:.3e} m)"
                    );
                }
            }
        }
    }

    // Every consumer vertex inside scm's link hull.
    let urdd = Urdd::open(&dir).unwrap();
    let hulls = urdd.shapes(ShapeType::Hull).unwrap();
    let mut checked = 0;
    for (link, points) in consumer["points"].as_object().unwrap() {
        let record = hulls
            .shapes
            .iter()
            .find(|s| &s.link == link)
            .unwrap_or_else(|| panic!("{name}: link \"{link}\" has no scm hull"));
        let Geometry::Hull(hull) = urdd.geometry(&record.geometry).unwrap() else {
            panic!("{name}: the hull type holds a non-hull shape");
        };
        for p in points.as_array().unwrap() {
            let p = scm::math::Vec3::from_array(corner(p));
            assert!(
                hull.contains(p, HULL_TOLERANCE),
                "{name}: link \"{link}\": Pinocchio's vertex {p:?} lies outside scm's hull"
            );
            checked += 1;
        }
    }
    assert!(checked > 0, "{name}: no consumer vertices checked");
    eprintln!(
        "{name}: boxes agree within {worst:.2e} m over {CONFIGURATIONS} configurations; \
         {checked} consumer vertices inside scm's hulls"
    );
}

#[test]
fn mesh_variants_load_as_pinocchio_loads_them() {
    let urdf = mesh_variants();
    // Its meshes are `package://mesh_variants/...`: Pinocchio's package folder is the one above it.
    let packages = urdf.parent().and_then(Path::parent).unwrap().to_path_buf();
    assert_parity(&urdf, &packages, "parity-variants");
}

#[test]
fn shared_robots_load_as_pinocchio_loads_them() {
    let Some(robots) = robots_dir() else { return };
    for (folder, file) in common::ROBOTS {
        let urdf = robots.join(folder).join(file);
        assert_parity(&urdf, &robots.join(folder), &format!("parity-{folder}"));
    }
}
