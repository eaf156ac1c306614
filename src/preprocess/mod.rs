//! The `preprocess` stage: URDF + meshes in, the six shape representations of every link out, written
//! into the URDD's `preprocess/` folder. Reruns with unchanged inputs and parameters are no-ops.

mod geometry;

pub use geometry::{
    MeshCache, element_mesh, exact_links, link_mesh, load_meshes, load_urdd_meshes, mesh_notes,
    urdd_urdf,
};

use crate::error::{Error, Result};
use crate::progress::Progress;
use crate::robot::{Kinematics, PackagePaths, Robot, ShapeSource, UrdfOptions, load_urdf};
use crate::shapes::{Geometry, LinkShapes, PerType, ShapeParams, ShapeType, build_link_shapes};
use crate::urdd::stage_key;
use crate::urdd::{
    FORMAT_VERSION, GeometryRecord, InputFile, LinkRecord, PREPROCESS, RobotRecord, ShapeFile,
    ShapeRecord, StageDir, StageRecord, Urdd, json_bytes, sha256_hex, shape_file_name, to_obj,
};
use rayon::prelude::*;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// What to preprocess and how.
#[derive(Debug, Clone)]
pub struct PreprocessOptions {
    /// The URDF.
    pub urdf: PathBuf,
    /// The URDD directory to write.
    pub out: PathBuf,
    /// `package://` and `model://` resolution.
    pub packages: PackagePaths,
    /// Build shapes for links without `<collision>` from their `<visual>` (no consumer checks those).
    pub visual_fallback: bool,
    /// Shape construction parameters.
    pub params: ShapeParams,
    /// Rebuild even when up to date.
    pub force: bool,
}

/// What a preprocess run did (printed as `--json`).
#[derive(Debug, Clone, Serialize)]
pub struct PreprocessReport {
    /// Robot name.
    pub robot: String,
    /// The URDD directory.
    pub urdd: PathBuf,
    /// True when nothing was done because the output was up to date.
    pub up_to_date: bool,
    /// Number of links.
    pub links: usize,
    /// Links that have geometry (and so shapes).
    pub links_with_geometry: usize,
    /// Sampled degrees of freedom.
    pub dofs: usize,
    /// Shapes per type.
    pub shapes: PerType<usize>,
    /// Leniencies applied to the input.
    pub warnings: Vec<String>,
}

/// Runs the preprocess stage.
pub fn preprocess(opts: &PreprocessOptions, progress: &dyn Progress) -> Result<PreprocessReport> {
    // Absolute, so the URDD's record of the URDF and its meshes reads back from any folder.
    let urdf = std::path::absolute(&opts.urdf).map_err(|e| Error::io(&opts.urdf, e))?;
    let robot = load_urdf(
        &urdf,
        &UrdfOptions {
            packages: opts.packages.clone(),
            visual_fallback: opts.visual_fallback,
        },
    )?;
    let inputs = hash_inputs(&robot, &urdf)?;
    let mut parameters = crate::urdd::parameters(PREPROCESS, &opts.params)?;
    if let Some(map) = parameters.as_object_mut() {
        map.insert("visual_fallback".into(), opts.visual_fallback.into());
    }
    let hashes: Vec<&str> = inputs.iter().map(|i| i.sha256.as_str()).collect();
    let key = stage_key(
        PREPROCESS,
        serde_json::json!({ "inputs": hashes, "parameters": parameters }),
    );
    let _lock = Urdd::lock_for_writing(&opts.out, progress)?;
    let mut urdd = Urdd::open_or_new(&opts.out, &robot.name)?;
    let kinematics = Kinematics::new(&robot);

    if !opts.force && urdd.is_up_to_date(PREPROCESS, &key) {
        let shapes = urdd.stage_summary(PREPROCESS, Some("shapes"))?;
        return Ok(report(&robot, &opts.out, true, &kinematics, shapes));
    }

    let rerun = urdd.rerun_note(PREPROCESS, &key);
    let meshes = geometry::load_meshes(&robot, &urdf)?;
    let notes = geometry::mesh_notes(&robot, &meshes);
    let with_geometry: Vec<usize> = (0..robot.links.len())
        .filter(|&i| !robot.links[i].geometry.is_empty())
        .collect();
    progress.start("building shapes", with_geometry.len() as u64);
    let built: Vec<(usize, LinkShapes)> = with_geometry
        .par_iter()
        .map(|&i| {
            let link = &robot.links[i];
            let mesh = geometry::link_mesh(link, &meshes);
            let shapes = build_link_shapes(&mesh, &opts.params).map_err(|e| {
                Error::input(
                    &urdf,
                    format!("<link name=\"{}\">", link.name),
                    format!("its geometry is degenerate: {e}"),
                )
            })?;
            progress.advance(1);
            Ok((i, shapes))
        })
        .collect::<Result<_>>()?;
    progress.finish();

    let stage = StageDir::create(&opts.out.join(PREPROCESS))?;
    let mut outputs = Vec::new();
    let mut put = |name: String, bytes: Vec<u8>| -> Result<()> {
        stage.write(&name, &bytes)?;
        outputs.push(name);
        Ok(())
    };
    let adjacent = robot
        .adjacent_pairs()
        .into_iter()
        .map(|(a, b)| [robot.links[a].name.clone(), robot.links[b].name.clone()])
        .collect();
    let record = RobotRecord {
        format_version: FORMAT_VERSION,
        robot: robot.clone(),
        dofs: kinematics.dofs().to_vec(),
        adjacent,
    };
    put("robot.json".into(), json_bytes("robot.json", &record)?)?;
    let links: Vec<LinkRecord> = built
        .iter()
        .map(|(i, s)| LinkRecord {
            link: robot.links[*i].name.clone(),
            link_index: *i,
            geometry: robot.links[*i].geometry_source,
            fit: s.fit.clone(),
        })
        .collect();
    put("links.json".into(), json_bytes("links.json", &links)?)?;
    for t in ShapeType::ALL {
        let mut shapes = Vec::new();
        for (link_index, link_shapes) in &built {
            let link = &robot.links[*link_index];
            for (piece, geometry) in link_shapes.shapes[t].iter().enumerate() {
                let geometry = match geometry {
                    Geometry::Sphere(s) => GeometryRecord::Sphere {
                        center: s.center,
                        radius: s.radius,
                    },
                    Geometry::Obb(b) => GeometryRecord::Obb {
                        center: b.center,
                        rotation: b.rotation,
                        half_extents: b.half_extents,
                    },
                    Geometry::Hull(h) => {
                        let mesh = mesh_file_name(*link_index, &link.name, t, piece);
                        put(mesh.clone(), to_obj(h).into_bytes())?;
                        GeometryRecord::Hull {
                            mesh,
                            vertices: h.vertices.len(),
                            faces: h.faces.len(),
                            volume: h.volume(),
                        }
                    }
                };
                shapes.push(ShapeRecord {
                    index: shapes.len(),
                    link: link.name.clone(),
                    link_index: *link_index,
                    piece,
                    geometry,
                });
            }
        }
        let file = shape_file_name(t);
        let bytes = json_bytes(
            &file,
            &ShapeFile {
                format_version: FORMAT_VERSION,
                shape_type: t,
                shapes,
            },
        )?;
        put(file, bytes)?;
    }
    let counts = PerType::from_fn(|t| built.iter().map(|(_, s)| s.shapes[t].len()).sum::<usize>());
    let mut out = report(&robot, &opts.out, false, &kinematics, counts);
    out.warnings.extend(rerun.into_iter().chain(notes));
    stage.commit()?;
    let summary = serde_json::json!({
        "links": out.links,
        "links_with_geometry": out.links_with_geometry,
        "dofs": out.dofs,
        "shapes": out.shapes,
    });
    urdd.record_stage(
        PREPROCESS,
        &robot.name,
        StageRecord {
            key,
            tool_version: crate::VERSION.into(),
            inputs,
            parameters,
            folder: PREPROCESS.into(),
            outputs,
            stamps: Default::default(),
            summary,
            depends_on: Default::default(),
        },
    )?;
    Ok(out)
}

fn report(
    robot: &Robot,
    dir: &Path,
    up_to_date: bool,
    kinematics: &Kinematics,
    shapes: PerType<usize>,
) -> PreprocessReport {
    PreprocessReport {
        robot: robot.name.clone(),
        urdd: dir.to_path_buf(),
        up_to_date,
        links: robot.links.len(),
        links_with_geometry: robot
            .links
            .iter()
            .filter(|l| !l.geometry.is_empty())
            .count(),
        dofs: kinematics.dofs().len(),
        shapes,
        warnings: robot.warnings.clone(),
    }
}

/// `meshes/003-forearm.hull.obj` or `meshes/003-forearm.piece02.obj`.
fn mesh_file_name(link_index: usize, link: &str, t: ShapeType, piece: usize) -> String {
    let safe: String = link
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    match t.scope() {
        crate::shapes::Scope::Link => format!("meshes/{link_index:03}-{safe}.hull.obj"),
        crate::shapes::Scope::Pieces => {
            format!("meshes/{link_index:03}-{safe}.piece{piece:02}.obj")
        }
    }
}

/// Hashes the URDF and every mesh file it uses.
fn hash_inputs(robot: &Robot, urdf: &Path) -> Result<Vec<InputFile>> {
    let read = |path: &Path| {
        std::fs::read(path).map_err(|e| Error::input(path, "file", format!("cannot read: {e}")))
    };
    let mut inputs = vec![InputFile {
        role: "urdf".into(),
        path: urdf.display().to_string(),
        sha256: sha256_hex(&read(urdf)?),
    }];
    let mut paths: Vec<&PathBuf> = robot
        .links
        .iter()
        .flat_map(|l| &l.geometry)
        .filter_map(|g| match &g.shape {
            ShapeSource::Mesh { path, .. } => Some(path),
            _ => None,
        })
        .collect();
    paths.sort();
    paths.dedup();
    let hashed: Vec<InputFile> = paths
        .par_iter()
        .map(|p| {
            Ok(InputFile {
                role: "mesh".into(),
                path: p.display().to_string(),
                sha256: sha256_hex(&read(p)?),
            })
        })
        .collect::<Result<_>>()?;
    inputs.extend(hashed);
    Ok(inputs)
}
