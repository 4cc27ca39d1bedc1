//! Model comparison: estimate every candidate, score it, rank by BIC and say which model
//! the evidence supports.

use super::estimate::{NonlinearEstimate, NonlinearOptions, estimate_nonlinear};
use super::model::{ModelStructure, NonlinearParameters};
use super::simulate::{NonlinearSimulation, SimulationUsed, simulate_nonlinear};
use crate::residuals::sandwich::CovarianceUsed;
use crate::{
    data::DataSet,
    error::{IdentError, Result},
    metrics::FitMetrics,
    params::{InitialState, Parameters},
    residuals::{ResidualOptions, residual_analysis},
    simulate::Backend,
    stop::StopReason,
};
use msd_opt::statistics::Interval;
use serde::{Deserialize, Serialize};

/// How each candidate's validation simulation starts.
///
/// By default from rest, every sample scored.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ValidationStart {
    /// From rest; every sample is scored.
    #[default]
    Rest,
    /// x(t₀), x'(t₀) fitted (least squares, parameters fixed) to the first `samples`
    /// outputs, which are then left out of every score: the Silverbox benchmark's rule.
    FitInitialState {
        /// Leading samples used for the initial state and not scored.
        samples: usize,
    },
}

/// Options of [`compare_models`].
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ComparisonOptions {
    /// Estimation of each candidate (the linear start is estimated once and shared
    /// when `estimation.linear_start` is `None`).
    pub estimation: NonlinearOptions,
    /// The validation start.
    pub validation_start: ValidationStart,
    /// Residual tests on the validation residuals.
    pub residuals: ResidualOptions,
}

/// One candidate's scores.
///
/// Displays the model, its size, SSE, BIC (and ΔBIC), validation RMS and whether it
/// converged, in one line.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ComparisonRow {
    /// The candidate.
    pub structure: ModelStructure,
    /// Its estimate.
    pub parameters: NonlinearParameters,
    /// Parameter names, in vector order.
    pub names: Vec<String>,
    /// Intervals of the parameters (value, standard error, 95 %).
    pub intervals: Vec<Interval>,
    /// Which covariance they come from (the block sandwich where the identification
    /// residuals are coloured).
    pub covariance_used: CovarianceUsed,
    /// With the sandwich: the intervals white residuals would have given.
    pub white_intervals: Option<Vec<Interval>>,
    /// Estimated quantities p (parameters, plus the initial state when estimated).
    pub estimated: usize,
    /// Samples N of the identification data.
    pub samples: usize,
    /// SSE on the identification data.
    pub sse: f64,
    /// AIC = N·ln(SSE/N) + 2p.
    pub aic: f64,
    /// BIC = N·ln(SSE/N) + p·ln N.
    pub bic: f64,
    /// BIC − the lowest BIC of the comparison (0 for the winner).
    pub delta_bic: f64,
    /// Fit on the validation data (scored samples only).
    pub validation: FitMetrics,
    /// RMS of the validation residuals (scored samples only).
    pub validation_rms: f64,
    /// Ljung–Box p-value of the validation residuals.
    pub whiteness_p: f64,
    /// Whether the residuals pass the whiteness test.
    pub whiteness_passed: bool,
    /// Whether the residual–input cross-correlation test passes.
    pub cross_correlation_passed: bool,
    /// Validation model output (all samples).
    pub validation_output: Vec<f64>,
    /// Validation residuals y − ŷ (all samples; the first `scored_from` are not scored).
    pub validation_residuals: Vec<f64>,
    /// Index of the first scored validation sample.
    pub scored_from: usize,
    /// Why the estimator stopped, and whether it met its convergence test
    /// ([`StopReason::converged`]).
    pub stop: StopReason,
    /// Simulations spent on the estimate.
    pub simulations: usize,
    /// How the estimate's model was simulated.
    pub simulation: SimulationUsed,
}

impl std::fmt::Display for ComparisonRow {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: p = {}, SSE = {:.4e}, BIC = {:.1} (ΔBIC = {:.1}), validation RMS = {:.4e}, {}",
            self.structure,
            self.estimated,
            self.sse,
            self.bic,
            self.delta_bic,
            self.validation_rms,
            if self.stop.converged() {
                "converged"
            } else {
                "not converged"
            }
        )
    }
}

/// The result of [`compare_models`]: rows ranked by BIC (best first) and a verdict.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    /// One row per candidate, lowest BIC first.
    pub rows: Vec<ComparisonRow>,
    /// Which model the evidence supports and how strongly, in one or two sentences.
    pub verdict: String,
    /// Candidates that could not be estimated or simulated on the validation data
    /// (e.g. an estimate with negative damping that diverges), with the reason; they are
    /// not ranked. The linear baseline never fails silently: its error is returned.
    pub failures: Vec<CandidateFailure>,
}

/// A candidate left out of the ranking, and why.
///
/// Displays as `model: not ranked: reason`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CandidateFailure {
    /// The candidate.
    pub structure: ModelStructure,
    /// The error, in words.
    pub reason: String,
}

impl std::fmt::Display for CandidateFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: not ranked: {}", self.structure, self.reason)
    }
}

impl Comparison {
    /// The winner (lowest BIC).
    pub fn best(&self) -> &ComparisonRow {
        &self.rows[0]
    }

    /// The row of `structure`, if it was a candidate.
    pub fn row(&self, structure: ModelStructure) -> Option<&ComparisonRow> {
        self.rows.iter().find(|r| r.structure == structure)
    }
}

impl std::fmt::Display for Comparison {
    /// A Markdown table of the ranking (AIC is in the rows, not the table: BIC ranks),
    /// then the verdict.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "| rank | model | p | SSE | BIC | ΔBIC | RMS on validation | fit % on validation | Ljung–Box p | white | independent of the input |"
        )?;
        writeln!(f, "|---|---|---|---|---|---|---|---|---|---|---|")?;
        for (i, r) in self.rows.iter().enumerate() {
            writeln!(
                f,
                "| {} | {} | {} | {:.4e} | {:.1} | {:.1} | {:.4e} | {:.2} | {:.3} | {} | {} |",
                i + 1,
                // Spaced, so that a narrow page can wrap the name.
                r.structure
                    .to_string()
                    .replace('+', " + ")
                    .replace('_', " "),
                r.estimated,
                r.sse,
                r.bic,
                r.delta_bic,
                r.validation_rms,
                r.validation.fit_percent,
                r.whiteness_p,
                if r.whiteness_passed { "yes" } else { "no" },
                if r.cross_correlation_passed {
                    "yes"
                } else {
                    "no"
                },
            )?;
        }
        for failure in &self.failures {
            writeln!(
                f,
                "| – | {} | not ranked: {} |",
                failure.structure, failure.reason
            )?;
        }
        writeln!(f)?;
        writeln!(f, "{}", self.verdict)
    }
}

/// Kass & Raftery's scale for a BIC difference.
pub fn bic_evidence(delta: f64) -> &'static str {
    if delta > 10.0 {
        "very strong"
    } else if delta > 6.0 {
        "strong"
    } else if delta > 2.0 {
        "positive"
    } else {
        "not worth more than a bare mention"
    }
}

/// The model whose initial state [`fit_initial_state`] fits, its parameters held fixed,
/// and how it is simulated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FixedModel<'a> {
    /// A linear model whose output carries a constant sensor `offset`, simulated by
    /// `backend`: the fit is [`estimate`](crate::estimate::estimate())'s Levenberg–Marquardt with m,
    /// c, k and the offset fixed (exact sensitivities on the exact backend).
    Linear {
        /// m, c, k.
        parameters: &'a Parameters,
        /// How the model is simulated.
        backend: Backend,
        /// The sensor offset added to the model output.
        offset: f64,
    },
    /// A nonlinear model simulated by [`simulate_nonlinear`]: Levenberg–Marquardt on the
    /// state scaled by the outputs' RMS, the Jacobian from the state's sensitivities.
    Nonlinear {
        /// The model and its parameters.
        parameters: &'a NonlinearParameters,
        /// How it is simulated.
        simulation: &'a NonlinearSimulation,
        /// The Coulomb smoothing velocity v_s.
        smoothing_velocity: f64,
    },
}

/// Fits x(t₀), x'(t₀) of `model` to the first `samples` outputs of `data` by least
/// squares, the model's parameters fixed (as the Silverbox benchmark's rule sets the
/// validation's initial state from its first outputs).
///
/// ```
/// use msd_ident::{simulate, Backend, DataSet, Excitation, InitialState, Parameters, nonlinear::{fit_initial_state, FixedModel}};
/// let input = Excitation::from_samples(0.0, 0.002, vec![0.0; 200])?;
/// let start = InitialState { displacement: 0.01, velocity: -0.2 };
/// let ringing = simulate(&Parameters::PAPER, &input, start, &Backend::EXACT)?;
/// let data = DataSet::new("free decay", input, ringing)?;
/// let model = FixedModel::Linear { parameters: &Parameters::PAPER, backend: Backend::EXACT, offset: 0.0 };
/// let fitted = fit_initial_state(model, &data, 50)?;
/// assert!((fitted.displacement - 0.01).abs() < 1e-9 && (fitted.velocity + 0.2).abs() < 1e-7);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn fit_initial_state(
    model: FixedModel<'_>,
    data: &DataSet,
    samples: usize,
) -> Result<InitialState> {
    if samples < 3 || samples > data.len() {
        return Err(IdentError::TooFewSamples {
            got: samples.min(data.len()),
            needed: 3,
            why: "fitting the initial state needs at least 3 samples within the data",
        });
    }
    let head = data.slice(0, samples)?;
    let (parameters, simulation, smoothing_velocity) = match model {
        FixedModel::Linear {
            parameters,
            backend,
            offset,
        } => {
            let options = crate::estimate::EstimationOptions {
                method: crate::estimate::Method::LevenbergMarquardt,
                backend,
                initial_guess: Some(*parameters),
                fixed: crate::estimate::FixedParameters {
                    mass: Some(parameters.mass),
                    damping: Some(parameters.damping),
                    stiffness: Some(parameters.stiffness),
                },
                estimate_initial_state: true,
                offset,
                ..crate::estimate::EstimationOptions::default()
            };
            return crate::estimate::estimate(&head, &options).map(|e| e.initial_state);
        }
        FixedModel::Nonlinear {
            parameters,
            simulation,
            smoothing_velocity,
        } => (parameters, simulation, smoothing_velocity),
    };
    super::problem::fit_state(parameters, &head, simulation, smoothing_velocity)
}

/// Prediction of an estimate on validation data, scored after the start rule.
struct Scored {
    output: Vec<f64>,
    residuals: Vec<f64>,
    from: usize,
}

fn predict(
    estimate: &NonlinearEstimate,
    validation: &DataSet,
    options: &ComparisonOptions,
) -> Result<Scored> {
    let sim = &options.estimation.simulation;
    let (initial, from) = match options.validation_start {
        ValidationStart::Rest => (InitialState::REST, 0),
        ValidationStart::FitInitialState { samples } => (
            fit_initial_state(
                FixedModel::Nonlinear {
                    parameters: &estimate.parameters,
                    simulation: sim,
                    smoothing_velocity: estimate.smoothing_velocity,
                },
                validation,
                samples,
            )?,
            samples,
        ),
    };
    let (output, _) = simulate_nonlinear(
        &estimate.parameters,
        &validation.excitation,
        initial,
        sim,
        estimate.smoothing_velocity,
    )?;
    let residuals = validation
        .output
        .iter()
        .zip(&output)
        .map(|(y, m)| y - m)
        .collect();
    Ok(Scored {
        output,
        residuals,
        from,
    })
}

/// Estimates every candidate on `identification`, predicts `validation`, and ranks the
/// candidates by BIC.
///
/// The linear model is always included as the baseline (added when missing). The
/// verdict names the winner, its BIC margin over the runner-up and over the linear
/// model on Kass & Raftery's scale (ΔBIC > 10 very strong, 6–10 strong, 2–6 positive,
/// below 2 not worth more than a bare mention), and its validation RMS and residual
/// tests against the linear model's.
///
/// ```
/// use msd_ident::{Excitation, nonlinear::{compare_models, ComparisonOptions, DampingLaw, ModelStructure, NonlinearParameters, NonlinearSimulation, StiffnessLaw, synthetic_nonlinear_data}, Parameters, SyntheticOptions};
/// use msd_signal::{paper_identification_input, paper_validation_input};
/// let plant = NonlinearParameters::from_linear(ModelStructure::LINEAR, &Parameters::PAPER);
/// let sim = NonlinearSimulation::default();
/// let id = Excitation::from_signal(paper_identification_input(), 0.0, 0.004, 2001)?;
/// let val = Excitation::from_signal(paper_validation_input(), 0.0, 0.004, 2001)?;
/// let noise = |name| SyntheticOptions { seed: 3, ..SyntheticOptions::named(name) };
/// let (id, _) = synthetic_nonlinear_data(&plant, id, &sim, &noise("id"))?;
/// let (val, _) = synthetic_nonlinear_data(&plant, val, &sim, &noise("val"))?;
/// let duffing = ModelStructure { damping: DampingLaw::Viscous, stiffness: StiffnessLaw::Cubic };
/// let c = compare_models(&id, &val, &[ModelStructure::LINEAR, duffing], &ComparisonOptions::default())?;
/// assert_eq!(c.best().structure, ModelStructure::LINEAR);
/// println!("{c}");
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn compare_models(
    identification: &DataSet,
    validation: &DataSet,
    candidates: &[ModelStructure],
    options: &ComparisonOptions,
) -> Result<Comparison> {
    options.residuals.validate()?;
    let mut structures = vec![ModelStructure::LINEAR];
    for s in candidates {
        if !structures.contains(s) {
            structures.push(*s);
        }
    }
    let mut estimation = options.estimation.clone();
    if estimation.linear_start.is_none() {
        let linear = crate::estimate::EstimationOptions {
            initial_state: estimation.initial_state,
            estimate_initial_state: estimation.estimate_initial_state,
            ..crate::estimate::EstimationOptions::default()
        };
        estimation.linear_start =
            Some(crate::estimate::estimate(identification, &linear)?.parameters);
    }
    let mut rows = Vec::with_capacity(structures.len());
    let mut failures = Vec::new();
    for structure in structures {
        match score(structure, identification, validation, &estimation, options) {
            Ok(row) => rows.push(row),
            Err(e) if !structure.is_linear() => failures.push(CandidateFailure {
                structure,
                reason: e.to_string(),
            }),
            Err(e) => return Err(e),
        }
    }
    rows.sort_by(|a, b| a.bic.total_cmp(&b.bic));
    let best_bic = rows[0].bic;
    for r in &mut rows {
        r.delta_bic = r.bic - best_bic;
    }
    let mut verdict = verdict(&rows);
    if !failures.is_empty() {
        let names: Vec<String> = failures.iter().map(|f| f.structure.name()).collect();
        verdict.push_str(&format!(
            " Not ranked (estimation or validation failed): {}.",
            names.join(", ")
        ));
    }
    Ok(Comparison {
        rows,
        verdict,
        failures,
    })
}

/// Estimates one candidate and scores it on the validation data.
fn score(
    structure: ModelStructure,
    identification: &DataSet,
    validation: &DataSet,
    estimation: &NonlinearOptions,
    options: &ComparisonOptions,
) -> Result<ComparisonRow> {
    let e = estimate_nonlinear(identification, structure, estimation)?;
    assess_estimate(&e, validation, options)
}

/// Scores one estimate as [`compare_models`] scores each candidate: SSE, AIC and BIC on
/// its identification data, then the prediction of `validation` (started as
/// `options.validation_start` says) with its fit and residual tests. `delta_bic` is 0.
///
/// For a driver that estimates a single model ([`estimate_nonlinear`]) and wants the
/// same row as a comparison would give it.
///
/// ```
/// use msd_ident::{Excitation, nonlinear::{assess_estimate, ComparisonOptions, DampingLaw, estimate_nonlinear, ModelStructure, NonlinearOptions, NonlinearParameters, NonlinearSimulation, StiffnessLaw, synthetic_nonlinear_data}, SyntheticOptions};
/// use msd_signal::{paper_identification_input, paper_validation_input};
/// let duffing = ModelStructure { damping: DampingLaw::Viscous, stiffness: StiffnessLaw::Cubic };
/// let plant = NonlinearParameters::new(duffing, vec![2.5, 1.8, 120.0, 3000.0])?;
/// let sim = NonlinearSimulation::default();
/// let id = Excitation::from_signal(paper_identification_input(), 0.0, 0.004, 2001)?;
/// let val = Excitation::from_signal(paper_validation_input(), 0.0, 0.004, 2001)?;
/// let noise = |name| SyntheticOptions { seed: 3, ..SyntheticOptions::named(name) };
/// let (id, _) = synthetic_nonlinear_data(&plant, id, &sim, &noise("id"))?;
/// let (val, _) = synthetic_nonlinear_data(&plant, val, &sim, &noise("val"))?;
/// let e = estimate_nonlinear(&id, duffing, &NonlinearOptions::default())?;
/// let row = assess_estimate(&e, &val, &ComparisonOptions::default())?;
/// assert_eq!(row.structure, duffing);
/// assert_eq!(row.samples, 2001);
/// assert!(row.validation_rms < 2.0 * 0.0025); // about the noise level
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn assess_estimate(
    estimate: &NonlinearEstimate,
    validation: &DataSet,
    options: &ComparisonOptions,
) -> Result<ComparisonRow> {
    options.residuals.validate()?;
    let e = estimate;
    let structure = e.parameters.structure;
    let n = e.residuals.len();
    let scored = predict(e, validation, options)?;
    let from = scored.from;
    let measured = &validation.output[from..];
    let fit = FitMetrics::new(measured, &scored.output[from..]);
    let tail = &scored.residuals[from..];
    let analysis = residual_analysis(
        tail,
        &validation.excitation.samples()[from..],
        &options.residuals,
    )?;
    let p = e.estimated as f64;
    let nf = n as f64;
    let log_term = nf * (e.sse / nf).ln();
    Ok(ComparisonRow {
        structure,
        names: structure
            .parameter_names()
            .iter()
            .map(|s| s.to_string())
            .collect(),
        intervals: e.intervals.clone(),
        covariance_used: e.covariance_used,
        white_intervals: e.white_intervals.clone(),
        estimated: e.estimated,
        samples: n,
        sse: e.sse,
        aic: log_term + 2.0 * p,
        bic: log_term + p * nf.ln(),
        delta_bic: 0.0,
        validation_rms: fit.residual_rms,
        validation: fit,
        whiteness_p: analysis.ljung_box.p_value,
        whiteness_passed: analysis.whiteness_passed,
        cross_correlation_passed: analysis.cross_correlation_passed,
        validation_output: scored.output,
        validation_residuals: scored.residuals,
        scored_from: from,
        stop: e.stop.clone(),
        simulations: e.simulations,
        simulation: e.simulation,
        parameters: e.parameters.clone(),
    })
}

fn verdict(rows: &[ComparisonRow]) -> String {
    let best = &rows[0];
    let mut text = String::new();
    if rows.len() == 1 {
        return format!(
            "Only {} was compared (validation RMS {:.4e}).",
            best.structure, best.validation_rms
        );
    }
    let runner = &rows[1];
    let margin = runner.delta_bic;
    text.push_str(&format!(
        "The evidence supports {} (lowest BIC); over the runner-up {} ΔBIC = {:.1}: {} evidence on Kass & Raftery's scale (>10 very strong, 6–10 strong, 2–6 positive).",
        best.structure,
        runner.structure,
        margin,
        bic_evidence(margin)
    ));
    if best.structure.is_linear() {
        text.push_str(&format!(
            " No nonlinear term earns its parameters: the linear model is kept (validation RMS {:.4e}).",
            best.validation_rms
        ));
    } else if let Some(linear) = rows.iter().find(|r| r.structure.is_linear()) {
        text.push_str(&format!(
            " Against the linear baseline ΔBIC = {:.1} ({}); validation RMS {:.4e} vs {:.4e} for the linear model ({:.1} % lower).",
            linear.delta_bic,
            bic_evidence(linear.delta_bic),
            best.validation_rms,
            linear.validation_rms,
            100.0 * (1.0 - best.validation_rms / linear.validation_rms)
        ));
    }
    text.push_str(&format!(
        " Its validation residuals {} white (Ljung–Box p = {:.3}) and {} with the input.",
        if best.whiteness_passed {
            "are"
        } else {
            "are not"
        },
        best.whiteness_p,
        if best.cross_correlation_passed {
            "uncorrelated"
        } else {
            "correlated"
        }
    ));
    text
}
