//! The measuring harness: warm up, repeat a closure until a time budget is spent (within
//! a minimum and maximum count), and keep every wall time.

use std::hint::black_box;
use std::time::{Duration, Instant};

/// How long and how often each row is measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Budget {
    /// Time to spend on one row (after the warm-up). By default 1.5 s.
    pub time: Duration,
    /// Fewest repetitions, whatever the time. By default 5.
    pub min_reps: usize,
    /// Most repetitions. By default 200.
    pub max_reps: usize,
}

impl Default for Budget {
    fn default() -> Self {
        Self {
            time: Duration::from_millis(1500),
            min_reps: 5,
            max_reps: 200,
        }
    }
}

impl Budget {
    /// `--quick`: 0.3 s a row, at least 3 repetitions, at most 50.
    pub fn quick() -> Self {
        Self {
            time: Duration::from_millis(300),
            min_reps: 3,
            max_reps: 50,
        }
    }

    /// One repetition after one warm-up: for the smoke test.
    pub fn single() -> Self {
        Self {
            time: Duration::ZERO,
            min_reps: 1,
            max_reps: 1,
        }
    }
}

/// The wall times of one row's repetitions.
#[derive(Debug, Clone, PartialEq)]
pub struct Samples {
    /// Every repetition's wall time, in seconds, in the order measured.
    pub seconds: Vec<f64>,
}

impl Samples {
    /// The median (mean of the two middle values for an even count).
    pub fn median(&self) -> f64 {
        let mut s = self.seconds.clone();
        s.sort_by(f64::total_cmp);
        let n = s.len();
        if n == 0 {
            return f64::NAN;
        }
        if n % 2 == 1 {
            s[n / 2]
        } else {
            0.5 * (s[n / 2 - 1] + s[n / 2])
        }
    }

    /// The fastest repetition.
    pub fn min(&self) -> f64 {
        self.seconds.iter().copied().fold(f64::INFINITY, f64::min)
    }

    /// The slowest repetition.
    pub fn max(&self) -> f64 {
        self.seconds
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// The repetitions of `self` and `other` together.
    pub fn merged(&self, other: &Samples) -> Samples {
        let mut seconds = self.seconds.clone();
        seconds.extend_from_slice(&other.seconds);
        Samples { seconds }
    }
}

/// Runs `f` once to warm up, then repeatedly until `budget.time` is spent and at least
/// `budget.min_reps` (at most `budget.max_reps`) repetitions are timed. The result of
/// each call goes through [`black_box`] so the work cannot be optimised away.
pub fn measure<T>(budget: &Budget, mut f: impl FnMut() -> T) -> Samples {
    black_box(f());
    let mut seconds = Vec::new();
    let started = Instant::now();
    while seconds.len() < budget.max_reps
        && (seconds.len() < budget.min_reps || started.elapsed() < budget.time)
    {
        let t = Instant::now();
        black_box(f());
        seconds.push(t.elapsed().as_secs_f64());
    }
    Samples { seconds }
}

/// As [`measure`] for a fast closure: each timed repetition runs `f` `inner` times and
/// records the mean, so timer resolution does not matter for microsecond rows.
pub fn measure_batched<T>(budget: &Budget, inner: usize, mut f: impl FnMut() -> T) -> Samples {
    let inner = inner.max(1);
    let mut samples = measure(budget, || {
        for _ in 0..inner {
            black_box(f());
        }
    });
    for s in &mut samples.seconds {
        *s /= inner as f64;
    }
    samples
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_min_max_of_known_values() {
        let s = Samples {
            seconds: vec![3.0, 1.0, 2.0, 10.0],
        };
        assert_eq!(s.median(), 2.5);
        assert_eq!(s.min(), 1.0);
        assert_eq!(s.max(), 10.0);
        let odd = s.merged(&Samples { seconds: vec![0.5] });
        assert_eq!(odd.median(), 2.0);
    }

    #[test]
    fn single_budget_times_once() {
        let mut calls = 0;
        let s = measure(&Budget::single(), || calls += 1);
        assert_eq!(s.seconds.len(), 1);
        assert_eq!(calls, 2); // warm-up + one timed
    }
}
