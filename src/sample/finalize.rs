//! From samples to verdicts: per-pair mean budgets, parallel accumulation over chunks, and the
//! finalisation into records (rigid pairs, home distances, reasons, witnesses, targeted search).

use super::engine::{self, CHUNK, Engine};
use super::reasons::{Evidence, Reason, infer, never_upper_bound};
use super::records::{PairRecord, SampleFile, TypeSummary, Witness};
use super::search::{SearchOutcome, SearchTarget, search_link_pair};
use super::stats::PairStats;
use super::{EXACT_MEAN, SampleOptions};
use crate::progress::Progress;
use crate::urdd::FORMAT_VERSION;
use rayon::prelude::*;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::sync::{Mutex, PoisonError};

/// Samples of the pilot run that sizes each pair's exact-mean budget: the first samples of chunk 0.
/// Most pairs' control bound leaves so little spread that they need fewer (orca_hand: 73% of its
/// `decomp-*` pairs under 64), so the pilot is what most of them get.
const PILOT: u64 = 64;

/// How far the true variance of `n` samples' residuals may lie above their sample variance: the
/// one-sided 95% upper confidence factor `(n - 1) / chi2_0.05(n - 1)`, the quantile by the
/// Wilson-Hilferty approximation (within 0.1% of the tables from 30 degrees of freedom up). A budget
/// sized from a small pilot's spread with it holds its error bound about as often as one sized
/// from the true spread.
fn variance_margin(n: u64) -> f64 {
    let k = n.saturating_sub(1).max(1) as f64;
    // The 5% quantile of the standard normal.
    let z = -1.644_853_626_951_472_2;
    let c = 2.0 / (9.0 * k);
    let quantile = k * (1.0 - c + z * c.sqrt()).powi(3);
    k / quantile
}

/// Up to this many exact samples a pair's budget takes the pilot's [`variance_margin`]; a pair that
/// needs more gets what the spread it showed asks for, and at least this many, as every pair did when
/// the pilot itself was this long. So the short pilot saves the pairs that need few samples most of
/// their exact queries, and does not cost the pairs that need many more of them (the link-level
/// types on the small arms, whose budgets run into the thousands).
const MARGIN_UP_TO: u64 = 256;

/// The exact-mean budget of a pair that the pilot's spread says `needed` samples would bring within
/// 1% at 3 sigma (infinite for a zero mean), under the cap of `cap` (more than [`PILOT`]) of a run
/// of `samples`: with the margin where that stays within [`MARGIN_UP_TO`], else as seen and at least
/// that many; a pair the cap cannot bring within 1% gets every sample (an exact mean).
fn budget(needed: f64, margin: f64, cap: u64, samples: u64) -> u64 {
    let with_margin = needed * margin;
    if with_margin <= MARGIN_UP_TO as f64 && with_margin <= cap as f64 {
        (with_margin.ceil() as u64).max(PILOT)
    } else if with_margin <= MARGIN_UP_TO as f64 || needed > cap as f64 {
        samples
    } else {
        (needed.ceil() as u64).max(MARGIN_UP_TO).min(cap)
    }
}

/// Samples of the scout run (see [`Engine::scout`]): the first chunks, whose extremes prune the others.
const SCOUT: u64 = 16 * CHUNK;

/// The pilot's statistics (samples `0..PILOT`, exact for every pair: [`Engine::scout`] with that
/// budget) and, per pair, how many leading samples enter its mean estimate exactly: enough for a
/// 3-sigma error under 1% of the mean (residual spread after the control bound, judged from the
/// pilot: see [`budget`]), at least [`PILOT`]; a pair that would need more than `opts.mean_samples`
/// gets every sample, so its mean is exact. No pilot runs (empty statistics) when
/// the cap is [`PILOT`] or less, or is [`EXACT_MEAN`]: every pair then gets the cap (every sample,
/// an exact mean, for [`EXACT_MEAN`]).
/// Depends only on the seed and the robot, so every thread count and shard gets the same budgets.
pub(super) fn mean_budgets(
    engine: &Engine,
    opts: &SampleOptions,
) -> (Vec<Vec<PairStats>>, Vec<Vec<u64>>) {
    let cap = opts.mean_samples.min(opts.samples);
    if cap <= PILOT || opts.mean_samples == EXACT_MEAN {
        let budgets = engine.sets.iter().map(|s| vec![cap; s.pairs.len()]);
        return (Vec::new(), budgets.collect());
    }
    let uniform: Vec<Vec<u64>> = engine
        .sets
        .iter()
        .map(|s| vec![PILOT; s.pairs.len()])
        .collect();
    let run = engine::ChunkRun {
        seed: opts.seed,
        total: opts.samples,
        mean_budget: &uniform,
        tol: 0.0,
        known: &[],
        tethers: &[],
    };
    let mut pilot = engine.empty_stats();
    engine.scout(&run, 0, PILOT, &mut pilot);
    let margin = variance_margin(PILOT);
    let budgets = pilot
        .iter()
        .map(|stats| {
            stats
                .iter()
                .map(|st| {
                    let (mean, std) = (st.mean().abs(), st.std());
                    let needed = if mean > 0.0 {
                        (3.0 * std / (0.01 * mean)).powi(2)
                    } else {
                        f64::INFINITY
                    };
                    budget(needed, margin, cap, opts.samples)
                })
                .collect()
        })
        .collect();
    (pilot, budgets)
}

/// Runs the chunks in parallel. The first [`SCOUT`] samples go first, pair by pair (see
/// [`Engine::scout`]), from the pilot's statistics; their statistics are chunk 0's, and prune every
/// later chunk, which starts from empty accumulators (see [`Engine::run_chunk`]). Chunk results merge
/// exactly in any order, each into the total as soon as it is done, so memory holds one accumulator
/// per worker and the total, whatever the chunk count. Every shard runs the scout, and only the shard
/// of chunk 0 keeps it.
pub(super) fn accumulate(
    engine: &Engine,
    opts: &SampleOptions,
    chunks: &[u64],
    progress: &dyn Progress,
) -> Vec<Vec<PairStats>> {
    let empty = || engine.empty_stats();
    let (pilot, budgets) = mean_budgets(engine, opts);
    let mut run = engine::ChunkRun {
        seed: opts.seed,
        total: opts.samples,
        mean_budget: &budgets,
        tol: opts.tolerance,
        known: &[],
        tethers: &[],
    };
    let scouted = SCOUT.min(opts.samples);
    let (mut known, start) = if pilot.is_empty() {
        (empty(), 0)
    } else {
        (pilot, PILOT)
    };
    // Tethers where the pilot found each pair farthest apart for the scout, and where the scout did
    // for the chunks.
    let tethers = engine.tethers(opts.seed, start, &known);
    run.tethers = &tethers;
    engine.scout(&run, start, scouted, &mut known);
    let tethers = engine.tethers(opts.seed, scouted, &known);
    run.known = &known;
    run.tethers = &tethers;
    // One running total, and per worker one chunk's accumulator and scratch: a chunk's statistics are
    // merged in as soon as it is done (they merge exactly in any order), so memory holds the workers'
    // accumulators, not one per piece of work rayon splits the chunks into.
    let total = Mutex::new(empty());
    let add = |chunk: &[Vec<PairStats>]| {
        // Merging cannot panic, and a panic anywhere else ends the run before the total is used, so
        // a poisoned lock never hands on a half-merged total that is read.
        let mut total = total.lock().unwrap_or_else(PoisonError::into_inner);
        for (x, y) in total.iter_mut().zip(chunk) {
            x.iter_mut().zip(y).for_each(|(s, o)| s.merge(o));
        }
    };
    chunks.par_iter().for_each_init(
        || (empty(), engine::ChunkScratch::default()),
        |(chunk, scratch), &c| {
            if c * CHUNK < scouted {
                // The scout's samples: chunk 0 carries all of them.
                if c == 0 {
                    add(&known);
                }
            } else {
                chunk.iter_mut().for_each(|v| v.fill(PairStats::default()));
                engine.run_chunk(&run, c, chunk, scratch);
                add(chunk);
            }
            progress.advance(CHUNK.min(opts.samples - c * CHUNK));
        },
    );
    total.into_inner().unwrap_or_else(PoisonError::into_inner)
}

/// Rigid pairs, home distances, reasons, witnesses and the targeted search: from exact accumulators to files.
pub(super) fn finalize(
    engine: &Engine,
    opts: &SampleOptions,
    acc: Vec<Vec<PairStats>>,
) -> Vec<SampleFile> {
    let home = engine.kinematics.home();
    let adjacent: BTreeSet<(usize, usize)> = engine.robot.adjacent_pairs().into_iter().collect();
    // Witness configurations, generated once per distinct sample index.
    let witness_samples: BTreeSet<u64> = acc
        .iter()
        .flatten()
        .filter(|s| s.min_sample != u64::MAX)
        .map(|s| s.min_sample)
        .collect();
    let configs: HashMap<u64, Vec<f64>> = witness_samples
        .into_par_iter()
        .map(|k| (k, engine.configuration(opts.seed, k)))
        .collect();
    let n = opts.samples;
    let mean_samples = opts.mean_samples.min(n);

    // Records first, every type; then the targeted search of the close `never` pairs of all types,
    // a link pair at a time (see `search`).
    let mut records: Vec<Vec<(PairRecord, Evidence)>> = Vec::new();
    for (s, (set, stats)) in engine.sets.iter().zip(acc).enumerate() {
        let pairs = set
            .pairs
            .par_iter()
            .enumerate()
            .map(|(p, &(i, j))| {
                let (la, lb) = (set.links[i as usize], set.links[j as usize]);
                let home_distance = engine.pair_distance(s, p, &home);
                let (st, witness) = if set.moving[p] {
                    let st = stats[p];
                    (
                        st,
                        Witness {
                            sample: Some(st.min_sample),
                            q: configs.get(&st.min_sample).cloned().unwrap_or_default(),
                        },
                    )
                } else {
                    // Rigid: the distance is the same in every sample.
                    let c = u64::from(home_distance <= 0.0) * n;
                    let mut st = PairStats {
                        collisions: c,
                        ..PairStats::default()
                    };
                    st.observe_extremes(home_distance, 0);
                    st.sum = (home_distance * 1e12).round() as i128 * i128::from(mean_samples);
                    st.mean_count = mean_samples;
                    (
                        st,
                        Witness {
                            sample: None,
                            q: home.clone(),
                        },
                    )
                };
                let collision_fraction = if n == 0 {
                    0.0
                } else {
                    st.collisions as f64 / n as f64
                };
                let evidence = Evidence {
                    same_link: la == lb,
                    adjacent: adjacent.contains(&(la.min(lb), la.max(lb))),
                    home_collision: home_distance <= 0.0,
                    collision_fraction,
                    search_collision: false,
                };
                let record = PairRecord {
                    a: i as usize,
                    b: j as usize,
                    reason: infer(&evidence, opts.always_fraction),
                    d_min: st.min,
                    d_mean: st.mean(),
                    mean_samples: st.mean_count,
                    d_max: st.max,
                    collisions: st.collisions,
                    collision_fraction,
                    home_distance,
                    witness,
                    search: None,
                };
                (record, evidence)
            })
            .collect();
        records.push(pairs);
    }
    search(engine, opts, &mut records);

    let mut files = Vec::new();
    for (set, records) in engine.sets.iter().zip(records) {
        let mut pairs: Vec<PairRecord> = records.into_iter().map(|(r, _)| r).collect();
        pairs.sort_by_key(|r| (r.a, r.b));
        let mut summary = TypeSummary {
            shapes: set.shapes.len(),
            ..TypeSummary::default()
        };
        for r in &pairs {
            *summary.reasons.entry(r.reason).or_default() += 1;
            if let Some(o) = &r.search {
                summary.searched += 1;
                summary.overturned += usize::from(o.collision);
            }
        }
        files.push(SampleFile {
            format_version: FORMAT_VERSION,
            shape_type: set.shape_type,
            samples: n,
            seed: opts.seed,
            mean_samples,
            always_fraction: opts.always_fraction,
            never_upper_bound: never_upper_bound(n),
            summary,
            pairs,
        });
    }
    files
}

/// The targeted search of every moving `never` pair (of any type) with `d_min` below the search margin,
/// grouped by link pair and the groups in parallel; a collision found overturns the verdict.
fn search(engine: &Engine, opts: &SampleOptions, records: &mut [Vec<(PairRecord, Evidence)>]) {
    let mut groups: BTreeMap<(usize, usize), Vec<(usize, usize)>> = BTreeMap::new();
    for (s, (set, records)) in engine.sets.iter().zip(records.iter()).enumerate() {
        for (p, (record, _)) in records.iter().enumerate() {
            if record.reason == Reason::Never && set.moving[p] && record.d_min < opts.search.margin
            {
                let (la, lb) = set.pair_links(p);
                groups
                    .entry((la.min(lb), la.max(lb)))
                    .or_default()
                    .push((s, p));
            }
        }
    }
    let groups: Vec<_> = groups.into_iter().collect();
    let outcomes: Vec<Vec<SearchOutcome>> = groups
        .par_iter()
        .map(|(links, members)| {
            let targets: Vec<SearchTarget> = members
                .iter()
                .map(|&(s, p)| SearchTarget {
                    set: s,
                    pair: p,
                    witness: &records[s][p].0.witness.q,
                })
                .collect();
            search_link_pair(
                &engine.kinematics,
                &engine.sets,
                *links,
                &targets,
                opts.seed,
                &opts.search,
            )
        })
        .collect();
    for ((_, members), outcomes) in groups.iter().zip(outcomes) {
        for (&(s, p), outcome) in members.iter().zip(outcomes) {
            let (record, evidence) = &mut records[s][p];
            if outcome.collision {
                evidence.search_collision = true;
                record.reason = infer(evidence, opts.always_fraction);
            }
            record.search = Some(outcome);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{MARGIN_UP_TO, PILOT, budget, variance_margin};

    #[test]
    fn the_variance_margin_follows_the_chi_square_tables() {
        // 5% quantiles of chi-square with k degrees of freedom, from the printed tables.
        for (k, quantile) in [(30u64, 18.493), (60, 43.188), (100, 77.929)] {
            let margin = variance_margin(k + 1);
            let table = k as f64 / quantile;
            assert!(
                (margin / table - 1.0).abs() < 1e-3,
                "{k} degrees of freedom: {margin} vs {table}"
            );
        }
        // The pilot's: over a third more samples than its spread alone asks for, and less with more.
        assert!((1.3..1.45).contains(&variance_margin(64)));
        assert!(variance_margin(1000) < variance_margin(64));
    }

    #[test]
    fn budgets_take_the_margin_only_where_few_samples_are_needed() {
        let (margin, cap, samples) = (variance_margin(PILOT), 25_000, 100_000);
        assert_eq!(budget(3.0, margin, cap, samples), PILOT);
        assert_eq!(budget(100.0, margin, cap, samples), 138);
        // Past the margin's reach: the need as seen, but never below MARGIN_UP_TO.
        assert_eq!(budget(200.0, margin, cap, samples), MARGIN_UP_TO);
        assert_eq!(budget(5_000.2, margin, cap, samples), 5_001);
        // Beyond the cap, every sample: an exact mean; so too for a zero mean.
        assert_eq!(budget(24_000.0, margin, cap, samples), 24_000);
        assert_eq!(budget(25_001.0, margin, cap, samples), samples);
        assert_eq!(budget(f64::INFINITY, margin, cap, samples), samples);
        // Under a cap below MARGIN_UP_TO, a need (with the margin) above it asks for every sample.
        assert_eq!(budget(50.0, margin, 100, 1_000), 69);
        assert_eq!(budget(90.0, margin, 100, 1_000), 1_000);
        assert_eq!(budget(150.0, margin, 200, 1_000), 1_000);
    }
}
