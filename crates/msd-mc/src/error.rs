//! The one error type of this crate; `msd-ident`'s errors convert into it.

use msd_ident::IdentError;
use msd_opt::ThreadPoolError;

/// Everything that can go wrong in `msd-mc`, with the offending value.
///
/// ```
/// use msd_mc::{McError, McOptions};
/// let options = McOptions { samples: 0, ..McOptions::default() };
/// let err = options.validate().unwrap_err();
/// assert!(matches!(err, McError::ZeroSamples));
/// assert_eq!(err.to_string(), "the number of samples must be at least 1, got 0");
/// ```
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum McError {
    /// N = 0.
    #[error("the number of samples must be at least 1, got 0")]
    ZeroSamples,
    /// Zero worker threads.
    #[error("the number of threads must be at least 1, got 0")]
    ZeroThreads,
    /// The uniform half-width p is not in (0, 100) %.
    #[error("invalid uniform half-width {percent} %: expected 0 < p < 100")]
    InvalidPercent {
        /// The rejected p.
        percent: f64,
    },
    /// A percentile level is not a finite number in [0, 100].
    #[error("percentile {index} is {value}: expected a finite number in 0..=100")]
    PercentileOutOfRange {
        /// Position in the list.
        index: usize,
        /// The rejected level.
        value: f64,
    },
    /// Percentile levels are not strictly increasing.
    #[error(
        "percentiles must be strictly increasing: {previous} is followed by {value} at {index}"
    )]
    UnorderedPercentiles {
        /// Position of the offending level.
        index: usize,
        /// The level before it.
        previous: f64,
        /// The offending level.
        value: f64,
    },
    /// No percentile levels at all.
    #[error("at least one percentile level is needed")]
    NoPercentiles,
    /// The covariance scale is not a finite number > 0.
    #[error("invalid covariance scale {scale}: expected a finite number > 0")]
    InvalidScale {
        /// The rejected scale.
        scale: f64,
    },
    /// The covariance is not symmetric positive semi-definite.
    #[error("the covariance is not symmetric positive semi-definite (pivot {pivot} is {value})")]
    NotPositiveSemidefinite {
        /// The row of the failing Cholesky pivot (0 = mass, 1 = damping, 2 = stiffness).
        pivot: usize,
        /// Its value (negative or not finite), or the asymmetry.
        value: f64,
    },
    /// More worker threads than [`crate::options::MAX_THREADS`].
    #[error("the number of threads is {threads}: expected at most {max}")]
    TooManyThreads {
        /// The threads asked for.
        threads: usize,
        /// The limit.
        max: usize,
    },
    /// The memory budget cannot hold the two chunk buffers of one time column each.
    #[error(
        "memory budget {budget} bytes is below two time columns of {samples} samples ({needed} bytes)"
    )]
    BudgetTooSmall {
        /// The budget.
        budget: usize,
        /// N.
        samples: usize,
        /// Bytes for two columns with their envelopes: 1408 per group of 64 samples.
        needed: usize,
    },
    /// Measurements do not match the excitation's grid.
    #[error("length mismatch: {what} has {got} samples, expected {expected}")]
    LengthMismatch {
        /// What was compared.
        what: &'static str,
        /// Required length.
        expected: usize,
        /// Length found.
        got: usize,
    },
    /// Every sample failed to simulate (or was non-physical).
    #[error("all {samples} samples failed; the first: {first}")]
    AllSamplesFailed {
        /// N.
        samples: usize,
        /// Why the first sample failed.
        #[source]
        first: SampleFailure,
    },
    /// The rayon pool could not be built.
    #[error("could not build a pool of {threads} threads: {source}")]
    ThreadPool {
        /// Requested threads.
        threads: usize,
        /// rayon's error.
        source: ThreadPoolError,
    },
    /// The caller's model function panicked inside a worker thread; the panic was caught
    /// and the run abandoned.
    #[error("the model function panicked at sample row {row}: {message}")]
    WorkerPanicked {
        /// Sample row whose evaluation panicked (the lowest such row).
        row: usize,
        /// The panic message (`"non-string panic payload"` when it was not text).
        message: String,
    },
    /// A Sobol option or input distribution is out of range.
    #[error("invalid {name} = {value}: expected {expected}")]
    InvalidOption {
        /// Name of the option.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// The allowed range, in words.
        expected: &'static str,
    },
    /// The Sobol model returned the wrong number of outputs.
    #[error("model evaluation {evaluation} returned {got} values, expected {expected}")]
    ModelOutputLength {
        /// Index of the evaluation (row-major over the Saltelli design).
        evaluation: usize,
        /// Expected number of quantities of interest.
        expected: usize,
        /// Number returned.
        got: usize,
    },
    /// The Sobol model returned NaN or infinity.
    #[error("model evaluation {evaluation} gave {value} for quantity {quantity}")]
    NonFiniteOutput {
        /// Index of the evaluation.
        evaluation: usize,
        /// Index of the quantity of interest.
        quantity: usize,
        /// The value.
        value: f64,
    },
    /// From the identification layer (simulation, parameters, data).
    #[error(transparent)]
    Ident(#[from] IdentError),
}

/// Why the first sample of a band failed (see [`McError::AllSamplesFailed`]).
///
/// ```
/// use msd_ident::IdentError;
/// use msd_mc::{McError, SampleFailure};
/// let failure = SampleFailure::NonPhysical { redraws: 100 };
/// assert_eq!(failure.to_string(), "non-physical draw after 100 redraws");
/// // A simulation's error is kept whole, as the source of the band's error.
/// let ident = IdentError::TooFewSamples { got: 1, needed: 2, why: "an example" };
/// let err = McError::AllSamplesFailed { samples: 4, first: ident.clone().into() };
/// assert_eq!(err.to_string(), format!("all 4 samples failed; the first: {ident}"));
/// let source = std::error::Error::source(&err).map(ToString::to_string);
/// assert_eq!(source, Some(ident.to_string()));
/// ```
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SampleFailure {
    /// No draw of the sample was physical, after `redraws` redraws.
    #[error("non-physical draw after {redraws} redraws")]
    NonPhysical {
        /// Redraws tried ([`MAX_REDRAWS`](crate::draw::MAX_REDRAWS)).
        redraws: usize,
    },
    /// Its parameters could not be simulated.
    #[error(transparent)]
    Simulation(#[from] IdentError),
    /// Its simulation failed among the others but succeeds alone (not expected).
    #[error("unknown")]
    Unknown,
}

/// Shorthand for results of this crate.
pub type Result<T, E = McError> = std::result::Result<T, E>;
