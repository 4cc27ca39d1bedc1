//! Every modal parameter at once: the modal constants and residual terms for fixed poles
//! by linear least squares (LSFD), then all of them with the poles by weighted nonlinear
//! least squares, and the Gauss–Newton covariance.
//!
//! The parameters θ are, per mode, (ωn, ζ, A, B) (see
//! [`ModalParameters`](msd_modal_core::modal::ModalParameters)), then the lower and upper residual terms
//! (L, U) of H(ω) = Σ_r H_r(ω) − L/ω² + U.

use msd_opt::{
    LeastSquaresProblem, LevenbergMarquardtOptions, LevenbergMarquardtResult, levenberg_marquardt,
};
use msd_signal::Complex64;
use nalgebra::{DMatrix, DVector};

use msd_modal_core::error::{ModalError, Result, not_identifiable};
use msd_modal_core::input_noise::InputNoise;
use msd_modal_core::lines::{FrfWeighting, Lines, leverages};
use msd_modal_core::modal::{term, term_with_gradient};
use msd_modal_core::noise_check::NoiseCheck;
use msd_opt::statistics::Linearization;

/// Parameters per mode.
pub(crate) const PER_MODE: usize = 4;

/// The model's receptance at ω for θ.
pub(crate) fn model(theta: &[f64], w: f64) -> Complex64 {
    let (modes, residual) = theta.split_at(theta.len() - 2);
    let sum: Complex64 = modes.chunks_exact(PER_MODE).map(|m| term(m, w)).sum();
    sum + Complex64::new(residual[1] - residual[0] / (w * w), 0.0)
}

/// The modal constants and residual terms for the poles (ωn, ζ) by weighted linear
/// least squares (columns scaled to unit norm, normal equations by Cholesky): the full θ.
pub(crate) fn lsfd(lines: &Lines, poles: &[(f64, f64)]) -> Result<Vec<f64>> {
    let (a, b) = lsfd_system(lines, poles);
    lsfd_solve(a, &b, poles)
}

/// The weighted LSFD system for the poles (ωn, ζ): the design matrix (2K × (2M + 2):
/// per mode the columns of A and of B, then L and U; real parts in the first K rows,
/// imaginary parts in the last K) and the weighted data.
pub(crate) fn lsfd_system(lines: &Lines, poles: &[(f64, f64)]) -> (DMatrix<f64>, DVector<f64>) {
    let n = lines.omega.len();
    let p = 2 * poles.len() + 2;
    let mut a = DMatrix::<f64>::zeros(2 * n, p);
    let mut b = DVector::<f64>::zeros(2 * n);
    for (k, ((&w, h), &s)) in lines
        .omega
        .iter()
        .zip(&lines.h)
        .zip(&lines.sigma)
        .enumerate()
    {
        for (r, &(wn, zeta)) in poles.iter().enumerate() {
            for (i, theta) in [[wn, zeta, 1.0, 0.0], [wn, zeta, 0.0, 1.0]]
                .iter()
                .enumerate()
            {
                let c = term(theta, w);
                a[(k, 2 * r + i)] = c.re / s;
                a[(n + k, 2 * r + i)] = c.im / s;
            }
        }
        // −L/ω² and U, both real.
        a[(k, p - 2)] = -1.0 / (w * w * s);
        a[(k, p - 1)] = 1.0 / s;
        b[k] = h.re / s;
        b[n + k] = h.im / s;
    }
    (a, b)
}

/// Continues [`lsfd`]: the solution of the scaled normal equations.
fn lsfd_solve(mut a: DMatrix<f64>, b: &DVector<f64>, poles: &[(f64, f64)]) -> Result<Vec<f64>> {
    let p = a.ncols();
    let norms: Vec<f64> = a.column_iter().map(|c| c.norm()).collect();
    for (j, &norm) in norms.iter().enumerate() {
        a.column_mut(j).scale_mut(1.0 / norm);
    }
    let solution = (a.transpose() * &a)
        .cholesky()
        .map(|c| c.solve(&(a.transpose() * b)))
        .ok_or_else(|| ModalError::NotIdentifiable {
            reason: "the modal constants cannot be told apart (two poles too close?)".into(),
        })?;
    let mut theta = Vec::with_capacity(PER_MODE * poles.len() + 2);
    for (r, &(wn, zeta)) in poles.iter().enumerate() {
        let (j, i) = (2 * r, 2 * r + 1);
        theta.extend([wn, zeta, solution[j] / norms[j], solution[i] / norms[i]]);
    }
    theta.extend([
        solution[p - 2] / norms[p - 2],
        solution[p - 1] / norms[p - 1],
    ]);
    Ok(theta)
}

/// The result of [`polish`]: θ, its covariance and the solver's statistics.
pub(crate) struct Polished {
    pub theta: Vec<f64>,
    pub covariance: DMatrix<f64>,
    pub sigma: f64,
    pub degrees_of_freedom: usize,
    pub fit: LevenbergMarquardtResult,
    /// The residuals against the lines' own noise, where their σ are absolute.
    pub noise_check: Option<NoiseCheck>,
    /// The force's noise the lines were corrected for (or that was said), where known.
    pub input_noise: Option<InputNoise>,
}

/// Levenberg–Marquardt on every parameter from `start`, and the covariance s²N⁻¹ with
/// s² = SSE/(2K − p) and N the lines' [`effective_normal`](Lines::effective_normal).
pub(crate) fn polish(lines: &Lines, start: Vec<f64>) -> Result<Polished> {
    let scale = scales(lines, &start);
    let mut problem = ModalProblem {
        lines,
        scale: &scale,
        theta: vec![0.0; start.len()],
    };
    let x0: Vec<f64> = start.iter().zip(&scale).map(|(t, s)| t / s).collect();
    let fit = levenberg_marquardt(&mut problem, &x0, &LevenbergMarquardtOptions::default())?;
    if !fit.exit.is_success() {
        return Err(ModalError::EstimationFailed {
            reason: format!("the modal fit did not converge: {}", fit.exit),
        });
    }
    let theta: Vec<f64> = fit.x.iter().zip(&scale).map(|(x, s)| x * s).collect();
    // Uniform weights: each line's variance from the polished model's residuals.
    let scaled;
    let lines = if lines.weighting == FrfWeighting::Uniform {
        let mut l = lines.clone();
        l.residual_variances(|w| model(&theta, w), &leverages(&fit.jacobian));
        scaled = l;
        &scaled
    } else {
        lines
    };
    let (rows, p) = fit.jacobian.shape();
    // J in θ: the solver's J (in x) with each column divided by its scale.
    let jacobian = DMatrix::from_fn(rows, p, |i, j| fit.jacobian[(i, j)] / scale[j]);
    // Errors correlated from line to line: the sandwich, as a normal matrix, and the
    // residual's variance from the degrees of freedom the fit leaves it (rows − p for
    // independent lines).
    let (normal, taken) = lines.effective_normal(&jacobian);
    let residual_dof = (rows as f64 - taken).max(1.0);
    let s2 = lines.residual_variance(fit.cost, residual_dof);
    let degrees_of_freedom = residual_dof.floor() as usize;
    let covariance = covariance(&normal, s2)?;
    Ok(Polished {
        theta,
        covariance,
        sigma: s2.sqrt(),
        degrees_of_freedom,
        noise_check: lines.noise_check(fit.cost, &jacobian),
        input_noise: None,
        fit,
    })
}

/// s²N⁻¹, inverted with the columns scaled to unit norm.
fn covariance(normal: &DMatrix<f64>, s2: f64) -> Result<DMatrix<f64>> {
    Linearization::from_normal_matrix(normal)
        .map(|l| l.covariance(s2))
        .map_err(|e| not_identifiable(e, "the modal fit's lines", &[]))
}

/// Typical sizes of the parameters, so that the solver's variables are near 1: ωn and
/// ζ their starts, A and B the larger of the mode's |A|, |B|, the residual terms what
/// would give the median |H| at the lowest line (L) or anywhere (U).
fn scales(lines: &Lines, start: &[f64]) -> Vec<f64> {
    let mut magnitudes: Vec<f64> = lines.h.iter().map(|h| h.norm()).collect();
    magnitudes.sort_by(f64::total_cmp);
    let typical = magnitudes[magnitudes.len() / 2].max(f64::MIN_POSITIVE);
    let (modes, _) = start.split_at(start.len() - 2);
    let mut scale = Vec::with_capacity(start.len());
    for m in modes.chunks_exact(PER_MODE) {
        let constant = m[2].abs().max(m[3].abs()).max(f64::MIN_POSITIVE);
        scale.extend([m[0], m[1], constant, constant]);
    }
    scale.extend([typical * lines.omega[0] * lines.omega[0], typical]);
    scale
}

/// The weighted residuals (model − H)/σ in the scaled variables x = θ/scale: real
/// parts, then imaginary parts.
struct ModalProblem<'a> {
    lines: &'a Lines,
    scale: &'a [f64],
    /// θ of the last evaluation (a work array).
    theta: Vec<f64>,
}

impl ModalProblem<'_> {
    /// θ = x·scale into the work array.
    fn set_theta(&mut self, x: &[f64]) {
        for ((t, x), s) in self.theta.iter_mut().zip(x).zip(self.scale) {
            *t = x * s;
        }
    }
}

impl LeastSquaresProblem for ModalProblem<'_> {
    fn residual_count(&self) -> usize {
        2 * self.lines.omega.len()
    }

    fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> bool {
        self.set_theta(x);
        let theta = &self.theta;
        self.lines.weighted_residuals(|w| model(theta, w), out);
        true
    }

    fn jacobian(&mut self, x: &[f64], out: &mut DMatrix<f64>) -> bool {
        self.set_theta(x);
        let theta = &self.theta;
        let n = self.lines.omega.len();
        let p = theta.len();
        for (k, (&w, &s)) in self.lines.omega.iter().zip(&self.lines.sigma).enumerate() {
            for (r, mode) in theta[..p - 2].chunks_exact(PER_MODE).enumerate() {
                let (_, gradient) = term_with_gradient(mode, w);
                for (i, g) in gradient.iter().enumerate() {
                    let j = PER_MODE * r + i;
                    out[(k, j)] = g.re * self.scale[j] / s;
                    out[(n + k, j)] = g.im * self.scale[j] / s;
                }
            }
            // ∂H/∂L = −1/ω², ∂H/∂U = 1 (real).
            out[(k, p - 2)] = -self.scale[p - 2] / (w * w * s);
            out[(n + k, p - 2)] = 0.0;
            out[(k, p - 1)] = self.scale[p - 1] / s;
            out[(n + k, p - 1)] = 0.0;
        }
        true
    }
}
