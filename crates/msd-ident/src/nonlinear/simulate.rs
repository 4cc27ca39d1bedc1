//! Response of a nonlinear model: RK4 sample by sample on the hold polynomial of the
//! force ([`super::rk4`]), or msd-ode's ode45 (Dormand–Prince 5(4)) on the force as a
//! function of time.

use super::model::{Forces, NonlinearParameters};
use super::rk4::{Columns, HoldRk4};
use crate::{
    data::Excitation,
    error::{IdentError, Result},
    params::InitialState,
    simulate::{Backend, simulate},
};
use msd_ode::{Hold, Ode45Options, SVector, Stats, ode45_with};
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

/// The smoothing velocity v_s of the Coulomb term F_c·tanh(x'/v_s).
///
/// By default `Relative(1e-3)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SmoothingVelocity {
    /// v_s = factor × the RMS velocity of the nominal (linear-part) response to the
    /// excitation: 1e-3 makes tanh a sign function except within 0.1 % of the typical
    /// speed around each reversal.
    Relative(f64),
    /// v_s in the units of x' (e.g. m/s).
    Absolute(f64),
}

impl Default for SmoothingVelocity {
    fn default() -> Self {
        SmoothingVelocity::Relative(1e-3)
    }
}

/// The integrator of a nonlinear model.
///
/// By default [`NonlinearSolver::Auto`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NonlinearSolver {
    /// [`Rk4`](NonlinearSolver::Rk4) on a force known only by its samples (measured
    /// data), [`Ode45`](NonlinearSolver::Ode45) on a known signal (synthetic data).
    #[default]
    Auto,
    /// Classical RK4 sample interval by sample interval on the hold polynomial of the
    /// force, with as many sub-steps as the model's fastest eigenvalue needs: the fast
    /// way on measured data.
    Rk4,
    /// msd-ode's ode45 (Dormand–Prince 5(4)) with the force evaluated continuously
    /// ([`Excitation::value`]): the paper's way.
    Ode45,
}

impl std::fmt::Display for NonlinearSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            NonlinearSolver::Auto => "auto",
            NonlinearSolver::Rk4 => "RK4 on the hold",
            NonlinearSolver::Ode45 => "ode45",
        })
    }
}

/// How nonlinear models are simulated.
///
/// | field | default | why |
/// |---|---|---|
/// | `solver` | `Auto` | RK4 on the hold for measured data, ode45 for a known signal |
/// | `hold` | cubic | as the linear model's exact backend ([`Backend::EXACT`](crate::simulate::Backend::EXACT)) |
/// | `rel_tol` | 1e-8 | ode45 only: tighter than the paper's 1e-6 so that the solver's error stays far below the noise |
/// | `abs_tol` | 1e-12 | ode45 only: idem, far below any noise level in metres or volts |
/// | `smoothing_velocity` | `Relative(1e-3)` | see [`SmoothingVelocity`] |
///
/// Under either solver the estimator's Jacobian comes from the forward sensitivities
/// integrated by RK4 on the hold (one augmented simulation a Jacobian).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NonlinearSimulation {
    /// The integrator. By default `Auto`.
    pub solver: NonlinearSolver,
    /// The force between samples for RK4 (and the Jacobian): `"zero"`, `"first"` or
    /// `"cubic"`. By default cubic.
    #[serde(with = "crate::simulate::hold_serde")]
    pub hold: Hold,
    /// ode45 relative tolerance. By default 1e-8.
    pub rel_tol: f64,
    /// ode45 absolute tolerance. By default 1e-12.
    pub abs_tol: f64,
    /// The Coulomb smoothing velocity. By default 1e-3 × the nominal RMS velocity.
    pub smoothing_velocity: SmoothingVelocity,
}

impl Default for NonlinearSimulation {
    fn default() -> Self {
        Self {
            solver: NonlinearSolver::Auto,
            hold: Hold::Cubic,
            rel_tol: 1e-8,
            abs_tol: 1e-12,
            smoothing_velocity: SmoothingVelocity::default(),
        }
    }
}

impl NonlinearSimulation {
    /// Checks the tolerances and the smoothing velocity (finite, > 0).
    pub fn validate(&self) -> Result<()> {
        self.ode45_options().validate()?;
        let (name, v) = match self.smoothing_velocity {
            SmoothingVelocity::Relative(v) => ("smoothing_velocity.relative", v),
            SmoothingVelocity::Absolute(v) => ("smoothing_velocity.absolute", v),
        };
        if !(v.is_finite() && v > 0.0) {
            return Err(IdentError::InvalidParameter {
                name,
                value: v,
                expected: "a finite number > 0",
            });
        }
        Ok(())
    }

    /// The solver `Auto` stands for on `excitation`: RK4 when the force is known only
    /// by its samples, ode45 when its signal is known; any other solver as it is.
    ///
    /// ```
    /// use msd_ident::{Excitation, nonlinear::{NonlinearSimulation, NonlinearSolver}};
    /// use msd_signal::paper_identification_input;
    /// let measured = Excitation::from_samples(0.0, 0.01, vec![0.0; 20])?;
    /// let known = Excitation::from_signal(paper_identification_input(), 0.0, 0.01, 20)?;
    /// let auto = NonlinearSimulation::default();
    /// assert_eq!(auto.solver_for(&measured), NonlinearSolver::Rk4);
    /// assert_eq!(auto.solver_for(&known), NonlinearSolver::Ode45);
    /// # Ok::<(), msd_ident::IdentError>(())
    /// ```
    pub fn solver_for(&self, excitation: &Excitation) -> NonlinearSolver {
        match self.solver {
            NonlinearSolver::Auto if excitation.signal().is_none() => NonlinearSolver::Rk4,
            NonlinearSolver::Auto => NonlinearSolver::Ode45,
            solver => solver,
        }
    }

    fn ode45_options(&self) -> Ode45Options {
        Ode45Options {
            rel_tol: self.rel_tol,
            abs_tol: self.abs_tol,
            ..Ode45Options::default()
        }
    }

    /// The smoothing velocity v_s for `parameters` on `excitation`: the absolute value,
    /// or the factor times the RMS velocity of the linear part's response (exact
    /// simulation, velocity by central differences of the displacement).
    pub fn resolve_smoothing_velocity(
        &self,
        parameters: &NonlinearParameters,
        excitation: &Excitation,
        initial: InitialState,
    ) -> Result<f64> {
        self.validate()?;
        match self.smoothing_velocity {
            SmoothingVelocity::Absolute(v) => Ok(v),
            SmoothingVelocity::Relative(factor) => {
                let x = simulate(
                    &parameters.linear_part(),
                    excitation,
                    initial,
                    &Backend::EXACT,
                )?;
                let rms = nominal_rms_velocity(&x, excitation.dt());
                if rms > 0.0 && rms.is_finite() {
                    Ok(factor * rms)
                } else {
                    Err(IdentError::NotIdentifiable {
                        reason: "the nominal response does not move, so the Coulomb smoothing velocity (relative to its RMS velocity) is undefined".into(),
                    })
                }
            }
        }
    }
}

/// RMS of the central-difference velocity of `x` sampled at `dt`.
fn nominal_rms_velocity(x: &[f64], dt: f64) -> f64 {
    if x.len() < 3 {
        return 0.0;
    }
    let sum: f64 = x
        .windows(3)
        .map(|w| ((w[2] - w[0]) / (2.0 * dt)).powi(2))
        .sum();
    (sum / (x.len() - 2) as f64).sqrt()
}

/// Displacement response of the nonlinear model `parameters` to `excitation` from
/// `initial`, by the solver of `options` ([`NonlinearSimulation::solver_for`]), v_s the
/// Coulomb smoothing velocity (ignored without a Coulomb term). Returns the
/// displacement at the sample times and the solver's statistics (for RK4: four
/// evaluations a sub-step; a pass redone with more sub-steps counts as rejected).
///
/// ```
/// use msd_ident::{Backend, Excitation, InitialState, nonlinear::{ModelStructure, NonlinearParameters, NonlinearSimulation, NonlinearSolver, simulate_nonlinear}, Parameters, simulate};
/// use msd_signal::paper_identification_input;
/// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 2001)?;
/// // The linear member of the family agrees with the exact linear simulation, by
/// // either solver.
/// let p = NonlinearParameters::from_linear(ModelStructure::LINEAR, &Parameters::PAPER);
/// let exact = simulate(&Parameters::PAPER, &input, InitialState::REST, &Backend::EXACT)?;
/// for solver in [NonlinearSolver::Ode45, NonlinearSolver::Rk4] {
///     let options = NonlinearSimulation { solver, ..NonlinearSimulation::default() };
///     let (x, _stats) = simulate_nonlinear(&p, &input, InitialState::REST, &options, 1e-3)?;
///     let worst = x.iter().zip(&exact).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
///     assert!(worst < 1e-7);
/// }
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn simulate_nonlinear(
    parameters: &NonlinearParameters,
    excitation: &Excitation,
    initial: InitialState,
    options: &NonlinearSimulation,
    smoothing_velocity: f64,
) -> Result<(Vec<f64>, Stats)> {
    let forces = checked_forces(parameters, options, smoothing_velocity)?;
    let mut simulator = Simulator::new(excitation, options)?;
    let mut out = vec![0.0; excitation.len()];
    let stats = match simulator.solver {
        NonlinearSolver::Ode45 => simulator.output(&forces, initial, &mut out)?,
        _ => simulator.fit_steps(&forces, initial, &mut out)?,
    };
    Ok((out, stats))
}

/// A nonlinear model's response and its exact sensitivities (see
/// [`nonlinear_sensitivities`]).
#[derive(Debug, Clone, PartialEq)]
pub struct NonlinearSensitivities {
    /// x(tᵢ) at every sample.
    pub displacement: Vec<f64>,
    /// ∂x(tᵢ)/∂θⱼ, samples × parameters, in the order of
    /// [`ModelStructure::parameter_names`](crate::nonlinear::ModelStructure::parameter_names).
    pub parameters: DMatrix<f64>,
    /// ∂x(tᵢ)/∂x(t₀) and ∂x(tᵢ)/∂x'(t₀), samples × 2.
    pub initial_state: DMatrix<f64>,
    /// RK4's sub-steps per sample interval.
    pub steps_per_sample: usize,
}

/// The response of the nonlinear model `parameters` to `excitation` from `initial` and
/// its sensitivities to the parameters and the initial state: the forward sensitivity
/// equations of the damping and stiffness laws (the smoothed Coulomb law is
/// differentiable) integrated beside the state by RK4 on the hold polynomial of
/// `options.hold`, with the sub-steps [`simulate_nonlinear`] takes. Whatever
/// `options.solver`, this is the exact derivative of the RK4 output, the Jacobian the
/// estimator uses. v_s is the Coulomb smoothing velocity (ignored without a Coulomb law).
///
/// ```
/// use msd_ident::{Excitation, InitialState, nonlinear::{DampingLaw, ModelStructure, nonlinear_sensitivities, NonlinearParameters, NonlinearSimulation, StiffnessLaw}};
/// use msd_signal::paper_identification_input;
/// let duffing = ModelStructure { damping: DampingLaw::Viscous, stiffness: StiffnessLaw::Cubic };
/// let p = NonlinearParameters::new(duffing, vec![2.5, 1.8, 120.0, 3000.0])?;
/// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 2001)?;
/// let s = nonlinear_sensitivities(&p, &input, InitialState::REST, &NonlinearSimulation::default(), 1.0)?;
/// assert_eq!(s.parameters.shape(), (2001, 4));
/// // A stiffer spring moves less: at the peak displacement, ∂x/∂k₃ < 0.
/// let peak = (0..2001).max_by(|&a, &b| s.displacement[a].total_cmp(&s.displacement[b])).unwrap();
/// assert!(s.parameters[(peak, 3)] < 0.0);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn nonlinear_sensitivities(
    parameters: &NonlinearParameters,
    excitation: &Excitation,
    initial: InitialState,
    options: &NonlinearSimulation,
    smoothing_velocity: f64,
) -> Result<NonlinearSensitivities> {
    let forces = checked_forces(parameters, options, smoothing_velocity)?;
    let n = excitation.len();
    let mut displacement = vec![0.0; n];
    let rk4 = NonlinearSimulation {
        solver: NonlinearSolver::Rk4,
        ..*options
    };
    let mut simulator = Simulator::new(excitation, &rk4)?;
    simulator.fit_steps(&forces, initial, &mut displacement)?;
    let rk4 = &simulator.rk4;
    let np = parameters.values.len();
    let columns = Columns::new(&forces, &vec![1.0; np], Some([1.0, 1.0]));
    let mut all = DMatrix::<f64>::zeros(n, np + 2);
    rk4.sensitivities(
        &forces,
        initial,
        &columns,
        &mut displacement,
        all.as_mut_slice(),
    );
    check_finite(all.as_slice())?;
    Ok(NonlinearSensitivities {
        displacement,
        parameters: all.columns(0, np).into_owned(),
        initial_state: all.columns(np, 2).into_owned(),
        steps_per_sample: rk4.steps(),
    })
}

/// How an estimate's model was simulated.
///
/// Displays e.g. `RK4 on the cubic hold, 8 sub-steps a sample, error ≈ 1.20e-7` or
/// `ode45, Jacobian by RK4 on the cubic hold with 1 sub-step a sample`.
///
/// ```
/// use msd_ident::{nonlinear::{NonlinearSolver, SimulationUsed}};
/// use msd_ode::Hold;
/// let used = SimulationUsed { solver: NonlinearSolver::Rk4, hold: Hold::Cubic,
///     steps_per_sample: 8, error_estimate: Some(1.2e-7) };
/// assert_eq!(used.to_string(), "RK4 on the cubic hold, 8 sub-steps a sample, error ≈ 1.20e-7");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SimulationUsed {
    /// The solver that ran (what `Auto` resolved to).
    pub solver: NonlinearSolver,
    /// The hold of the RK4 simulation, and of the sensitivities under either solver
    /// (under ode45 on measured data the first-order hold, as ode45 interpolates).
    #[serde(with = "crate::simulate::hold_serde")]
    pub hold: Hold,
    /// RK4's sub-steps per sample interval (of the sensitivities under ode45).
    pub steps_per_sample: usize,
    /// Under RK4, the output's largest error over the record by step doubling,
    /// 16/15·max|ŷ(M) − ŷ(2M)| (RK4's error falls 16-fold when the sub-steps double);
    /// `None` under ode45.
    pub error_estimate: Option<f64>,
}

impl std::fmt::Display for SimulationUsed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let hold = crate::simulate::hold_serde::name(self.hold);
        let steps = self.steps_per_sample;
        let plural = if steps == 1 { "" } else { "s" };
        match (self.solver, self.error_estimate) {
            (NonlinearSolver::Ode45, _) => write!(
                f,
                "ode45, Jacobian by RK4 on the {hold} hold with {steps} sub-step{plural} a sample"
            ),
            (_, error) => {
                write!(
                    f,
                    "RK4 on the {hold} hold, {steps} sub-step{plural} a sample"
                )?;
                match error {
                    Some(e) => write!(f, ", error ≈ {e:.2e}"),
                    None => Ok(()),
                }
            }
        }
    }
}

/// The forces of `parameters` once they, the options and v_s (needed with F_c ≠ 0)
/// are checked.
pub(crate) fn checked_forces(
    parameters: &NonlinearParameters,
    options: &NonlinearSimulation,
    smoothing_velocity: f64,
) -> Result<Forces> {
    parameters.validate()?;
    options.validate()?;
    if parameters.coulomb_force() != 0.0
        && !(smoothing_velocity.is_finite() && smoothing_velocity > 0.0)
    {
        return Err(IdentError::InvalidParameter {
            name: "smoothing_velocity",
            value: smoothing_velocity,
            expected: "a finite number > 0",
        });
    }
    Ok(Forces::new(parameters, smoothing_velocity))
}

/// A nonlinear model's simulator for one excitation: set up once (the hold
/// polynomials), run for many parameter vectors without allocating.
#[derive(Debug, Clone)]
pub(crate) struct Simulator<'e> {
    excitation: &'e Excitation,
    options: NonlinearSimulation,
    /// The solver that runs (never `Auto`).
    pub solver: NonlinearSolver,
    /// RK4 on the hold: the simulation (solver RK4) and the sensitivities (either).
    pub rk4: HoldRk4,
}

impl<'e> Simulator<'e> {
    pub fn new(excitation: &'e Excitation, options: &NonlinearSimulation) -> Result<Self> {
        options.validate()?;
        let solver = options.solver_for(excitation);
        Ok(Self {
            excitation,
            options: *options,
            solver,
            rk4: HoldRk4::new(
                excitation,
                sensitivity_hold(solver, excitation, options.hold),
            )?,
        })
    }

    /// The hold of the RK4 simulation and sensitivities.
    pub fn hold(&self) -> Hold {
        sensitivity_hold(self.solver, self.excitation, self.options.hold)
    }

    /// Sets RK4's sub-steps to what `forces` need along their trajectory from
    /// `initial`, simulating into `out`: first by the eigenvalue bound at rest (the
    /// linear part, and the Coulomb term's steepest slope), then again, at most three
    /// times, while the trajectory met a larger bound (a stiffening spring at large
    /// amplitude). Returns the statistics of the passes, the redone ones as rejected.
    pub fn fit_steps(
        &mut self,
        forces: &Forces,
        initial: InitialState,
        out: &mut [f64],
    ) -> Result<Stats> {
        let intervals = out.len().saturating_sub(1);
        let mut steps = self.rk4.steps_for(forces.rate(0.0, 0.0))?;
        let mut stats = Stats::default();
        for pass in 0.. {
            self.rk4.set_steps(steps);
            let rate = self.rk4.simulate(forces, initial, out);
            check_finite(out)?;
            stats.rhs_evaluations += 4 * steps * intervals;
            let needed = self.rk4.steps_for(rate)?;
            if needed <= steps || pass == 3 {
                break;
            }
            stats.rejected_steps += steps * intervals;
            steps = needed;
        }
        stats.accepted_steps = steps * intervals;
        Ok(stats)
    }

    /// The displacement into `out` by the solver (RK4 with its current sub-steps).
    pub fn output(&self, forces: &Forces, initial: InitialState, out: &mut [f64]) -> Result<Stats> {
        debug_assert_eq!(out.len(), self.excitation.len());
        let stats = match self.solver {
            NonlinearSolver::Ode45 => self.ode45(forces, initial, out)?,
            _ => {
                self.rk4.simulate(forces, initial, out);
                let steps = self.rk4.steps() * out.len().saturating_sub(1);
                Stats {
                    rhs_evaluations: 4 * steps,
                    accepted_steps: steps,
                    rejected_steps: 0,
                }
            }
        };
        check_finite(out)?;
        Ok(stats)
    }

    fn ode45(&self, forces: &Forces, initial: InitialState, out: &mut [f64]) -> Result<Stats> {
        let excitation = self.excitation;
        let mut rhs = |t: f64, y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| {
            d[0] = y[1];
            d[1] = forces.acceleration(excitation.value(t), y[0], y[1]);
        };
        let y0 = SVector::<f64, 2>::new(initial.displacement, initial.velocity);
        let mut i = 0;
        let stats = ode45_with(
            &mut rhs,
            excitation.times(),
            &y0,
            &self.options.ode45_options(),
            |_, y| {
                out[i] = y[0];
                i += 1;
            },
        )?;
        Ok(stats)
    }
}

/// The hold RK4 follows: the options' — but under ode45 on a force known only by its
/// samples the first-order hold, the linear interpolation ode45 itself sees
/// ([`Excitation::value`]), so that the Jacobian differentiates the model simulated.
fn sensitivity_hold(solver: NonlinearSolver, excitation: &Excitation, hold: Hold) -> Hold {
    if solver == NonlinearSolver::Ode45 && excitation.signal().is_none() {
        Hold::First
    } else {
        hold
    }
}

/// A simulated output that diverged names its first non-finite sample.
fn check_finite(out: &[f64]) -> Result<()> {
    match out.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(IdentError::NonFiniteSample {
            field: "simulated output",
            index,
            value: out[index],
        }),
        None => Ok(()),
    }
}
