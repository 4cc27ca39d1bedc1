//! CSV files of every time series and curve of a run (numbers in Rust's shortest
//! round-trip form, so the files are exact and deterministic).
//!
//! - `identification.csv`: t, input, measured, model, residual (and true_response for
//!   synthetic data);
//! - `validation.csv`: the same on the validation record, plus the Monte Carlo band
//!   (band_lower, band_median, band_upper, band_nominal) when it ran;
//! - `residual_correlation.csv`: lag, autocorrelation, cross_correlation, bound;
//! - `frf.csv`: frequency_hz and the empirical and model magnitude and phase;
//! - `nonlinear.csv` (with `[nonlinear]`): t, input, measured on the validation record,
//!   then `model_<name>` and `residual_<name>` of each candidate in rank order (e.g.
//!   `residual_viscous+cubic`).

use crate::paper::Outcome;
use crate::table::Table;

/// The CSV files of `outcome` as (file name, contents).
pub fn csv_files(outcome: &Outcome) -> Vec<(&'static str, String)> {
    let o = outcome;
    let mut files = Vec::new();

    let d = &o.data.identification;
    let mut t = Table::new();
    t.column("t", d.excitation.times());
    t.column("input", d.excitation.samples());
    t.column("measured", &d.output);
    t.column("model", &o.estimate.model_output);
    t.column("residual", &o.estimate.residuals);
    if let Some(truth) = &o.data.identification_truth {
        t.column("true_response", truth);
    }
    files.push(("identification.csv", t.render()));

    let d = &o.data.validation;
    let mut t = Table::new();
    t.column("t", d.excitation.times());
    t.column("input", d.excitation.samples());
    t.column("measured", &d.output);
    t.column("model", &o.validation.model_output);
    t.column("residual", &o.validation.residuals);
    if let Some(truth) = &o.data.validation_truth {
        t.column("true_response", truth);
    }
    if let Some(mc) = &o.monte_carlo {
        t.column("band_lower", &mc.lower);
        t.column("band_median", &mc.median);
        t.column("band_upper", &mc.upper);
        t.column("band_nominal", &mc.nominal);
    }
    files.push(("validation.csv", t.render()));

    if let Some(r) = &o.residuals {
        let cross = &r.cross_correlation;
        let auto = &r.autocorrelation;
        let mut t = Table::new();
        let lags: Vec<f64> = cross.lags.iter().map(|&k| k as f64).collect();
        t.column("lag", &lags);
        t.sparse(
            "autocorrelation",
            cross
                .lags
                .iter()
                .map(|&k| {
                    auto.lags
                        .iter()
                        .position(|&a| a == k)
                        .map(|i| auto.values[i])
                })
                .collect(),
        );
        t.column("cross_correlation", &cross.values);
        t.column("bound", &vec![cross.bound; lags.len()]);
        files.push(("residual_correlation.csv", t.render()));
    }

    if let Some(f) = o.frequency.check() {
        let mut t = Table::new();
        t.column("frequency_hz", &f.frequency_hz);
        t.column("empirical_magnitude", &f.empirical_magnitude);
        t.column("empirical_phase_deg", &f.empirical_phase_deg);
        t.column("model_magnitude", &f.model_magnitude);
        t.column("model_phase_deg", &f.model_phase_deg);
        t.column("coherence", &f.coherence);
        files.push(("frf.csv", t.render()));
    }

    if let Some(n) = &o.nonlinear {
        let d = &o.data.validation;
        let mut t = Table::new();
        t.column("t", d.excitation.times());
        t.column("input", d.excitation.samples());
        t.column("measured", &d.output);
        for r in &n.comparison.rows {
            t.column(format!("model_{}", r.structure), &r.validation_output);
            t.column(format!("residual_{}", r.structure), &r.validation_residuals);
        }
        files.push(("nonlinear.csv", t.render()));
    }
    files
}
