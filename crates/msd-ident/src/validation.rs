//! Validation of an identified model on fresh data (never used for fitting).

use crate::{
    Backend, DataSet, FitMetrics, InitialState, Parameters, ResidualAnalysis, ResidualOptions,
    Result, residual_analysis, simulate,
};
use serde::{Deserialize, Serialize};

/// How the identified model does on validation data.
///
/// Displays the data set's name, the fit and the residual analysis.
///
/// ```
/// use msd_ident::{validate_model, Backend, InitialState, PaperExperiment, Parameters, ResidualOptions};
/// let experiment = PaperExperiment::generate(1)?;
/// let v = validate_model(&Parameters::PAPER, &experiment.validation, InitialState::REST, 0.0,
///     &Backend::EXACT, &ResidualOptions::default())?;
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

/// Simulates `parameters` on `data`'s input and judges the prediction.
///
/// ```
/// use msd_ident::{validate_model, Backend, InitialState, PaperExperiment, Parameters, ResidualOptions};
/// let experiment = PaperExperiment::generate(1)?;
/// let v = validate_model(&Parameters::PAPER, &experiment.validation, InitialState::REST, 0.0,
///     &Backend::EXACT, &ResidualOptions::default())?;
/// assert!(v.fit.r_squared > 0.99);
/// assert!(v.residual_analysis.whiteness_passed);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn validate_model(
    parameters: &Parameters,
    data: &DataSet,
    initial: InitialState,
    offset: f64,
    backend: &Backend,
    options: &ResidualOptions,
) -> Result<Validation> {
    let mut model_output = simulate(parameters, &data.excitation, initial, backend)?;
    for m in &mut model_output {
        *m += offset;
    }
    let residuals: Vec<f64> = data
        .output
        .iter()
        .zip(&model_output)
        .map(|(y, m)| y - m)
        .collect();
    let fit = FitMetrics::new(&data.output, &model_output);
    let residual_analysis = residual_analysis(&residuals, data.excitation.samples(), options)?;
    Ok(Validation {
        data_name: data.name.clone(),
        model_output,
        residuals,
        fit,
        residual_analysis,
    })
}
