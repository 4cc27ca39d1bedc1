//! Limited-memory BFGS for smooth problems with a gradient (Nocedal & Wright,
//! *Numerical Optimization*, 2nd ed., Algorithm 7.4 and 7.5).
//!
//! ## The algorithm
//! * The search direction is −H·g, with H the inverse-Hessian approximation built from
//!   the last `memory` pairs (s, y) by the two-loop recursion, started from
//!   γ·I with γ = sᵀy/yᵀy of the latest pair (Nocedal & Wright eq. 7.20).
//! * The step meets the weak Wolfe conditions f(x + αd) ≤ f(x) + 10⁻⁴·α·gᵀd and
//!   g(x + αd)ᵀd ≥ 0.9·gᵀd, found by bracketing from α = 1 (Lewis & Overton 2013), so
//!   every stored pair has sᵀy > 0.
//! * A pair with sᵀy ≤ 10⁻¹²·|s|·|y| (rounding) is not stored; a direction that is not a
//!   descent direction is replaced by −g and the memory cleared.
//!
//! ```
//! use msd_opt::{LbfgsExit, LbfgsOptions, lbfgs};
//! // Rosenbrock's function and its gradient from the classical start.
//! let f = |x: &[f64], g: &mut [f64]| {
//!     g[0] = -400.0 * x[0] * (x[1] - x[0] * x[0]) - 2.0 * (1.0 - x[0]);
//!     g[1] = 200.0 * (x[1] - x[0] * x[0]);
//!     100.0 * (x[1] - x[0] * x[0]).powi(2) + (1.0 - x[0]).powi(2)
//! };
//! let r = lbfgs(f, &[-1.2, 1.0], &LbfgsOptions::default())?;
//! // Stopped by the gradient, or where f stops decreasing in floating point.
//! assert!(matches!(r.exit, LbfgsExit::Gradient | LbfgsExit::FTolerance), "{r}");
//! assert!((r.x[0] - 1.0).abs() < 1e-6 && (r.x[1] - 1.0).abs() < 1e-6, "{r}");
//! # Ok::<(), msd_opt::OptError>(())
//! ```

use std::fmt;

use crate::error::OptError;
use crate::error::{check_non_negative, check_start};

/// Options of [`lbfgs`](crate::lbfgs::lbfgs()).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LbfgsOptions {
    /// Number of (s, y) pairs kept. By default 8 (Nocedal & Wright: 3 to 20 work well).
    pub memory: usize,
    /// Largest number of iterations. By default 200.
    pub max_iterations: usize,
    /// Stop when the largest |gradient component| is at most this. By default 1e-8.
    pub gradient_tolerance: f64,
    /// Stop when an iteration lowers f by at most this relative to max(|f|, 1). By
    /// default 0: only an iteration that does not lower f at all stops it.
    pub f_tolerance: f64,
}

impl Default for LbfgsOptions {
    fn default() -> Self {
        Self {
            memory: 8,
            max_iterations: 200,
            gradient_tolerance: 1e-8,
            f_tolerance: 0.0,
        }
    }
}

/// Why [`lbfgs`](crate::lbfgs::lbfgs()) stopped. Serializes in snake case.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LbfgsExit {
    /// The gradient is within `gradient_tolerance`.
    Gradient,
    /// An iteration lowered f by at most `f_tolerance` (relative).
    FTolerance,
    /// `max_iterations` reached.
    MaxIterations,
    /// No step along the steepest descent lowered f (a kink, or f not finite nearby).
    LineSearchFailed,
}

impl fmt::Display for LbfgsExit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Gradient => "the gradient is within gradient_tolerance",
            Self::FTolerance => "an iteration lowered f by at most f_tolerance (relative)",
            Self::MaxIterations => "max_iterations reached",
            Self::LineSearchFailed => "no step along the steepest descent lowered f",
        })
    }
}

/// What [`lbfgs`](crate::lbfgs::lbfgs()) found.
#[derive(Debug, Clone, PartialEq)]
pub struct LbfgsResult {
    /// The best point.
    pub x: Vec<f64>,
    /// f there.
    pub cost: f64,
    /// Iterations done.
    pub iterations: usize,
    /// Evaluations of f and its gradient.
    pub evaluations: usize,
    /// Why it stopped.
    pub exit: LbfgsExit,
}

impl fmt::Display for LbfgsResult {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "L-BFGS: f = {:.6e} after {} iterations, {} evaluations ({})",
            self.cost, self.iterations, self.evaluations, self.exit
        )
    }
}

/// Minimises `f(x, gradient) -> value` (the closure writes the gradient at `x` into its
/// second argument) from `x0`. See the [module docs](mod@crate::lbfgs) for the algorithm.
///
/// Errors: an empty or non-finite `x0`, a `memory` of 0, a negative tolerance.
pub fn lbfgs<F: FnMut(&[f64], &mut [f64]) -> f64>(
    mut f: F,
    x0: &[f64],
    options: &LbfgsOptions,
) -> Result<LbfgsResult, OptError> {
    check_start(x0)?;
    check_non_negative("gradient_tolerance", options.gradient_tolerance)?;
    check_non_negative("f_tolerance", options.f_tolerance)?;
    if options.memory == 0 {
        return Err(OptError::InvalidOption {
            name: "memory",
            value: 0.0,
            expected: "at least 1 pair",
        });
    }
    let n = x0.len();
    let mut x = x0.to_vec();
    let mut g = vec![0.0; n];
    let mut fx = f(&x, &mut g);
    let mut evaluations = 1;
    let mut memory = Memory::new(options.memory, n);
    let (mut d, mut x_new, mut g_new) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut iterations = 0;
    let exit = loop {
        if g.iter().all(|v| v.abs() <= options.gradient_tolerance) {
            break LbfgsExit::Gradient;
        }
        if iterations == options.max_iterations {
            break LbfgsExit::MaxIterations;
        }
        memory.direction(&g, &mut d);
        let mut slope = dot(&g, &d);
        if slope.is_nan() || slope >= 0.0 {
            memory.clear();
            d.iter_mut().zip(&g).for_each(|(d, g)| *d = -g);
            slope = -dot(&g, &g);
        }
        let Some(f_new) = line_search(&mut f, &x, fx, &d, slope, &mut x_new, &mut g_new) else {
            if memory.is_empty() {
                break LbfgsExit::LineSearchFailed;
            }
            memory.clear();
            continue;
        };
        evaluations += f_new.1;
        iterations += 1;
        memory.push(&x_new, &x, &g_new, &g);
        let decrease = fx - f_new.0;
        x.copy_from_slice(&x_new);
        g.copy_from_slice(&g_new);
        fx = f_new.0;
        if decrease <= options.f_tolerance * fx.abs().max(1.0) {
            break LbfgsExit::FTolerance;
        }
    };
    Ok(LbfgsResult {
        x,
        cost: fx,
        iterations,
        evaluations,
        exit,
    })
}

/// A weak-Wolfe step by bracketing (Lewis & Overton 2013): from α = 1, halve towards
/// the last point that met the Armijo condition while it fails, double while the slope
/// is still below c₂ = 0.9 times the first (Nocedal & Wright eq. 3.6); the new value
/// and the evaluations spent, or `None` when 60 trials find no Armijo point. A point
/// that meets Armijo only is taken when the trials run out.
fn line_search<F: FnMut(&[f64], &mut [f64]) -> f64>(
    f: &mut F,
    x: &[f64],
    fx: f64,
    d: &[f64],
    slope: f64,
    x_new: &mut [f64],
    g_new: &mut [f64],
) -> Option<(f64, usize)> {
    let (mut low, mut high, mut alpha) = (0.0, f64::INFINITY, 1.0);
    let mut armijo: Option<f64> = None;
    for evaluations in 1..=60 {
        for ((xn, xi), di) in x_new.iter_mut().zip(x).zip(d) {
            *xn = xi + alpha * di;
        }
        let value = f(x_new, g_new);
        if !(value.is_finite() && value <= fx + 1e-4 * alpha * slope) {
            high = alpha;
        } else if dot(g_new, d) < 0.9 * slope {
            armijo = Some(alpha);
            low = alpha;
        } else {
            return Some((value, evaluations));
        }
        alpha = if high.is_finite() {
            0.5 * (low + high)
        } else {
            2.0 * low
        };
    }
    let alpha = armijo?;
    for ((xn, xi), di) in x_new.iter_mut().zip(x).zip(d) {
        *xn = xi + alpha * di;
    }
    Some((f(x_new, g_new), 61))
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum()
}

/// The last pairs s = x₊ − x, y = g₊ − g, oldest first, in a ring.
struct Memory {
    s: Vec<Vec<f64>>,
    y: Vec<Vec<f64>>,
    rho: Vec<f64>,
    alpha: Vec<f64>,
    len: usize,
    next: usize,
}

impl Memory {
    fn new(capacity: usize, n: usize) -> Self {
        Self {
            s: vec![vec![0.0; n]; capacity],
            y: vec![vec![0.0; n]; capacity],
            rho: vec![0.0; capacity],
            alpha: vec![0.0; capacity],
            len: 0,
            next: 0,
        }
    }

    fn is_empty(&self) -> bool {
        self.len == 0
    }

    fn clear(&mut self) {
        self.len = 0;
        self.next = 0;
    }

    fn push(&mut self, x_new: &[f64], x: &[f64], g_new: &[f64], g: &[f64]) {
        let k = self.next;
        for i in 0..x.len() {
            self.s[k][i] = x_new[i] - x[i];
            self.y[k][i] = g_new[i] - g[i];
        }
        let sy = dot(&self.s[k], &self.y[k]);
        let scale = (dot(&self.s[k], &self.s[k]) * dot(&self.y[k], &self.y[k])).sqrt();
        if sy > 1e-12 * scale {
            self.rho[k] = 1.0 / sy;
            self.next = (k + 1) % self.s.len();
            self.len = (self.len + 1).min(self.s.len());
        }
    }

    /// d = −H·g by the two-loop recursion (Nocedal & Wright, Algorithm 7.4).
    fn direction(&mut self, g: &[f64], d: &mut [f64]) {
        let m = self.s.len();
        d.iter_mut().zip(g).for_each(|(d, g)| *d = -g);
        let order = |j: usize| (self.next + m - 1 - j) % m; // newest first
        for j in 0..self.len {
            let k = order(j);
            self.alpha[k] = self.rho[k] * dot(&self.s[k], d);
            let a = self.alpha[k];
            d.iter_mut().zip(&self.y[k]).for_each(|(d, y)| *d -= a * y);
        }
        if self.len > 0 {
            let k = order(0);
            let gamma = 1.0 / (self.rho[k] * dot(&self.y[k], &self.y[k]));
            d.iter_mut().for_each(|d| *d *= gamma);
        }
        for j in (0..self.len).rev() {
            let k = order(j);
            let beta = self.rho[k] * dot(&self.y[k], d);
            let a = self.alpha[k];
            d.iter_mut()
                .zip(&self.s[k])
                .for_each(|(d, s)| *d += (a - beta) * s);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a quadratic ½xᵀAx − bᵀx with A diagonal, the minimiser is A⁻¹b.
    #[test]
    fn a_quadratic_is_minimised_to_its_exact_solution() {
        let a = [1.0, 10.0, 100.0, 1000.0];
        let b = [1.0, -2.0, 3.0, -4.0];
        let f = |x: &[f64], g: &mut [f64]| {
            let mut v = 0.0;
            for i in 0..4 {
                g[i] = a[i] * x[i] - b[i];
                v += 0.5 * a[i] * x[i] * x[i] - b[i] * x[i];
            }
            v
        };
        let r = lbfgs(f, &[0.0; 4], &LbfgsOptions::default()).unwrap();
        // f − f* = Σ gᵢ²/(2aᵢ) falls below the rounding of f before |g| reaches 1e-8:
        // either stop is right, and x is then within |gᵢ|/aᵢ of the solution.
        assert!(
            matches!(r.exit, LbfgsExit::Gradient | LbfgsExit::FTolerance),
            "{r}"
        );
        for i in 0..4 {
            assert!((r.x[i] - b[i] / a[i]).abs() < 1e-7, "{:?}", r.x);
        }
    }

    #[test]
    fn bad_options_are_refused_by_name() {
        let f = |_: &[f64], _: &mut [f64]| 0.0;
        let options = LbfgsOptions {
            memory: 0,
            ..LbfgsOptions::default()
        };
        let err = lbfgs(f, &[1.0], &options).unwrap_err();
        assert!(matches!(
            err,
            OptError::InvalidOption { name: "memory", .. }
        ));
        assert!(matches!(
            lbfgs(f, &[f64::NAN], &LbfgsOptions::default()),
            Err(OptError::NonFiniteStart { index: 0, .. })
        ));
    }
}
