//! The stabilization diagram as data: the poles of every model order with their stability
//! flags, and the modes that stay stable. Any method that gives poles order by order
//! (LSCF here, stochastic subspace identification next) fills one; the figures, the
//! report and the selection read it.

use serde::Serialize;

/// One pole of one model order in the diagram.
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
/// ζ ≤ `max_damping_ratio`), by frequency.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DiagramOrder {
    /// The order n of the common denominator (n poles, n/2 conjugate pairs at most).
    pub order: usize,
    /// Its poles.
    pub poles: Vec<DiagramPole>,
}

/// A column of the diagram: poles stable at several orders, at nearly one frequency (a
/// candidate mode).
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
/// for a plot (`msd_modal::stabilization_diagram` fills one; its documentation shows
/// both).
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
