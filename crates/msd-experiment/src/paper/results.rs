//! The paper workflow's `results.json`: every number of a run, the config as read, the
//! seed, the crate version and the solver statistics.
//!
//! The file is deterministic: the same config and seed give the same bytes, whatever
//! the thread count, apart from `timings_ms` (wall times) and the recorded thread
//! counts (`experiment.threads`, `monte_carlo.threads`). Keys are sorted.

use super::Outcome;
use crate::config::{Config, Kind};
use crate::results::{Header, ms};
use msd_ident::Ode45Stats as Stats;
use msd_ident::{
    Backend, FitMetrics, InitialState, Interval, Parameters, ResidualAnalysis,
    frequency::FrequencyCheck,
};
use serde::Serialize;
use serde_json::Value;
use std::collections::BTreeMap;
use std::time::Duration;

/// The whole document: the library's result types where they are the answer
/// (intervals, fits, states, residual tests, the frequency check), named sections
/// around them. Optional sections are absent, not null, when a stage did not run.
#[derive(Serialize)]
struct Results<'a> {
    experiment: Header<'a>,
    config: &'a Config,
    data: DataSection<'a>,
    #[serde(skip_serializing_if = "Option::is_none")]
    truth: Option<Truth>,
    estimate: EstimateSection<'a>,
    identification: FitSection<'a>,
    validation: ValidationSection<'a>,
    #[serde(skip_serializing_if = "Option::is_none")]
    residuals: Option<&'a ResidualAnalysis>,
    #[serde(skip_serializing_if = "Option::is_none")]
    frequency_check: Option<FrequencySection<'a>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    monte_carlo: Option<MonteCarloSection>,
    #[serde(skip_serializing_if = "Option::is_none")]
    nonlinear: Option<NonlinearSection<'a>>,
    timings_ms: BTreeMap<String, f64>,
}

/// The true plant and how far the estimate is from it, in its own standard errors.
#[derive(Serialize)]
struct Truth {
    #[serde(flatten)]
    parameters: Parameters,
    natural_frequency_hz: f64,
    damping_ratio: f64,
    error_in_standard_errors: BTreeMap<&'static str, f64>,
}

#[derive(Serialize)]
struct EstimateSection<'a> {
    mass: Interval,
    damping: Interval,
    stiffness: Interval,
    natural_frequency_hz: Interval,
    damping_ratio: Interval,
    method: &'static str,
    backend: &'static str,
    backend_settings: Backend,
    initial_guess: Guess,
    initial_state: InitialState,
    offset: f64,
    iterations: usize,
    evaluations: usize,
    jacobian_evaluations: usize,
    starts: usize,
    /// The optimiser's own words; `converged` also asks for a minimum (see StopReason).
    exit: String,
    converged: bool,
    cost: f64,
    noise_sigma: f64,
    degrees_of_freedom: usize,
    condition_number: f64,
    correlation: Correlation<'a>,
    warnings: &'a [String],
    ode45_at_estimate: Option<Stats>,
}

#[derive(Serialize)]
struct Guess {
    #[serde(flatten)]
    parameters: Parameters,
    source: String,
}

#[derive(Serialize)]
struct Correlation<'a> {
    names: &'a [&'static str],
    matrix: Vec<Vec<f64>>,
}

/// A fit's scores and, for synthetic data, the R² of the noise-free response.
#[derive(Serialize)]
struct FitSection<'a> {
    #[serde(flatten)]
    fit: &'a FitMetrics,
    r2_of_true_response: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    f_test: Option<&'a msd_ident::FTest>,
}

#[derive(Serialize)]
struct ValidationSection<'a> {
    #[serde(flatten)]
    fit: FitSection<'a>,
    scored_from_sample: usize,
    backend: &'static str,
    initial_state: InitialState,
    residuals: Option<&'a ResidualAnalysis>,
    ode45: Option<Stats>,
}

/// The check's scalars (the curves go to frf.csv), or why it was skipped: one shape.
#[derive(Serialize)]
#[serde(untagged)]
enum FrequencySection<'a> {
    Measured {
        #[serde(flatten)]
        check: Value,
        skipped: bool,
        points: usize,
    },
    Skipped {
        skipped: bool,
        reason: &'a str,
    },
}

#[derive(Serialize)]
struct MonteCarloSection {
    samples: usize,
    failed_samples: usize,
    threads: usize,
    spread: f64,
    percentiles: [f64; 2],
    backend: &'static str,
    coverage: f64,
    coverage_of_true_response: Option<f64>,
    mean_band_width: f64,
    max_band_width: f64,
}

/// The JSON document of `outcome`; `extra_timings` are the writing stages (figures,
/// report) and `total` the run's wall time.
pub fn to_json(
    outcome: &Outcome,
    extra_timings: &[(&'static str, Duration)],
    total: Duration,
) -> Value {
    let o = outcome;
    let mut timings: BTreeMap<String, f64> = o
        .timings
        .iter()
        .chain(extra_timings)
        .map(|(name, d)| ((*name).to_string(), ms(*d)))
        .collect();
    timings.insert("total".into(), ms(total));
    let document = Results {
        experiment: experiment(o),
        config: &o.config,
        data: data(o),
        truth: o.data.truth.map(|t| truth(&t, &o.estimate.uncertainty)),
        estimate: estimate(o),
        identification: FitSection {
            f_test: Some(&o.significance),
            fit: &o.estimate.fit,
            r2_of_true_response: true_r2(
                &o.data.identification_truth,
                &o.data.identification.output,
            ),
        },
        validation: validation(o),
        residuals: o.residuals.as_ref(),
        frequency_check: frequency(o),
        monte_carlo: o.monte_carlo.as_ref().map(monte_carlo),
        nonlinear: o.nonlinear.as_ref().map(nonlinear),
        timings_ms: timings,
    };
    serde_json::to_value(document).unwrap_or(Value::Null)
}

fn experiment(o: &Outcome) -> Header<'_> {
    let kind = match o.data.kind {
        Kind::Synthetic => "synthetic",
        Kind::Measured => "measured",
    };
    Header::new(&o.config, &o.config_path, kind, o.seed, Some(o.threads))
}

fn truth(plant: &Parameters, u: &msd_ident::Uncertainty) -> Truth {
    let z = |est: &Interval, true_value: f64| {
        if est.standard_error > 0.0 {
            (est.value - true_value) / est.standard_error
        } else {
            0.0
        }
    };
    Truth {
        parameters: *plant,
        natural_frequency_hz: plant.natural_frequency_hz(),
        damping_ratio: plant.damping_ratio(),
        error_in_standard_errors: BTreeMap::from([
            ("mass", z(&u.mass, plant.mass)),
            ("damping", z(&u.damping, plant.damping)),
            ("stiffness", z(&u.stiffness, plant.stiffness)),
        ]),
    }
}

fn estimate(o: &Outcome) -> EstimateSection<'_> {
    let e = &o.estimate;
    let u = &e.uncertainty;
    let c = &u.correlation;
    EstimateSection {
        mass: u.mass,
        damping: u.damping,
        stiffness: u.stiffness,
        natural_frequency_hz: u.natural_frequency_hz,
        damping_ratio: u.damping_ratio,
        method: e.method.name(),
        backend: e.backend.name(),
        backend_settings: e.backend,
        initial_guess: Guess {
            parameters: e.initial_guess.0,
            source: e.initial_guess.1.to_string(),
        },
        initial_state: e.initial_state,
        offset: e.offset,
        iterations: e.iterations,
        evaluations: e.evaluations,
        jacobian_evaluations: e.jacobian_evaluations,
        starts: e.starts,
        exit: e.stop.optimiser_reason().to_string(),
        converged: e.stop.converged(),
        cost: e.cost,
        noise_sigma: u.sigma,
        degrees_of_freedom: u.degrees_of_freedom,
        condition_number: u.condition_number,
        correlation: Correlation {
            names: &u.names,
            matrix: (0..c.nrows())
                .map(|r| (0..c.ncols()).map(|k| c[(r, k)]).collect())
                .collect(),
        },
        warnings: &u.warnings,
        ode45_at_estimate: o.estimation_solver,
    }
}

fn true_r2(truth: &Option<Vec<f64>>, measured: &[f64]) -> Option<f64> {
    truth
        .as_ref()
        .map(|t| FitMetrics::new(measured, t).r_squared)
}

fn validation(o: &Outcome) -> ValidationSection<'_> {
    let v = &o.validation;
    ValidationSection {
        fit: FitSection {
            f_test: None,
            fit: &v.fit,
            r2_of_true_response: v.truth_fit.map(|f| f.r_squared),
        },
        scored_from_sample: v.scored_from,
        backend: v.backend.name(),
        initial_state: v.initial_state,
        residuals: v.residual_analysis.as_ref(),
        ode45: v.solver,
    }
}

fn frequency(o: &Outcome) -> Option<FrequencySection<'_>> {
    if let Some(reason) = o.frequency.skipped() {
        return Some(FrequencySection::Skipped {
            skipped: true,
            reason,
        });
    }
    o.frequency.check().map(|f: &FrequencyCheck| {
        let mut check = serde_json::to_value(f).unwrap_or(Value::Null);
        if let Value::Object(map) = &mut check {
            // The curves go to frf.csv; keep the scalars here.
            map.retain(|_, value| {
                !value.is_array() || value.as_array().is_some_and(|a| a.len() <= 2)
            });
        }
        FrequencySection::Measured {
            check,
            skipped: false,
            points: f.frequency_hz.len(),
        }
    })
}

fn monte_carlo(mc: &crate::paper::MonteCarloOutcome) -> MonteCarloSection {
    let widths = || mc.upper.iter().zip(&mc.lower).map(|(h, l)| h - l);
    MonteCarloSection {
        samples: mc.samples,
        failed_samples: mc.failed_samples,
        threads: mc.threads,
        spread: mc.spread,
        percentiles: mc.percentiles,
        backend: mc.backend.name(),
        coverage: mc.coverage,
        coverage_of_true_response: mc.truth_coverage,
        mean_band_width: widths().sum::<f64>() / mc.upper.len().max(1) as f64,
        max_band_width: widths().fold(0.0f64, f64::max),
    }
}

/// The `data` object: where the records came from, their shape and the notes on them.
#[derive(Serialize)]
struct DataSection<'a> {
    source: SourceSection,
    identification: SetSection<'a>,
    validation: SetSection<'a>,
    notes: &'a [String],
}

#[derive(Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
enum SourceSection {
    InMemory,
    Synthetic {
        noise_sigma: f64,
        noise_streams: [&'static str; 2],
    },
    Measured {
        file: Option<String>,
        rows: usize,
        dt: f64,
        estimation_range: [usize; 2],
        validation_range: [usize; 2],
    },
}

#[derive(Serialize)]
struct SetSection<'a> {
    samples: usize,
    t0: f64,
    dt: f64,
    input_unit: &'a str,
    output_unit: &'a str,
}

impl<'a> SetSection<'a> {
    fn new(d: &'a msd_ident::DataSet) -> Self {
        SetSection {
            samples: d.len(),
            t0: d.excitation.t0(),
            dt: d.excitation.dt(),
            input_unit: &d.input_unit,
            output_unit: &d.output_unit,
        }
    }
}

fn data(o: &Outcome) -> DataSection<'_> {
    use crate::data::Source;
    let source = match &o.data.source {
        Source::InMemory => SourceSection::InMemory,
        Source::Synthetic { sigma } => SourceSection::Synthetic {
            noise_sigma: *sigma,
            noise_streams: ["identification", "validation"],
        },
        Source::Measured {
            path,
            rows,
            dt,
            estimation_range,
            validation_range,
        } => SourceSection::Measured {
            file: path.file_name().map(|f| f.to_string_lossy().into_owned()),
            rows: *rows,
            dt: *dt,
            estimation_range: *estimation_range,
            validation_range: *validation_range,
        },
    };
    DataSection {
        source,
        identification: SetSection::new(&o.data.identification),
        validation: SetSection::new(&o.data.validation),
        notes: &o.data.notes,
    }
}

/// The `nonlinear` object: the candidates ranked by BIC (rank 1 first), each with its
/// parameters (value, standard error, 95 % interval), SSE, AIC, BIC, validation scores,
/// residual tests and how it was simulated (solver, hold, sub-steps a sample, the RK4
/// output's error by step doubling); the verdict, failures and, for synthetic data, the
/// true plant.
#[derive(Serialize)]
struct NonlinearSection<'a> {
    mode: &'static str,
    rows: Vec<CandidateSection<'a>>,
    best: Option<String>,
    verdict: &'a str,
    failures: Vec<FailureSection<'a>>,
    linear_stage_validation_rms: f64,
    plant: Option<PlantSection>,
}

#[derive(Serialize)]
struct CandidateSection<'a> {
    rank: usize,
    model: String,
    damping: msd_ident::law::DampingLaw,
    stiffness: msd_ident::nonlinear::StiffnessLaw,
    parameters: BTreeMap<&'a str, Interval>,
    /// Which covariance the intervals come from (the block sandwich where the
    /// identification residuals are coloured).
    covariance: msd_ident::residuals::sandwich::CovarianceUsed,
    /// With the sandwich: the intervals white residuals would have given.
    #[serde(skip_serializing_if = "Option::is_none")]
    white_noise_parameters: Option<BTreeMap<&'a str, Interval>>,
    estimated: usize,
    samples: usize,
    sse: f64,
    aic: f64,
    bic: f64,
    delta_bic: f64,
    validation: CandidateValidation,
    converged: bool,
    simulations: usize,
    simulation: &'a msd_ident::nonlinear::SimulationUsed,
}

#[derive(Serialize)]
struct CandidateValidation {
    residual_rms: f64,
    fit_percent: f64,
    r2: f64,
    scored_from_sample: usize,
    whiteness_p_value: f64,
    whiteness_passed: bool,
    cross_correlation_passed: bool,
}

#[derive(Serialize)]
struct FailureSection<'a> {
    model: String,
    reason: &'a str,
}

#[derive(Serialize)]
struct PlantSection {
    model: String,
    parameters: BTreeMap<&'static str, f64>,
}

fn candidate((i, r): (usize, &msd_ident::nonlinear::ComparisonRow)) -> CandidateSection<'_> {
    CandidateSection {
        rank: i + 1,
        model: r.structure.name(),
        damping: r.structure.damping,
        stiffness: r.structure.stiffness,
        parameters: r
            .names
            .iter()
            .map(String::as_str)
            .zip(r.intervals.iter().copied())
            .collect(),
        covariance: r.covariance_used,
        white_noise_parameters: r.white_intervals.as_ref().map(|w| {
            (r.names.iter().map(String::as_str))
                .zip(w.iter().copied())
                .collect()
        }),
        estimated: r.estimated,
        samples: r.samples,
        sse: r.sse,
        aic: r.aic,
        bic: r.bic,
        delta_bic: r.delta_bic,
        validation: CandidateValidation {
            residual_rms: r.validation_rms,
            fit_percent: r.validation.fit_percent,
            r2: r.validation.r_squared,
            scored_from_sample: r.scored_from,
            whiteness_p_value: r.whiteness_p,
            whiteness_passed: r.whiteness_passed,
            cross_correlation_passed: r.cross_correlation_passed,
        },
        converged: r.stop.converged(),
        simulations: r.simulations,
        simulation: &r.simulation,
    }
}

fn nonlinear(n: &crate::paper::nonlinear::NonlinearOutcome) -> NonlinearSection<'_> {
    let c = &n.comparison;
    NonlinearSection {
        mode: if n.comparison_asked {
            "comparison"
        } else {
            "model"
        },
        rows: c.rows.iter().enumerate().map(candidate).collect(),
        best: c.rows.first().map(|r| r.structure.name()),
        verdict: &c.verdict,
        failures: c
            .failures
            .iter()
            .map(|f| FailureSection {
                model: f.structure.name(),
                reason: &f.reason,
            })
            .collect(),
        linear_stage_validation_rms: n.linear_validation_rms,
        plant: n.plant.as_ref().map(|p| PlantSection {
            model: p.structure.name(),
            parameters: p
                .names()
                .into_iter()
                .zip(p.values.iter().copied())
                .collect(),
        }),
    }
}
