//! ode45 for many systems at once: [`Ode45Lanes`] steps B systems of one family side by
//! side on one output grid, each lane exactly what [`Ode45Stepper`](super::Ode45Stepper)
//! gives alone.
//!
//! ## Why
//! One Dormand–Prince step is a chain of dependent stages (each needs the previous
//! one's right-hand side), so a single solve waits on floating-point latency. B
//! independent solves stepped together fill the pipeline: every stage, the error
//! estimate and the new state are computed for all lanes at once, in loops over the
//! lanes that vectorise. Each lane keeps its own time, step size and step-size
//! controller; in one *round* every lane that still has work attempts one step
//! (accepted or rejected by its own error test), and lanes with no more work that round
//! wait. The arithmetic of each lane is the single-lane solver's, operation for
//! operation, so every lane's outputs and statistics are bit for bit those of
//! `Ode45Stepper` with the same system, grid and options.

#![allow(clippy::needless_range_loop)] // lane and tableau indices mirror the notation

use super::step::POW;
use super::{TimeGrid, eps_of};
use crate::error::OdeError;
use crate::options::{Ode45Options, Stats};
use crate::tableau::{A, C, E, INTERPOLANT};

/// A right-hand side for B systems of N states, evaluated for all lanes at once:
/// lane l's system is y' = f_l(t, y).
///
/// ```
/// use msd_ode::LaneSystem;
/// /// y' = −rate_l·y for each lane l.
/// struct Decays([f64; 4]);
/// impl LaneSystem<1, 4> for Decays {
///     fn rhs(&mut self, _active: &[bool; 4], _t: &[f64; 4], y: &[[f64; 4]; 1], dydt: &mut [[f64; 4]; 1]) {
///         for l in 0..4 {
///             dydt[0][l] = -self.0[l] * y[0][l];
///         }
///     }
/// }
/// let mut out = [[0.0; 4]; 1];
/// Decays([1.0, 2.0, 3.0, 4.0]).rhs(&[true; 4], &[0.0; 4], &[[1.0; 4]], &mut out);
/// assert_eq!(out[0], [-1.0, -2.0, -3.0, -4.0]);
/// ```
pub trait LaneSystem<const N: usize, const B: usize> {
    /// Writes `f_l(t[l], y[·][l])` into `dydt[·][l]` for every lane l with `active[l]`;
    /// the other lanes' entries are not used (leave them, or fill them with anything).
    fn rhs(
        &mut self,
        active: &[bool; B],
        t: &[f64; B],
        y: &[[f64; B]; N],
        dydt: &mut [[f64; B]; N],
    );
}

/// Where a lane is.
#[derive(Debug, Clone, PartialEq)]
enum Status {
    /// Between steps, or holding an accepted step whose grid points are not all out.
    Running,
    /// Every grid point is out.
    Finished,
    /// Not started (no system for it) or stopped by an error.
    Failed(Option<OdeError>),
}

/// B systems integrated by ode45 on one output grid, one stretch at a time, side by
/// side. One solve waits on floating-point latency (each stage needs the previous
/// one's right-hand side); B solves stepped together fill the pipeline: in each round
/// every lane with work attempts one step under its own step-size control, and the
/// stages, new states and error estimates of all lanes are computed in loops that
/// vectorise. [`advance`](Self::advance) hands out
/// one state component of every lane at the grid points up to an index and keeps the
/// solvers' states. Lane l's values are bit for bit those of an
/// [`Ode45Stepper`](crate::dopri::Ode45Stepper) on lane l's system alone, however the grid is
/// cut, and so are its statistics.
///
/// ```
/// use msd_ode::{LaneSystem, Ode45Lanes, Ode45Options, Ode45Stepper, SVector, TimeGrid};
/// /// x'' = −ω_l² x for two lanes.
/// struct Springs([f64; 2]);
/// impl LaneSystem<2, 2> for Springs {
///     fn rhs(&mut self, _: &[bool; 2], _t: &[f64; 2], y: &[[f64; 2]; 2], d: &mut [[f64; 2]; 2]) {
///         for l in 0..2 {
///             d[0][l] = y[1][l];
///             d[1][l] = -self.0[l] * self.0[l] * y[0][l];
///         }
///     }
/// }
/// let times: Vec<f64> = (0..=500).map(|i| i as f64 * 0.01).collect();
/// let grid = TimeGrid::new(&times)?;
/// let options = Ode45Options::default();
/// let mut springs = Springs([1.0, 3.0]);
/// let y0 = [[1.0, 1.0], [0.0, 0.0]]; // y0[component][lane]
/// let mut lanes = Ode45Lanes::new(&mut springs, grid, &y0, [true; 2], &options);
/// let mut x = vec![[0.0; 2]; 501];
/// let ok = lanes.advance(&mut springs, 501, 0, |lane, i, v| x[i][lane] = v);
/// assert_eq!(ok, [true, true]);
///
/// // Lane 1 alone.
/// let mut f = |_t: f64, y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| { d[0] = y[1]; d[1] = -9.0 * y[0]; };
/// let mut alone = Ode45Stepper::new(&mut f, grid, &SVector::<f64, 2>::new(1.0, 0.0), &options)?;
/// alone.advance(&mut f, 501, |i, y| assert_eq!(y[0], x[i][1]))?;
/// assert_eq!(alone.stats(), lanes.stats(1));
/// # Ok::<(), msd_ode::OdeError>(())
/// ```
#[derive(Debug, Clone)]
pub struct Ode45Lanes<'a, const N: usize, const B: usize> {
    grid: &'a [f64],
    rtol: f64,
    threshold: f64,
    hmax: f64,
    tfinal: f64,
    tdir: f64,
    max_steps: usize,
    status: [Status; B],
    stats: [Stats; B],
    /// Start of each lane's current step, its state and stages (k[0] = f(t, y); after an
    /// accepted step k[1..7] are its stages and k[6] = f(tnew, ynew)).
    t: [f64; B],
    y: [[f64; B]; N],
    k: [[[f64; B]; N]; 7],
    absh: [f64; B],
    /// The accepted step: end, state, purified size, error, flags.
    tnew: [f64; B],
    ynew: [[f64; B]; N],
    h: [f64; B],
    err: [f64; B],
    nofailed: [bool; B],
    done: [bool; B],
    /// An accepted step is held (`pending`), its interpolant built for `poly_component`.
    pending: [bool; B],
    poly: [Option<[f64; 4]>; B],
    /// The next grid index to output.
    next: [usize; B],
    /// The attempt in progress: first of a new step (`fresh`), its h, its hmin.
    fresh: [bool; B],
    attempt_h: [f64; B],
    attempt_done: [bool; B],
    attempt_nofailed: [bool; B],
    hmin: [f64; B],
    /// The attempt in progress, all lanes.
    trial: Attempt<N, B>,
}

/// The stages of one attempt (k[1..7]), its new state and time, for every lane.
#[derive(Debug, Clone)]
struct Attempt<const N: usize, const B: usize> {
    k: [[[f64; B]; N]; 7],
    ynew: [[f64; B]; N],
    tnew: [f64; B],
    /// The purified step.
    h: [f64; B],
    err: [f64; B],
}

impl<'a, const N: usize, const B: usize> Ode45Lanes<'a, N, B> {
    /// Lanes at the grid's first time with states `y0[component][lane]`, the lanes with
    /// `used[lane]` false left out (they count as failed): checks each lane's initial
    /// state and f(t0, y0) and takes ode45's initial step, as
    /// [`Ode45Stepper::new`](crate::Ode45Stepper::new). A lane whose check fails is
    /// failed ([`error`](Self::error) says why); invalid `options` fail every lane.
    pub fn new<S: LaneSystem<N, B> + ?Sized>(
        system: &mut S,
        grid: TimeGrid<'a>,
        y0: &[[f64; B]; N],
        used: [bool; B],
        options: &Ode45Options,
    ) -> Self {
        let times = grid.times();
        let (t0, tfinal) = (times[0], times[times.len() - 1]);
        let tdir = (tfinal - t0).signum();
        let htspan = (tfinal - t0).abs();
        let rtol = options.rel_tol;
        let threshold = options.abs_tol / rtol;
        let hmax = options.max_step.unwrap_or(0.1 * htspan);
        let mut lanes = Self {
            grid: times,
            rtol,
            threshold,
            hmax,
            tfinal,
            tdir,
            max_steps: options.max_steps,
            status: std::array::from_fn(|_| Status::Running),
            stats: [Stats::default(); B],
            t: [t0; B],
            y: *y0,
            k: [[[0.0; B]; N]; 7],
            absh: [0.0; B],
            tnew: [t0; B],
            ynew: *y0,
            h: [0.0; B],
            err: [0.0; B],
            nofailed: [true; B],
            done: [false; B],
            pending: [false; B],
            poly: [None; B],
            next: [0; B],
            fresh: [true; B],
            attempt_h: [0.0; B],
            attempt_done: [false; B],
            attempt_nofailed: [true; B],
            hmin: [0.0; B],
            trial: Attempt {
                k: [[[0.0; B]; N]; 7],
                ynew: [[0.0; B]; N],
                tnew: [0.0; B],
                h: [0.0; B],
                err: [0.0; B],
            },
        };
        if let Err(e) = options.validate() {
            lanes.status = std::array::from_fn(|_| Status::Failed(Some(e.clone())));
            return lanes;
        }
        let mut active = used;
        for (lane, on) in active.iter_mut().enumerate() {
            if !*on {
                lanes.status[lane] = Status::Failed(None);
            } else if let Some(index) = (0..N).find(|&r| !y0[r][lane].is_finite()) {
                let value = y0[index][lane];
                lanes.status[lane] =
                    Status::Failed(Some(OdeError::NonFiniteInitialState { index, value }));
                *on = false;
            }
        }
        let mut k0 = [[0.0; B]; N];
        system.rhs(&active, &[t0; B], y0, &mut k0);
        lanes.k[0] = k0;
        for lane in (0..B).filter(|&l| active[l]) {
            lanes.stats[lane].rhs_evaluations = 1;
            if let Some(component) = (0..N).find(|&r| !k0[r][lane].is_finite()) {
                lanes.status[lane] =
                    Status::Failed(Some(OdeError::NonFiniteState { t: t0, component }));
                continue;
            }
            // Initial step, as ode45.m (and `Core::new`).
            let hmin = 16.0 * eps_of(t0);
            lanes.absh[lane] = match options.initial_step {
                Some(htry) => hmax.min(hmin.max(htry)),
                None => {
                    let mut absh = hmax.min(htspan);
                    let rh = scaled_norm(&k0, y0, y0, threshold, lane) / (0.8 * rtol.powf(POW));
                    if absh * rh > 1.0 {
                        absh = 1.0 / rh;
                    }
                    absh.max(hmin)
                }
            };
        }
        lanes
    }

    /// The statistics of `lane` so far.
    pub fn stats(&self, lane: usize) -> Stats {
        self.stats[lane]
    }

    /// Why `lane` failed: `None` while it is good, or when it was left out at
    /// [`new`](Self::new).
    pub fn error(&self, lane: usize) -> Option<&OdeError> {
        match &self.status[lane] {
            Status::Failed(e) => e.as_ref(),
            _ => None,
        }
    }

    /// Which lanes are good (not left out, no error).
    pub fn good(&self) -> [bool; B] {
        std::array::from_fn(|l| !matches!(self.status[l], Status::Failed(_)))
    }

    /// Steps every good lane until its grid points before index `until` (clamped to the
    /// grid) are all out, handing component `component` of each to
    /// `output(lane, index, value)`; returns [`good`](Self::good). A lane that fails
    /// stops there (its later points are not handed out). Allocates nothing.
    ///
    /// # Panics
    /// If `component ≥ N` (a programming error).
    pub fn advance<S, F>(
        &mut self,
        system: &mut S,
        until: usize,
        component: usize,
        mut output: F,
    ) -> [bool; B]
    where
        S: LaneSystem<N, B> + ?Sized,
        F: FnMut(usize, usize, f64),
    {
        assert!(component < N, "component {component} of {N}");
        let until = until.min(self.grid.len());
        let mut active = [false; B];
        loop {
            for (lane, active) in active.iter_mut().enumerate() {
                *active = self.settle(lane, until, component, &mut output);
            }
            if !active.contains(&true) {
                return self.good();
            }
            self.attempt(system, &active);
        }
    }

    /// Hands out `lane`'s points of its held step (and the initial point) below `until`
    /// and moves past the step when it has no more; whether the lane needs a step
    /// attempt to go on.
    fn settle<F: FnMut(usize, usize, f64)>(
        &mut self,
        lane: usize,
        until: usize,
        component: usize,
        output: &mut F,
    ) -> bool {
        if self.status[lane] != Status::Running {
            return false;
        }
        if self.next[lane] == 0 && until > 0 {
            output(lane, 0, self.y[component][lane]);
            self.next[lane] = 1;
        }
        if self.pending[lane] {
            let tdir = self.tdir;
            let (t, tnew, h) = (self.t[lane], self.tnew[lane], self.h[lane]);
            // The step's points below `until`: interpolated, but a point on the step's
            // end (only the last can be) takes the new state.
            // A step holds a few points: a forward scan (as `Ode45Stepper`'s) beats a
            // binary search, and costs no more than interpolating what it passes.
            let from = self.next[lane];
            let mut end = from;
            while end < until && tdir * (tnew - self.grid[end]) >= 0.0 {
                end += 1;
            }
            let on_end = end > from && self.grid[end - 1] == tnew;
            let inside = if on_end { end - 1 } else { end };
            if inside > from {
                let q = match self.poly[lane] {
                    Some(q) => q,
                    None => *self.poly[lane].insert(self.interpolant(lane, component)),
                };
                let y = self.y[component][lane];
                // Independent points, a few at a time into a buffer: the loop vectorises.
                let mut values = [0.0; 16];
                for (times, first) in self.grid[from..inside].chunks(16).zip((from..).step_by(16)) {
                    for (value, &tout) in values.iter_mut().zip(times) {
                        let s = (tout - t) / h;
                        let p = ((q[3] * s + q[2]) * s + q[1]) * s + q[0];
                        *value = y + p * s;
                    }
                    for (index, &value) in values[..times.len()].iter().enumerate() {
                        output(lane, first + index, value);
                    }
                }
            }
            if on_end {
                output(lane, end - 1, self.ynew[component][lane]);
            }
            self.next[lane] = end;
            let next = self.next[lane];
            if next < self.grid.len() && tdir * (tnew - self.grid[next]) >= 0.0 {
                return false; // this step still has points beyond `until`
            }
            if self.done[lane] {
                self.pending[lane] = false;
                self.status[lane] = Status::Finished;
                return false;
            }
            if let Err(e) = self.step_past(lane) {
                self.status[lane] = Status::Failed(Some(e));
                return false;
            }
        }
        self.next[lane] < until
    }

    /// `Core::advance` for one lane: refuses to go past `max_steps`, grows the step after
    /// one that did not fail, and moves to the end of the held step.
    fn step_past(&mut self, lane: usize) -> Result<(), OdeError> {
        if self.stats[lane].accepted_steps >= self.max_steps {
            return Err(OdeError::TooManySteps {
                t: self.tnew[lane],
                steps: self.stats[lane].accepted_steps,
            });
        }
        if self.nofailed[lane] {
            let temp = 1.25 * (self.err[lane] / self.rtol).powf(POW);
            self.absh[lane] = if temp > 0.2 {
                self.absh[lane] / temp
            } else {
                5.0 * self.absh[lane]
            };
        }
        self.t[lane] = self.tnew[lane];
        for r in 0..N {
            self.y[r][lane] = self.ynew[r][lane];
            self.k[0][r][lane] = self.k[6][r][lane];
        }
        self.pending[lane] = false;
        self.poly[lane] = None;
        self.fresh[lane] = true;
        Ok(())
    }

    /// The held step's `ntrp45` polynomial for one component: q_j = h·Σᵢ BIᵢⱼ kᵢ,
    /// summed as `Interpolant::new` sums them.
    fn interpolant(&self, lane: usize, component: usize) -> [f64; 4] {
        // The rows with an entry in columns 1..4 (column 0 has row 0 only): fixed
        // loops over constants, unrolled, so no test of a coefficient is left.
        const ROWS: [usize; 6] = [0, 2, 3, 4, 5, 6];
        debug_assert!(
            (1..7).all(|r| INTERPOLANT[r][0] == 0.0 && (r != 1 || INTERPOLANT[1] == [0.0; 4]))
        );
        let h = self.h[lane];
        let k: [f64; 7] = std::array::from_fn(|i| self.k[i][component][lane]);
        let mut q = [0.0; 4];
        q[0] += h * INTERPOLANT[0][0] * k[0];
        for (j, q) in q.iter_mut().enumerate().skip(1) {
            for r in ROWS {
                *q += h * INTERPOLANT[r][j] * k[r];
            }
        }
        q
    }

    /// One step attempt of every `active` lane (as one pass of `Core::step`'s loop),
    /// then each lane's error test: accepted, the step is held; rejected, the next
    /// attempt is set up (or the lane fails).
    fn attempt<S: LaneSystem<N, B> + ?Sized>(&mut self, system: &mut S, active: &[bool; B]) {
        // The start of a step: its size, landing on tfinal when within 10 %.
        for lane in 0..B {
            if !(active[lane] && self.fresh[lane]) {
                continue;
            }
            let t = self.t[lane];
            let hmin = 16.0 * eps_of(t);
            let mut absh = self.hmax.min(hmin.max(self.absh[lane]));
            let mut h = self.tdir * absh;
            let mut done = false;
            if 1.1 * absh >= (self.tfinal - t).abs() {
                h = self.tfinal - t;
                absh = h.abs();
                done = true;
            }
            (self.hmin[lane], self.absh[lane], self.attempt_h[lane]) = (hmin, absh, h);
            (self.attempt_done[lane], self.attempt_nofailed[lane]) = (done, true);
            self.fresh[lane] = false;
        }
        self.stages(system, active);
        for lane in (0..B).filter(|&l| active[l]) {
            self.stats[lane].rhs_evaluations += 6;
            if self.trial.err[lane] <= self.rtol {
                self.accept(lane);
            } else {
                self.reject(lane);
            }
        }
    }

    /// The stages, new state and error of one attempt, all lanes at once.
    fn stages<S: LaneSystem<N, B> + ?Sized>(&mut self, system: &mut S, active: &[bool; B]) {
        let h = self.attempt_h;
        let a = &mut self.trial;
        a.k[0] = self.k[0];
        let mut t = [0.0; B];
        // Stages 2..6 (index 1..5) at t + c_i h: stage = y + Σ_j (h·a_ij)·k_j.
        for i in 1..6 {
            let mut stage = self.y;
            for j in 0..i {
                if A[i][j] != 0.0 {
                    for (s, k) in stage.iter_mut().zip(&a.k[j]) {
                        for l in 0..B {
                            s[l] += h[l] * A[i][j] * k[l];
                        }
                    }
                }
            }
            for l in 0..B {
                t[l] = self.t[l] + C[i] * h[l];
            }
            system.rhs(active, &t, &stage, &mut a.k[i]);
        }
        a.ynew = self.y;
        for l in 0..B {
            a.tnew[l] = if self.attempt_done[l] {
                self.tfinal
            } else {
                self.t[l] + C[6] * h[l]
            };
            a.h[l] = a.tnew[l] - self.t[l]; // purified; ynew uses the unpurified h
        }
        for j in 0..6 {
            if A[6][j] != 0.0 {
                for (s, k) in a.ynew.iter_mut().zip(&a.k[j]) {
                    for l in 0..B {
                        s[l] += h[l] * A[6][j] * k[l];
                    }
                }
            }
        }
        let (tnew, ynew) = (a.tnew, a.ynew);
        system.rhs(active, &tnew, &ynew, &mut a.k[6]);
        // Error estimate: Σ_j E_j·k_j from zero, then the scaled max norm.
        let mut error = [[0.0; B]; N];
        for (e, kj) in E.iter().zip(&a.k) {
            if *e != 0.0 {
                for (s, k) in error.iter_mut().zip(kj) {
                    for l in 0..B {
                        s[l] += e * k[l];
                    }
                }
            }
        }
        for l in (0..B).filter(|&l| active[l]) {
            let norm = scaled_norm(&error, &self.y, &a.ynew, self.threshold, l);
            a.err[l] = self.absh[l] * norm;
        }
    }

    fn accept(&mut self, lane: usize) {
        let a = &self.trial;
        self.stats[lane].accepted_steps += 1;
        for i in 1..7 {
            for r in 0..N {
                self.k[i][r][lane] = a.k[i][r][lane];
            }
        }
        for r in 0..N {
            self.ynew[r][lane] = a.ynew[r][lane];
        }
        (self.tnew[lane], self.h[lane], self.err[lane]) = (a.tnew[lane], a.h[lane], a.err[lane]);
        (self.nofailed[lane], self.done[lane]) =
            (self.attempt_nofailed[lane], self.attempt_done[lane]);
        self.pending[lane] = true;
        self.poly[lane] = None;
    }

    fn reject(&mut self, lane: usize) {
        let a = &self.trial;
        self.stats[lane].rejected_steps += 1;
        let (absh, hmin, err) = (self.absh[lane], self.hmin[lane], a.err[lane]);
        if absh <= hmin {
            let t = self.t[lane];
            let error = if !err.is_finite() {
                let component = (0..N)
                    .find(|&r| !a.ynew[r][lane].is_finite())
                    .or_else(|| (0..N).find(|&r| !a.k[6][r][lane].is_finite()))
                    .unwrap_or(0);
                OdeError::NonFiniteState { t, component }
            } else {
                OdeError::StepSizeUnderflow { t, step: absh }
            };
            self.status[lane] = Status::Failed(Some(error));
            return;
        }
        self.absh[lane] = if self.attempt_nofailed[lane] && err.is_finite() {
            hmin.max(absh * 0.1f64.max(0.8 * (self.rtol / err).powf(POW)))
        } else {
            hmin.max(0.5 * absh)
        };
        self.attempt_nofailed[lane] = false;
        self.attempt_h[lane] = self.tdir * self.absh[lane];
        self.attempt_done[lane] = false;
    }
}

/// ‖v ./ max(|y|, |ynew|, threshold)‖∞ for `lane`, as `scaled_norm`. NaN in `v` gives
/// NaN.
fn scaled_norm<const N: usize, const B: usize>(
    v: &[[f64; B]; N],
    y: &[[f64; B]; N],
    ynew: &[[f64; B]; N],
    threshold: f64,
    lane: usize,
) -> f64 {
    let mut norm = 0.0f64;
    for r in 0..N {
        let scale = y[r][lane].abs().max(ynew[r][lane].abs()).max(threshold);
        let ratio = (v[r][lane] / scale).abs();
        if ratio.is_nan() {
            return f64::NAN;
        }
        norm = norm.max(ratio);
    }
    norm
}
