//! ode45 on an output grid, resumable: advance to any grid index, stop, go on later.

use super::step::{Core, Interpolant};
use super::validate_span;
use crate::error::OdeError;
use crate::options::{Ode45Options, Stats};
use crate::system::OdeSystem;
use nalgebra::SVector;

/// Output times checked once (at least two, finite, strictly monotonic), to be shared
/// by any number of [`Ode45Stepper`]s without checking them again.
///
/// ```
/// use msd_ode::{OdeError, TimeGrid};
/// let times: Vec<f64> = (0..=100).map(|i| i as f64 * 0.01).collect();
/// assert_eq!(TimeGrid::new(&times)?.len(), 101);
/// assert!(matches!(TimeGrid::new(&[0.0, 0.2, 0.1]), Err(OdeError::InvalidTimeSpan { index: 2, .. })));
/// # Ok::<(), OdeError>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub struct TimeGrid<'a> {
    times: &'a [f64],
}

impl<'a> TimeGrid<'a> {
    /// Checks `times` as [`ode45`](crate::dopri::ode45) checks its time span.
    pub fn new(times: &'a [f64]) -> Result<Self, OdeError> {
        validate_span(times)?;
        Ok(Self { times })
    }

    /// The times.
    pub fn times(&self) -> &'a [f64] {
        self.times
    }

    /// Number of times (at least two).
    #[allow(clippy::len_without_is_empty)]
    pub fn len(&self) -> usize {
        self.times.len()
    }
}

/// [`ode45_with`](crate::dopri::ode45_with) on a grid of output times, one stretch at a time:
/// [`advance`](Ode45Stepper::advance) outputs the grid points up to a given index and
/// keeps the solver's state, so a long record can be produced in pieces (a Monte Carlo
/// engine streaming the time axis keeps one stepper per sample instead of every
/// response). The outputs are bit for bit those of `ode45_with` on the same grid,
/// however the grid is cut.
///
/// The right-hand side is passed to every call, so the stepper holds no borrow of it;
/// pass the same system each time.
///
/// ```
/// use msd_ode::{ode45_with, Ode45Options, Ode45Stepper, SVector, TimeGrid};
/// let mut f = |_t: f64, y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| { d[0] = y[1]; d[1] = -y[0]; };
/// let times: Vec<f64> = (0..=1000).map(|i| i as f64 * 0.01).collect();
/// let options = Ode45Options { rel_tol: 1e-8, ..Ode45Options::default() };
/// let y0 = SVector::<f64, 2>::new(1.0, 0.0);
/// let mut whole = Vec::new();
/// ode45_with(&mut f, &times, &y0, &options, |_, y| whole.push(y[0]))?;
///
/// let mut stepper = Ode45Stepper::new(&mut f, TimeGrid::new(&times)?, &y0, &options)?;
/// let mut pieces = vec![0.0; times.len()];
/// for until in [1, 250, 600, 1001] {
///     stepper.advance(&mut f, until, |i, y| pieces[i] = y[0])?;
/// }
/// assert_eq!(whole, pieces);
/// assert!(stepper.is_finished());
/// # Ok::<(), msd_ode::OdeError>(())
/// ```
#[derive(Debug, Clone)]
pub struct Ode45Stepper<'a, const N: usize> {
    grid: &'a [f64],
    core: Core<N>,
    /// The next grid index to output.
    next: usize,
    /// The core holds an accepted step whose grid points are not all output yet.
    pending: bool,
    /// That step's continuous extension, once a point inside it was asked for.
    poly: Option<Interpolant<N>>,
    out: SVector<f64, N>,
}

impl<'a, const N: usize> Ode45Stepper<'a, N> {
    /// A stepper at the grid's first time with state `y0`: checks the options and `y0`
    /// and evaluates f(t0, y0), as `ode45_with` does before its first step.
    pub fn new<S: OdeSystem<N> + ?Sized>(
        system: &mut S,
        grid: TimeGrid<'a>,
        y0: &SVector<f64, N>,
        options: &Ode45Options,
    ) -> Result<Self, OdeError> {
        options.validate()?;
        if let Some((index, &value)) = y0.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(OdeError::NonFiniteInitialState { index, value });
        }
        let times = grid.times;
        let core = Core::new(system, times[0], times[times.len() - 1], y0, options)?;
        Ok(Self {
            grid: times,
            core,
            next: 0,
            pending: false,
            poly: None,
            out: *y0,
        })
    }

    /// The next grid index to be output (0 after [`Ode45Stepper::new`]).
    pub fn next_index(&self) -> usize {
        self.next
    }

    /// Whether every grid point has been output.
    pub fn is_finished(&self) -> bool {
        self.next == self.grid.len()
    }

    /// The solver's statistics so far.
    pub fn stats(&self) -> Stats {
        self.core.stats
    }

    /// Steps until the grid points before index `until` (clamped to the grid) are all
    /// output, handing each to `output(index, y)`; the state of the step in progress is
    /// kept for the next call. Allocates nothing.
    ///
    /// On an error the stepper must not be advanced again.
    pub fn advance<S, F>(
        &mut self,
        system: &mut S,
        until: usize,
        mut output: F,
    ) -> Result<(), OdeError>
    where
        S: OdeSystem<N> + ?Sized,
        F: FnMut(usize, &SVector<f64, N>),
    {
        let until = until.min(self.grid.len());
        if self.next == 0 && until > 0 {
            output(0, &self.core.y);
            self.next = 1;
        }
        loop {
            if self.pending {
                let tdir = self.core.tdir;
                let (t, tnew, h) = (self.core.t, self.core.tnew, self.core.h);
                while self.next < until {
                    let tout = self.grid[self.next];
                    if tdir * (tnew - tout) < 0.0 {
                        break;
                    }
                    if tout == tnew {
                        output(self.next, &self.core.ynew);
                    } else {
                        let poly = match &self.poly {
                            Some(poly) => poly,
                            None => self.poly.insert(self.core.interpolant()),
                        };
                        poly.eval_into(&mut self.out, (tout - t) / h);
                        output(self.next, &self.out);
                    }
                    self.next += 1;
                }
                let covered = |i: usize| tdir * (tnew - self.grid[i]) >= 0.0;
                if self.next < self.grid.len() && covered(self.next) {
                    debug_assert!(self.next >= until);
                    return Ok(()); // this step still has points beyond `until`
                }
                if self.core.done {
                    self.pending = false;
                    debug_assert!(self.is_finished());
                    return Ok(());
                }
                self.core.advance()?;
                self.pending = false;
                self.poly = None;
            }
            if self.next >= until {
                return Ok(());
            }
            self.core.step(system)?;
            self.pending = true;
        }
    }
}
