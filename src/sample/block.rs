//! A block of consecutive samples placed together: configurations, link poses, and per shape type
//! the world centres of every shape's spheres and its placed bounding box, laid out so that one pair's
//! values over the block sit side by side.

use super::sets::PairSet;
use crate::collision::PlacedBox;
use crate::math::{Pose, Vec3};
use crate::rng::Rng;
use crate::robot::{Kinematics, random_configuration};

/// Samples per block: a chunk is placed a block at a time, and each pair then runs through the block
/// with its statistics in cache (the order of samples per pair, and so every result, is unchanged).
pub(super) const BLOCK: usize = 128;

/// Consecutive samples placed together: their configurations, link poses and, per set, the world
/// centres of every shape's enclosing and inscribed spheres (a shape's over the block side by side).
#[derive(Debug, Default, Clone)]
pub struct Block {
    /// Index of the block's first sample.
    pub(super) first: u64,
    /// Number of samples.
    pub(super) len: usize,
    /// Configurations, `len` rows of one value per DOF.
    pub(super) q: Vec<f64>,
    /// Link poses, `len` rows of one pose per link.
    pub(super) links: Vec<Pose>,
    /// Per set, enclosing-sphere centres: `len` per shape, shape after shape.
    pub(super) outer: Vec<Vec<Vec3>>,
    /// Per set, inscribed-sphere centres, laid out as `outer`.
    pub(super) inner: Vec<Vec<Vec3>>,
    /// Per set, the shapes' bounding boxes placed, laid out as `outer` (empty for spheres).
    pub(super) boxes: Vec<Vec<PlacedBox>>,
}

impl Block {
    /// Draws the next `len` samples from `rng` (the first numbered `first`) and places them.
    pub(super) fn place(
        &mut self,
        kinematics: &Kinematics,
        sets: &[PairSet],
        rng: &mut Rng,
        first: u64,
        len: usize,
    ) {
        let (dofs, links) = (kinematics.dofs().len(), kinematics.link_count());
        self.first = first;
        self.len = len;
        self.q.clear();
        self.links.clear();
        let (mut q, mut poses) = (Vec::with_capacity(dofs), Vec::with_capacity(links));
        for _ in 0..len {
            random_configuration(kinematics.dofs(), rng, &mut q);
            kinematics.link_poses_into(&q, &mut poses);
            self.q.extend_from_slice(&q);
            self.links.extend_from_slice(&poses);
        }
        self.outer.resize(sets.len(), Vec::new());
        self.inner.resize(sets.len(), Vec::new());
        self.boxes.resize(sets.len(), Vec::new());
        for (s, set) in sets.iter().enumerate() {
            let (outer, inner) = (&mut self.outer[s], &mut self.inner[s]);
            let boxes = &mut self.boxes[s];
            outer.clear();
            inner.clear();
            boxes.clear();
            for (shape, &link) in set.shapes.iter().zip(&set.links) {
                let poses = || (0..len).map(|kk| &self.links[kk * links + link]);
                outer.extend(poses().map(|pose| pose.transform_point(shape.outer_center)));
                inner.extend(poses().map(|pose| pose.transform_point(shape.inner_center)));
                if let Some(b) = &shape.bounding_box {
                    boxes.extend(poses().map(|pose| b.place(pose)));
                }
            }
        }
    }
}
