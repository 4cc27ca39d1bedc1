//! Optimal excitation design: the force that will give the smallest uncertainty of
//! m, c and k within the limits of the test rig, before the test is run.
//!
//! ## The family
//! A multisine on the frequency grid of its period (lines j/T, T the record length, or for
//! a long record a shorter period it repeats: [`DesignOptions::period`]) over a band,
//! with an amplitude and phase per line, optionally in several time segments with their
//! own amplitudes and phases, plus an optional step (for the static stiffness).
//!
//! ## The algorithm
//! * The Fisher information of the relative parameters (m/m₀, c/c₀, k/k₀) comes from the
//!   exact sensitivities, by superposition: the response of each line, segment edge and
//!   step is computed once per plant (steady state by frequency response, transients
//!   from the free response of the 8-state sensitivity system), the sums over lines are
//!   inverse FFTs of the period's length. Once the free responses have settled, the
//!   series repeat with the period, so a long record costs one period and the settling
//!   after each edge, whatever its length. A design's information and its exact gradient
//!   cost a few FFTs per plant; no ODE is solved while optimising.
//! * The cost is the criterion (D: det, A: trace, minimax: worst diagonal of the
//!   inverse information) combined over the plants, plus twice the log of a smooth
//!   maximum of the force, stroke and RMS ratios to their limits (and a penalty on a
//!   step below its least height): it does not change when
//!   the force is scaled, so the limits are met by scaling the optimum at the end. The
//!   smooth maximum is sharpened in three stages (p = 8, 32, 128), each minimised by
//!   L-BFGS ([`msd_opt::lbfgs()`]).
//! * The result is scaled so that the largest of force, RMS force and stroke (the last
//!   from the exact simulation of the sampled force on the prior plant, or on every
//!   plant with [`StrokeOn::EveryPlant`]) meets its limit; a step left below its least
//!   height is raised to it and the multisine scaled down until the limits hold again.
//!   It is compared with the reference input by the Cramér–Rao bound
//!   ([`predicted_uncertainty`](crate::estimate::predicted_uncertainty)).
//!
//! Sequential design: design from a pilot test's estimate instead of a guess, with
//! [`RobustBox::around`] its uncertainty.
//!
//! ```
//! use msd_ident::{design::{Criterion, design_input, DesignOptions}, Excitation, Parameters};
//! use msd_signal::paper_identification_input;
//! let paper = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
//! let options = DesignOptions { lines: 20, iterations: 20, ..DesignOptions::default() };
//! let design = design_input(&Parameters::PAPER, &paper, 2.5e-3, &options)?;
//! assert!(design.peak_force <= 9.0 && design.peak_stroke <= 0.1115);
//! assert!(design.comparison.determinant_ratio < 1.0); // better than the paper's input
//! # Ok::<(), msd_ident::IdentError>(())
//! ```

mod basis;
mod compare;
mod objective;
mod options;
mod signal;

pub use compare::InputComparison;
pub use options::{
    Aggregate, Criterion, DesignConstraints, DesignOptions, LONGEST_PERIOD, Normalise, RobustBox,
    StepOption, StrokeOn,
};

use crate::{data::Excitation, error::Result, params::Parameters};
use basis::PlantBasis;
use msd_opt::{LbfgsExit, LbfgsOptions, lbfgs};
use msd_signal::Signal;
use objective::{Limits, Objective};
use serde::Serialize;

/// A designed input and what it is predicted to give.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Design {
    /// The criterion it optimises.
    pub criterion: Criterion,
    /// The force, as msd-signal terms (a step and windowed sines).
    pub signal: Signal,
    /// The force sampled on the reference's record.
    #[serde(skip)]
    pub excitation: Excitation,
    /// The excited frequencies, Hz.
    pub frequencies_hz: Vec<f64>,
    /// The step's height, N (0 without a step).
    pub step_amplitude: f64,
    /// Largest |force| of the samples, N.
    pub peak_force: f64,
    /// RMS force, N.
    pub rms_force: f64,
    /// Largest |displacement| of the exact response on the prior plant, m.
    pub peak_stroke: f64,
    /// The plants it was optimised over, the prior first.
    pub plants: Vec<Parameters>,
    /// Largest |displacement| of the exact response on each of `plants`, m: within
    /// `max_stroke` on every one only with [`StrokeOn::EveryPlant`].
    pub plant_strokes: Vec<f64>,
    /// The plants the stroke limit holds on.
    pub stroke_on: StrokeOn,
    /// Its predicted standard errors beside the reference's, on the prior plant.
    pub comparison: InputComparison,
    /// L-BFGS iterations, over all stages and starts.
    pub iterations: usize,
    /// Cost and gradient evaluations.
    pub evaluations: usize,
    /// Why the last stage of the best start stopped.
    pub exit: LbfgsExit,
}

impl std::fmt::Display for Design {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let band = match (self.frequencies_hz.first(), self.frequencies_hz.last()) {
            (Some(a), Some(b)) => format!("{} lines {a:.3} … {b:.3} Hz", self.frequencies_hz.len()),
            _ => "no lines".into(),
        };
        writeln!(
            f,
            "{} design over {} plant(s): {band}, step {:.4} N",
            self.criterion,
            self.plants.len(),
            self.step_amplitude
        )?;
        writeln!(
            f,
            "  peak force {:.4} N, RMS force {:.4} N, peak stroke {:.5} m on the prior",
            self.peak_force, self.rms_force, self.peak_stroke
        )?;
        if let [_, others @ ..] = self.plant_strokes.as_slice()
            && !others.is_empty()
        {
            let top = others.iter().fold(0.0f64, |m, x| m.max(*x));
            let holds = match self.stroke_on {
                StrokeOn::Prior => "the stroke limit holds on the prior only",
                StrokeOn::EveryPlant => "the stroke limit holds on every plant",
            };
            writeln!(
                f,
                "  peak stroke on the box's other plants up to {top:.5} m: {holds}"
            )?;
        }
        writeln!(
            f,
            "  L-BFGS: {} iterations, {} evaluations ({})",
            self.iterations, self.evaluations, self.exit
        )?;
        write!(f, "{}", self.comparison)
    }
}

/// Designs the input for `prior` on the record of `reference` (its start, sampling
/// interval and length), with measurement noise `sigma`, and compares it with
/// `reference`. See the [module docs](self) for the method.
pub fn design_input(
    prior: &Parameters,
    reference: &Excitation,
    sigma: f64,
    options: &DesignOptions,
) -> Result<Design> {
    options.validate(prior, reference)?;
    let mut layout = signal::layout(options, reference);
    let plants = plants(prior, &options.robust, options.seed)?;
    let bases = plants
        .iter()
        .map(|p| PlantBasis::new(p, &layout))
        .collect::<Result<Vec<_>>>()?;
    layout.keep(bases.iter().map(|b| b.free.len()).max().unwrap_or(0));
    let c = &options.constraints;
    let limits = Limits {
        force: c.max_force,
        stroke: c.max_stroke,
        rms_force: c.max_rms_force,
        min_step: c.step.map_or(0.0, |s| s.min_amplitude),
        stroke_plants: match c.stroke_on {
            StrokeOn::Prior => 1,
            StrokeOn::EveryPlant => plants.len(),
        },
    };
    let mut objective = Objective::new(
        &layout,
        &bases,
        limits,
        options.criterion,
        options.robust.aggregate,
    );
    if options.normalise == Normalise::Reference {
        objective.units = plants
            .iter()
            .map(|p| reference_units(p, reference))
            .collect::<Result<_>>()?;
    }
    let (mut best, mut iterations, mut evaluations) = (None::<(f64, Vec<f64>, LbfgsExit)>, 0, 0);
    for start in 0..options.starts {
        let mut w = signal::initial(&layout, start, options.seed, c.max_force)?;
        let mut last = None;
        for sharpness in [8.0, 32.0, 128.0] {
            objective.sharpness = sharpness;
            let lbfgs_options = LbfgsOptions {
                max_iterations: options.iterations,
                ..LbfgsOptions::default()
            };
            let r = lbfgs(
                |x: &[f64], g: &mut [f64]| objective.evaluate(x, g),
                &w,
                &lbfgs_options,
            )?;
            (iterations, evaluations) = (iterations + r.iterations, evaluations + r.evaluations);
            let norm = r.x.iter().map(|v| v * v).sum::<f64>().sqrt();
            w = r.x.iter().map(|v| v / norm).collect();
            last = Some((r.cost, r.exit));
        }
        if let Some((cost, exit)) = last
            && best.as_ref().is_none_or(|b| cost < b.0)
        {
            best = Some((cost, w, exit));
        }
    }
    let Some((_, w, exit)) = best else {
        unreachable!("validated: at least one start")
    };
    let scaled = signal::scaled(&layout, &w, &plants, reference, c)?;
    let comparison = InputComparison::new(prior, &scaled.excitation, reference, sigma)?;
    Ok(Design {
        criterion: options.criterion,
        signal: scaled.signal,
        excitation: scaled.excitation,
        frequencies_hz: (0..layout.lines.len())
            .map(|l| layout.omega(l) / std::f64::consts::TAU)
            .collect(),
        step_amplitude: scaled.step_amplitude,
        peak_force: scaled.peak_force,
        rms_force: scaled.rms_force,
        peak_stroke: scaled.peak_strokes[0],
        plants,
        plant_strokes: scaled.peak_strokes,
        stroke_on: c.stroke_on,
        comparison,
        iterations,
        evaluations,
        exit,
    })
}

/// The reference input's relative standard errors on `plant` (for σ = 1).
fn reference_units(plant: &Parameters, reference: &Excitation) -> Result<[f64; 3]> {
    let u = crate::estimate::predicted_uncertainty(
        plant,
        reference,
        1.0,
        &crate::estimate::EstimationOptions::default(),
    )?;
    Ok([
        u.mass.standard_error / plant.mass,
        u.damping.standard_error / plant.damping,
        u.stiffness.standard_error / plant.stiffness,
    ])
}

/// The prior, then a seeded Latin hypercube of `robust.plants − 1` plants in its box.
fn plants(prior: &Parameters, robust: &RobustBox, seed: u64) -> Result<Vec<Parameters>> {
    let mut plants = vec![*prior];
    if robust.plants > 1 && robust.spread > 0.0 {
        let theta = [prior.mass, prior.damping, prior.stiffness];
        let low = theta.iter().map(|t| t * (1.0 - robust.spread)).collect();
        let high = theta.iter().map(|t| t * (1.0 + robust.spread)).collect();
        let bounds = msd_opt::Bounds::new(low, high)?;
        let sampling = msd_opt::MultistartOptions {
            starts: robust.plants - 1,
            seed,
            ..Default::default()
        };
        for p in msd_opt::starting_points(&bounds, &sampling)? {
            plants.push(Parameters {
                mass: p[0],
                damping: p[1],
                stiffness: p[2],
            });
        }
    }
    Ok(plants)
}

#[cfg(test)]
mod tests;
