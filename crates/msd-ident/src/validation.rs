//! Validation of an identified model on fresh data (never used for fitting).

use crate::{
    data::DataSet,
    error::Result,
    metrics::FitMetrics,
    params::{InitialState, Parameters},
    residuals::{ResidualAnalysis, ResidualOptions, residual_analysis},
    simulate::{Backend, simulate},
};
use serde::{Deserialize, Serialize};

/// How the identified model does on validation data.
///
/// Displays the data set's name, the fit and the residual analysis.
///
/// ```
/// use msd_ident::{validate_model, PaperExperiment, Parameters, ValidationOptions};
/// let experiment = PaperExperiment::generate(1)?;
/// let v = validate_model(&Parameters::PAPER, &experiment.validation, &ValidationOptions::default())?;
/// assert!(v.to_string().starts_with("validation on validation: R² = 0.99"));
/// let json = serde_json::to_value(&v).expect("serializable");
/// assert_eq!(json["data_name"], "validation");
/// assert_eq!(json["residuals"].as_array().map(Vec::len), Some(7501));
/// assert_eq!(json["residual_analysis"]["whiteness_passed"], true);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Validation {
    /// Name of the validation data set.
    pub data_name: String,
    /// The model's prediction (simulation from the initial state, offset added).
    pub model_output: Vec<f64>,
    /// Measurement minus prediction.
    pub residuals: Vec<f64>,
    /// R², fit %, residual RMS.
    pub fit: FitMetrics,
    /// Whiteness and input-independence of the residuals.
    pub residual_analysis: ResidualAnalysis,
}

impl std::fmt::Display for Validation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "validation on {}: {}", self.data_name, self.fit)?;
        write!(f, "{}", self.residual_analysis)
    }
}

/// How [`validate_model`] simulates the model and tests its residuals.
///
/// By default from rest, no offset, exact simulation with a cubic hold, and
/// [`ResidualOptions::default`] (25 lags, 99 %, as MATLAB's `resid`).
///
/// ```
/// use msd_ident::{Backend, InitialState, ValidationOptions};
/// let paper = ValidationOptions { backend: Backend::PAPER, ..ValidationOptions::default() };
/// assert_eq!(paper.initial_state, InitialState::REST);
/// assert_eq!(paper.residuals.max_lag, 25);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ValidationOptions {
    /// The initial state of the simulation. By default at rest.
    pub initial_state: InitialState,
    /// A constant sensor offset added to the prediction. By default 0.
    pub offset: f64,
    /// The simulator. By default exact with a cubic hold.
    pub backend: Backend,
    /// The residual tests. By default 25 lags at 99 % confidence.
    pub residuals: ResidualOptions,
}

/// Simulates `parameters` on `data`'s input and judges the prediction.
///
/// ```
/// use msd_ident::{validate_model, PaperExperiment, Parameters, ValidationOptions};
/// let experiment = PaperExperiment::generate(1)?;
/// let v = validate_model(&Parameters::PAPER, &experiment.validation, &ValidationOptions::default())?;
/// assert!(v.fit.r_squared > 0.99);
/// assert!(v.residual_analysis.whiteness_passed);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn validate_model(
    parameters: &Parameters,
    data: &DataSet,
    options: &ValidationOptions,
) -> Result<Validation> {
    let mut model_output = simulate(
        parameters,
        &data.excitation,
        options.initial_state,
        &options.backend,
    )?;
    for m in &mut model_output {
        *m += options.offset;
    }
    let residuals = crate::metrics::residuals(&data.output, &model_output);
    let fit = FitMetrics::new(&data.output, &model_output);
    let residual_analysis =
        residual_analysis(&residuals, data.excitation.samples(), &options.residuals)?;
    Ok(Validation {
        data_name: data.name.clone(),
        model_output,
        residuals,
        fit,
        residual_analysis,
    })
}
