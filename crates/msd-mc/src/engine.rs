//! The bounded-memory, thread-count-independent percentile engine behind the band.
//!
//! ## The algorithm
//! The N × T responses would need 8·N·T bytes (6 GB for N = 100 000, T = 7501), so the
//! time axis is cut into chunks of `chunk_points` = ⌊budget / 8N⌋ columns. Samples are
//! simulated in blocks of [`LANES`] (stepped together by the exact backend) and each
//! block keeps only the chunk's columns, time-major within the block
//! (`buffer[block][t][lane]`), so a time column is gathered from N/8 runs of 8 contiguous
//! values. Then the chunk's percentiles are computed exactly, column by column, in
//! parallel blocks of columns. So the buffer never exceeds the budget, the percentiles
//! are exact (no streaming approximation), and the price is `passes` =
//! ⌈T / chunk_points⌉ simulations per sample — one pass whenever 8·N·T fits the budget
//! (N ≤ 4473 at T = 7501 and the default 256 MiB).
//!
//! Every value written depends only on its sample index and its time index, and
//! percentiles are functions of the multiset of a column, so the result is bit-for-bit
//! the same for any thread count and any chunking.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::quantile::ColumnTracker;
pub(crate) use msd_ident::LANES;

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
    /// Bytes of the N × chunk response buffer (N rounded up to a multiple of [`LANES`]).
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
        let n = samples.max(1).next_multiple_of(LANES);
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

/// Runs `simulate(scratch, block, range, out, ok)` (`scratch` made per worker by
/// `scratch()`) for every block of [`LANES`] samples (block b
/// holds samples b·LANES …; it writes sample b·LANES + lane's response at the samples
/// `range` to `out[(t − range.start)·LANES + lane]` and its success to `ok[lane]`),
/// `plan.passes` times, on the current rayon pool, and returns the pointwise `levels`
/// percentiles over the successful samples. Lanes past the last sample are ignored.
pub(crate) fn run<S, I, F>(
    plan: &MemoryPlan,
    levels: &[f64],
    progress: &(dyn Fn(usize, usize) + Sync),
    scratch: I,
    simulate: F,
) -> EngineOutput
where
    I: Fn() -> S + Sync + Send,
    F: Fn(&mut S, usize, std::ops::Range<usize>, &mut [f64], &mut [bool]) + Sync,
{
    let (n, points, l) = (plan.samples, plan.points, levels.len());
    let padded = n.next_multiple_of(LANES);
    let mut buffer = vec![0.0; padded * plan.chunk_points];
    debug_assert_eq!(8 * buffer.len(), plan.buffer_bytes);
    let mut ok = vec![false; padded];
    let mut transposed = vec![0.0; points * l]; // time-major: levels of point t at t·l
    let total = n * plan.passes;
    let done = AtomicUsize::new(0);
    for pass in 0..plan.passes {
        let start = pass * plan.chunk_points;
        let end = (start + plan.chunk_points).min(points);
        let width = end - start;
        let blocks = &mut buffer[..padded * width];
        blocks
            .par_chunks_mut(LANES * width)
            .zip(ok.par_chunks_mut(LANES))
            .enumerate()
            .for_each_init(&scratch, |scratch, (b, (block, flags))| {
                simulate(scratch, b, start..end, block, flags);
                let real = LANES.min(n - b * LANES);
                flags[real..].fill(false);
                // One call per simulation, as documented (the lanes finish together).
                for _ in 0..real {
                    progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
                }
            });
        let good: Vec<usize> = (0..n).filter(|&i| ok[i]).collect();
        if good.is_empty() {
            break;
        }
        let blocks = &buffer[..padded * width];
        let g = plan.gather_columns;
        let all_good = good.len() == n;
        transposed[start * l..end * l]
            .par_chunks_mut(g * l)
            .enumerate()
            .for_each_init(
                || {
                    let tracker = ColumnTracker::new(levels, good.len());
                    (vec![0.0; good.len() * g], tracker)
                },
                |(columns, tracker), (chunk, out)| {
                    let c0 = chunk * g;
                    let cols = out.len() / l;
                    let columns = &mut columns[..good.len() * cols];
                    // columns[j·G + k]: sample good[k] at column c0 + j (G = good samples).
                    if all_good {
                        // Block by block: 8 contiguous values per column.
                        for (b, block) in blocks.chunks_exact(LANES * width).enumerate() {
                            let lanes = LANES.min(n - b * LANES);
                            for j in 0..cols {
                                let from = &block[(c0 + j) * LANES..(c0 + j) * LANES + lanes];
                                let to = j * n + b * LANES;
                                // + 0.0 turns −0.0 into +0.0: f64 order = key order.
                                for (t, &f) in columns[to..to + lanes].iter_mut().zip(from) {
                                    *t = f + 0.0;
                                }
                            }
                        }
                    } else {
                        for (k, &i) in good.iter().enumerate() {
                            let base = (i / LANES) * LANES * width + c0 * LANES + i % LANES;
                            for j in 0..cols {
                                columns[j * good.len() + k] = blocks[base + j * LANES] + 0.0;
                            }
                        }
                    }
                    tracker.reset();
                    let mut previous: Option<&[f64]> = None;
                    for (j, column) in columns.chunks_exact(good.len()).enumerate() {
                        let change = previous.map_or(f64::INFINITY, |p| {
                            p.iter()
                                .zip(column)
                                .map(|(a, b)| (a - b).abs())
                                .fold(0.0, f64::max)
                        });
                        tracker.percentiles(column, change, &mut out[j * l..(j + 1) * l]);
                        previous = Some(column);
                    }
                },
            );
    }
    let percentiles = (0..l)
        .map(|k| (0..points).map(|t| transposed[t * l + k]).collect())
        .collect();
    ok.truncate(n);
    EngineOutput { percentiles, ok }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample_rng;
    use rand::Rng;

    /// Response of sample i at time j: a_j + b_j·u with u ~ U(0, 1) from sample i's
    /// generator, so the q-th percentile is a_j + b_j·q/100.
    fn linear(b: usize, range: std::ops::Range<usize>, out: &mut [f64], ok: &mut [bool]) {
        for lane in 0..LANES {
            let u: f64 = sample_rng(11, (b * LANES + lane) as u64).random();
            for j in range.clone() {
                out[(j - range.start) * LANES + lane] = j as f64 + (1.0 + j as f64) * u;
            }
            ok[lane] = true;
        }
    }

    fn run_with(n: usize, threads: usize, budget: usize) -> (MemoryPlan, EngineOutput) {
        let levels = [5.0, 50.0, 95.0];
        let plan = MemoryPlan::new(n, 40, threads, 3, budget);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let out = pool.install(|| {
            run(
                &plan,
                &levels,
                &|_, _| {},
                || (),
                |_, b, r, o, k| linear(b, r, o, k),
            )
        });
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
            let chunk = (budget / (8 * n.next_multiple_of(LANES))).max(1);
            assert_eq!(plan.passes, 40usize.div_ceil(chunk));
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
