//! Pairs whose relative pose depends on one or two degrees of freedom (adjacent links, a finger and its
//! mimic twin, links two joints apart, two hips on one trunk) are tabulated over those DOFs once, on a
//! grid. With a Lipschitz constant L_d of the distance in each DOF d, the table bounds the distance at
//! any configuration x: |d(x) - d(g)| <= sum_d L_d |x_d - g_d| for every grid point g, and the corners
//! of the grid cell around x give the tightest such bounds. Sampling then runs an exact query only
//! where those bounds cannot rule out a new minimum, maximum or collision verdict, so the results stay
//! exact.
//!
//! Two links that each turn on one joint about the same line (the two hips of a quadruped's side, the
//! wheels on an axle) have a relative pose that depends only on how far the two joints turn relative
//! to each other: their table spans that one coordinate, `q_b - s q_a` (`s` = 1 for the same axis
//! direction, -1 for opposite ones), so its grid is as fine as a one-DOF table's.

use super::sets::PairSet;
use crate::collision::Hint;
use crate::robot::{JointKind, Kinematics, Robot};

/// Most DOFs a table spans.
pub const MAX_RANK: usize = 2;

/// The slack a table aims for: grid points close enough that the bound inside a cell is within this of
/// the exact distance (m), as fine as [`MAX_POINTS`] allows.
const TARGET_SLACK: f64 = 1e-5;

/// Most grid points per table, by rank. A table costs one exact query per point to build and two
/// bytes per point to keep.
const MAX_POINTS: [usize; MAX_RANK] = [1024, 1024];

/// Fewest grid points per axis, by rank.
const MIN_POINTS: [usize; MAX_RANK] = [64, 8];

/// One coordinate of a table, `q[dof] - coaxial * q[other]`: a DOF (`coaxial` 0), or the relative
/// turn of two coaxial joints. Its grid and how fast the distance can change along it.
#[derive(Debug, Clone, Copy)]
struct Axis {
    /// The DOF index.
    dof: usize,
    /// The DOF subtracted, and its factor (0 for a plain DOF; then `other` is `dof`).
    other: usize,
    coaxial: f64,
    /// The first grid value (the DOF's lower limit).
    lower: f64,
    /// Grid spacing, and its inverse.
    step: f64,
    inv_step: f64,
    /// Grid points.
    points: usize,
    /// Distance between consecutive values of the axis's grid index in the value array.
    stride: usize,
    /// Lipschitz constant of the distance in this DOF (m per unit of the DOF), slightly inflated so
    /// rounding cannot make a bound too tight.
    lipschitz: f64,
}

/// The distance of one pair tabulated over the DOFs it depends on.
#[derive(Debug, Clone)]
pub struct Table {
    axes: Vec<Axis>,
    /// The distance at every grid point, the last axis varying fastest, as `base + unit * value`:
    /// 16 bits a point, so that the tables of a large robot stay in cache (a table spans the distances
    /// of links at most two joints apart, so its step is a few micrometres).
    values: Vec<u16>,
    /// The least distance in the table (m).
    base: f64,
    /// The distance of one unit of `values` (m).
    unit: f64,
    /// At least the largest rounding error of `values` (m).
    rounding: f64,
}

impl Table {
    /// The number of coordinates the table spans (1 or 2; a coaxial pair's relative turn is one).
    pub fn rank(&self) -> usize {
        self.axes.len()
    }

    /// Whether the table spans the relative turn of two coaxial joints.
    pub fn is_coaxial(&self) -> bool {
        self.axes.iter().any(|a| a.coaxial != 0.0)
    }

    /// Lower and upper bounds of the signed distance at configuration `q` (all DOFs; the table reads
    /// its own), from the grid values at the corners of the cell around it.
    pub fn bounds(&self, q: &[f64]) -> (f64, f64) {
        let mut out = [(f64::NEG_INFINITY, f64::INFINITY)];
        self.tighten(q, q.len(), &mut out);
        out[0]
    }

    /// Starts bringing the table's values into cache (see [`super::prefetch`]): a block's lookups land
    /// anywhere in the table.
    #[inline]
    pub fn prefetch(&self) {
        super::prefetch::prefetch(&self.values);
    }

    /// [`Table::bounds`] for a block of samples: tightens `out`'s lower and upper bounds at every
    /// sample, `q` holding one row of `dofs` values per element of `out`.
    #[inline]
    pub fn tighten(&self, q: &[f64], dofs: usize, out: &mut [(f64, f64)]) {
        match (self.axes.len(), self.is_coaxial()) {
            (1, false) => self.tighten_in::<1, false>(q, dofs, out),
            (1, true) => self.tighten_in::<1, true>(q, dofs, out),
            _ => self.tighten_in::<2, false>(q, dofs, out),
        }
    }

    /// [`Table::tighten`] for `R` axes, `COAXIAL` when an axis is a relative turn (else the
    /// subtraction is compiled out).
    #[inline]
    fn tighten_in<const R: usize, const COAXIAL: bool>(
        &self,
        q: &[f64],
        dofs: usize,
        out: &mut [(f64, f64)],
    ) {
        debug_assert_eq!(self.axes.len(), R);
        // The axes held in locals for the whole block, and the rows checked once.
        let axes: [Axis; R] = std::array::from_fn(|r| self.axes[r]);
        let (values, rounding) = (&self.values[..], self.rounding);
        let value = |index: usize| decode(self.base, self.unit, values[index]);
        for (row, (lower, upper)) in q.chunks_exact(dofs).zip(out.iter_mut()) {
            // Per axis: the Lipschitz slack to the cell's lower and upper grid value. The cell found
            // by rounding may be off by one at a boundary; the bounds hold from any grid point.
            let (mut base, mut near, mut far) = (0, [0.0; R], [0.0; R]);
            for (r, axis) in axes.iter().enumerate() {
                let x = if COAXIAL {
                    row[axis.dof] - axis.coaxial * row[axis.other]
                } else {
                    row[axis.dof]
                };
                // The cell below `x`: truncation is the floor for the values it keeps (at least 0;
                // a float-to-int `as` saturates; through i64, one instruction), without a call to
                // libm's `floor` on every lookup.
                let g = (((x - axis.lower) * axis.inv_step).max(0.0) as i64 as usize)
                    .min(axis.points - 2);
                let x0 = axis.lower + g as f64 * axis.step;
                near[r] = axis.lipschitz * (x - x0).abs();
                far[r] = axis.lipschitz * (x0 + axis.step - x).abs();
                base += g * axis.stride;
            }
            let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
            for corner in 0..1usize << R {
                let (mut index, mut slack) = (base, 0.0);
                for (r, axis) in axes.iter().enumerate() {
                    if corner >> r & 1 == 1 {
                        index += axis.stride;
                        slack += far[r];
                    } else {
                        slack += near[r];
                    }
                }
                let v = value(index);
                lo = lo.max(v - slack);
                hi = hi.min(v + slack);
            }
            *lower = lower.max(lo - rounding);
            *upper = upper.min(hi + rounding);
        }
    }
}

/// The table of pair `p` of `set`, or `None` when the pair depends on no DOF or on more than
/// [`MAX_RANK`], or when both shapes are spheres (whose sphere bounds are exact already).
pub fn build(robot: &Robot, kinematics: &Kinematics, set: &PairSet, p: usize) -> Option<Table> {
    let (i, j) = set.pairs[p];
    let (a, b) = (i as usize, j as usize);
    if set.shapes[a].is_ball() && set.shapes[b].is_ball() {
        return None;
    }
    let (la, lb) = (set.links[a], set.links[b]);
    let dofs = kinematics.path_dofs(la, lb);
    if dofs.is_empty() || dofs.len() > MAX_RANK {
        return None;
    }
    let coordinates = match coaxial(robot, kinematics, set, p) {
        Some(turn) => vec![turn],
        None => {
            let lipschitz = lipschitz(robot, kinematics, set, p, &dofs);
            dofs.iter()
                .zip(lipschitz)
                .map(|(&d, lipschitz)| {
                    let dof = &kinematics.dofs()[d];
                    Coordinate {
                        dof: d,
                        other: d,
                        coaxial: 0.0,
                        lower: dof.lower,
                        span: dof.span(),
                        lipschitz,
                    }
                })
                .collect()
        }
    };
    let lipschitz: Vec<f64> = coordinates.iter().map(|c| c.lipschitz).collect();
    let spans: Vec<f64> = coordinates.iter().map(|c| c.span).collect();
    let points = grid(&lipschitz, &spans);
    let mut axes: Vec<Axis> = coordinates
        .iter()
        .zip(&points)
        .map(|(c, &points)| {
            let step = c.span / (points - 1) as f64;
            Axis {
                dof: c.dof,
                other: c.other,
                coaxial: c.coaxial,
                lower: c.lower,
                step,
                inv_step: 1.0 / step,
                points,
                stride: 0,
                lipschitz: c.lipschitz * (1.0 + 1e-9) + 1e-12,
            }
        })
        .collect();
    let mut stride = 1;
    for axis in axes.iter_mut().rev() {
        axis.stride = stride;
        stride *= axis.points;
    }
    // Row by row, each query starting from the last one's points (neighbours on the grid are close).
    // A relative turn is placed with the subtracted joint at 0: only the difference matters.
    let mut q = kinematics.home();
    for axis in axes.iter().filter(|a| a.coaxial != 0.0) {
        q[axis.other] = 0.0;
    }
    let mut hint = Hint::default();
    let values: Vec<f64> = (0..stride)
        .map(|index| {
            for axis in &axes {
                let g = index / axis.stride % axis.points;
                q[axis.dof] = axis.lower + g as f64 * axis.step;
            }
            let pair = set.pair_at(kinematics, p, &q);
            pair.distance_hinted(&mut hint)
        })
        .collect();
    // The bounds assume the computed distance changes no faster than the constants allow. Where it
    // jumps between grid neighbours, the table would settle samples the exact query decides otherwise:
    // none. (parry's EPA jumped by a fraction of a millimetre in deep overlaps and dropped 6 of b1's
    // 4,292 tables; the exact query's EPA drops none, so this is a guard.)
    let jumps = axes.iter().any(|axis| {
        (0..stride).any(|index| {
            index / axis.stride % axis.points + 1 < axis.points
                && (values[index + axis.stride] - values[index]).abs() > axis.lipschitz * axis.step
        })
    });
    if jumps || values.iter().any(|v| !v.is_finite()) {
        return None;
    }
    // 65,535 steps from the least value to the greatest; the rounding error is measured as the
    // lookup will see it.
    let base = values.iter().copied().fold(f64::INFINITY, f64::min);
    let top = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let unit = ((top - base) / f64::from(u16::MAX)).max(1e-15);
    // A whole number in 0..=u16::MAX after the clamp, so the cast is exact.
    let units: Vec<u16> = values
        .iter()
        .map(|&v| ((v - base) / unit).round().clamp(0.0, f64::from(u16::MAX)) as u16)
        .collect();
    let error = values.iter().zip(&units).fold(0.0f64, |m, (&v, &n)| {
        m.max((decode(base, unit, n) - v).abs())
    });
    Some(Table {
        axes,
        values: units,
        base,
        unit,
        rounding: error * (1.0 + 1e-9) + 1e-12,
    })
}

/// A coordinate a table spans, `q[dof] - coaxial * q[other]` over `lower .. lower + span`, along which
/// the distance changes by at most `lipschitz` per unit.
struct Coordinate {
    dof: usize,
    other: usize,
    coaxial: f64,
    lower: f64,
    span: f64,
    lipschitz: f64,
}

/// Whether pair `p` of `set` is a coaxial pair: each link turns on exactly one joint below the links'
/// common ancestor (revolute or continuous, driven by its own DOF, the two DOFs distinct), and the two
/// joints' axes lie on one line. Then the links' relative pose is the first joint's turn undone and
/// the second's done about that line, a turn by `q_b - s q_a` (`s` = +-1 as the axes point the same
/// way or opposite ways), so the distance depends on that coordinate alone, and changes per radian of
/// it by at most either shape's reach about the line (turning one shape about the line, or the other
/// back).
fn coaxial(robot: &Robot, kinematics: &Kinematics, set: &PairSet, p: usize) -> Option<Coordinate> {
    /// Axes this close to one line (unit vectors; metres) count as one: URDF origins and axes are
    /// written as decimals, so a coaxial pair's cross products are rounding (about 1e-17).
    const ON_LINE: f64 = 1e-12;
    let (i, j) = set.pairs[p];
    let (a, b) = (i as usize, j as usize);
    let (la, lb) = (set.links[a], set.links[b]);
    let joints: Vec<usize> = robot
        .path_joints(la, lb)
        .into_iter()
        .filter(|&j| robot.joints[j].kind.is_actuated())
        .collect();
    let plain = |j: usize| {
        let joint = &robot.joints[j];
        joint.mimic.is_none() && matches!(joint.kind, JointKind::Revolute | JointKind::Continuous)
    };
    if joints.len() != 2 || !joints.iter().all(|&j| plain(j)) {
        return None;
    }
    // Each link's own joint, as an axis line in the links' common ancestor's frame.
    let (mut side_a, mut side_b) = (Vec::new(), Vec::new());
    let (pose_a, pose_b) =
        kinematics.pair_path(&kinematics.home(), la, lb, &mut side_a, &mut side_b);
    let ([ja], [jb]) = (side_a.as_slice(), side_b.as_slice()) else {
        return None;
    };
    if ja.dof == jb.dof
        || ja.axis.cross(jb.axis).length() > ON_LINE
        || (jb.point - ja.point).cross(ja.axis).length() > ON_LINE
    {
        return None;
    }
    let sign = ja.axis.dot(jb.axis).signum();
    let (da, db) = (&kinematics.dofs()[ja.dof], &kinematics.dofs()[jb.dof]);
    // sign * q_a runs over [min, max]; q_b - sign * q_a over [lower_b - max, upper_b - min].
    let (x, y) = (sign * da.lower, sign * da.upper);
    let lower = db.lower - x.max(y);
    let span = db.upper - x.min(y) - lower;
    let reach = |k: usize, pose| set.shapes[k].reach(pose, ja.point, ja.axis);
    Some(Coordinate {
        dof: jb.dof,
        other: ja.dof,
        coaxial: sign,
        lower,
        span,
        lipschitz: reach(a, &pose_a).min(reach(b, &pose_b)),
    })
}

/// The distance a table stores as `n` units of `unit` above `base`: the one decoding, so that the
/// rounding measured when the table is built is the one its lookups see.
#[inline]
fn decode(base: f64, unit: f64, n: u16) -> f64 {
    base + unit * f64::from(n)
}

/// Grid points per axis for Lipschitz constants `lipschitz` over spans `spans`: the slack in a cell
/// is sum_d L_d step_d / 2, smallest for a given number of points when every axis contributes the same,
/// so points go to the axis contributing most until the table holds [`MAX_POINTS`] or the slack is
/// down to [`TARGET_SLACK`].
fn grid(lipschitz: &[f64], spans: &[f64]) -> Vec<usize> {
    let rank = lipschitz.len();
    let (most, fewest) = (MAX_POINTS[rank - 1], MIN_POINTS[rank - 1]);
    let mut points = vec![fewest; rank];
    let slack = |points: &[usize], d: usize| lipschitz[d] * spans[d] / (2 * (points[d] - 1)) as f64;
    loop {
        let total: f64 = (0..rank).map(|d| slack(&points, d)).sum();
        if total.is_nan() || total <= TARGET_SLACK {
            return points;
        }
        let widest = (0..rank)
            .max_by(|&x, &y| slack(&points, x).total_cmp(&slack(&points, y)))
            .unwrap_or(0);
        let more = points[widest] + (points[widest] / 8).max(1);
        let product: usize = (0..rank)
            .map(|d| if d == widest { more } else { points[d] })
            .product();
        if product > most {
            return points;
        }
        points[widest] = more;
    }
}

/// Per DOF of `dofs` (the DOFs pair `p` of set `s` depends on), how fast the distance can change per
/// unit of it: at most as fast as either shape's points move relative to the other. A shape moves by
/// the path joints above its own link, each as fast per radian as the shape's farthest point from its
/// axis (taken at home, plus how far the joints in between can shift the shape); and turning a joint
/// that hangs from the links' common ancestor is turning the other shape back about the same axis, so
/// the nearer of the two shapes bounds its rate (with one joint on the path, the pair's exact reach).
fn lipschitz(
    robot: &Robot,
    kinematics: &Kinematics,
    set: &PairSet,
    p: usize,
    dofs: &[usize],
) -> Vec<f64> {
    let (i, j) = set.pairs[p];
    let (a, b) = (i as usize, j as usize);
    let (la, lb) = (set.links[a], set.links[b]);
    let poses = kinematics.link_poses(&kinematics.home());
    let path: Vec<usize> = robot
        .path_joints(la, lb)
        .into_iter()
        .filter(|&j| robot.joints[j].kind.is_actuated())
        .collect();
    // The shape's farthest point from the joint's axis.
    let about = |k: usize, link: usize, joint: usize| -> f64 {
        let jt = &robot.joints[joint];
        let frame = poses[jt.parent] * jt.origin;
        set.shapes[k].reach(&poses[link], frame.translation, frame.rotation * jt.axis)
    };
    // The distance's rate of change per unit of the joint's DOF, for a shape of that reach turned
    // (or, prismatic, shifted) by the joint; and how far the joint moves such a shape over its range.
    let rate = |joint: usize| {
        robot.joints[joint]
            .mimic
            .map_or(1.0, |m| m.multiplier.abs())
    };
    let span = |joint: usize| {
        kinematics
            .joint_dof(joint)
            .map_or(0.0, |d| kinematics.dofs()[d].span())
    };
    let speed = |joint: usize, reach: f64| -> f64 {
        match robot.joints[joint].kind {
            JointKind::Revolute | JointKind::Continuous => rate(joint) * reach,
            _ => rate(joint),
        }
    };
    let sweep = |joint: usize, reach: f64| -> f64 {
        let turn = rate(joint) * span(joint);
        match robot.joints[joint].kind {
            // A point at distance r from the axis turned by an angle t moves 2 r sin(t / 2).
            JointKind::Revolute | JointKind::Continuous => reach * turn.min(2.0),
            _ => turn,
        }
    };
    // Per side (the path runs up from `a`'s link and down to `b`'s): its joints bottom-up, each
    // turning the side's shape at the shape's reach about its axis plus how far the joints below
    // shift it, and how far the side's joints shift the shape in all.
    let above_a = robot.path_joints(la, robot.root);
    let sides = [(a, la, true), (b, lb, false)];
    let mut rates: Vec<(usize, f64)> = Vec::new();
    let mut moved = [0.0; 2];
    let mut tops = [None; 2];
    for (s, &(k, link, side)) in sides.iter().enumerate() {
        for &joint in path.iter().filter(|j| above_a.contains(j) == side) {
            let reach = about(k, link, joint) + moved[s];
            rates.push((joint, speed(joint, reach)));
            moved[s] += sweep(joint, reach);
            tops[s] = Some(rates.len() - 1);
        }
    }
    // The top joint of a side turns about an axis fixed to the links' common ancestor; turning it is
    // turning the other shape back about that axis, and only the other side's joints move that shape
    // from it, so the other shape's reach there bounds the rate too.
    for (s, top) in tops.iter().enumerate() {
        if let Some(t) = *top {
            let (joint, own) = rates[t];
            let (k, link, _) = sides[1 - s];
            rates[t].1 = own.min(speed(joint, about(k, link, joint) + moved[1 - s]));
        }
    }
    let mut lipschitz = vec![0.0; dofs.len()];
    for (joint, v) in rates {
        if let Some(slot) = kinematics
            .joint_dof(joint)
            .and_then(|d| dofs.iter().position(|&x| x == d))
        {
            lipschitz[slot] += v;
        }
    }
    lipschitz
}
