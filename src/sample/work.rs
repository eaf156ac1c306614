//! What the sampling loop did, counted per shape type: how many pair-samples it bounded and how each was
//! settled, from the cheap sphere bounds to an exact query; and where a run's time went, per phase. The
//! counts explain a run's time (see docs/benchmarks.md); they never enter the sample records, and every
//! chunk's work is fixed by the seed, so they are the same at any thread count. The times are the
//! run's own (wall clock), reported and never written into the URDD.

use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// Where a run's wall-clock time went (seconds), phase by phase.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Phases {
    /// Loading the robot and the shapes and, to sample, building the pairs' distance tables (a merge
    /// of shards builds none).
    pub load: f64,
    /// The sampling loop: the mean's pilot, the scout and the chunks (or, merging shards, reading
    /// and merging them).
    pub sampling: f64,
    /// Rigid pairs, reasons, witnesses and the targeted collision search.
    pub search: f64,
    /// The link-level verdicts on the exact geometry, with their `never` certificates.
    pub verdicts: f64,
}

impl Phases {
    /// The seconds after loading: what a report calls its run's time.
    pub fn after_load(&self) -> f64 {
        self.sampling + self.search + self.verdicts
    }
}

/// Reads the time at the end of each phase.
pub(super) struct Laps(Instant);

impl Laps {
    /// Starts the first phase now.
    pub(super) fn start() -> Laps {
        Laps(Instant::now())
    }

    /// Seconds since the last lap (or the start), and starts the next phase.
    pub(super) fn lap(&mut self) -> f64 {
        let now = Instant::now();
        let seconds = (now - self.0).as_secs_f64();
        self.0 = now;
        seconds
    }
}

/// How the engine settled one sample of one pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Settled {
    /// By the sphere (and table) bounds alone.
    Cheap,
    /// By the tighter bounds: tether, boxes, hint, extreme points along an axis.
    Bounds,
    /// By a GJK run that stopped once the distance was known to lie inside the extremes.
    Window,
    /// By the exact signed distance (also every sample entering the mean exactly).
    Exact,
}

/// The work of one shape type (or a sum of runs: shards add theirs in the merge).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Work {
    /// Pair-samples of moving pairs: each one's sphere bounds were evaluated.
    pub pair_samples: u64,
    /// Of those, settled by the sphere and table bounds alone.
    pub cheap: u64,
    /// Settled by the tighter bounds (tether, boxes, hint, extreme points).
    pub bounds: u64,
    /// Settled by a GJK run stopped early inside the extremes.
    pub windows: u64,
    /// Settled by an exact signed distance query.
    pub exact: u64,
}

impl Work {
    /// Adds `other`'s counts.
    pub fn add(&mut self, other: &Work) {
        self.pair_samples += other.pair_samples;
        self.cheap += other.cheap;
        self.bounds += other.bounds;
        self.windows += other.windows;
        self.exact += other.exact;
    }

    /// Counts one settled pair-sample (not `pair_samples`, counted per block).
    #[inline]
    pub(super) fn count(&mut self, settled: Settled) {
        *match settled {
            Settled::Cheap => &mut self.cheap,
            Settled::Bounds => &mut self.bounds,
            Settled::Window => &mut self.windows,
            Settled::Exact => &mut self.exact,
        } += 1;
    }
}

/// [`Work`] shared by the worker threads: each adds a chunk's (or a scout block's) counts at once.
#[derive(Debug, Default)]
pub(super) struct SharedWork([AtomicU64; 5]);

impl SharedWork {
    /// Adds a chunk's counts.
    pub(super) fn add(&self, w: &Work) {
        let fields = [w.pair_samples, w.cheap, w.bounds, w.windows, w.exact];
        for (total, n) in self.0.iter().zip(fields) {
            if n > 0 {
                total.fetch_add(n, Ordering::Relaxed);
            }
        }
    }

    /// The counts so far.
    pub(super) fn get(&self) -> Work {
        let [pair_samples, cheap, bounds, windows, exact] =
            self.0.each_ref().map(|n| n.load(Ordering::Relaxed));
        Work {
            pair_samples,
            cheap,
            bounds,
            windows,
            exact,
        }
    }
}
