//! Wavefront OBJ: the `v` positions and `f` faces of every object and group, as Assimp reads them.
//!
//! Faces with more than three corners (quads, n-gons) become fans; indices may be negative (relative to
//! the vertices read so far); a corner's texture and normal indices (`v/vt/vn`) are not geometry and are
//! skipped, as are points (`p`), lines (`l`), materials and smoothing groups. A line ending in `\` goes
//! on in the next one.

use super::TriMesh;
use crate::math::Vec3;

/// Reads the triangles of an OBJ file's `text`; errors name the line.
pub fn read_obj(bytes: &[u8]) -> Result<TriMesh, String> {
    let text = String::from_utf8_lossy(bytes);
    let mut positions: Vec<Vec3> = Vec::new();
    let mut mesh = TriMesh::default();
    let mut corners: Vec<u32> = Vec::new();
    let mut pending = String::new();
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        if let Some(head) = raw.strip_suffix('\\') {
            pending.push_str(head);
            pending.push(' ');
            continue;
        }
        pending.push_str(raw);
        let line = std::mem::take(&mut pending);
        let line = line.split('#').next().unwrap_or("");
        let mut words = line.split_ascii_whitespace();
        let err = |what: String| format!("line {line_no}: {what}");
        match words.next() {
            Some("v") => {
                let mut c = [0.0; 3];
                for slot in &mut c {
                    let w = words
                        .next()
                        .ok_or_else(|| err("a vertex needs three coordinates".into()))?;
                    *slot = w
                        .parse::<f64>()
                        .map_err(|_| err(format!("`{w}` is not a number")))?;
                }
                positions.push(Vec3::from_array(c));
            }
            Some("f") => {
                corners.clear();
                for w in words {
                    let index = w.split('/').next().unwrap_or("");
                    let k: i64 = index
                        .parse()
                        .map_err(|_| err(format!("`{w}` is not a face corner")))?;
                    let n = positions.len() as i64;
                    let at = if k < 0 { n + k } else { k - 1 };
                    if k == 0 || !(0..n).contains(&at) {
                        return Err(err(format!(
                            "face index {k} is out of range ({n} vertices so far)"
                        )));
                    }
                    corners.push(at as u32);
                }
                if corners.len() < 3 {
                    return Err(err("a face needs three corners".into()));
                }
                for k in 1..corners.len() - 1 {
                    mesh.triangles
                        .push([corners[0], corners[k], corners[k + 1]]);
                }
            }
            _ => {}
        }
    }
    mesh.vertices = positions;
    Ok(mesh)
}
