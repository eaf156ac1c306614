//! URDF primitives as closed triangle meshes that circumscribe the true shape, so every shape built from
//! them contains the primitive (the curved ones over-approximate by well under 1%).

use super::TriMesh;
use crate::math::{Pose, Vec3};
use crate::robot::ShapeSource;
use std::f64::consts::PI;

/// Segments around a circle; the circumscribed polygon is 1/cos(pi/48) = +0.21% larger in radius.
const SEGMENTS: usize = 48;
/// Latitude rings per hemisphere of spheres and capsule caps.
const RINGS: usize = 12;

/// The triangle mesh of a primitive in its own frame (`None` for meshes, which are loaded from files).
pub fn tessellate(shape: &ShapeSource) -> Option<TriMesh> {
    Some(match *shape {
        ShapeSource::Box { size } => cuboid(size * 0.5),
        ShapeSource::Cylinder { radius, length } => {
            lathe(&[(radius, -length / 2.0), (radius, length / 2.0)], true)
        }
        ShapeSource::Sphere { radius } => lathe(&round_profile(radius, 0.0), false),
        ShapeSource::Capsule { radius, length } => lathe(&round_profile(radius, length), false),
        ShapeSource::Mesh { .. } => return None,
    })
}

/// The exact axis-aligned bounds of a primitive placed by `pose` (`None` for meshes): what the true
/// shape occupies, not its circumscribing mesh.
pub fn primitive_bounds(shape: &ShapeSource, pose: &Pose) -> Option<(Vec3, Vec3)> {
    let axis = pose.rotation * Vec3::Z;
    let extent = match *shape {
        ShapeSource::Box { size } => {
            let h = size * 0.5;
            let (x, y, z) = (
                pose.rotation * Vec3::X,
                pose.rotation * Vec3::Y,
                pose.rotation * Vec3::Z,
            );
            x.abs() * h.x + y.abs() * h.y + z.abs() * h.z
        }
        ShapeSource::Sphere { radius } => Vec3::splat(radius),
        ShapeSource::Cylinder { radius, length } => {
            let side = (Vec3::ONE - axis * axis).max(Vec3::ZERO);
            axis.abs() * (length / 2.0)
                + Vec3::new(side.x.sqrt(), side.y.sqrt(), side.z.sqrt()) * radius
        }
        ShapeSource::Capsule { radius, length } => {
            axis.abs() * (length / 2.0) + Vec3::splat(radius)
        }
        ShapeSource::Mesh { .. } => return None,
    };
    Some((pose.translation - extent, pose.translation + extent))
}

fn cuboid(h: Vec3) -> TriMesh {
    let vertices = (0..8)
        .map(|i| {
            Vec3::new(
                if i & 1 == 0 { -h.x } else { h.x },
                if i & 2 == 0 { -h.y } else { h.y },
                if i & 4 == 0 { -h.z } else { h.z },
            )
        })
        .collect();
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let triangles = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    TriMesh {
        vertices,
        triangles,
    }
}

/// The profile of a sphere (`length` 0) or capsule: lower hemisphere, then upper, each centred at
/// -+length/2; the two equator rings coincide for a sphere, so one is dropped.
fn round_profile(radius: f64, length: f64) -> Vec<(f64, f64)> {
    let mut profile = hemisphere_profile(radius, -length / 2.0, false);
    let upper = hemisphere_profile(radius, length / 2.0, true);
    let skip = usize::from(length == 0.0);
    profile.extend(upper.into_iter().skip(skip));
    profile
}

/// Rings of `(radius, z)` for a hemisphere centred at `z0`, upper (`up`) or lower, from the equator
/// outwards (lower: from the pole up to the equator). Radii are scaled so the polyhedron circumscribes
/// the sphere: each ring radius and pole height divided by cos(half the angular step).
fn hemisphere_profile(radius: f64, z0: f64, up: bool) -> Vec<(f64, f64)> {
    let step = PI / 2.0 / RINGS as f64;
    let r = radius / (step / 2.0).cos() / (PI / SEGMENTS as f64).cos();
    let mut rings: Vec<(f64, f64)> = (0..=RINGS)
        .map(|k| {
            let a = k as f64 * step;
            (
                r * a.cos(),
                z0 + if up { r * a.sin() } else { -r * a.sin() },
            )
        })
        .collect();
    if !up {
        rings.reverse();
    }
    rings
}

/// Revolves a profile of `(radius, z)` rings (increasing z) about the z axis. Rings of radius ~0 become
/// poles; `cap` closes the first and last rings with flat discs.
fn lathe(profile: &[(f64, f64)], cap: bool) -> TriMesh {
    let ring_scale = 1.0 / (PI / SEGMENTS as f64).cos();
    let mut mesh = TriMesh::default();
    let mut rings: Vec<Vec<u32>> = Vec::new();
    for &(radius, z) in profile {
        let start = mesh.vertices.len() as u32;
        if radius < 1e-12 {
            mesh.vertices.push(Vec3::new(0.0, 0.0, z));
            rings.push(vec![start; SEGMENTS]);
            continue;
        }
        for s in 0..SEGMENTS {
            let a = 2.0 * PI * s as f64 / SEGMENTS as f64;
            let r = radius * if cap { ring_scale } else { 1.0 };
            mesh.vertices.push(Vec3::new(r * a.cos(), r * a.sin(), z));
        }
        rings.push((start..start + SEGMENTS as u32).collect());
    }
    for w in rings.windows(2) {
        let (lo, hi) = (&w[0], &w[1]);
        for s in 0..SEGMENTS {
            let t = (s + 1) % SEGMENTS;
            for tri in [[lo[s], lo[t], hi[t]], [lo[s], hi[t], hi[s]]] {
                if tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2] {
                    mesh.triangles.push(tri);
                }
            }
        }
    }
    if cap {
        for (ring, z, outward_up) in [
            (&rings[0], profile[0].1, false),
            (&rings[rings.len() - 1], profile[profile.len() - 1].1, true),
        ] {
            let centre = mesh.vertices.len() as u32;
            mesh.vertices.push(Vec3::new(0.0, 0.0, z));
            for s in 0..SEGMENTS {
                let t = (s + 1) % SEGMENTS;
                mesh.triangles.push(if outward_up {
                    [centre, ring[s], ring[t]]
                } else {
                    [centre, ring[t], ring[s]]
                });
            }
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    fn contains_sphere_surface(mesh: &TriMesh, radius: f64) -> bool {
        // Every triangle's plane must be at least `radius` from the origin.
        mesh.triangles.iter().all(|t| {
            let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
            let n = (b - a).cross(c - a).normalize();
            n.dot(a) >= radius * (1.0 - 1e-12)
        })
    }

    #[test]
    fn sphere_circumscribes_and_is_outward() {
        let m = tessellate(&ShapeSource::Sphere { radius: 0.1 }).unwrap();
        assert!(contains_sphere_surface(&m, 0.1));
        let v = m.signed_volume();
        let exact = 4.0 / 3.0 * PI * 0.001;
        assert!(v > exact && v < exact * 1.02, "volume {v} vs {exact}");
    }

    #[test]
    fn cylinder_and_box_volumes() {
        let c = tessellate(&ShapeSource::Cylinder {
            radius: 0.05,
            length: 0.2,
        })
        .unwrap();
        let exact = PI * 0.05 * 0.05 * 0.2;
        let v = c.signed_volume();
        assert!(v > exact && v < exact * 1.01, "{v} vs {exact}");
        let b = tessellate(&ShapeSource::Box {
            size: Vec3::new(0.1, 0.2, 0.3),
        })
        .unwrap();
        assert!((b.signed_volume() - 0.006).abs() < 1e-12);
    }

    #[test]
    fn capsule_volume() {
        let c = tessellate(&ShapeSource::Capsule {
            radius: 0.05,
            length: 0.2,
        })
        .unwrap();
        let exact = PI * 0.05f64.powi(2) * 0.2 + 4.0 / 3.0 * PI * 0.05f64.powi(3);
        let v = c.signed_volume();
        assert!(v > exact && v < exact * 1.02, "{v} vs {exact}");
    }
}
