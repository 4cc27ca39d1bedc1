//! Identification of a mass–spring–damper m·x'' + c·x' + k·x = F(t) from a known force
//! and a measured displacement: what are m, c and k, how sure are we, and is the model
//! adequate?
//!
//! This crate builds on `msd-ode` (simulation), `msd-signal` (excitations, noise, spectra)
//! and `msd-opt` (optimisers):
//!
//! - the model: [`Parameters`] and derived quantities, [`Excitation`], [`DataSet`],
//!   [`simulate`] by either [`Backend`] (the paper's ode45, or exact simulation), exact
//!   [`sensitivities`](sensitivity::sensitivities);
//! - estimation: [`estimate()`] by the paper's Nelder–Mead or by Levenberg–Marquardt with the
//!   exact Jacobian, fixed parameters, bounds, initial state, offset, multistart and an
//!   automatic ARX guess ([`arx_initial_guess`](arx::arx_initial_guess)); every [`Estimate`] carries an
//!   [`Uncertainty`] (covariance, 95 % intervals, identifiability warnings);
//! - validation: [`validate_model`], [`residual_analysis`] (Ljung–Box, residual–input
//!   correlation, verdicts in words) and [`frequency_check`](frequency::frequency_check);
//! - every lab setup as one joint fit, [`fit_records`]: a force on the mass, the base's
//!   acceleration or displacement, or a free decay ([`Drive`]); displacement, velocity and
//!   acceleration sensors, absolute or relative ([`Channel`], [`Frame`]: msd-signal's, as
//!   every engine's records), several at once with their noise levels estimated; a
//!   [`Record`] built by hand or read from an msd-signal
//!   [`Recording`](msd_signal::Recording) ([`Record::from_recording`]); several records of one rig with
//!   leave-one-record-out validation; what each setup identifies said in
//!   [`PlantIntervals`](records::PlantIntervals), its Cramér–Rao prediction by [`predicted_records_uncertainty`](records::predicted_records_uncertainty);
//! - frequency responses as a way in: [`fit_one_mode`] (m, c, k with intervals, the
//!   classroom half-power estimate beside them); the modal fits (stabilization diagram,
//!   several modes, sets and shapes) are msd-modal's;
//! - imposed motion, measured force (a damper test machine): [`dynamometer()`](dynamometer::dynamometer) gives each
//!   condition's loop energy, equivalent damping, storage stiffness and loss factor, and
//!   fits and ranks the damping laws across all conditions;
//! - a chain of one to eight masses ([`chain`]): every m, c, k from force or base-motion
//!   records with sensor delays and low-pass filters, the modes, the Cramér–Rao plan;
//! - planning the test: [`predicted_uncertainty`] (the Cramér–Rao bound of an input) and
//!   [`design_input`](design::design_input) (the input that minimises it within the rig's limits);
//! - synthetic data for tests and teaching: [`PaperExperiment`], [`synthetic_data`] with
//!   [`SyntheticOptions`].
//!
//! ```
//! use msd_ident::{
//!     estimate, validate_model, EstimationOptions, PaperExperiment, ValidationOptions,
//!     frequency::{frequency_check, FrequencyCheckOptions},
//! };
//!
//! // The paper's experiment (docs/paper-experiment.md) with noise seed 1.
//! let experiment = PaperExperiment::generate(1)?;
//!
//! // The fast method from the paper's initial guess θ0 = (2, 1, 100).
//! let fit = estimate(&experiment.identification, &EstimationOptions::fast())?;
//! let k = &fit.uncertainty.stiffness;
//! assert!(k.ci95[0] < 120.5 && 119.5 < k.ci95[1]);
//!
//! // Is the model adequate on fresh data?
//! let validation = validate_model(&fit.parameters, &experiment.validation,
//!     &ValidationOptions::default())?;
//! assert!(validation.fit.r_squared > 0.99);
//! println!("{}", validation.residual_analysis.verdict);
//!
//! // Does the data's resonance agree with the model's?
//! let check = frequency_check(&experiment.validation, &fit.parameters, Some(&fit.uncertainty),
//!     &FrequencyCheckOptions::default())?;
//! assert!(check.consistent, "{}", check.verdict);
//! # Ok::<(), msd_ident::IdentError>(())
//! ```

pub mod arx;
pub mod chain;
pub mod correlation;
pub mod data;
pub mod design;
pub mod dynamometer;
mod error;
pub mod estimate;
mod fft;
pub mod free_decay;
pub mod frequency;
pub mod frf;
mod input_noise;
pub mod law;
mod least_squares;
mod local;
mod metrics;
pub mod nonlinear;
mod params;
mod plant;
pub mod records;
pub mod residuals;
pub mod sensitivity;
mod ser;
mod simulate;
mod stop;
mod synthetic;
mod uncertainty;
mod validation;

pub use data::{DataSet, Excitation};
pub use error::{IdentError, Result};
pub use estimate::{
    Estimate, EstimationOptions, Method, PlannedInformation, estimate, predicted_uncertainty,
};
pub use frf::{OneModeFit, OneModeOptions, fit_one_mode};
pub use metrics::{FTest, FitMetrics};
/// The solver types that appear in this crate's options and results: how a sampled
/// input is held between samples, ode45's step counts, and why Levenberg–Marquardt
/// stopped.
pub use msd_ode::{Hold, Stats as Ode45Stats};
#[doc(no_inline)]
pub use msd_opt::LmExit;
pub use msd_opt::statistics::Interval;
/// A sensor's channel, its frame and what it measures (msd-signal's, shared by every
/// record and engine).
pub use msd_signal::{Channel, Frame, Quantity, ResponseQuantity};
pub use params::{InitialState, KnownParameter, Parameters};
pub use plant::Drive;
pub use records::{Record, RecordsFit, RecordsOptions, fit_records};
pub use residuals::{ResidualAnalysis, ResidualOptions, residual_analysis};
pub use simulate::{Backend, simulate, simulate_into};
pub use stop::StopReason;
pub use synthetic::{PaperExperiment, SyntheticOptions, synthetic_data};
pub use uncertainty::Uncertainty;
pub use validation::{Validation, ValidationOptions, validate_model};
