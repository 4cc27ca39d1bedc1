//! The bounded-memory, thread-count-independent percentile engine behind the band.
//!
//! ## The algorithm
//! The N × T responses would need 8·N·T bytes (6 GB for N = 100 000, T = 7501), so the
//! time axis is cut into chunks of `chunk_points` = ⌊budget / 8N⌋ columns. For each
//! chunk every sample is simulated in full (in a per-thread scratch of T values) and only
//! the chunk's columns are kept, in an N × chunk buffer; then the chunk's percentiles are
//! computed exactly, column by column, in parallel blocks of columns. So the buffer never
//! exceeds the budget, the percentiles are exact (no streaming approximation), and the
//! price is `passes` = ⌈T / chunk_points⌉ simulations per sample — one pass whenever
//! 8·N·T fits the budget (N ≤ 4473 at T = 7501 and the default 256 MiB).
//!
//! Every value written depends only on its sample index and its time index, and
//! percentiles are functions of the multiset of a column, so the result is bit-for-bit
//! the same for any thread count and any chunking.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::quantile::{key, percentiles_of_keys};

/// Bytes of the per-thread column-gather scratch the engine aims at.
const GATHER_BYTES: usize = 1 << 20;

/// How a run uses memory: the chunking of the time axis and the bytes it allocates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct MemoryPlan {
    /// N.
    pub samples: usize,
    /// T, points per response.
    pub points: usize,
    /// Time columns kept per pass.
    pub chunk_points: usize,
    /// Simulation passes over all samples: ⌈T / chunk_points⌉.
    pub passes: usize,
    /// Columns gathered per parallel percentile task.
    pub gather_columns: usize,
    /// Bytes of the N × chunk response buffer.
    pub buffer_bytes: usize,
    /// Upper bound of everything a band run allocates: the buffer, per-thread scratch
    /// (a full response and a column block), per-sample draws, flags and summaries, and
    /// the time series of the result.
    pub peak_bytes: usize,
}

impl MemoryPlan {
    /// The plan for N `samples` of `points` values on `threads` threads with `levels`
    /// percentile levels and a response buffer of at most `max_buffer_bytes` (≥ 8·N).
    ///
    /// ```
    /// use msd_mc::MemoryPlan;
    /// let plan = MemoryPlan::new(100_000, 7501, 2, 3, 256 << 20);
    /// assert_eq!((plan.chunk_points, plan.passes), (335, 23));
    /// assert!(plan.peak_bytes < 300 << 20);
    /// ```
    pub fn new(
        samples: usize,
        points: usize,
        threads: usize,
        levels: usize,
        max_buffer_bytes: usize,
    ) -> Self {
        let n = samples.max(1);
        let chunk_points = (max_buffer_bytes / (8 * n)).clamp(1, points.max(1));
        let passes = points.div_ceil(chunk_points);
        let gather_columns = (GATHER_BYTES / (8 * n)).clamp(1, 64);
        let buffer_bytes = 8 * n * chunk_points;
        let per_thread = 8 * points + 8 * n * gather_columns + 8 * levels * gather_columns;
        // Draw (32), ok flag (1), index of a good sample (8), and the summaries' copies of
        // the parameters, fn, ζ and their sort keys (48): rounded up.
        let per_sample = 96;
        let outputs = 8 * points * (2 * levels + 4); // percentiles (twice: transposed), nominal, width, times, measured
        Self {
            samples,
            points,
            chunk_points,
            passes,
            gather_columns,
            buffer_bytes,
            peak_bytes: buffer_bytes + threads * per_thread + n * per_sample + outputs,
        }
    }
}

/// Output of the engine: the percentiles (level-major) and which samples succeeded.
pub(crate) struct EngineOutput {
    pub(crate) percentiles: Vec<Vec<f64>>,
    pub(crate) ok: Vec<bool>,
}

/// Runs `simulate(i, scratch)` (fills the full response of sample i, returns success)
/// for every sample, `plan.passes` times, on the current rayon pool, and returns the
/// pointwise `levels` percentiles over the successful samples.
pub(crate) fn run<F>(
    plan: &MemoryPlan,
    levels: &[f64],
    progress: &(dyn Fn(usize, usize) + Sync),
    simulate: F,
) -> EngineOutput
where
    F: Fn(usize, &mut [f64]) -> bool + Sync,
{
    let (n, points, l) = (plan.samples, plan.points, levels.len());
    let mut buffer = vec![0.0; n * plan.chunk_points];
    debug_assert_eq!(8 * buffer.len(), plan.buffer_bytes);
    let mut ok = vec![false; n];
    let mut transposed = vec![0.0; points * l]; // time-major: levels of point t at t·l
    let total = n * plan.passes;
    let done = AtomicUsize::new(0);
    for pass in 0..plan.passes {
        let start = pass * plan.chunk_points;
        let end = (start + plan.chunk_points).min(points);
        let width = end - start;
        let rows = &mut buffer[..n * width];
        rows.par_chunks_mut(width)
            .zip(ok.par_iter_mut())
            .enumerate()
            .for_each_init(
                || vec![0.0; points],
                |scratch, (i, (row, flag))| {
                    *flag = simulate(i, scratch);
                    if *flag {
                        row.copy_from_slice(&scratch[start..end]);
                    }
                    progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
                },
            );
        let good: Vec<usize> = (0..n).filter(|&i| ok[i]).collect();
        if good.is_empty() {
            break;
        }
        let rows = &buffer[..n * width];
        let g = plan.gather_columns;
        transposed[start * l..end * l]
            .par_chunks_mut(g * l)
            .enumerate()
            .for_each_init(
                || vec![0i64; good.len() * g],
                |column, (block, out)| {
                    let c0 = block * g;
                    let cols = out.len() / l;
                    for (k, &i) in good.iter().enumerate() {
                        let row = &rows[i * width + c0..i * width + c0 + cols];
                        for (j, &v) in row.iter().enumerate() {
                            column[j * good.len() + k] = key(v);
                        }
                    }
                    for j in 0..cols {
                        let values = &mut column[j * good.len()..(j + 1) * good.len()];
                        percentiles_of_keys(values, levels, &mut out[j * l..(j + 1) * l]);
                    }
                },
            );
    }
    let percentiles = (0..l)
        .map(|k| (0..points).map(|t| transposed[t * l + k]).collect())
        .collect();
    EngineOutput { percentiles, ok }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample_rng;
    use rand::Rng;

    /// Response of sample i at time j: a_j + b_j·u with u ~ U(0, 1) from sample i's
    /// generator, so the q-th percentile is a_j + b_j·q/100.
    fn linear(i: usize, out: &mut [f64]) -> bool {
        let u: f64 = sample_rng(11, i as u64).random();
        for (j, v) in out.iter_mut().enumerate() {
            *v = j as f64 + (1.0 + j as f64) * u;
        }
        true
    }

    fn run_with(n: usize, threads: usize, budget: usize) -> (MemoryPlan, EngineOutput) {
        let levels = [5.0, 50.0, 95.0];
        let plan = MemoryPlan::new(n, 40, threads, 3, budget);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let out = pool.install(|| run(&plan, &levels, &|_, _| {}, linear));
        (plan, out)
    }

    /// The q-quantile estimate of N uniform draws has standard error √(q(1−q)/N)/f with
    /// density f = 1/b_j; with the ½-step interpolation a bias of at most b_j/N. Allow 5σ.
    #[test]
    fn percentiles_of_a_linear_function_of_uniform_draws() {
        let n = 4000;
        let (_, out) = run_with(n, 2, 1 << 30);
        for (k, q) in [0.05, 0.5, 0.95].into_iter().enumerate() {
            for j in 0..40 {
                let b = 1.0 + j as f64;
                let exact = j as f64 + b * q;
                let bound = 5.0 * b * (q * (1.0 - q) / n as f64).sqrt() + b / n as f64;
                let got = out.percentiles[k][j];
                assert!(
                    (got - exact).abs() < bound,
                    "q {q}, t {j}: {got} vs {exact}"
                );
            }
        }
    }

    #[test]
    fn chunking_and_threads_do_not_change_a_bit() {
        let n = 300;
        let (one, reference) = run_with(n, 1, 1 << 30);
        assert_eq!(one.passes, 1);
        for (threads, budget) in [(2, 8 * n * 7), (8, 8 * n), (3, 8 * n * 40)] {
            let (plan, out) = run_with(n, threads, budget);
            assert_eq!(plan.passes, 40usize.div_ceil(budget / (8 * n)));
            assert_eq!(out.percentiles, reference.percentiles, "{threads} threads");
        }
    }

    /// Paper-sized response, N = 100 000: the buffer and the whole plan stay far below
    /// 1 GiB (the unchunked buffer alone would be 6.0 GB).
    #[test]
    fn memory_for_a_hundred_thousand_samples_is_bounded() {
        let default_budget = crate::McOptions::default().max_buffer_bytes;
        for threads in [1, 2, 8] {
            let plan = MemoryPlan::new(100_000, 7501, threads, 3, default_budget);
            assert!(plan.buffer_bytes <= default_budget);
            assert!(plan.peak_bytes < 300 << 20, "{plan:?}");
            assert_eq!(plan.passes, 23);
        }
    }
}
