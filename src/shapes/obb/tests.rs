//! Tests of the tight oriented bounding box.
use super::*;

use crate::shapes::test_rng::{Rng, test_clouds};

fn check_box(b: &Obb, pts: &[Vec3]) {
    assert!(pts.iter().all(|p| b.contains(*p, 0.0)), "{b:?}");
    assert!((b.rotation.length() - 1.0).abs() < 1e-12);
    let m = Mat3::from_quat(b.rotation);
    assert!((m.determinant() - 1.0).abs() < 1e-9);
    let [x, y, z] = b.axes();
    assert!(x.dot(y).abs() < 1e-12 && x.cross(y).distance(z) < 1e-12);
}

#[test]
fn recovers_a_rotated_box() {
    let mut r = Rng(3);
    let he = Vec3::new(0.3, 0.1, 0.05);
    for _ in 0..5 {
        let (rot, t) = (r.rotation(), r.v(-2.0, 2.0));
        let mut pts: Vec<Vec3> = (0..8)
            .map(|i| {
                Obb {
                    center: t,
                    rotation: rot,
                    half_extents: he,
                }
                .corners()[i]
            })
            .collect();
        pts.extend((0..200).map(|_| rot * (r.v(-1.0, 1.0) * he) + t));
        let b = tight_obb(&convex_hull(&pts).unwrap());
        check_box(&b, &pts);
        let mut got = b.half_extents.to_array();
        got.sort_by(f64::total_cmp);
        assert!(
            Vec3::from_array(got).distance(Vec3::new(0.05, 0.1, 0.3)) < 1e-6,
            "{b:?}"
        );
        assert!((b.volume() / (8.0 * 0.3 * 0.1 * 0.05) - 1.0).abs() < 1e-6);
        assert!(b.center.distance(t) < 1e-6);
    }
}

#[test]
fn axis_aligned_box_keeps_identity() {
    let pts: Vec<Vec3> = (0..8)
        .map(|i| {
            Vec3::new(
                (i & 1) as f64 * 0.6,
                (i >> 1 & 1) as f64 * 0.2,
                (i >> 2) as f64 * 0.1,
            )
        })
        .collect();
    let b = tight_obb(&convex_hull(&pts).unwrap());
    assert!(b.rotation.angle_between(Rotation::IDENTITY) < 1e-9, "{b:?}");
    assert!(b.half_extents.distance(Vec3::new(0.3, 0.1, 0.05)) < 1e-9);
    let c = b.corners();
    assert!(
        c.iter().all(|p| b.contains(*p, 1e-12)) && c[7].distance(Vec3::new(0.6, 0.2, 0.1)) < 1e-9
    );
}

#[test]
fn clouds_are_enclosed_tightly() {
    let mut r = Rng(9);
    for pts in test_clouds() {
        let hull = convex_hull(&pts).unwrap();
        let b = tight_obb(&hull);
        check_box(&b, &pts);
        assert_eq!(b, tight_obb(&hull));
        // No better than the PCA box or the axis-aligned box, nor than the best of 3000 random
        // orientations.
        let rel: Vec<Vec3> = pts.iter().map(|p| *p - b.center).collect();
        let pca = box_volume(&rel, &pca_frame(&rel));
        let random = (0..3000)
            .map(|_| {
                let q = r.rotation();
                box_volume(&rel, &[q * Vec3::X, q * Vec3::Y, q * Vec3::Z])
            })
            .fold(f64::MAX, f64::min);
        let aabb = box_volume(&rel, &[Vec3::X, Vec3::Y, Vec3::Z]);
        println!(
            "obb {:.6e}  pca {pca:.6e}  aabb {aabb:.6e}  best random {random:.6e}",
            b.volume()
        );
        assert!(b.volume() <= pca * (1.0 + 1e-9) && b.volume() <= aabb * (1.0 + 1e-9));
        assert!(b.volume() <= random * (1.0 + 1e-9));
    }
}

#[test]
fn jacobi_diagonalises() {
    let mut r = Rng(8);
    for k in 0..20 {
        let q = r.rotation();
        let d =
            Mat3::from_diagonal(Vec3::new(3.0, 2.0, if k % 4 == 0 { 2.0 } else { 0.5 }) * r.f());
        let m = Mat3::from_quat(q) * d * Mat3::from_quat(q).transpose();
        let f = eigen_frame(m);
        let e = Mat3::from_cols(f[0], f[1], f[2]);
        let t = e.transpose() * m * e;
        let off = t.x_axis.y.abs() + t.x_axis.z.abs() + t.y_axis.z.abs();
        assert!(
            off < 1e-12 * 3.0 && (e.determinant() - 1.0).abs() < 1e-12,
            "{t:?}"
        );
    }
}

#[test]
fn degenerate_and_empty() {
    let e = ConvexMesh {
        vertices: vec![],
        faces: vec![],
    };
    assert_eq!(tight_obb(&e).volume(), 0.0);
    // A flat square given as a mesh, and a bare vertex list with no faces.
    let sq = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
    let flat = ConvexMesh {
        vertices: sq.clone(),
        faces: vec![[0, 1, 2], [0, 2, 3], [0, 2, 1], [0, 3, 2]],
    };
    let b = tight_obb(&flat);
    assert!(sq.iter().all(|p| b.contains(*p, 0.0)) && b.volume() < 1e-9);
    let mut r = Rng(4);
    let cloud: Vec<Vec3> = (0..100).map(|_| r.v(-1.0, 1.0)).collect();
    let bare = ConvexMesh {
        vertices: cloud.clone(),
        faces: vec![],
    };
    check_box(&tight_obb(&bare), &cloud);
    let with_nan = ConvexMesh {
        vertices: vec![Vec3::X, Vec3::splat(f64::NAN), Vec3::Y],
        faces: vec![],
    };
    assert!(tight_obb(&with_nan).contains(Vec3::X, 0.0));
}

#[test]
fn fast_on_2000_vertices() {
    let mut r = Rng(1);
    let pts: Vec<Vec3> = (0..2000)
        .map(|_| r.unit() * Vec3::new(0.3, 0.2, 0.1))
        .collect();
    let hull = convex_hull(&pts).unwrap();
    assert_eq!(hull.vertices.len(), 2000);
    let t = std::time::Instant::now();
    let b = tight_obb(&hull);
    let el = t.elapsed();
    println!(
        "tight_obb on {} vertices: {el:?}, volume {:.5} (ideal 0.048)",
        hull.vertices.len(),
        b.volume()
    );
    check_box(&b, &pts);
    assert!(el.as_millis() < 500);
}
