//! One mode fitted to a frequency response as the physical one-mass plant: m, c and k of
//! H(ω) = 1/(k − mω² + jcω), with 95 % intervals, fn and ζ by the delta method, the gain,
//! and the classroom half-power estimate beside them.
//!
//! The modal fits (the stabilization diagram, several modes, sets of FRFs, shapes) are
//! msd-modal's; this fit shares their ground, msd-modal-core (its weighted lines,
//! [`msd_modal_core::lines`]), and reports the
//! plant in this crate's [`Parameters`](crate::params::Parameters) and
//! [`Uncertainty`](crate::uncertainty::Uncertainty).
//!
//! The data are a [`FrequencyResponseEstimate`](msd_signal::FrequencyResponseEstimate):
//! estimated from time records by msd-signal ([`frf_estimate`](msd_signal::frf_estimate):
//! H1, H2 or Hv with the coherence), or measured line by line, as a stepped-sine sweep
//! gives it (one line per excitation frequency, even or uneven:
//! [`from_magnitude_phase`](msd_signal::FrequencyResponseEstimate::from_magnitude_phase),
//! [`from_real_imaginary`](msd_signal::FrequencyResponseEstimate::from_real_imaginary)).
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

mod one_mode;

pub use one_mode::{LowCoherence, OneModeFit, OneModeOptions, fit_one_mode};
