//! One Dormand–Prince step at a time: the state between steps and the step itself,
//! shared by [`ode45_with`](crate::dopri::ode45_with) and [`Ode45Stepper`](crate::dopri::Ode45Stepper)
//! so that both perform exactly the same arithmetic.

use super::{eps_of, first_non_finite, scaled_norm};
use crate::error::OdeError;
use crate::options::{Ode45Options, Stats};
use crate::system::OdeSystem;
use crate::tableau::{A, C, E, INTERPOLANT};
use nalgebra::SVector;

pub(crate) const POW: f64 = 1.0 / 5.0;

/// The solver between two steps: (t, y) and the stages of the last step, the step-size
/// state, and — after [`Core::step`] — the accepted step to (tnew, ynew).
#[derive(Debug, Clone)]
pub(crate) struct Core<const N: usize> {
    rtol: f64,
    threshold: f64,
    hmax: f64,
    tfinal: f64,
    pub(crate) tdir: f64,
    max_steps: usize,
    pub(crate) stats: Stats,
    /// Start of the current step.
    pub(crate) t: f64,
    pub(crate) y: SVector<f64, N>,
    /// Stages; k[0] = f(t, y), k[6] = f(tnew, ynew) after a step.
    pub(crate) k: [SVector<f64, N>; 7],
    absh: f64,
    /// The accepted step ends at tfinal.
    pub(crate) done: bool,
    /// End of the accepted step, its state and its (purified) size.
    pub(crate) tnew: f64,
    pub(crate) ynew: SVector<f64, N>,
    pub(crate) h: f64,
    err: f64,
    nofailed: bool,
    stage: SVector<f64, N>,
}

impl<const N: usize> Core<N> {
    /// The solver at (t0, y0) towards `tfinal` (≠ t0), with ode45's initial step.
    /// `options` must be valid and `y0` finite.
    pub(crate) fn new<S: OdeSystem<N> + ?Sized>(
        system: &mut S,
        t0: f64,
        tfinal: f64,
        y0: &SVector<f64, N>,
        options: &Ode45Options,
    ) -> Result<Self, OdeError> {
        debug_assert!(options.validate().is_ok() && tfinal != t0);
        let tdir = (tfinal - t0).signum();
        let htspan = (tfinal - t0).abs();
        let rtol = options.rel_tol;
        let threshold = options.abs_tol / rtol;
        let hmax = options.max_step.unwrap_or(0.1 * htspan);
        let mut k = [SVector::<f64, N>::zeros(); 7];
        system.rhs(t0, y0, &mut k[0]);
        let stats = Stats {
            rhs_evaluations: 1,
            ..Stats::default()
        };
        if let Some(component) = first_non_finite(&k[0]) {
            return Err(OdeError::NonFiniteState { t: t0, component });
        }
        // Initial step, as ode45.m.
        let hmin = 16.0 * eps_of(t0);
        let absh = match options.initial_step {
            Some(htry) => hmax.min(hmin.max(htry)),
            None => {
                let mut absh = hmax.min(htspan);
                let rh = scaled_norm(&k[0], y0, y0, threshold) / (0.8 * rtol.powf(POW));
                if absh * rh > 1.0 {
                    absh = 1.0 / rh;
                }
                absh.max(hmin)
            }
        };
        Ok(Self {
            rtol,
            threshold,
            hmax,
            tfinal,
            tdir,
            max_steps: options.max_steps,
            stats,
            t: t0,
            y: *y0,
            k,
            absh,
            done: false,
            tnew: t0,
            ynew: *y0,
            h: 0.0,
            err: 0.0,
            nofailed: true,
            stage: SVector::zeros(),
        })
    }

    /// Attempts steps from (t, y) until one passes the error test; it ends at
    /// (tnew, ynew) with stages `k`, and `done` tells whether it reached tfinal.
    pub(crate) fn step<S: OdeSystem<N> + ?Sized>(
        &mut self,
        system: &mut S,
    ) -> Result<(), OdeError> {
        debug_assert!(!self.done);
        let (t, tdir, rtol) = (self.t, self.tdir, self.rtol);
        let hmin = 16.0 * eps_of(t);
        let mut absh = self.hmax.min(hmin.max(self.absh));
        let mut h = tdir * absh;
        let mut done = false;
        if 1.1 * absh >= (self.tfinal - t).abs() {
            h = self.tfinal - t;
            absh = h.abs();
            done = true;
        }
        let (k, stage, y, ynew) = (&mut self.k, &mut self.stage, &self.y, &mut self.ynew);
        let mut nofailed = true;
        let (tnew, err) = loop {
            // Stages 2..6 (index 1..5) at t + c_i h.
            for i in 1..6 {
                stage.copy_from(y);
                for j in 0..i {
                    let a = A[i][j];
                    if a != 0.0 {
                        stage.axpy(h * a, &k[j], 1.0);
                    }
                }
                system.rhs(t + C[i] * h, stage, &mut k[i]);
            }
            let mut tnew = t + C[6] * h;
            if done {
                tnew = self.tfinal;
            }
            let hb = h; // ynew uses the unpurified h, as ode45.m
            h = tnew - t; // purify h
            ynew.copy_from(y);
            for (j, kj) in k.iter().enumerate().take(6) {
                let b = A[6][j];
                if b != 0.0 {
                    ynew.axpy(hb * b, kj, 1.0);
                }
            }
            system.rhs(tnew, ynew, &mut k[6]);
            self.stats.rhs_evaluations += 6;

            // Error estimate, as ode45.m with NormControl off.
            stage.fill(0.0);
            for (j, kj) in k.iter().enumerate() {
                if E[j] != 0.0 {
                    stage.axpy(E[j], kj, 1.0);
                }
            }
            let err = absh * scaled_norm(stage, y, ynew, self.threshold);
            if err <= rtol {
                break (tnew, err);
            }
            // Failed step (also when err is NaN: the right-hand side was not finite).
            self.stats.rejected_steps += 1;
            if absh <= hmin {
                if !err.is_finite() {
                    let component = first_non_finite(ynew)
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
        self.stats.accepted_steps += 1;
        debug_assert!(err.is_finite() && self.ynew.iter().all(|v| v.is_finite()));
        (self.absh, self.h, self.tnew, self.err) = (absh, h, tnew, err);
        (self.nofailed, self.done) = (nofailed, done);
        Ok(())
    }

    /// Moves to the end of the accepted step (after its output), with ode45's step
    /// growth; refuses to go past `max_steps`.
    pub(crate) fn advance(&mut self) -> Result<(), OdeError> {
        debug_assert!(!self.done);
        if self.stats.accepted_steps >= self.max_steps {
            return Err(OdeError::TooManySteps {
                t: self.tnew,
                steps: self.stats.accepted_steps,
            });
        }
        if self.nofailed {
            let temp = 1.25 * (self.err / self.rtol).powf(POW);
            self.absh = if temp > 0.2 {
                self.absh / temp
            } else {
                5.0 * self.absh
            };
        }
        self.t = self.tnew;
        self.y = self.ynew;
        self.k[0] = self.k[6];
        Ok(())
    }

    /// The accepted step's continuous extension.
    pub(crate) fn interpolant(&self) -> Interpolant<N> {
        Interpolant::new(&self.y, self.h, &self.k)
    }
}

/// ode45's `ntrp45` for one step, as a polynomial in s = (t − tₙ)/h:
/// y(s) = yₙ + q₀ s + q₁ s² + q₂ s³ + q₃ s⁴ with q_j = h Σᵢ BIᵢⱼ kᵢ, evaluated by Horner.
/// Building it costs one pass over the stages per step; each output point then costs
/// four multiply-adds per component.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Interpolant<const N: usize> {
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
    pub(crate) fn eval_into(&self, out: &mut SVector<f64, N>, s: f64) {
        for i in 0..N {
            let p = ((self.q[3][i] * s + self.q[2][i]) * s + self.q[1][i]) * s + self.q[0][i];
            out[i] = self.y[i] + p * s;
        }
    }
}
