//! The signed-distance query path against an exact brute-force reference on real robots: for separated
//! convex pairs, the minimum over vertex-triangle and edge-edge distances; for overlapping ones, the
//! penetration depth as the least overlap of the two shapes' projections over face normals and
//! edge-edge cross products (no axis may separate them). Prints the worst errors per type.

mod common;

use scm::collision::{CollisionShape, closest_on_segments, closest_on_triangle, signed_distance};
use scm::math::{Pose, Vec3};
use scm::robot::Kinematics;
use scm::shapes::{ConvexMesh, Geometry, ShapeType, convex_hull};
use scm::urdd::Urdd;
use std::path::Path;

fn posed(mesh: &ConvexMesh, pose: &Pose) -> ConvexMesh {
    ConvexMesh {
        vertices: mesh
            .vertices
            .iter()
            .map(|v| pose.transform_point(*v))
            .collect(),
        faces: mesh.faces.clone(),
    }
}

/// Exact distance between two separated convex polyhedra.
fn brute_distance(a: &ConvexMesh, b: &ConvexMesh) -> f64 {
    let mut best = f64::INFINITY;
    for (p, m) in [(a, b), (b, a)] {
        for v in &p.vertices {
            for f in &m.faces {
                let [x, y, z] = f.map(|i| m.vertices[i as usize]);
                best = best.min(v.distance(closest_on_triangle(*v, x, y, z)));
            }
        }
    }
    let (ea, eb) = (a.edges(), b.edges());
    for (p1, q1) in &ea {
        for (p2, q2) in &eb {
            let (x, y) = closest_on_segments(*p1, *q1, *p2, *q2);
            best = best.min(x.distance(y));
        }
    }
    best
}

/// Exact penetration depth of two convex polyhedra, negative when they are apart along some axis: the
/// least overlap of their projections over every face normal of either and every cross product of an
/// edge of each. Those include the facet normals of their Minkowski difference, whose facet nearest
/// the origin gives the depth; any other axis overlaps by more, so the extra ones cannot lower it.
fn exact_depth(a: &ConvexMesh, b: &ConvexMesh) -> f64 {
    let normal = |m: &ConvexMesh, f: &[u32; 3]| {
        let [x, y, z] = f.map(|i| m.vertices[i as usize]);
        (y - x).cross(z - x)
    };
    let mut best = f64::INFINITY;
    // The overlap along `u`, abandoned once it exceeds `best`: each of the four extremes only grows
    // as more vertices are seen, so a partial overlap above `best` stays above it.
    let mut overlap = |u: Vec3| {
        let Some(u) = u.try_normalize() else {
            return;
        };
        let (mut a0, mut a1, mut b0, mut b1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        let (na, nb) = (a.vertices.len(), b.vertices.len());
        for k in 0..na.max(nb) {
            if let Some(v) = a.vertices.get(k) {
                let x = v.dot(u);
                (a0, a1) = (a0.min(x), a1.max(x));
            }
            if let Some(v) = b.vertices.get(k) {
                let x = v.dot(u);
                (b0, b1) = (b0.min(x), b1.max(x));
            }
            if (a1 - b0).min(b1 - a0) > best {
                return;
            }
        }
        best = best.min((a1 - b0).min(b1 - a0));
    };
    for f in &a.faces {
        overlap(normal(a, f));
    }
    for f in &b.faces {
        overlap(normal(b, f));
    }
    let eb = b.edges();
    for (p1, q1) in a.edges() {
        for (p2, q2) in &eb {
            overlap((q1 - p1).cross(*q2 - *p2));
        }
    }
    best
}

fn as_mesh(g: &Geometry) -> Option<ConvexMesh> {
    match g {
        Geometry::Hull(h) => Some(h.clone()),
        Geometry::Obb(b) => convex_hull(&b.corners()).ok(),
        Geometry::Sphere(_) => None,
    }
}

fn check(urdf: &Path, name: &str, configurations: usize) {
    let out = common::preprocessed(urdf, name);
    let urdd = Urdd::open(&out).unwrap();
    let robot = urdd.robot().unwrap().robot;
    let kinematics = Kinematics::new(&robot);
    for t in [ShapeType::Obb, ShapeType::Hull, ShapeType::DecompHull] {
        let file = urdd.shapes(t).unwrap();
        let geometry: Vec<Geometry> = file
            .shapes
            .iter()
            .map(|s| urdd.geometry(&s.geometry).unwrap())
            .collect();
        let shapes: Vec<CollisionShape> = geometry
            .iter()
            .map(|g| CollisionShape::new(g).unwrap())
            .collect();
        let meshes: Vec<ConvexMesh> = geometry.iter().map(|g| as_mesh(g).unwrap()).collect();
        let (mut worst, mut worst_depth, mut separated, mut overlapping) = (0.0f64, 0.0f64, 0, 0);
        let mut state = 12345u64;
        let mut unit = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..configurations {
            let q: Vec<f64> = kinematics
                .dofs()
                .iter()
                .map(|d| d.lower + (d.upper - d.lower) * unit())
                .collect();
            let poses = kinematics.link_poses(&q);
            for i in 0..shapes.len() {
                for j in i + 1..shapes.len() {
                    let (li, lj) = (file.shapes[i].link_index, file.shapes[j].link_index);
                    if li == lj {
                        continue;
                    }
                    let (pi, pj) = (shapes[i].pose(&poses[li]), shapes[j].pose(&poses[lj]));
                    let d = signed_distance(&shapes[i], &pi, &shapes[j], &pj);
                    let (mi, mj) = (posed(&meshes[i], &poses[li]), posed(&meshes[j], &poses[lj]));
                    // Near contact, the reference decides which side it is on: a pair reported
                    // touching (0) may overlap by a millimetre (parry's EPA did that on b1).
                    let depth = if d > 1e-6 {
                        -1.0
                    } else {
                        exact_depth(&mi, &mj)
                    };
                    if depth < 0.0 {
                        // Some axis separates them: they are apart.
                        assert!(
                            d > 0.0,
                            "{name} {t}: pair {i}-{j} reported overlapping ({d}) but an axis separates it"
                        );
                        separated += 1;
                        worst = worst.max((d - brute_distance(&mi, &mj)).abs());
                    } else {
                        overlapping += 1;
                        worst_depth = worst_depth.max((d + depth).abs());
                    }
                }
            }
        }
        eprintln!(
            "{name} {t}: {separated} separated pairs, worst distance error {worst:.2e} m; {overlapping} overlapping pairs, worst depth error {worst_depth:.2e} m"
        );
        assert!(worst < 1e-7, "{name} {t}: worst distance error {worst}");
        assert!(
            worst_depth < 1e-9,
            "{name} {t}: worst depth error {worst_depth}"
        );
        assert!(separated > 0 && overlapping > 0);
    }
}

#[test]
fn demo_arm_distances_match_brute_force() {
    check(&common::demo_urdf(), "exact-demo", 25);
}

#[test]
fn ur5e_distances_match_brute_force() {
    let Some(robots) = common::robots_dir() else {
        return;
    };
    check(&robots.join("ur5e/ur5e.urdf"), "exact-ur5e", 25);
}

#[test]
fn b1_distances_match_brute_force() {
    let Some(robots) = common::robots_dir() else {
        return;
    };
    check(&robots.join("b1/b1.urdf"), "exact-b1", 10);
}
