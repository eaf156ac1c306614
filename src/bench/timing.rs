//! Tables 1 and 2: how much the skip matrix speeds up collision and proximity queries, measured as the
//! time over the same configurations with skips divided by the time without, repeated.

use crate::query::{Scratch, SelfChecker};
use serde::Serialize;
use std::hint::black_box;
use std::time::Instant;

/// The three queries a planner asks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QueryKind {
    /// Every colliding pair ([`SelfChecker::collisions`]): the same pairs are examined in every
    /// configuration, so the ratio shows the work the skips save.
    Collisions,
    /// Is anything in collision ([`SelfChecker::in_collision`]), stopping at the first hit.
    FirstHit,
    /// The minimum distance ([`SelfChecker::min_distance`]).
    Proximity,
}

/// One query's timing: the ratio with skips / without over the repeats, and the time per query.
#[derive(Debug, Clone, Serialize)]
pub struct Timing {
    /// Mean over the repeats of (time with skips / time without skips).
    pub ratio_mean: f64,
    /// Sample standard deviation of that ratio (0 for one repeat).
    pub ratio_std: f64,
    /// Mean time per query with skips, microseconds.
    pub skips_us: f64,
    /// Standard deviation over the repeats of the time per query with skips, microseconds.
    pub skips_us_std: f64,
    /// Mean time per query without skips, microseconds.
    pub no_skips_us: f64,
    /// Standard deviation over the repeats of the time per query without skips, microseconds.
    pub no_skips_us_std: f64,
}

/// Runs `kind` over every configuration once; returns the seconds taken.
fn run(checker: &SelfChecker, kind: QueryKind, configs: &[Vec<f64>], scratch: &mut Scratch) -> f64 {
    let start = Instant::now();
    for q in configs {
        // The configurations come from the checker's own DOFs, so the queries cannot fail.
        match kind {
            QueryKind::Collisions => {
                black_box(checker.collisions(black_box(q), scratch).ok());
            }
            QueryKind::FirstHit => {
                black_box(checker.in_collision(black_box(q), scratch).ok());
            }
            QueryKind::Proximity => {
                black_box(checker.min_distance(black_box(q), scratch).ok());
            }
        }
    }
    start.elapsed().as_secs_f64()
}

/// Configurations per timed batch: the two checkers alternate batch by batch, so a change in machine
/// load during a repeat affects both sides of the ratio alike.
const BATCH: usize = 250;

/// Times `kind` with skips against without, `repeats` times over `configs` (single thread, after one
/// untimed warm-up pass each; within a repeat the checkers alternate every 250 configurations).
/// `tick` is called after every repeat.
pub fn time_query(
    skips: &SelfChecker,
    no_skips: &SelfChecker,
    kind: QueryKind,
    configs: &[Vec<f64>],
    repeats: u32,
    tick: &dyn Fn(),
) -> Timing {
    let mut scratch = skips.scratch();
    run(skips, kind, configs, &mut scratch);
    run(no_skips, kind, configs, &mut scratch);
    let per_query = 1e6 / configs.len().max(1) as f64;
    let (mut ratios, mut with, mut without) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..repeats {
        let (mut s, mut a) = (0.0, 0.0);
        for batch in configs.chunks(BATCH) {
            s += run(skips, kind, batch, &mut scratch);
            a += run(no_skips, kind, batch, &mut scratch);
        }
        ratios.push(s / a);
        with.push(s * per_query);
        without.push(a * per_query);
        tick();
    }
    let (ratio_mean, ratio_std) = mean_std(&ratios);
    let (skips_us, skips_us_std) = mean_std(&with);
    let (no_skips_us, no_skips_us_std) = mean_std(&without);
    Timing {
        ratio_mean,
        ratio_std,
        skips_us,
        skips_us_std,
        no_skips_us,
        no_skips_us_std,
    }
}

/// Mean and sample standard deviation (0 for fewer than two values).
pub fn mean_std(x: &[f64]) -> (f64, f64) {
    if x.is_empty() {
        return (0.0, 0.0);
    }
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    if x.len() < 2 {
        return (mean, 0.0);
    }
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, var.sqrt())
}

#[cfg(test)]
mod tests {
    use super::mean_std;

    #[test]
    fn sample_standard_deviation() {
        let (m, s) = mean_std(&[2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0]);
        assert_eq!(m, 5.0);
        assert!((s - (32.0f64 / 7.0).sqrt()).abs() < 1e-12);
        assert_eq!(mean_std(&[3.0]), (3.0, 0.0));
    }
}
