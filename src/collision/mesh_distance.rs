//! The distance between two triangle meshes by one simultaneous traversal of their bounding-volume
//! trees: a pair of nodes is opened only while the gap between their boxes is below the least
//! triangle-pair distance found so far (from the start, that of two vertices facing each other), and
//! each pair of leaves is one triangle-triangle query.
//!
//! parry's own mesh-mesh distance walks the first mesh's tree against the whole second mesh's box and
//! starts a walk of the second tree for every triangle it reaches, so meshes that nest closely (the
//! fingers of a hand, a motor in its housing) cost thousands of walks. The answer is the same least
//! triangle-pair distance, by the same triangle queries. (Its intersection test is left as parry's:
//! the same traversal was slower there, as the boxes of meshes that nearly touch overlap everywhere.)

use crate::math::{Mat3, Pose, Vec3};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::partitioning::BvhNode;
use parry3d_f64::query::{DefaultQueryDispatcher, QueryDispatcher};
use parry3d_f64::shape::TriMesh;
use std::cell::Cell;

/// The least distance between a triangle of `a` (posed at `pa`) and one of `b` (at `pb`): 0 where two
/// triangles meet. A caller with no use for a distance at or below `enough` gets one as soon as the
/// walk meets it: then the value returned is only known to be at most `enough` (two points that far
/// apart); above `enough` it is the least distance (`f64::NEG_INFINITY`: always).
pub(super) fn mesh_distance(a: &TriMesh, pa: &Pose, b: &TriMesh, pb: &Pose, enough: f64) -> f64 {
    // Everything in `a`'s frame.
    let pos12 = pa.inv_mul(pb);
    let turn = Turn::new(&pos12);
    // The first bound: two vertices, each the farthest of its mesh towards the other's box.
    let towards =
        turn.translation + turn.rotation * b.local_aabb().center() - a.local_aabb().center();
    let back = turn.rotation.transpose() * -towards;
    let farthest = |m: &TriMesh, dir: Vec3| {
        m.vertices()
            .iter()
            .copied()
            .max_by(|x, y| x.dot(dir).total_cmp(&y.dot(dir)))
    };
    let seed = match (farthest(a, towards), farthest(b, back)) {
        (Some(va), Some(vb)) => va.distance(pos12.transform_point(vb)),
        _ => f64::INFINITY,
    };
    if seed <= enough {
        return seed;
    }
    let best = Cell::new(seed);
    // Boxes are kept while they could hold a closer triangle pair than the best (with a margin far
    // below the triangle queries' own tolerance, against the rounding of the boxes).
    let near = |x: &Aabb, y: &Aabb| turn.gap(x, y) - 1e-12 < best.get();
    let open = |n1: &BvhNode, n2: &BvhNode| near(&n1.aabb(), &n2.aabb());
    for (i, j) in a.bvh().leaf_pairs(b.bvh(), open) {
        let (ta, tb) = (a.triangle(i), b.triangle(j));
        // A pair pushed before the best improved is judged again before its query.
        if !near(&ta.local_aabb(), &tb.local_aabb()) {
            continue;
        }
        // A pairing parry does not support could be touching: 0 is the safe bound.
        let d = DefaultQueryDispatcher
            .distance(&pos12, &ta, &tb)
            .map_or(0.0, |r| r.distance);
        if d < best.get() {
            best.set(d.max(0.0));
            if d <= 0.0 || best.get() <= enough {
                break;
            }
        }
    }
    best.get()
}

/// The pose of `b`'s frame in `a`'s, its rotation as a matrix once for every box it turns.
struct Turn {
    rotation: Mat3,
    /// The rotation's entries, each made positive: the half-extents of a turned box's enclosing box.
    spread: Mat3,
    translation: Vec3,
}

impl Turn {
    fn new(pos12: &Pose) -> Turn {
        let rotation = Mat3::from_quat(pos12.rotation);
        Turn {
            rotation,
            spread: rotation.abs(),
            translation: pos12.translation,
        }
    }

    /// The distance between box `a` (`a`'s frame) and box `b` (`b`'s frame): the gap between `a` and
    /// the box that encloses `b` turned into `a`'s frame, so a lower bound on the distance between
    /// anything inside the two (0 where the boxes meet).
    fn gap(&self, a: &Aabb, b: &Aabb) -> f64 {
        let centre = self.rotation * b.center() + self.translation;
        let half = self.spread * b.half_extents();
        let gaps = (a.center() - centre).abs() - a.half_extents() - half;
        gaps.max(Vec3::ZERO).length()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::test_shapes::{link, values};
    use parry3d_f64::query;

    /// A torus of `n` x `n / 2` quads (two triangles each) about z: concave, so two of them can link
    /// and nest, as finger links and motor housings do.
    fn torus(major: f64, minor: f64, n: u32) -> TriMesh {
        let m = n / 2;
        let tau = std::f64::consts::TAU;
        let vertices = (0..n)
            .flat_map(|i| (0..m).map(move |j| (i, j)))
            .map(|(i, j)| {
                let (u, v) = (
                    tau * f64::from(i) / f64::from(n),
                    tau * f64::from(j) / f64::from(m),
                );
                let r = major + minor * v.cos();
                Vec3::new(r * u.cos(), r * u.sin(), minor * v.sin())
            })
            .collect();
        let at = |i: u32, j: u32| (i % n) * m + j % m;
        let triangles = (0..n)
            .flat_map(|i| (0..m).map(move |j| (i, j)))
            .flat_map(|(i, j)| {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                [[a, b, c], [a, c, d]]
            })
            .collect();
        TriMesh::new(vertices, triangles).expect("a torus is a valid mesh")
    }

    /// Two tori of different sizes and 300 random pose pairs for them (linked, nested, touching and
    /// apart), drawn from `seed`.
    fn tori_posed(seed: u64) -> (TriMesh, TriMesh, Vec<(Pose, Pose)>) {
        let mut r = values(seed);
        let poses = (0..300).map(|_| (link(&mut r), link(&mut r))).collect();
        (torus(0.2, 0.05, 32), torus(0.12, 0.03, 24), poses)
    }

    /// Over random poses, the distance is parry's mesh-mesh distance: the same least triangle-pair
    /// query, found without walking every pair (the same to rounding: the first bound is a vertex
    /// pair's distance, which can be the answer).
    #[test]
    fn equals_parrys_mesh_distance() {
        let (a, b, poses) = tori_posed(7);
        let (mut apart, mut meeting) = (0, 0);
        for (pa, pb) in poses {
            let ours = mesh_distance(&a, &pa, &b, &pb, f64::NEG_INFINITY);
            let parry = query::distance(&pa, &a, &pb, &b)
                .expect("meshes are supported")
                .distance;
            let parry = parry.max(0.0);
            assert!(
                (ours - parry).abs() <= 1e-12 && (ours == 0.0) == (parry == 0.0),
                "ours {ours}, parry {parry}, poses {pa:?} {pb:?}"
            );
            if ours > 0.0 { apart += 1 } else { meeting += 1 }
        }
        // Both kinds of configuration were met.
        assert!(
            apart > 50 && meeting > 10,
            "apart {apart}, meeting {meeting}"
        );
    }

    /// A caller's `enough` changes nothing above it (the same distance, to the bit) and, at or below
    /// it, returns a distance at most `enough` that is still at least the least one.
    #[test]
    fn stopping_at_enough_keeps_every_distance_above_it() {
        let (a, b, poses) = tori_posed(11);
        let (mut above, mut below) = (0, 0);
        for (pa, pb) in poses {
            let least = mesh_distance(&a, &pa, &b, &pb, f64::NEG_INFINITY);
            if least <= 0.0 {
                continue;
            }
            for enough in [least.next_down(), 0.5 * least, -1.0] {
                let d = mesh_distance(&a, &pa, &b, &pb, enough);
                assert_eq!(d.to_bits(), least.to_bits(), "{enough} below {least}");
                above += 1;
            }
            for enough in [least, 1.001 * least, 2.0 * least, 10.0] {
                let d = mesh_distance(&a, &pa, &b, &pb, enough);
                assert!(least <= d && d <= enough, "{d} for {enough}, least {least}");
                below += 1;
            }
        }
        assert!(above > 150 && below > 200, "above {above}, below {below}");
    }
}
