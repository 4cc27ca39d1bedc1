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
use crate::plots::{Figure, register_fonts, save};
use std::path::Path;

/// Writes every figure the outcome supports; returns the base names written.
pub fn write_all(outcome: &Outcome, dir: &Path) -> Result<Vec<&'static str>> {
    register_fonts();
    let mut written = Vec::new();
    let units = Units::of(outcome);
    let f2 = time::Identification::new(outcome, &units);
    save(&f2, dir)?;
    written.push(f2.name());
    let f3 = time::validation(outcome, &units);
    save(&f3, dir)?;
    written.push(f3.name());
    if let Some(f4) = time::monte_carlo(outcome, &units) {
        save(&f4, dir)?;
        written.push(f4.name());
    }
    if let Some(r) = &outcome.residuals {
        let f = diagnostics::Correlation::new(r);
        save(&f, dir)?;
        written.push(f.name());
    }
    if let Some(fc) = outcome.frequency.check() {
        let f = diagnostics::Bode::new(
            fc,
            outcome.estimate.parameters,
            &units,
            outcome.config.frequency_check.data.name(),
        );
        save(&f, dir)?;
        written.push(f.name());
    }
    if let Some(f) = models::residuals(outcome, &units) {
        save(&f, dir)?;
        written.push(f.name());
    }
    Ok(written)
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
