//! The streaming, thread-count-independent percentile engine behind the band.
//!
//! ## The algorithm
//! Nothing of size N × T is ever stored. The samples are simulated in blocks of
//! [`LANES`] (stepped together), eight blocks to a group of [`GROUP`] samples, each
//! block keeping its simulator's state; the time axis is walked in chunks of
//! `chunk_points` columns. For each chunk every group is advanced into its region of a
//! chunk buffer, one row per time holding the group's values and their envelopes
//! (smallest and largest value of the group and of each block, see
//! [`ROW`]), and the chunk's percentiles are computed exactly,
//! column after column, by one tracker per level that narrows each column's search with
//! the previous columns and skips the blocks its window does not cut
//! ([`LevelTracker`]). Two chunk buffers alternate: in phase p the level
//! trackers of chunk p − 1 and the groups of chunk p are all independent tasks.
//!
//! ## The parallel schedule
//! Every worker of the pool runs the same loop over the phases ([`run`], on
//! `rayon::broadcast`): it takes the phase's tasks one at a time, each claimed by one
//! atomic exchange — trackers first (they are the longest), starting with a tracker of
//! its own, then its own share of the groups (their simulator states and chunk regions
//! stay in its core's cache), then whatever the others left — and then waits for the
//! others at a [`SpinBarrier`]. Waiting by spinning instead of sleeping matters on a virtual
//! machine, where a worker put to sleep between two chunks was measured to miss whole
//! chunks. Memory is two chunk buffers (about 1 MiB for N = 1000) and the blocks'
//! states (about 0.5 KiB per sample) whatever T, and every sample is simulated once.
//!
//! Every value written depends only on its sample index and its time index, and a
//! level's percentiles are computed in column order by whichever worker takes each of
//! its chunks, so the result is bit-for-bit the same for any thread count and any
//! chunking.

use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, RwLock};

use crate::barrier::SpinBarrier;
pub(crate) use crate::batch::LANES;
use crate::tracker::{LevelTracker, ROW, Region, TrackerCounts, VALUES, write_envelopes};

/// Samples per group: a group is simulated by one task and its values at one time are
/// contiguous in the chunk buffer (`buffer[group][t][sample]`).
pub(crate) const GROUP: usize = 8 * LANES;

/// Bytes the two chunk buffers take per group of [`GROUP`] samples and column: its
/// values and its envelopes, twice (1408: 22 a sample).
pub(crate) const GROUP_COLUMN_BYTES: usize = 2 * 8 * ROW;

/// Bytes of the two chunk buffers the engine aims at: small enough to stay in cache.
const CACHE_BYTES: usize = 1 << 20;
/// Fewest columns per chunk unless the budget forbids (fork–join overhead per chunk).
const MIN_CHUNK_POINTS: usize = 32;

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
    /// Bytes of the two N × chunk buffers with the blocks' envelopes (N rounded up to a
    /// multiple of 64).
    pub buffer_bytes: usize,
    /// Bytes of the simulators' states, all blocks.
    pub state_bytes: usize,
    /// Upper bound of everything a band run allocates: the buffers, the states, the
    /// tracker, per-sample draws, flags and summaries, and the result's time series.
    pub peak_bytes: usize,
}

impl MemoryPlan {
    /// The plan for N `samples` of `points` values with `levels` percentile levels and
    /// chunk buffers of at most `max_buffer_bytes` (≥ 22·N) together. The thread count
    /// does not enter: the pipeline has one percentile task and a shared simulation.
    ///
    /// ```
    /// use msd_mc::MemoryPlan;
    /// let plan = MemoryPlan::new(100_000, 7501, 3, 256 << 20);
    /// assert_eq!((plan.chunk_points, plan.chunks), (32, 235));
    /// assert!(plan.peak_bytes < 160 << 20);
    /// ```
    pub fn new(samples: usize, points: usize, levels: usize, max_buffer_bytes: usize) -> Self {
        let n = samples.max(1).next_multiple_of(GROUP);
        let column = GROUP_COLUMN_BYTES * (n / GROUP);
        let affordable = (max_buffer_bytes / column).max(1);
        let wanted = (CACHE_BYTES / column).max(MIN_CHUNK_POINTS);
        let chunk_points = wanted.min(affordable).clamp(1, points.max(1));
        let chunks = points.div_ceil(chunk_points);
        let buffer_bytes = column * chunk_points;
        let state_bytes = (n / LANES) * (crate::batch::BatchRun::MAX_BYTES + 16);
        // Per level's tracker: keys and candidates (8 bytes a value each), listed blocks
        // (4 bytes a block) and the previous column with its envelopes (10.25 a value).
        let tracker = levels * (27 * n + 8);
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

/// An atomic counter alone on its cache line (workers claim items on separate lines).
#[derive(Default)]
#[repr(align(64))]
struct Padded(AtomicUsize);

/// A level's tracker and its percentile at every time.
type Level = (LevelTracker, Vec<f64>);

/// The percentiles (level-major) over the good samples and which samples were good.
#[derive(Debug)]
pub(crate) struct EngineOutput {
    pub(crate) percentiles: Vec<Vec<f64>>,
    pub(crate) ok: Vec<bool>,
    /// How each level's tracker found its order statistics.
    pub(crate) counts: Vec<TrackerCounts>,
}

/// A sample failed after the percentiles of earlier columns had counted it: the run
/// must be repeated without it. Holds which samples were good as far as the run went.
#[derive(Debug)]
pub(crate) struct Restart(pub(crate) Vec<bool>);

/// Runs the band's simulations and percentiles. `start(b)` makes the state of block b
/// (samples b·LANES …); `advance(state, until, out, stride)` produces its samples up
/// to time index `until` into `out[(t − from)·stride + lane]` and returns which lanes
/// are still good (failed lanes' values must be +∞; lanes past the last sample must fail).
/// Returns the `levels` percentiles over the samples good at the end, or a
/// [`Restart`] when a sample failed after its values entered a percentile.
///
/// Runs on every thread of `pool` at once ([`rayon::ThreadPool::broadcast`]): in
/// phase p the workers take, one at a time, the level trackers of chunk p − 1 and the
/// simulation groups of chunk p, then meet at a
/// [`SpinBarrier`]. A panic in one worker stops the others and is resumed here.
///
/// Nothing else may run on `pool` meanwhile (the band's pool is its own): a worker
/// busy elsewhere would keep the others waiting at the barrier, and two broadcasts
/// on one pool would wait on each other for ever. Call it from outside the pool.
pub(crate) fn run<S, I, F>(
    pool: &rayon::ThreadPool,
    plan: &MemoryPlan,
    levels: &[f64],
    progress: &(dyn Fn(usize, usize) + Sync),
    start: I,
    advance: F,
) -> Result<EngineOutput, Restart>
where
    S: Send,
    I: Fn(usize) -> S + Sync,
    F: Fn(&mut S, usize, &mut [f64], usize) -> [bool; LANES] + Sync,
{
    let (n, points, width, chunks) = (plan.samples, plan.points, plan.chunk_points, plan.chunks);
    let padded = n.next_multiple_of(GROUP);
    let (groups, l) = (padded / GROUP, levels.len());
    let per_group = GROUP / LANES;
    let states: Vec<Mutex<Vec<Option<S>>>> = (0..groups)
        .map(|_| Mutex::new((0..per_group).map(|_| None).collect()))
        .collect();
    let buffers = chunk_buffers(groups, width);
    debug_assert_eq!(GROUP_COLUMN_BYTES * groups * width, plan.buffer_bytes);
    let ok: Vec<AtomicBool> = (0..padded).map(|_| AtomicBool::new(true)).collect();
    // Per level: its tracker (made once the first chunk has settled the good samples)
    // and its percentiles.
    let trackers: Vec<Mutex<Option<Level>>> = (0..l).map(|_| Mutex::new(None)).collect();
    let (restart, no_good) = (AtomicBool::new(false), AtomicBool::new(false));
    // The first phase in which a reason to stop arose. After barrier p the workers stop
    // if it is ≤ p: a worker already in phase p + 1 may raise it, but then with p + 1,
    // so that every worker takes the same decision at every barrier.
    let stop = AtomicUsize::new(usize::MAX);
    let (total, done) = (n * chunks, AtomicUsize::new(0));

    // Phase p: the trackers of chunk p − 1 (p ≥ 1), then the groups of chunk p (p < chunks).
    let trackers_in = |p: usize| if p >= 1 { l } else { 0 };
    let groups_in = |p: usize| if p < chunks { groups } else { 0 };
    let span = |chunk: usize| chunk_span(chunk, width, points);

    let simulate = |chunk: usize, g: usize| {
        let (t0, w) = span(chunk);
        let mut states = states[g].lock().expect("no worker panicked");
        let mut region = buffers[chunk % 2][g].write().expect("no worker panicked");
        let buffer = region.rows_mut();
        for (k, state) in states.iter_mut().enumerate() {
            let b = g * per_group + k;
            let state = state.get_or_insert_with(|| start(b));
            // Straight into the group's rows: sample t of lane l at
            // [t·ROW + VALUES + k·LANES + l].
            let good = advance(state, t0 + w, &mut buffer[VALUES + k * LANES..], ROW);
            for (flag, good) in ok[b * LANES..(b + 1) * LANES].iter().zip(good) {
                // A failure in the first chunk is free: no percentile has been taken.
                if !good && flag.swap(false, Ordering::Relaxed) && chunk > 0 {
                    restart.store(true, Ordering::Relaxed);
                    stop.fetch_min(chunk, Ordering::Relaxed); // phase `chunk`
                }
            }
            let real = LANES.min(n.saturating_sub(b * LANES));
            if real > 0 {
                progress(done.fetch_add(real, Ordering::Relaxed) + real, total);
            }
        }
        write_envelopes(buffer, w);
    };
    let track = |chunk: usize, k: usize| {
        let mut slot = trackers[k].lock().expect("no worker panicked");
        if slot.is_none() {
            // The flags are settled: the first chunk is done.
            let good = ok[..n].iter().filter(|f| f.load(Ordering::Relaxed)).count();
            if good == 0 {
                no_good.store(true, Ordering::Relaxed);
                stop.fetch_min(chunk + 1, Ordering::Relaxed); // phase `chunk + 1`
                return;
            }
            *slot = Some((
                LevelTracker::new(levels[k], good, padded),
                vec![0.0; points],
            ));
        }
        let (tracker, out) = slot.as_mut().expect("made above");
        let guards: Vec<_> = buffers[chunk % 2]
            .iter()
            .map(|b| b.read().expect("no worker panicked"))
            .collect();
        let regions: Vec<&[f64]> = guards.iter().map(|g| g.rows()).collect();
        let (t0, w) = span(chunk);
        tracker.chunk(&regions, &mut out[t0..t0 + w]);
    };

    // claimed[i]: 1 + the last phase in which item i (trackers 0..l, then the groups)
    // was taken; a worker takes an item at most once a phase, by raising it to p + 1.
    let claimed: Vec<Padded> = (0..l + groups).map(|_| Padded::default()).collect();
    let threads = pool.current_num_threads();
    let barrier = SpinBarrier::new(threads);
    let worker = |w: usize| {
        let order = work_order(w, threads, l, groups);
        for p in 0..=chunks {
            for &i in &order {
                let available = if i < l {
                    trackers_in(p) > 0
                } else {
                    groups_in(p) > 0
                };
                match (available && claim(&claimed[i], p), i < l) {
                    (false, _) => {}
                    (true, true) => track(p - 1, i),
                    (true, false) => simulate(p, i - l),
                }
            }
            if !barrier.wait() || stop.load(Ordering::Relaxed) <= p {
                return;
            }
        }
    };
    broadcast(pool, &barrier, &worker);
    finish(&ok[..n], restart.into_inner(), trackers)
}

/// Chunk `chunk` of `width` points (the last one shorter) of a record of `points`: its
/// first point and its width.
fn chunk_span(chunk: usize, width: usize, points: usize) -> (usize, usize) {
    (
        chunk * width,
        ((chunk + 1) * width).min(points) - chunk * width,
    )
}

/// Two chunk buffers, a region of rows (envelopes and values, see `tracker`) of `width`
/// points per group; chunk c goes in buffer c % 2.
fn chunk_buffers(groups: usize, width: usize) -> [Vec<RwLock<Region>>; 2] {
    std::array::from_fn(|_| {
        (0..groups)
            .map(|_| RwLock::new(Region::new(width)))
            .collect()
    })
}

/// The order in which worker `w` of `threads` looks at the items (trackers 0..l, then the
/// groups): a tracker of its own and its own share of the groups first (their states and
/// chunk regions stay in its cache), then the rest.
fn work_order(w: usize, threads: usize, l: usize, groups: usize) -> Vec<usize> {
    let own = (groups * w / threads)..(groups * (w + 1) / threads);
    let others = (0..groups).rev().filter(|g| !own.contains(g));
    let trackers = (0..l).map(|k| (k + w) % l);
    trackers
        .chain(own.clone().chain(others).map(|g| l + g))
        .collect()
}

/// Takes an item in phase `p` unless a worker took it in this phase already: its claim
/// (1 + the last phase it was taken in) raised to p + 1 by this worker alone.
fn claim(claimed: &Padded, p: usize) -> bool {
    let taken = claimed.0.load(Ordering::Relaxed);
    taken <= p
        && claimed
            .0
            .compare_exchange(taken, p + 1, Ordering::AcqRel, Ordering::Relaxed)
            .is_ok()
}

/// Runs `worker(index)` on every thread of `pool`; a panic in one aborts the barrier
/// (so that the others return) and is resumed here once all have.
fn broadcast(pool: &rayon::ThreadPool, barrier: &SpinBarrier, worker: &(dyn Fn(usize) + Sync)) {
    let panicked: Mutex<Option<Box<dyn std::any::Any + Send>>> = Mutex::new(None);
    pool.broadcast(|context| {
        let work = || worker(context.index());
        if let Err(payload) = std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)) {
            barrier.abort();
            panicked
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .get_or_insert(payload);
        }
    });
    if let Some(payload) = panicked.into_inner().unwrap_or_else(|e| e.into_inner()) {
        std::panic::resume_unwind(payload);
    }
}

/// The run's output from the samples' flags and the levels' trackers, or a restart
/// without the samples that failed after the first chunk.
fn finish(
    ok: &[AtomicBool],
    restart: bool,
    trackers: Vec<Mutex<Option<Level>>>,
) -> Result<EngineOutput, Restart> {
    let ok: Vec<bool> = ok.iter().map(|f| f.load(Ordering::Relaxed)).collect();
    if restart {
        return Err(Restart(ok));
    }
    let (percentiles, counts) = trackers
        .into_iter()
        .map(|t| match t.into_inner().expect("no worker panicked") {
            Some((tracker, out)) => (out, tracker.counts),
            None => (Vec::new(), TrackerCounts::default()),
        })
        .unzip();
    Ok(EngineOutput {
        percentiles,
        ok,
        counts,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::draw::sample_rng;
    use rand::Rng;

    /// Response of sample i at time j: a_j + b_j·u with u ~ U(0, 1) from sample i's
    /// generator, so the q-th percentile is a_j + b_j·q/100.
    struct Linear {
        block: usize,
        next: usize,
    }

    fn linear(
        n: usize,
        state: &mut Linear,
        until: usize,
        out: &mut [f64],
        stride: usize,
    ) -> [bool; LANES] {
        let good = std::array::from_fn(|lane| state.block * LANES + lane < n);
        for (lane, &ok) in good.iter().enumerate() {
            let u: f64 = sample_rng(11, (state.block * LANES + lane) as u64).random();
            for j in state.next..until {
                let v = j as f64 + (1.0 + j as f64) * u;
                out[(j - state.next) * stride + lane] = if ok { v } else { f64::INFINITY };
            }
        }
        state.next = until;
        good
    }

    /// The engine on [`linear`], sample i failing from the stretch ending at `until`
    /// where `fails(i, until)`.
    fn run_failing(
        pool: &rayon::ThreadPool,
        plan: &MemoryPlan,
        levels: &[f64],
        n: usize,
        fails: &(dyn Fn(usize, usize) -> bool + Sync),
    ) -> Result<EngineOutput, Restart> {
        let start = |block| Linear { block, next: 0 };
        run(
            pool,
            plan,
            levels,
            &|_, _| {},
            start,
            |s, until, o, stride| {
                let (b, rows) = (s.block, until - s.next);
                let mut good = linear(n, s, until, o, stride);
                for (lane, g) in good.iter_mut().enumerate() {
                    if fails(b * LANES + lane, until) {
                        *g = false;
                        (0..rows).for_each(|t| o[t * stride + lane] = f64::INFINITY);
                    }
                }
                good
            },
        )
    }

    fn run_with(n: usize, threads: usize, budget: usize) -> (MemoryPlan, EngineOutput) {
        let levels = [5.0, 50.0, 95.0];
        let plan = MemoryPlan::new(n, 40, 3, budget);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let out = run(
            &pool,
            &plan,
            &levels,
            &|_, _| {},
            |block| Linear { block, next: 0 },
            |s, until, o, stride| linear(n, s, until, o, stride),
        );
        (plan, out.expect("no failures"))
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
        for (threads, columns) in [(2, 7), (8, 1), (3, 39)] {
            let budget = GROUP_COLUMN_BYTES * 5 * columns; // 300 samples are 5 groups of 64
            let (plan, out) = run_with(n, threads, budget);
            assert_eq!(
                (plan.chunk_points, plan.chunks),
                (columns, 40usize.div_ceil(columns))
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
        let plan = MemoryPlan::new(n, 40, 3, GROUP_COLUMN_BYTES * 4 * 10);
        assert_eq!(plan.chunks, 4);
        let late = |i: usize| i == 3 || i == 77;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let run_without = |failed: &(dyn Fn(usize) -> bool + Sync), late_too: bool| {
            let fails = |i: usize, until: usize| failed(i) || (late_too && late(i) && until > 25);
            run_failing(&pool, &plan, &levels, n, &fails)
        };
        let Err(Restart(ok)) = run_without(&|_| false, true) else {
            panic!("a failure after the first chunk must ask for a restart");
        };
        assert_eq!((0..n).filter(|&i| !ok[i]).collect::<Vec<_>>(), [3, 77]);
        let again = run_without(&|i| i < n && !ok[i], true).expect("no new failure");
        let reference = run_without(&late, false).expect("no failure");
        assert_eq!(again.percentiles, reference.percentiles);
        assert_eq!(again.ok, ok);
    }

    /// Every worker must leave at the same barrier when a run stops (a sample failing
    /// late; no good sample at all), however fast each sees the others: a worker that
    /// left one barrier early would leave the rest waiting for ever. Repeated on 2, 3 and
    /// 8 workers under a watchdog, so that a regression fails instead of hanging.
    #[test]
    fn every_worker_stops_at_the_same_barrier() {
        let (done, finished) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let (n, levels) = (200, [5.0, 50.0, 95.0]);
            let plan = MemoryPlan::new(n, 40, 3, GROUP_COLUMN_BYTES * 4 * 10);
            for threads in [2, 3, 8] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                for round in 0..30 {
                    let fails = |i: usize, until: usize| match round % 2 {
                        0 => i == 5 && until > 15, // late: a restart
                        _ => true,                 // every sample: no good one
                    };
                    let out = run_failing(&pool, &plan, &levels, n, &fails);
                    match (round % 2, out) {
                        (0, Err(Restart(ok))) => assert!(!ok[5] && ok[4]),
                        (1, Ok(out)) => {
                            assert!(out.ok.iter().all(|g| !g) && out.percentiles[0].is_empty())
                        }
                        (_, other) => panic!("round {round}: {}", other.is_ok()),
                    }
                }
            }
            done.send(()).unwrap();
        });
        finished
            .recv_timeout(std::time::Duration::from_secs(120))
            .expect("the workers must not wait for ever");
    }

    /// A panic in one worker (here the progress callback, which is the caller's code)
    /// stops the others at their next barrier, and the panic reaches the caller with its
    /// message; the pool can be used again.
    #[test]
    fn a_panicking_worker_stops_the_run_and_the_panic_resumes() {
        let (done, finished) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let (n, levels) = (300, [50.0]);
            let plan = MemoryPlan::new(n, 40, 1, GROUP_COLUMN_BYTES * 5 * 4);
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(3)
                .build()
                .unwrap();
            let progress = |done: usize, _: usize| assert!(done < 500, "progress refused {done}");
            let start = |block| Linear { block, next: 0 };
            let panicked = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                run(
                    &pool,
                    &plan,
                    &levels,
                    &progress,
                    start,
                    |s, until, o, stride| linear(n, s, until, o, stride),
                )
            }))
            .expect_err("the callback's panic reaches the caller");
            let message = panicked
                .downcast_ref::<String>()
                .cloned()
                .unwrap_or_default();
            assert!(message.starts_with("progress refused"), "{message}");
            let again = run(
                &pool,
                &plan,
                &levels,
                &|_, _| {},
                start,
                |s, until, o, stride| linear(n, s, until, o, stride),
            );
            assert!(again.is_ok());
            done.send(()).unwrap();
        });
        finished
            .recv_timeout(std::time::Duration::from_secs(120))
            .expect("the workers must not wait for ever");
    }

    /// Paper-sized response, N = 100 000: the whole plan stays far below 1 GiB (the
    /// responses alone would be 6.0 GB), on the default budget or a tiny one.
    #[test]
    fn memory_for_a_hundred_thousand_samples_is_bounded() {
        let default_budget = crate::McOptions::default().max_buffer_bytes;
        for budget in [default_budget, GROUP_COLUMN_BYTES * 1563] {
            let plan = MemoryPlan::new(100_000, 7501, 3, budget);
            assert!(plan.buffer_bytes <= budget);
            assert!(plan.peak_bytes < 160 << 20, "{plan:?}");
            assert_eq!(plan.chunks, 7501usize.div_ceil(plan.chunk_points));
        }
    }
}
