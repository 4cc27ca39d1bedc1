//! The nonlinear-models stage (`[nonlinear]` in a config): estimate one nonlinear model
//! or compare candidates by BIC on the identification record, each scored on the
//! validation record, as msd-ident's [`compare_models`] does.
//!
//! The estimation starts from the `[estimation]` stage's linear estimate (and its
//! initial state); the validation prediction starts at rest, or from the state fitted
//! to the first `data.validation.initial_samples` samples, which are then not scored.
//!
//! ```no_run
//! use msd_experiment::{RunOptions, run_experiment};
//! let run = run_experiment("configs/silverbox-models.toml".as_ref(), &RunOptions::default())?;
//! println!("{}", run.results["nonlinear"]["verdict"]);
//! # Ok::<(), msd_experiment::ExperimentError>(())
//! ```

use crate::config::{Config, NonlinearSection};
use crate::data::ExperimentData;
use crate::error::{ExperimentError, Result};
use msd_ident::{
    Estimate, ResidualOptions,
    nonlinear::{
        Comparison, ComparisonOptions, NonlinearMultistart, NonlinearOptions, NonlinearParameters,
        ValidationStart, assess_estimate, compare_models, estimate_nonlinear,
    },
};

/// What the nonlinear-models stage produced.
#[derive(Debug, Clone)]
pub struct NonlinearOutcome {
    /// Whether several candidates were compared (else one model was estimated).
    pub comparison_asked: bool,
    /// The ranking (one row for a single model), the verdict and any failures.
    pub comparison: Comparison,
    /// The true plant when the data are synthetic from a plant with nonlinear terms.
    pub plant: Option<NonlinearParameters>,
    /// The validation RMS of the `[estimation]` stage's linear model, for reference.
    pub linear_validation_rms: f64,
}

/// The options of the stage: the section's fields over msd-ident's defaults, the
/// initial state from `[estimation]` and the linear estimate as the start.
pub fn options(
    section: &NonlinearSection,
    config: &Config,
    data: &ExperimentData,
    estimate: &Estimate,
    seed: u64,
    threads: usize,
) -> ComparisonOptions {
    let mut estimation = NonlinearOptions {
        method: section.method,
        simulation: section.simulation,
        linear_start: Some(estimate.parameters),
        initial_state: estimate.initial_state,
        estimate_initial_state: section
            .estimate_initial_state
            .unwrap_or(config.estimation.estimate_initial_state),
        dissipative_damping: section.dissipative_damping,
        covariance: section.covariance,
        multistart: section.multistart.map(|m| NonlinearMultistart {
            starts: m.starts,
            decades: m.decades,
            nonlinear_width: m.nonlinear_width,
            seed: m.seed.unwrap_or(seed),
            threads,
        }),
        ..NonlinearOptions::default()
    };
    if let Some(n) = section.max_evaluations {
        estimation.levenberg_marquardt.max_evaluations = Some(n);
        estimation.nelder_mead.max_evaluations = Some(n);
    }
    let n0 = data.validation_initial_samples;
    ComparisonOptions {
        estimation,
        validation_start: if n0 > 0 {
            ValidationStart::FitInitialState { samples: n0 }
        } else {
            ValidationStart::Rest
        },
        residuals: ResidualOptions {
            max_lag: config.residuals.max_lag,
            confidence: config.residuals.confidence,
        },
    }
}

/// Runs the stage: [`compare_models`] for `compare`, or [`estimate_nonlinear`] and
/// [`assess_estimate`] for `model`.
pub fn run(
    section: &NonlinearSection,
    config: &Config,
    data: &ExperimentData,
    estimate: &Estimate,
    linear_validation_rms: f64,
    seed: u64,
    threads: usize,
) -> Result<NonlinearOutcome> {
    let fail = |e: msd_ident::IdentError| ExperimentError::run("nonlinear models", e);
    let options = options(section, config, data, estimate, seed, threads);
    let comparison = match section.model {
        None => compare_models(
            &data.identification,
            &data.validation,
            &section.candidates(),
            &options,
        )
        .map_err(fail)?,
        Some(model) => {
            let e = estimate_nonlinear(&data.identification, model, &options.estimation)
                .map_err(fail)?;
            let row = assess_estimate(&e, &data.validation, &options).map_err(fail)?;
            Comparison {
                verdict: single_verdict(&row, linear_validation_rms),
                rows: vec![row],
                failures: Vec::new(),
            }
        }
    };
    Ok(NonlinearOutcome {
        comparison_asked: section.is_comparison(),
        comparison,
        plant: config.plant.as_ref().and_then(|p| p.nonlinear()),
        linear_validation_rms,
    })
}

/// The verdict of a single estimated model, against the linear model's validation RMS.
fn single_verdict(row: &msd_ident::nonlinear::ComparisonRow, linear_rms: f64) -> String {
    format!(
        "One model estimated: {} ({} estimated quantities, {}). On the validation data its RMS error is {:.4e} against {:.4e} for the linear model of the estimation stage ({:+.1} %); its residuals {} white (Ljung–Box p = {:.3}) and {} with the input.",
        row.structure,
        row.estimated,
        if row.stop.converged() {
            "converged"
        } else {
            "NOT converged"
        },
        row.validation_rms,
        linear_rms,
        100.0 * (row.validation_rms / linear_rms - 1.0),
        if row.whiteness_passed {
            "are"
        } else {
            "are not"
        },
        row.whiteness_p,
        if row.cross_correlation_passed {
            "uncorrelated"
        } else {
            "correlated"
        }
    )
}
