//! The project's own demo robot: every supported format and leniency in one URDF, with known answers.

mod common;

use scm::preprocess::{PreprocessOptions, preprocess};
use scm::progress::NoProgress;
use scm::robot::{GeometryOrigin, PackagePaths};
use scm::shapes::{ShapeParams, ShapeType};
use scm::urdd::Urdd;

#[test]
fn demo_arm_preprocesses_with_known_structure() {
    let out = common::scratch("demo");
    let opts = PreprocessOptions {
        urdf: common::demo_urdf(),
        out: out.clone(),
        packages: PackagePaths::new(),
        visual_fallback: false,
        params: ShapeParams::default(),
        force: false,
    };
    let report = preprocess(&opts, &NoProgress).unwrap();
    assert_eq!(
        (report.links, report.links_with_geometry, report.dofs),
        (14, 13, 8)
    );
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);

    let urdd = Urdd::open(&out).unwrap();
    let record = urdd.robot().unwrap();
    // Transmission and gazebo <joint> children are not joints: 13 real ones.
    assert_eq!(record.robot.joints.len(), 13);
    // joint4's range [0.1, 3.4] excludes 0: home is its middle.
    let joint4 = record.dofs.iter().find(|d| d.name == "joint4").unwrap();
    assert!((joint4.home() - 1.75).abs() < 1e-12);
    // link7 and hand meet through the geometry-less flange link8: adjacent by MoveIt's rule.
    let adjacent: Vec<(&str, &str)> = record
        .adjacent
        .iter()
        .map(|[a, b]| (a.as_str(), b.as_str()))
        .collect();
    assert!(adjacent.contains(&("link7", "hand")), "{adjacent:?}");
    assert_eq!(adjacent.len(), 12);
    assert!(
        record
            .robot
            .links
            .iter()
            .all(|l| l.name == "link8" || l.geometry_source == GeometryOrigin::Collision)
    );

    // The U-shaped palm is split; the plain cylinder (link7) is not.
    let links = urdd.links().unwrap();
    let pieces = |name: &str| links.iter().find(|l| l.link == name).unwrap().fit.pieces;
    assert!(pieces("hand") > 1, "hand: {}", pieces("hand"));
    assert_eq!(pieces("link7"), 1);
    for l in &links {
        let fit = &l.fit.relative_volume;
        // Every enclosing representation is at least the hull's volume (within the simplification).
        assert!(
            fit[ShapeType::Hull] >= 0.999 && fit[ShapeType::Hull] < 1.1,
            "{}: {fit:?}",
            l.link
        );
        assert!(
            fit[ShapeType::Obb] >= 0.999 && fit[ShapeType::Sphere] >= fit[ShapeType::Obb] * 0.5,
            "{}: {fit:?}",
            l.link
        );
    }
    // The millimetre DAE with a node transform (link4) lands where the URDF puts it: within the arm's
    // reach, not 100 m away.
    let obb = urdd.shapes(ShapeType::Obb).unwrap();
    let link4 = obb.shapes.iter().find(|s| s.link == "link4").unwrap();
    if let scm::urdd::GeometryRecord::Obb {
        center,
        half_extents,
        ..
    } = link4.geometry
    {
        assert!(
            center.length() < 0.5 && half_extents.max_element() < 0.3,
            "{center:?} {half_extents:?}"
        );
    } else {
        panic!("obb expected");
    }
}
