//! Mesh files (STL, OBJ, COLLADA) read as the consumers' Assimp reads them: triangles only, in the
//! file's own units, no axis conversion.

use super::TriMesh;
use super::collada::read_collada;
use super::obj::read_obj;
use super::stl::read_stl;
use std::path::Path;

/// A mesh file's triangles and notes on what the reader ignored or repaired.
#[derive(Debug, Clone, Default)]
pub struct MeshFile {
    /// The triangles, only the vertices they use.
    pub mesh: TriMesh,
    /// What the reader ignored as the consumers do, or repaired (one sentence each).
    pub notes: Vec<String>,
}

/// Loads every triangle of the mesh file at `path`. Errors are plain messages; the caller names the URDF
/// element.
pub fn load_mesh_file(path: &Path) -> Result<MeshFile, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read: {e}"))?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or_default();
    read_mesh(&bytes, ext)
}

/// Reads the triangles of a mesh file's `bytes`; `ext` (`stl`, `obj`, `dae`, any case) names the format.
pub fn read_mesh(bytes: &[u8], ext: &str) -> Result<MeshFile, String> {
    let ext = ext.to_ascii_lowercase();
    let mut notes = Vec::new();
    let mut mesh = match ext.as_str() {
        "stl" => read_stl(bytes, &mut notes)?,
        "dae" => {
            let c = read_collada(bytes)?;
            notes = c.notes;
            c.mesh
        }
        "obj" => read_obj(bytes)?,
        other => {
            return Err(format!(
                "unsupported mesh format \".{other}\" (use STL, OBJ or DAE)"
            ));
        }
    };
    if mesh.vertices.iter().any(|v| !crate::math::is_finite(*v)) {
        return Err("vertex with a NaN or infinite coordinate".into());
    }
    let limit = crate::robot::MAX_MAGNITUDE;
    if let Some(v) = mesh.vertices.iter().find(|v| v.abs().max_element() > limit) {
        return Err(format!(
            "vertex {v:?} lies beyond ±{limit:e} (file units; scm cannot compute with it)"
        ));
    }
    mesh.compact();
    if mesh.triangles.is_empty() {
        return Err("the mesh has no triangles".into());
    }
    Ok(MeshFile { mesh, notes })
}
