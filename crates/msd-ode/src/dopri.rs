//! Dormand–Prince 5(4) with the semantics of MATLAB's `ode45`.
//!
//! ## The algorithm
//! One step from (t, y) with step h evaluates the seven stages of the Dormand–Prince
//! pair (the seventh at the new point, reused as the first stage of the next step:
//! first-same-as-last). The fifth-order result is propagated (local extrapolation).
//! The error test is MATLAB's, with `NormControl` off:
//!
//! err = |h| · ‖ (h⁻¹·(y₅ − y₄)) ./ max(|y|, |y_new|, AbsTol/RelTol) ‖∞ ≤ RelTol,
//!
//! i.e. the difference of the embedded pair, measured relative to the larger of the old
//! and new state and never below the threshold AbsTol/RelTol, in the max norm. A failed
//! first attempt shrinks h by max(0.1, 0.8·(RelTol/err)^(1/5)); a repeated failure halves
//! it. After a step that did not fail, h grows by 1/(1.25·(err/RelTol)^(1/5)), at most 5×.
//! Steps never exceed `MaxStep` and never fall below 16·eps(t), and a step that would
//! come within 10 % of the end is stretched to land on it.
//!
//! Output on a grid of more than two times is interpolated with MATLAB's `ntrp45`
//! (fourth-order continuous extension), exactly at the requested times; a grid point that
//! coincides with a step end takes the step's value.
//!
//! ## Differences from MATLAB, on purpose
//! - A non-finite error estimate (the right-hand side returned NaN or ∞) counts as a
//!   failed step instead of being accepted silently; if the step cannot shrink any more
//!   the solver returns [`OdeError::NonFiniteState`].
//! - `RelTol` below 100·eps is an error, not a warning.
//! - A step budget (`max_steps`) exists as a safety net.
//! - Only the scalar `AbsTol` is supported; events and `NonNegative` are not.

use crate::OdeError;
use crate::options::{Ode45Options, Stats};
use crate::system::OdeSystem;
use crate::tableau::{A, C, E, INTERPOLANT};
use nalgebra::SVector;

/// Sampled solution of an initial-value problem.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution<const N: usize> {
    /// Output times.
    pub t: Vec<f64>,
    /// States at the output times.
    pub y: Vec<SVector<f64, N>>,
    /// Solver statistics.
    pub stats: Stats,
}

impl<const N: usize> Solution<N> {
    /// One state component over all output times.
    ///
    /// ```
    /// # use msd_ode::{ode45, Ode45Options, SVector};
    /// let mut f = |_t: f64, y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| { d[0] = y[1]; d[1] = -y[0]; };
    /// let sol = ode45(&mut f, &[0.0, 0.5, 1.0], &SVector::<f64, 2>::new(1.0, 0.0), &Ode45Options::default())?;
    /// assert_eq!(sol.component(0).len(), 3);
    /// # Ok::<(), msd_ode::OdeError>(())
    /// ```
    pub fn component(&self, index: usize) -> Vec<f64> {
        self.y.iter().map(|y| y[index]).collect()
    }
}

/// Solves y' = f(t, y), `y(t_span[0]) = y0`, as MATLAB's `ode45(f, t_span, y0, options)`.
///
/// With two entries in `t_span` the solution is returned at every step (refined by
/// `options.refine`); with more, exactly at the given times, which must be strictly
/// monotonic (increasing or decreasing).
///
/// ```
/// use msd_ode::{ode45, Ode45Options, SVector};
/// // Harmonic oscillator x'' = -x from x = 1: x(t) = cos t.
/// let mut f = |_t: f64, y: &SVector<f64, 2>, dydt: &mut SVector<f64, 2>| {
///     dydt[0] = y[1];
///     dydt[1] = -y[0];
/// };
/// let grid: Vec<f64> = (0..=100).map(|i| i as f64 * 0.1).collect();
/// let options = Ode45Options { rel_tol: 1e-8, abs_tol: 1e-10, ..Ode45Options::default() };
/// let sol = ode45(&mut f, &grid, &SVector::<f64, 2>::new(1.0, 0.0), &options)?;
/// assert!((sol.y[100][0] - 10f64.cos()).abs() < 1e-6);
/// println!("{}", sol.stats);
/// # Ok::<(), msd_ode::OdeError>(())
/// ```
pub fn ode45<const N: usize, S: OdeSystem<N> + ?Sized>(
    system: &mut S,
    t_span: &[f64],
    y0: &SVector<f64, N>,
    options: &Ode45Options,
) -> Result<Solution<N>, OdeError> {
    let capacity = if t_span.len() > 2 { t_span.len() } else { 64 };
    let mut t = Vec::with_capacity(capacity);
    let mut y = Vec::with_capacity(capacity);
    let stats = ode45_with(system, t_span, y0, options, |ti, yi| {
        t.push(ti);
        y.push(*yi);
    })?;
    Ok(Solution { t, y, stats })
}

/// As [`ode45`], but hands each output `(t, y)` to `output` instead of storing it: no
/// allocation at all, for callers that keep only part of the state.
///
/// ```
/// use msd_ode::{ode45_with, Ode45Options, SVector};
/// let mut f = |_t: f64, y: &SVector<f64, 1>, d: &mut SVector<f64, 1>| d[0] = -y[0];
/// let grid = [0.0, 0.5, 1.0];
/// let mut last = 0.0;
/// let stats = ode45_with(&mut f, &grid, &SVector::<f64, 1>::new(1.0), &Ode45Options::default(),
///     |_t, y| last = y[0])?;
/// assert!((last - (-1.0f64).exp()).abs() < 1e-3);
/// assert!(stats.accepted_steps > 0);
/// # Ok::<(), msd_ode::OdeError>(())
/// ```
pub fn ode45_with<const N: usize, S, F>(
    system: &mut S,
    t_span: &[f64],
    y0: &SVector<f64, N>,
    options: &Ode45Options,
    mut output: F,
) -> Result<Stats, OdeError>
where
    S: OdeSystem<N> + ?Sized,
    F: FnMut(f64, &SVector<f64, N>),
{
    options.validate()?;
    validate_span(t_span)?;
    if let Some((index, &value)) = y0.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(OdeError::NonFiniteInitialState { index, value });
    }

    let t0 = t_span[0];
    let tfinal = t_span[t_span.len() - 1];
    let tdir = (tfinal - t0).signum();
    let htspan = (tfinal - t0).abs();
    let rtol = options.rel_tol;
    let threshold = options.abs_tol / rtol;
    let hmax = options.max_step.unwrap_or(0.1 * htspan);
    const POW: f64 = 1.0 / 5.0;

    let mut stats = Stats::default();
    let mut k = [SVector::<f64, N>::zeros(); 7];
    let mut t = t0;
    let mut y = *y0;
    system.rhs(t, &y, &mut k[0]);
    stats.rhs_evaluations += 1;
    if let Some(component) = first_non_finite(&k[0]) {
        return Err(OdeError::NonFiniteState { t, component });
    }

    output(t0, &y);
    let dense_grid = t_span.len() > 2;
    let mut next = 1; // next grid index to output

    // Initial step, as ode45.m.
    let mut hmin = 16.0 * eps_of(t);
    let mut absh = match options.initial_step {
        Some(htry) => hmax.min(hmin.max(htry)),
        None => {
            let mut absh = hmax.min(htspan);
            let rh = scaled_norm(&k[0], &y, &y, threshold) / (0.8 * rtol.powf(POW));
            if absh * rh > 1.0 {
                absh = 1.0 / rh;
            }
            absh.max(hmin)
        }
    };

    let mut done = false;
    let mut ynew = y;
    let mut stage = SVector::<f64, N>::zeros();
    while !done {
        hmin = 16.0 * eps_of(t);
        absh = hmax.min(hmin.max(absh));
        let mut h = tdir * absh;
        if 1.1 * absh >= (tfinal - t).abs() {
            h = tfinal - t;
            absh = h.abs();
            done = true;
        }

        let mut nofailed = true;
        let (tnew, err) = loop {
            // Stages 2..6 (index 1..5) at t + c_i h.
            for i in 1..6 {
                stage.copy_from(&y);
                for (j, kj) in k.iter().enumerate().take(i) {
                    let a = A[i][j];
                    if a != 0.0 {
                        stage.axpy(h * a, kj, 1.0);
                    }
                }
                system.rhs(t + C[i] * h, &stage, &mut k[i]);
            }
            let mut tnew = t + C[6] * h;
            if done {
                tnew = tfinal;
            }
            let hb = h; // ynew uses the unpurified h, as ode45.m
            h = tnew - t; // purify h
            ynew.copy_from(&y);
            for (j, kj) in k.iter().enumerate().take(6) {
                let b = A[6][j];
                if b != 0.0 {
                    ynew.axpy(hb * b, kj, 1.0);
                }
            }
            system.rhs(tnew, &ynew, &mut k[6]);
            stats.rhs_evaluations += 6;

            // Error estimate, as ode45.m with NormControl off.
            stage.fill(0.0);
            for (j, kj) in k.iter().enumerate() {
                if E[j] != 0.0 {
                    stage.axpy(E[j], kj, 1.0);
                }
            }
            let err = absh * scaled_norm(&stage, &y, &ynew, threshold);
            if err <= rtol {
                break (tnew, err);
            }
            // Failed step (also when err is NaN: the right-hand side was not finite).
            stats.rejected_steps += 1;
            if absh <= hmin {
                if !err.is_finite() {
                    let component = first_non_finite(&ynew)
                        .or_else(|| first_non_finite(&k[6]))
                        .unwrap_or(0);
                    return Err(OdeError::NonFiniteState { t, component });
                }
                return Err(OdeError::StepSizeUnderflow { t, step: absh });
            }
            if nofailed && err.is_finite() {
                nofailed = false;
                absh = hmin.max(absh * 0.1f64.max(0.8 * (rtol / err).powf(POW)));
            } else {
                nofailed = false;
                absh = hmin.max(0.5 * absh);
            }
            h = tdir * absh;
            done = false;
        };
        stats.accepted_steps += 1;
        debug_assert!(err.is_finite() && ynew.iter().all(|v| v.is_finite()));

        // Output.
        if dense_grid {
            if next < t_span.len() && tdir * (tnew - t_span[next]) >= 0.0 {
                let poly = Interpolant::new(&y, h, &k);
                while next < t_span.len() {
                    let tout = t_span[next];
                    if tdir * (tnew - tout) < 0.0 {
                        break;
                    }
                    if tout == tnew {
                        output(tout, &ynew);
                    } else {
                        poly.eval_into(&mut stage, (tout - t) / h);
                        output(tout, &stage);
                    }
                    next += 1;
                }
            }
        } else {
            let poly = Interpolant::new(&y, h, &k);
            for r in 1..options.refine {
                let tref = t + (tnew - t) * (r as f64 / options.refine as f64);
                poly.eval_into(&mut stage, (tref - t) / h);
                output(tref, &stage);
            }
            output(tnew, &ynew);
        }

        if done {
            break;
        }
        if stats.accepted_steps >= options.max_steps {
            return Err(OdeError::TooManySteps {
                t: tnew,
                steps: stats.accepted_steps,
            });
        }
        if nofailed {
            let temp = 1.25 * (err / rtol).powf(POW);
            absh = if temp > 0.2 { absh / temp } else { 5.0 * absh };
        }
        t = tnew;
        y = ynew;
        k[0] = k[6];
    }
    Ok(stats)
}

/// ode45's `ntrp45` for one step, as a polynomial in s = (t − tₙ)/h:
/// y(s) = yₙ + q₀ s + q₁ s² + q₂ s³ + q₃ s⁴ with q_j = h Σᵢ BIᵢⱼ kᵢ, evaluated by Horner.
/// Building it costs one pass over the stages per step; each output point then costs
/// four multiply-adds per component.
struct Interpolant<const N: usize> {
    y: SVector<f64, N>,
    q: [SVector<f64, N>; 4],
}

impl<const N: usize> Interpolant<N> {
    #[inline]
    fn new(y: &SVector<f64, N>, h: f64, k: &[SVector<f64, N>; 7]) -> Self {
        let q = std::array::from_fn(|j| {
            let mut qj = SVector::<f64, N>::zeros();
            for (row, ki) in INTERPOLANT.iter().zip(k.iter()) {
                if row[j] != 0.0 {
                    qj.axpy(h * row[j], ki, 1.0);
                }
            }
            qj
        });
        Self { y: *y, q }
    }

    #[inline]
    fn eval_into(&self, out: &mut SVector<f64, N>, s: f64) {
        for i in 0..N {
            let p = ((self.q[3][i] * s + self.q[2][i]) * s + self.q[1][i]) * s + self.q[0][i];
            out[i] = self.y[i] + p * s;
        }
    }
}

/// ‖v ./ max(|y|, |ynew|, threshold)‖∞. NaN in `v` gives NaN.
#[inline]
fn scaled_norm<const N: usize>(
    v: &SVector<f64, N>,
    y: &SVector<f64, N>,
    ynew: &SVector<f64, N>,
    threshold: f64,
) -> f64 {
    let mut norm = 0.0f64;
    for i in 0..N {
        let scale = y[i].abs().max(ynew[i].abs()).max(threshold);
        let ratio = (v[i] / scale).abs();
        if ratio.is_nan() {
            return f64::NAN;
        }
        norm = norm.max(ratio);
    }
    norm
}

fn first_non_finite<const N: usize>(v: &SVector<f64, N>) -> Option<usize> {
    v.iter().position(|x| !x.is_finite())
}

/// MATLAB's `eps(x)`: the distance from |x| to the next larger double.
pub(crate) fn eps_of(x: f64) -> f64 {
    let a = x.abs();
    if a == 0.0 {
        f64::from_bits(1)
    } else {
        a.next_up() - a
    }
}

fn validate_span(t_span: &[f64]) -> Result<(), OdeError> {
    if t_span.len() < 2 {
        return Err(OdeError::InvalidTimeSpan {
            index: 0,
            value: t_span.first().copied().unwrap_or(f64::NAN),
            reason: "the time span needs at least two entries [t0, tf]",
        });
    }
    if let Some((index, &value)) = t_span.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(OdeError::InvalidTimeSpan {
            index,
            value,
            reason: "times must be finite",
        });
    }
    let dir = (t_span[t_span.len() - 1] - t_span[0]).signum();
    if dir == 0.0 {
        return Err(OdeError::InvalidTimeSpan {
            index: t_span.len() - 1,
            value: t_span[0],
            reason: "the final time equals the initial time",
        });
    }
    for i in 1..t_span.len() {
        if dir * (t_span[i] - t_span[i - 1]) <= 0.0 {
            return Err(OdeError::InvalidTimeSpan {
                index: i,
                value: t_span[i],
                reason: "times must be strictly monotonic",
            });
        }
    }
    Ok(())
}
