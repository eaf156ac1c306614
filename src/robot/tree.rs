//! Paths in the kinematic tree: which joints lie between two links, and the links in tree order.

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

    /// Every link index in kinematic order: depth first from the root, a link's children in the order
    /// of their joints in the document (so a chain reads base to tip and each branch stays together).
    pub fn kinematic_order(&self) -> Vec<usize> {
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); self.links.len()];
        for j in &self.joints {
            children[j.parent].push(j.child);
        }
        let mut order = Vec::with_capacity(self.links.len());
        let mut stack = vec![self.root];
        while let Some(link) = stack.pop() {
            order.push(link);
            stack.extend(children[link].iter().rev());
        }
        order
    }

    /// The link names in [`Robot::kinematic_order`]: the axes of a matrix picture.
    pub fn kinematic_link_names(&self) -> Vec<String> {
        self.kinematic_order()
            .into_iter()
            .map(|i| self.links[i].name.clone())
            .collect()
    }

    /// Whether any joint between links `a` and `b` moves (actuated, including mimics).
    pub fn moves_between(&self, a: usize, b: usize) -> bool {
        self.path_joints(a, b)
            .iter()
            .any(|&j| self.joints[j].kind.is_actuated())
    }
}
