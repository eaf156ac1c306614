//! Pairs whose relative pose depends on one degree of freedom (adjacent links, a finger and its mimic
//! twin) are tabulated over that DOF once. With a Lipschitz constant L of the distance in the DOF, the
//! table bounds the distance at any value: |d(x) - d(g)| <= L |x - g| for the nearest grid value g.
//! Sampling then runs an exact query only where those bounds cannot rule out a new minimum, maximum or
//! collision verdict, so the results stay exact.

use super::engine::Engine;
use super::search::path_dofs;
use crate::robot::JointKind;

/// Grid points per table.
const GRID: usize = 256;

/// The distance of one pair tabulated over its single DOF.
#[derive(Debug, Clone)]
pub struct Table {
    /// The DOF index.
    pub dof: usize,
    lower: f64,
    step: f64,
    values: Vec<f64>,
    lipschitz: f64,
}

impl Table {
    /// Lower and upper bounds of the signed distance at DOF value `x`.
    #[inline]
    pub fn bounds(&self, x: f64) -> (f64, f64) {
        let g =
            (((x - self.lower) / self.step).round().max(0.0) as usize).min(self.values.len() - 1);
        let slack = self.lipschitz * (x - (self.lower + g as f64 * self.step)).abs();
        (self.values[g] - slack, self.values[g] + slack)
    }
}

/// The table of pair `p` of set `s`, or `None` when the pair depends on zero or several DOFs.
pub fn build(engine: &Engine, s: usize, p: usize) -> Option<Table> {
    let set = &engine.sets[s];
    let (i, j) = set.pairs[p];
    let (a, b) = (i as usize, j as usize);
    let (la, lb) = (set.links[a], set.links[b]);
    let [dof] = path_dofs(engine, la, lb)[..] else {
        return None;
    };
    let d = &engine.kinematics.dofs()[dof];
    let home = engine.kinematics.home();
    let poses = engine.kinematics.link_poses(&home);
    // Every point of either shape moves at most this fast per unit of the DOF.
    let reach = |joint: usize| -> f64 {
        let jt = &engine.robot.joints[joint];
        let frame = poses[jt.parent] * jt.origin;
        let axis = frame.rotation * jt.axis;
        [(a, la), (b, lb)]
            .iter()
            .map(|&(k, link)| {
                let shape = &set.shapes[k];
                let c = poses[link].transform_point(shape.outer_center) - frame.translation;
                (c - axis * c.dot(axis)).length() + shape.outer_radius
            })
            .fold(0.0, f64::max)
    };
    let mut lipschitz = 0.0;
    for joint in engine.robot.path_joints(la, lb) {
        let jt = &engine.robot.joints[joint];
        let rate = jt.mimic.map_or(1.0, |m| m.multiplier.abs());
        lipschitz += match jt.kind {
            JointKind::Revolute | JointKind::Continuous => rate * reach(joint),
            JointKind::Prismatic => rate,
            _ => 0.0,
        };
    }
    let step = (d.upper - d.lower) / (GRID - 1) as f64;
    let mut q = home;
    let values = (0..GRID)
        .map(|g| {
            q[dof] = d.lower + g as f64 * step;
            engine.pair_distance(s, p, &q)
        })
        .collect();
    // Slightly inflated so rounding in the grid values cannot make a bound too tight.
    Some(Table {
        dof,
        lower: d.lower,
        step,
        values,
        lipschitz: lipschitz * (1.0 + 1e-9) + 1e-12,
    })
}
