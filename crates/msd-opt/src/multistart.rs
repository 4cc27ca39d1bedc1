//! Multistart: seeded starting points spread over a box, each refined by a local
//! solver, optionally in parallel, all local results returned ranked.
//!
//! Starting points come from a Latin hypercube or a randomly shifted Halton
//! sequence, generated up front from the seed (ChaCha8), so start `i` is the same
//! point whatever the thread count. The local runs go on a rayon pool of
//! `threads` threads built for the call (the global pool is left alone), and the
//! results are collected in start order before ranking: the output does not
//! depend on the thread count.
//!
//! ```
//! use msd_opt::{multistart, nelder_mead, Bounds, MultistartOptions, NelderMeadOptions};
//!
//! // A tilted double well: local minimum near x = 2, global near x = −2.
//! let cost = |x: &[f64]| (x[0] * x[0] - 4.0).powi(2) + x[0];
//! let local = nelder_mead(cost, &[3.0], &NelderMeadOptions::default()).unwrap();
//! assert!(local.x[0] > 0.0);
//!
//! let bounds = Bounds::new(vec![-4.0], vec![4.0]).unwrap();
//! let options = MultistartOptions { starts: 8, seed: 7, ..Default::default() };
//! let ranked = multistart(&bounds, &options, |x0| {
//!     nelder_mead(cost, x0, &NelderMeadOptions::default())
//! })
//! .unwrap();
//! assert_eq!(ranked.len(), 8);
//! assert!(ranked[0].result.x[0] < 0.0);
//! ```

use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::check_count;
use crate::{
    bounds::Bounds, error::OptError, levenberg_marquardt::LevenbergMarquardtResult,
    nelder_mead::NelderMeadResult,
};

/// How starting points are spread over the box.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Sampling {
    /// Latin hypercube: each coordinate's range cut into `starts` equal strata,
    /// one point per stratum, strata paired by seeded random permutations.
    #[default]
    LatinHypercube,
    /// Halton sequence (bases 2, 3, 5, …, points 1…starts) with a seeded
    /// Cranley–Patterson random shift per coordinate.
    Halton,
}

/// Options of [`multistart`].
///
/// | field | default |
/// |---|---|
/// | `starts` | 16 |
/// | `seed` | 0 |
/// | `threads` | 2 (the project's pool size) |
/// | `sampling` | Latin hypercube |
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MultistartOptions {
    /// Number of starting points. By default 16.
    pub starts: usize,
    /// Seed of the ChaCha8 generator. By default 0.
    pub seed: u64,
    /// Threads of the local rayon pool (1 runs serially). By default 2.
    pub threads: usize,
    /// Design of the starting points. By default Latin hypercube.
    pub sampling: Sampling,
}

impl Default for MultistartOptions {
    /// 16 starts, seed 0, 2 threads, Latin hypercube.
    fn default() -> Self {
        Self {
            starts: 16,
            seed: 0,
            threads: 2,
            sampling: Sampling::LatinHypercube,
        }
    }
}

impl MultistartOptions {
    /// Checks `starts ≥ 1` and `threads ≥ 1`.
    ///
    /// # Errors
    /// [`OptError::InvalidOption`] naming the field.
    pub fn validate(&self) -> Result<(), OptError> {
        check_count("starts", Some(self.starts))?;
        check_count("threads", Some(self.threads))
    }
}

/// A local result that multistart can rank: lower cost is better.
pub trait RankedCost {
    /// The cost used for ranking (non-finite ranks last).
    fn ranked_cost(&self) -> f64;
}

impl RankedCost for NelderMeadResult {
    fn ranked_cost(&self) -> f64 {
        self.cost
    }
}

impl RankedCost for LevenbergMarquardtResult {
    fn ranked_cost(&self) -> f64 {
        self.cost
    }
}

/// One local run of [`multistart`].
#[derive(Debug, Clone, PartialEq)]
pub struct StartResult<T> {
    /// Index of the starting point (0-based, in generation order).
    pub start: usize,
    /// The starting point.
    pub x0: Vec<f64>,
    /// The local solver's result.
    pub result: T,
}

/// The starting points [`multistart`] uses, in start order.
///
/// # Errors
/// Invalid options, invalid or infinite bounds.
///
/// ```
/// use msd_opt::{starting_points, Bounds, MultistartOptions};
/// let b = Bounds::new(vec![0.0, 10.0], vec![1.0, 20.0]).unwrap();
/// let pts = starting_points(&b, &MultistartOptions { starts: 4, ..Default::default() }).unwrap();
/// assert_eq!(pts.len(), 4);
/// assert!(pts.iter().all(|p| b.contains(p)));
/// ```
pub fn starting_points(
    bounds: &Bounds,
    options: &MultistartOptions,
) -> Result<Vec<Vec<f64>>, OptError> {
    options.validate()?;
    bounds.validate()?;
    bounds.require_finite()?;
    if bounds.is_empty() {
        return Err(OptError::EmptyStart);
    }
    let (n, k) = (bounds.len(), options.starts);
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let mut unit = vec![vec![0.0; n]; k];
    match options.sampling {
        Sampling::LatinHypercube => {
            let mut perm: Vec<usize> = (0..k).collect();
            for d in 0..n {
                perm.shuffle(&mut rng);
                for (i, p) in unit.iter_mut().enumerate() {
                    let u: f64 = rng.random();
                    p[d] = (perm[i] as f64 + u) / k as f64;
                }
            }
        }
        Sampling::Halton => {
            let bases = first_primes(n);
            for (d, &base) in bases.iter().enumerate() {
                let shift: f64 = rng.random();
                for (i, p) in unit.iter_mut().enumerate() {
                    let h = radical_inverse(i as u64 + 1, base) + shift;
                    p[d] = h - h.floor();
                }
            }
        }
    }
    Ok(unit
        .into_iter()
        .map(|u| {
            u.iter()
                .enumerate()
                .map(|(d, &t)| {
                    let (l, h) = (bounds.lower[d], bounds.upper[d]);
                    (l + t * (h - l)).clamp(l, h)
                })
                .collect()
        })
        .collect())
}

/// Runs `local` from every starting point and returns all results, best first
/// (ties keep start order).
///
/// A panic inside `local` does not unwind through the pool: it is caught on the worker
/// and returned as [`OptError::WorkerPanicked`] (the other starts still run, their
/// results are discarded).
///
/// # Errors
/// Invalid options or bounds, a thread pool that cannot be built
/// ([`OptError::ThreadPool`]), [`OptError::WorkerPanicked`] or
/// [`OptError::LocalSolver`] with the lowest-index start whose local run panicked or
/// failed.
pub fn multistart<T, L>(
    bounds: &Bounds,
    options: &MultistartOptions,
    local: L,
) -> Result<Vec<StartResult<T>>, OptError>
where
    T: RankedCost + Send,
    L: Fn(&[f64]) -> Result<T, OptError> + Sync,
{
    let points = starting_points(bounds, options)?;
    let pool = pool(options.threads, None)?;
    let outcomes: Vec<Result<T, OptError>> = pool.install(|| {
        points
            .par_iter()
            .enumerate()
            .map(|(start, x0)| caught(start, || local(x0)))
            .collect()
    });
    let mut ranked = Vec::with_capacity(points.len());
    for (start, (x0, outcome)) in points.into_iter().zip(outcomes).enumerate() {
        match outcome {
            Ok(result) => ranked.push(StartResult { start, x0, result }),
            Err(e @ OptError::WorkerPanicked { .. }) => return Err(e),
            Err(e) => {
                return Err(OptError::LocalSolver {
                    start,
                    source: Box::new(e),
                });
            }
        }
    }
    let key = |r: &StartResult<T>| {
        let c = r.result.ranked_cost();
        if c.is_nan() { f64::INFINITY } else { c }
    };
    ranked.sort_by(|a, b| key(a).total_cmp(&key(b)));
    Ok(ranked)
}

/// A local rayon pool of `threads` workers (with `stack_size` bytes of stack each, when
/// given; rayon's default otherwise).
fn pool(threads: usize, stack_size: Option<usize>) -> Result<rayon::ThreadPool, OptError> {
    let mut builder = rayon::ThreadPoolBuilder::new().num_threads(threads);
    if let Some(bytes) = stack_size {
        builder = builder.stack_size(bytes);
    }
    builder.build().map_err(|e| OptError::ThreadPool {
        threads,
        source: e.into(),
    })
}

/// Runs the local work of `start`, turning a panic into [`OptError::WorkerPanicked`].
///
/// `AssertUnwindSafe`: after a panic nothing of that start's run is used again (its
/// result is the error), and the whole multistart returns an error, so no broken
/// invariant of the caller's closure is observed through this call.
fn caught<T>(start: usize, work: impl FnOnce() -> Result<T, OptError>) -> Result<T, OptError> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)).unwrap_or_else(|payload| {
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| (*s).to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "non-string panic payload".into());
        Err(OptError::WorkerPanicked { start, message })
    })
}

fn first_primes(n: usize) -> Vec<u64> {
    let mut primes = Vec::with_capacity(n);
    let mut c = 2u64;
    while primes.len() < n {
        if primes
            .iter()
            .take_while(|&&p| p * p <= c)
            .all(|&p| !c.is_multiple_of(p))
        {
            primes.push(c);
        }
        c += 1;
    }
    primes
}

/// Van der Corput radical inverse of `i` in `base`.
fn radical_inverse(mut i: u64, base: u64) -> f64 {
    let (mut result, mut f) = (0.0, 1.0 / base as f64);
    while i > 0 {
        result += f * (i % base) as f64;
        i /= base;
        f /= base as f64;
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halton_and_primes() {
        assert_eq!(first_primes(5), [2, 3, 5, 7, 11]);
        assert_eq!(radical_inverse(1, 2), 0.5);
        assert_eq!(radical_inverse(3, 2), 0.75);
        assert_eq!(radical_inverse(5, 3), 2.0 / 3.0 + 1.0 / 9.0);
    }

    /// rayon's pool fails to build only when a worker thread cannot be spawned; a stack
    /// of 2⁶⁰ bytes cannot be mapped on any machine (it exceeds the 48-bit address space),
    /// so the spawn fails and the error names the pool size and rayon's reason.
    #[test]
    fn a_pool_whose_threads_cannot_be_spawned_is_a_thread_pool_error() {
        let err = pool(3, Some(1 << 60)).expect_err("a 2^60-byte stack cannot be mapped");
        match &err {
            OptError::ThreadPool { threads, source } => {
                assert_eq!(*threads, 3);
                assert!(!source.to_string().is_empty());
                let typed = std::error::Error::source(&err).map(ToString::to_string);
                assert_eq!(typed, Some(source.as_rayon().to_string()));
                assert_eq!(
                    err.to_string(),
                    format!("multistart: could not build a thread pool of 3 threads: {source}")
                );
            }
            other => panic!("expected ThreadPool, got {other:?}"),
        }
        assert!(pool(3, None).is_ok());
    }

    #[test]
    fn latin_hypercube_has_one_point_per_stratum() {
        let b = Bounds::new(vec![0.0, -1.0, 5.0], vec![1.0, 1.0, 6.0]).unwrap();
        let k = 10;
        let opts = MultistartOptions {
            starts: k,
            seed: 3,
            ..Default::default()
        };
        let pts = starting_points(&b, &opts).unwrap();
        for d in 0..3 {
            let mut hit = vec![false; k];
            for p in &pts {
                let t = (p[d] - b.lower[d]) / (b.upper[d] - b.lower[d]);
                hit[((t * k as f64) as usize).min(k - 1)] = true;
            }
            assert!(hit.iter().all(|&h| h), "dimension {d}");
        }
        assert_eq!(pts, starting_points(&b, &opts).unwrap());
    }
}
