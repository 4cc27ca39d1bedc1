//! The paper's workflow, one kind of experiment: its stages, each timed (data →
//! estimation → validation → residual diagnostics → frequency check → Monte Carlo →
//! nonlinear models when the config has a `[nonlinear]` section, [`nonlinear`]), and
//! the parts the writer ([`crate::run`]) takes: [`figures`], [`tables`], [`report`],
//! [`results`] and [`summary`].

pub mod figures;
pub mod nonlinear;
pub mod report;
pub mod results;
pub mod summary;
pub mod tables;

pub use crate::options::RunOptions;

use crate::config::{Config, Kind, RecordChoice};
use crate::data::{self, ExperimentData};
use crate::error::{ExperimentError, Result};
use crate::progress::Progress;
use msd_ident::{
    Backend, Estimate, FitMetrics, IdentError, InitialState, Parameters, ResidualOptions,
    ValidationOptions, estimate,
    frequency::frequency_check,
    nonlinear::{FixedModel, fit_initial_state},
    residual_analysis, simulate_into, validate_model,
};
use msd_mc::{McOptions, monte_carlo_band_with_progress};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Everything an experiment produced, in memory.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The config as read.
    pub config: Config,
    /// The config file as given.
    pub config_path: PathBuf,
    /// The command that ran it, for the report (`msd run`, `cargo xtask experiment`).
    pub command: String,
    /// The seed used (`--seed` or the config's).
    pub seed: u64,
    /// Worker threads of the parallel stages (`--threads` or the config's).
    pub threads: usize,
    /// Both records.
    pub data: ExperimentData,
    /// The estimate on the identification record.
    pub estimate: Estimate,
    /// The prediction on the validation record.
    pub validation: ValidationOutcome,
    /// ode45 statistics (accepted steps, rejected steps, right-hand-side evaluations) of
    /// one simulation of the identification record at θ̂, for the ode45 backend.
    pub estimation_solver: Option<msd_ident::Ode45Stats>,
    /// Residual diagnostics of the identification residuals.
    pub residuals: Option<msd_ident::ResidualAnalysis>,
    /// Whether the model explains the identification data significantly better than
    /// their mean (the regression F-test): white residuals alone do not make it adequate.
    pub significance: msd_ident::FTest,
    /// Frequency-domain consistency check on the record `[frequency_check] data` names
    /// (validation by default): done, skipped with its reason, or off.
    pub frequency: FrequencyStage,
    /// Monte Carlo band on the validation record.
    pub monte_carlo: Option<MonteCarloOutcome>,
    /// Nonlinear models estimated or compared (`[nonlinear]`).
    pub nonlinear: Option<crate::paper::nonlinear::NonlinearOutcome>,
    /// Wall time of each stage, in order.
    pub timings: Vec<(&'static str, Duration)>,
}

/// What became of the frequency-domain consistency check.
#[derive(Debug, Clone)]
pub enum FrequencyStage {
    /// Not asked for (`[frequency_check] enabled = false`).
    Off,
    /// Done.
    Checked(Box<msd_ident::frequency::FrequencyCheck>),
    /// Asked for, but not possible on these data (no resonance in the excited band — an
    /// over-damped plant, or a mode outside the band — or no input power above DC): the
    /// check's reason, in words. The run goes on without it.
    Skipped(String),
}

impl FrequencyStage {
    /// The check, when it was done.
    pub fn check(&self) -> Option<&msd_ident::frequency::FrequencyCheck> {
        match self {
            Self::Checked(check) => Some(check),
            _ => None,
        }
    }

    /// Why it was skipped, when it was.
    pub fn skipped(&self) -> Option<&str> {
        match self {
            Self::Skipped(reason) => Some(reason),
            _ => None,
        }
    }
}

/// The model's prediction on the validation record.
#[derive(Debug, Clone)]
pub struct ValidationOutcome {
    /// The simulator used.
    pub backend: Backend,
    /// The initial state of the prediction (settled on the first samples for measured
    /// data when asked).
    pub initial_state: InitialState,
    /// Model output on the whole validation record (offset included).
    pub model_output: Vec<f64>,
    /// Measurement minus model on the whole record.
    pub residuals: Vec<f64>,
    /// Samples at the start that only settled the initial state (not scored).
    pub scored_from: usize,
    /// Fit on the scored samples.
    pub fit: FitMetrics,
    /// Residual diagnostics of the scored validation residuals.
    pub residual_analysis: Option<msd_ident::ResidualAnalysis>,
    /// Fit of the noise-free true response (synthetic only): the ceiling R².
    pub truth_fit: Option<FitMetrics>,
    /// ode45 statistics of the prediction (accepted steps, rejected steps, right-hand-side
    /// evaluations), for the ode45 backend.
    pub solver: Option<msd_ident::Ode45Stats>,
}

/// The Monte Carlo band on the validation record.
#[derive(Debug, Clone)]
pub struct MonteCarloOutcome {
    /// Number of draws.
    pub samples: usize,
    /// Draws whose simulation failed (left out of the band).
    pub failed_samples: usize,
    /// Worker threads.
    pub threads: usize,
    /// ± spread of the uniform draw, as a fraction.
    pub spread: f64,
    /// Lower and upper percentiles, percent.
    pub percentiles: [f64; 2],
    /// Simulator of the draws.
    pub backend: Backend,
    /// The nominal prediction (θ̂).
    pub nominal: Vec<f64>,
    /// Pointwise lower percentile.
    pub lower: Vec<f64>,
    /// Pointwise median.
    pub median: Vec<f64>,
    /// Pointwise upper percentile.
    pub upper: Vec<f64>,
    /// Share of (scored) validation measurements inside the band.
    pub coverage: f64,
    /// Share of the noise-free true response inside the band (synthetic only).
    pub truth_coverage: Option<f64>,
}

/// Runs every computing stage of the experiment in `config_path`.
pub fn run_stages(
    config: Config,
    config_path: &Path,
    options: &RunOptions,
    progress: &Progress,
) -> Result<Outcome> {
    let seed = options.seed.unwrap_or(config.seed);
    progress.stage("data");
    let t = Instant::now();
    let data = data::load(&config, config_path, seed)?;
    let loaded = t.elapsed();
    let mut outcome = run_on_data(config, config_path, data, options, progress)?;
    outcome.timings.insert(0, ("data", loaded));
    Ok(outcome)
}

/// Runs the stages after the data (estimation, validation, residuals, frequency check,
/// Monte Carlo, nonlinear models) on records already loaded; `config_path` names the
/// config in errors and the report (empty for a config built in Rust).
pub fn run_on_data(
    config: Config,
    config_path: &Path,
    data: ExperimentData,
    options: &RunOptions,
    progress: &Progress,
) -> Result<Outcome> {
    let seed = options.seed.unwrap_or(config.seed);
    let threads = options.threads.unwrap_or(config.monte_carlo.threads);
    if threads == 0 {
        return Err(ExperimentError::config(
            config_path,
            "--threads 0: expected an integer >= 1",
        ));
    }
    let mut timings = Vec::new();
    let mut timed = |name: &'static str, started: Instant| timings.push((name, started.elapsed()));

    progress.stage("estimation");
    let t = Instant::now();
    let (estimate, estimation_solver) = estimation_stage(&config, &data, threads)?;
    timed("estimation", t);

    progress.stage("validation");
    let t = Instant::now();
    let validation = validate(&config, &data, &estimate)?;
    timed("validation", t);

    progress.stage("residuals");
    let t = Instant::now();
    let residuals = Some(
        residual_analysis(
            &estimate.residuals,
            data.identification.excitation.samples(),
            &residual_options(&config),
        )
        .map_err(|e| ExperimentError::run("residual analysis", e))?,
    );
    timed("residuals", t);

    let frequency = if config.frequency_check.enabled {
        progress.stage("frequency check");
        let t = Instant::now();
        let stage = frequency_stage(&config, &data, &estimate)?;
        timed("frequency_check", t);
        stage
    } else {
        FrequencyStage::Off
    };

    let monte_carlo = if config.monte_carlo.enabled {
        progress.stage("Monte Carlo");
        let t = Instant::now();
        let mc = monte_carlo(
            &config,
            &data,
            &estimate,
            &validation,
            threads,
            seed,
            progress,
        )?;
        timed("monte_carlo", t);
        Some(mc)
    } else {
        None
    };

    let nonlinear = match &config.nonlinear {
        Some(section) => {
            progress.stage("nonlinear models");
            let t = Instant::now();
            let n = crate::paper::nonlinear::run(
                section,
                &config,
                &data,
                &estimate,
                validation.fit.residual_rms,
                seed,
                threads,
            )?;
            timed("nonlinear", t);
            Some(n)
        }
        None => None,
    };

    let significance = estimate.fit.f_test(estimate.uncertainty.names.len());
    Ok(Outcome {
        significance,
        config,
        config_path: config_path.to_path_buf(),
        command: options.command.clone().unwrap_or_else(|| "msd run".into()),
        seed,
        threads,
        data,
        estimate,
        validation,
        estimation_solver,
        residuals,
        frequency,
        monte_carlo,
        nonlinear,
        timings,
    })
}

/// The estimation stage: the fit (its multistart on the run's threads) and the ode45
/// statistics of its model.
fn estimation_stage(
    config: &Config,
    data: &ExperimentData,
    threads: usize,
) -> Result<(Estimate, Option<msd_ident::Ode45Stats>)> {
    let mut est_options = config.estimation.clone();
    if let Some(ms) = &mut est_options.multistart
        && config.estimation.multistart.is_some()
    {
        ms.threads = threads;
    }
    let estimate =
        estimate(&data.identification, &est_options).map_err(|e| {
            match acceleration_hint(config) {
                Some(hint) => {
                    ExperimentError::config("data.output", format!("{hint}; the fit said: {e}"))
                }
                None => estimation_error(e),
            }
        })?;
    let estimation_solver = ode45_stats(
        &estimate.parameters,
        &data.identification.excitation,
        estimate.initial_state,
        &estimate.backend,
    );
    Ok((estimate, estimation_solver))
}

/// The frequency check on the record the config names.
fn frequency_stage(
    config: &Config,
    data: &ExperimentData,
    estimate: &Estimate,
) -> Result<FrequencyStage> {
    let set = match config.frequency_check.data {
        RecordChoice::Identification => &data.identification,
        RecordChoice::Validation => &data.validation,
    };
    let check = frequency_check(
        set,
        &estimate.parameters,
        Some(&estimate.uncertainty),
        &config.frequency_check.options(),
    );
    match check {
        Ok(check) => Ok(FrequencyStage::Checked(Box::new(check))),
        // Nothing to measure (no resonance in the excited band — a damper past
        // critical damping, a mode the input misses — or no input power): the other
        // stages still stand, so the run goes on and says why.
        Err(IdentError::NotIdentifiable { reason }) => Ok(FrequencyStage::Skipped(reason)),
        // A record too short to resolve the mode (a few seconds of validation data):
        // the check cannot be made on it; the estimate stands.
        Err(e @ IdentError::TooFewSamples { .. }) => {
            let (record, other) = match config.frequency_check.data {
                RecordChoice::Identification => ("identification", "validation"),
                RecordChoice::Validation => ("validation", "identification"),
            };
            Ok(FrequencyStage::Skipped(format!(
                "the {record} record ({:.4} s) is too short to resolve the mode: {e}; check on a longer record (frequency_check.data = \"{other}\")",
                set.excitation.dt() * set.len() as f64
            )))
        }
        Err(e) => Err(ExperimentError::run("frequency check", e)),
    }
}

/// What to use instead when a failed fit's output column looks like an acceleration (its
/// name holds "acc", or its unit is g or m/s²): this kind fits a displacement x(t).
fn acceleration_hint(config: &Config) -> Option<String> {
    let data = config.data.as_ref()?;
    let column = data.output.as_ref()?.to_string();
    let name = column.to_lowercase();
    let unit = data.output_unit.trim().to_lowercase();
    let acceleration =
        name.contains("acc") || ["g", "m/s²", "m/s^2", "m/s2", "m s-2"].contains(&unit.as_str());
    acceleration.then(|| {
        format!(
            "{column} looks like an acceleration, and a config with [data] and no [setup] fits a displacement x(t) to it: for an accelerometer start from configs/templates/accelerometer.toml (a [setup] with an acceleration channel; a unit of g is scaled by 9.80665)"
        )
    })
}

/// A failed estimation as a failure of the stage "estimation", its reason said once
/// ("estimation failed: …", not "estimation failed: estimation failed: …").
fn estimation_error(e: IdentError) -> ExperimentError {
    match e {
        IdentError::EstimationFailed { reason } => ExperimentError::run("estimation", reason),
        other => ExperimentError::run("estimation", other),
    }
}

fn validate(config: &Config, data: &ExperimentData, est: &Estimate) -> Result<ValidationOutcome> {
    let backend = config.validation_backend();
    let set = &data.validation;
    let n0 = data.validation_initial_samples;
    let initial_state = if n0 > 0 {
        // The benchmark's rule: the first n0 outputs set the initial state.
        let model = FixedModel::Linear {
            parameters: &est.parameters,
            backend: Backend::EXACT,
            offset: est.offset,
        };
        fit_initial_state(model, set, n0).map_err(|e| {
            ExperimentError::run(
                "validation",
                format!("settling the initial state on the first {n0} samples: {e}"),
            )
        })?
    } else {
        config.estimation.initial_state
    };
    let options = ValidationOptions {
        initial_state,
        offset: est.offset,
        backend,
        residuals: residual_options(config),
    };
    let v = validate_model(&est.parameters, set, &options)
        .map_err(|e| ExperimentError::run("validation", e))?;
    let (fit, analysis) = if n0 == 0 {
        (v.fit, v.residual_analysis)
    } else {
        // Score only the samples after those that settled the initial state.
        let fit = FitMetrics::new(&set.output[n0..], &v.model_output[n0..]);
        let analysis = residual_analysis(
            &v.residuals[n0..],
            &set.excitation.samples()[n0..],
            &options.residuals,
        )
        .map_err(|e| ExperimentError::run("validation", e))?;
        (fit, analysis)
    };
    let solver = ode45_stats(&est.parameters, &set.excitation, initial_state, &backend);
    let truth_fit = data
        .validation_truth
        .as_ref()
        .map(|truth| FitMetrics::new(&set.output, truth));
    Ok(ValidationOutcome {
        backend,
        initial_state,
        model_output: v.model_output,
        residuals: v.residuals,
        scored_from: n0,
        fit,
        residual_analysis: Some(analysis),
        truth_fit,
        solver,
    })
}

/// The ode45 solver's statistics for one simulation (`None` for the exact backend).
fn ode45_stats(
    parameters: &Parameters,
    excitation: &msd_ident::Excitation,
    initial: InitialState,
    backend: &Backend,
) -> Option<msd_ident::Ode45Stats> {
    let mut out = vec![0.0; excitation.len()];
    simulate_into(parameters, excitation, initial, backend, &mut out)
        .ok()
        .flatten()
}

fn residual_options(config: &Config) -> ResidualOptions {
    ResidualOptions {
        max_lag: config.residuals.max_lag,
        confidence: config.residuals.confidence,
    }
}

fn monte_carlo(
    config: &Config,
    data: &ExperimentData,
    estimate: &Estimate,
    validation: &ValidationOutcome,
    threads: usize,
    seed: u64,
    progress: &Progress,
) -> Result<MonteCarloOutcome> {
    let mc = &config.monte_carlo;
    let options = McOptions {
        threads,
        seed,
        backend: config.monte_carlo_backend(),
        initial_state: validation.initial_state,
        ..mc.options()
    };
    let set = &data.validation;
    let offset = estimate.offset;
    // The band is of the model without the sensor offset: compare the measurements
    // less the offset, then shift the curves back.
    let measured: Vec<f64> = set.output.iter().map(|y| y - offset).collect();
    progress.bar("Monte Carlo", mc.samples as u64);
    let report = |done: usize, total: usize| {
        progress.set_position((done * mc.samples / total.max(1)) as u64);
    };
    let band = monte_carlo_band_with_progress(
        &estimate.parameters,
        &set.excitation,
        Some(&measured),
        &options,
        &report,
    )
    .map_err(|e| ExperimentError::run("Monte Carlo", e))?;
    let shift = |v: &[f64]| -> Vec<f64> { v.iter().map(|x| x + offset).collect() };
    let lower = shift(band.lower());
    let upper = shift(band.upper());
    let median = band.median().map(shift).unwrap_or_default();
    let nominal = shift(&band.nominal);
    let n0 = validation.scored_from;
    let inside = |y: &[f64]| {
        let scored = y.len() - n0;
        let count = (n0..y.len())
            .filter(|&i| lower[i] <= y[i] && y[i] <= upper[i])
            .count();
        count as f64 / scored.max(1) as f64
    };
    let coverage = match band.coverage {
        Some(c) if n0 == 0 => c,
        _ => inside(&set.output),
    };
    let truth_coverage = data.validation_truth.as_deref().map(inside);
    Ok(MonteCarloOutcome {
        samples: band.samples,
        failed_samples: band.failed_samples,
        threads: band.threads,
        spread: mc.spread,
        percentiles: mc.percentiles,
        backend: band.backend,
        nominal,
        lower,
        median,
        upper,
        coverage,
        truth_coverage,
    })
}

/// Whether the experiment is synthetic.
pub fn is_synthetic(outcome: &Outcome) -> bool {
    outcome.data.kind == Kind::Synthetic
}

impl crate::finished::Finished for Outcome {
    fn config(&self) -> &Config {
        &self.config
    }

    fn figures(&self, dir: &Path) -> Result<Vec<&'static str>> {
        figures::write_all(self, dir)
    }

    fn tables(&self) -> Vec<(String, String)> {
        tables::csv_files(self)
            .into_iter()
            .map(|(name, text)| (name.to_string(), text))
            .collect()
    }

    fn timings(&self) -> &[(&'static str, Duration)] {
        &self.timings
    }

    fn report(&self, figures: &[&str]) -> String {
        report::markdown(self, figures)
    }

    fn results(
        &self,
        extra: &[(&'static str, Duration)],
        total: Duration,
    ) -> Result<serde_json::Value> {
        Ok(results::to_json(self, extra, total))
    }

    fn summary(&self) -> String {
        summary::text(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_estimation_says_estimation_failed_once() {
        let failed = IdentError::EstimationFailed {
            reason: "the cost is not finite at any point tried".into(),
        };
        assert_eq!(
            estimation_error(failed).to_string(),
            "estimation failed: the cost is not finite at any point tried"
        );
        let other = IdentError::NotIdentifiable {
            reason: "no input".into(),
        };
        assert_eq!(
            estimation_error(other).to_string(),
            "estimation failed: parameters are not identifiable from these data: no input"
        );
    }
}
