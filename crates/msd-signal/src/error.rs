//! The crate's one error type, [`SignalError`].
//!
//! Every variant carries enough context to say *what* was rejected: the parameter's
//! name (a path such as `terms[1].segments[0].frequency` for nested signals), the
//! offending value and the accepted range, or the index of a bad sample.
//!
//! ```
//! use msd_signal::{Signal, SignalError};
//!
//! let sine = Signal::Sine { amplitude: 1.0, frequency: -2.0, phase: 0.0, t_on: 0.0, t_off: None };
//! let err = sine.validate().unwrap_err();
//! assert!(matches!(err, SignalError::InvalidParameter { ref parameter, value, .. }
//!     if parameter == "frequency" && value == -2.0));
//! assert_eq!(err.to_string(), "invalid parameter `frequency` = -2: expected a finite value >= 0");
//! ```

use thiserror::Error;

/// Everything that `msd-signal` can refuse.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum SignalError {
    /// A scalar parameter is NaN, infinite or outside its range.
    #[error("invalid parameter `{parameter}` = {value}: expected {expected}")]
    InvalidParameter {
        /// Name (or path) of the parameter.
        parameter: String,
        /// The rejected value.
        value: f64,
        /// The accepted range, in words.
        expected: &'static str,
    },
    /// An active window `[t_on, t_off)` whose end is not after its start.
    #[error("reversed window `{parameter}`: t_on = {t_on} must be < t_off = {t_off}")]
    ReversedWindow {
        /// Name (or path) of the signal that owns the window.
        parameter: String,
        /// Start of the window.
        t_on: f64,
        /// End of the window.
        t_off: f64,
    },
    /// Segments of a stepped sine that overlap or are not in time order.
    #[error(
        "segments `{parameter}`: segment {index} starts at {t_on}, before the previous one ends at {previous_end}"
    )]
    OverlappingSegments {
        /// Name (or path) of the segment list.
        parameter: String,
        /// Index of the segment that starts too early.
        index: usize,
        /// Its start time.
        t_on: f64,
        /// End of the previous segment (infinite if it never ends).
        previous_end: f64,
    },
    /// A PRBS order outside the supported table of maximum-length feedback taps.
    #[error("PRBS order {order} out of range: expected {min} ..= {max}")]
    PrbsOrder {
        /// The requested order n.
        order: u32,
        /// Smallest supported order.
        min: u32,
        /// Largest supported order.
        max: u32,
    },
    /// A multisine band that contains no harmonic line of the base frequency.
    #[error(
        "multisine band [{f_min}, {f_max}] Hz contains no harmonic of {base_frequency} Hz (with the chosen line selection)"
    )]
    NoMultisineLines {
        /// Base (fundamental) frequency.
        base_frequency: f64,
        /// Lower band edge.
        f_min: f64,
        /// Upper band edge.
        f_max: f64,
    },
    /// A multisine with more lines than the crate will synthesise.
    #[error("multisine needs harmonic {harmonic}, above the limit {max}")]
    TooManyLines {
        /// Highest harmonic index requested.
        harmonic: u64,
        /// Largest supported harmonic index.
        max: u64,
    },
    /// A data series with no samples.
    #[error("`{name}` is empty")]
    EmptyData {
        /// Name of the series.
        name: &'static str,
    },
    /// A data series shorter than the operation needs.
    #[error("`{name}` has {len} samples, at least {min} are needed")]
    TooShort {
        /// Name of the series.
        name: &'static str,
        /// Its length.
        len: usize,
        /// The minimum needed.
        min: usize,
    },
    /// Two series that must have the same length do not.
    #[error("length mismatch: `{left}` has {left_len} samples, `{right}` has {right_len}")]
    LengthMismatch {
        /// Name of the first series.
        left: &'static str,
        /// Its length.
        left_len: usize,
        /// Name of the second series.
        right: &'static str,
        /// Its length.
        right_len: usize,
    },
    /// A NaN or infinite sample.
    #[error("`{name}`[{index}] = {value} is not finite")]
    NonFinite {
        /// Name of the series.
        name: &'static str,
        /// Index of the first bad sample.
        index: usize,
        /// The bad value.
        value: f64,
    },
    /// Time stamps that are not strictly increasing (a repeat or a step back).
    #[error(
        "time stamps not strictly increasing: t[{index}] = {current} does not exceed the previous stamp {previous}"
    )]
    NonMonotonicTime {
        /// Index of the first offending stamp.
        index: usize,
        /// The stamp before it.
        previous: f64,
        /// The offending stamp.
        current: f64,
    },
    /// A filter or segment window longer than the data it runs over.
    #[error("window of {window} samples is longer than the {len} samples of data")]
    WindowTooLong {
        /// Window length.
        window: usize,
        /// Data length.
        len: usize,
    },
    /// Frequencies of a frequency response that are not strictly increasing.
    #[error(
        "frequencies not strictly increasing: frequency[{index}] = {current} Hz does not exceed the previous {previous} Hz"
    )]
    NonIncreasingFrequency {
        /// Index of the first offending frequency.
        index: usize,
        /// The frequency before it.
        previous: f64,
        /// The offending frequency.
        current: f64,
    },
    /// A record whose length differs from the first record's.
    #[error("record {index} has {len} samples, the first record has {expected}")]
    RecordLength {
        /// Index of the record.
        index: usize,
        /// Its length.
        len: usize,
        /// The first record's length.
        expected: usize,
    },
    /// A [`Recording`](crate::Recording)'s grid, a channel's scale or a sample that is not
    /// what it must be.
    #[error("recording `{recording}`: {what} = {value}: expected {expected}")]
    InvalidRecording {
        /// The recording's name.
        recording: String,
        /// What is wrong: `dt`, `channel `force` scale`, `channel `laser` sample 3`.
        what: String,
        /// The rejected value.
        value: f64,
        /// What was expected, in words.
        expected: &'static str,
    },
    /// A channel of a [`Recording`](crate::Recording) whose length differs from the first
    /// channel's.
    #[error(
        "recording `{recording}`: channel `{channel}` has {len} samples, `{first}` has {expected}"
    )]
    ChannelLength {
        /// The recording's name.
        recording: String,
        /// The channel's name.
        channel: String,
        /// Its length.
        len: usize,
        /// The first channel's name.
        first: String,
        /// The first channel's length.
        expected: usize,
    },
    /// An input with no power at all (after detrending), so no frequency response exists.
    #[error(
        "the input `{name}` has zero power after detrending: no frequency response can be estimated"
    )]
    ZeroInputPower {
        /// Name of the series.
        name: &'static str,
    },
}

/// Shorthand for `Result<T, SignalError>`.
pub type Result<T> = std::result::Result<T, SignalError>;

/// `InvalidParameter` unless `value` is finite.
pub(crate) fn finite(parameter: impl Fn() -> String, value: f64) -> Result<()> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(SignalError::InvalidParameter {
            parameter: parameter(),
            value,
            expected: "a finite value",
        })
    }
}

/// `InvalidParameter` unless `value` is finite and `>= 0`.
pub(crate) fn non_negative(parameter: impl Fn() -> String, value: f64) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(SignalError::InvalidParameter {
            parameter: parameter(),
            value,
            expected: "a finite value >= 0",
        })
    }
}

/// `InvalidParameter` unless `value` is finite and `> 0`.
pub(crate) fn positive(parameter: impl Fn() -> String, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(SignalError::InvalidParameter {
            parameter: parameter(),
            value,
            expected: "a finite value > 0",
        })
    }
}

/// Checks a data series: non-empty and every sample finite.
pub(crate) fn check_data(name: &'static str, x: &[f64]) -> Result<()> {
    if x.is_empty() {
        return Err(SignalError::EmptyData { name });
    }
    if let Some((index, &value)) = x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(SignalError::NonFinite { name, index, value });
    }
    Ok(())
}

/// Checks that two series have the same length.
pub(crate) fn same_length(
    left: &'static str,
    a: &[f64],
    right: &'static str,
    b: &[f64],
) -> Result<()> {
    if a.len() == b.len() {
        Ok(())
    } else {
        Err(SignalError::LengthMismatch {
            left,
            left_len: a.len(),
            right,
            right_len: b.len(),
        })
    }
}
