//! The ground every modal fit stands on, shared by `msd-modal` (the modal analysis) and
//! `msd-ident` (the physical models, whose one-mode FRF fit and chains report modes
//! too), so that neither waits for the other to build.
//!
//! - [`lines`]: a frequency response's lines prepared for any fit, weighted by
//!   [`FrfWeighting`] (coherence, variance, relative, uniform), with the coherence's
//!   noise model and the lines' correlations ([`correlated`]);
//! - [`dominant_peak`]: the dominant resonance and the band a one-mode fit takes around
//!   it; the classroom [`half_power()`] estimate;
//! - the FRF's own noise: [`InputNoise`] (the force's bias of H1) and [`NoiseCheck`]
//!   (residuals against the noise the coherence shows);
//! - the vocabulary fits report in: [`Mode`] (fn, ζ, a complex shape over named DOFs
//!   ([`Dof`], [`ShapeEntry`]) with its MPC and MPD ([`phase`]), the modal constant's
//!   parameters [`ModalParameters`]), the exponential window's correction
//!   ([`WindowCorrection`]), the [`StabilizationDiagram`] any source of poles fills, and
//!   the one error type [`ModalError`];
//! - [`synthetic_frequency_response`] for tests and teaching.
//!
//! It builds on `msd-signal` (the [`FrequencyResponseEstimate`]) and `msd-opt` (the
//! intervals) and knows no fit.
//!
//! ```
//! use msd_modal_core::{ModalParameters, dominant_peak, half_power, synthetic_frequency_response};
//! // One mode at 6 Hz, ζ = 0.02, measured at 400 lines with 1 % noise.
//! let mode = ModalParameters {
//!     natural_frequency_hz: 6.0, damping_ratio: 0.02, modal_constant: 1.0, modal_constant_imaginary: 0.0,
//! };
//! let f: Vec<f64> = (1..=400).map(|i| 0.05 * i as f64).collect();
//! let frf = synthetic_frequency_response(&f, 0.01, 1, |f| mode.receptance(f))?;
//! let peak = dominant_peak(&frf)?;
//! assert!((peak.peak_hz - 6.0).abs() < 0.05);
//! let classroom = half_power(&frf, Some(peak.band_hz))?;
//! assert!((classroom.damping_ratio / 0.02 - 1.0).abs() < 0.2);
//! # Ok::<(), msd_modal_core::ModalError>(())
//! ```

pub mod correlated;
pub mod diagram;
pub mod error;
pub mod half_power;
pub mod input_noise;
pub mod lines;
pub mod modal;
pub mod mode;
pub mod noise_check;
pub mod peak;
pub mod phase;
pub mod synthetic;
pub mod window;

pub use diagram::{DiagramOrder, DiagramPole, StabilizationDiagram, StableColumn};
pub use error::{ModalError, Result};
pub use half_power::{HalfPower, half_power};
pub use input_noise::InputNoise;
pub use lines::FrfWeighting;
pub use modal::ModalParameters;
pub use mode::{Dof, Mode, ShapeEntry};
pub use msd_signal::FrequencyResponseEstimate;
pub use noise_check::{NOISE_CHECK_LEVEL, NoiseCheck};
pub use peak::{BANDWIDTHS, DominantPeak, PROMINENCE, dominant_peak};
pub use phase::{mean_phase_deviation, modal_phase_collinearity};
pub use synthetic::synthetic_frequency_response;
pub use window::WindowCorrection;
