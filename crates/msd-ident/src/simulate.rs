//! Response of the model to a known excitation, by either backend.

use crate::{
    data::Excitation,
    error::{IdentError, Result},
    params::{InitialState, Parameters},
};
use msd_ode::{ExactSimulator, Hold, Ode45Options, SVector, SampledInput, Stats, ode45_with};
use serde::{Deserialize, Serialize};

/// How the model is simulated.
///
/// By default [`Backend::Exact`] with a cubic hold.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Backend {
    /// msd-ode's Dormand–Prince 5(4) with ode45 semantics, the force evaluated as a
    /// continuous function of time: the paper's way.
    Ode45 {
        /// Relative tolerance (the paper: 1e-6).
        rel_tol: f64,
        /// Absolute tolerance (the paper: 1e-9).
        abs_tol: f64,
    },
    /// Exact simulation of the linear model on the sampled force with its jumps: the
    /// fast way.
    Exact {
        /// Reconstruction of the force between samples.
        #[serde(default = "default_hold", with = "hold_serde")]
        hold: Hold,
    },
}

fn default_hold() -> Hold {
    Hold::Cubic
}

impl Default for Backend {
    fn default() -> Self {
        Backend::Exact { hold: Hold::Cubic }
    }
}

impl std::fmt::Display for Backend {
    /// The name with its settings, e.g. "ode45 (RelTol 1e-6, AbsTol 1e-9)" or
    /// "exact (cubic hold)".
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Backend::Ode45 { rel_tol, abs_tol } => {
                write!(f, "ode45 (RelTol {rel_tol:e}, AbsTol {abs_tol:e})")
            }
            Backend::Exact { hold } => write!(f, "exact ({} hold)", hold_serde::name(*hold)),
        }
    }
}

impl Backend {
    /// The paper's solver: ode45 with RelTol 1e-6, AbsTol 1e-9.
    pub const PAPER: Backend = Backend::Ode45 {
        rel_tol: 1e-6,
        abs_tol: 1e-9,
    };

    /// Exact simulation with the cubic hold.
    pub const EXACT: Backend = Backend::Exact { hold: Hold::Cubic };

    /// A short name for reports: "ode45" or "exact".
    pub fn name(&self) -> &'static str {
        match self {
            Backend::Ode45 { .. } => "ode45",
            Backend::Exact { .. } => "exact",
        }
    }

    /// Checks the tolerances.
    pub fn validate(&self) -> Result<()> {
        if let Some(options) = self.ode45_options() {
            options.validate()?;
        }
        Ok(())
    }

    /// The options [`simulate`]'s ode45 backend runs msd-ode's solver with: the
    /// tolerances, the rest msd-ode's defaults (as MATLAB's). `None` for the exact backend.
    ///
    /// ```
    /// use msd_ident::Backend;
    /// let options = Backend::PAPER.ode45_options().unwrap();
    /// assert_eq!((options.rel_tol, options.abs_tol), (1e-6, 1e-9));
    /// assert!(Backend::EXACT.ode45_options().is_none());
    /// ```
    pub fn ode45_options(&self) -> Option<Ode45Options> {
        match *self {
            Backend::Ode45 { rel_tol, abs_tol } => Some(ode45_options(rel_tol, abs_tol)),
            Backend::Exact { .. } => None,
        }
    }
}

fn ode45_options(rel_tol: f64, abs_tol: f64) -> Ode45Options {
    Ode45Options {
        rel_tol,
        abs_tol,
        ..Ode45Options::default()
    }
}

pub(crate) mod hold_serde {
    use msd_ode::Hold;
    use serde::{Deserialize, Deserializer, Serializer};

    /// The hold's name in configs and reports.
    pub(crate) fn name(hold: Hold) -> &'static str {
        match hold {
            Hold::Zero => "zero",
            Hold::First => "first",
            Hold::Cubic => "cubic",
        }
    }

    pub(crate) fn serialize<S: Serializer>(hold: &Hold, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(name(*hold))
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Hold, D::Error> {
        let name = String::deserialize(d)?;
        match name.as_str() {
            "zero" => Ok(Hold::Zero),
            "first" => Ok(Hold::First),
            "cubic" => Ok(Hold::Cubic),
            other => Err(serde::de::Error::custom(format!(
                "unknown hold `{other}`: expected one of zero, first, cubic"
            ))),
        }
    }
}

/// Displacement response of the model to `excitation` from `initial`.
///
/// ```
/// use msd_ident::{simulate, Backend, Excitation, InitialState, Parameters};
/// use msd_signal::paper_identification_input;
/// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
/// let fast = simulate(&Parameters::PAPER, &input, InitialState::REST, &Backend::EXACT)?;
/// let paper = simulate(&Parameters::PAPER, &input, InitialState::REST, &Backend::PAPER)?;
/// let worst = fast.iter().zip(&paper).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
/// assert!(worst < 1e-6); // both backends agree to within the ODE tolerance
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn simulate(
    parameters: &Parameters,
    excitation: &Excitation,
    initial: InitialState,
    backend: &Backend,
) -> Result<Vec<f64>> {
    let mut out = vec![0.0; excitation.len()];
    simulate_into(parameters, excitation, initial, backend, &mut out)?;
    Ok(out)
}

/// As [`simulate`], into `out` (one value per excitation sample). Returns the ODE
/// solver's statistics for the ode45 backend.
pub fn simulate_into(
    parameters: &Parameters,
    excitation: &Excitation,
    initial: InitialState,
    backend: &Backend,
    out: &mut [f64],
) -> Result<Option<Stats>> {
    parameters.validate()?;
    if out.len() != excitation.len() {
        return Err(IdentError::LengthMismatch {
            what: "simulation output buffer",
            expected: excitation.len(),
            got: out.len(),
        });
    }
    let x0 = initial.vector();
    match *backend {
        Backend::Exact { hold } => {
            let sim = ExactSimulator::new(&parameters.state_space(), excitation.dt(), hold)?;
            let input = SampledInput {
                values: excitation.samples(),
                breakpoints: excitation.breakpoints(),
            };
            sim.simulate_with(&x0, &input, |i, x| out[i] = x[0])?;
            Ok(None)
        }
        Backend::Ode45 { rel_tol, abs_tol } => {
            let options = ode45_options(rel_tol, abs_tol);
            let mut rhs = ode45_rhs(parameters, excitation);
            let mut i = 0;
            let stats = ode45_with(&mut rhs, excitation.times(), &x0, &options, |_, y| {
                out[i] = y[0];
                i += 1;
            })?;
            debug_assert_eq!(i, out.len());
            Ok(Some(stats))
        }
    }
}

/// The model's right-hand side for ode45, the force evaluated as a continuous function
/// of time (one definition, so that every ode45 path gives the same bits).
pub(crate) fn ode45_rhs<'e>(
    parameters: &Parameters,
    excitation: &'e Excitation,
) -> impl FnMut(f64, &SVector<f64, 2>, &mut SVector<f64, 2>) + 'e {
    let (m, c, k) = (parameters.mass, parameters.damping, parameters.stiffness);
    move |t, y, d| {
        d[0] = y[1];
        d[1] = (excitation.value(t) - c * y[1] - k * y[0]) / m;
    }
}
