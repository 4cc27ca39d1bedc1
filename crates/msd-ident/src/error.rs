//! The one error type of this crate; errors of the layers below convert into it.

use msd_ode::OdeError;
use msd_opt::OptError;
use msd_signal::SignalError;

/// Everything that can go wrong in `msd-ident`, with the place and the value.
///
/// ```
/// use msd_ident::{IdentError, Parameters};
/// let err = Parameters::new(-2.5, 1.8, 120.0).unwrap_err();
/// assert!(matches!(err, IdentError::InvalidParameter { name: "mass", .. }));
/// assert_eq!(err.to_string(), "invalid mass = -2.5: expected a finite number > 0");
/// ```
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IdentError {
    /// A physical parameter or an option is out of range.
    #[error("invalid {name} = {value}: expected {expected}")]
    InvalidParameter {
        /// Name of the parameter or option.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// The allowed range, in words.
        expected: &'static str,
    },
    /// A data sample is NaN or infinite.
    #[error("{field} sample {index} is {value}: expected a finite number")]
    NonFiniteSample {
        /// `"input"`, `"output"` or `"time"`.
        field: &'static str,
        /// Index of the sample.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// Two series that must have equal lengths do not.
    #[error("length mismatch: {what} has {got} samples, expected {expected}")]
    LengthMismatch {
        /// What was compared.
        what: &'static str,
        /// Required length.
        expected: usize,
        /// Length found.
        got: usize,
    },
    /// Too few samples for the requested analysis.
    #[error("too few samples: {got}, need at least {needed} ({why})")]
    TooFewSamples {
        /// Samples available.
        got: usize,
        /// Samples needed.
        needed: usize,
        /// Why that many are needed.
        why: &'static str,
    },
    /// Time stamps are not uniformly spaced (or not increasing).
    #[error(
        "time stamps are not uniform: step {index} is {step} s, expected {expected} s (within 1e-6 relative)"
    )]
    NonUniformTime {
        /// Index of the offending step (between samples index−1 and index).
        index: usize,
        /// The step found.
        step: f64,
        /// The nominal step.
        expected: f64,
    },
    /// A sample range is outside the data.
    #[error("range {start}..{end} is outside the data (0..{len})")]
    RangeOutOfBounds {
        /// Start of the range.
        start: usize,
        /// End of the range (exclusive).
        end: usize,
        /// Length of the data.
        len: usize,
    },
    /// An excitation design's option or constraint is out of range, named by its key in
    /// a config's `[design]` section.
    #[error("invalid design.{key} = {value}: expected {expected}")]
    InvalidDesign {
        /// The key, e.g. `constraints.max_stroke`.
        key: &'static str,
        /// The rejected value.
        value: f64,
        /// What is allowed, with the numbers it depends on.
        expected: String,
    },
    /// The data cannot determine the parameters.
    #[error("parameters are not identifiable from these data: {reason}")]
    NotIdentifiable {
        /// Why, in words.
        reason: String,
    },
    /// The estimator ran but did not produce a usable estimate.
    #[error("estimation failed: {reason}")]
    EstimationFailed {
        /// Why, in words.
        reason: String,
    },
    /// From the ODE layer.
    #[error(transparent)]
    Ode(#[from] OdeError),
    /// From the signal layer.
    #[error(transparent)]
    Signal(#[from] SignalError),
    /// From the optimisation layer.
    #[error(transparent)]
    Opt(#[from] OptError),
}

/// Shorthand for results of this crate.
pub type Result<T, E = IdentError> = std::result::Result<T, E>;
