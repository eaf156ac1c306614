//! The ground truth of table 3: the robot's original link geometry as triangle meshes, checked exactly
//! against each other at a configuration.
//!
//! What counts: two links collide when their exact geometry overlaps as solid bodies
//! ([`ExactLink::overlap`]: surfaces meet, or one lies wholly inside the other).
//!
//! Which link pairs count: pairs of different links with geometry that are not adjacent and whose
//! meshes do not collide at the home configuration. Adjacent links' meshes touch or overlap at their
//! joint, and links whose meshes already overlap at home are built into each other (a motor housing
//! inside a trunk box); these are design contacts, not self-collisions, which is why MoveIt's rules
//! skip them too (`Adjacent`, `Default`). Counting them would make nearly every configuration a
//! collision (on B1, every one).

use crate::collision::ExactLink;
use crate::error::Result;
use crate::math::Pose;
use crate::preprocess::{exact_links, load_meshes, urdd_urdf};
use crate::robot::Kinematics;
use crate::urdd::Urdd;

/// The exact geometry of every link with geometry and the link pairs the ground truth checks.
pub struct MeshTruth {
    links: Vec<Option<ExactLink>>,
    /// Pairs `(a, b)`, `a < b`, of non-adjacent links that both have geometry and whose meshes do not
    /// collide at home.
    pairs: Vec<(usize, usize)>,
    /// Non-adjacent pairs whose meshes collide at home (left out).
    at_home: Vec<(usize, usize)>,
}

impl std::fmt::Debug for MeshTruth {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeshTruth")
            .field("pairs", &self.pairs.len())
            .finish_non_exhaustive()
    }
}

impl MeshTruth {
    /// Loads the original link geometry the way the consumers do (the `mesh` type: mesh files as
    /// recorded in `robot.json`, primitives exact).
    pub fn load(urdd: &Urdd) -> Result<MeshTruth> {
        let record = urdd.robot()?;
        let robot = &record.robot;
        let urdf = urdd_urdf(urdd)?;
        let links = exact_links(robot, &load_meshes(robot, &urdf)?, &urdf)?;
        let adjacent: Vec<(usize, usize)> = robot.adjacent_pairs();
        let n = links.len();
        let pairs = (0..n)
            .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
            .filter(|&(a, b)| links[a].is_some() && links[b].is_some())
            .filter(|&(a, b)| !adjacent.contains(&(a, b)) && !adjacent.contains(&(b, a)))
            .collect();
        let mut truth = MeshTruth {
            links,
            pairs,
            at_home: Vec::new(),
        };
        let kinematics = Kinematics::new(robot);
        let home = kinematics.link_poses(&kinematics.home());
        truth.at_home = truth.colliding(&home);
        truth.pairs.retain(|p| !truth.at_home.contains(p));
        Ok(truth)
    }

    /// Non-adjacent link pairs left out because their meshes collide at the home configuration.
    pub fn at_home(&self) -> &[(usize, usize)] {
        &self.at_home
    }

    /// The link pairs the ground truth checks.
    pub fn pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }

    /// The checked link pairs whose meshes collide (as solids, [`ExactLink::overlap`]) with link poses
    /// `poses`, in order.
    pub fn colliding(&self, poses: &[Pose]) -> Vec<(usize, usize)> {
        self.pairs
            .iter()
            .copied()
            .filter(|&(a, b)| match (&self.links[a], &self.links[b]) {
                (Some(la), Some(lb)) => la.overlap(&poses[a], lb, &poses[b]),
                _ => false,
            })
            .collect()
    }
}
