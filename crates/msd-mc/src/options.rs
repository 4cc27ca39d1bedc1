//! Options of a Monte Carlo band run and how parameters are sampled.

use crate::error::{McError, Result};
use msd_ident::{Backend, InitialState, Parameters, Uncertainty};
use serde::{Deserialize, Serialize};

/// How the N parameter samples are drawn around the nominal θ̂ = (m, c, k).
///
/// By default [`Sampling::Uniform`] with p = 10 %, the paper's.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Sampling {
    /// Each parameter independently uniform in θ̂ⱼ·[1 − p/100, 1 + p/100] (the paper).
    Uniform {
        /// Half-width p in percent, 0 < p < 100.
        percent: f64,
    },
    /// θ = θ̂ + scale·L·z with z ~ N(0, I₃) and L Lᵀ the covariance (as MATLAB's `simsd`).
    ///
    /// A draw with m ≤ 0, c < 0 or k ≤ 0 is rejected and redrawn from the same
    /// per-sample generator (so the draws follow the normal distribution truncated to
    /// the physical region); after [`MAX_REDRAWS`](crate::draw::MAX_REDRAWS) rejections the
    /// sample counts as failed. All deterministic in (seed, sample index).
    Covariance {
        /// Symmetric positive semi-definite covariance of (m, c, k); a zero row and
        /// column keeps that parameter fixed.
        covariance: [[f64; 3]; 3],
        /// Factor on the standard deviations (1 = the estimated covariance).
        scale: f64,
    },
}

impl Default for Sampling {
    fn default() -> Self {
        Sampling::Uniform { percent: 10.0 }
    }
}

impl Sampling {
    /// The covariance of the physical parameters from an `msd-ident` estimate: the rows
    /// and columns named "mass", "damping", "stiffness" (a fixed parameter, absent from
    /// the estimate, gets zero variance); initial state and offset columns are dropped.
    pub fn from_uncertainty(uncertainty: &Uncertainty, scale: f64) -> Self {
        let column = |name: &str| uncertainty.names.iter().position(|n| *n == name);
        let columns = Parameters::NAMES.map(column);
        let mut covariance = [[0.0; 3]; 3];
        for (r, row) in covariance.iter_mut().enumerate() {
            for (c, value) in row.iter_mut().enumerate() {
                if let (Some(a), Some(b)) = (columns[r], columns[c]) {
                    *value = uncertainty.covariance[(a, b)];
                }
            }
        }
        Sampling::Covariance { covariance, scale }
    }

    /// Checks p (0 < p < 100) or the scale and the covariance.
    pub fn validate(&self) -> Result<()> {
        match *self {
            Sampling::Uniform { percent } => {
                if !(percent.is_finite() && percent > 0.0 && percent < 100.0) {
                    return Err(McError::InvalidPercent { percent });
                }
            }
            Sampling::Covariance { covariance, scale } => {
                if !(scale.is_finite() && scale > 0.0) {
                    return Err(McError::InvalidScale { scale });
                }
                crate::draw::cholesky(&covariance)?;
            }
        }
        Ok(())
    }
}

/// Options of [`monte_carlo_band`](crate::band::monte_carlo_band).
///
/// By default the paper's: N = 1000, p = 10 % uniform, percentiles 5/50/95 (the 90 %
/// band), 2 threads, seed 0, the paper's ode45 (RelTol 1e-6, AbsTol 1e-9) from rest, and
/// a 256 MiB budget for the chunk buffers.
///
/// ```
/// use msd_mc::McOptions;
/// let options: McOptions = toml::from_str(r#"
///     samples = 200
///     threads = 1
///     percentiles = [2.5, 97.5]
///     sampling = { kind = "uniform", percent = 5.0 }
///     backend = { kind = "exact" }
/// "#).unwrap();
/// options.validate()?;
/// assert_eq!(options.seed, 0);
/// # Ok::<(), msd_mc::McError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct McOptions {
    /// N, the number of parameter samples (≥ 1). By default 1000.
    pub samples: usize,
    /// How they are drawn. By default uniform ±10 %.
    pub sampling: Sampling,
    /// Percentile levels in percent, strictly increasing in [0, 100]; the first and last
    /// bound the band. By default 5, 50, 95.
    pub percentiles: Vec<f64>,
    /// Worker threads of the local rayon pool (≥ 1). By default 2.
    pub threads: usize,
    /// Seed of the run; sample i draws from ChaCha8(seed) on stream i. By default 0.
    pub seed: u64,
    /// Simulation backend. By default [`Backend::PAPER`] (ode45, RelTol 1e-6, AbsTol 1e-9).
    pub backend: Backend,
    /// Initial state of every simulation. By default at rest.
    pub initial_state: InitialState,
    /// Upper bound in bytes of the two N × chunk buffers the responses stream through
    /// (the engine wants about 1 MiB; a smaller budget means shorter chunks, never a
    /// different result). At least 1408 bytes per 64 samples (22·N). By default 256 MiB.
    pub max_buffer_bytes: usize,
}

impl Default for McOptions {
    fn default() -> Self {
        Self {
            samples: 1000,
            sampling: Sampling::default(),
            percentiles: vec![5.0, 50.0, 95.0],
            threads: 2,
            seed: 0,
            backend: Backend::PAPER,
            initial_state: InitialState::REST,
            max_buffer_bytes: 256 << 20,
        }
    }
}

/// The most worker threads a band accepts (the same limit as the command line's
/// `--threads`): far beyond any machine's cores, low enough that a typo cannot start
/// thousands of threads.
pub const MAX_THREADS: usize = 1024;

impl McOptions {
    /// The largest N whose two time columns fit in `max_buffer_bytes`.
    ///
    /// ```
    /// let options = msd_mc::McOptions::default();
    /// let largest = options.max_samples();
    /// assert!(largest >= 1000);
    /// assert!(msd_mc::McOptions { samples: largest, ..options.clone() }.validate().is_ok());
    /// assert!(msd_mc::McOptions { samples: largest + 1, ..options }.validate().is_err());
    /// ```
    pub fn max_samples(&self) -> usize {
        self.max_buffer_bytes / crate::engine::GROUP_COLUMN_BYTES * crate::engine::GROUP
    }

    /// Checks every field and names the first violated range.
    pub fn validate(&self) -> Result<()> {
        if self.samples == 0 {
            return Err(McError::ZeroSamples);
        }
        if self.threads == 0 {
            return Err(McError::ZeroThreads);
        }
        if self.threads > MAX_THREADS {
            return Err(McError::TooManyThreads {
                threads: self.threads,
                max: MAX_THREADS,
            });
        }
        self.sampling.validate()?;
        validate_percentiles(&self.percentiles)?;
        self.backend.validate()?;
        let groups = self.samples.div_ceil(crate::engine::GROUP);
        let needed = crate::engine::GROUP_COLUMN_BYTES * groups;
        if self.max_buffer_bytes < needed {
            return Err(McError::BudgetTooSmall {
                budget: self.max_buffer_bytes,
                samples: self.samples,
                needed,
            });
        }
        Ok(())
    }
}

/// Levels finite, in [0, 100], strictly increasing, at least one.
pub(crate) fn validate_percentiles(levels: &[f64]) -> Result<()> {
    if levels.is_empty() {
        return Err(McError::NoPercentiles);
    }
    for (index, &value) in levels.iter().enumerate() {
        if !(value.is_finite() && (0.0..=100.0).contains(&value)) {
            return Err(McError::PercentileOutOfRange { index, value });
        }
        if index > 0 && value <= levels[index - 1] {
            return Err(McError::UnorderedPercentiles {
                index,
                previous: levels[index - 1],
                value,
            });
        }
    }
    Ok(())
}
