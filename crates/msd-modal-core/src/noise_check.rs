//! A fit's weighted residuals against the frequency response's own noise: where each
//! line's σ is its absolute standard deviation (the coherence's noise model with two or
//! more averages), the residuals' SSE under the noise alone is a sum of squares of
//! correlated errors, SSE = eᵀMe with M = I − J(JᵀJ)⁻¹Jᵀ and e's correlation C (the
//! windows', [`Lines::error_information`]): E\[SSE\] = tr(MC), Var\[SSE\] = 2·tr(MCMC).
//! Satterthwaite's g·χ²_h with the same two moments (h = 2E²/Var, g = Var/(2E)) gives
//! the p value; for independent lines (C = I) that is χ² on rows − p degrees of
//! freedom. A force window correlates the force noise's errors over T/T_f lines, and
//! its few independent squares make SSE vary far more than a χ² on rows − p would say.

use msd_signal::LineCorrelation;
use nalgebra::DMatrix;
use serde::Serialize;
use statrs::distribution::{ChiSquared, ContinuousCDF};

use crate::correlated::complex_inner;
use crate::lines::Lines;

/// The p value below which the residuals are taken to hold more than the noise.
pub const NOISE_CHECK_LEVEL: f64 = 0.01;

/// A fit's residuals against the frequency response's own noise: where each line's σ
/// is its absolute standard deviation, the SSE of the weighted residuals against
/// Satterthwaite's g·χ²_h with the mean tr(MC) and variance 2·tr(MCMC) of the lines'
/// correlated errors (M the fit's residual projector, C their correlation). A small p says the data hold more than the model and the
/// noise: a mode the model lacks, a nonlinearity, leakage.
///
/// ```
/// use msd_modal_core::NoiseCheck;
/// // SSE 520 where the noise alone gives 500 ± √(2·400·(500/400)) on 400 effective dof.
/// let check = NoiseCheck::from_moments(520.0, 500.0, 1250.0).expect("valid moments");
/// assert!((check.degrees_of_freedom - 400.0).abs() < 1e-9);
/// assert!((check.variance_ratio - 1.04).abs() < 1e-12 && check.passed);
/// assert!(check.to_string().starts_with("residuals against the FRF's own noise"));
/// assert!(!NoiseCheck::from_moments(900.0, 500.0, 1250.0).unwrap().passed);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NoiseCheck {
    /// SSE/E\[SSE\]: about 1 when the model leaves only the noise the coherence shows.
    pub variance_ratio: f64,
    /// h, the effective degrees of freedom of SSE ≈ g·χ²_h: rows − p for independent
    /// lines, fewer where the windows correlate neighbouring lines' errors.
    pub degrees_of_freedom: f64,
    /// P(g·χ²_h ≥ SSE).
    pub p_value: f64,
    /// p ≥ [`NOISE_CHECK_LEVEL`].
    pub passed: bool,
}

impl NoiseCheck {
    /// The check of `sse` against the noise alone's `mean` and `variance` of SSE;
    /// `None` unless both are positive and finite.
    pub fn from_moments(sse: f64, mean: f64, variance: f64) -> Option<Self> {
        if !(mean > 0.0 && variance > 0.0 && mean.is_finite() && variance.is_finite()) {
            return None;
        }
        let (g, h) = (variance / (2.0 * mean), 2.0 * mean * mean / variance);
        let p_value = ChiSquared::new(h).ok()?.sf(sse / g);
        Some(NoiseCheck {
            variance_ratio: sse / mean,
            degrees_of_freedom: h,
            p_value,
            passed: p_value >= NOISE_CHECK_LEVEL,
        })
    }
}

impl std::fmt::Display for NoiseCheck {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "residuals against the FRF's own noise (coherence): SSE/E[SSE] = {:.3} on {:.1} effective dof, p = {:.3}",
            self.variance_ratio, self.degrees_of_freedom, self.p_value
        )?;
        if !self.passed {
            write!(
                f,
                "; warning: the model leaves more than the noise (a mode it lacks, a nonlinearity, leakage): the intervals rest on a model the data contradict"
            )?;
        }
        Ok(())
    }
}

impl Lines {
    /// The check of a fit's weighted residuals' `sse` at its weighted `jacobian` (rows
    /// as [`weighted_residuals`](Self::weighted_residuals) lays them out) against the
    /// lines' own noise; `None` where the σ are not absolute (no noise model, fewer than
    /// two averages) or the moments cannot be formed.
    pub fn noise_check(&self, sse: f64, jacobian: &DMatrix<f64>) -> Option<NoiseCheck> {
        if self.noise_model.is_none() || self.averages < 2 {
            return None;
        }
        let (mean, variance) = self.residual_moments(jacobian)?;
        NoiseCheck::from_moments(sse, mean, variance)
    }

    /// E\[SSE\] and Var\[SSE\] under the noise alone (see the module docs), with
    /// A = JᵀJ, G = JᵀCJ and H = JᵀC²J: tr(MC) = tr C − tr(A⁻¹G) and
    /// tr(MCMC) = tr C² − 2·tr(A⁻¹H) + tr((A⁻¹G)²); tr C = rows (every weighted error
    /// of unit variance). Formed with the columns scaled to unit norm.
    pub fn residual_moments(&self, jacobian: &DMatrix<f64>) -> Option<(f64, f64)> {
        let (rows, p) = jacobian.shape();
        let norms: Vec<f64> = (0..p)
            .map(|j| jacobian.column(j).norm().max(f64::MIN_POSITIVE))
            .collect();
        let scaled = DMatrix::from_fn(rows, p, |i, j| jacobian[(i, j)] / norms[j]);
        let Some((z, cz)) = self.correlated_columns(&scaled) else {
            let dof = (rows - p) as f64;
            return Some((dof, 2.0 * dof));
        };
        let normal = (scaled.transpose() * &scaled).cholesky()?;
        let g = DMatrix::from_fn(p, p, |a, b| complex_inner(&z[a], &cz[b]));
        let h = DMatrix::from_fn(p, p, |a, b| complex_inner(&cz[a], &cz[b]));
        let (ag, ah) = (normal.solve(&g), normal.solve(&h));
        let mean = rows as f64 - ag.trace();
        let variance = 2.0 * (self.squared_correlation() - 2.0 * ah.trace() + (&ag * &ag).trace());
        Some((mean, variance))
    }

    /// tr C² = 2·Σ_kl |R_kl|² over the lines, R_kl = r_k·r_l·ρ_resp(d) +
    /// f_k·f̄_l·ρ_force(d) (see [`error_information`](Self::error_information)).
    fn squared_correlation(&self) -> f64 {
        let (response, force) = self.shares();
        let kernels = [&self.correlation.response, &self.correlation.force];
        let reach = kernels.iter().map(|k| k.len()).max().unwrap_or(1).max(1) - 1;
        let n = self.omega.len();
        let mut sum = 0.0;
        for k in 0..n {
            for l in k..n {
                let d = self.index[l] as i64 - self.index[k] as i64;
                if d > reach as i64 {
                    break;
                }
                let r = LineCorrelation::at(kernels[0], d) * (response[k] * response[l])
                    + LineCorrelation::at(kernels[1], d) * (force[k] * force[l].conj());
                sum += if l == k { 1.0 } else { 2.0 } * r.norm_sqr();
            }
        }
        2.0 * sum
    }
}
