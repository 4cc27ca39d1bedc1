//! Identification of a mass–spring–damper m·x'' + c·x' + k·x = F(t) from a known force
//! and a measured displacement: what are m, c and k, how sure are we, and is the model
//! adequate?
//!
//! This crate builds on `msd-ode` (simulation), `msd-signal` (excitations, noise, spectra)
//! and `msd-opt` (optimisers):
//!
//! - the model: [`Parameters`] and derived quantities, [`Excitation`], [`DataSet`],
//!   [`simulate`] by either [`Backend`] (the paper's ode45, or exact simulation), exact
//!   [`sensitivities`];
//! - estimation: [`estimate`] by the paper's Nelder–Mead or by Levenberg–Marquardt with the
//!   exact Jacobian, fixed parameters, bounds, initial state, offset, multistart and an
//!   automatic ARX guess ([`arx_initial_guess`]); every [`Estimate`] carries an
//!   [`Uncertainty`] (covariance, 95 % intervals, identifiability warnings);
//! - validation: [`validate_model`], [`residual_analysis`] (Ljung–Box, residual–input
//!   correlation, verdicts in words) and [`frequency_check`];
//! - every lab setup as one joint fit, [`fit_records`]: a force on the mass, the base's
//!   acceleration or displacement, or a free decay ([`Drive`]); displacement, velocity and
//!   acceleration sensors, absolute or relative ([`Channel`], [`Frame`]), several at once
//!   with their noise levels estimated; several [`Record`]s of one rig with
//!   leave-one-record-out validation; what each setup identifies said in
//!   [`PlantIntervals`], its Cramér–Rao prediction by [`predicted_records_uncertainty`];
//! - frequency responses as a way in: [`fit_one_mode`] (m, c, k with intervals), the
//!   classroom [`half_power`] estimates, the [`stabilization_diagram`] and [`fit_modes`]
//!   (several modes with intervals);
//! - imposed motion, measured force (a damper test machine): [`dynamometer`] gives each
//!   condition's loop energy, equivalent damping, storage stiffness and loss factor, and
//!   fits and ranks the damping laws across all conditions;
//! - planning the test: [`predicted_uncertainty`] (the Cramér–Rao bound of an input) and
//!   [`design_input`] (the input that minimises it within the rig's limits);
//! - synthetic data for tests and teaching: [`PaperExperiment`], [`synthetic_data`] with
//!   [`SyntheticOptions`].
//!
//! ```
//! use msd_ident::{
//!     estimate, frequency_check, validate_model, EstimationOptions, FrequencyCheckOptions,
//!     PaperExperiment, ValidationOptions,
//! };
//!
//! // The paper's experiment (shared/paper-experiment.md) with noise seed 1.
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

mod arx;
mod chain;
mod correlation;
mod data;
pub mod design;
mod dynamometer;
mod error;
mod estimate;
mod fft;
mod free_decay;
mod frequency;
mod frf;
mod least_squares;
mod local;
mod metrics;
mod nonlinear;
pub mod pair;
mod params;
mod records;
mod residuals;
mod sensitivity;
mod ser;
mod simulate;
mod stop;
mod synthetic;
mod uncertainty;
mod validation;

pub use arx::arx_initial_guess;
pub use chain::ChainPlant;
pub use correlation::{autocorrelation, cross_correlation};
pub use data::{DataSet, Excitation, MIN_SAMPLES};
pub use design::{
    Aggregate, Criterion, Design, DesignConstraints, DesignOptions, InputComparison, Normalise,
    RobustBox, StepOption, StrokeOn, design_input,
};
pub use dynamometer::{
    Condition, ConditionSummary, Dynamometer, DynamometerNoise, DynamometerOptions, LawFit,
    MIN_CYCLES, PredictedLaw, Stroke, SyntheticDynamometer, dynamometer, predicted_dynamometer,
    synthetic_dynamometer,
};
pub use error::{IdentError, Result};
pub use estimate::{
    Estimate, EstimationOptions, FixedParameters, GuessSource, Method, MultistartSettings,
    ParameterBounds, estimate, predicted_uncertainty,
};
pub use free_decay::{
    ClassroomEstimates, FreeDecay, FreeDecayOptions, KnownParameter, PhysicalParameters,
    ResponseQuantity, free_decay,
};
pub use frequency::{FrequencyCheck, FrequencyCheckOptions, frequency_check, model_response};
pub use frf::{
    DiagramOrder, DiagramPole, FrfWeighting, HalfPower, ModalFit, ModalOptions, ModalParameters,
    Mode, OneModeFit, OneModeOptions, StabilizationDiagram, StableMode, WindowCorrection,
    fit_modes, fit_one_mode, half_power, stabilization_diagram, synthetic_frequency_response,
};
pub use metrics::{FTest, FitMetrics};
/// The solver types that appear in this crate's options and results: how a sampled
/// input is held between samples, ode45's step counts, and why Levenberg–Marquardt
/// stopped.
pub use msd_ode::{Hold, Stats as Ode45Stats};
#[doc(no_inline)]
pub use msd_opt::LmExit;
pub use nonlinear::{
    CandidateFailure, Comparison, ComparisonOptions, ComparisonRow, DampingLaw, FixedModel,
    ModelStructure, NonlinearEstimate, NonlinearMethod, NonlinearMultistart, NonlinearOptions,
    NonlinearParameters, NonlinearSensitivities, NonlinearSimulation, NonlinearSolver,
    SimulationUsed, SmoothingVelocity, StiffnessLaw, ValidationStart, assess_estimate,
    bic_evidence, compare_models, estimate_nonlinear, fit_initial_state, nonlinear_sensitivities,
    simulate_nonlinear, synthetic_nonlinear_data,
};
pub use params::{InitialState, PARAMETER_NAMES, Parameters};
pub use records::{
    Channel, ChannelFit, ChannelNoise, Drive, Frame, LeftOut, PlannedChannel, PlannedRecord,
    PlantIntervals, Record, RecordFit, RecordsFit, RecordsOptions, fit_records,
    predicted_records_uncertainty, simulate_channels, simulate_response,
};
pub use residuals::{
    CorrelationTest, LjungBox, ResidualAnalysis, ResidualOptions, ljung_box, residual_analysis,
};
pub use sensitivity::{SensitivitySample, sensitivities};
pub use simulate::{Backend, simulate, simulate_into};
pub use stop::StopReason;
pub use synthetic::{PaperExperiment, SyntheticOptions, synthetic_data};
pub use uncertainty::{Interval, Uncertainty};
pub use validation::{Validation, ValidationOptions, validate_model};
