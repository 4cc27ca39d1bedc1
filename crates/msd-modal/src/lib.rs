//! Experimental and operational modal analysis: which modes a structure has, their
//! natural frequencies, damping ratios and shapes, and how sure we are.
//!
//! This crate builds on `msd-signal` (the [`FrequencyResponseEstimate`] it fits, from time
//! records or measured line by line) and `msd-opt` (Levenberg–Marquardt and the
//! linearised statistics behind every interval). It knows nothing of the physical
//! models of `msd-ident`, which uses it (a chain of masses' modes, the one-mode m, c, k
//! fit's weighted lines).
//!
//! - [`stabilization_diagram`]: poles by the least-squares complex-frequency estimator
//!   (LSCF, `lscf`) over a range of model orders, flagged stable in frequency and damping,
//!   and the stable modes selected automatically or by count;
//! - [`fit_modes`]: the diagram's modes, then fn, ζ, modal constants and the upper and
//!   lower residual terms polished together by weighted Levenberg–Marquardt, with 95 %
//!   intervals;
//! - [`fit_mode_set`]: several FRFs of one structure (a roving hammer or sensor) with
//!   common poles by variable projection, the shapes over named DOFs ([`Dof`]);
//! - shapes: [`mac`], [`mac_matrix`], [`compare_shapes`], [`modal_phase_collinearity`]
//!   (MPC), [`mean_phase_deviation`] (MPD); [`mode_indicator`] (CMIF and MIF);
//! - [`dominant_peak`]: the dominant resonance and the band a one-mode fit takes around
//!   it;
//! - the classroom [`half_power()`] estimate, the exponential window's correction
//!   ([`WindowCorrection`]) and [`synthetic_frequency_response`] for tests and teaching;
//! - [`lines`]: a frequency response's lines prepared for any fit, weighted by
//!   [`FrfWeighting`] (coherence, variance, relative, uniform);
//! - output-only (operational) analysis of records with no measured input
//!   ([`OutputRecord`]): [`ssi_cov`], covariance-driven stochastic subspace identification
//!   with references (and [`ssi_dat`], its data-driven form), its diagram, the automatic selection by clustering and jackknife
//!   intervals ([`OmaOptions`], [`OmaFit`]); [`efdd`], frequency domain decomposition
//!   with EFDD's damping, the quick look ([`FddOptions`], [`SingularSpectrum`], and
//!   [`singular_spectrum`], the CMIF behind any diagram); [`merge_setups`] merges several setups
//!   with shared references into global modes (PoSER), [`node_components`] turns a node's
//!   oblique channels into x, y, z; [`ShearBuilding`] simulates a known truth.
//!
//! Receptance, mobility and accelerance are all fitted as receptance.
//!
//! ```
//! use msd_modal::{ModalOptions, ModalParameters, fit_modes, synthetic_frequency_response};
//! // Two modes, 6 and 15 Hz, measured at 400 lines with 1 % noise.
//! let modes = [(6.0, 0.02, 1.0), (15.0, 0.01, 0.3)].map(|(f, z, a)| ModalParameters {
//!     natural_frequency_hz: f, damping_ratio: z, modal_constant: a, modal_constant_imaginary: 0.0,
//! });
//! let f: Vec<f64> = (1..=400).map(|i| 0.05 * i as f64).collect();
//! let frf = synthetic_frequency_response(&f, 0.01, 1, |f| modes.iter().map(|m| m.receptance(f)).sum())?;
//! let fit = fit_modes(&frf, &ModalOptions::default())?;
//! assert_eq!(fit.modes.len(), 2);
//! assert!(fit.modes[1].natural_frequency_hz.contains(15.0));
//! # Ok::<(), msd_modal::ModalError>(())
//! ```

mod indicator;
mod lscf;
mod modes;
mod oma;
mod options;
mod polish;
mod set;
mod set_poles;
mod shapes;
mod shared_force;
mod stabilization;

pub use indicator::{ModeIndicator, mode_indicator};
pub use modes::{ModalFit, RefusedMode, fit_modes};
// The ground this crate shares with msd-ident (the lines, the modal vocabulary, the
// error), where a user of the modal analysis expects to find it.
pub use msd_modal_core::{
    BANDWIDTHS, DiagramOrder, DiagramPole, Dof, DominantPeak, FrequencyResponseEstimate,
    FrfWeighting, HalfPower, InputNoise, ModalError, ModalParameters, Mode, NOISE_CHECK_LEVEL,
    NoiseCheck, PROMINENCE, Result, ShapeEntry, StabilizationDiagram, StableColumn,
    WindowCorrection, dominant_peak, error, half_power, lines, mean_phase_deviation,
    modal_phase_collinearity, synthetic_frequency_response,
};
pub use oma::{
    FddOptions, MergedFit, OmaFit, OmaMethod, OmaOptions, OutputRecord, Setup, ShearBuilding,
    SingularSpectrum, accelerometer, direction_from_angles, efdd, merge_setups, node_components,
    singular_spectrum, ssi_cov, ssi_dat,
};
// An output-only record's channels, msd-signal's: where its user expects them.
pub use msd_signal::{Channel, Quantity, Recording};
pub use options::ModalOptions;
pub use set::{MemberFit, ModeSetFit, Roving, SetMember, fit_mode_set};
pub use shapes::{ShapeComparison, compare_shapes, mac, mac_matrix, unit_normalised};
pub use shared_force::SharedForce;
pub use stabilization::{stabilization_diagram, why_too_few};
