//! Options and statistics of the Dormand–Prince solver.

use crate::error::OdeError;

/// Options of [`ode45`](crate::dopri::ode45), named and defaulted as MATLAB's `odeset`.
///
/// Plain public fields; call [`validate`](Ode45Options::validate) (the solver does) to
/// check them.
///
/// ```
/// use msd_ode::Ode45Options;
/// let paper = Ode45Options { rel_tol: 1e-6, abs_tol: 1e-9, ..Ode45Options::default() };
/// assert!(paper.validate().is_ok());
/// assert_eq!(Ode45Options::default().rel_tol, 1e-3);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ode45Options {
    /// Relative tolerance. By default 1e-3, as MATLAB's `ode45`. Must be at least
    /// 100·eps ≈ 2.2e-14 (MATLAB raises smaller values to that with a warning; we refuse
    /// them with an error instead of silently changing the request).
    pub rel_tol: f64,
    /// Absolute tolerance (all components). By default 1e-6, as MATLAB's `ode45`.
    pub abs_tol: f64,
    /// Largest step size. By default `None`: 0.1·|tf − t0|, as MATLAB's `MaxStep`.
    pub max_step: Option<f64>,
    /// First step to try. By default `None`: MATLAB's rule from the initial slope,
    /// h = min(hmax, |tf − t0|), reduced to 1/rh where
    /// rh = ‖f(t0, y0) ./ max(|y0|, AbsTol/RelTol)‖∞ / (0.8·RelTol^(1/5)).
    pub initial_step: Option<f64>,
    /// Dense output points per step when the time span has only two entries (MATLAB's
    /// `Refine`). By default 4, as MATLAB's `ode45`.
    pub refine: usize,
    /// Safety net on the number of accepted steps (MATLAB has none). By default
    /// 10 000 000.
    pub max_steps: usize,
}

impl Default for Ode45Options {
    fn default() -> Self {
        Self {
            rel_tol: 1e-3,
            abs_tol: 1e-6,
            max_step: None,
            initial_step: None,
            refine: 4,
            max_steps: 10_000_000,
        }
    }
}

impl Ode45Options {
    /// Smallest relative tolerance accepted: 100·eps, as MATLAB's `ode45`.
    pub const MIN_REL_TOL: f64 = 100.0 * f64::EPSILON;

    /// Checks every option, naming the first one out of range.
    ///
    /// ```
    /// use msd_ode::{Ode45Options, OdeError};
    /// let bad = Ode45Options { max_step: Some(0.0), ..Ode45Options::default() };
    /// assert!(matches!(bad.validate(), Err(OdeError::InvalidOption { name: "max_step", .. })));
    /// ```
    pub fn validate(&self) -> Result<(), OdeError> {
        let positive = "a finite number > 0";
        if !(self.rel_tol.is_finite() && self.rel_tol >= Self::MIN_REL_TOL) {
            return Err(OdeError::InvalidOption {
                name: "rel_tol",
                value: self.rel_tol,
                expected: "a finite number >= 100·eps (2.22e-14)",
            });
        }
        if !(self.abs_tol.is_finite() && self.abs_tol > 0.0) {
            return Err(OdeError::InvalidOption {
                name: "abs_tol",
                value: self.abs_tol,
                expected: positive,
            });
        }
        for (name, value) in [
            ("max_step", self.max_step),
            ("initial_step", self.initial_step),
        ] {
            if let Some(v) = value
                && !(v.is_finite() && v > 0.0)
            {
                return Err(OdeError::InvalidOption {
                    name,
                    value: v,
                    expected: positive,
                });
            }
        }
        if self.refine == 0 {
            return Err(OdeError::InvalidOption {
                name: "refine",
                value: 0.0,
                expected: "an integer >= 1",
            });
        }
        if self.max_steps == 0 {
            return Err(OdeError::InvalidOption {
                name: "max_steps",
                value: 0.0,
                expected: "an integer >= 1",
            });
        }
        Ok(())
    }
}

/// Cost of a solution, as MATLAB's `ode45` reports it (`nsteps`, `nfailed`, `nfevals`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Stats {
    /// Right-hand-side evaluations (one initial, then six per attempted step).
    pub rhs_evaluations: usize,
    /// Accepted steps.
    pub accepted_steps: usize,
    /// Rejected steps (failed error tests).
    pub rejected_steps: usize,
}

impl std::fmt::Display for Stats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} successful steps, {} failed attempts, {} function evaluations",
            self.accepted_steps, self.rejected_steps, self.rhs_evaluations
        )
    }
}
