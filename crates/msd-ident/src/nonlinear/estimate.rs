//! Estimation of a nonlinear model's parameters by output error, the Jacobian from the
//! forward sensitivities.

use super::model::{Forces, ModelStructure, NonlinearParameters};
use super::problem::{OutputError, Scaling, Statistics, at_optimum, step_doubling};
use super::simulate::{NonlinearSimulation, SimulationUsed, Simulator, simulate_nonlinear};
use crate::local::Local;
use crate::residuals::sandwich::{CovarianceUsed, ResidualCovariance};
use crate::{
    data::DataSet,
    error::{IdentError, Result},
    estimate::{EstimationOptions, estimate},
    metrics::FitMetrics,
    params::{InitialState, Parameters},
    stop::StopReason,
};
use msd_opt::statistics::Interval;
use msd_opt::{
    Bounds, LevenbergMarquardtOptions, MultistartOptions, NelderMeadOptions, levenberg_marquardt,
    multistart, nelder_mead,
};
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};
use std::time::{Duration, Instant};

/// The optimiser of [`estimate_nonlinear`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NonlinearMethod {
    /// Levenberg–Marquardt with the Jacobian from the forward sensitivities.
    #[default]
    LevenbergMarquardt,
    /// Nelder–Mead (fminsearch) on the sum of squares.
    NelderMead,
}

/// Multistart of [`estimate_nonlinear`]: local runs from a Latin hypercube around the
/// start, in the scaled parameters.
///
/// By default 8 starts, ±0.5 decades for m, c, k, ±1 scale unit for the nonlinear
/// coefficients, seed 0, 2 threads.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NonlinearMultistart {
    /// Number of starts (the first is the nominal start). By default 8.
    pub starts: usize,
    /// Half-width of the box for m, c, k in decades. By default 0.5.
    pub decades: f64,
    /// Half-width of the box for the nonlinear coefficients in scale units (see the
    /// module doc). By default 1.
    pub nonlinear_width: f64,
    /// Seed of the design. By default 0.
    pub seed: u64,
    /// Threads. By default 2.
    pub threads: usize,
}

impl Default for NonlinearMultistart {
    fn default() -> Self {
        Self {
            starts: 8,
            decades: 0.5,
            nonlinear_width: 1.0,
            seed: 0,
            threads: 2,
        }
    }
}

/// Options of [`estimate_nonlinear`].
///
/// | field | default |
/// |---|---|
/// | `method` | Levenberg–Marquardt |
/// | `simulation` | [`NonlinearSimulation::default`] (RK4 on the cubic hold for measured data, ode45 1e-8/1e-12 for a known signal; v_s = 1e-3 × RMS velocity) |
/// | `linear_start` | `None`: the fast linear estimate (LM, exact simulation, ARX guess) |
/// | `initial_state` | at rest |
/// | `estimate_initial_state` | false |
/// | `levenberg_marquardt` | MINPACK defaults, the Jacobian from the sensitivities, at most 20·(p + 1) evaluations when `max_evaluations` is `None` |
/// | `nelder_mead` | fminsearch defaults with relative tolerances 1e-8 |
/// | `multistart` | `None` |
/// | `dissipative_damping` | true: F_c ≥ 0, c₂ ≥ 0 |
/// | `covariance` | `auto`: the block sandwich where the residuals are coloured ([`ResidualCovariance`]) |
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NonlinearOptions {
    /// The optimiser. By default Levenberg–Marquardt.
    pub method: NonlinearMethod,
    /// The simulator. By default [`NonlinearSimulation::default`].
    pub simulation: NonlinearSimulation,
    /// Linear parameters to start from (nonlinear coefficients start at 0). `None`:
    /// [`estimate()`] with its default (fast) options. By default `None`.
    pub linear_start: Option<Parameters>,
    /// The initial state (or its start value when estimated). By default at rest.
    pub initial_state: InitialState,
    /// Estimate x(t₀) and x'(t₀) with the parameters. By default false.
    pub estimate_initial_state: bool,
    /// Levenberg–Marquardt settings (its finite-difference fields are unused: the
    /// problem supplies its Jacobian).
    pub levenberg_marquardt: LevenbergMarquardtOptions,
    /// Nelder–Mead settings.
    pub nelder_mead: NelderMeadOptions,
    /// Multistart, or `None` for one local run. By default `None`.
    pub multistart: Option<NonlinearMultistart>,
    /// Keep F_c ≥ 0 and c₂ ≥ 0 (dissipative friction) by bounds in Levenberg–Marquardt
    /// and in the multistart box; Nelder–Mead runs unbounded. Without it an estimate may
    /// take a negative coefficient, whose prediction can diverge. By default true.
    pub dissipative_damping: bool,
    /// How the intervals treat the residuals: by default the block sandwich where they
    /// fail the whiteness test (a measured record's noise is seldom white, and
    /// s²·(JᵀJ)⁻¹ is then too narrow), s²·(JᵀJ)⁻¹ where they look white.
    pub covariance: ResidualCovariance,
}

impl Default for NonlinearOptions {
    fn default() -> Self {
        Self {
            method: NonlinearMethod::LevenbergMarquardt,
            simulation: NonlinearSimulation::default(),
            linear_start: None,
            initial_state: InitialState::REST,
            estimate_initial_state: false,
            levenberg_marquardt: LevenbergMarquardtOptions::default(),
            nelder_mead: NelderMeadOptions {
                x_tolerance: 1e-8,
                f_tolerance: 1e-8,
                relative_tolerances: true,
                adaptive: true,
                ..NelderMeadOptions::default()
            },
            multistart: None,
            dissipative_damping: true,
            covariance: ResidualCovariance::Auto,
        }
    }
}

/// The result of [`estimate_nonlinear`].
///
/// Serializes every field, the matrices as lists of rows and the wall time as
/// `wall_time_s` in seconds. Displays the model, each parameter with its interval, the
/// fit, the counts and why the estimator stopped.
#[derive(Debug, Clone, Serialize)]
pub struct NonlinearEstimate {
    /// θ̂.
    pub parameters: NonlinearParameters,
    /// Intervals of the parameters, in the order of their names.
    pub intervals: Vec<Interval>,
    /// The initial state used (estimated when asked).
    pub initial_state: InitialState,
    /// Intervals of x(t₀), x'(t₀) when estimated.
    pub initial_state_intervals: Option<[Interval; 2]>,
    /// Covariance of the physical parameters (and initial state, last, when
    /// estimated): σ̂²·D(JᵀJ)⁻¹D with J the Jacobian in the scaled parameters and D
    /// the derivative of the physical by the scaled parameters, or with coloured
    /// residuals D times the block sandwich times D (`covariance_used`).
    #[serde(serialize_with = "crate::ser::matrix_rows")]
    pub covariance: DMatrix<f64>,
    /// Which covariance the intervals come from (the block sandwich where the residuals
    /// are coloured) and the residuals' whiteness.
    pub covariance_used: CovarianceUsed,
    /// With the sandwich: the parameters' intervals s²·(JᵀJ)⁻¹ would have given.
    pub white_intervals: Option<Vec<Interval>>,
    /// Correlation matrix of the estimated quantities (same order as `covariance`).
    #[serde(serialize_with = "crate::ser::matrix_rows")]
    pub correlation: DMatrix<f64>,
    /// Condition number of JᵀJ with its columns scaled to unit norm (unit-free; large
    /// values mean nearly collinear sensitivities, i.e. poorly separable terms).
    pub condition_number: f64,
    /// σ̂ = √(SSE/(N − p)).
    pub sigma: f64,
    /// N − p.
    pub degrees_of_freedom: usize,
    /// Number of estimated quantities p (parameters plus initial state).
    pub estimated: usize,
    /// Σ(y − ŷ)².
    pub sse: f64,
    /// Fit on the estimation data.
    pub fit: FitMetrics,
    /// ŷ on the estimation data.
    pub model_output: Vec<f64>,
    /// y − ŷ.
    pub residuals: Vec<f64>,
    /// The Coulomb smoothing velocity used.
    pub smoothing_velocity: f64,
    /// How the model was simulated: the solver, RK4's sub-steps per sample and, under
    /// RK4, the output's error by step doubling.
    pub simulation: SimulationUsed,
    /// The linear start.
    pub linear_start: Parameters,
    /// The optimiser.
    pub method: NonlinearMethod,
    /// Starts (1 without multistart).
    pub starts: usize,
    /// Iterations of the best run.
    pub iterations: usize,
    /// Simulations in total (all starts and the covariance included; an augmented
    /// sensitivity simulation counts as one).
    pub simulations: usize,
    /// Why the best run stopped, and whether it met its convergence test
    /// ([`StopReason::converged`]).
    pub stop: StopReason,
    /// Wall-clock time (serialized as `wall_time_s`, in seconds).
    #[serde(rename = "wall_time_s", serialize_with = "crate::ser::seconds")]
    pub wall_time: Duration,
}

impl std::fmt::Display for NonlinearEstimate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "model {}", self.parameters.structure)?;
        for (name, i) in self.parameters.names().iter().zip(&self.intervals) {
            writeln!(
                f,
                "  {name:<18} = {:>14.6e} ± {:.3e}  (95 % [{:.6e}, {:.6e}])",
                i.value, i.standard_error, i.ci95[0], i.ci95[1]
            )?;
        }
        writeln!(f, "  {}", self.covariance_used)?;
        writeln!(
            f,
            "  SSE = {:.6e}, σ̂ = {:.4e}, fit {:.2} %, {} simulations ({}), {:.2?}, {}",
            self.sse,
            self.sigma,
            self.fit.fit_percent,
            self.simulations,
            self.simulation,
            self.wall_time,
            self.stop
        )
    }
}

/// The linear start: given, or [`estimate()`] with its default (fast) options.
fn linear_start(data: &DataSet, options: &NonlinearOptions) -> Result<Parameters> {
    match options.linear_start {
        Some(p) => {
            p.validate()?;
            Ok(p)
        }
        None => {
            let linear = EstimationOptions {
                initial_state: options.initial_state,
                estimate_initial_state: options.estimate_initial_state,
                ..EstimationOptions::default()
            };
            Ok(estimate(data, &linear)?.parameters)
        }
    }
}

/// Indices of F_c or c₂ in z, bounded below by 0 when dissipative damping is asked.
fn dissipative_indices(structure: ModelStructure, options: &NonlinearOptions) -> Vec<usize> {
    if !options.dissipative_damping {
        return Vec::new();
    }
    structure
        .parameter_names()
        .iter()
        .enumerate()
        .filter(|(_, n)| matches!(**n, "coulomb_force" | "quadratic_damping"))
        .map(|(i, _)| i)
        .collect()
}

/// The Levenberg–Marquardt options of a run in p scaled parameters: at most
/// 20·(p + 1) evaluations unless given, the dissipative bounds unless bounds are given.
fn lm_options(
    options: &NonlinearOptions,
    p: usize,
    dissipative: &[usize],
) -> Result<LevenbergMarquardtOptions> {
    let mut lm = options.levenberg_marquardt.clone();
    if lm.max_evaluations.is_none() {
        lm.max_evaluations = Some(20 * (p + 1));
    }
    if !dissipative.is_empty() && lm.bounds.is_none() {
        let mut lower = vec![f64::NEG_INFINITY; p];
        for &i in dissipative {
            lower[i] = 0.0;
        }
        lm.bounds = Some(Bounds::new(lower, vec![f64::INFINITY; p])?);
    }
    Ok(lm)
}

/// Everything a local run needs, shared by the starts.
struct Search<'a> {
    scaling: &'a Scaling,
    data: &'a DataSet,
    simulator: Simulator<'a>,
    smoothing: f64,
    options: &'a NonlinearOptions,
    lm: LevenbergMarquardtOptions,
    dissipative: Vec<usize>,
}

impl Search<'_> {
    fn problem(&self) -> OutputError<'_> {
        OutputError::new(
            self.scaling,
            self.data,
            self.simulator.clone(),
            self.smoothing,
        )
    }

    /// One local run from `z`; its counts include every simulation.
    fn local(&self, z: &[f64]) -> std::result::Result<Local, msd_opt::OptError> {
        let mut problem = self.problem();
        let mut run = match self.options.method {
            NonlinearMethod::LevenbergMarquardt => {
                Local::levenberg_marquardt(levenberg_marquardt(&mut problem, z, &self.lm)?)
            }
            NonlinearMethod::NelderMead => {
                let mut buffer = vec![0.0; self.data.len()];
                let nm = &self.options.nelder_mead;
                Local::nelder_mead(nelder_mead(|z| problem.sse(z, &mut buffer), z, nm)?)
            }
        };
        // Every simulation, the sensitivity runs included, is what the estimate counts.
        run.evaluations = problem.simulations;
        run.finite_differences = 0;
        Ok(run)
    }

    /// The best of one run from `z0`, or of the multistart design around it; the number
    /// of starts and of simulations.
    fn best(&self, z0: &[f64]) -> Result<(Local, usize, usize)> {
        let Some(ms) = &self.options.multistart else {
            let r = self.local(z0)?;
            let s = r.simulations();
            return Ok((r, 1, s));
        };
        let mut lower = z0.to_vec();
        let mut upper = z0.to_vec();
        for i in 0..z0.len() {
            let w = if i < 3 {
                ms.decades * std::f64::consts::LN_10
            } else {
                ms.nonlinear_width
            };
            lower[i] -= w;
            upper[i] += w;
        }
        for &i in &self.dissipative {
            lower[i] = lower[i].max(0.0);
        }
        let bounds = Bounds::new(lower, upper)?;
        let design = MultistartOptions {
            starts: ms.starts.saturating_sub(1).max(1),
            seed: ms.seed,
            threads: ms.threads,
            ..MultistartOptions::default()
        };
        // A start that cannot even be simulated ranks last instead of failing all.
        let tolerant = |z: &[f64]| Ok(self.local(z).unwrap_or_else(|e| Local::failed(z, e)));
        let mut results = multistart(&bounds, &design, tolerant)?;
        let nominal = self.local(z0)?;
        let total = results
            .iter()
            .map(|r| r.result.simulations())
            .sum::<usize>()
            + nominal.simulations();
        let count = results.len() + 1;
        let first = results.remove(0).result;
        let best = if nominal.cost <= first.cost {
            nominal
        } else {
            first
        };
        Ok((best, count, total))
    }
}

impl Search<'_> {
    /// The optimum may need more sub-steps than the start (a stiffer spring): searched
    /// again from it with them, at most twice. Returns the final run and the
    /// simulations spent here.
    fn refine(&mut self, mut best: Local, scratch: &mut [f64]) -> Result<(Local, usize)> {
        let mut simulations = 0;
        for _ in 0..2 {
            let Some((forces, initial)) = self.problem().point(&best.x) else {
                break;
            };
            let rk4 = &mut self.simulator.rk4;
            let needed = rk4.steps_for(rk4.simulate(&forces, initial, scratch))?;
            simulations += 1;
            if needed <= rk4.steps() {
                break;
            }
            rk4.set_steps(needed);
            let again = self.local(&best.x)?;
            simulations += again.simulations();
            best = again;
        }
        Ok((best, simulations))
    }
}

/// Estimates the parameters of `structure` on `data` by output error.
///
/// ## The algorithm
/// 1. Linear start: `options.linear_start` or [`estimate()`] with its default options
///    (Levenberg–Marquardt on the exact simulator from the ARX guess); nonlinear
///    coefficients start at 0. The Coulomb smoothing velocity is fixed from that start.
/// 2. Scaled parameters z: ln m, ln c, ln k, and the nonlinear coefficients divided by
///    a scale making them O(1) when their force is comparable to the linear one (see the
///    module doc); the initial state (when estimated) divided by the output's RMS and
///    RMS·ωₙ.
/// 3. RK4's sub-steps per sample from the start's trajectory, held fixed during the
///    search so that the simulated output is a smooth function of z.
/// 4. Levenberg–Marquardt (Jacobian from the forward sensitivities) or Nelder–Mead on
///    Σ(ŷ − y)², each evaluation one simulation; optionally from several starts. If the
///    optimum's trajectory needs more sub-steps than the start's, the search is redone
///    from the optimum with them.
/// 5. Covariance σ̂²·D(JᵀJ)⁻¹D from the sensitivities at ẑ, with σ̂² = SSE/(N − p) and
///    Student-t 95 % intervals; under RK4 the output's error by step doubling.
///
/// ```
/// use msd_ident::{Excitation, nonlinear::{estimate_nonlinear, ModelStructure, NonlinearOptions, NonlinearParameters, NonlinearSimulation, synthetic_nonlinear_data}, Parameters, SyntheticOptions};
/// use msd_signal::paper_identification_input;
/// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.004, 2001)?;
/// let plant = NonlinearParameters::from_linear(ModelStructure::LINEAR, &Parameters::PAPER);
/// let (data, _) = synthetic_nonlinear_data(&plant, input, &NonlinearSimulation::default(),
///     &SyntheticOptions::named("id"))?;
/// let e = estimate_nonlinear(&data, ModelStructure::LINEAR, &NonlinearOptions::default())?;
/// assert!(e.intervals[2].value > 100.0 && e.intervals[2].value < 140.0);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn estimate_nonlinear(
    data: &DataSet,
    structure: ModelStructure,
    options: &NonlinearOptions,
) -> Result<NonlinearEstimate> {
    let started = Instant::now();
    options.simulation.validate()?;
    let linear_start = linear_start(data, options)?;
    let start = NonlinearParameters::from_linear(structure, &linear_start);
    let smoothing = options.simulation.resolve_smoothing_velocity(
        &start,
        &data.excitation,
        options.initial_state,
    )?;
    let scaling = Scaling::new(structure, &linear_start, data, options);
    let p = scaling.len();
    let n = data.len();
    if n <= p + 1 {
        return Err(IdentError::TooFewSamples {
            got: n,
            needed: p + 2,
            why: "output-error estimation needs more samples than estimated quantities",
        });
    }
    let z0 = scaling.to_z(&start, options.initial_state);
    let dissipative = dissipative_indices(structure, options);
    let mut simulator = Simulator::new(&data.excitation, &options.simulation)?;
    let mut scratch = vec![0.0; n];
    let forces = Forces::new(&start, smoothing);
    simulator.fit_steps(&forces, options.initial_state, &mut scratch)?;
    let mut search = Search {
        lm: lm_options(options, p, &dissipative)?,
        scaling: &scaling,
        data,
        simulator,
        smoothing,
        options,
        dissipative,
    };
    let (best, starts, simulations) = search.best(&z0)?;
    let (best, more) = search.refine(best, &mut scratch)?;
    let mut simulations = simulations + more;
    let stop = best
        .finished()
        .map_err(|why| IdentError::EstimationFailed {
            reason: format!("{structure}: no start reached a finite cost ({why})"),
        })?;
    let mut problem = search.problem();
    let at = at_optimum(&mut problem, &best.x)?;
    simulations += problem.simulations;
    let (parameters, initial_state) = scaling.physical(&best.x);
    let error_estimate = step_doubling(&problem, &parameters, initial_state, &at.output)?;
    let used = SimulationUsed {
        solver: problem.simulator.solver,
        hold: problem.simulator.hold(),
        steps_per_sample: problem.simulator.rk4.steps(),
        error_estimate,
    };
    let statistics = Statistics::new(&at, &scaling, &best.x, structure, options.covariance)?;
    let (intervals, initial_state_intervals) =
        statistics.intervals(&parameters, initial_state, options.estimate_initial_state);
    let residuals: Vec<f64> = at.residuals.iter().map(|r| -r).collect();
    let white_intervals = statistics.white_intervals(&parameters);
    Ok(NonlinearEstimate {
        fit: FitMetrics::new(&data.output, &at.output),
        parameters,
        intervals,
        initial_state,
        initial_state_intervals,
        covariance_used: statistics.used,
        white_intervals,
        covariance: statistics.covariance,
        correlation: statistics.correlation,
        condition_number: statistics.condition_number,
        sigma: statistics.sigma2.sqrt(),
        degrees_of_freedom: statistics.dof,
        estimated: p,
        sse: statistics.sse,
        model_output: at.output,
        residuals,
        smoothing_velocity: smoothing,
        simulation: used,
        linear_start,
        method: options.method,
        starts,
        iterations: best.iterations,
        simulations,
        stop,
        wall_time: started.elapsed(),
    })
}

/// Noisy synthetic data from a nonlinear plant: its ode45 response to `excitation` from
/// `options.initial_state` plus the noise of `options` (see
/// [`SyntheticOptions`](crate::synthetic::SyntheticOptions)). The Coulomb smoothing velocity is
/// resolved from `simulation` on this excitation.
///
/// Returns the noisy data set and the noise-free response, as
/// [`synthetic_data`](crate::synthetic::synthetic_data).
///
/// ```
/// use msd_ident::{Excitation, nonlinear::{ModelStructure, NonlinearParameters, NonlinearSimulation, synthetic_nonlinear_data}, Parameters, SyntheticOptions};
/// use msd_signal::paper_identification_input;
/// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.004, 501)?;
/// let plant = NonlinearParameters::from_linear(ModelStructure::LINEAR, &Parameters::PAPER);
/// let options = SyntheticOptions { sigma: 0.0, ..SyntheticOptions::named("id") };
/// let (data, truth) = synthetic_nonlinear_data(&plant, input, &NonlinearSimulation::default(), &options)?;
/// assert_eq!((data.name.as_str(), data.len()), ("id", 501));
/// assert_eq!(data.output, truth); // σ = 0
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn synthetic_nonlinear_data(
    plant: &NonlinearParameters,
    excitation: crate::data::Excitation,
    simulation: &NonlinearSimulation,
    options: &crate::synthetic::SyntheticOptions,
) -> Result<(DataSet, Vec<f64>)> {
    options.validate()?;
    let initial = options.initial_state;
    let smoothing = simulation.resolve_smoothing_velocity(plant, &excitation, initial)?;
    let (truth, _) = simulate_nonlinear(plant, &excitation, initial, simulation, smoothing)?;
    Ok((options.data_set(excitation, truth.clone())?, truth))
}
