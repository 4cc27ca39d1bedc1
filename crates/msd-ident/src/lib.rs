//! Identification of a mass–spring–damper m·x'' + c·x' + k·x = F(t) from a known force
//! and a measured displacement.
//!
//! This crate builds on `msd-ode` (simulation), `msd-signal` (excitations, spectra) and
//! `msd-opt` (optimisers).

mod arx;
mod data;
mod error;
mod estimate;
mod frequency;
mod metrics;
mod nonlinear;
mod params;
mod residuals;
mod sensitivity;
mod simulate;
mod synthetic;
mod uncertainty;
mod validation;

pub use arx::arx_initial_guess;
pub use data::{DataSet, Excitation, MIN_SAMPLES};
pub use error::{IdentError, Result};
pub use estimate::{
    Estimate, EstimationOptions, FixedParameters, GuessSource, Method, MultistartSettings,
    ParameterBounds, estimate,
};
pub use frequency::{FrequencyCheck, FrequencyCheckOptions, frequency_check, model_response};
pub use metrics::FitMetrics;
pub use nonlinear::{
    CandidateFailure, Comparison, ComparisonOptions, ComparisonRow, DampingLaw, ModelStructure,
    NonlinearEstimate, NonlinearMethod, NonlinearMultistart, NonlinearOptions, NonlinearParameters,
    NonlinearSimulation, SmoothingVelocity, StiffnessLaw, ValidationStart, bic_evidence,
    compare_models, estimate_nonlinear, fit_initial_state, simulate_nonlinear,
    synthetic_nonlinear_data,
};
pub use params::{InitialState, PARAMETER_NAMES, Parameters};
pub use residuals::{
    CorrelationTest, LjungBox, ResidualAnalysis, ResidualOptions, autocorrelation,
    cross_correlation, ljung_box, residual_analysis,
};
pub use sensitivity::{SensitivitySample, sensitivities};
pub use simulate::{Backend, simulate, simulate_into};
pub use synthetic::{PaperExperiment, synthetic_data};
pub use uncertainty::{Interval, Uncertainty};
pub use validation::{Validation, validate_model};
