//! Reproducible parallel Monte Carlo robustness bands and Sobol sensitivity indices for
//! an identified mass–spring–damper, on `msd-ident` and rayon.
//!
//! It answers the paper's two questions — do realistic parameter variations keep the
//! predictions around the data ([`monte_carlo_band`]), and where in time is the response
//! most sensitive (the band's width) — and which parameter matters most
//! ([`sobol_indices`], [`msd_sobol`]).
//!
//! Every random number of sample (or Saltelli row) i comes from [`sample_rng`](seed, i),
//! and every reduction runs in index order, so results are bit-for-bit the same for any
//! thread count. Work runs on a local rayon pool of the requested size (2 by default),
//! never on the global pool.
//!
//! ## Memory and speed
//! Percentiles are exact (MATLAB `prctile` convention) and no N × T matrix of responses
//! is ever stored: every sample is simulated once, its simulator's state kept, and the
//! time axis is walked in cache-sized chunks ([`MemoryPlan`]) whose percentiles are
//! tracked level by level while the next chunk is simulated. Similar draws are
//! simulated side by side, so that a level's search skips whole blocks of them by their
//! smallest and largest value. Memory grows as N, not N × T: the paper's N = 1000 × 7501
//! points need about 2 MiB in all (the whole matrix would be 60 MB), and
//! [`MemoryPlan::peak_bytes`] states the bound for any N before anything is allocated.
//! [`McOptions::max_buffer_bytes`] bounds the buffers (a smaller budget means shorter
//! chunks, never a different result).
//!
//! ```
//! use msd_ident::{Backend, PaperExperiment, Parameters};
//! use msd_mc::{McOptions, monte_carlo_band};
//!
//! let experiment = PaperExperiment::generate(1)?;
//! let validation = &experiment.validation;
//! let options = McOptions { samples: 100, seed: 42, backend: Backend::EXACT, ..McOptions::default() };
//! let band = monte_carlo_band(&Parameters::PAPER, &validation.excitation, Some(&validation.output), &options)?;
//! assert_eq!(band.lower().len(), 7501);
//! assert!(band.coverage.unwrap() > 0.5);
//! println!("{band}");
//! # Ok::<(), msd_mc::McError>(())
//! ```

mod band;
mod barrier;
mod batch;
mod chain;
pub mod coverage;
mod draw;
mod engine;
mod error;
mod options;
mod order;
mod quantile;
mod sobol;
mod sobol_msd;
mod tracker;

pub use band::{Band, monte_carlo_band, monte_carlo_band_with_progress};
pub use chain::{ChainBand, ChainBandOptions, chain_band};
pub use draw::{MAX_REDRAWS, sample_rng};
pub use engine::MemoryPlan;
pub use error::{McError, Result, SampleFailure};
pub use options::{MAX_THREADS, McOptions, Sampling};
pub use quantile::Summary;
pub use sobol::{
    Distribution, SobolIndex, SobolOptions, SobolQuantity, SobolResult, sobol_indices,
};
pub use sobol_msd::{MSD_QUANTITIES, MsdSobolOptions, msd_sobol};

/// A local rayon pool of `threads` workers.
pub(crate) fn pool(threads: usize) -> Result<rayon::ThreadPool> {
    pool_with_stack(threads, None)
}

/// As [`pool`], with `stack_size` bytes of stack per worker when given.
fn pool_with_stack(threads: usize, stack_size: Option<usize>) -> Result<rayon::ThreadPool> {
    if threads == 0 {
        return Err(McError::ZeroThreads);
    }
    let mut builder = rayon::ThreadPoolBuilder::new().num_threads(threads);
    if let Some(bytes) = stack_size {
        builder = builder.stack_size(bytes);
    }
    builder.build().map_err(|e| McError::ThreadPool {
        threads,
        source: e.into(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// rayon's pool fails to build only when a worker cannot be spawned; a 2⁶⁰-byte stack
    /// cannot be mapped (it exceeds the 48-bit address space), so the spawn fails.
    #[test]
    fn a_pool_whose_threads_cannot_be_spawned_is_a_thread_pool_error() {
        let err = pool_with_stack(3, Some(1 << 60)).expect_err("cannot map 2^60 bytes");
        let McError::ThreadPool { threads, source } = &err else {
            panic!("expected ThreadPool, got {err:?}");
        };
        assert_eq!(*threads, 3);
        assert!(!source.to_string().is_empty());
        assert_eq!(
            err.to_string(),
            format!("could not build a pool of 3 threads: {source}")
        );
        let typed = std::error::Error::source(&err).map(ToString::to_string);
        assert_eq!(typed, Some(source.as_rayon().to_string()));
        assert!(pool(3).is_ok());
    }
}
