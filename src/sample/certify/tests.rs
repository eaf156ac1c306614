//! The certificate's bound and search on authored arms with known least distances.

use super::*;
use crate::math::{Pose, Rotation, Vec3};
use crate::rng::Rng;
use crate::robot::{UrdfOptions, parse_urdf};
use crate::shapes::{Geometry, Obb, Sphere};
use std::path::Path;

/// A robot from URDF joints over links `base, l1, l2, ...` (no geometry: shapes are given apart).
fn robot(joints: &str, links: usize) -> Kinematics {
    let links: String = (0..links)
        .map(|i| {
            format!(
                "<link name=\"{}\"/>",
                if i == 0 {
                    "base".into()
                } else {
                    format!("l{i}")
                }
            )
        })
        .collect();
    let text = format!("<robot name=\"t\">{links}{joints}</robot>");
    let robot = parse_urdf(&text, Path::new("t.urdf"), &UrdfOptions::default()).unwrap();
    Kinematics::new(&robot)
}

/// Links `a` and `b` with their hulls, the other DOFs at `base`, hulls only.
fn hulls<'a>(
    kinematics: &'a Kinematics,
    (link_a, hull_a): (usize, &'a CollisionShape),
    (link_b, hull_b): (usize, &'a CollisionShape),
    base: &'a [f64],
) -> PairGeometry<'a> {
    PairGeometry {
        kinematics,
        link_a,
        hull_a,
        link_b,
        hull_b,
        base,
        exact: None,
    }
}

fn ball(center: Vec3, radius: f64) -> CollisionShape {
    CollisionShape::new(&Geometry::Sphere(Sphere { center, radius })).unwrap()
}

/// The arm of `certify_two_links`: l1 turns about z at the origin over `[lower, upper]`.
const ONE_JOINT: &str = r#"<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <axis xyz="0 0 1"/><limit lower="-1.0" upper="1.5" effort="1" velocity="1"/></joint>"#;

fn run_one(gap: f64) -> Certificate {
    // A ball of radius 0.1 at 1 m from the axis sweeps past a ball at (2, 0, 0): the least
    // distance, at angle 0, is 2 - 1 - 0.1 - r = gap.
    let k = robot(ONE_JOINT, 2);
    let moving = ball(Vec3::new(1.0, 0.0, 0.0), 0.1);
    let fixed = ball(Vec3::new(2.0, 0.0, 0.0), 0.9 - gap);
    let base = k.home();
    let pair = hulls(&k, (0, &fixed), (1, &moving), &base);
    let exact = |q: &[f64]| {
        let (pa, pb) = k.pair_poses(q, 0, 1);
        signed_distance(&fixed, &fixed.pose(&pa), &moving, &moving.pose(&pb)) <= 0.0
    };
    certify(&pair, 1e-6, 100_000, exact)
}

#[test]
fn certify_two_links() {
    let c = run_one(1e-3);
    assert_eq!(c.status, Status::Certified, "{c:?}");
    assert!(c.lower_bound > 1e-6 && c.lower_bound <= 1e-3, "{c:?}");
    assert!(c.closest >= 1e-3 - 1e-12, "{c:?}");
    assert_eq!(c.cleared, 1.0);
    // Closing the gap to -1 mm turns the certificate into a witness.
    let w = run_one(-1e-3);
    assert_eq!(w.status, Status::Collides, "{w:?}");
    assert!(
        w.q[0].abs() < 0.0317,
        "the collision is within 0.0316 rad of 0: {w:?}"
    );
}

/// A planar 2R arm (l1 about z at the origin, l2 about z at x = 1) whose tip ball at x = 0.5 in
/// l2 reaches x = 1.5 + 0.1 only at the configuration (0, 0).
const TWO_JOINTS: &str = r#"
    <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
      <axis xyz="0 0 1"/><limit lower="-0.4" upper="0.6" effort="1" velocity="1"/></joint>
    <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
      <origin xyz="1 0 0"/><axis xyz="0 0 1"/>
      <limit lower="-0.7" upper="0.3" effort="1" velocity="1"/></joint>"#;

#[test]
fn certify_three_links() {
    for (gap, expected) in [(1e-3, Status::Certified), (-1e-3, Status::Collides)] {
        let k = robot(TWO_JOINTS, 3);
        let tip = ball(Vec3::new(0.5, 0.0, 0.0), 0.1);
        let wall = ball(Vec3::new(2.0, 0.0, 0.0), 0.4 - gap);
        let base = k.home();
        let pair = hulls(&k, (0, &wall), (2, &tip), &base);
        let exact = |q: &[f64]| {
            let (pa, pb) = k.pair_poses(q, 0, 2);
            signed_distance(&wall, &wall.pose(&pa), &tip, &tip.pose(&pb)) <= 0.0
        };
        let c = certify(&pair, 1e-6, 100_000, exact);
        assert_eq!(c.status, expected, "gap {gap}: {c:?}");
        if expected == Status::Certified {
            assert!(c.lower_bound > 0.0 && c.lower_bound <= gap, "{c:?}");
            assert!(c.closest >= gap - 1e-12, "{c:?}");
        }
    }
}

#[test]
fn a_tiny_budget_reports_what_it_cleared() {
    let k = robot(TWO_JOINTS, 3);
    let tip = ball(Vec3::new(0.5, 0.0, 0.0), 0.1);
    let wall = ball(Vec3::new(2.0, 0.0, 0.0), 0.399);
    let base = k.home();
    let pair = hulls(&k, (0, &wall), (2, &tip), &base);
    let c = certify(&pair, 1e-6, 9, |_| false);
    assert_eq!(c.status, Status::Budget);
    assert!(
        c.boxes <= 9 && c.cleared < 1.0 && c.lower_bound < 1e-6,
        "{c:?}"
    );
}

/// Random configurations inside random sub-boxes are never closer than the box's bound, on a chain
/// with revolute, prismatic, continuous and mimic joints and boxes far off every axis.
#[test]
fn the_bound_is_sound() {
    let joints = r#"
        <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
          <origin xyz="0.1 0.2 0.3" rpy="0.3 -0.2 0.5"/><axis xyz="0 1 0"/>
          <limit lower="-2" upper="2.5" effort="1" velocity="1"/></joint>
        <joint name="j2" type="prismatic"><parent link="l1"/><child link="l2"/>
          <origin xyz="0.4 0 0.1"/><axis xyz="0.6 0 0.8"/>
          <limit lower="-0.2" upper="0.3" effort="1" velocity="1"/></joint>
        <joint name="j3" type="continuous"><parent link="l2"/><child link="l3"/>
          <origin xyz="0 0.3 0" rpy="1 0 0"/><axis xyz="1 0 0"/></joint>
        <joint name="j4" type="revolute"><parent link="l3"/><child link="l4"/>
          <origin xyz="0.2 0 0.2"/><axis xyz="0 0 1"/>
          <mimic joint="j1" multiplier="-1.7" offset="0.2"/>
          <limit lower="-5" upper="5" effort="1" velocity="1"/></joint>
        <joint name="j5" type="revolute"><parent link="base"/><child link="l5"/>
          <origin xyz="-0.3 0 0"/><axis xyz="0 0 1"/>
          <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"#;
    let k = robot(joints, 6);
    let obb = |c: Vec3, r: Rotation, h: Vec3| {
        CollisionShape::new(&Geometry::Obb(Obb {
            center: c,
            rotation: r,
            half_extents: h,
        }))
        .unwrap()
    };
    let a = obb(
        Vec3::new(0.3, -0.2, 0.4),
        Rotation::from_rotation_y(0.7),
        Vec3::new(0.1, 0.05, 0.2),
    );
    let b = obb(
        Vec3::new(-0.5, 0.1, 0.2),
        Rotation::from_rotation_z(0.4),
        Vec3::new(0.05, 0.1, 0.15),
    );
    let base = k.home();
    let pair = hulls(&k, (4, &a), (5, &b), &base);
    let dofs = path_dofs(&pair);
    assert_eq!(dofs.len(), 4, "j1 (and its mimic j4), j2, j3, j5");
    let mut eval = Evaluator {
        pair: &pair,
        dofs: dofs.clone(),
        q: base.clone(),
        side_a: Vec::new(),
        side_b: Vec::new(),
        margin: 1e-6,
        exact_queries: 0,
    };
    let mut rng = Rng::new(11, 0);
    for _ in 0..300 {
        let (center, half): (Vec<f64>, Vec<f64>) = dofs
            .iter()
            .map(|&d| {
                let dof = &k.dofs()[d];
                let c = rng.range(dof.lower, dof.upper);
                (c, rng.range(0.0, 0.5) * rng.unit())
            })
            .unzip();
        let bound = eval.evaluate(&center, &half, None).lower;
        for _ in 0..50 {
            let mut q = base.clone();
            for (i, &d) in dofs.iter().enumerate() {
                q[d] = center[i] + half[i] * rng.range(-1.0, 1.0);
            }
            let (pa, pb) = k.pair_poses(&q, 4, 5);
            let d = signed_distance(&a, &a.pose(&pa), &b, &b.pose(&pb));
            assert!(
                d >= bound - 1e-9,
                "distance {d} below the bound {bound} at {q:?}"
            );
        }
        // A child box may take its parent's reaches about every joint not above one its split DOF
        // drives (j1 drives j4 too, at the bottom of its side): they are what it would compute.
        let parent = eval.evaluate(&center, &half, None);
        for split in 0..dofs.len() {
            let mut child = center.clone();
            child[split] += 0.5 * half[split];
            let from = Inherited {
                reaches: parent.reaches.clone(),
                split,
            };
            let (kept, fresh) = (
                eval.evaluate(&child, &half, Some(&from)),
                eval.evaluate(&child, &half, None),
            );
            for (x, y) in kept.reaches.iter().zip(&fresh.reaches) {
                assert!(
                    (x - y).abs() < 1e-12,
                    "split {split}: reach {x} kept, {y} fresh"
                );
            }
            assert!((kept.lower - fresh.lower).abs() < 1e-12);
        }
        // And it converges: over a tiny box the bound is the centre's distance, so branch and
        // bound ends wherever the hulls are apart.
        let tiny = vec![1e-7; dofs.len()];
        let e = eval.evaluate(&center, &tiny, None);
        assert!(e.distance - e.lower < 1e-5, "{} vs {}", e.distance, e.lower);
    }
}

/// Over a box where one joint tilts the axis of another that spins a ball far off it, random
/// configurations never come closer than the bound (which counts motion along the separating
/// direction only).
#[test]
fn the_bound_holds_under_tilted_axes() {
    let joints = r#"
        <joint name="tilt" type="revolute"><parent link="base"/><child link="l1"/>
          <axis xyz="1 0 0"/><limit lower="-0.6" upper="0.6" effort="1" velocity="1"/></joint>
        <joint name="spin" type="revolute"><parent link="l1"/><child link="l2"/>
          <axis xyz="0 0 1"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>"#;
    let k = robot(joints, 3);
    // A ball on l2 0.5 m off the spin axis; a ball on the base straight above the spin axis.
    let arm = ball(Vec3::new(0.0, 0.5, 0.0), 0.05);
    let top = ball(Vec3::new(0.0, 0.0, 1.0), 0.05);
    let base = k.home();
    let pair = hulls(&k, (0, &top), (2, &arm), &base);
    let mut eval = Evaluator {
        pair: &pair,
        dofs: vec![0, 1],
        q: base.clone(),
        side_a: Vec::new(),
        side_b: Vec::new(),
        margin: 1e-6,
        exact_queries: 0,
    };
    let (center, half) = ([0.0, 0.0], [0.6, 1.5]);
    let bound = eval.evaluate(&center, &half, None).lower;
    let mut rng = Rng::new(3, 0);
    for _ in 0..2000 {
        let q = [rng.range(-0.6, 0.6), rng.range(-1.5, 1.5)];
        let (pa, pb) = k.pair_poses(&q, 0, 2);
        let d = signed_distance(&top, &top.pose(&pa), &arm, &arm.pose(&pb));
        assert!(
            d >= bound - 1e-9,
            "distance {d} below the bound {bound} at {q:?}"
        );
    }
}

/// Hulls that overlap where the geometry inside them does not: the hulls alone stop, the exact
/// geometry's distance certifies.
#[test]
fn the_exact_geometry_certifies_where_the_hulls_touch() {
    let k = robot(ONE_JOINT, 2);
    // Hull balls of radius 0.5 and 0.6 reach each other (1 + 0.5 + 0.6 > 2); the geometry inside,
    // balls of radius 0.1 and 0.5, stays 0.4 m apart.
    let (moving, fixed) = (
        ball(Vec3::new(1.0, 0.0, 0.0), 0.5),
        ball(Vec3::new(2.0, 0.0, 0.0), 0.6),
    );
    let (inner_moving, inner_fixed) = (
        ball(Vec3::new(1.0, 0.0, 0.0), 0.1),
        ball(Vec3::new(2.0, 0.0, 0.0), 0.5),
    );
    let exact = |pa: &Pose, pb: &Pose, enough: f64| {
        let d = signed_distance(
            &inner_fixed,
            &inner_fixed.pose(pa),
            &inner_moving,
            &inner_moving.pose(pb),
        )
        .max(0.0);
        (d > enough).then_some(d)
    };
    let base = k.home();
    let mut pair = hulls(&k, (0, &fixed), (1, &moving), &base);
    let hulls = certify(&pair, 1e-6, 100_000, |_| false);
    assert_eq!(hulls.status, Status::HullsTouch, "{hulls:?}");
    pair.exact = Some((&exact, 2_000));
    let c = certify(&pair, 1e-6, 100_000, |_| false);
    assert_eq!(c.status, Status::Certified, "{c:?}");
    assert!(
        c.exact_queries > 0 && c.lower_bound > 0.0 && c.lower_bound <= 0.4,
        "{c:?}"
    );
    // With too few exact distances the budget runs out instead.
    pair.exact = Some((&exact, 1));
    assert_eq!(
        certify(&pair, 1e-6, 1_000, |_| false).status,
        Status::Budget
    );
}

#[test]
fn dropping_boxes_the_budget_cannot_reach_keeps_the_pop_order() {
    // Boxes with distinct and with tied lower bounds (ties break by centre).
    let boxes = || {
        let mut rng = Rng::new(7, 0);
        (0..500)
            .map(|i| SubBox {
                center: vec![rng.range(-1.0, 1.0), f64::from(i)],
                half: vec![0.5, 0.5],
                volume: 1.0,
                lower: (rng.unit() * 20.0).round() / 20.0,
                split: 0,
                reaches: Vec::new(),
            })
            .collect::<BinaryHeap<SubBox>>()
    };
    let order = |mut heap: BinaryHeap<SubBox>| {
        std::iter::from_fn(|| heap.pop().map(|b| (b.lower, b.center[1]))).collect::<Vec<_>>()
    };
    let all = order(boxes());
    for keep in [0, 1, 37, 499, 500, 800] {
        let mut kept = boxes();
        keep_first(&mut kept, keep);
        assert_eq!(order(kept), all[..keep.min(500)], "keep {keep}");
    }
}
