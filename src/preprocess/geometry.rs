//! Assembles each link's triangle geometry in the link frame from its URDF elements, loading every mesh
//! file once and rejecting empty or degenerate meshes with a message naming the URDF element.

use crate::collision::{ExactLink, ExactMesh};
use crate::error::{Error, Result};
use crate::mesh::{MeshFile, TriMesh, load_mesh_file, tessellate};
use crate::robot::{GeometryElement, Link, Robot, ShapeSource};
use crate::shapes::convex_hull;
use rayon::prelude::*;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Every mesh file the robot uses, loaded and checked, keyed by resolved path.
pub type MeshCache = BTreeMap<PathBuf, MeshFile>;

/// `<link name="x"> <collision> (line N)`, for messages.
fn element_label(link: &Link, line: u32) -> String {
    let tag = match link.geometry_source {
        crate::robot::GeometryOrigin::Visual => "visual",
        _ => "collision",
    };
    format!("<link name=\"{}\"> <{tag}> (line {line})", link.name)
}

/// Loads all mesh files of `robot` in parallel.
pub fn load_meshes(robot: &Robot, urdf: &Path) -> Result<MeshCache> {
    // First use of each file, for the error message.
    let mut first_use: BTreeMap<PathBuf, (String, String)> = BTreeMap::new();
    for link in &robot.links {
        for g in &link.geometry {
            if let ShapeSource::Mesh { uri, path, .. } = &g.shape {
                first_use
                    .entry(path.clone())
                    .or_insert_with(|| (element_label(link, g.line), uri.clone()));
            }
        }
    }
    first_use
        .into_par_iter()
        .map(|(path, (element, uri))| {
            let fail =
                |msg: String| Error::input(urdf, element.clone(), format!("mesh \"{uri}\": {msg}"));
            let file = load_mesh_file(&path).map_err(fail)?;
            // Rejects single-point, collinear and flat meshes: they enclose nothing.
            convex_hull(&file.mesh.vertices).map_err(|e| fail(format!("degenerate mesh: {e}")))?;
            Ok((path, file))
        })
        .collect()
}

/// Loads every mesh file of a preprocessed URDD's robot, from the URDF the preprocess stage recorded
/// (the original link geometry, as [`link_mesh`] assembles it).
pub fn load_urdd_meshes(urdd: &crate::urdd::Urdd, robot: &Robot) -> Result<MeshCache> {
    load_meshes(robot, &urdd_urdf(urdd)?)
}

/// The link's geometry as one triangle soup in the link frame (empty for links without geometry).
pub fn link_mesh(link: &Link, meshes: &MeshCache) -> TriMesh {
    let mut out = TriMesh::default();
    for g in &link.geometry {
        append_element(&mut out, g, meshes);
    }
    out
}

/// One geometry element's triangles in the link frame (a primitive as its circumscribing mesh).
pub fn element_mesh(element: &GeometryElement, meshes: &MeshCache) -> TriMesh {
    let mut out = TriMesh::default();
    append_element(&mut out, element, meshes);
    out
}

fn append_element(out: &mut TriMesh, g: &GeometryElement, meshes: &MeshCache) {
    match &g.shape {
        ShapeSource::Mesh { path, scale, .. } => {
            if let Some(m) = meshes.get(path) {
                out.append_transformed(&m.mesh, &g.origin, *scale);
            }
        }
        primitive => {
            if let Some(m) = tessellate(primitive) {
                out.append_transformed(&m, &g.origin, crate::math::Vec3::ONE);
            }
        }
    }
}

/// The notes of the mesh readers (a unit or up axis ignored as the consumers ignore it, a repaired
/// header), one line per mesh file, naming it as the URDF does.
pub fn mesh_notes(robot: &Robot, meshes: &MeshCache) -> Vec<String> {
    let mut uris: BTreeMap<&PathBuf, &str> = BTreeMap::new();
    for g in robot.links.iter().flat_map(|l| &l.geometry) {
        if let ShapeSource::Mesh { uri, path, .. } = &g.shape {
            uris.entry(path).or_insert(uri);
        }
    }
    meshes
        .iter()
        .flat_map(|(path, file)| {
            let uri = uris.get(path).copied().unwrap_or_default();
            file.notes
                .iter()
                .map(move |note| format!("mesh \"{uri}\" {note}"))
        })
        .collect()
}

/// Every link's exact collision geometry (the `mesh` type: meshes as loaded, primitives exact), `None`
/// for links without geometry. Each mesh file is indexed once per scale and shared by every element
/// that uses it (b1's twelve leg meshes are four files). A mesh parry cannot index is bad input naming
/// the element.
pub fn exact_links(
    robot: &Robot,
    meshes: &MeshCache,
    urdf: &Path,
) -> Result<Vec<Option<crate::collision::ExactLink>>> {
    type Key = (PathBuf, [u64; 3]);
    let key = |path: &Path, scale: &crate::math::Vec3| -> Key {
        (path.to_path_buf(), scale.to_array().map(f64::to_bits))
    };
    let keys: BTreeSet<Key> = robot
        .links
        .iter()
        .flat_map(|l| &l.geometry)
        .filter_map(|g| match &g.shape {
            ShapeSource::Mesh { path, scale, .. } => Some(key(path, scale)),
            _ => None,
        })
        .collect();
    let shared: BTreeMap<Key, std::result::Result<Option<ExactMesh>, String>> = keys
        .into_par_iter()
        .map(|(path, bits)| {
            let mut soup = TriMesh::default();
            if let Some(m) = meshes.get(&path) {
                let scale = crate::math::Vec3::from_array(bits.map(f64::from_bits));
                soup.append_transformed(&m.mesh, &crate::math::Pose::IDENTITY, scale);
            }
            let mesh = ExactMesh::new(soup);
            ((path, bits), mesh)
        })
        .collect();
    robot
        .links
        .par_iter()
        .map(|link| {
            ExactLink::new(&link.geometry, |g| match &g.shape {
                ShapeSource::Mesh { path, scale, .. } => {
                    shared.get(&key(path, scale)).cloned().unwrap_or(Ok(None))
                }
                _ => Ok(None),
            })
            .map_err(|e| Error::input(urdf, element_label(link, e.line), e.message))
        })
        .collect()
}

/// The URDF a preprocessed URDD was built from, as its preprocess record names it.
pub fn urdd_urdf(urdd: &crate::urdd::Urdd) -> Result<PathBuf> {
    Ok(urdd
        .stage(crate::urdd::PREPROCESS)?
        .inputs
        .iter()
        .find(|i| i.role == "urdf")
        .map_or_else(
            || urdd.dir().join("robot.urdf"),
            |i| Path::new(&i.path).into(),
        ))
}
