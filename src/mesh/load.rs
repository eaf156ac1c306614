//! Mesh files (STL, OBJ, COLLADA) through mesh-loader, plus the COLLADA `up_axis` it ignores.

use super::TriMesh;
use crate::math::Vec3;
use std::path::Path;

/// Loads every triangle of the mesh file at `path`, in metres, Z up. Errors are plain messages; the
/// caller names the URDF element.
pub fn load_mesh_file(path: &Path) -> Result<TriMesh, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read: {e}"))?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let loader = mesh_loader::Loader::default();
    // mesh-loader scales COLLADA vertices by <unit> but not node translations, and ignores <up_axis>:
    // it reads the file with the unit set to 1, and the unit and up axis are applied here.
    let collada = (ext == "dae").then(|| ColladaAsset::read(&bytes));
    let scene = match ext.as_str() {
        "stl" => loader.load_stl_from_slice(&bytes, path),
        "dae" => {
            let asset = collada.as_ref().and_then(|c| c.as_ref());
            loader.load_collada_from_slice(asset.map_or(&bytes[..], |a| &a.unit_free), path)
        }
        "obj" => loader.load_obj_from_slice(&bytes, path),
        other => {
            return Err(format!(
                "unsupported mesh format \".{other}\" (use STL, OBJ or DAE)"
            ));
        }
    }
    .map_err(|e| format!("cannot parse: {e}"))?;
    let (up, unit) = collada
        .flatten()
        .map_or((UpAxis::Z, 1.0), |a| (a.up, a.unit));
    let mut mesh = TriMesh::default();
    for m in &scene.meshes {
        let base = mesh.vertices.len() as u32;
        for v in &m.vertices {
            let p = Vec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]));
            if !crate::math::is_finite(p) {
                return Err("vertex with a NaN or infinite coordinate".into());
            }
            mesh.vertices.push(up.to_z_up(p) * unit);
        }
        let count = m.vertices.len() as u32;
        for f in &m.faces {
            if f.iter().any(|&i| i >= count) {
                return Err(format!("face index out of range ({} vertices)", count));
            }
            mesh.triangles.push([f[0] + base, f[1] + base, f[2] + base]);
        }
    }
    if mesh.triangles.is_empty() {
        return Err("the mesh has no triangles".into());
    }
    Ok(mesh)
}

/// COLLADA `<asset><up_axis>`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum UpAxis {
    X,
    Y,
    Z,
}

impl UpAxis {
    /// Rotates into Z-up the way assimp (and so ROS) does.
    fn to_z_up(self, p: Vec3) -> Vec3 {
        match self {
            UpAxis::Z => p,
            UpAxis::Y => Vec3::new(p.x, -p.z, p.y),
            UpAxis::X => Vec3::new(-p.y, p.x, p.z),
        }
    }
}

/// What mesh-loader does not handle of a COLLADA `<asset>`.
struct ColladaAsset {
    up: UpAxis,
    /// Metres per unit.
    unit: f64,
    /// The file with `<unit meter>` set to 1.
    unit_free: Vec<u8>,
}

impl ColladaAsset {
    /// Reads `<asset>`; `None` when the file is not readable XML (mesh-loader then reports the error).
    fn read(bytes: &[u8]) -> Option<ColladaAsset> {
        let text = std::str::from_utf8(bytes).ok()?;
        let doc = roxmltree::Document::parse(text).ok()?;
        let asset = doc
            .root_element()
            .children()
            .find(|c| c.tag_name().name() == "asset")?;
        let child = |name: &str| asset.children().find(|c| c.tag_name().name() == name);
        let up = match child("up_axis").and_then(|n| n.text()).map(str::trim) {
            Some("Y_UP") => UpAxis::Y,
            Some("X_UP") => UpAxis::X,
            _ => UpAxis::Z,
        };
        let meter = child("unit").and_then(|u| u.attribute_node("meter"));
        let unit = meter
            .and_then(|m| m.value().trim().parse::<f64>().ok())
            .filter(|u| u.is_finite() && *u > 0.0)
            .unwrap_or(1.0);
        let unit_free = match meter {
            Some(m) => {
                let r = m.range_value();
                [&bytes[..r.start], b"1", &bytes[r.end..]].concat()
            }
            None => bytes.to_vec(),
        };
        Some(ColladaAsset {
            up,
            unit,
            unit_free,
        })
    }
}
