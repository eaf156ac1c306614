//! STL: binary or ASCII decided the way robust readers (Assimp among them) decide it.
//!
//! A file of exactly 84 + 50 * N bytes, N being the triangle count at offset 80, is binary whatever its
//! 80-byte header says: many exporters write `solid NAME` into binary headers. Anything else that starts
//! with `solid` is read as ASCII (mesh-loader, which tolerates irregular whitespace and falls back to
//! binary when the text is not STL); the rest is binary with the triangle count taken from the size.

use super::TriMesh;
use crate::math::Vec3;

const HEADER: usize = 80;
const TRIANGLES: usize = HEADER + 4;
const TRIANGLE: usize = 50;

/// Reads the triangles of an STL file's `bytes`; notes say what was repaired.
pub fn read_stl(bytes: &[u8], notes: &mut Vec<String>) -> Result<TriMesh, String> {
    if let Some(count) = exact_binary_count(bytes) {
        return Ok(read_binary(&bytes[TRIANGLES..], count));
    }
    if bytes.len() >= TRIANGLES && !starts_with_solid(bytes) {
        let declared = declared_count(bytes);
        let held = (bytes.len() - TRIANGLES) / TRIANGLE;
        if declared != held {
            notes.push(format!(
                "binary STL header says {declared} triangles, the file holds {held}: {held} read"
            ));
        }
    }
    let scene = mesh_loader::Loader::default()
        .load_stl_from_slice(bytes, "mesh.stl")
        .map_err(|e| format!("cannot parse: {e}"))?;
    from_scene(&scene)
}

/// The header's triangle count.
fn declared_count(bytes: &[u8]) -> usize {
    let mut count = [0u8; 4];
    count.copy_from_slice(&bytes[HEADER..TRIANGLES]);
    u32::from_le_bytes(count) as usize
}

/// The triangle count when the size is exactly that of a binary STL with the header's count.
fn exact_binary_count(bytes: &[u8]) -> Option<usize> {
    if bytes.len() < TRIANGLES {
        return None;
    }
    let count = declared_count(bytes);
    (count.checked_mul(TRIANGLE)?.checked_add(TRIANGLES)? == bytes.len()).then_some(count)
}

fn starts_with_solid(bytes: &[u8]) -> bool {
    let text = bytes.trim_ascii_start();
    text.len() >= 5 && text[..5].eq_ignore_ascii_case(b"solid")
}

/// `count` binary triangle records: normal, three vertices (little-endian f32), attribute bytes.
fn read_binary(records: &[u8], count: usize) -> TriMesh {
    let f = |b: &[u8]| {
        let mut word = [0u8; 4];
        word.copy_from_slice(b);
        f64::from(f32::from_le_bytes(word))
    };
    let mut mesh = TriMesh {
        vertices: Vec::with_capacity(count * 3),
        triangles: Vec::with_capacity(count),
    };
    for record in records.chunks_exact(TRIANGLE).take(count) {
        let base = mesh.vertices.len() as u32;
        for corner in 0..3 {
            let at = 12 + corner * 12;
            mesh.vertices.push(Vec3::new(
                f(&record[at..at + 4]),
                f(&record[at + 4..at + 8]),
                f(&record[at + 8..at + 12]),
            ));
        }
        mesh.triangles.push([base, base + 1, base + 2]);
    }
    mesh
}

/// The triangles of a mesh-loader scene, its meshes appended in order.
fn from_scene(scene: &mesh_loader::Scene) -> Result<TriMesh, String> {
    let mut mesh = TriMesh::default();
    for m in &scene.meshes {
        let base = mesh.vertices.len() as u32;
        mesh.vertices.extend(
            m.vertices
                .iter()
                .map(|v| Vec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))),
        );
        let count = m.vertices.len() as u32;
        for f in &m.faces {
            if f.iter().any(|&i| i >= count) {
                return Err(format!("face index out of range ({count} vertices)"));
            }
            mesh.triangles.push([f[0] + base, f[1] + base, f[2] + base]);
        }
    }
    Ok(mesh)
}
