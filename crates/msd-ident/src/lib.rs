//! Identification of a mass–spring–damper m·x'' + c·x' + k·x = F(t) from a known force
//! and a measured displacement.
//!
//! This crate builds on `msd-ode` (simulation), `msd-signal` (excitations, spectra) and
//! `msd-opt` (optimisers).

mod arx;
mod data;
mod error;
mod estimate;
mod metrics;
mod params;
mod sensitivity;
mod simulate;
mod synthetic;
mod uncertainty;

pub use arx::arx_initial_guess;
pub use data::{DataSet, Excitation, MIN_SAMPLES};
pub use error::{IdentError, Result};
pub use estimate::{
    Estimate, EstimationOptions, FixedParameters, GuessSource, Method, MultistartSettings,
    ParameterBounds, estimate,
};
pub use metrics::FitMetrics;
pub use params::{InitialState, PARAMETER_NAMES, Parameters};
pub use sensitivity::{SensitivitySample, sensitivities};
pub use simulate::{Backend, simulate, simulate_into};
pub use synthetic::{PaperExperiment, synthetic_data};
pub use uncertainty::{Interval, Uncertainty};
