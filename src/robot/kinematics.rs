//! Forward kinematics: link poses in the root frame for a joint configuration.

use super::{JointKind, Robot};
use crate::math::{Pose, Rotation, Vec3};
use crate::rng::Rng;
use serde::{Deserialize, Serialize};

/// One value per degree of freedom, in [`Kinematics::dofs`] order.
pub type Configuration = Vec<f64>;

/// A sampled degree of freedom: an actuated joint that is not a mimic.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Dof {
    /// Joint index in the robot.
    pub joint: usize,
    /// Joint name.
    pub name: String,
    /// Lower bound (continuous joints: -pi).
    pub lower: f64,
    /// Upper bound (continuous joints: +pi).
    pub upper: f64,
}

impl Dof {
    /// The home value: 0, or the middle of the limits where 0 is outside them.
    pub fn home(&self) -> f64 {
        if (self.lower..=self.upper).contains(&0.0) {
            0.0
        } else {
            0.5 * (self.lower + self.upper)
        }
    }

    /// The width of the range (continuous joints: a full turn).
    pub fn span(&self) -> f64 {
        self.upper - self.lower
    }
}

/// A configuration drawn uniformly within the DOF limits from `rng`, one draw per DOF in order,
/// written into `q`: the one way samples, benchmarks and the viewer draw configurations.
pub fn random_configuration(dofs: &[Dof], rng: &mut Rng, q: &mut Vec<f64>) {
    q.clear();
    q.extend(dofs.iter().map(|d| rng.range(d.lower, d.upper)));
}

/// A moving joint on the path between two links, placed at some configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathJoint {
    /// A point on the joint's axis.
    pub point: Vec3,
    /// The unit axis.
    pub axis: Vec3,
    /// Whether the joint slides along its axis (prismatic) rather than turning about it.
    pub prismatic: bool,
    /// The DOF that drives it (its own, or its leader's for a mimic joint).
    pub dof: usize,
    /// How far the joint moves per unit of its DOF: 1, or a mimic joint's |multiplier|.
    pub rate: f64,
}

#[derive(Debug, Clone)]
struct Step {
    /// The joint's index in the robot.
    joint: usize,
    kind: JointKind,
    parent: usize,
    child: usize,
    origin: Pose,
    axis: Vec3,
    /// How the joint's value is obtained.
    value: Value,
}

impl Step {
    /// The DOF that drives the joint (a mimic joint's leader's), if it moves.
    fn dof(&self) -> Option<usize> {
        match self.value {
            Value::Dof(d) => Some(d),
            Value::Mimic { dof, .. } => dof,
            Value::Fixed => None,
        }
    }

    /// The joint's value at configuration `q` (0 for joints that do not move).
    fn value(&self, q: &[f64]) -> f64 {
        match self.value {
            Value::Fixed => 0.0,
            Value::Dof(d) => q[d],
            Value::Mimic {
                dof,
                multiplier,
                offset,
            } => dof.map_or(0.0, |d| q[d]) * multiplier + offset,
        }
    }

    /// The child link's pose in the parent link's frame at configuration `q`.
    fn transform(&self, q: &[f64]) -> Pose {
        let value = self.value(q);
        let motion = match self.kind {
            JointKind::Revolute | JointKind::Continuous => {
                Pose::from_rotation(Rotation::from_axis_angle(self.axis, value))
            }
            JointKind::Prismatic => Pose::from_translation(self.axis * value),
            JointKind::Fixed | JointKind::Floating | JointKind::Planar => Pose::IDENTITY,
        };
        self.origin * motion
    }
}

#[derive(Debug, Clone, Copy)]
enum Value {
    Fixed,
    Dof(usize),
    Mimic {
        dof: Option<usize>,
        multiplier: f64,
        offset: f64,
    },
}

/// Precomputed forward kinematics of a robot: joints in parent-before-child order and the DOF mapping.
#[derive(Debug, Clone)]
pub struct Kinematics {
    steps: Vec<Step>,
    /// Per link, the steps from the root to it, in order.
    chains: Vec<Vec<usize>>,
    dofs: Vec<Dof>,
    root: usize,
    link_count: usize,
}

impl Kinematics {
    /// Prepares forward kinematics for `robot` (which [`super::load_urdf`] has validated to be a tree).
    pub fn new(robot: &Robot) -> Self {
        let mut dof_of_joint = vec![None; robot.joints.len()];
        let mut dofs = Vec::new();
        for (i, j) in robot.joints.iter().enumerate() {
            if j.kind.is_actuated() && j.mimic.is_none() {
                let (lower, upper) = match (j.kind, j.limits) {
                    (JointKind::Continuous, _) | (_, None) => {
                        (-std::f64::consts::PI, std::f64::consts::PI)
                    }
                    (_, Some(l)) => (l.lower, l.upper),
                };
                dof_of_joint[i] = Some(dofs.len());
                dofs.push(Dof {
                    joint: i,
                    name: j.name.clone(),
                    lower,
                    upper,
                });
            }
        }
        // Breadth-first from the root so every parent pose is known before its children.
        let mut steps = Vec::with_capacity(robot.joints.len());
        let mut frontier = vec![robot.root];
        while let Some(link) = frontier.pop() {
            for (i, j) in robot
                .joints
                .iter()
                .enumerate()
                .filter(|(_, j)| j.parent == link)
            {
                let value = match (j.kind.is_actuated(), j.mimic) {
                    (false, _) => Value::Fixed,
                    (true, None) => Value::Dof(dof_of_joint[i].unwrap_or_default()),
                    (true, Some(m)) => Value::Mimic {
                        dof: dof_of_joint[m.joint],
                        multiplier: m.multiplier,
                        offset: m.offset,
                    },
                };
                steps.push(Step {
                    joint: i,
                    kind: j.kind,
                    parent: j.parent,
                    child: j.child,
                    origin: j.origin,
                    axis: j.axis,
                    value,
                });
                frontier.push(j.child);
            }
        }
        let mut chains: Vec<Vec<usize>> = vec![Vec::new(); robot.links.len()];
        for (i, step) in steps.iter().enumerate() {
            let mut chain = chains[step.parent].clone();
            chain.push(i);
            chains[step.child] = chain;
        }
        Kinematics {
            steps,
            chains,
            dofs,
            root: robot.root,
            link_count: robot.links.len(),
        }
    }

    /// The sampled degrees of freedom.
    pub fn dofs(&self) -> &[Dof] {
        &self.dofs
    }

    /// The home configuration.
    pub fn home(&self) -> Configuration {
        self.dofs.iter().map(Dof::home).collect()
    }

    /// The number of links.
    pub fn link_count(&self) -> usize {
        self.link_count
    }

    /// Pose of every link in the root frame at configuration `q`, written into `poses` (indexed by link).
    pub fn link_poses_into(&self, q: &[f64], poses: &mut Vec<Pose>) {
        poses.clear();
        poses.resize(self.link_count, Pose::IDENTITY);
        poses[self.root] = Pose::IDENTITY;
        for s in &self.steps {
            poses[s.child] = poses[s.parent] * s.transform(q);
        }
    }

    /// Pose of one link in the root frame at configuration `q`: only the joints on its chain.
    pub fn link_pose(&self, q: &[f64], link: usize) -> Pose {
        self.chains[link]
            .iter()
            .fold(Pose::IDENTITY, |pose, &i| pose * self.steps[i].transform(q))
    }

    /// Poses of links `a` and `b` at configuration `q` in the frame of their nearest common ancestor:
    /// the same relative pose as [`Kinematics::link_pose`] gives both, without the joints they share.
    pub fn pair_poses(&self, q: &[f64], a: usize, b: usize) -> (Pose, Pose) {
        let (ca, cb) = (&self.chains[a], &self.chains[b]);
        let common = ca.iter().zip(cb).take_while(|(x, y)| x == y).count();
        let pose = |chain: &[usize]| {
            chain
                .iter()
                .fold(Pose::IDENTITY, |pose, &i| pose * self.steps[i].transform(q))
        };
        (pose(&ca[common..]), pose(&cb[common..]))
    }

    /// The chains of links `a` and `b` below their nearest common ancestor, ready to place the pair at
    /// configurations that differ from one base in a single DOF (see [`PairChains`]).
    pub fn pair_chains(&self, a: usize, b: usize) -> PairChains<'_> {
        let (ca, cb) = (&self.chains[a], &self.chains[b]);
        let common = ca.iter().zip(cb).take_while(|(x, y)| x == y).count();
        PairChains {
            kinematics: self,
            sides: [&ca[common..], &cb[common..]].map(|chain| ChainSide {
                steps: chain.to_vec(),
                transforms: Vec::new(),
                prefix: Vec::new(),
            }),
        }
    }

    /// The DOF that drives joint `joint` (its own, or its leader's for a mimic joint), if it moves.
    pub fn joint_dof(&self, joint: usize) -> Option<usize> {
        self.steps
            .iter()
            .find(|s| s.joint == joint)
            .and_then(Step::dof)
    }

    /// The DOFs that drive a joint on the tree path between links `a` and `b` (a mimic joint through its
    /// leader), ascending: the only ones that can change the pair's relative pose.
    pub fn path_dofs(&self, a: usize, b: usize) -> Vec<usize> {
        let (ca, cb) = (&self.chains[a], &self.chains[b]);
        let common = ca.iter().zip(cb).take_while(|(x, y)| x == y).count();
        let mut dofs: Vec<usize> = ca[common..]
            .iter()
            .chain(&cb[common..])
            .filter_map(|&i| self.steps[i].dof())
            .collect();
        dofs.sort_unstable();
        dofs.dedup();
        dofs
    }

    /// Poses of links `a` and `b` at configuration `q` in the frame of their nearest common ancestor
    /// (as [`Kinematics::pair_poses`]), writing into `side_a` and `side_b` the moving joints of each
    /// side's chain, from the ancestor down, placed at `q` in that frame.
    pub fn pair_path(
        &self,
        q: &[f64],
        a: usize,
        b: usize,
        side_a: &mut Vec<PathJoint>,
        side_b: &mut Vec<PathJoint>,
    ) -> (Pose, Pose) {
        let (ca, cb) = (&self.chains[a], &self.chains[b]);
        let common = ca.iter().zip(cb).take_while(|(x, y)| x == y).count();
        let walk = |chain: &[usize], joints: &mut Vec<PathJoint>| {
            joints.clear();
            chain.iter().fold(Pose::IDENTITY, |pose, &i| {
                let step = &self.steps[i];
                let frame = pose * step.origin;
                let (dof, rate) = match step.value {
                    Value::Dof(d) => (Some(d), 1.0),
                    Value::Mimic {
                        dof, multiplier, ..
                    } => (dof, multiplier.abs()),
                    Value::Fixed => (None, 0.0),
                };
                let turns = matches!(step.kind, JointKind::Revolute | JointKind::Continuous);
                if let Some(dof) = dof.filter(|_| turns || step.kind == JointKind::Prismatic) {
                    joints.push(PathJoint {
                        point: frame.translation,
                        axis: frame.rotation * step.axis,
                        prismatic: !turns,
                        dof,
                        rate,
                    });
                }
                pose * step.transform(q)
            })
        };
        (walk(&ca[common..], side_a), walk(&cb[common..], side_b))
    }

    /// Every joint's value at configuration `q`, indexed by joint (mimic joints follow their leader;
    /// fixed, floating and planar joints read 0).
    pub fn joint_values(&self, q: &[f64]) -> Vec<f64> {
        let mut values = vec![0.0; self.steps.len()];
        for s in &self.steps {
            values[s.joint] = s.value(q);
        }
        values
    }

    /// Pose of every link in the root frame at configuration `q`.
    pub fn link_poses(&self, q: &[f64]) -> Vec<Pose> {
        let mut poses = Vec::new();
        self.link_poses_into(q, &mut poses);
        poses
    }
}

/// The two chains of a link pair below their common ancestor with every step's transform at a base
/// configuration, for a local search that moves one DOF at a time: a pose at a configuration that
/// differs from the base in one DOF recomputes only the steps that DOF drives and the products from the
/// first of them on. The products are formed in the same order as [`Kinematics::pair_poses`] forms
/// them, so the poses are the same to the bit.
#[derive(Debug, Clone)]
pub struct PairChains<'k> {
    kinematics: &'k Kinematics,
    sides: [ChainSide; 2],
}

#[derive(Debug, Clone)]
struct ChainSide {
    /// The chain's step indices, from the common ancestor down.
    steps: Vec<usize>,
    /// Each step's transform at the base.
    transforms: Vec<Pose>,
    /// `prefix[t]`: the product of the first `t` transforms (one more entry than steps).
    prefix: Vec<Pose>,
}

impl PairChains<'_> {
    /// Makes `q` the base.
    pub fn set_base(&mut self, q: &[f64]) {
        let steps = &self.kinematics.steps;
        for side in &mut self.sides {
            side.transforms.clear();
            side.transforms
                .extend(side.steps.iter().map(|&i| steps[i].transform(q)));
            side.prefix.clear();
            side.prefix.push(Pose::IDENTITY);
            for (t, transform) in side.transforms.iter().enumerate() {
                let next = side.prefix[t] * *transform;
                side.prefix.push(next);
            }
        }
    }

    /// The poses of the two links at `q`, which may differ from the base only in DOF `dof`: the same
    /// as [`Kinematics::pair_poses`] gives.
    pub fn poses(&self, q: &[f64], dof: usize) -> (Pose, Pose) {
        let steps = &self.kinematics.steps;
        let pose = |side: &ChainSide| {
            let moved = |i: usize| steps[i].dof() == Some(dof);
            match side.steps.iter().position(|&i| moved(i)) {
                None => side.prefix[side.steps.len()],
                Some(first) => side.steps[first..]
                    .iter()
                    .zip(&side.transforms[first..])
                    .fold(side.prefix[first], |pose, (&i, transform)| {
                        pose * if moved(i) {
                            steps[i].transform(q)
                        } else {
                            *transform
                        }
                    }),
            }
        };
        (pose(&self.sides[0]), pose(&self.sides[1]))
    }
}
