//! What reaches the target: the record length (searched), the repeats (the 1/√N law),
//! and the spread of simulated experiments.

use crate::error::Result;

/// The shortest record (to 1 %) whose relative half-width `width_at(duration)` is within
/// `target`, given the planned `duration` and its width `now`: doubling the duration up
/// to `longest`, then bisection. `None` when `longest` is not enough.
pub(super) fn duration_needed(
    duration: f64,
    now: f64,
    target: f64,
    longest: f64,
    mut width_at: impl FnMut(f64) -> Result<f64>,
) -> Result<Option<f64>> {
    if now <= target {
        return Ok(Some(duration));
    }
    let (mut low, mut high) = (duration, duration);
    loop {
        high *= 2.0;
        if high > longest {
            return Ok(None);
        }
        if width_at(high)? <= target {
            break;
        }
        low = high;
    }
    while high - low > 0.01 * high {
        let mid = 0.5 * (low + high);
        if width_at(mid)? <= target {
            high = mid;
        } else {
            low = mid;
        }
    }
    Ok(Some(high))
}

/// The longest record the search tries: 64× the planned `duration`, and no more than
/// the budget of samples held ([`crate::budget::SAMPLES_HELD`]) for an experiment of
/// `samples` samples now. The search's cost is bounded by it: at most six doublings and
/// seven bisections, each one prediction of every quantity at once ([`Widths`]).
pub(super) fn longest_record(duration: f64, samples: f64) -> f64 {
    let per_second = samples / duration;
    (64.0 * duration).min(crate::budget::SAMPLES_HELD / per_second)
}

/// The widths of every quantity at a record length, each length predicted once and
/// shared by the searches of all quantities, the search shown as a progress line.
pub(super) struct Widths<F> {
    compute: F,
    seen: Vec<(f64, Vec<f64>)>,
    progress: crate::progress::Progress,
}

impl<F: FnMut(f64) -> Result<Vec<f64>>> Widths<F> {
    /// Widths from `compute(duration)`; progress drawn when `progress`.
    pub(super) fn new(compute: F, progress: bool) -> Self {
        Self {
            compute,
            seen: Vec::new(),
            progress: crate::progress::Progress::new(progress),
        }
    }

    /// Quantity `q`'s width for a record of `duration` s.
    pub(super) fn width(&mut self, duration: f64, q: usize) -> Result<f64> {
        if let Some((_, w)) = self.seen.iter().find(|(d, _)| *d == duration) {
            return Ok(w[q]);
        }
        self.progress.stage(&format!(
            "plan: the record-length search, predicting a record of {duration:.4} s"
        ));
        let w = (self.compute)(duration)?;
        let width = w[q];
        self.seen.push((duration, w));
        Ok(width)
    }
}

impl<F> Drop for Widths<F> {
    fn drop(&mut self) {
        self.progress.finish();
    }
}

/// Runs `draw(seed)` for the seeds 0 … n − 1 of a `--verify` on [`VERIFY_THREADS`]
/// threads (each draw depends on its seed alone, and the results keep the seeds'
/// order: the same numbers whatever the thread count), with a progress bar named `name`
/// when `progress`.
pub(crate) fn draws<T: Send>(
    n: usize,
    name: &str,
    progress: bool,
    draw: impl Fn(u64) -> Result<T> + Sync,
) -> Result<Vec<T>> {
    use rayon::prelude::*;
    use std::sync::atomic::{AtomicU64, Ordering};
    let bar = crate::progress::Progress::new(progress);
    bar.bar(name, n as u64);
    let done = AtomicU64::new(0);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(VERIFY_THREADS)
        .build()
        .map_err(|e| crate::error::ExperimentError::run("verify", e))?;
    let out = pool.install(|| {
        (0..n as u64)
            .into_par_iter()
            .map(|seed| {
                let result = draw(seed);
                bar.set_position(done.fetch_add(1, Ordering::Relaxed) + 1);
                result
            })
            .collect::<Result<Vec<T>>>()
    });
    bar.finish();
    out
}

/// The threads a `--verify` fits its draws on (as the Monte Carlo band's default).
pub(crate) const VERIFY_THREADS: usize = 2;

/// The repeats that reach `target` from `planned` repeats of relative half-width `now`:
/// the information of independent identical repeats adds up, so the width scales as
/// 1/√repeats (the Student's t factor, already near 1.96, is left as it is). `None` for
/// an infinite width.
pub(super) fn repeats_needed(planned: usize, now: f64, target: f64) -> Option<usize> {
    let needed = planned as f64 * (now / target).powi(2);
    needed.is_finite().then(|| (needed.ceil() as usize).max(1))
}

/// The sample standard deviation (n − 1) of each column of `draws` (one row per draw).
pub(crate) fn standard_deviations(draws: &[Vec<f64>]) -> Vec<f64> {
    let columns = draws.first().map_or(0, Vec::len);
    let n = draws.len() as f64;
    (0..columns)
        .map(|j| {
            let mean = draws.iter().map(|d| d[j]).sum::<f64>() / n;
            let ss = draws.iter().map(|d| (d[j] - mean).powi(2)).sum::<f64>();
            (ss / (n - 1.0)).sqrt()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeats_follow_the_square_root_law() {
        // ±2 % from 1 record to ±1 %: 4 records; from 5 records at ±1.5 %: 11.25 → 12.
        assert_eq!(repeats_needed(1, 0.02, 0.01), Some(4));
        assert_eq!(repeats_needed(5, 0.015, 0.01), Some(12));
        assert_eq!(repeats_needed(3, f64::INFINITY, 0.01), None);
    }

    #[test]
    fn the_search_brackets_then_bisects() {
        // width = 1/√T: the target 0.2 needs T = 25 from T = 1, found to 1 %.
        let found = duration_needed(1.0, 1.0, 0.2, 64.0, |t| Ok(1.0 / t.sqrt())).unwrap();
        let t = found.unwrap();
        assert!((25.0..=25.0 / 0.99).contains(&t), "{t}");
        assert_eq!(
            duration_needed(1.0, 1.0, 1e-3, 64.0, |_| Ok(1.0)).unwrap(),
            None
        );
    }

    #[test]
    fn standard_deviation_of_known_draws() {
        let draws = vec![vec![1.0, 0.0], vec![3.0, 0.0]];
        assert_eq!(standard_deviations(&draws), [2f64.sqrt(), 0.0]);
    }
}
