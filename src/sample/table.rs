//! Pairs whose relative pose depends on one degree of freedom (adjacent links, a finger and its mimic
//! twin) are tabulated over that DOF once. With a Lipschitz constant L of the distance in the DOF, the
//! table bounds the distance at any value: |d(x) - d(g)| <= L |x - g| for the nearest grid value g.
//! Sampling then runs an exact query only where those bounds cannot rule out a new minimum, maximum or
//! collision verdict, so the results stay exact.

use super::engine::Engine;
use super::search::path_dofs;
use crate::robot::JointKind;

/// The slack a table aims for: grid points close enough that the bound between two of them is within
/// this of the exact distance (m), as fine as [`MAX_GRID`] allows.
const TARGET_SLACK: f64 = 1e-5;

/// Fewest and most grid points per table.
const MIN_GRID: usize = 64;
const MAX_GRID: usize = 1024;

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
    /// Lower and upper bounds of the signed distance at DOF value `x`, from the two grid values
    /// around it.
    #[inline]
    pub fn bounds(&self, x: f64) -> (f64, f64) {
        let t = (x - self.lower) / self.step;
        let g = (t.floor().max(0.0) as usize).min(self.values.len() - 2);
        let (v0, v1) = (self.values[g], self.values[g + 1]);
        let s0 = self.lipschitz * (x - (self.lower + g as f64 * self.step)).abs();
        let s1 = self.lipschitz * (self.lower + (g + 1) as f64 * self.step - x).abs();
        ((v0 - s0).max(v1 - s1), (v0 + s0).min(v1 + s1))
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
    // How fast the distance can change per unit of the DOF: at most as fast as either shape's points
    // move relative to the other. With one moving joint on the path, turning one shape about its axis
    // is turning the other back about it, so the closer of the two shapes bounds the rate. Otherwise a
    // shape moves by the path joints above its own link (the path runs up from one link and down to
    // the other), each as fast per radian as the shape's farthest point from its axis (taken at home);
    // a moving joint between the shape and an axis shifts the shape's points by up to its own sweep,
    // so each adds that sweep to the reach of the joints above it.
    let span = d.upper - d.lower;
    let path: Vec<usize> = engine
        .robot
        .path_joints(la, lb)
        .into_iter()
        .filter(|&j| engine.robot.joints[j].kind.is_actuated())
        .collect();
    // The shape's farthest point from the joint's axis, and the distance's rate of change for a
    // shape of that reach turned (or, prismatic, shifted) by the joint.
    let about = |k: usize, link: usize, joint: usize| -> f64 {
        let jt = &engine.robot.joints[joint];
        let frame = poses[jt.parent] * jt.origin;
        set.shapes[k].reach(&poses[link], frame.translation, frame.rotation * jt.axis)
    };
    let speed = |joint: usize, reach: f64| -> f64 {
        let jt = &engine.robot.joints[joint];
        let rate = jt.mimic.map_or(1.0, |m| m.multiplier.abs());
        match jt.kind {
            JointKind::Revolute | JointKind::Continuous => rate * reach,
            _ => rate,
        }
    };
    let lipschitz = if let [joint] = path[..] {
        speed(joint, about(a, la, joint).min(about(b, lb, joint)))
    } else {
        let above_a = engine.robot.path_joints(la, engine.robot.root);
        let mut total = 0.0;
        for (k, link, side) in [(a, la, true), (b, lb, false)] {
            let mut sweep = 0.0;
            for &joint in path.iter().filter(|j| above_a.contains(j) == side) {
                let v = speed(joint, about(k, link, joint) + sweep);
                total += v;
                sweep += v * span;
            }
        }
        total
    };
    // Between two grid points the slack is at most lipschitz * step / 2.
    let wanted = (lipschitz * span / (2.0 * TARGET_SLACK)).ceil();
    let grid = if wanted.is_finite() {
        (wanted as usize).clamp(MIN_GRID, MAX_GRID)
    } else {
        MAX_GRID
    };
    let step = span / (grid - 1) as f64;
    let mut q = home;
    let values = (0..grid)
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
