//! Wavefront OBJ for hull and piece meshes: written with round-trip float precision, read back exactly.

use crate::math::Vec3;
use crate::shapes::ConvexMesh;
use std::fmt::Write as _;

/// The OBJ text of a convex mesh (`v` lines, then 1-based `f` lines).
pub fn to_obj(mesh: &ConvexMesh) -> String {
    let mut s = String::with_capacity(mesh.vertices.len() * 48 + mesh.faces.len() * 24);
    for v in &mesh.vertices {
        // `{}` on f64 prints the shortest text that parses back to the same value.
        let _ = writeln!(s, "v {} {} {}", v.x, v.y, v.z);
    }
    for f in &mesh.faces {
        let _ = writeln!(s, "f {} {} {}", f[0] + 1, f[1] + 1, f[2] + 1);
    }
    s
}

/// Parses OBJ text written by [`to_obj`] (triangles only). The error names the line.
pub fn from_obj(text: &str) -> Result<ConvexMesh, String> {
    let mut mesh = ConvexMesh {
        vertices: Vec::new(),
        faces: Vec::new(),
    };
    for (n, line) in text.lines().enumerate() {
        let mut parts = line.split_whitespace();
        let bad = || format!("line {}: cannot read `{line}`", n + 1);
        match parts.next() {
            Some("v") => {
                let c: Vec<f64> = parts
                    .map(|p| p.parse().map_err(|_| bad()))
                    .collect::<Result<_, _>>()?;
                if c.len() != 3 || c.iter().any(|x| !x.is_finite()) {
                    return Err(bad());
                }
                mesh.vertices.push(Vec3::new(c[0], c[1], c[2]));
            }
            Some("f") => {
                let i: Vec<u32> = parts
                    .map(|p| p.parse().map_err(|_| bad()))
                    .collect::<Result<_, _>>()?;
                if i.len() != 3
                    || i.iter()
                        .any(|&k| k == 0 || k as usize > mesh.vertices.len())
                {
                    return Err(bad());
                }
                mesh.faces.push([i[0] - 1, i[1] - 1, i[2] - 1]);
            }
            _ => {}
        }
    }
    Ok(mesh)
}
