//! Paths in the kinematic tree: which joints lie between two links.

use super::Robot;

impl Robot {
    /// Joints on the tree path between links `a` and `b` (order unspecified).
    pub fn path_joints(&self, a: usize, b: usize) -> Vec<usize> {
        let up = |mut link: usize| {
            let mut chain = Vec::new();
            while let Some(j) = self.links[link].parent_joint {
                chain.push(j);
                link = self.joints[j].parent;
            }
            chain
        };
        let (mut pa, mut pb) = (up(a), up(b));
        // Drop the common part above the lowest common ancestor.
        while let (Some(x), Some(y)) = (pa.last(), pb.last()) {
            if x != y {
                break;
            }
            pa.pop();
            pb.pop();
        }
        pa.extend(pb);
        pa
    }

    /// Whether any joint between links `a` and `b` moves (actuated, including mimics).
    pub fn moves_between(&self, a: usize, b: usize) -> bool {
        self.path_joints(a, b)
            .iter()
            .any(|&j| self.joints[j].kind.is_actuated())
    }
}
