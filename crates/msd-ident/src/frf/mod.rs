//! Fitting a frequency response: one mode (m, c, k, or fn, ζ and a gain), several modes
//! (poles from a stabilization diagram, then every modal parameter polished), each with
//! 95 % intervals; and the classroom peak-picking and half-power estimates beside them.
//!
//! The data are a [`FrequencyResponseEstimate`](msd_signal::FrequencyResponseEstimate):
//! estimated from time records by msd-signal ([`frf_estimate`](msd_signal::frf_estimate):
//! H1, H2 or Hv with the coherence), or measured line by line, as a stepped-sine sweep
//! gives it (one line per excitation frequency, even or uneven:
//! [`from_magnitude_phase`](msd_signal::FrequencyResponseEstimate::from_magnitude_phase),
//! [`from_real_imaginary`](msd_signal::FrequencyResponseEstimate::from_real_imaginary)).
//! Receptance, mobility and accelerance are all fitted as receptance. The lines are
//! weighted by [`FrfWeighting`]: from the coherence, from given variances, relative or
//! uniform. An exponential window recorded in the estimate is taken off the damping
//! ([`WindowCorrection`]).
//!
//! - [`fit_one_mode`]: m, c, k of 1/(k − mω² + jcω) by weighted Levenberg–Marquardt from
//!   Levy's linear start, Gauss–Newton intervals, fn and ζ by the delta method.
//! - [`half_power`]: peak picking and ζ ≈ (f₂ − f₁)/(2·fn).
//! - [`stabilization_diagram`]: poles by the least-squares complex-frequency estimator
//!   (LSCF) over a range of model orders, flagged stable in frequency and damping, and
//!   the stable modes selected automatically or by count.
//! - [`synthetic_frequency_response`]: a table with known truth and seeded noise.
//! - [`fit_modes`]: the diagram's modes, then fn, ζ, modal constants and the upper and
//!   lower residual terms polished together by weighted Levenberg–Marquardt, with
//!   intervals.
//!
//! ```
//! use msd_ident::{fit_one_mode, OneModeOptions, Parameters, frequency::model_response};
//! use msd_signal::FrequencyResponseEstimate;
//! // The paper's plant measured at 40 frequencies (exact values, as magnitude and phase).
//! let f: Vec<f64> = (0..40).map(|i| 0.25 + 0.0577 * i as f64).collect();
//! let h: Vec<_> = f.iter().map(|f| model_response(&Parameters::PAPER, std::f64::consts::TAU * f)).collect();
//! let magnitude: Vec<f64> = h.iter().map(|h| h.norm()).collect();
//! let phase: Vec<f64> = h.iter().map(|h| h.arg().to_degrees()).collect();
//! let sweep = FrequencyResponseEstimate::from_magnitude_phase(&f, &magnitude, &phase)?;
//! let fit = fit_one_mode(&sweep, &OneModeOptions::default())?;
//! assert!((fit.parameters.mass - 2.5).abs() < 1e-9);
//! assert!((fit.uncertainty.natural_frequency_hz.value - 1.1027).abs() < 1e-4);
//! let classroom = fit.half_power.expect("the peak is resolved");
//! assert!((classroom.damping_ratio / 0.052 - 1.0).abs() < 0.1);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod half_power;
mod indicator;
mod lines;
mod lscf;
mod modal;
mod modes;
mod one_mode;
mod polish;
mod set;
mod set_poles;
mod shapes;
mod stabilization;
mod synthetic;
mod window;

pub use half_power::{HalfPower, half_power};
pub use indicator::{ModeIndicator, mode_indicator};
pub use lines::FrfWeighting;
pub use modal::ModalParameters;
pub use modes::{ModalFit, ModalOptions, Mode, RefusedMode, fit_modes};
pub use one_mode::{OneModeFit, OneModeOptions, fit_one_mode};
pub use set::{Dof, MemberFit, ModeSetFit, Roving, SetMember, SetMode, ShapeEntry, fit_mode_set};
pub use shapes::{
    ShapeComparison, compare_shapes, mac, mac_matrix, mean_phase_deviation,
    modal_phase_collinearity, unit_normalised,
};
pub use stabilization::{
    DiagramOrder, DiagramPole, StabilizationDiagram, StableMode, stabilization_diagram,
};
pub use synthetic::synthetic_frequency_response;
pub use window::WindowCorrection;
