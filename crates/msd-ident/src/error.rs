//! The one error type of this crate; errors of the layers below convert into it.

use msd_modal_core::ModalError;
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
    /// A record or one of its channels cannot be used as given: the record's name, the
    /// channel's name when one is at fault, and what is wrong with it.
    ///
    /// ```
    /// use msd_ident::IdentError;
    /// let err = IdentError::InvalidRecord {
    ///     record: "run 2".into(),
    ///     channel: Some("laser".into()),
    ///     reason: "every sample is 0.3: a constant channel carries no information".into(),
    /// };
    /// assert_eq!(err.to_string(), "record `run 2`, channel `laser`: every sample is 0.3: a constant channel carries no information");
    /// ```
    #[error("record `{record}`{}: {reason}", channel_suffix(.channel))]
    InvalidRecord {
        /// Name of the record.
        record: String,
        /// Name of the channel at fault, if one is.
        channel: Option<String>,
        /// What is wrong, and what to do about it.
        reason: String,
    },
    /// The setup (what drives the plant, what is measured, what is known) cannot give
    /// what is asked: what it can identify and what to change.
    ///
    /// ```
    /// use msd_ident::IdentError;
    /// let err = IdentError::Setup { setup: "free decay", reason: "no records to fit".into() };
    /// assert_eq!(err.to_string(), "free decay: no records to fit");
    /// ```
    #[error("{setup}: {reason}")]
    Setup {
        /// The setup, in words ("free decay", "base excitation", …).
        setup: &'static str,
        /// What it cannot do, and what to change.
        reason: String,
    },
    /// A test condition of a dynamometer record is unusable.
    #[error("condition '{condition}', {field}: {found}; expected {expected}")]
    InvalidCondition {
        /// The condition's name.
        condition: String,
        /// The field: `dt`, `displacement`, `force` or `frequency_hz`.
        field: &'static str,
        /// What was found.
        found: String,
        /// What was expected, in words.
        expected: String,
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
    /// An error from msd-modal (a modal fit's lines, its diagram, too few modes).
    #[error(transparent)]
    Modal(#[from] ModalError),
}

fn channel_suffix(channel: &Option<String>) -> String {
    channel
        .as_ref()
        .map_or_else(String::new, |c| format!(", channel `{c}`"))
}

/// Shorthand for results of this crate.
pub type Result<T, E = IdentError> = std::result::Result<T, E>;
