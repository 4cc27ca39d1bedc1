//! The streaming, thread-count-independent percentile engine behind the band.
//!
//! ## The algorithm
//! Nothing of size N × T is ever stored. The samples are simulated in blocks of
//! [`LANES`], each block keeping its simulator's state, and the time axis is walked in
//! chunks of `chunk_points` columns: every block advances one chunk into a chunk buffer
//! (`buffer[block][t][lane]`, so a time column is N/8 runs of 8 contiguous values), and
//! the chunk's percentiles are then computed exactly, column after column, by one
//! tracker per level that narrows each column's search with the previous columns
//! ([`LevelTracker`]). Two chunk buffers alternate so that the percentiles of chunk c
//! (one task per level) run while chunk c + 1 is simulated (in parallel over blocks):
//! `rayon::join`, whose idle thread takes simulation blocks. Memory is two chunk buffers plus the blocks'
//! states — about 0.3 MiB per 1000 samples — whatever T, and every sample is simulated
//! exactly once.
//!
//! Every value written depends only on its sample index and its time index, and the
//! percentiles of a level are computed in column order by one task, so the result is bit-for-bit
//! the same for any thread count and any chunking.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::tracker::LevelTracker;
pub(crate) use msd_ident::LANES;

/// Samples per group: a group is simulated by one task and its values at one time are
/// contiguous in the chunk buffer (`buffer[group][t][sample]`).
pub(crate) const GROUP: usize = 8 * LANES;

/// Bytes of the two chunk buffers the engine aims at: small enough to stay in cache.
const CACHE_BYTES: usize = 1 << 20;
/// Fewest columns per chunk unless the budget forbids (fork–join overhead per chunk).
const MIN_CHUNK_POINTS: usize = 16;

/// How a run uses memory: the chunking of the time axis and the bytes it allocates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct MemoryPlan {
    /// N.
    pub samples: usize,
    /// T, points per response.
    pub points: usize,
    /// Time columns per chunk.
    pub chunk_points: usize,
    /// Chunks of the time axis: ⌈T / chunk_points⌉ (every sample is simulated once).
    pub chunks: usize,
    /// Bytes of the two N × chunk buffers (N rounded up to a multiple of [`LANES`]).
    pub buffer_bytes: usize,
    /// Bytes of the simulators' states, all blocks.
    pub state_bytes: usize,
    /// Upper bound of everything a band run allocates: the buffers, the states, the
    /// tracker, per-sample draws, flags and summaries, and the result's time series.
    pub peak_bytes: usize,
}

impl MemoryPlan {
    /// The plan for N `samples` of `points` values with `levels` percentile levels and
    /// chunk buffers of at most `max_buffer_bytes` (≥ 16·N) together. `threads` does not
    /// change the plan (the pipeline has one percentile task and a shared simulation).
    ///
    /// ```
    /// use msd_mc::MemoryPlan;
    /// let plan = MemoryPlan::new(100_000, 7501, 2, 3, 256 << 20);
    /// assert_eq!((plan.chunk_points, plan.chunks), (16, 469));
    /// assert!(plan.peak_bytes < 128 << 20);
    /// ```
    pub fn new(
        samples: usize,
        points: usize,
        threads: usize,
        levels: usize,
        max_buffer_bytes: usize,
    ) -> Self {
        let _ = threads;
        let n = samples.max(1).next_multiple_of(GROUP);
        let affordable = (max_buffer_bytes / (16 * n)).max(1);
        let wanted = (CACHE_BYTES / (16 * n)).max(MIN_CHUNK_POINTS);
        let chunk_points = wanted.min(affordable).clamp(1, points.max(1));
        let chunks = points.div_ceil(chunk_points);
        let buffer_bytes = 16 * n * chunk_points;
        let state_bytes = (n / LANES) * (msd_ident::BatchRun::MAX_BYTES + 16);
        // Tracker: keys and candidates per level, the previous column (8 per value).
        let tracker = 8 * n * (levels + 2);
        // Draw (32), ok flag (1), and the summaries' copies of the parameters, fn, ζ
        // and their sort keys (48): rounded up.
        let per_sample = 96;
        let outputs = 8 * points * (2 * levels + 4); // percentiles (twice), nominal, width, times, measured
        Self {
            samples,
            points,
            chunk_points,
            chunks,
            buffer_bytes,
            state_bytes,
            peak_bytes: buffer_bytes + state_bytes + tracker + n * per_sample + outputs,
        }
    }
}

/// The percentiles (level-major) over the good samples and which samples were good.
pub(crate) struct EngineOutput {
    pub(crate) percentiles: Vec<Vec<f64>>,
    pub(crate) ok: Vec<bool>,
}

/// A sample failed after the percentiles of earlier columns had counted it: the run
/// must be repeated without it. Holds which samples were good as far as the run went.
pub(crate) struct Restart(pub(crate) Vec<bool>);

/// Runs the band's simulations and percentiles. `start(b)` makes the state of block b
/// (samples b·LANES …); `advance(state, until, out)` produces its samples up to time
/// index `until` into `out[(t − from)·LANES + lane]` and returns which lanes are still
/// good (failed lanes' values must be +∞; lanes past the last sample must fail).
/// Returns the `levels` percentiles over the samples good at the end, or a
/// [`Restart`] when a sample failed after its values entered a percentile.
pub(crate) fn run<S, I, F>(
    plan: &MemoryPlan,
    levels: &[f64],
    progress: &(dyn Fn(usize, usize) + Sync),
    start: I,
    advance: F,
) -> Result<EngineOutput, Restart>
where
    S: Send,
    I: Fn(usize) -> S + Sync,
    F: Fn(&mut S, usize, &mut [f64]) -> [bool; LANES] + Sync,
{
    let (n, points, width) = (plan.samples, plan.points, plan.chunk_points);
    let padded = n.next_multiple_of(GROUP);
    let stride = GROUP * width;
    let mut buffers = [vec![0.0; padded * width], vec![0.0; padded * width]];
    debug_assert_eq!(16 * buffers[0].len(), plan.buffer_bytes);
    let mut states: Vec<Option<S>> = (0..padded / LANES).map(|_| None).collect();
    let mut ok = vec![true; padded];
    let total = n * plan.chunks;
    let done = AtomicUsize::new(0);

    let simulate = |chunk: usize, buffer: &mut [f64], states: &mut [Option<S>], ok: &mut [bool]| {
        let end = ((chunk + 1) * width).min(points);
        let w = end - chunk * width;
        buffer
            .par_chunks_mut(stride)
            .zip(states.par_chunks_mut(GROUP / LANES))
            .zip(ok.par_chunks_mut(GROUP))
            .enumerate()
            .for_each_init(
                || vec![0.0; LANES * width],
                |scratch, (g, ((group, states), flags))| {
                    for (k, (state, flags)) in states
                        .iter_mut()
                        .zip(flags.chunks_exact_mut(LANES))
                        .enumerate()
                    {
                        let b = g * (GROUP / LANES) + k;
                        let state = state.get_or_insert_with(|| start(b));
                        let good = advance(state, end, &mut scratch[..LANES * w]);
                        for (flag, good) in flags.iter_mut().zip(good) {
                            *flag &= good;
                        }
                        // Into the group's rows; + 0.0 turns −0.0 into +0.0, so that f64
                        // order is the keys' order.
                        for (row, values) in group
                            .chunks_exact_mut(GROUP)
                            .zip(scratch.chunks_exact(LANES))
                        {
                            for (to, v) in row[k * LANES..(k + 1) * LANES].iter_mut().zip(values) {
                                *to = v + 0.0;
                            }
                        }
                        let real = LANES.min(n.saturating_sub(b * LANES));
                        if real > 0 {
                            progress(done.fetch_add(real, Ordering::Relaxed) + real, total);
                        }
                    }
                },
            );
    };

    simulate(0, &mut buffers[0], &mut states, &mut ok);
    // Failures in the first chunk cost nothing: no percentile has been taken yet.
    let good = ok[..n].iter().filter(|&&g| g).count();
    if good == 0 {
        ok.truncate(n);
        return Ok(EngineOutput {
            percentiles: vec![Vec::new(); levels.len()],
            ok,
        });
    }
    let mut trackers: Vec<LevelTracker> = levels
        .iter()
        .map(|&level| LevelTracker::new(level, good, padded))
        .collect();
    let mut percentiles = vec![vec![0.0; points]; levels.len()];
    let mut last = vec![f64::INFINITY; padded]; // the previous chunk's last column
    let expected = ok.clone();
    for chunk in 0..plan.chunks {
        let (first, second) = buffers.split_at_mut(1);
        let (current, next) = if chunk % 2 == 0 {
            (&first[0], &mut second[0])
        } else {
            (&second[0], &mut first[0])
        };
        let t0 = chunk * width;
        let w = (t0 + width).min(points) - t0;
        rayon::join(
            || {
                trackers
                    .par_iter_mut()
                    .zip(percentiles.par_iter_mut())
                    .for_each(|(tracker, out)| {
                        tracker.chunk(current, stride, &last, &mut out[t0..t0 + w])
                    });
            },
            || {
                if chunk + 1 < plan.chunks {
                    simulate(chunk + 1, next, &mut states, &mut ok);
                }
            },
        );
        if ok != expected {
            ok.truncate(n);
            return Err(Restart(ok));
        }
        for (to, group) in last
            .chunks_exact_mut(GROUP)
            .zip(current.chunks_exact(stride))
        {
            to.copy_from_slice(&group[(w - 1) * GROUP..w * GROUP]);
        }
    }
    ok.truncate(n);
    Ok(EngineOutput { percentiles, ok })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample_rng;
    use rand::Rng;

    /// Response of sample i at time j: a_j + b_j·u with u ~ U(0, 1) from sample i's
    /// generator, so the q-th percentile is a_j + b_j·q/100.
    struct Linear {
        block: usize,
        next: usize,
    }

    fn linear(n: usize, state: &mut Linear, until: usize, out: &mut [f64]) -> [bool; LANES] {
        let good = std::array::from_fn(|lane| state.block * LANES + lane < n);
        for (lane, &ok) in good.iter().enumerate() {
            let u: f64 = sample_rng(11, (state.block * LANES + lane) as u64).random();
            for j in state.next..until {
                let v = j as f64 + (1.0 + j as f64) * u;
                out[(j - state.next) * LANES + lane] = if ok { v } else { f64::INFINITY };
            }
        }
        state.next = until;
        good
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
                |block| Linear { block, next: 0 },
                |s, until, o| linear(n, s, until, o),
            )
        });
        (plan, out.ok().expect("no failures"))
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
        let n = 300; // not a multiple of LANES: the last block has padding lanes
        let (one, reference) = run_with(n, 1, 1 << 30);
        assert_eq!(one.chunks, 1);
        for (threads, budget) in [(2, 16 * 320 * 7), (8, 16 * 320), (3, 16 * 320 * 39)] {
            let (plan, out) = run_with(n, threads, budget);
            let chunk = budget / (16 * 320); // 300 samples are 320 in groups of 64
            assert_eq!(
                (plan.chunk_points, plan.chunks),
                (chunk, 40usize.div_ceil(chunk))
            );
            assert_eq!(out.percentiles, reference.percentiles, "{threads} threads");
        }
    }

    /// Samples 3 and 77 fail at time 25 (in the third chunk of 10): the run asks for a
    /// restart naming exactly them; run again with them failed from the start, it gives
    /// the percentiles of the other samples, as a run without them would.
    #[test]
    fn a_late_failure_asks_for_a_restart_without_the_sample() {
        let (n, levels) = (200, [5.0, 50.0, 95.0]);
        let plan = MemoryPlan::new(n, 40, 1, 3, 16 * 256 * 10);
        assert_eq!(plan.chunks, 4);
        let late = |i: usize| i == 3 || i == 77;
        let run_without = |failed: &(dyn Fn(usize) -> bool + Sync), late_too: bool| {
            run(
                &plan,
                &levels,
                &|_, _| {},
                |block| Linear { block, next: 0 },
                |s, until, o| {
                    let b = s.block;
                    let mut good = linear(n, s, until, o);
                    for (lane, g) in good.iter_mut().enumerate() {
                        let i = b * LANES + lane;
                        if failed(i) || (late_too && late(i) && until > 25) {
                            *g = false;
                            (0..o.len() / LANES).for_each(|t| o[t * LANES + lane] = f64::INFINITY);
                        }
                    }
                    good
                },
            )
        };
        let Err(Restart(ok)) = run_without(&|_| false, true) else {
            panic!("a failure after the first chunk must ask for a restart");
        };
        assert_eq!((0..n).filter(|&i| !ok[i]).collect::<Vec<_>>(), [3, 77]);
        let again = run_without(&|i| i < n && !ok[i], true)
            .ok()
            .expect("no new failure");
        let reference = run_without(&late, false).ok().expect("no failure");
        assert_eq!(again.percentiles, reference.percentiles);
        assert_eq!(again.ok, ok);
    }

    /// Paper-sized response, N = 100 000: the whole plan stays far below 1 GiB (the
    /// responses alone would be 6.0 GB), on the default budget or a tiny one.
    #[test]
    fn memory_for_a_hundred_thousand_samples_is_bounded() {
        let default_budget = crate::McOptions::default().max_buffer_bytes;
        for budget in [default_budget, 16 * 100_032] {
            let plan = MemoryPlan::new(100_000, 7501, 2, 3, budget);
            assert!(plan.buffer_bytes <= budget);
            assert!(plan.peak_bytes < 128 << 20, "{plan:?}");
            assert_eq!(plan.chunks, 7501usize.div_ceil(plan.chunk_points));
        }
    }
}
