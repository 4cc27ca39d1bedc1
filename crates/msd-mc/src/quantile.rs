//! Exact percentiles with MATLAB's `prctile` convention, and summaries of scalars.
//!
//! ## The definition
//! For n sorted values x₍₁₎ ≤ … ≤ x₍ₙ₎, x₍ᵢ₎ is taken as the 100·(i − ½)/n percentile;
//! between these points the percentile is interpolated linearly, below the first it is
//! x₍₁₎ and above the last x₍ₙ₎ (MATLAB's `prctile`, Hyndman & Fan's definition 5). The
//! order statistics are found by selection (`select_nth_unstable`), not a full sort, so
//! one time column of N values costs O(N) per level; the result depends only on the
//! multiset of values, never on their order.

use serde::{Deserialize, Serialize};

/// Where the `level` percentile of n sorted values lies: the 0-based rank of the lower
/// neighbour and the interpolation fraction towards the next.
fn position(n: usize, level: f64) -> (usize, f64) {
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

/// The `levels` percentiles (ascending, in [0, 100]) of `values` (finite, non-empty),
/// written to `out`. Reorders `values`.
pub(crate) fn percentiles_in_place(values: &mut [f64], levels: &[f64], out: &mut [f64]) {
    let n = values.len();
    debug_assert!(n > 0 && levels.len() == out.len());
    // values[..start] hold the `start` smallest values, in some order.
    let mut start = 0;
    for (level, slot) in levels.iter().zip(out.iter_mut()) {
        let (rank, fraction) = position(n, *level);
        let rank = rank.max(start);
        let (_, x, _) = values[start..].select_nth_unstable_by(rank - start, f64::total_cmp);
        let x = *x;
        start = rank;
        *slot = if fraction > 0.0 {
            let next = values[rank + 1..]
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            x + fraction * (next - x)
        } else {
            x
        };
    }
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
        let mut sorted = values.to_vec();
        let mut out = vec![0.0; levels.len()];
        percentiles_in_place(&mut sorted, levels, &mut out);
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
        let mut v: Vec<f64> = (1..=10).rev().map(f64::from).collect();
        let levels = [0.0, 5.0, 10.0, 50.0, 72.0, 95.0, 100.0];
        let mut out = [0.0; 7];
        percentiles_in_place(&mut v, &levels, &mut out);
        let expected = [1.0, 1.0, 1.5, 5.5, 7.7, 10.0, 10.0];
        for (a, b) in out.iter().zip(expected) {
            assert!((a - b).abs() < 1e-12, "{out:?}");
        }
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
