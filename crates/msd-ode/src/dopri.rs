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

mod lanes;
mod step;
mod stepper;

use crate::error::OdeError;
use crate::options::{Ode45Options, Stats};
use crate::system::OdeSystem;
pub use lanes::{LaneSystem, Ode45Lanes};
use nalgebra::SVector;
use step::Core;
pub use stepper::{Ode45Stepper, TimeGrid};

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
    let grid = TimeGrid::new(t_span)?;
    if t_span.len() > 2 {
        let mut stepper = Ode45Stepper::new(system, grid, y0, options)?;
        stepper.advance(system, t_span.len(), |i, y| output(t_span[i], y))?;
        return Ok(stepper.stats());
    }
    if let Some((index, &value)) = y0.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(OdeError::NonFiniteInitialState { index, value });
    }
    // Two entries: every step, refined.
    let mut core = Core::new(system, t_span[0], t_span[1], y0, options)?;
    output(t_span[0], y0);
    let mut stage = SVector::<f64, N>::zeros();
    loop {
        core.step(system)?;
        let poly = core.interpolant();
        let (t, tnew, h) = (core.t, core.tnew, core.h);
        for r in 1..options.refine {
            let tref = t + (tnew - t) * (r as f64 / options.refine as f64);
            poly.eval_into(&mut stage, (tref - t) / h);
            output(tref, &stage);
        }
        output(tnew, &core.ynew);
        if core.done {
            return Ok(core.stats);
        }
        core.advance()?;
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
