//! Exact percentiles with MATLAB's `prctile` convention, and summaries of scalars.
//!
//! ## The definition
//! For n sorted values x₍₁₎ ≤ … ≤ x₍ₙ₎, x₍ᵢ₎ is taken as the 100·(i − ½)/n percentile;
//! between these points the percentile is interpolated linearly, below the first it is
//! x₍₁₎ and above the last x₍ₙ₎ (MATLAB's `prctile`, Hyndman & Fan's definition 5). The
//! order statistics are found by selection (`select_nth_unstable` on integer keys that
//! order like `f64::total_cmp`), not a full sort, so
//! one time column of N values costs O(N) per level; the result depends only on the
//! multiset of values, never on their order.

use serde::{Deserialize, Serialize};

/// Where the `level` percentile of n sorted values lies: the 0-based rank of the lower
/// neighbour and the interpolation fraction towards the next.
pub(crate) fn position(n: usize, level: f64) -> (usize, f64) {
    let h = n as f64 * level / 100.0 - 0.5;
    if h <= 0.0 {
        (0, 0.0)
    } else if h >= (n - 1) as f64 {
        (n - 1, 0.0)
    } else {
        let floor = h.floor();
        (floor as usize, h - floor)
    }
}

/// The integer key of `x` whose order is `f64::total_cmp`'s, −0.0 counted as +0.0 (so
/// that on values that are not NaN it is the order of `<`; [`value`] gives the value
/// back, zeros as +0.0).
pub(crate) fn key(x: f64) -> i64 {
    let bits = (x + 0.0).to_bits() as i64;
    bits ^ (((bits >> 63) as u64) >> 1) as i64
}

fn value(key: i64) -> f64 {
    f64::from_bits((key ^ (((key >> 63) as u64) >> 1) as i64) as u64)
}

/// The `levels` percentiles (ascending, in [0, 100]) of the values whose [`key`]s are
/// `keys` (finite, non-empty), written to `out`. Reorders `keys`. Selecting on integer
/// keys is exact and about twice as fast as on `f64::total_cmp`.
pub(crate) fn percentiles_of_keys(keys: &mut [i64], levels: &[f64], out: &mut [f64]) {
    let n = keys.len();
    debug_assert!(n > 0 && levels.len() == out.len());
    // keys[..start] hold the `start` smallest keys, in some order.
    let mut start = 0;
    for (level, slot) in levels.iter().zip(out.iter_mut()) {
        let (rank, fraction) = position(n, *level);
        let rank = rank.max(start);
        let x = value(*keys[start..].select_nth_unstable(rank - start).1);
        start = rank;
        *slot = if fraction > 0.0 {
            let next = value(keys[rank + 1..].iter().copied().fold(i64::MAX, i64::min));
            x + fraction * (next - x)
        } else {
            x
        };
    }
}

/// The values of ranks `rank` and `next` (`rank ≤ next ≤ rank + 1`) among `keys`.
pub(crate) fn order_statistics(keys: &mut [i64], rank: usize, next: usize) -> (f64, f64) {
    // A few dozen keys (a tracker's window) sort faster than they select.
    if keys.len() <= 48 {
        keys.sort_unstable();
        return (value(keys[rank]), value(keys[next]));
    }
    let x = *keys.select_nth_unstable(rank).1;
    let y = if next == rank {
        x
    } else {
        keys[rank + 1..].iter().copied().fold(i64::MAX, i64::min)
    };
    (value(x), value(y))
}

/// As [`percentiles_of_keys`], for plain values.
pub(crate) fn percentiles(values: &[f64], levels: &[f64], out: &mut [f64]) {
    let mut keys: Vec<i64> = values.iter().map(|&v| key(v)).collect();
    percentiles_of_keys(&mut keys, levels, out);
}

/// Mean, standard deviation, extremes and percentiles of a scalar across the samples.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Arithmetic mean (summed in sample order).
    pub mean: f64,
    /// Sample standard deviation (n − 1 in the denominator; 0 for one value).
    pub std: f64,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
    /// (level in percent, value) at the run's percentile levels.
    pub percentiles: Vec<(f64, f64)>,
}

impl Summary {
    /// Summarises `values` (finite, non-empty) at `levels`.
    pub(crate) fn new(values: &[f64], levels: &[f64]) -> Self {
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let ss: f64 = values.iter().map(|v| (v - mean) * (v - mean)).sum();
        let std = if values.len() > 1 {
            (ss / (n - 1.0)).sqrt()
        } else {
            0.0
        };
        let mut out = vec![0.0; levels.len()];
        percentiles(values, levels, &mut out);
        Self {
            mean,
            std,
            min: values.iter().copied().fold(f64::INFINITY, f64::min),
            max: values.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            percentiles: levels.iter().copied().zip(out).collect(),
        }
    }
}

impl std::fmt::Display for Summary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "mean {:.6}, std {:.6}", self.mean, self.std)?;
        for (level, value) in &self.percentiles {
            write!(f, ", P{level} {value:.6}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// MATLAB: prctile(1:10, [0 5 10 50 72 95 100]) = [1 1 1.5 5.5 7.7 10 10].
    #[test]
    fn matches_matlab_prctile() {
        let v: Vec<f64> = (1..=10).rev().map(f64::from).collect();
        let levels = [0.0, 5.0, 10.0, 50.0, 72.0, 95.0, 100.0];
        let mut out = [0.0; 7];
        percentiles(&v, &levels, &mut out);
        let expected = [1.0, 1.0, 1.5, 5.5, 7.7, 10.0, 10.0];
        for (a, b) in out.iter().zip(expected) {
            assert!((a - b).abs() < 1e-12, "{out:?}");
        }
    }

    #[test]
    fn keys_order_like_less_than_and_round_trip() {
        let xs = [
            -f64::MAX,
            -2.5,
            -1e-300,
            0.0,
            1e-300,
            3.0,
            f64::MAX,
            f64::INFINITY,
        ];
        for w in xs.windows(2) {
            assert!(key(w[0]) < key(w[1]));
        }
        for x in xs {
            assert_eq!(value(key(x)).to_bits(), x.to_bits());
        }
        assert_eq!(key(-0.0), key(0.0)); // as -0.0 == 0.0
        assert_eq!(value(key(-0.0)).to_bits(), 0.0f64.to_bits());
    }

    #[test]
    fn summary_of_known_values() {
        let s = Summary::new(&[2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0], &[50.0]);
        assert_eq!(s.mean, 5.0);
        assert!((s.std - (32.0f64 / 7.0).sqrt()).abs() < 1e-15);
        assert_eq!((s.min, s.max), (2.0, 9.0));
        assert_eq!(s.percentiles, vec![(50.0, 4.5)]);
    }
}
