//! `fit_chain`: every mass, damper and spring of a chain, with intervals, from one record.

use super::identifiable::hold_lost;
use super::noise::treat;
use super::problem::{ChainProblem, Layout, enough_rows};
use super::setup::{ChainParameters, ChainSetup, levels, rms, setup_error};
use super::uncertainty::{ChainUncertainty, Point, uncertainty_at};
use crate::error::{IdentError, Result};
use crate::input_noise::{NoiseModel, NoiseModelFit, ResidualWhiteness, notes};
use crate::residuals::ResidualOptions;
use msd_opt::statistics::Interval;
use msd_opt::{LeastSquaresProblem, LevenbergMarquardtOptions, LmExit, levenberg_marquardt};
use msd_signal::Recording;
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

/// How a chain is fitted.
///
/// ```
/// use msd_ident::chain::ChainOptions;
/// assert!(ChainOptions::default().known_masses.is_empty());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ChainOptions {
    /// Masses (numbered from 1) that are known: held at the guess's value.
    pub known_masses: Vec<usize>,
    /// At most this many fits, each re-estimating every channel's noise level from the
    /// last one's residuals. By default 4.
    pub passes: usize,
    /// Which noise model sets the intervals: by default the drive's own noise estimated
    /// with the sensors' and seen through the chain (errors-in-variables, see
    /// [`NoiseModel`]); `White` takes the drive as exact.
    pub noise_model: NoiseModel,
    /// The residual tests' lags and confidence.
    pub residuals: ResidualOptions,
}

impl Default for ChainOptions {
    fn default() -> Self {
        Self {
            known_masses: Vec::new(),
            passes: 4,
            noise_model: NoiseModel::InputNoise,
            residuals: ResidualOptions::default(),
        }
    }
}

/// What [`fit_chain`] found.
///
/// Serialises flat: the estimates, the fields of [`ChainUncertainty`], the noise levels
/// and the solver's record. Displays the uncertainty, then σ̂ of each channel.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainFit {
    /// The estimates (a known mass as given).
    pub parameters: ChainParameters,
    /// Their intervals, the modes, the delays, what is lost.
    #[serde(flatten)]
    pub uncertainty: ChainUncertainty,
    /// σ̂ of each channel, in its own unit.
    pub noise: Vec<f64>,
    /// Which noise model the intervals come from and what it found.
    pub noise_model: NoiseModelFit,
    /// The intervals and modes under white noise (the drive taken as exact), when the
    /// reported ones come from another noise model.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub white_noise_uncertainty: Option<ChainUncertainty>,
    /// Each sensor's residual: white (Ljung–Box) as fitted and under the noise model,
    /// and its correlation with the drive.
    pub whiteness: Vec<ResidualWhiteness>,
    /// What the reader should know: the drive's noise when it shows, residuals that are
    /// not white or that correlate with the drive.
    pub notes: Vec<String>,
    /// The solver's exit on the last pass.
    pub exit: LmExit,
    /// Model evaluations over all passes.
    pub evaluations: usize,
}

impl std::fmt::Display for ChainFit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "{}", self.uncertainty)?;
        write!(f, "σ̂ per channel")?;
        for (i, sigma) in self.noise.iter().enumerate() {
            write!(f, "{}{sigma:.3e}", if i == 0 { " " } else { ", " })?;
        }
        write!(f, "\n{}", self.noise_model)?;
        for note in &self.notes {
            write!(f, "\nnote: {note}")?;
        }
        Ok(())
    }
}

/// Fits every m, c and k of the chain `setup` (and the delays it asks to estimate) to
/// `record` by weighted output error, from `guess`: each channel is weighted by its own
/// noise level, re-estimated between passes. Exact simulation and exact sensitivities
/// (see the module's equations), the Levenberg–Marquardt solver, intervals from
/// σ̂²(JᵀJ)⁻¹ on the logarithms (so they stay positive).
///
/// When the records cannot separate the parameters (a base acceleration with no known
/// mass, too few sensors) the fit says which combinations are lost and reports the modes.
///
/// ```
/// use msd_ident::{chain::{ChainOptions, ChainParameters, ChainSensor, ChainSetup, fit_chain, simulate_chain}};
/// use msd_ident::ResponseQuantity::Acceleration;
/// let setup = ChainSetup {
///     masses: 2,
///     force_at: 2,
///     sensors: vec![
///         ChainSensor { at: 1, quantity: Acceleration, ..ChainSensor::default() },
///         ChainSensor { at: 2, quantity: Acceleration, ..ChainSensor::default() },
///     ],
///     ..ChainSetup::default()
/// };
/// let truth = ChainParameters { masses: vec![2.0, 1.0], dampers: vec![4.0, 2.0], springs: vec![2e4, 1e4], ..ChainParameters::default() };
/// let dt = 2e-3;
/// let force: Vec<f64> = (0..2000).map(|i| ((i * 7919) % 1000) as f64 / 500.0 - 1.0).collect();
/// let outputs = simulate_chain(&setup, &truth, &force, dt)?;
/// let record = setup.recording("test", dt, force, outputs);
/// let guess = ChainParameters { masses: vec![2.4, 0.8], dampers: vec![3.0, 3.0], springs: vec![2.5e4, 0.8e4], ..ChainParameters::default() };
/// let fit = fit_chain(&setup, &record, &guess, &ChainOptions::default())?;
/// assert!((fit.parameters.springs[1] / 1e4 - 1.0).abs() < 1e-6);
/// assert_eq!(fit.uncertainty.modes.len(), 2);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn fit_chain(
    setup: &ChainSetup,
    record: &Recording,
    guess: &ChainParameters,
    options: &ChainOptions,
) -> Result<ChainFit> {
    check(setup, record, guess, options)?;
    let mut layout = Layout::new(setup, &options.known_masses, guess);
    let delays: Vec<f64> = setup
        .sensors
        .iter()
        .map(|s| s.delay.unwrap_or(0.0))
        .collect();
    let lost = hold_lost(setup, record, guess, &delays, &mut layout);
    let start = Start {
        setup,
        layout: &layout,
        guess,
        delays: &delays,
    };
    let solved = solve(&start, record, options.passes)?;
    if let Some(j) = runaway(&start, &solved.theta) {
        return absent_or_lost(&start, &solved.theta, j, record, options);
    }
    let mut fit = statistics(&start, record, solved, options)?;
    if !lost.is_empty() {
        not_identified(&mut fit.uncertainty, &lost);
        if let Some(white) = fit.white_noise_uncertainty.as_mut() {
            not_identified(white, &lost);
        }
    }
    let runaway = runaway_cutoffs(&fit, record.dt);
    if runaway.is_empty() {
        return Ok(fit);
    }
    // A cut-off the record cannot pin runs off (past Nyquist, an unbounded interval):
    // a first-order filter at fc delays by about 1/(2π fc) at low frequency, so with
    // the delay estimated the two are nearly confounded. Refit without those filters and
    // say so, rather than report a number whose interval means nothing.
    let mut without = setup.clone();
    for &i in &runaway {
        without.sensors[i].estimate_cutoff = false;
        without.sensors[i].low_pass = None;
    }
    let mut refit = fit_chain(&without, record, guess, options)?;
    for &i in &runaway {
        let fc = fit.uncertainty.cutoffs[i].map_or(f64::NAN, |c| c.value);
        refit.notes.push(format!(
            "sensor {}: {CUTOFF_NOT_SEPARATED} {fc:.3e} Hz (past the Nyquist frequency, or with an unbounded interval): the record cannot separate a first-order filter from the sensor's delay (the filter delays by about 1/(2π·fc)); refitted without the filter, so the delay reported is the sensor's whole lag, filter included",
            i + 1
        ));
    }
    Ok(refit)
}

/// The words of the note a refit without a runaway cut-off leaves in [`ChainFit::notes`].
pub const CUTOFF_NOT_SEPARATED: &str = "its low-pass cut-off ran to";

/// The words of the note a refit without a ground spring or damper that ran to zero
/// leaves in [`ChainFit::notes`].
pub const GROUND_NOT_IN_RECORDS: &str = "the records show no";

/// The words of the note on a spring or damper to the ground whose interval reaches zero.
pub const GROUND_AT_ZERO: &str = "its interval reaches zero";

/// The sensors whose estimated cut-off ran off: past the Nyquist frequency, not finite,
/// or with an interval that is not bounded above.
fn runaway_cutoffs(fit: &ChainFit, dt: f64) -> Vec<usize> {
    let nyquist = 0.5 / dt;
    (fit.uncertainty.cutoffs.iter().enumerate())
        .filter_map(|(i, c)| c.map(|c| (i, c)))
        .filter(|(_, c)| !(c.value.is_finite() && c.value < nyquist && c.ci95[1].is_finite()))
        .map(|(i, _)| i)
        .collect()
}

/// Checks the inputs; the errors name the key.
fn check(
    setup: &ChainSetup,
    record: &Recording,
    guess: &ChainParameters,
    options: &ChainOptions,
) -> Result<()> {
    setup.validate()?;
    guess.validate(setup.masses)?;
    setup.check_recording(record)?;
    if let Some(&m) = options
        .known_masses
        .iter()
        .find(|&&m| !(1..=setup.masses).contains(&m))
    {
        return Err(setup_error(format!(
            "known_masses contains {m}: expected masses from 1 to {}",
            setup.masses
        )));
    }
    levels(record)?;
    let rows = record.len() * setup.sensors.len();
    let estimated = Layout::new(setup, &options.known_masses, guess).len();
    enough_rows(rows, estimated)
}

/// What the fit starts from and holds.
struct Start<'a> {
    setup: &'a ChainSetup,
    layout: &'a Layout,
    guess: &'a ChainParameters,
    delays: &'a [f64],
}

impl<'a> Start<'a> {
    /// The point θ of this fit, for the statistics.
    fn at(&self, theta: &'a [f64]) -> Point<'a> {
        Point {
            setup: self.setup,
            layout: self.layout,
            theta,
            base: self.guess,
            delays: self.delays,
        }
    }

    /// The problem on `record`, each channel weighted by its RMS.
    fn problem(&self, record: &'a Recording) -> ChainProblem<'a> {
        ChainProblem {
            setup: self.setup,
            record,
            layout: self.layout,
            base: self.guess,
            delays: self.delays,
            noise: record.responses().map(rms).collect(),
        }
    }
}

/// Where the solver ended.
struct Solved {
    theta: Vec<f64>,
    /// Each channel's noise level from the final residuals.
    noise: Vec<f64>,
    /// The levels the last pass weighted by, and its Jacobian and residuals at `theta`.
    weights: Vec<f64>,
    jacobian: DMatrix<f64>,
    residuals: Vec<f64>,
    exit: LmExit,
    evaluations: usize,
}

/// Prefix stages first, then `passes` fits of the whole record with the noise levels
/// re-estimated between them.
///
/// An output-error fit of lightly damped modes has many local minima over a long record
/// (a wrong frequency drifts out of phase); over a short one it has few. So the solver
/// first fits the record's first sixteenth, then its first quarter (each of at least
/// [`MIN_STAGE`] samples), each starting where the last ended; these stages are also
/// cheap. A stage that fails, or runs a parameter away (see [`runaway`]), leaves the
/// start as it was.
fn solve(start: &Start<'_>, record: &Recording, passes: usize) -> Result<Solved> {
    // The step test at 1e-6 of ‖θ‖: a step of 1e-6 in a logarithm is 1e-6 relative, far
    // below any standard error a record gives; the cost test stays MINPACK's √ε.
    let lm = LevenbergMarquardtOptions {
        max_evaluations: Some(400),
        x_tolerance: 1e-6,
        ..LevenbergMarquardtOptions::default()
    };
    let mut theta = start.layout.theta(start.guess, start.delays);
    let mut evaluations = 0;
    for length in [record.len() / 16, record.len() / 4] {
        if length < MIN_STAGE.max(20 * start.layout.len()) {
            continue;
        }
        let prefix = record.prefix(length);
        let mut problem = start.problem(&prefix);
        if let Ok(result) = levenberg_marquardt(&mut problem, &theta, &lm) {
            evaluations += result.evaluations;
            // A short record may not fix every parameter: a stage that ran one away
            // is dropped.
            if runaway(start, &result.x).is_none() {
                theta = result.x;
            }
        }
    }
    let mut problem = start.problem(record);
    let rows = problem.residual_count();
    let inflation = rows as f64 / (rows - start.layout.len()) as f64;
    // The first weights: each channel's noise level at the stages' estimate.
    if let Some(sim) = problem.simulate(&theta, None) {
        let noise = channel_noise(&sim.outputs, record, inflation);
        if noise.iter().all(|v| v.is_finite() && *v > 0.0) {
            problem.noise = noise;
        }
    }
    let mut last = None;
    for _ in 0..passes.max(1) {
        let result = levenberg_marquardt(&mut problem, &theta, &lm)?;
        evaluations += result.evaluations;
        let sim =
            problem
                .simulate(&result.x, None)
                .ok_or_else(|| IdentError::EstimationFailed {
                    reason: "the chain cannot be simulated at the estimate".into(),
                })?;
        let noise = channel_noise(&sim.outputs, record, inflation);
        let change = noise
            .iter()
            .zip(&problem.noise)
            .map(|(a, b)| (a / b - 1.0).abs())
            .fold(0.0, f64::max);
        theta.clone_from(&result.x);
        last = Some((result, std::mem::replace(&mut problem.noise, noise)));
        // Weights a few per cent off move the estimate by a few hundredths of its
        // standard error (0.03 SE measured on the two-storey rig) and lose a second-order
        // amount of efficiency; the intervals use the final noise levels.
        if change < REWEIGHT {
            break;
        }
    }
    let Some((result, weights)) = last else {
        return Err(IdentError::EstimationFailed {
            reason: "no pass of the chain fit ran".into(),
        });
    };
    if !result.exit.is_success() {
        return Err(IdentError::EstimationFailed {
            reason: format!("the chain fit did not converge: {}", result.exit),
        });
    }
    // A delay past zero was read as zero during the fit (ChainProblem::simulate): the
    // estimate is that zero, at which the residuals and sensitivities were taken.
    let simulated = start.layout.simulated();
    for t in &mut theta[simulated..] {
        *t = t.max(0.0);
    }
    Ok(Solved {
        theta,
        noise: problem.noise,
        weights,
        jacobian: result.jacobian,
        residuals: result.residuals,
        exit: result.exit,
        evaluations,
    })
}

/// A change of the noise levels below this ends the passes.
const REWEIGHT: f64 = 0.05;

/// The fewest samples of a prefix stage.
const MIN_STAGE: usize = 256;

/// The first parameter that left its guess by more than [`RUNAWAY`] (or to 0 or ∞).
fn runaway(start: &Start<'_>, theta: &[f64]) -> Option<usize> {
    let first = start.layout.theta(start.guess, start.delays);
    let free = start.layout.free.len();
    (theta.iter().zip(&first).take(free)).position(|(t, t0)| {
        let ratio = (t - t0).exp();
        !(ratio.is_finite() && ratio > 1.0 / RUNAWAY && ratio < RUNAWAY && t.exp() > 0.0)
    })
}

/// A fit whose column `j` ran away: a spring or damper to the ground that ran to zero is
/// one the chain does not have (refitted without it, said in a note); anything else is a
/// wrong minimum, not an estimate: an error naming it.
fn absent_or_lost(
    start: &Start<'_>,
    theta: &[f64],
    j: usize,
    record: &Recording,
    options: &ChainOptions,
) -> Result<ChainFit> {
    use super::model::Family::{GroundDamper, GroundSpring};
    let (name, t0, t) = (
        start.layout.name(j),
        start.layout.theta(start.guess, start.delays)[j].exp(),
        theta[j].exp(),
    );
    let (family, i) = start.layout.free[j];
    if matches!(family, GroundDamper | GroundSpring) && t < t0 {
        let mut without = start.guess.clone();
        let values = match family {
            GroundDamper => &mut without.ground_dampers,
            _ => &mut without.ground_springs,
        };
        values[i] = 0.0;
        let mut fit = fit_chain(start.setup, record, &without, options)?;
        fit.notes.push(format!(
            "{name} ran from the guess {t0:.3e} to {t:.3e}: {GROUND_NOT_IN_RECORDS} {} from mass {} to the ground; refitted without it",
            if family == GroundDamper { "damper" } else { "spring" },
            i + 1
        ));
        return Ok(fit);
    }
    Err(IdentError::EstimationFailed {
        reason: format!(
            "{name} ran from the guess {t0:e} to {t:e}: the fit fell into a wrong minimum (or the records do not fix it); start from a closer guess"
        ),
    })
}

/// Marks `uncertainty` as not identifying m, c, k for the reasons `lost` (found before
/// the fit, which held one parameter per reason), before any found at the estimate.
fn not_identified(uncertainty: &mut ChainUncertainty, lost: &[String]) {
    uncertainty.intervals = None;
    let found = std::mem::take(&mut uncertainty.unidentifiable);
    uncertainty.unidentifiable = lost.iter().cloned().chain(found).collect();
}

/// The factor a parameter may move from its guess.
const RUNAWAY: f64 = 1e4;

/// The intervals, the modes and what is lost, at the solution.
fn statistics(
    start: &Start<'_>,
    record: &Recording,
    solved: Solved,
    options: &ChainOptions,
) -> Result<ChainFit> {
    let layout = start.layout;
    let theta = &solved.theta;
    let rows = solved.residuals.len();
    let dof = rows - layout.len();
    // The last pass's Jacobian and residuals, reweighted by the final noise levels.
    let (mut jacobian, mut residuals) = (solved.jacobian, solved.residuals);
    let samples = record.len();
    for (ch, (old, new)) in solved.weights.iter().zip(&solved.noise).enumerate() {
        let factor = old / new;
        jacobian.rows_mut(ch * samples, samples).scale_mut(factor);
        residuals[ch * samples..(ch + 1) * samples]
            .iter_mut()
            .for_each(|r| *r *= factor);
    }
    let s2 = residuals.iter().map(|r| r * r).sum::<f64>() / dof as f64;
    if !s2.is_finite() || jacobian.iter().any(|v| !v.is_finite()) {
        return Err(IdentError::EstimationFailed {
            reason: "the chain's residuals or sensitivities are not finite at the estimate".into(),
        });
    }
    let (parameters, _) = layout.unpack(theta, start.guess, start.delays);
    let mut problem = start.problem(record);
    problem.noise.clone_from(&solved.noise);
    let treated = treat(
        &problem,
        theta,
        &jacobian,
        &residuals,
        dof,
        options.noise_model,
        &options.residuals,
    );
    let at = start.at(theta);
    let reported = treated.covariance.as_ref().map(|c| (c, treated.t_dof));
    let uncertainty = uncertainty_at(&at, &jacobian, s2, dof, reported);
    let white_noise_uncertainty = reported.map(|_| uncertainty_at(&at, &jacobian, s2, dof, None));
    let mut notes = notes(
        &treated.fit,
        &treated.whiteness,
        "white_noise_uncertainty",
        true,
    );
    notes.extend(ground_at_zero(&uncertainty));
    Ok(ChainFit {
        parameters,
        uncertainty,
        noise: solved.noise,
        noise_model: treated.fit,
        white_noise_uncertainty,
        whiteness: treated.whiteness,
        notes,
        exit: solved.exit,
        evaluations: solved.evaluations,
    })
}

/// A note for each spring or damper to the ground whose interval reaches zero.
fn ground_at_zero(uncertainty: &ChainUncertainty) -> Vec<String> {
    let Some(iv) = &uncertainty.intervals else {
        return Vec::new();
    };
    let each = |values: &[Interval], symbol: &str, what: &str, unit: &str| {
        (values.iter().enumerate())
            .filter(|(_, v)| v.standard_error > 0.0 && v.ci95[0] <= 0.0)
            .map(|(i, v)| {
                format!(
                    "{symbol}{} = {:.3e} {unit}: {GROUND_AT_ZERO}, so the records do not show that the {what} from mass {} to the ground is there",
                    i + 1,
                    v.value,
                    i + 1
                )
            })
            .collect::<Vec<_>>()
    };
    let mut notes = each(&iv.ground_springs, "kg", "spring", "N/m");
    notes.extend(each(&iv.ground_dampers, "cg", "damper", "N·s/m"));
    notes
}

/// σ̂ of each channel from its residuals, with `inflation` = rows/dof shared evenly.
fn channel_noise(outputs: &[f64], record: &Recording, inflation: f64) -> Vec<f64> {
    let samples = record.len();
    record
        .responses()
        .enumerate()
        .map(|(ch, measured)| {
            let sse: f64 = outputs[ch * samples..(ch + 1) * samples]
                .iter()
                .zip(measured)
                .map(|(y, m)| (y - m) * (y - m))
                .sum();
            (sse * inflation / samples as f64)
                .sqrt()
                .max(f64::MIN_POSITIVE)
        })
        .collect()
}
