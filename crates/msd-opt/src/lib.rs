//! Optimisation for parameter identification: a Nelder–Mead simplex search that
//! reproduces MATLAB's `fminsearch`, a bounded Levenberg–Marquardt least-squares
//! solver after MINPACK's `lmder`, and a seeded multistart driver for either.
//!
//! The crate knows nothing of the problems it solves: a cost is a closure
//! `FnMut(&[f64]) -> f64`, a least-squares problem implements
//! [`LeastSquaresProblem`].
//!
//! ```
//! use msd_opt::{nelder_mead, NelderMeadExit, NelderMeadOptions};
//!
//! // Rosenbrock's function from the classical start, with fminsearch's defaults.
//! let cost = |x: &[f64]| 100.0 * (x[1] - x[0] * x[0]).powi(2) + (1.0 - x[0]).powi(2);
//! let r = nelder_mead(cost, &[-1.2, 1.0], &NelderMeadOptions::default()).unwrap();
//! assert_eq!(r.exit, NelderMeadExit::Converged);
//! assert!(r.cost < 1e-8);
//! ```

pub mod bounds;
pub mod error;
pub mod levenberg_marquardt;
pub mod multistart;
pub mod nelder_mead;

pub use bounds::Bounds;
pub use error::OptError;
pub use levenberg_marquardt::{
    FiniteDifference, LeastSquaresProblem, LevenbergMarquardtOptions, LevenbergMarquardtResult,
    LmExit, ResidualFn, levenberg_marquardt,
};
pub use multistart::{
    MultistartOptions, RankedCost, Sampling, StartResult, multistart, starting_points,
};
pub use nelder_mead::{
    NelderMeadExit, NelderMeadOptions, NelderMeadResult, Step, TRACE_HEADER, TraceRow, nelder_mead,
};
