//! Convex decomposition with parry's VHACD, tuned for robot links, with a fall-back to the single hull
//! when splitting does not pay.

use super::hull::{ConvexMesh, convex_hull, simplify_hull};
use crate::mesh::TriMesh;
use parry3d_f64::transformation::vhacd::{VHACD, VHACDParameters};
use serde::{Deserialize, Serialize};

/// Parameters of the convex decomposition.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DecompParams {
    /// Voxel grid resolution along the longest side.
    pub resolution: u32,
    /// Concavity at which VHACD stops splitting a part (relative to the link size).
    pub concavity: f64,
    /// Upper bound on the number of pieces per link.
    pub max_pieces: u32,
    /// The pieces must shrink the hull's volume by at least this fraction, else the link keeps one piece.
    pub min_volume_gain: f64,
    /// Upper bound on each piece hull's vertex count.
    pub max_piece_vertices: usize,
}

impl Default for DecompParams {
    fn default() -> Self {
        DecompParams {
            resolution: 40,
            concavity: 0.01,
            max_pieces: 8,
            min_volume_gain: 0.15,
            max_piece_vertices: 48,
        }
    }
}

/// The convex pieces of `mesh`, each simplified to at most `params.max_piece_vertices` vertices. When the
/// decomposition does not reduce the volume of `hull` by `params.min_volume_gain`, returns `[hull]`
/// simplified: a nearly convex link stays one piece.
pub fn convex_decomposition(
    mesh: &TriMesh,
    hull: &ConvexMesh,
    params: &DecompParams,
) -> Vec<ConvexMesh> {
    let single = || vec![simplify_hull(hull, params.max_piece_vertices)];
    let vhacd_params = VHACDParameters {
        resolution: params.resolution,
        concavity: params.concavity,
        max_convex_hulls: params.max_pieces,
        ..VHACDParameters::default()
    };
    let decomposition = VHACD::decompose(&vhacd_params, &mesh.vertices, &mesh.triangles, true);
    let mut pieces: Vec<ConvexMesh> = decomposition
        .compute_exact_convex_hulls(&mesh.vertices, &mesh.triangles)
        .into_iter()
        // A part that holds no surface (only interior voxels) has no exact hull: it adds nothing.
        .filter_map(|(points, _)| convex_hull(&points).ok())
        .collect();
    merge_down_to(&mut pieces, params.max_pieces.max(1) as usize);
    if pieces.len() <= 1 {
        return single();
    }
    let hull_volume = hull.volume();
    let pieces_volume: f64 = pieces.iter().map(ConvexMesh::volume).sum();
    if pieces_volume > hull_volume * (1.0 - params.min_volume_gain) {
        return single();
    }
    for p in &mut pieces {
        *p = simplify_hull(p, params.max_piece_vertices);
    }
    pieces
}

/// Merges pieces pairwise, cheapest first (the smallest growth of hull volume), until at most `max` remain.
/// VHACD's own limit is not a hard bound.
fn merge_down_to(pieces: &mut Vec<ConvexMesh>, max: usize) {
    let merged = |a: &ConvexMesh, b: &ConvexMesh| -> Option<(f64, ConvexMesh)> {
        let points: Vec<_> = a.vertices.iter().chain(&b.vertices).copied().collect();
        let hull = convex_hull(&points).ok()?;
        Some((hull.volume() - a.volume() - b.volume(), hull))
    };
    // cost[i][j] (i < j): growth of merging i and j.
    let mut cost: Vec<Vec<Option<(f64, ConvexMesh)>>> = (0..pieces.len())
        .map(|i| {
            (0..pieces.len())
                .map(|j| {
                    if i < j {
                        merged(&pieces[i], &pieces[j])
                    } else {
                        None
                    }
                })
                .collect()
        })
        .collect();
    while pieces.len() > max {
        let mut best: Option<(usize, usize, f64)> = None;
        for (i, row) in cost.iter().enumerate() {
            for (j, c) in row.iter().enumerate() {
                if let Some((g, _)) = c
                    && best.is_none_or(|(_, _, b)| *g < b)
                {
                    best = Some((i, j, *g));
                }
            }
        }
        let Some((i, j, _)) = best else { break };
        let Some((_, hull)) = cost[i][j].take() else {
            break;
        };
        pieces[i] = hull;
        pieces.remove(j);
        cost.remove(j);
        for row in &mut cost {
            row.remove(j);
        }
        for k in 0..pieces.len() {
            if k != i {
                let (lo, hi) = (k.min(i), k.max(i));
                cost[lo][hi] = merged(&pieces[lo], &pieces[hi]);
            }
        }
    }
}
