//! The quantity a sensor measures, the vocabulary every record and engine shares.

use serde::{Deserialize, Serialize};

/// The quantity a sensor measures.
///
/// ```
/// use msd_signal::ResponseQuantity;
/// let q: ResponseQuantity = serde_json::from_str("\"acceleration\"")?;
/// assert_eq!(q, ResponseQuantity::Acceleration);
/// assert_eq!(ResponseQuantity::default(), ResponseQuantity::Displacement);
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ResponseQuantity {
    /// Displacement x (a laser or LVDT).
    #[default]
    Displacement,
    /// Velocity x′ (a geophone or laser vibrometer).
    Velocity,
    /// Acceleration x″ (an accelerometer).
    Acceleration,
}
