//! Estimation of m, c, k (and optionally the initial state and a sensor offset).
//!
//! Two methods (see [`Method`]): the paper's Nelder–Mead on the summed squared output
//! error, and Levenberg–Marquardt on the residual vector with the exact Jacobian from
//! the sensitivity equations. Either can run on either [`Backend`], from a
//! given θ₀ or from the automatic ARX guess, with fixed parameters, bounds and
//! multistart. Every estimate comes with fit metrics and, from the exact sensitivities at
//! θ̂, a Gauss–Newton covariance with confidence intervals.

mod identifiability;
mod layout;
mod options;
mod plan;
mod problem;

pub use options::{
    EstimationOptions, FixedParameters, Method, MultistartSettings, ParameterBounds,
};
pub use plan::{PlannedInformation, predicted_uncertainty};

use crate::local::Local;
use crate::uncertainty::{Uncertainty, from_jacobian};
use crate::{
    arx::arx_initial_guess,
    data::DataSet,
    error::{IdentError, Result},
    metrics::FitMetrics,
    params::{InitialState, Parameters},
    simulate::Backend,
    stop::StopReason,
};
use layout::Layout;
use msd_ode::Hold;
use msd_opt::{Bounds, MultistartOptions, levenberg_marquardt, multistart, nelder_mead};
use problem::{Cost, Residuals, output_jacobian};
use serde::{Deserialize, Serialize};
use std::time::{Duration, Instant};

/// Where θ₀ came from.
///
/// Displays as "given" or "automatic (ARX)"; serializes as "given" or "automatic".
///
/// ```
/// use msd_ident::estimate::GuessSource;
/// assert_eq!(GuessSource::Automatic.to_string(), "automatic (ARX)");
/// assert_eq!(serde_json::to_value(GuessSource::Given)?, "given");
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GuessSource {
    /// Given by the caller.
    Given,
    /// The automatic ARX guess.
    Automatic,
}

impl std::fmt::Display for GuessSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            GuessSource::Given => "given",
            GuessSource::Automatic => "automatic (ARX)",
        })
    }
}

/// The result of an estimation.
///
/// Serializes every field, the matrices of the uncertainty as lists of rows and the wall
/// time as `wall_time_s` in seconds. Displays the method, why it stopped, m, c, k with
/// their intervals, fn, ζ, the fit and the counts.
#[derive(Debug, Clone, Serialize)]
pub struct Estimate {
    /// θ̂.
    pub parameters: Parameters,
    /// The initial state used (estimated when asked).
    pub initial_state: InitialState,
    /// The sensor offset used (estimated when asked).
    pub offset: f64,
    /// θ₀ and where it came from.
    pub initial_guess: (Parameters, GuessSource),
    /// The optimiser.
    pub method: Method,
    /// The simulator inside the cost.
    pub backend: Backend,
    /// Final cost Σ(y − ŷ)².
    pub cost: f64,
    /// Optimiser iterations.
    pub iterations: usize,
    /// Cost (residual) evaluations, each one simulation.
    pub evaluations: usize,
    /// Jacobian evaluations (Levenberg–Marquardt), each one sensitivity simulation.
    pub jacobian_evaluations: usize,
    /// Why the optimiser stopped, and whether the estimate converged
    /// ([`StopReason::converged`]: the optimiser met its test and a Gauss–Newton step
    /// from the estimate stays within one standard error).
    pub stop: StopReason,
    /// Starting points tried (1 without multistart).
    pub starts: usize,
    /// Wall-clock time of the estimation (serialized as `wall_time_s`, in seconds).
    #[serde(rename = "wall_time_s", serialize_with = "crate::ser::seconds")]
    pub wall_time: Duration,
    /// Fit on the estimation data.
    pub fit: FitMetrics,
    /// Model output ŷ on the estimation data (offset included).
    pub model_output: Vec<f64>,
    /// Residuals y − ŷ.
    pub residuals: Vec<f64>,
    /// Covariance and intervals.
    pub uncertainty: Uncertainty,
}

impl std::fmt::Display for Estimate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let u = &self.uncertainty;
        writeln!(
            f,
            "method {} on {}: {}",
            self.method.name(),
            self.backend.name(),
            self.stop
        )?;
        for (name, i) in [("m", &u.mass), ("c", &u.damping), ("k", &u.stiffness)] {
            writeln!(f, "  {name} = {i}")?;
        }
        writeln!(
            f,
            "  fn = {:.5} Hz, ζ = {:.5}, R² = {:.5}, fit = {:.2} %",
            u.natural_frequency_hz.value,
            u.damping_ratio.value,
            self.fit.r_squared,
            self.fit.fit_percent
        )?;
        write!(
            f,
            "  {} iterations, {} evaluations, {:.1} ms",
            self.iterations,
            self.evaluations,
            self.wall_time.as_secs_f64() * 1e3
        )
    }
}

/// Estimates the parameters from `data`.
///
/// ```
/// use msd_ident::{estimate, simulate, Backend, DataSet, EstimationOptions, Excitation, InitialState, Parameters};
/// use msd_signal::{gaussian_noise, paper_identification_input};
/// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
/// let mut y = simulate(&Parameters::PAPER, &input, InitialState::REST, &Backend::EXACT)?;
/// for (yi, e) in y.iter_mut().zip(gaussian_noise(1, "identification", 0.0025, 7501)?) {
///     *yi += e;
/// }
/// let data = DataSet::new("paper", input, y)?;
/// let fit = estimate(&data, &EstimationOptions::fast())?;
/// assert!(fit.uncertainty.stiffness.contains(120.0) || (fit.parameters.stiffness - 120.0).abs() < 1.0);
/// println!("{fit}");
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn estimate(data: &DataSet, options: &EstimationOptions) -> Result<Estimate> {
    fit(data, options, Checks::All)
}

/// Whether [`fit`] runs the likelihood-ratio checks of [`identifiability`] (the probes
/// that those checks fit themselves run without them).
#[derive(Clone, Copy, PartialEq)]
enum Checks {
    All,
    None,
}

fn fit(data: &DataSet, options: &EstimationOptions, checks: Checks) -> Result<Estimate> {
    options.validate()?;
    let started = Instant::now();
    let (guess, source) = match options.initial_guess {
        Some(g) => (g, GuessSource::Given),
        None => (arx_initial_guess(data)?, GuessSource::Automatic),
    };
    let log = options.method == Method::LevenbergMarquardt;
    let layout = Layout::new(options, log);
    if data.len() <= layout.len() {
        return Err(IdentError::TooFewSamples {
            got: data.len(),
            needed: layout.len() + 1,
            why: "more samples than estimated quantities",
        });
    }
    let mut notes = Vec::new();
    let theta0 = starting_point(&guess, options, &layout, log, &mut notes);
    let v0 = layout.pack(&theta0, options.initial_state, options.offset);
    let hold = match options.backend {
        Backend::Exact { hold } => hold,
        Backend::Ode45 { .. } => Hold::Cubic,
    };

    let nm_options = scaled_nelder_mead_options(options, &layout, &theta0, &mut notes);
    let local = |start: &[f64]| -> std::result::Result<Local, msd_opt::OptError> {
        match options.method {
            Method::NelderMead => {
                let mut cost = Cost::new(data, &layout, options.backend);
                let r = nelder_mead(|v| cost.sse(v), start, &nm_options)?;
                Ok(Local::nelder_mead(r))
            }
            Method::LevenbergMarquardt => {
                let mut problem = Residuals {
                    cost: Cost::new(data, &layout, options.backend),
                    hold,
                    jacobians: 0,
                };
                let mut lm = options.levenberg_marquardt.clone();
                lm.bounds = log_bounds(options, &layout);
                let r = levenberg_marquardt(&mut problem, start, &lm)?;
                Ok(Local::levenberg_marquardt(r))
            }
        }
    };

    let (best, starts) = run_starts(options, &layout, &theta0, &v0, &local)?;
    let stop = best
        .finished()
        .map_err(|why| IdentError::EstimationFailed {
            reason: format!("the cost is not finite at any point tried ({why})"),
        })?;
    let (parameters, initial_state, offset) = layout.unpack(&best.x);
    parameters.validate()?;

    // Model output on the estimation backend, fit metrics, uncertainty.
    let raw_layout = Layout::new(options, false);
    let v_raw = raw_layout.pack(&parameters, initial_state, offset);
    let mut cost = Cost::new(data, &raw_layout, options.backend);
    let sse = cost.sse(&v_raw);
    if !sse.is_finite() {
        return Err(IdentError::EstimationFailed {
            reason: "the model cannot be simulated at the estimate".into(),
        });
    }
    let model_output = cost.model;
    let residuals = crate::metrics::residuals(&data.output, &model_output);
    let fit = FitMetrics::new(&data.output, &model_output);
    let jacobian = output_jacobian(data, &raw_layout, &v_raw)?;
    let mut uncertainty = from_jacobian(
        &jacobian,
        sse,
        raw_layout.names(),
        v_raw,
        &parameters,
        raw_layout.parameter_columns(),
    )?;
    let at_bounds = bound_notes(&parameters, &options.bounds);
    let stop = at_minimum(
        stop,
        at_bounds,
        &jacobian,
        &residuals,
        &uncertainty,
        &mut notes,
    );
    if checks == Checks::All {
        let at = (&parameters, initial_state, offset);
        notes.extend(identifiability::check(data, options, at, &uncertainty)?);
    }
    uncertainty.warnings.extend(notes);
    Ok(Estimate {
        parameters,
        initial_state,
        offset,
        initial_guess: (guess, source),
        method: options.method,
        backend: options.backend,
        cost: sse,
        iterations: best.iterations,
        evaluations: best.evaluations,
        jacobian_evaluations: best.jacobians,
        stop,
        starts,
        wall_time: started.elapsed(),
        fit,
        model_output,
        residuals,
        uncertainty,
    })
}

/// Is it a minimum? A Gauss–Newton step from the estimate that moves some quantity by
/// more than one standard error means the optimiser stopped short: the stop reason says
/// so, and `notes`. A parameter held at a bound (`at_bounds`, its notes) is not at a
/// minimum of the data's cost either, but that is the bound's doing: said instead.
fn at_minimum(
    stop: StopReason,
    at_bounds: Vec<String>,
    jacobian: &nalgebra::DMatrix<f64>,
    residuals: &[f64],
    uncertainty: &Uncertainty,
    notes: &mut Vec<String>,
) -> StopReason {
    let at_a_bound = !at_bounds.is_empty();
    notes.extend(at_bounds);
    if let Some((name, ratio)) = gauss_newton_distance(jacobian, residuals, uncertainty)
        && ratio > 1.0
        && !at_a_bound
    {
        notes.push(format!(
            "not at a minimum of the squared error: a Gauss–Newton step from the estimate moves {name} by {ratio:.1} standard errors (the optimiser stopped short: {stop}); try Levenberg–Marquardt, multistart or a better guess"
        ));
        return StopReason::StoppedShort {
            exit: Box::new(stop),
            quantity: name.to_string(),
            standard_errors: ratio,
        };
    }
    stop
}

/// The first guess within the bounds, with the fixed parameters set; for
/// Levenberg–Marquardt (which works on ln c) an undamped guess starts at ζ = 1 %, said in
/// `notes`.
fn starting_point(
    guess: &Parameters,
    options: &EstimationOptions,
    layout: &Layout,
    log: bool,
    notes: &mut Vec<String>,
) -> Parameters {
    let mut theta0 = clamp_to_bounds(&layout.apply_fixed(guess), options);
    if log && theta0.damping <= 0.0 && options.fixed.as_array()[1].is_none() {
        theta0.damping = 0.02 * (theta0.mass * theta0.stiffness).sqrt();
        notes.push(format!(
            "the damping guess 0 was replaced by {:.4e} (ζ = 1 %): Levenberg–Marquardt works on ln c",
            theta0.damping
        ));
    }
    theta0
}

/// Nelder–Mead's options. fminsearch's tolerances are absolute: against parameters far
/// below 1 (m = 1e-6 kg in SI units) they would stop the search at once, so they become
/// relative there, said in `notes`.
fn scaled_nelder_mead_options(
    options: &EstimationOptions,
    layout: &Layout,
    theta0: &Parameters,
    notes: &mut Vec<String>,
) -> msd_opt::NelderMeadOptions {
    let mut nm_options = nelder_mead_options(options, layout);
    let scale = theta0.mass.min(theta0.stiffness);
    if options.method == Method::NelderMead
        && !nm_options.relative_tolerances
        && scale < 100.0 * nm_options.x_tolerance
    {
        nm_options.relative_tolerances = true;
        notes.push(format!(
            "Nelder–Mead used relative tolerances: the absolute TolX = {:e} is coarse against parameters of size {scale:.3e}",
            nm_options.x_tolerance
        ));
    }
    nm_options
}

/// The local search from `v0`, or from every start of the configured multistart (the
/// best run, and how many starts ran).
fn run_starts(
    options: &EstimationOptions,
    layout: &Layout,
    theta0: &Parameters,
    v0: &[f64],
    local: &(dyn Fn(&[f64]) -> std::result::Result<Local, msd_opt::OptError> + Sync),
) -> Result<(Local, usize)> {
    let log = options.method == Method::LevenbergMarquardt;
    match &options.multistart {
        None => Ok((local(v0)?, 1)),
        Some(ms) => {
            let (bounds, pick) = multistart_box(options, layout, theta0, ms);
            let ms_options = MultistartOptions {
                starts: ms.starts,
                seed: ms.seed,
                threads: ms.threads,
                ..MultistartOptions::default()
            };
            let ranked = multistart(&bounds, &ms_options, |point| {
                // Sampled coordinates are log-parameters; convert for Nelder–Mead.
                let mut start = v0.to_vec();
                for (k, &column) in pick.iter().enumerate() {
                    start[column] = if log { point[k] } else { point[k].exp() };
                }
                local(&start)
            })?;
            let total = ranked.len();
            let best = ranked
                .into_iter()
                .next()
                .ok_or_else(|| IdentError::EstimationFailed {
                    reason: "no multistart run finished".into(),
                })?;
            Ok((best.result, total))
        }
    }
}

fn nelder_mead_options(options: &EstimationOptions, layout: &Layout) -> msd_opt::NelderMeadOptions {
    let mut nm = options.nelder_mead.clone();
    if nm.bounds.is_none() && options.bounds.as_array().iter().any(Option::is_some) {
        let n = layout.len();
        let (mut lower, mut upper) = (vec![f64::NEG_INFINITY; n], vec![f64::INFINITY; n]);
        for (column, i) in layout.free().enumerate() {
            if let Some([lo, hi]) = options.bounds.as_array()[i] {
                lower[column] = lo;
                upper[column] = hi;
            }
        }
        nm.bounds = Bounds::new(lower, upper).ok();
    }
    nm
}

fn log_bounds(options: &EstimationOptions, layout: &Layout) -> Option<Bounds> {
    let b = options.bounds.as_array();
    if b.iter().all(Option::is_none) {
        return options.levenberg_marquardt.bounds.clone();
    }
    let n = layout.len();
    let (mut lower, mut upper) = (vec![f64::NEG_INFINITY; n], vec![f64::INFINITY; n]);
    for (column, i) in layout.free().enumerate() {
        if let Some([lo, hi]) = b[i] {
            lower[column] = lo.ln();
            upper[column] = hi.ln();
        }
    }
    Bounds::new(lower, upper).ok()
}

fn clamp_to_bounds(theta: &Parameters, options: &EstimationOptions) -> Parameters {
    let mut v = theta.to_array();
    for (value, bound) in v.iter_mut().zip(options.bounds.as_array()) {
        if let Some([lo, hi]) = bound {
            *value = value.clamp(lo, hi);
        }
    }
    Parameters::from_array(v)
}

/// The multistart box in log-parameters (bounds, or θ₀·10^(±decades)) and the columns
/// of the free physical parameters it samples.
fn multistart_box(
    options: &EstimationOptions,
    layout: &Layout,
    theta0: &Parameters,
    ms: &MultistartSettings,
) -> (Bounds, Vec<usize>) {
    let values = theta0.to_array();
    let b = options.bounds.as_array();
    let half = ms.decades * std::f64::consts::LN_10;
    let (mut lower, mut upper, mut pick) = (Vec::new(), Vec::new(), Vec::new());
    for (column, i) in layout.free().enumerate() {
        let (lo, hi) = match b[i] {
            Some([lo, hi]) => (lo.ln(), hi.ln()),
            None => (values[i].ln() - half, values[i].ln() + half),
        };
        lower.push(lo);
        upper.push(hi);
        pick.push(column);
    }
    // Valid by construction: finite and lower < upper.
    let bounds = Bounds { lower, upper };
    (bounds, pick)
}

/// The Gauss–Newton step δ = (JᵀJ)⁻¹Jᵀr from the estimate, as the largest |δᵢ|/σᵢ over
/// the estimated quantities with its name; `None` if it cannot be formed.
/// A note for each parameter the optimiser left at one of its bounds (within 1e-6
/// relative): the estimate there is the bound, and its interval does not hold.
fn bound_notes(theta: &Parameters, bounds: &ParameterBounds) -> Vec<String> {
    let names = ["mass", "damping", "stiffness"];
    let values = theta.to_array();
    let mut notes = Vec::new();
    for ((name, value), bound) in names.iter().zip(values).zip(bounds.as_array()) {
        let Some([low, high]) = bound else { continue };
        let side = if (value - low).abs() <= 1e-6 * low {
            "lower"
        } else if (value - high).abs() <= 1e-6 * high {
            "upper"
        } else {
            continue;
        };
        notes.push(format!(
            "{name} = {value:.6e} sits at its {side} bound (bounds.{name} = [{low}, {high}]): the data's optimum lies beyond it, so the estimate is the bound and its 95 % interval does not hold there; widen or drop the bound"
        ));
    }
    notes
}

fn gauss_newton_distance(
    jacobian: &nalgebra::DMatrix<f64>,
    residuals: &[f64],
    uncertainty: &crate::uncertainty::Uncertainty,
) -> Option<(&'static str, f64)> {
    let r = nalgebra::DVector::from_column_slice(residuals);
    let step = jacobian
        .tr_mul(jacobian)
        .cholesky()?
        .solve(&jacobian.tr_mul(&r));
    // A step below the optimisers' resolution (1e-8 relative, about √ε: MINPACK's and
    // fminsearch's scale) says nothing: on noise-free data the standard errors are
    // rounding-sized too, and their ratio is noise.
    (0..step.len())
        .filter_map(|i| {
            let se = uncertainty.covariance[(i, i)].sqrt();
            let resolved = step[i].abs() > 1e-8 * uncertainty.values[i].abs();
            (se > 0.0 && resolved).then(|| (uncertainty.names[i], step[i].abs() / se))
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
}
