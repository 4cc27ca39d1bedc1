//! Levenberg–Marquardt for nonlinear least squares, after MINPACK's `lmder`
//! (Moré, 1978, "The Levenberg–Marquardt algorithm: implementation and theory"),
//! with box bounds.
//!
//! ## The algorithm
//! Minimise `‖r(x)‖²` over `lower ≤ x ≤ upper`. Each outer iteration forms the
//! Jacobian J at the current x, factors it by Householder QR with column pivoting,
//! and scales the variables by `D = diag(max over iterations of ‖J column‖)`
//! (MINPACK mode 1; a fixed `diagonal` gives mode 2). The step p solves the damped
//! problem `min ‖J·p + r‖² + λ‖D·p‖²` with λ chosen by Moré's `lmpar` so that
//! `‖D·p‖ ≈ Δ`; the system is solved stably from the QR factors by Givens
//! rotations (`qrsolv`), never by forming JᵀJ. The trust radius Δ starts at
//! `initial_step_bound · ‖D·x0‖` and is updated from the ratio of actual to
//! predicted reduction exactly as `lmder` does; a step is accepted when the ratio
//! is at least 1e-4.
//!
//! **Termination** (MINPACK's `info`): relative reduction (actual and predicted)
//! at most `f_tolerance`; trust radius at most `x_tolerance·‖D·x‖`; the cosine
//! between r and every column of J at most `g_tolerance`; the evaluation limit; or
//! one of the tolerances so small that no further progress is possible.
//!
//! **Bounds** (an addition to MINPACK): x0 is projected onto the box; at each
//! outer iteration a variable on a bound whose gradient component `(Jᵀr)_j` pushes
//! outward is held fixed (its Jacobian column is zeroed for the step computation,
//! which makes its step component exactly zero); every trial point is projected
//! onto the box, and when projection shortens the step the predicted reduction is
//! recomputed from the projected step. Finite-difference steps stay inside the box.
//! A step that projection shrinks to zero length ends the run with
//! [`LmExit::XTolerance`]. Without bounds the method is `lmder` step for step.
//!
//! **Non-finite residuals** at a trial point count as a failed step: the trust
//! region shrinks and the point is never accepted.
//!
//! ## Call order
//! The solver calls `residuals(x)` first at x0, then for each trial point. It calls
//! `jacobian(x)` only at a point x whose residuals were the last ones evaluated
//! (x0, or a trial point just accepted), so a problem may compute residuals and
//! Jacobian in one simulation and hand the cached Jacobian over. When the run
//! ends right after an accepted step, `jacobian` is called once more at the final
//! x (again right after its residuals) so the result carries J at the solution.
//!
//! ```
//! use msd_opt::{levenberg_marquardt, LevenbergMarquardtOptions, ResidualFn};
//!
//! // Fit y = a·exp(b·t) to exact data from a = 2, b = −0.5.
//! let t: Vec<f64> = (0..10).map(|i| i as f64 * 0.5).collect();
//! let y: Vec<f64> = t.iter().map(|t| 2.0 * (-0.5 * t).exp()).collect();
//! let mut problem = ResidualFn::new(t.len(), |x: &[f64], r: &mut [f64]| {
//!     for ((ri, ti), yi) in r.iter_mut().zip(&t).zip(&y) {
//!         *ri = x[0] * (x[1] * ti).exp() - yi;
//!     }
//!     true
//! });
//! let fit = levenberg_marquardt(&mut problem, &[1.0, 0.0], &LevenbergMarquardtOptions::default())
//!     .unwrap();
//! assert!(fit.exit.is_success());
//! assert!((fit.x[0] - 2.0).abs() < 1e-8 && (fit.x[1] + 0.5).abs() < 1e-8);
//! assert_eq!(fit.jacobian.shape(), (10, 2));
//! ```

// A translation of MINPACK keeps its index loops, which read like the Fortran.
#![allow(clippy::needless_range_loop)]

mod minpack;
mod types;

use nalgebra::DMatrix;

use crate::error::OptError;
use crate::error::check_start;
use minpack::{enorm, lmpar, qrfac};
pub use types::{
    FiniteDifference, LeastSquaresProblem, LevenbergMarquardtOptions, LevenbergMarquardtResult,
    LmExit, ResidualFn,
};

/// Work arrays, allocated once per solve.
struct Work {
    jac: DMatrix<f64>,
    qr: Vec<f64>,
    ipvt: Vec<usize>,
    rdiag: Vec<f64>,
    qr_norms: Vec<f64>,
    col_norms: Vec<f64>,
    diag: Vec<f64>,
    qtf: Vec<f64>,
    step: Vec<f64>,
    trial: Vec<f64>,
    sdiag: Vec<f64>,
    wa1: Vec<f64>,
    wa2: Vec<f64>,
    wa3: Vec<f64>,
    wa4: Vec<f64>,
    f_trial: Vec<f64>,
    f_minus: Vec<f64>,
    x_fd: Vec<f64>,
}

impl Work {
    /// QR with column pivoting of the Jacobian, with the columns of the active set (the
    /// variables on a bound that the gradient Jᵀr pushes outward) zeroed; the column
    /// norms of J.
    fn factor(&mut self, x: &[f64], fvec: &[f64], options: &LevenbergMarquardtOptions) {
        let (m, n) = self.jac.shape();
        let w = self;
        w.qr.copy_from_slice(w.jac.as_slice());
        for j in 0..n {
            let column = &w.jac.as_slice()[j * m..(j + 1) * m];
            w.col_norms[j] = enorm(column);
            if let Some(b) = &options.bounds {
                let g: f64 = column.iter().zip(fvec).map(|(a, r)| a * r).sum();
                let fixed = b.lower[j] == b.upper[j];
                let at_lower = x[j] <= b.lower[j] && g > 0.0;
                let at_upper = x[j] >= b.upper[j] && g < 0.0;
                if fixed || at_lower || at_upper {
                    w.qr[j * m..(j + 1) * m].iter_mut().for_each(|v| *v = 0.0);
                }
            }
        }
        qrfac(
            m,
            n,
            &mut w.qr,
            &mut w.ipvt,
            &mut w.rdiag,
            &mut w.qr_norms,
            &mut w.wa1,
        );
    }

    /// The first iteration's diagonal scaling (the column norms, or the given one), the
    /// scaled norm of x and the initial trust radius.
    fn initial_scaling(&mut self, x: &[f64], options: &LevenbergMarquardtOptions) -> (f64, f64) {
        let n = x.len();
        let w = self;
        match &options.diagonal {
            Some(d) => w.diag.copy_from_slice(d),
            None => {
                for j in 0..n {
                    w.diag[j] = if w.col_norms[j] == 0.0 {
                        1.0
                    } else {
                        w.col_norms[j]
                    };
                }
            }
        }
        for j in 0..n {
            w.wa3[j] = w.diag[j] * x[j];
        }
        let xnorm = enorm(&w.wa3);
        let mut delta = options.initial_step_bound * xnorm;
        if delta == 0.0 {
            delta = options.initial_step_bound;
        }
        (xnorm, delta)
    }

    /// Forms qtf = the first n components of Qᵀ·r (R's diagonal back in place) and
    /// returns the scaled gradient norm: the largest cosine between r and a column of J.
    fn gradient_norm(&mut self, fvec: &[f64], fnorm: f64) -> f64 {
        let (m, n) = self.jac.shape();
        let w = self;
        w.wa4.copy_from_slice(fvec);
        for j in 0..n {
            let cj = j * m;
            if w.qr[cj + j] != 0.0 {
                let mut sum = 0.0;
                for i in j..m {
                    sum += w.qr[cj + i] * w.wa4[i];
                }
                let temp = -sum / w.qr[cj + j];
                for i in j..m {
                    w.wa4[i] += w.qr[cj + i] * temp;
                }
            }
            w.qr[cj + j] = w.rdiag[j];
            w.qtf[j] = w.wa4[j];
        }

        let mut gnorm = 0.0_f64;
        if fnorm != 0.0 {
            for j in 0..n {
                let l = w.ipvt[j];
                if w.qr_norms[l] != 0.0 {
                    let mut sum = 0.0;
                    for i in 0..=j {
                        sum += w.qr[i + j * m] * (w.qtf[i] / fnorm);
                    }
                    gnorm = gnorm.max((sum / w.qr_norms[l]).abs());
                }
            }
        }
        gnorm
    }

    /// The predicted reduction of ‖r‖² by the step and the directional derivative, both
    /// scaled by ‖r‖²: from R for an interior step, from J along a projected (clipped) one.
    fn predicted_reduction(
        &mut self,
        fvec: &[f64],
        fnorm: f64,
        par: f64,
        pnorm: f64,
        clipped: bool,
    ) -> (f64, f64) {
        let (m, n) = self.jac.shape();
        let w = self;
        if !clipped {
            for j in 0..n {
                w.wa3[j] = 0.0;
            }
            for j in 0..n {
                let temp = w.step[w.ipvt[j]];
                for i in 0..=j {
                    w.wa3[i] += w.qr[i + j * m] * temp;
                }
            }
            let temp1 = enorm(&w.wa3) / fnorm;
            let temp2 = (par.sqrt() * pnorm) / fnorm;
            (
                temp1 * temp1 + temp2 * temp2 / 0.5,
                -(temp1 * temp1 + temp2 * temp2),
            )
        } else {
            // Linear model along the projected step: ‖r + J·p‖².
            w.wa4.iter_mut().for_each(|v| *v = 0.0);
            for j in 0..n {
                let pj = w.step[j];
                if pj != 0.0 {
                    for (acc, a) in w.wa4.iter_mut().zip(&w.jac.as_slice()[j * m..]) {
                        *acc += a * pj;
                    }
                }
            }
            let jp = enorm(&w.wa4) / fnorm;
            let rjp: f64 =
                w.wa4.iter().zip(fvec).map(|(a, r)| a * r).sum::<f64>() / (fnorm * fnorm);
            (-(2.0 * rjp + jp * jp), rjp)
        }
    }

    /// The trial point x + p for the step p that lmpar left in `step` (negated), projected
    /// onto the bounds; returns the scaled step norm ‖D·p‖ and whether the projection
    /// clipped the step.
    fn trial_step(&mut self, x: &[f64], options: &LevenbergMarquardtOptions) -> (f64, bool) {
        let n = x.len();
        let w = self;
        let mut clipped = false;
        for j in 0..n {
            w.step[j] = -w.step[j];
            w.trial[j] = x[j] + w.step[j];
        }
        if let Some(b) = &options.bounds {
            b.project(&mut w.trial);
            for j in 0..n {
                let p = w.trial[j] - x[j];
                if p != w.step[j] {
                    clipped = true;
                    w.step[j] = p;
                }
            }
        }
        debug_assert!(options.bounds.as_ref().is_none_or(|b| b.contains(&w.trial)));
        for j in 0..n {
            w.wa3[j] = w.diag[j] * w.step[j];
        }
        let pnorm = enorm(&w.wa3);
        (pnorm, clipped)
    }

    fn new(m: usize, n: usize) -> Self {
        Self {
            jac: DMatrix::zeros(m, n),
            qr: vec![0.0; m * n],
            ipvt: vec![0; n],
            rdiag: vec![0.0; n],
            qr_norms: vec![0.0; n],
            col_norms: vec![0.0; n],
            diag: vec![1.0; n],
            qtf: vec![0.0; n],
            step: vec![0.0; n],
            trial: vec![0.0; n],
            sdiag: vec![0.0; n],
            wa1: vec![0.0; n],
            wa2: vec![0.0; n],
            wa3: vec![0.0; n],
            wa4: vec![0.0; m],
            f_trial: vec![0.0; m],
            f_minus: vec![0.0; m],
            x_fd: vec![0.0; n],
        }
    }
}

fn residuals_ok<P: LeastSquaresProblem + ?Sized>(p: &mut P, x: &[f64], out: &mut [f64]) -> bool {
    p.residuals(x, out) && out.iter().all(|v| v.is_finite())
}

/// Computes the Jacobian at `x` (whose residuals `fvec` were just evaluated) into
/// `w.jac`; returns the first non-finite entry, if any.
fn compute_jacobian<P: LeastSquaresProblem + ?Sized>(
    problem: &mut P,
    x: &[f64],
    fvec: &[f64],
    options: &LevenbergMarquardtOptions,
    w: &mut Work,
    fd_evaluations: &mut usize,
) -> Result<(), (usize, usize)> {
    if !problem.jacobian(x, &mut w.jac) {
        finite_differences(problem, x, fvec, options, w, fd_evaluations);
    }
    let m = w.jac.nrows();
    match w.jac.as_slice().iter().position(|v| !v.is_finite()) {
        Some(k) => Err((k % m, k / m)),
        None => Ok(()),
    }
}

/// Finite-difference Jacobian, each step kept inside the bounds: a forward step
/// that would leave the box is taken backward (or to the farther bound); a central
/// difference that would leave the box falls back to that one-sided step.
fn finite_differences<P: LeastSquaresProblem + ?Sized>(
    problem: &mut P,
    x: &[f64],
    fvec: &[f64],
    options: &LevenbergMarquardtOptions,
    w: &mut Work,
    fd_evaluations: &mut usize,
) {
    let m = fvec.len();
    let central = options.finite_difference == FiniteDifference::Central;
    let rel = options.finite_difference_step.unwrap_or(if central {
        f64::EPSILON.cbrt()
    } else {
        f64::EPSILON.sqrt()
    });
    w.x_fd.copy_from_slice(x);
    for j in 0..x.len() {
        let (l, u) = match &options.bounds {
            Some(b) => (b.lower[j], b.upper[j]),
            None => (f64::NEG_INFINITY, f64::INFINITY),
        };
        let mut h = rel * x[j].abs();
        if h == 0.0 {
            h = rel;
        }
        let column = &mut w.jac.as_mut_slice()[j * m..(j + 1) * m];
        if central && x[j] - h >= l && x[j] + h <= u {
            w.x_fd[j] = x[j] + h;
            let ok_plus = residuals_ok(problem, &w.x_fd, &mut w.f_trial);
            w.x_fd[j] = x[j] - h;
            let ok_minus = residuals_ok(problem, &w.x_fd, &mut w.f_minus);
            *fd_evaluations += 2;
            let h2 = (x[j] + h) - (x[j] - h);
            for i in 0..m {
                column[i] = if ok_plus && ok_minus {
                    (w.f_trial[i] - w.f_minus[i]) / h2
                } else {
                    f64::NAN
                };
            }
        } else {
            if x[j] + h > u {
                h = if x[j] - h >= l {
                    -h
                } else if u - x[j] >= x[j] - l {
                    u - x[j]
                } else {
                    l - x[j]
                };
            }
            if h == 0.0 {
                // A fixed variable (lower = upper): no direction to move in.
                column.iter_mut().for_each(|c| *c = 0.0);
                continue;
            }
            w.x_fd[j] = x[j] + h;
            let h_exact = w.x_fd[j] - x[j];
            let ok = residuals_ok(problem, &w.x_fd, &mut w.f_trial);
            *fd_evaluations += 1;
            for i in 0..m {
                column[i] = if ok {
                    (w.f_trial[i] - fvec[i]) / h_exact
                } else {
                    f64::NAN
                };
            }
        }
        w.x_fd[j] = x[j];
    }
}

/// MINPACK's update of the trust radius `delta` and the Levenberg–Marquardt parameter
/// `par` from the step's ratio of actual to predicted reduction.
fn update_radius(
    ratio: f64,
    [actred, dirder]: [f64; 2],
    [fnorm, fnorm1, pnorm]: [f64; 3],
    delta: &mut f64,
    par: &mut f64,
) {
    if ratio <= 0.25 {
        let mut temp = if actred >= 0.0 {
            0.5
        } else {
            0.5 * dirder / (dirder + 0.5 * actred)
        };
        if 0.1 * fnorm1 >= fnorm || temp < 0.1 || !temp.is_finite() {
            temp = 0.1;
        }
        *delta = temp * delta.min(pnorm / 0.1);
        *par /= temp;
    } else if *par == 0.0 || ratio >= 0.75 {
        *delta = pnorm / 0.5;
        *par *= 0.5;
    }
}

/// What the convergence tests look at after a step.
struct Tests {
    actred: f64,
    prered: f64,
    ratio: f64,
    delta: f64,
    xnorm: f64,
    gnorm: f64,
    nfev: usize,
}

impl Tests {
    /// Why to stop, if so: the tolerances met, else the evaluation budget or a tolerance
    /// too small for double precision (the last one found wins, as MINPACK).
    fn stop(&self, options: &LevenbergMarquardtOptions, max_evaluations: usize) -> Option<LmExit> {
        let Tests {
            actred,
            prered,
            ratio,
            delta,
            xnorm,
            gnorm,
            nfev,
        } = *self;
        let eps = f64::EPSILON;
        let f_small = actred.abs() <= options.f_tolerance
            && prered <= options.f_tolerance
            && 0.5 * ratio <= 1.0;
        let x_small = delta <= options.x_tolerance * xnorm;
        match (f_small, x_small) {
            (true, true) => return Some(LmExit::FAndXTolerance),
            (true, false) => return Some(LmExit::FTolerance),
            (false, true) => return Some(LmExit::XTolerance),
            (false, false) => {}
        }
        let mut stop = None;
        if nfev >= max_evaluations {
            stop = Some(LmExit::MaxEvaluations);
        }
        if actred.abs() <= eps && prered <= eps && 0.5 * ratio <= 1.0 {
            stop = Some(LmExit::FToleranceTooSmall);
        }
        if delta <= eps * xnorm {
            stop = Some(LmExit::XToleranceTooSmall);
        }
        if gnorm <= eps {
            stop = Some(LmExit::GToleranceTooSmall);
        }
        stop
    }
}

/// The start projected onto the bounds and its residuals, refused when they cannot be
/// evaluated or are not finite.
fn start<P: LeastSquaresProblem + ?Sized>(
    problem: &mut P,
    x0: &[f64],
    options: &LevenbergMarquardtOptions,
    m: usize,
) -> Result<(Vec<f64>, Vec<f64>), OptError> {
    let mut x = x0.to_vec();
    if let Some(b) = &options.bounds {
        b.project(&mut x);
    }
    let mut fvec = vec![0.0; m];
    if !problem.residuals(&x, &mut fvec) {
        return Err(OptError::InitialResiduals { index: None });
    }
    if let Some(index) = fvec.iter().position(|v| !v.is_finite()) {
        return Err(OptError::InitialResiduals { index: Some(index) });
    }
    Ok((x, fvec))
}

/// Refuses what cannot start: an empty or non-finite start, invalid options, fewer
/// residuals than parameters, bounds or a diagonal of the wrong length. Returns (m, n).
fn check_inputs<P: LeastSquaresProblem + ?Sized>(
    problem: &P,
    x0: &[f64],
    options: &LevenbergMarquardtOptions,
) -> Result<(usize, usize), OptError> {
    check_start(x0)?;
    options.validate()?;
    let n = x0.len();
    let m = problem.residual_count();
    if m < n {
        return Err(OptError::TooFewResiduals {
            residuals: m,
            parameters: n,
        });
    }
    if let Some(b) = &options.bounds {
        b.validate_for(n)?;
    }
    if let Some(d) = &options.diagonal
        && d.len() != n
    {
        return Err(OptError::LengthMismatch {
            what: "diagonal vs x0",
            expected: n,
            found: d.len(),
        });
    }
    Ok((m, n))
}

impl Work {
    /// MINPACK's `lmpar` on the factored Jacobian: the Levenberg–Marquardt parameter for
    /// the trust radius `delta` from the previous `par`, the step in `step`.
    fn levenberg_parameter(&mut self, delta: f64, par: f64) -> f64 {
        let (m, n) = self.jac.shape();
        lmpar(
            n,
            &mut self.qr,
            m,
            &self.ipvt,
            &self.diag,
            &self.qtf,
            delta,
            par,
            &mut self.step,
            &mut self.sdiag,
            &mut self.wa1,
            &mut self.wa2,
        )
    }

    /// The scaling D = max(D, column norms of J), as lmder does without a given `diag`.
    fn raise_diagonal(&mut self) {
        for (d, c) in self.diag.iter_mut().zip(&self.col_norms) {
            *d = d.max(*c);
        }
    }

    /// The residuals at the trial point and their norm (infinite where they are not
    /// finite).
    fn trial_norm<P: LeastSquaresProblem + ?Sized>(&mut self, problem: &mut P) -> f64 {
        if residuals_ok(problem, &self.trial, &mut self.f_trial) {
            enorm(&self.f_trial)
        } else {
            f64::INFINITY
        }
    }

    /// Takes the trial point and its residuals as the new iterate; ‖D·x‖.
    fn accept(&mut self, x: &mut [f64], fvec: &mut [f64]) -> f64 {
        let n = x.len();
        x.copy_from_slice(&self.trial);
        fvec.copy_from_slice(&self.f_trial);
        for j in 0..n {
            self.wa2[j] = self.diag[j] * x[j];
        }
        enorm(&self.wa2[..n])
    }
}

/// The actual reduction 1 − (‖r₁‖/‖r‖)², −1 where the trial's norm is ten times the
/// current one or more (MINPACK's guard against overflow).
fn actual_reduction(fnorm: f64, fnorm1: f64) -> f64 {
    if 0.1 * fnorm1 < fnorm {
        1.0 - (fnorm1 / fnorm).powi(2)
    } else {
        -1.0
    }
}

/// Solves `min ‖r(x)‖²` (within the bounds, if any) from `x0` by MINPACK's
/// Levenberg–Marquardt method.
///
/// # Errors
/// Bad input ([`OptError::EmptyStart`], [`OptError::NonFiniteStart`], an invalid
/// option, bounds or diagonal that do not fit, [`OptError::TooFewResiduals`]), or a
/// problem that cannot be started ([`OptError::InitialResiduals`],
/// [`OptError::InitialJacobian`]). Everything after the start ends in an [`LmExit`].
pub fn levenberg_marquardt<P: LeastSquaresProblem + ?Sized>(
    problem: &mut P,
    x0: &[f64],
    options: &LevenbergMarquardtOptions,
) -> Result<LevenbergMarquardtResult, OptError> {
    let (m, n) = check_inputs(problem, x0, options)?;
    let max_evaluations = options.max_evaluations.unwrap_or(100 * (n + 1));

    let mut w = Work::new(m, n);
    let (mut x, mut fvec) = start(problem, x0, options, m)?;
    let mut nfev = 1;
    let mut njev = 0;
    let mut fd_evaluations = 0;
    let mut fnorm = enorm(&fvec);
    let mut par = 0.0;
    let mut iter = 1; // MINPACK's counter: 1 + accepted steps
    let mut delta = 0.0;
    let mut xnorm = 0.0;
    let mut jacobian_current: bool;

    let exit = 'outer: loop {
        // Jacobian at x: the last residual evaluation was at this x.
        njev += 1;
        jacobian_current = true;
        if let Err((row, column)) =
            compute_jacobian(problem, &x, &fvec, options, &mut w, &mut fd_evaluations)
        {
            if njev == 1 {
                return Err(OptError::InitialJacobian { row, column });
            }
            break LmExit::NonFiniteJacobian;
        }

        w.factor(&x, &fvec, options);

        if iter == 1 {
            (xnorm, delta) = w.initial_scaling(&x, options);
        }

        let gnorm = w.gradient_norm(&fvec, fnorm);
        if gnorm <= options.g_tolerance {
            break LmExit::Gradient;
        }
        if options.diagonal.is_none() {
            w.raise_diagonal();
        }

        // Inner loop: find an acceptable step.
        loop {
            par = w.levenberg_parameter(delta, par);
            let (pnorm, clipped) = w.trial_step(&x, options);
            if pnorm == 0.0 {
                break 'outer LmExit::XTolerance;
            }
            if iter == 1 {
                delta = delta.min(pnorm);
            }

            let fnorm1 = w.trial_norm(problem);
            nfev += 1;
            let actred = actual_reduction(fnorm, fnorm1);

            // Predicted reduction and directional derivative, both scaled by ‖r‖².
            let (prered, dirder) = w.predicted_reduction(&fvec, fnorm, par, pnorm, clipped);
            let ratio = if prered > 0.0 { actred / prered } else { 0.0 };

            update_radius(
                ratio,
                [actred, dirder],
                [fnorm, fnorm1, pnorm],
                &mut delta,
                &mut par,
            );

            if ratio >= 1e-4 {
                xnorm = w.accept(&mut x, &mut fvec);
                fnorm = fnorm1;
                iter += 1;
                jacobian_current = false;
            }

            let tests = Tests {
                actred,
                prered,
                ratio,
                delta,
                xnorm,
                gnorm,
                nfev,
            };
            if let Some(reason) = tests.stop(options, max_evaluations) {
                break 'outer reason;
            }
            if ratio >= 1e-4 {
                break;
            }
        }
    };

    let mut exit = exit;
    if !jacobian_current {
        // The last residual evaluation was at x (the accepted step): J at the solution.
        njev += 1;
        if compute_jacobian(problem, &x, &fvec, options, &mut w, &mut fd_evaluations).is_err() {
            exit = LmExit::NonFiniteJacobian;
        }
    }
    Ok(LevenbergMarquardtResult {
        residual_norm: fnorm,
        cost: fnorm * fnorm,
        x,
        residuals: fvec,
        jacobian: w.jac,
        iterations: iter - 1,
        evaluations: nfev,
        jacobian_evaluations: njev,
        finite_difference_evaluations: fd_evaluations,
        exit,
    })
}
