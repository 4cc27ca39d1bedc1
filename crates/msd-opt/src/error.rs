//! The crate's one error type, [`OptError`].
//!
//! Every variant names what was wrong and where: which option and its value, which
//! coordinate of `x0` or of the bounds. Solvers return it only for bad input or
//! for a problem that cannot even be started; a run that stops early for a
//! numerical reason is a normal result with an exit reason instead.
//!
//! ```
//! use msd_opt::{nelder_mead, NelderMeadOptions, OptError};
//!
//! let err = nelder_mead(|x| x[0] * x[0], &[f64::NAN], &NelderMeadOptions::default())
//!     .unwrap_err();
//! assert!(matches!(err, OptError::NonFiniteStart { index: 0, .. }));
//! assert_eq!(err.to_string(), "x0[0] = NaN is not finite");
//! ```

use std::fmt;
use std::sync::Arc;

/// Everything that can go wrong before or while starting a solver.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OptError {
    /// The starting point has no coordinates.
    #[error("x0 is empty: at least one parameter is needed")]
    EmptyStart,
    /// A coordinate of the starting point is NaN or infinite.
    #[error("x0[{index}] = {value} is not finite")]
    NonFiniteStart {
        /// Coordinate index.
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// An option is outside its valid range.
    #[error("option `{name}` = {value} is invalid: expected {expected}")]
    InvalidOption {
        /// Field name of the option.
        name: &'static str,
        /// The rejected value (integers are shown as floats).
        value: f64,
        /// The valid range, in words.
        expected: &'static str,
    },
    /// Two things that must have the same length do not.
    #[error("{what}: expected length {expected}, found {found}")]
    LengthMismatch {
        /// What was compared, e.g. "upper bounds vs lower bounds".
        what: &'static str,
        /// The length required.
        expected: usize,
        /// The length given.
        found: usize,
    },
    /// A lower bound is above its upper bound.
    #[error("lower bound {lower} is above upper bound {upper} at coordinate {index}")]
    InvertedBounds {
        /// Coordinate index.
        index: usize,
        /// Lower bound.
        lower: f64,
        /// Upper bound.
        upper: f64,
    },
    /// A bound is NaN (infinite bounds are allowed where the solver says so).
    #[error("{which} bound at coordinate {index} is NaN")]
    NaNBound {
        /// "lower" or "upper".
        which: &'static str,
        /// Coordinate index.
        index: usize,
    },
    /// Multistart needs finite bounds to spread its starting points over.
    #[error("multistart needs finite bounds; coordinate {index} has [{lower}, {upper}]")]
    InfiniteBounds {
        /// Coordinate index.
        index: usize,
        /// Lower bound.
        lower: f64,
        /// Upper bound.
        upper: f64,
    },
    /// Levenberg–Marquardt needs at least as many residuals as parameters.
    #[error(
        "{residuals} residuals for {parameters} parameters: Levenberg–Marquardt needs residuals ≥ parameters"
    )]
    TooFewResiduals {
        /// Number of residuals m.
        residuals: usize,
        /// Number of parameters n.
        parameters: usize,
    },
    /// The residuals could not be computed, or were not finite, at the starting point.
    #[error(
        "residuals at the starting point are not finite or could not be computed (first bad index: {index:?})"
    )]
    InitialResiduals {
        /// First non-finite residual, if the problem reported success but gave one.
        index: Option<usize>,
    },
    /// The Jacobian at the starting point has a non-finite entry.
    #[error("Jacobian at the starting point has a non-finite entry at row {row}, column {column}")]
    InitialJacobian {
        /// Row (residual index).
        row: usize,
        /// Column (parameter index).
        column: usize,
    },
    /// A local solver inside multistart failed on one start.
    #[error("multistart: local solver failed on start {start}: {source}")]
    LocalSolver {
        /// Index of the start that failed (the lowest such index).
        start: usize,
        /// The local solver's error.
        source: Box<OptError>,
    },
    /// The rayon thread pool could not be built.
    #[error("multistart: could not build a thread pool of {threads} threads: {source}")]
    ThreadPool {
        /// Requested number of threads.
        threads: usize,
        /// rayon's error.
        source: ThreadPoolError,
    },
    /// The local run of one start panicked on a worker thread (a bug in the cost or
    /// residual function, or in a solver); the panic was caught and the other starts'
    /// results discarded.
    #[error("multistart: the local run of start {start} panicked: {message}")]
    WorkerPanicked {
        /// Index of the start whose run panicked (the lowest such index).
        start: usize,
        /// The panic message (`"non-string panic payload"` when it was not text).
        message: String,
    },
}

/// rayon's error building a thread pool, kept whole as the source of
/// [`OptError::ThreadPool`] (and of msd-mc's pool error).
///
/// Shared behind an `Arc` so that the errors holding it stay `Clone`; two are equal when
/// their messages are (rayon's error cannot be compared otherwise). It displays as
/// rayon's message and is transparent: its `source` is rayon's.
///
/// ```
/// use msd_opt::ThreadPoolError;
/// // A 2⁶⁰-byte stack cannot be mapped, so the pool's first worker cannot be spawned.
/// let rayon = rayon::ThreadPoolBuilder::new().num_threads(1).stack_size(1 << 60).build();
/// let err = ThreadPoolError::from(rayon.expect_err("cannot map 2^60 bytes"));
/// assert_eq!(err.to_string(), err.as_rayon().to_string());
/// assert_eq!(err.clone(), err);
/// ```
#[derive(Debug, Clone)]
pub struct ThreadPoolError(Arc<rayon::ThreadPoolBuildError>);

impl ThreadPoolError {
    /// rayon's error.
    ///
    /// ```
    /// use msd_opt::ThreadPoolError;
    /// let built = rayon::ThreadPoolBuilder::new().stack_size(1 << 60).build();
    /// let err = ThreadPoolError::from(built.expect_err("cannot map 2^60 bytes"));
    /// assert!(!err.as_rayon().to_string().is_empty());
    /// ```
    pub fn as_rayon(&self) -> &rayon::ThreadPoolBuildError {
        &self.0
    }
}

impl From<rayon::ThreadPoolBuildError> for ThreadPoolError {
    fn from(error: rayon::ThreadPoolBuildError) -> Self {
        Self(Arc::new(error))
    }
}

impl fmt::Display for ThreadPoolError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

impl std::error::Error for ThreadPoolError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.0.source()
    }
}

impl PartialEq for ThreadPoolError {
    fn eq(&self, other: &Self) -> bool {
        self.to_string() == other.to_string()
    }
}

/// Checks a starting point: non-empty and finite.
pub(crate) fn check_start(x0: &[f64]) -> Result<(), OptError> {
    if x0.is_empty() {
        return Err(OptError::EmptyStart);
    }
    match x0.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(OptError::NonFiniteStart {
            index,
            value: x0[index],
        }),
        None => Ok(()),
    }
}

/// Checks that a tolerance is finite and strictly positive.
pub(crate) fn check_positive(name: &'static str, value: f64) -> Result<(), OptError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(OptError::InvalidOption {
            name,
            value,
            expected: "a finite number > 0",
        })
    }
}

/// Checks that a tolerance is finite and non-negative.
pub(crate) fn check_non_negative(name: &'static str, value: f64) -> Result<(), OptError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(OptError::InvalidOption {
            name,
            value,
            expected: "a finite number ≥ 0",
        })
    }
}

/// Checks that an optional count is at least one.
pub(crate) fn check_count(name: &'static str, value: Option<usize>) -> Result<(), OptError> {
    match value {
        Some(0) => Err(OptError::InvalidOption {
            name,
            value: 0.0,
            expected: "at least 1 (or None for the default)",
        }),
        _ => Ok(()),
    }
}
