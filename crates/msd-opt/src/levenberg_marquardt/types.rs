//! The problem trait, options, exit reasons and result of Levenberg–Marquardt.

use std::fmt;

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use crate::error::{check_count, check_non_negative, check_positive};
use crate::{bounds::Bounds, error::OptError};

/// A nonlinear least-squares problem: residuals r(x) ∈ ℝᵐ and optionally their
/// Jacobian.
pub trait LeastSquaresProblem {
    /// Number of residuals m (fixed for the problem, at least the number of
    /// parameters).
    fn residual_count(&self) -> usize;

    /// Writes the residuals at `x` into `out` (length m). Return false if they
    /// could not be computed; false or a non-finite value is treated as a failed
    /// step (the trust region shrinks, the point is never accepted).
    fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> bool;

    /// Writes the m×n Jacobian ∂r_i/∂x_j at `x` into `out`. Called only right after
    /// `residuals(x)` at the same x (see the module doc). Return false if not
    /// supplied: the solver then uses finite differences. The default returns false.
    fn jacobian(&mut self, x: &[f64], out: &mut DMatrix<f64>) -> bool {
        let _ = (x, out);
        false
    }
}

/// A [`LeastSquaresProblem`] from a residual closure (Jacobian by finite
/// differences).
#[derive(Debug, Clone)]
pub struct ResidualFn<F> {
    m: usize,
    f: F,
}

impl<F: FnMut(&[f64], &mut [f64]) -> bool> ResidualFn<F> {
    /// Wraps `f(x, out) -> ok` producing `m` residuals.
    pub fn new(m: usize, f: F) -> Self {
        Self { m, f }
    }
}

impl<F: FnMut(&[f64], &mut [f64]) -> bool> LeastSquaresProblem for ResidualFn<F> {
    fn residual_count(&self) -> usize {
        self.m
    }

    fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> bool {
        (self.f)(x, out)
    }
}

/// Finite-difference scheme for a Jacobian the problem does not supply.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum FiniteDifference {
    /// `(r(x + h·e_j) − r(x))/h`, one evaluation per parameter (MINPACK `fdjac2`).
    #[default]
    Forward,
    /// `(r(x + h·e_j) − r(x − h·e_j))/(2h)`, two evaluations per parameter.
    Central,
}

/// Options of [`levenberg_marquardt`](crate::levenberg_marquardt::levenberg_marquardt()); defaults follow MINPACK (`lmder1`,
/// as SciPy's `leastsq`).
///
/// | field | default | source |
/// |---|---|---|
/// | `f_tolerance` | √ε ≈ 1.49e-8 | ftol, MINPACK `lmder1`/`leastsq` |
/// | `x_tolerance` | √ε ≈ 1.49e-8 | xtol, idem |
/// | `g_tolerance` | 0 | gtol, idem |
/// | `max_evaluations` | `None` = 100·(n + 1) | maxfev of `lmder1` |
/// | `initial_step_bound` | 100 | factor, MINPACK's recommended value |
/// | `diagonal` | `None` (mode 1: Jacobian column norms) | mode, MINPACK |
/// | `bounds` | `None` | unconstrained, as MINPACK |
/// | `finite_difference` | forward | `fdjac2` |
/// | `finite_difference_step` | `None`: √ε forward, ε^⅓ central | `fdjac2` with epsfcn = ε |
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LevenbergMarquardtOptions {
    /// Stop when both actual and predicted relative reductions of ‖r‖² are at most
    /// this. By default √ε.
    pub f_tolerance: f64,
    /// Stop when the trust radius is at most this times ‖D·x‖ (relative step).
    /// By default √ε.
    pub x_tolerance: f64,
    /// Stop when the largest cosine between r and a column of J is at most this.
    /// By default 0.
    pub g_tolerance: f64,
    /// Residual evaluations allowed (not counting finite differences); `None` means
    /// 100·(n + 1). By default `None`.
    pub max_evaluations: Option<usize>,
    /// Initial trust radius as a multiple of ‖D·x0‖ (or itself if that is zero).
    /// By default 100.
    pub initial_step_bound: f64,
    /// Fixed positive scaling D (MINPACK mode 2); `None` scales by the Jacobian's
    /// column norms (mode 1). By default `None`.
    pub diagonal: Option<Vec<f64>>,
    /// Box bounds (see the module doc). By default `None`.
    pub bounds: Option<Bounds>,
    /// Scheme for Jacobians the problem does not supply. By default forward.
    pub finite_difference: FiniteDifference,
    /// Relative finite-difference step: `h_j = step·|x_j|`, or `step` where
    /// `x_j = 0`. `None` means √ε (forward) or ε^⅓ (central). By default `None`.
    pub finite_difference_step: Option<f64>,
}

impl Default for LevenbergMarquardtOptions {
    /// MINPACK-like: ftol = xtol = √ε, gtol = 0, maxfev = 100·(n + 1), factor = 100, mode 1.
    fn default() -> Self {
        Self {
            f_tolerance: f64::EPSILON.sqrt(),
            x_tolerance: f64::EPSILON.sqrt(),
            g_tolerance: 0.0,
            max_evaluations: None,
            initial_step_bound: 100.0,
            diagonal: None,
            bounds: None,
            finite_difference: FiniteDifference::Forward,
            finite_difference_step: None,
        }
    }
}

impl LevenbergMarquardtOptions {
    /// Checks every option's range: tolerances finite and ≥ 0, step bound and
    /// finite-difference step finite and > 0, evaluation limit ≥ 1, diagonal
    /// entries finite and > 0, bounds well formed.
    ///
    /// # Errors
    /// [`OptError::InvalidOption`] naming the field, or a bounds error.
    ///
    /// ```
    /// use msd_opt::{LevenbergMarquardtOptions, OptError};
    /// let bad = LevenbergMarquardtOptions { f_tolerance: -1.0, ..Default::default() };
    /// assert!(matches!(bad.validate(), Err(OptError::InvalidOption { name: "f_tolerance", .. })));
    /// ```
    pub fn validate(&self) -> Result<(), OptError> {
        check_non_negative("f_tolerance", self.f_tolerance)?;
        check_non_negative("x_tolerance", self.x_tolerance)?;
        check_non_negative("g_tolerance", self.g_tolerance)?;
        check_count("max_evaluations", self.max_evaluations)?;
        check_positive("initial_step_bound", self.initial_step_bound)?;
        if let Some(h) = self.finite_difference_step {
            check_positive("finite_difference_step", h)?;
        }
        if let Some(d) = &self.diagonal {
            for &v in d {
                check_positive("diagonal", v)?;
            }
        }
        if let Some(b) = &self.bounds {
            b.validate()?;
        }
        Ok(())
    }
}

/// Why [`levenberg_marquardt`](crate::levenberg_marquardt::levenberg_marquardt()) stopped (MINPACK's `info` 1–8, plus one of ours).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum LmExit {
    /// info 1: actual and predicted relative reductions at most `f_tolerance`.
    FTolerance,
    /// info 2: relative change of x at most `x_tolerance`.
    XTolerance,
    /// info 3: both of the above.
    FAndXTolerance,
    /// info 4: r is orthogonal to the columns of J within `g_tolerance` (includes r = 0).
    Gradient,
    /// info 5: `max_evaluations` reached.
    MaxEvaluations,
    /// info 6: `f_tolerance` too small, no further reduction possible.
    FToleranceTooSmall,
    /// info 7: `x_tolerance` too small, no further improvement of x possible.
    XToleranceTooSmall,
    /// info 8: `g_tolerance` too small, r orthogonal to J to machine precision.
    GToleranceTooSmall,
    /// The Jacobian at the current point has a non-finite entry.
    NonFiniteJacobian,
}

impl LmExit {
    /// True for the convergence reasons (MINPACK info 1–4).
    pub fn is_success(&self) -> bool {
        matches!(
            self,
            Self::FTolerance | Self::XTolerance | Self::FAndXTolerance | Self::Gradient
        )
    }
}

impl fmt::Display for LmExit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::FTolerance => {
                "both actual and predicted relative reductions in the sum of squares are at most f_tolerance"
            }
            Self::XTolerance => "relative error between two consecutive iterates is at most x_tolerance",
            Self::FAndXTolerance => {
                "relative reduction at most f_tolerance and relative step at most x_tolerance"
            }
            Self::Gradient => {
                "the residuals are orthogonal to the Jacobian columns to within g_tolerance"
            }
            Self::MaxEvaluations => "number of residual evaluations has reached max_evaluations",
            Self::FToleranceTooSmall => {
                "f_tolerance is too small: no further reduction in the sum of squares is possible"
            }
            Self::XToleranceTooSmall => {
                "x_tolerance is too small: no further improvement in x is possible"
            }
            Self::GToleranceTooSmall => {
                "g_tolerance is too small: residuals orthogonal to the Jacobian to machine precision"
            }
            Self::NonFiniteJacobian => "the Jacobian has a non-finite entry",
        })
    }
}

/// What [`levenberg_marquardt`](crate::levenberg_marquardt::levenberg_marquardt()) found.
#[derive(Debug, Clone, PartialEq)]
pub struct LevenbergMarquardtResult {
    /// Final parameters (inside the bounds).
    pub x: Vec<f64>,
    /// Residuals at `x`.
    pub residuals: Vec<f64>,
    /// ‖r(x)‖₂.
    pub residual_norm: f64,
    /// Sum of squares ‖r(x)‖² (not halved), comparable with a Nelder–Mead cost
    /// written as Σ rᵢ². +∞ when ‖r‖ exceeds √f64::MAX ≈ 1.34e154 (a start far from any
    /// fit); `residual_norm` is always finite.
    pub cost: f64,
    /// Jacobian at `x` (m×n), e.g. for the covariance `s²·(JᵀJ)⁻¹`.
    pub jacobian: DMatrix<f64>,
    /// Accepted steps.
    pub iterations: usize,
    /// Residual evaluations by the solver (MINPACK `nfev`), excluding finite differences.
    pub evaluations: usize,
    /// Jacobian evaluations (analytic or by finite differences, MINPACK `njev`).
    pub jacobian_evaluations: usize,
    /// Residual evaluations spent on finite differences.
    pub finite_difference_evaluations: usize,
    /// Why the solver stopped.
    pub exit: LmExit,
}

impl fmt::Display for LevenbergMarquardtResult {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let xs: Vec<String> = self.x.iter().map(|v| format!("{v:.10e}")).collect();
        writeln!(f, "Levenberg–Marquardt (MINPACK lmder)")?;
        writeln!(f, "x = [{}]", xs.join(", "))?;
        writeln!(f, "residual norm = {:.10e}", self.residual_norm)?;
        writeln!(f, "sum of squares = {:.10e}", self.cost)?;
        writeln!(
            f,
            "iterations: {}, evaluations: {}, jacobian evaluations: {}, finite-difference evaluations: {}",
            self.iterations,
            self.evaluations,
            self.jacobian_evaluations,
            self.finite_difference_evaluations
        )?;
        write!(f, "exit: {}", self.exit)
    }
}
