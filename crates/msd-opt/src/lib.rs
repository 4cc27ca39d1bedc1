//! Optimisation for parameter identification, knowing nothing of the problems it
//! solves:
//!
//! - [`nelder_mead`](crate::nelder_mead()): the Nelder–Mead simplex search of MATLAB's `fminsearch`, step
//!   for step (initial simplex, coefficients, order of tests, stopping rule,
//!   counts), with an optional `Display = 'iter'` trace and, off by default,
//!   relative tolerances, Gao–Han adaptive coefficients and bounds.
//! - [`levenberg_marquardt`](crate::levenberg_marquardt()): MINPACK's `lmder` (Moré's trust-region
//!   Levenberg–Marquardt with QR and Givens rotations) plus box bounds and finite
//!   differences; the result carries the Jacobian at the solution.
//! - [`lbfgs`](crate::lbfgs()): limited-memory BFGS with Armijo backtracking, for smooth
//!   problems with a gradient (excitation design).
//! - [`multistart`](crate::multistart()): seeded Latin-hypercube or Halton starting points, refined by
//!   either method on a local rayon pool, ranked; identical for any thread count.
//!
//! Bad input is an [`OptError`]; a run that stops early is a result with an exit
//! reason.
//!
//! ```
//! use msd_opt::{
//!     levenberg_marquardt, nelder_mead, LevenbergMarquardtOptions, NelderMeadExit,
//!     NelderMeadOptions, ResidualFn,
//! };
//!
//! // Rosenbrock's function from the classical start, with fminsearch's defaults:
//! // 85 iterations and 159 evaluations, as MATLAB reports.
//! let cost = |x: &[f64]| 100.0 * (x[1] - x[0] * x[0]).powi(2) + (1.0 - x[0]).powi(2);
//! let r = nelder_mead(cost, &[-1.2, 1.0], &NelderMeadOptions::default()).unwrap();
//! assert_eq!(r.exit, NelderMeadExit::Converged);
//! assert_eq!((r.iterations, r.evaluations), (85, 159));
//!
//! // The same function as least squares, r = (10(x2 − x1²), 1 − x1).
//! let mut ls = ResidualFn::new(2, |x: &[f64], r: &mut [f64]| {
//!     r[0] = 10.0 * (x[1] - x[0] * x[0]);
//!     r[1] = 1.0 - x[0];
//!     true
//! });
//! let fit = levenberg_marquardt(&mut ls, &[-1.2, 1.0], &LevenbergMarquardtOptions::default())
//!     .unwrap();
//! assert!(fit.exit.is_success() && fit.cost < 1e-20);
//! ```

pub mod bounds;
pub mod error;
pub mod lbfgs;
pub mod levenberg_marquardt;
pub mod multistart;
pub mod nelder_mead;
pub mod statistics;

pub use bounds::Bounds;
pub use error::{OptError, ThreadPoolError};
pub use lbfgs::{LbfgsExit, LbfgsOptions, LbfgsResult, lbfgs};
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
pub use statistics::Interval;
