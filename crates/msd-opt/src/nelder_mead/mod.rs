//! Nelder–Mead simplex search, faithful to MATLAB's `fminsearch`.
//!
//! ## The algorithm
//! As MathWorks' "fminsearch Algorithm" page (Lagarias et al., 1998) and the
//! `fminsearch.m` source it describes:
//! 1. Initial simplex: x0 plus, for each coordinate j, x0 with `x0(j)` raised by 5 %
//!    (set to 0.00025 where it is zero). Vertices are sorted by cost (stable sort).
//! 2. Each iteration, with `xbar` the centroid of the n best vertices: reflect
//!    (ρ = 1); if the reflection beats the best, try the expansion (χ = 2) and keep
//!    the better; else if it beats the second worst, keep it; else contract outside
//!    (ψ = 0.5, kept if not worse than the reflection) when the reflection beats the
//!    worst, inside otherwise (kept if better than the worst); else shrink every
//!    vertex halfway towards the best (σ = 0.5). Then sort again.
//! 3. Stop when `max|f_j − f_1| ≤ max(TolFun, 10·eps(f_1))` **and**
//!    `max‖v_j − v_1‖∞ ≤ max(TolX, 10·eps(max(v_1)))`, or when the evaluation or
//!    iteration count reaches its limit (checked first, as fminsearch does).
//!
//! A non-finite cost (NaN, ±∞) is stored as +∞: worse than every finite cost, so the
//! simplex walks away from it. If every vertex of the initial simplex is non-finite
//! the run stops with [`NelderMeadExit::NonFiniteCost`].
//!
//! Beyond fminsearch, and off by default: relative tolerances, the adaptive
//! coefficients of Gao & Han (2012), and bounds by a smooth transformation (see
//! [`crate::bounds`]); with bounds the simplex and the tolerances live in the
//! transformed variable.
//!
//! ```
//! use msd_opt::{nelder_mead, NelderMeadExit, NelderMeadOptions};
//!
//! let rosenbrock = |x: &[f64]| 100.0 * (x[1] - x[0] * x[0]).powi(2) + (1.0 - x[0]).powi(2);
//! let r = nelder_mead(rosenbrock, &[-1.2, 1.0], &NelderMeadOptions::default()).unwrap();
//! assert_eq!(r.exit, NelderMeadExit::Converged);
//! assert!((r.x[0] - 1.0).abs() < 1e-3 && (r.x[1] - 1.0).abs() < 1e-3);
//! println!("{r}");
//! ```

mod moves;
mod trace;

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::error::{check_count, check_positive, check_start};
use crate::{bounds::Bounds, error::OptError};
use moves::{Coefficients, Simplex};
pub use trace::{Step, TRACE_HEADER, TraceRow};

/// Options of [`nelder_mead`]; the defaults are MATLAB's `fminsearch`/`optimset`.
///
/// | field | default | source |
/// |---|---|---|
/// | `x_tolerance` | 1e-4 | TolX, as fminsearch |
/// | `f_tolerance` | 1e-4 | TolFun, as fminsearch |
/// | `max_iterations` | `None` = 200·n | MaxIter, as fminsearch |
/// | `max_evaluations` | `None` = 200·n | MaxFunEvals, as fminsearch |
/// | `relative_tolerances` | false | absolute, as fminsearch |
/// | `adaptive` | false | fixed coefficients, as fminsearch |
/// | `bounds` | `None` | unconstrained, as fminsearch |
/// | `trace` | false | Display = 'off' |
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NelderMeadOptions {
    /// TolX: spread of the vertices around the best, in the max norm. By default 1e-4.
    pub x_tolerance: f64,
    /// TolFun: spread of the costs around the best. By default 1e-4.
    pub f_tolerance: f64,
    /// MaxIter; `None` means 200·n. By default `None`.
    pub max_iterations: Option<usize>,
    /// MaxFunEvals; `None` means 200·n. By default `None`.
    pub max_evaluations: Option<usize>,
    /// Scale TolFun by `|f_1|` and TolX by `‖v_1‖∞` (still floored at 10·eps as
    /// fminsearch). By default false.
    pub relative_tolerances: bool,
    /// Gao & Han's dimension-dependent coefficients ρ = 1, χ = 1 + 2/n,
    /// ψ = 0.75 − 1/(2n), σ = 1 − 1/n (for n ≥ 2). By default false.
    pub adaptive: bool,
    /// Box bounds, enforced by a smooth transformation. By default `None`.
    pub bounds: Option<Bounds>,
    /// Record one [`TraceRow`] per iteration. By default false.
    pub trace: bool,
}

impl Default for NelderMeadOptions {
    /// As MATLAB's fminsearch/optimset: TolX = TolFun = 1e-4, MaxIter = MaxFunEvals = 200·n.
    fn default() -> Self {
        Self {
            x_tolerance: 1e-4,
            f_tolerance: 1e-4,
            max_iterations: None,
            max_evaluations: None,
            relative_tolerances: false,
            adaptive: false,
            bounds: None,
            trace: false,
        }
    }
}

impl NelderMeadOptions {
    /// Checks every option's range: tolerances finite and > 0, limits ≥ 1, bounds
    /// well formed.
    ///
    /// # Errors
    /// [`OptError::InvalidOption`] naming the field, or a bounds error.
    ///
    /// ```
    /// use msd_opt::{NelderMeadOptions, OptError};
    /// let bad = NelderMeadOptions { x_tolerance: 0.0, ..Default::default() };
    /// assert!(matches!(bad.validate(), Err(OptError::InvalidOption { name: "x_tolerance", .. })));
    /// ```
    pub fn validate(&self) -> Result<(), OptError> {
        check_positive("x_tolerance", self.x_tolerance)?;
        check_positive("f_tolerance", self.f_tolerance)?;
        check_count("max_iterations", self.max_iterations)?;
        check_count("max_evaluations", self.max_evaluations)?;
        if let Some(b) = &self.bounds {
            b.validate()?;
        }
        Ok(())
    }
}

/// Why [`nelder_mead`] stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum NelderMeadExit {
    /// Both TolX and TolFun are satisfied (fminsearch exitflag 1).
    Converged,
    /// MaxIter reached (exitflag 0).
    MaxIterations,
    /// MaxFunEvals reached (exitflag 0).
    MaxEvaluations,
    /// The cost was non-finite at every vertex of the initial simplex
    /// (no fminsearch equivalent; exitflag −3 here).
    NonFiniteCost,
}

impl NelderMeadExit {
    /// fminsearch's `exitflag`: 1 converged, 0 a limit reached, −3 non-finite cost.
    pub fn exitflag(&self) -> i32 {
        match self {
            Self::Converged => 1,
            Self::MaxIterations | Self::MaxEvaluations => 0,
            Self::NonFiniteCost => -3,
        }
    }
}

impl fmt::Display for NelderMeadExit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Converged => {
                "Optimization terminated: the current x satisfies the termination criteria \
                 using OPTIONS.TolX and F(X) satisfies the convergence criteria using OPTIONS.TolFun"
            }
            Self::MaxIterations => {
                "Exiting: Maximum number of iterations has been exceeded - increase MaxIter option"
            }
            Self::MaxEvaluations => {
                "Exiting: Maximum number of function evaluations has been exceeded - increase MaxFunEvals option"
            }
            Self::NonFiniteCost => {
                "Exiting: the cost is not finite at any vertex of the initial simplex"
            }
        })
    }
}

/// What [`nelder_mead`] found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NelderMeadResult {
    /// Best vertex (inside the bounds when bounds are given).
    pub x: Vec<f64>,
    /// Cost at `x` (+∞ only with [`NelderMeadExit::NonFiniteCost`]).
    pub cost: f64,
    /// Why the search stopped.
    pub exit: NelderMeadExit,
    /// fminsearch's `output.iterations` (the initial simplex is iteration 1).
    pub iterations: usize,
    /// fminsearch's `output.funcCount`.
    pub evaluations: usize,
    /// One row per iteration, from iteration 0; empty unless `trace` was set.
    pub trace: Vec<TraceRow>,
}

impl fmt::Display for NelderMeadResult {
    /// The shape of fminsearch's `[x,fval,exitflag,output]`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let xs: Vec<String> = self.x.iter().map(|v| trace::format_g(*v, 6)).collect();
        writeln!(f, "x = [{}]", xs.join(", "))?;
        writeln!(f, "fval = {}", trace::format_g(self.cost, 6))?;
        writeln!(f, "exitflag = {}", self.exit.exitflag())?;
        writeln!(f, "output =")?;
        writeln!(f, "    iterations: {}", self.iterations)?;
        writeln!(f, "     funcCount: {}", self.evaluations)?;
        writeln!(f, "     algorithm: 'Nelder-Mead simplex direct search'")?;
        write!(f, "       message: '{}'", self.exit)
    }
}

/// Minimises `cost` from `x0` with fminsearch's Nelder–Mead method.
///
/// `cost` may return a non-finite value (e.g. `f64::INFINITY` outside a physical
/// region): it counts as worse than any finite cost. x0 outside `bounds` is first
/// projected onto them.
///
/// # Errors
/// [`OptError::EmptyStart`], [`OptError::NonFiniteStart`], an invalid option, or
/// bounds that do not fit x0. The solver itself never fails: limits and non-finite
/// costs are exit reasons.
///
/// ```
/// use msd_opt::{nelder_mead, NelderMeadOptions};
///
/// let r = nelder_mead(|x| (x[0] - 3.0).powi(2) + 1.0, &[0.0], &NelderMeadOptions::default())
///     .unwrap();
/// assert!((r.x[0] - 3.0).abs() < 1e-3);
/// assert!((r.cost - 1.0).abs() < 1e-4);
/// ```
pub fn nelder_mead<F: FnMut(&[f64]) -> f64>(
    mut cost: F,
    x0: &[f64],
    options: &NelderMeadOptions,
) -> Result<NelderMeadResult, OptError> {
    check_start(x0)?;
    options.validate()?;
    let n = x0.len();
    match &options.bounds {
        None => Ok(run(cost, x0, options)),
        Some(bounds) => {
            bounds.validate_for(n)?;
            let mut z0 = vec![0.0; n];
            bounds.unbounded_from_box(x0, &mut z0);
            let mut x = vec![0.0; n];
            let mut result = run(
                |z: &[f64]| {
                    bounds.box_from_unbounded(z, &mut x);
                    cost(&x)
                },
                &z0,
                options,
            );
            let z = std::mem::take(&mut result.x);
            result.x = vec![0.0; n];
            bounds.box_from_unbounded(&z, &mut result.x);
            Ok(result)
        }
    }
}

/// MATLAB's `eps(x)`: the spacing of doubles at `|x|`.
fn matlab_eps(x: f64) -> f64 {
    let a = x.abs();
    if !a.is_finite() {
        return f64::NAN;
    }
    if a < f64::MIN_POSITIVE {
        return f64::from_bits(1);
    }
    let e = ((a.to_bits() >> 52) & 0x7ff) as i64 - 1023 - 52;
    if e >= -1022 {
        f64::from_bits(((e + 1023) as u64) << 52)
    } else {
        f64::from_bits(1u64 << (e + 1074))
    }
}

/// fminsearch's convergence test on a sorted simplex.
fn converged(s: &Simplex, options: &NelderMeadOptions) -> bool {
    let f1 = s.values[0];
    let best = s.vertex(0);
    let (f_scale, x_scale) = if options.relative_tolerances {
        (f1.abs(), best.iter().fold(0.0_f64, |m, v| m.max(v.abs())))
    } else {
        (1.0, 1.0)
    };
    let f_threshold = (options.f_tolerance * f_scale).max(10.0 * matlab_eps(f1));
    if !s.values[1..].iter().all(|&f| (f - f1).abs() <= f_threshold) {
        return false;
    }
    let max_best = best.iter().fold(f64::NEG_INFINITY, |m, &v| m.max(v));
    let x_threshold = (options.x_tolerance * x_scale).max(10.0 * matlab_eps(max_best));
    (1..=s.n).all(|j| {
        s.vertex(j)
            .iter()
            .zip(best)
            .all(|(v, b)| (v - b).abs() <= x_threshold)
    })
}

/// One Nelder–Mead step from the centroid `xbar` of the best n vertices: reflect, then
/// expand, contract outside or inside, the worst vertex replaced where the move pays, or
/// `Step::Shrink` for the caller; and the evaluations it used. `xr` and `xe` are work
/// space.
fn step(
    s: &mut Simplex,
    c: &Coefficients,
    eval: &mut impl FnMut(&[f64]) -> f64,
    xbar: &[f64],
    [xr, xe]: [&mut Vec<f64>; 2],
) -> (Step, usize) {
    let n = s.n;
    moves::reflect(xbar, s.vertex(n), c, xr);
    let fxr = eval(xr);
    let mut used = 1;

    let step = if fxr < s.values[0] {
        moves::expand(xbar, s.vertex(n), c, xe);
        let fxe = eval(xe);
        used += 1;
        if fxe < fxr {
            s.replace_worst(xe, fxe);
            Step::Expand
        } else {
            s.replace_worst(xr, fxr);
            Step::Reflect
        }
    } else if fxr < s.values[n - 1] {
        s.replace_worst(xr, fxr);
        Step::Reflect
    } else if fxr < s.values[n] {
        moves::contract_outside(xbar, s.vertex(n), c, xe);
        let fxc = eval(xe);
        used += 1;
        if fxc <= fxr {
            s.replace_worst(xe, fxc);
            Step::ContractOutside
        } else {
            Step::Shrink
        }
    } else {
        moves::contract_inside(xbar, s.vertex(n), c, xe);
        let fxcc = eval(xe);
        used += 1;
        if fxcc < s.values[n] {
            s.replace_worst(xe, fxcc);
            Step::ContractInside
        } else {
            Step::Shrink
        }
    };
    (step, used)
}

/// The vertices 1..=n of the initial simplex around `x0` (vertex 0, already set), as
/// fminsearch places them, with their costs; sorted.
fn initial_simplex(s: &mut Simplex, x0: &[f64], eval: &mut impl FnMut(&[f64]) -> f64) {
    for j in 0..x0.len() {
        moves::initial_vertex(x0, j, s.vertex_mut(j + 1));
        s.values[j + 1] = eval(s.vertex(j + 1));
    }
    s.sort();
}

/// Every vertex but the best moved towards it, with its new cost.
fn shrink(s: &mut Simplex, c: &Coefficients, eval: &mut impl FnMut(&[f64]) -> f64) {
    for j in 1..s.values.len() {
        let (best, vertex) = s.best_and_vertex_mut(j);
        moves::shrink_vertex(best, vertex, c);
        s.values[j] = eval(s.vertex(j));
    }
}

/// Why the search stopped: a budget spent ([evaluations, iterations] against their
/// maxima, evaluations first, as fminsearch says), or convergence.
fn exit([evaluations, iterations]: [usize; 2], [max_e, max_i]: [usize; 2]) -> NelderMeadExit {
    if evaluations >= max_e {
        NelderMeadExit::MaxEvaluations
    } else if iterations >= max_i {
        NelderMeadExit::MaxIterations
    } else {
        NelderMeadExit::Converged
    }
}

/// The method itself, on validated input, in the solver's working variables.
fn run<F: FnMut(&[f64]) -> f64>(
    mut cost: F,
    x0: &[f64],
    options: &NelderMeadOptions,
) -> NelderMeadResult {
    let n = x0.len();
    let c = if options.adaptive {
        Coefficients::adaptive(n)
    } else {
        Coefficients::FMINSEARCH
    };
    let max_iterations = options.max_iterations.unwrap_or(200 * n);
    let max_evaluations = options.max_evaluations.unwrap_or(200 * n);
    let mut eval = |x: &[f64]| {
        let f = cost(x);
        if f.is_finite() { f } else { f64::INFINITY }
    };
    let mut trace = Vec::new();
    if options.trace {
        trace.reserve(max_iterations.saturating_add(1).min(1 << 16));
    }
    let record = |trace: &mut Vec<TraceRow>, iteration, evaluations, best_cost, step| {
        if options.trace {
            trace.push(TraceRow {
                iteration,
                evaluations,
                best_cost,
                step,
            });
        }
    };

    // Initial simplex.
    let mut s = Simplex::new(n);
    s.vertex_mut(0).copy_from_slice(x0);
    s.values[0] = eval(x0);
    record(&mut trace, 0, 1, s.values[0], Step::Start);
    initial_simplex(&mut s, x0, &mut eval);
    let mut iterations = 1;
    let mut evaluations = n + 1;
    record(
        &mut trace,
        1,
        evaluations,
        s.values[0],
        Step::InitialSimplex,
    );

    if s.values[0] == f64::INFINITY {
        return NelderMeadResult {
            x: s.vertex(0).to_vec(),
            cost: f64::INFINITY,
            exit: NelderMeadExit::NonFiniteCost,
            iterations,
            evaluations,
            trace,
        };
    }

    let mut xbar = vec![0.0; n];
    let mut xr = vec![0.0; n];
    let mut xe = vec![0.0; n];
    while evaluations < max_evaluations && iterations < max_iterations {
        if converged(&s, options) {
            break;
        }
        s.centroid(&mut xbar);
        let (step, used) = step(&mut s, &c, &mut eval, &xbar, [&mut xr, &mut xe]);
        evaluations += used;
        if step == Step::Shrink {
            shrink(&mut s, &c, &mut eval);
            evaluations += n;
        }
        s.sort();
        iterations += 1;
        record(&mut trace, iterations, evaluations, s.values[0], step);
    }

    NelderMeadResult {
        x: s.vertex(0).to_vec(),
        cost: s.values[0],
        exit: exit([evaluations, iterations], [max_evaluations, max_iterations]),
        iterations,
        evaluations,
        trace,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eps_matches_matlab() {
        assert_eq!(matlab_eps(1.0), f64::EPSILON);
        assert_eq!(matlab_eps(-1.0), f64::EPSILON);
        assert_eq!(matlab_eps(1.5), f64::EPSILON);
        assert_eq!(matlab_eps(2.0), 2.0 * f64::EPSILON);
        assert_eq!(matlab_eps(0.0), f64::from_bits(1));
        assert_eq!(matlab_eps(f64::MIN_POSITIVE), f64::from_bits(1));
        assert!(matlab_eps(f64::NAN).is_nan());
    }
}
