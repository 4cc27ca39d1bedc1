//! The one error type of this crate; msd-signal's and msd-opt's errors convert into it.

use crate::diagram::StabilizationDiagram;
use msd_opt::OptError;
use msd_opt::statistics::Singular;
use msd_signal::SignalError;

/// Everything that can go wrong in `msd-modal`, with the place and the value. The
/// messages are those of msd-ident's `IdentError`, into which this converts.
///
/// ```
/// use msd_modal_core::{ModalError, dominant_peak};
/// use msd_signal::{Complex64, FrequencyResponseEstimate};
/// // A smooth response with no resonance in it.
/// let f: Vec<f64> = (1..=200).map(|i| i as f64).collect();
/// let h = f.iter().map(|&f| Complex64::new(1.0 + 1e-3 * f, 0.0)).collect();
/// let err = dominant_peak(&FrequencyResponseEstimate::new(f, h)?).unwrap_err();
/// assert!(matches!(err, ModalError::NotIdentifiable { .. }), "{err}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModalError {
    /// An option or a value is out of range.
    #[error("invalid {name} = {value}: expected {expected}")]
    InvalidParameter {
        /// Name of the option.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// The allowed range, in words.
        expected: &'static str,
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
    /// Too few lines (or samples) for the requested analysis.
    #[error("too few samples: {got}, need at least {needed} ({why})")]
    TooFewSamples {
        /// Lines available.
        got: usize,
        /// Lines needed.
        needed: usize,
        /// Why that many are needed.
        why: &'static str,
    },
    /// A channel of a record that cannot be used: NaN or infinite samples, or constant
    /// throughout (a dead sensor).
    #[error("channel {channel} cannot be used: {reason}")]
    BadChannel {
        /// The channel's name.
        channel: String,
        /// Why, in words.
        reason: String,
    },
    /// The data cannot determine what was asked.
    #[error("parameters are not identifiable from these data: {reason}")]
    NotIdentifiable {
        /// Why, in words.
        reason: String,
    },
    /// The stabilization diagram holds fewer modes at peaks of the data than the fit
    /// needs (none, or fewer than `mode_count`): why, in words, and the diagram itself,
    /// so that a failed selection can still be drawn and looked at.
    #[error("parameters are not identifiable from these data: {reason}")]
    TooFewModes {
        /// Why, in words: the candidate columns, the likely cause and the keys to change.
        reason: String,
        /// The diagram as computed, with its candidate columns and no (or too few)
        /// selected modes.
        diagram: Box<StabilizationDiagram>,
    },
    /// The estimator ran but did not produce a usable estimate.
    #[error("estimation failed: {reason}")]
    EstimationFailed {
        /// Why, in words.
        reason: String,
    },
    /// An error from msd-signal (a frequency response that is not valid).
    #[error(transparent)]
    Signal(#[from] SignalError),
    /// An error from msd-opt.
    #[error(transparent)]
    Opt(#[from] OptError),
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, ModalError>;

/// [`ModalError::NotIdentifiable`] for a singular Jacobian: `data` is what was fitted,
/// `names` the columns' names.
pub fn not_identifiable(singular: Singular, data: &str, names: &[&str]) -> ModalError {
    ModalError::NotIdentifiable {
        reason: singular.reason(data, names),
    }
}
