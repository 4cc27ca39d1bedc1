//! Response of a nonlinear model by msd-ode's ode45 (Dormand–Prince 5(4)).

use super::model::{Forces, NonlinearParameters};
use crate::{Backend, Excitation, IdentError, InitialState, Result, simulate};
use msd_ode::{Ode45Options, SVector, Stats, ode45_with};
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

/// How nonlinear models are simulated.
///
/// | field | default | why |
/// |---|---|---|
/// | `rel_tol` | 1e-8 | tighter than the paper's 1e-6 so that central finite differences with a 1e-4 step are not swamped by the solver's error |
/// | `abs_tol` | 1e-12 | idem, far below any noise level in metres or volts |
/// | `smoothing_velocity` | `Relative(1e-3)` | see [`SmoothingVelocity`] |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NonlinearSimulation {
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
/// `initial`, by ode45 with the force evaluated continuously ([`Excitation::value`]),
/// and v_s the Coulomb smoothing velocity (ignored without a Coulomb term). Returns the
/// displacement at the sample times and the solver statistics.
///
/// ```
/// use msd_ident::{simulate, simulate_nonlinear, Backend, Excitation, InitialState,
///     ModelStructure, NonlinearParameters, NonlinearSimulation, Parameters};
/// use msd_signal::paper_identification_input;
/// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 2001)?;
/// // The linear member of the family agrees with the exact linear simulation.
/// let p = NonlinearParameters::from_linear(ModelStructure::LINEAR, &Parameters::PAPER);
/// let (x, _stats) = simulate_nonlinear(&p, &input, InitialState::REST, &NonlinearSimulation::default(), 1e-3)?;
/// let exact = simulate(&Parameters::PAPER, &input, InitialState::REST, &Backend::EXACT)?;
/// let worst = x.iter().zip(&exact).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
/// assert!(worst < 1e-7);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn simulate_nonlinear(
    parameters: &NonlinearParameters,
    excitation: &Excitation,
    initial: InitialState,
    options: &NonlinearSimulation,
    smoothing_velocity: f64,
) -> Result<(Vec<f64>, Stats)> {
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
    let forces = Forces::new(parameters, smoothing_velocity);
    let mut out = vec![0.0; excitation.len()];
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
        &options.ode45_options(),
        |_, y| {
            out[i] = y[0];
            i += 1;
        },
    )?;
    if let Some(index) = out.iter().position(|v| !v.is_finite()) {
        return Err(IdentError::NonFiniteSample {
            field: "simulated output",
            index,
            value: out[index],
        });
    }
    Ok((out, stats))
}
