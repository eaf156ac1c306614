//! MoveIt's adjacency rule: two links with geometry are adjacent when a joint joins them, directly or
//! through links that have no geometry.

use super::{GeometryOrigin, Robot};

/// Adjacent pairs `(a, b)` with `a < b`, sorted.
pub fn adjacent_pairs(robot: &Robot) -> Vec<(usize, usize)> {
    let n = robot.links.len();
    let mut neighbours = vec![Vec::new(); n];
    for j in &robot.joints {
        neighbours[j.parent].push(j.child);
        neighbours[j.child].push(j.parent);
    }
    let has_geometry = |i: usize| robot.links[i].geometry_source != GeometryOrigin::None;
    let mut pairs = Vec::new();
    for start in (0..n).filter(|&i| has_geometry(i)) {
        // Walk out from `start`, passing through geometry-less links only.
        let mut seen = vec![false; n];
        seen[start] = true;
        let mut stack = neighbours[start].clone();
        while let Some(at) = stack.pop() {
            if std::mem::replace(&mut seen[at], true) {
                continue;
            }
            if has_geometry(at) {
                if start < at {
                    pairs.push((start, at));
                }
            } else {
                stack.extend(neighbours[at].iter().copied());
            }
        }
    }
    pairs.sort_unstable();
    pairs
}
