//! The stabilization diagram as data: the poles of every model order with their stability
//! flags, and the modes that stay stable. Any method that gives poles order by order
//! (LSCF here, stochastic subspace identification next) fills one; the figures, the
//! report and the selection read it.

use serde::Serialize;

/// One pole of one model order in the diagram.
///
/// ```
/// use msd_modal::{ModalOptions, stabilization_diagram, synthetic_frequency_response, ModalParameters};
/// let mode = ModalParameters { natural_frequency_hz: 5.0, damping_ratio: 0.03,
///     modal_constant: 1.0, modal_constant_imaginary: 0.0 };
/// let f: Vec<f64> = (1..=200).map(|i| 0.05 * i as f64).collect();
/// let frf = synthetic_frequency_response(&f, 0.0, 1, |f| mode.receptance(f))?;
/// let diagram = stabilization_diagram(&frf, &ModalOptions { orders: [2, 10], ..ModalOptions::default() })?;
/// // The z-domain model needs a little more than the mode's two poles: order 2 puts it
/// // at 5.003 Hz (ζ = 0.0286), order 4 at 4.9997 Hz (ζ = 0.03002: stable in frequency,
/// // not yet in damping), order 6 at 5.00002 Hz, the first stable in both.
/// let order_6 = &diagram.orders[2];
/// assert_eq!(order_6.order, 6);
/// let pole = order_6.poles.iter().find(|p| p.stable).expect("the mode is stable");
/// assert!((pole.natural_frequency_hz / 5.0 - 1.0).abs() < 1e-4);
/// assert!(diagram.orders[1].poles.iter().all(|p| p.stable_frequency && !p.stable));
/// assert_eq!(diagram.modes.len(), 1);
/// assert_eq!(diagram.modes[0].stable_orders, 4); // stable in frequency at orders 4 to 10
/// # Ok::<(), msd_modal::ModalError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DiagramPole {
    /// fn = |λ|/2π, Hz.
    pub natural_frequency_hz: f64,
    /// ζ = −Re λ/|λ|.
    pub damping_ratio: f64,
    /// fn within `frequency_tolerance` of the nearest pole of the order before.
    pub stable_frequency: bool,
    /// ζ within `damping_tolerance` of that pole's.
    pub stable_damping: bool,
    /// Both: a stable pole.
    pub stable: bool,
    /// Which selected mode (index into the fit's modes) it is a pole of, where the
    /// selection clusters poles (output-only analysis); `None` elsewhere.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mode: Option<usize>,
}

/// The physical poles of one model order (Im λ > 0, Re λ < 0, fn in the band,
/// ζ ≤ `max_damping_ratio`), by frequency (see [`DiagramPole`] for an example).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DiagramOrder {
    /// The order n of the common denominator (n poles, n/2 conjugate pairs at most).
    pub order: usize,
    /// Its poles.
    pub poles: Vec<DiagramPole>,
}

/// A column of the diagram: poles stable at several orders, at nearly one frequency (a
/// candidate mode)
/// (see [`DiagramPole`] for an example).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StableColumn {
    /// The median fn of its stable poles, Hz.
    pub natural_frequency_hz: f64,
    /// The median ζ of its stable poles.
    pub damping_ratio: f64,
    /// At how many orders it has a pole stable in frequency.
    pub stable_orders: usize,
    /// Whether the measured magnitude has a peak within its half-power band (or 1.5
    /// lines): only such columns are selected.
    pub at_peak: bool,
}

/// The stabilization diagram of a frequency response and the modes selected from it.
///
/// Displays one line per selected mode; serializes with every order's poles and flags,
/// for a plot.
///
/// ```
/// use msd_modal::{ModalOptions, stabilization_diagram, synthetic_frequency_response, ModalParameters};
/// let mode = ModalParameters { natural_frequency_hz: 5.0, damping_ratio: 0.03,
///     modal_constant: 1.0, modal_constant_imaginary: 0.0 };
/// let f: Vec<f64> = (1..=200).map(|i| 0.05 * i as f64).collect();
/// let frf = synthetic_frequency_response(&f, 0.01, 1, |f| mode.receptance(f))?;
/// let diagram = stabilization_diagram(&frf, &ModalOptions::default())?;
/// assert!(diagram.to_string().starts_with("stabilization diagram, orders 2–40"));
/// let json = serde_json::to_value(&diagram).expect("serializable");
/// assert_eq!(json["orders"].as_array().map(Vec::len), Some(20));
/// # Ok::<(), msd_modal::ModalError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StabilizationDiagram {
    /// Every order, lowest first.
    pub orders: Vec<DiagramOrder>,
    /// Every column of poles stable in frequency (the modes' candidates), by frequency.
    pub candidates: Vec<StableColumn>,
    /// The selected modes, by frequency.
    pub modes: Vec<StableColumn>,
    /// The first and last line used, Hz.
    pub band_hz: [f64; 2],
}

impl std::fmt::Display for StabilizationDiagram {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (first, last) = (
            self.orders.first().map_or(0, |o| o.order),
            self.orders.last().map_or(0, |o| o.order),
        );
        write!(
            f,
            "stabilization diagram, orders {first}–{last}, {:.4}–{:.4} Hz: {} stable modes",
            self.band_hz[0],
            self.band_hz[1],
            self.modes.len()
        )?;
        for m in &self.modes {
            write!(
                f,
                "\n  fn = {:.4} Hz, ζ = {:.5}, stable at {} of {} orders",
                m.natural_frequency_hz,
                m.damping_ratio,
                m.stable_orders,
                self.orders.len()
            )?;
        }
        Ok(())
    }
}
