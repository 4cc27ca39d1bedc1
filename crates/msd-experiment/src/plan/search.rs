//! What reaches the target: the record length (searched), the repeats (the 1/√N law),
//! and the spread of simulated experiments.

use crate::Result;

/// The shortest record (to 1 %) whose relative half-width `width_at(duration)` is within
/// `target`, given the planned `duration` and its width `now`: doubling the duration up
/// to 64×, then bisection. `None` when 64× is not enough.
pub(super) fn duration_needed(
    duration: f64,
    now: f64,
    target: f64,
    mut width_at: impl FnMut(f64) -> Result<f64>,
) -> Result<Option<f64>> {
    if now <= target {
        return Ok(Some(duration));
    }
    let (mut low, mut high) = (duration, duration);
    loop {
        high *= 2.0;
        if high > 64.0 * duration {
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
        let found = duration_needed(1.0, 1.0, 0.2, |t| Ok(1.0 / t.sqrt())).unwrap();
        let t = found.unwrap();
        assert!((25.0..=25.0 / 0.99).contains(&t), "{t}");
        assert_eq!(duration_needed(1.0, 1.0, 1e-3, |_| Ok(1.0)).unwrap(), None);
    }

    #[test]
    fn standard_deviation_of_known_draws() {
        let draws = vec![vec![1.0, 0.0], vec![3.0, 0.0]];
        assert_eq!(standard_deviations(&draws), [2f64.sqrt(), 0.0]);
    }
}
