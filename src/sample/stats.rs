//! Per-pair distance statistics that merge exactly: any split of the samples (threads, chunks, shards)
//! gives the same bytes.

use serde::{Deserialize, Serialize};

/// Distances are summed in fixed point (1e-12 m) so the sum does not depend on the order of addition.
const SUM_UNITS_PER_METRE: f64 = 1e12;

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
    /// Sum of the distances entering the mean, in units of 1e-12 m.
    #[serde(with = "i128_string")]
    pub sum: i128,
    /// Sum of the squared distances entering the mean, in units of 1e-12 m^2.
    #[serde(with = "i128_string")]
    pub sum_sq: i128,
    /// Number of distances in `sum`.
    pub mean_count: u64,
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

    /// Adds `d` to the mean.
    #[inline]
    pub fn observe_mean(&mut self, d: f64) {
        self.sum += (d * SUM_UNITS_PER_METRE).round() as i128;
        self.sum_sq += (d * d * SUM_UNITS_PER_METRE).round() as i128;
        self.mean_count += 1;
    }

    /// The mean of the distances added, or NaN when none were.
    pub fn mean(&self) -> f64 {
        if self.mean_count == 0 {
            f64::NAN
        } else {
            self.sum as f64 / SUM_UNITS_PER_METRE / self.mean_count as f64
        }
    }

    /// The standard deviation of the distances added (0 for fewer than two).
    pub fn std(&self) -> f64 {
        if self.mean_count < 2 {
            return 0.0;
        }
        let n = self.mean_count as f64;
        let mean = self.mean();
        let var = self.sum_sq as f64 / SUM_UNITS_PER_METRE / n - mean * mean;
        (var.max(0.0) * n / (n - 1.0)).sqrt()
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
    fn merge_is_order_independent() {
        let ds = [0.3, -0.01, 0.25, 0.3, 0.7, -0.01, 0.1];
        let mut all = PairStats::default();
        for (k, d) in ds.iter().enumerate() {
            all.observe_extremes(*d, k as u64);
            all.observe_mean(*d);
        }
        let mut a = PairStats::default();
        let mut b = PairStats::default();
        for (k, d) in ds.iter().enumerate() {
            let s = if k % 2 == 0 { &mut a } else { &mut b };
            s.observe_extremes(*d, k as u64);
            s.observe_mean(*d);
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
}
