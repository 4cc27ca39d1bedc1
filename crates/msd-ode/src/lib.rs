//! ODE integration for mass–spring–damper identification, useful on its own.
//!
//! Two solvers:
//! - [`ode45`]: the Dormand–Prince 5(4) pair with the semantics of MATLAB's `ode45`
//!   (tableau, first-same-as-last, error test, step-size rules, defaults and `ntrp45`
//!   dense output), so results can be compared step for step with the reference tool;
//!   for any system y' = f(t, y) with a fixed-size state.
//! - [`ExactSimulator`]: exact simulation of a linear time-invariant system on a sampled
//!   input, by the matrix exponential of an augmented system that integrates a polynomial
//!   hold of the input exactly (zero-, first- or cubic-order), with jumps at sample
//!   instants represented exactly.
//!
//! For Monte Carlo work, both also run many systems of one family side by side, each
//! lane bit for bit the single solver: [`Ode45Lanes`] (ode45, each lane with its own
//! step-size control) and [`Lockstep`] (exact simulation on one input).
//!
//! ```
//! use msd_ode::{ode45, ExactSimulator, Hold, LtiModel, Ode45Options, SampledInput, SMatrix, SVector};
//!
//! // m x'' + c x' + k x = F(t), the paper's plant, driven by F = 3 sin(2π·0.5 t).
//! let (m, c, k) = (2.5, 1.8, 120.0);
//! let force = |t: f64| 3.0 * (2.0 * std::f64::consts::PI * 0.5 * t).sin();
//! let grid: Vec<f64> = (0..=5000).map(|i| i as f64 * 0.002).collect();
//!
//! // The paper's way: ode45 at RelTol 1e-6, AbsTol 1e-9.
//! let mut rhs = |t: f64, y: &SVector<f64, 2>, dydt: &mut SVector<f64, 2>| {
//!     dydt[0] = y[1];
//!     dydt[1] = (force(t) - c * y[1] - k * y[0]) / m;
//! };
//! let options = Ode45Options { rel_tol: 1e-6, abs_tol: 1e-9, ..Ode45Options::default() };
//! let adaptive = ode45(&mut rhs, &grid, &SVector::zeros(), &options)?;
//!
//! // The fast way: exact simulation with a cubic hold of the sampled force.
//! let model = LtiModel {
//!     a: SMatrix::<f64, 2, 2>::new(0.0, 1.0, -k / m, -c / m),
//!     b: SVector::<f64, 2>::new(0.0, 1.0 / m),
//! };
//! let samples: Vec<f64> = grid.iter().map(|&t| force(t)).collect();
//! let exact = ExactSimulator::new(&model, 0.002, Hold::Cubic)?
//!     .simulate(&SVector::zeros(), &SampledInput::smooth(&samples))?;
//!
//! let worst = adaptive.y.iter().zip(&exact).map(|(a, e)| (a[0] - e[0]).abs()).fold(0.0, f64::max);
//! assert!(worst < 1e-6);
//! # Ok::<(), msd_ode::OdeError>(())
//! ```

mod dopri;
mod error;
mod lti;
mod options;
mod system;
pub mod tableau;

pub use dopri::{LaneSystem, Ode45Lanes, Ode45Stepper, Solution, TimeGrid, ode45, ode45_with};
pub use error::OdeError;
pub use lti::{
    Breakpoint, ExactSimulator, Hold, InputSchedule, Lockstep, LtiModel, RampStep, Resolvent,
    SampledInput,
};
pub use nalgebra::{Complex, SMatrix, SVector};
pub use options::{Ode45Options, Stats};
pub use system::{OdeSystem, SliceSystem};
