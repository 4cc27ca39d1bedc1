//! The options of every modal fit: the orders of the stabilization diagram, its
//! tolerances and selection, the band and the weighting.

use serde::{Deserialize, Serialize};

use msd_modal_core::error::{ModalError, Result};
use msd_modal_core::lines::{FrfWeighting, check_band};

/// Options of [`fit_modes`](crate::fit_modes) and [`stabilization_diagram`](crate::stabilization_diagram)
/// (in TOML: a table with any of these fields).
///
/// ```
/// use msd_modal::ModalOptions;
/// let options: ModalOptions = toml::from_str("orders = [2, 60]\nmode_count = 2")?;
/// assert_eq!((options.orders, options.order_step, options.mode_count), ([2, 60], 2, Some(2)));
/// assert_eq!(options.frequency_tolerance, 0.01);
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ModalOptions {
    /// The band to fit in Hz; `None` = every line above 0 Hz. By default `None`.
    #[serde(default, deserialize_with = "msd_signal::pair::optional")]
    pub band_hz: Option<[f64; 2]>,
    /// How the lines are weighted. By default [`FrfWeighting::Coherence`].
    pub weighting: FrfWeighting,
    /// The lowest and highest model order of the diagram. By default [2, 40].
    #[serde(deserialize_with = "msd_signal::pair::exactly_two")]
    pub orders: [usize; 2],
    /// The step between orders. By default 2 (the poles come in conjugate pairs).
    pub order_step: usize,
    /// Relative change of fn from the order before that counts as stable. By default
    /// 0.01 (1 %, the usual criterion; Peeters et al., "The PolyMAX frequency-domain
    /// method", Shock and Vibration 11, 2004).
    pub frequency_tolerance: f64,
    /// Relative change of ζ that counts as stable. By default 0.05 (5 %, idem).
    pub damping_tolerance: f64,
    /// Poles more damped than this are left out of the diagram. By default 0.5.
    pub max_damping_ratio: f64,
    /// Automatic selection: a mode must be stable at this share of the orders.
    /// By default 0.4.
    pub min_stable_share: f64,
    /// Select this many modes (those stable at the most orders) instead. By default
    /// `None` (automatic).
    pub mode_count: Option<usize>,
}

impl Default for ModalOptions {
    fn default() -> Self {
        Self {
            band_hz: None,
            weighting: FrfWeighting::Coherence,
            orders: [2, 40],
            order_step: 2,
            frequency_tolerance: 0.01,
            damping_tolerance: 0.05,
            max_damping_ratio: 0.5,
            min_stable_share: 0.4,
            mode_count: None,
        }
    }
}

impl ModalOptions {
    /// Checks every option, naming the first out of range.
    ///
    /// ```
    /// use msd_modal::{ModalError, ModalOptions};
    /// let bad = ModalOptions { orders: [10, 4], ..ModalOptions::default() };
    /// assert!(matches!(bad.validate(), Err(ModalError::InvalidParameter { name: "orders[1]", .. })));
    /// ```
    pub fn validate(&self) -> Result<()> {
        check_band(self.band_hz)?;
        check_orders(self.orders, self.order_step)?;
        check_fractions(&[
            ("frequency_tolerance", self.frequency_tolerance),
            ("damping_tolerance", self.damping_tolerance),
            ("max_damping_ratio", self.max_damping_ratio),
            ("min_stable_share", self.min_stable_share),
        ])?;
        let invalid = |name, value: f64, expected| {
            Err(ModalError::InvalidParameter {
                name,
                value,
                expected,
            })
        };
        if self.mode_count == Some(0) {
            return invalid("mode_count", 0.0, "at least 1 mode");
        }
        Ok(())
    }
}

/// A diagram's lowest and highest order (1 ≤ low ≤ high ≤ 400) and its step (≥ 1).
pub(crate) fn check_orders([low, high]: [usize; 2], step: usize) -> Result<()> {
    let invalid = |name, value: usize, expected| {
        Err(ModalError::InvalidParameter {
            name,
            value: value as f64,
            expected,
        })
    };
    if low < 1 {
        return invalid("orders[0]", low, "an order >= 1");
    }
    if !(low..=400).contains(&high) {
        return invalid("orders[1]", high, "an order from orders[0] to 400");
    }
    if step < 1 {
        return invalid("order_step", step, "a step >= 1");
    }
    Ok(())
}

/// Tolerances and shares, each in (0, 1], the first outside named.
pub(crate) fn check_fractions(values: &[(&'static str, f64)]) -> Result<()> {
    match values.iter().find(|(_, v)| !(*v > 0.0 && *v <= 1.0)) {
        Some(&(name, value)) => Err(ModalError::InvalidParameter {
            name,
            value,
            expected: "a number in (0, 1]",
        }),
        None => Ok(()),
    }
}
