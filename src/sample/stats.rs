//! Per-pair distance statistics that merge exactly: any split of the samples (threads, chunks, shards)
//! gives the same bytes.

use serde::{Deserialize, Serialize};

/// Distances are summed in fixed point (1e-12 m) so the sum does not depend on the order of addition.
const SUM_UNITS_PER_METRE: f64 = 1e12;

/// `x` in fixed point: `(x * 1e12).round() as i128`, without the slow float-to-i128 conversion and
/// `round` library calls in the range robots need (|x| below 9,000 km).
#[inline]
fn fixed(x: f64) -> i128 {
    let y = x * SUM_UNITS_PER_METRE;
    if y.abs() < 9.0e18 {
        // Truncation toward zero is exact in i64 here, and so is the fraction left over.
        let t = y as i64;
        let frac = y - t as f64;
        i128::from(t + i64::from(frac >= 0.5) - i64::from(frac <= -0.5))
    } else {
        y.round() as i128
    }
}

/// Statistics of one shape pair over a set of samples.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PairStats {
    /// Smallest signed distance seen (m); +inf (null in JSON) before any.
    #[serde(with = "pos_inf_as_null")]
    pub min: f64,
    /// Sample index where `min` was first reached (smallest index on ties).
    pub min_sample: u64,
    /// Largest signed distance seen (m); -inf (null in JSON) before any.
    #[serde(with = "neg_inf_as_null")]
    pub max: f64,
    /// Sample index where `max` was first reached.
    pub max_sample: u64,
    /// Sum of the exact distances entering the mean, in units of 1e-12 m.
    #[serde(with = "i128_string")]
    pub sum: i128,
    /// Sum of their squares, in units of 1e-12 m^2.
    #[serde(with = "i128_string")]
    pub sum_sq: i128,
    /// Number of distances in `sum`.
    pub mean_count: u64,
    /// Sum of the control bound over the same samples as `sum` (1e-12 m).
    #[serde(with = "i128_string", default)]
    pub ctl_sum: i128,
    /// Sum of its squares over those samples (1e-12 m^2).
    #[serde(with = "i128_string", default)]
    pub ctl_sq: i128,
    /// Sum of distance times control bound over those samples (1e-12 m^2).
    #[serde(with = "i128_string", default)]
    pub ctl_cross: i128,
    /// Sum of the control bound over every sample (1e-12 m).
    #[serde(with = "i128_string", default)]
    pub bound_sum: i128,
    /// Number of samples in `bound_sum`.
    #[serde(default)]
    pub bound_count: u64,
    /// Samples in collision (signed distance <= 0).
    pub collisions: u64,
}

impl Default for PairStats {
    fn default() -> Self {
        PairStats {
            min: f64::INFINITY,
            min_sample: u64::MAX,
            max: f64::NEG_INFINITY,
            max_sample: u64::MAX,
            sum: 0,
            sum_sq: 0,
            mean_count: 0,
            ctl_sum: 0,
            ctl_sq: 0,
            ctl_cross: 0,
            bound_sum: 0,
            bound_count: 0,
            collisions: 0,
        }
    }
}

impl PairStats {
    /// Whether a distance bounded below by `lower` at sample `k` could lower `min` by more than `tol`
    /// (with `tol == 0`, change it at all, ties included).
    #[inline]
    pub fn could_lower_min(&self, lower: f64, k: u64, tol: f64) -> bool {
        lower < self.min - tol || (tol == 0.0 && lower == self.min && k < self.min_sample)
    }

    /// Whether a distance bounded above by `upper` at sample `k` could raise `max` by more than `tol`.
    #[inline]
    pub fn could_raise_max(&self, upper: f64, k: u64, tol: f64) -> bool {
        upper > self.max + tol || (tol == 0.0 && upper == self.max && k < self.max_sample)
    }

    /// Records an exact distance `d` at sample `k` for the extremes.
    #[inline]
    pub fn observe_extremes(&mut self, d: f64, k: u64) {
        if d < self.min || (d == self.min && k < self.min_sample) {
            self.min = d;
            self.min_sample = k;
        }
        if d > self.max || (d == self.max && k < self.max_sample) {
            self.max = d;
            self.max_sample = k;
        }
    }

    /// Adds a sample's control bound (a cheap function of the configuration, computed for every
    /// sample) to the control mean.
    #[inline]
    pub fn observe_bound(&mut self, bound: f64) {
        self.bound_sum += fixed(bound);
        self.bound_count += 1;
    }

    /// [`PairStats::observe_bound`] for a block of samples at once: summed in f64, in order, and the
    /// sum added in fixed point. Every run places the same blocks (the pilot's and the scout's, then
    /// aligned to the block length within each chunk), so the sum, and with it the merged total, is the same in any run; it differs
    /// from adding each bound in fixed point by rounding alone (below 1e-15 m per sample).
    #[inline]
    pub fn observe_bounds(&mut self, bounds: impl ExactSizeIterator<Item = f64>) {
        self.bound_count += bounds.len() as u64;
        self.bound_sum += fixed(bounds.sum::<f64>());
    }

    /// Adds the samples of a block (the first numbered `first`) at exact distances `d` (two spheres):
    /// every one to the control mean (its bound is its distance) and the collisions, the first
    /// `exact_mean` to the mean, and the block's extremes exactly (the first sample on ties, as one
    /// sample after another would). In passes without branches on the samples, with four running sums
    /// of the control (its bits differ from one running sum's, as the shard format's version says).
    pub fn observe_exact_block(&mut self, d: &[f64], first: u64, exact_mean: usize) {
        for &d in &d[..exact_mean] {
            self.observe_mean(d, d);
        }
        let (mut min, mut max, mut collisions) = (f64::INFINITY, f64::NEG_INFINITY, 0u64);
        let mut sums = [0.0; 4];
        for (k, &d) in d.iter().enumerate() {
            sums[k % 4] += d;
            min = if d < min { d } else { min };
            max = if d > max { d } else { max };
            collisions += u64::from(d <= 0.0);
        }
        self.bound_count += d.len() as u64;
        self.bound_sum += fixed((sums[0] + sums[1]) + (sums[2] + sums[3]));
        self.collisions += collisions;
        for extreme in [min, max] {
            if extreme <= self.min || extreme >= self.max {
                // The block's first sample at that extreme (one of the block's values, so present).
                let kk = d.iter().position(|&x| x == extreme).unwrap_or_default();
                self.observe_extremes(extreme, first + kk as u64);
            }
        }
    }

    /// Adds an exact distance `d` at a sample whose control bound is `bound` to the mean estimate.
    #[inline]
    pub fn observe_mean(&mut self, d: f64, bound: f64) {
        self.sum += fixed(d);
        self.sum_sq += fixed(d * d);
        self.ctl_sum += fixed(bound);
        self.ctl_sq += fixed(bound * bound);
        self.ctl_cross += fixed(d * bound);
        self.mean_count += 1;
    }

    /// Means of d, L, d^2, L^2, dL over the mean samples.
    fn moments(&self) -> [f64; 5] {
        let m = self.mean_count as f64;
        [
            self.sum,
            self.ctl_sum,
            self.sum_sq,
            self.ctl_sq,
            self.ctl_cross,
        ]
        .map(|x| x as f64 / SUM_UNITS_PER_METRE / m)
    }

    /// Regression coefficient of the distance on the control bound over the mean samples, and the
    /// residual variance (of the distance minus its regression on the bound).
    fn regression(&self) -> (f64, f64) {
        let [d, l, d2, l2, dl] = self.moments();
        let var_d = (d2 - d * d).max(0.0);
        let var_l = (l2 - l * l).max(0.0);
        let cov = dl - d * l;
        if self.bound_count == 0 || var_l <= 1e-18 {
            return (0.0, var_d);
        }
        let beta = cov / var_l;
        (beta, (var_d - cov * cov / var_l).max(0.0))
    }

    /// The mean distance, by a regression (control-variate) estimator: the mean of the exact
    /// distances over the first `mean_count` samples, corrected by how far the control bound's mean
    /// over those samples is from its exact mean over every sample. The bound follows the distance,
    /// so the estimate is far less noisy than the plain subsample mean, and exact when every sample
    /// entered. NaN when nothing was added.
    pub fn mean(&self) -> f64 {
        if self.mean_count == 0 {
            return f64::NAN;
        }
        let [d, l, ..] = self.moments();
        if self.bound_count == 0 || self.mean_count < 2 {
            return d;
        }
        let bound_mean = self.bound_sum as f64 / SUM_UNITS_PER_METRE / self.bound_count as f64;
        let (beta, _) = self.regression();
        d - beta * (l - bound_mean)
    }

    /// The residual standard deviation the error of [`PairStats::mean`] scales with (0 for fewer
    /// than two samples).
    pub fn std(&self) -> f64 {
        if self.mean_count < 2 {
            return 0.0;
        }
        let n = self.mean_count as f64;
        (self.regression().1 * n / (n - 1.0)).sqrt()
    }

    /// Combines the statistics of two disjoint sample sets.
    pub fn merge(&mut self, o: &PairStats) {
        if o.min < self.min || (o.min == self.min && o.min_sample < self.min_sample) {
            self.min = o.min;
            self.min_sample = o.min_sample;
        }
        if o.max > self.max || (o.max == self.max && o.max_sample < self.max_sample) {
            self.max = o.max;
            self.max_sample = o.max_sample;
        }
        self.sum += o.sum;
        self.sum_sq += o.sum_sq;
        self.mean_count += o.mean_count;
        self.ctl_sum += o.ctl_sum;
        self.ctl_sq += o.ctl_sq;
        self.ctl_cross += o.ctl_cross;
        self.bound_sum += o.bound_sum;
        self.bound_count += o.bound_count;
        self.collisions += o.collisions;
    }
}

/// Infinite extremes (nothing seen yet) as JSON null, which JSON has instead of infinities.
macro_rules! inf_as_null {
    ($name:ident, $inf:expr) => {
        mod $name {
            use serde::{Deserialize, Deserializer, Serializer};

            pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
                if v.is_finite() {
                    s.serialize_some(v)
                } else {
                    s.serialize_none()
                }
            }

            pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
                Ok(Option::<f64>::deserialize(d)?.unwrap_or($inf))
            }
        }
    };
}
inf_as_null!(pos_inf_as_null, f64::INFINITY);
inf_as_null!(neg_inf_as_null, f64::NEG_INFINITY);

/// i128 as a decimal string (JSON numbers that large do not survive every reader).
mod i128_string {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &i128, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&v.to_string())
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<i128, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_point_rounds_like_round() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        let mut values = vec![
            0.0,
            -0.0,
            0.5e-12,
            -0.5e-12,
            1.5e-12,
            -2.5e-12,
            4_503_599_627_370_495.5 / SUM_UNITS_PER_METRE,
            1e7,
            -1e7,
            f64::NAN,
        ];
        for _ in 0..100_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            values.push(
                f64::from_bits(x % 0x4100_0000_0000_0000) * if x & 1 == 0 { 1.0 } else { -1.0 },
            );
        }
        for v in values {
            assert_eq!(fixed(v), (v * SUM_UNITS_PER_METRE).round() as i128, "{v:e}");
        }
    }

    #[test]
    fn merge_is_order_independent() {
        let ds = [0.3, -0.01, 0.25, 0.3, 0.7, -0.01, 0.1];
        let mut all = PairStats::default();
        for (k, d) in ds.iter().enumerate() {
            all.observe_extremes(*d, k as u64);
            all.observe_mean(*d, 0.5 * *d);
            all.observe_bound(0.5 * *d);
        }
        let mut a = PairStats::default();
        let mut b = PairStats::default();
        for (k, d) in ds.iter().enumerate() {
            let s = if k % 2 == 0 { &mut a } else { &mut b };
            s.observe_extremes(*d, k as u64);
            s.observe_mean(*d, 0.5 * *d);
            s.observe_bound(0.5 * *d);
        }
        let mut ab = a;
        ab.merge(&b);
        let mut ba = b;
        ba.merge(&a);
        assert_eq!(ab, all);
        assert_eq!(ba, all);
        assert_eq!(all.min_sample, 1, "ties go to the first sample");
        assert!((all.mean() - ds.iter().sum::<f64>() / 7.0).abs() < 1e-12);
    }

    #[test]
    fn control_bound_corrects_a_subsample_mean() {
        // d = bound + small noise: the subsample's bias in the bound is corrected by its exact mean.
        let n = 4000;
        let bound = |k: usize| ((k * 7919) % 1000) as f64 * 1e-4;
        let noise = |k: usize| ((k * 104_729) % 11) as f64 * 1e-6;
        let d = |k: usize| bound(k) + noise(k);
        let exact = (0..n).map(d).sum::<f64>() / n as f64;
        let mut st = PairStats::default();
        for k in 0..n {
            st.observe_bound(bound(k));
            if k < 200 {
                st.observe_mean(d(k), bound(k));
            }
        }
        let plain = (0..200).map(d).sum::<f64>() / 200.0;
        assert!((st.mean() - exact).abs() < 1e-6, "{} vs {exact}", st.mean());
        assert!((plain - exact).abs() > 10.0 * (st.mean() - exact).abs());
        assert!(st.std() < 1e-5, "residual std {}", st.std());
    }

    #[test]
    fn exact_blocks_keep_what_one_sample_after_another_would() {
        // Ties at both extremes, a collision at exactly 0, and a block that neither extreme reaches.
        let blocks: [&[f64]; 3] = [
            &[0.3, -0.1, 0.5, -0.1, 0.5, 0.0],
            &[0.2, 0.4],
            &[-0.1, 0.7, 0.7],
        ];
        let (mut by_block, mut one_by_one) = (PairStats::default(), PairStats::default());
        let mut first = 0;
        for d in blocks {
            by_block.observe_exact_block(d, first, 1);
            for (kk, &x) in d.iter().enumerate() {
                one_by_one.observe_extremes(x, first + kk as u64);
                one_by_one.collisions += u64::from(x <= 0.0);
            }
            first += d.len() as u64;
        }
        assert_eq!((by_block.min, by_block.min_sample), (-0.1, 1));
        assert_eq!((by_block.max, by_block.max_sample), (0.7, 9));
        assert_eq!(
            (
                by_block.min,
                by_block.min_sample,
                by_block.max,
                by_block.max_sample
            ),
            (
                one_by_one.min,
                one_by_one.min_sample,
                one_by_one.max,
                one_by_one.max_sample
            )
        );
        assert_eq!(by_block.collisions, 4);
        assert_eq!(by_block.collisions, one_by_one.collisions);
        assert_eq!((by_block.mean_count, by_block.bound_count), (3, 11));
        // Every sample's distance is its control bound, so the estimate is the exact mean.
        let all: Vec<f64> = blocks.concat();
        let exact = all.iter().sum::<f64>() / all.len() as f64;
        assert!(
            (by_block.mean() - exact).abs() < 1e-12,
            "{}",
            by_block.mean()
        );
    }
}
