//! Forward kinematics against poses computed by hand, including prismatic, mimic and continuous joints.

mod common;

use scm::math::{Pose, Vec3};
use scm::robot::{Kinematics, UrdfOptions, load_urdf};
use std::f64::consts::FRAC_PI_2;

const URDF: &str = r#"<?xml version="1.0"?>
<robot name="fk">
  <link name="base"/>
  <link name="upper"/>
  <link name="slider"/>
  <link name="follower"/>
  <link name="tip"/>
  <link name="wheel"/>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/>
    <origin xyz="0 0 1" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1"/>
  </joint>
  <joint name="slide" type="prismatic">
    <parent link="upper"/><child link="slider"/>
    <origin xyz="1 0 0" rpy="0 0 0"/>
    <axis xyz="1 0 0"/>
    <limit lower="0" upper="0.5"/>
  </joint>
  <joint name="mirror" type="prismatic">
    <parent link="upper"/><child link="follower"/>
    <origin xyz="0 1 0"/>
    <axis xyz="0 1 0"/>
    <limit lower="-1" upper="1"/>
    <mimic joint="slide" multiplier="-2" offset="0.1"/>
  </joint>
  <joint name="bend" type="revolute">
    <parent link="slider"/><child link="tip"/>
    <origin xyz="0 0 0" rpy="1.5707963267948966 0 0"/>
    <axis/>
    <limit lower="0.5" upper="1.5"/>
  </joint>
  <joint name="spin" type="continuous">
    <parent link="tip"/><child link="wheel"/>
    <origin xyz="0 0 0.2"/>
    <axis xyz="0 0 1"/>
  </joint>
</robot>"#;

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-12
}

fn load() -> scm::robot::Robot {
    let dir = common::scratch("fk");
    let path = dir.join("fk.urdf");
    std::fs::write(&path, URDF).unwrap();
    load_urdf(&path, &UrdfOptions::default()).unwrap()
}

#[test]
fn dofs_limits_and_home() {
    let robot = load();
    let k = Kinematics::new(&robot);
    let names: Vec<&str> = k.dofs().iter().map(|d| d.name.as_str()).collect();
    assert_eq!(
        names,
        ["shoulder", "slide", "bend", "spin"],
        "mimic joints are not DOFs"
    );
    // `bend` does not contain 0: home is the middle of its limits; `spin` is continuous: a full turn.
    assert_eq!(k.home(), vec![0.0, 0.0, 1.0, 0.0]);
    let spin = &k.dofs()[3];
    assert_eq!(
        (spin.lower, spin.upper),
        (-std::f64::consts::PI, std::f64::consts::PI)
    );
    // `<axis/>` without xyz means the x axis.
    assert_eq!(
        robot.joints[robot.joint_index("bend").unwrap()].axis,
        Vec3::X
    );
}

#[test]
fn poses_match_hand_computation() {
    let robot = load();
    let k = Kinematics::new(&robot);
    let link = |name: &str| robot.link_index(name).unwrap();
    // shoulder = 90 deg, slide = 0.25, bend = 90 deg, spin = 90 deg.
    let q = [FRAC_PI_2, 0.25, FRAC_PI_2, FRAC_PI_2];
    let poses: Vec<Pose> = k.link_poses(&q);
    // upper: at (0,0,1), rotated 90 deg about z: its x axis points along world +y.
    assert!(close(
        poses[link("upper")].translation,
        Vec3::new(0.0, 0.0, 1.0)
    ));
    assert!(close(poses[link("upper")].rotation * Vec3::X, Vec3::Y));
    // slider: 1 + 0.25 along upper's x = world +y.
    assert!(close(
        poses[link("slider")].translation,
        Vec3::new(0.0, 1.25, 1.0)
    ));
    // follower mimics slide: -2 * 0.25 + 0.1 = -0.4 along upper's y (= world -x), from (0,1,0) in upper.
    // upper's y axis is world -x, so origin (0,1,0) -> world (-1,0,1), then -0.4 * (-x) -> +0.4 in x.
    assert!(close(
        poses[link("follower")].translation,
        Vec3::new(-0.6, 0.0, 1.0)
    ));
    // tip: origin roll 90 deg about slider x (= world y), then bend 90 deg about the new x (still world y).
    // Total: rotation about world y by 180 deg after the shoulder's 90 deg about z.
    let tip = poses[link("tip")];
    assert!(close(tip.translation, Vec3::new(0.0, 1.25, 1.0)));
    assert!(close(tip.rotation * Vec3::Z, Vec3::new(0.0, 0.0, -1.0)));
    // wheel: 0.2 along tip's z (world -z); spinning about that axis does not move its origin.
    let wheel = poses[link("wheel")];
    assert!(close(wheel.translation, Vec3::new(0.0, 1.25, 0.8)));
    assert!(close(wheel.rotation * Vec3::Z, Vec3::new(0.0, 0.0, -1.0)));
    // The spin of 90 deg about tip's z: tip's x axis (world y) goes to tip's y axis.
    assert!(close(wheel.rotation * Vec3::X, tip.rotation * Vec3::Y));
}

#[test]
fn rpy_is_fixed_axis_xyz() {
    // URDF rpy: R = Rz(yaw) * Ry(pitch) * Rx(roll).
    let r = scm::robot::rpy_to_rotation(Vec3::new(FRAC_PI_2, 0.0, FRAC_PI_2));
    // Rx(90) maps y -> z; then Rz(90) leaves z alone.
    assert!(close(r * Vec3::Y, Vec3::Z));
    // Rx(90) leaves x; Rz(90) maps x -> y.
    assert!(close(r * Vec3::X, Vec3::Y));
}

#[test]
fn one_dof_steps_give_the_full_poses_to_the_bit() {
    // The targeted search moves one DOF at a time from a base and recomputes only what it moves; its
    // poses must be the ones the full computation gives, or the search would depend on its path.
    let robot = load();
    let k = Kinematics::new(&robot);
    let base = [0.7, 0.31, 1.1, -2.5];
    let moved = [-1.9, 0.05, 0.6, 3.0];
    for a in 0..robot.links.len() {
        for b in 0..robot.links.len() {
            let mut chains = k.pair_chains(a, b);
            chains.set_base(&base);
            for dof in 0..base.len() {
                let mut q = base;
                q[dof] = moved[dof];
                let (pa, pb) = chains.poses(&q, dof);
                let (fa, fb) = k.pair_poses(&q, a, b);
                assert_eq!((pa, pb), (fa, fb), "links {a} and {b}, DOF {dof}");
                // Back at the base, unchanged.
                assert_eq!(chains.poses(&base, dof), k.pair_poses(&base, a, b));
            }
        }
    }
}
