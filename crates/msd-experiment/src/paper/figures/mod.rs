//! The paper workflow's figures:
//!
//! - `fig2_identification`: excitation, measurement and model fit, residuals (the
//!   paper's Figure 2);
//! - `fig3_validation`: validation measurements, model prediction and, for synthetic
//!   data, the true response (Figure 3);
//! - `fig4_monte_carlo`: the Monte Carlo band, nominal prediction and measurements
//!   (Figure 4);
//! - `residual_correlation`: residual autocorrelation and residual–input
//!   cross-correlation with their bands;
//! - `frf_bode`: the data's H1 frequency response beside the model's, ωn marked;
//! - `nonlinear_residuals` (with `[nonlinear]`): the validation residuals of every
//!   candidate model over time, their RMS in the legend.

mod diagnostics;
mod models;
mod time;

use super::Outcome;
use crate::error::Result;
use crate::plots::{Drawable, register_fonts, save_all};
use std::path::Path;

/// Writes every figure the outcome supports; returns the base names written.
pub fn write_all(outcome: &Outcome, dir: &Path) -> Result<Vec<&'static str>> {
    register_fonts();
    let units = Units::of(outcome);
    let identification = time::Identification::new(outcome, &units);
    let validation = time::validation(outcome, &units);
    let monte_carlo = time::monte_carlo(outcome, &units);
    let correlation = outcome
        .residuals
        .as_ref()
        .map(diagnostics::Correlation::new);
    let bode = outcome.frequency.check().map(|fc| {
        diagnostics::Bode::new(
            fc,
            outcome.estimate.parameters,
            &units,
            outcome.config.frequency_check.data.name(),
        )
    });
    let models = models::residuals(outcome, &units);
    let mut figures: Vec<&dyn Drawable> = vec![&identification, &validation];
    figures.extend(monte_carlo.as_ref().map(|f| f as &dyn Drawable));
    figures.extend(correlation.as_ref().map(|f| f as &dyn Drawable));
    figures.extend(bode.as_ref().map(|f| f as &dyn Drawable));
    figures.extend(models.as_ref().map(|f| f as &dyn Drawable));
    save_all(&figures, dir)?;
    Ok(figures.iter().map(|f| f.file_name()).collect())
}

/// Display units: displacement in mm when the data are in metres.
#[derive(Debug, Clone)]
pub(crate) struct Units {
    /// Factor from the output unit to the displayed one.
    pub output_factor: f64,
    /// Displayed output unit.
    pub output: String,
    /// Input unit.
    pub input: String,
    /// What the output is called on axes ("displacement" for metres, else "output y").
    pub output_name: &'static str,
    /// What the input is called on axes ("force F" for newtons, else "input u").
    pub input_name: &'static str,
}

impl Units {
    fn of(outcome: &Outcome) -> Self {
        let set = &outcome.data.identification;
        let (output_factor, output) = if set.output_unit == "m" {
            (1e3, "mm".to_string())
        } else {
            (1.0, set.output_unit.clone())
        };
        Self {
            output_factor,
            output,
            input: set.input_unit.clone(),
            output_name: if set.output_unit == "m" {
                "displacement"
            } else {
                "output y"
            },
            input_name: if set.input_unit == "N" {
                "force F"
            } else {
                "input u"
            },
        }
    }
}
