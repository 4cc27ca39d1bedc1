//! The covariance of a least-squares fit to lines whose errors are correlated: the
//! sandwich (JᵀJ)⁻¹·JᵀCJ·(JᵀJ)⁻¹, C the correlation of the weighted residuals that the
//! windows make ([`LineCorrelation`]), split between the response's noise and the
//! force's (see [`Lines::force_share`]).

use msd_signal::{Complex64, LineCorrelation};
use nalgebra::DMatrix;

use crate::lines::Lines;

impl Lines {
    /// JᵀCJ for a Jacobian of the weighted residuals (real parts of the lines in the
    /// first half of the rows, imaginary parts in the second), C the correlation of the
    /// weighted errors: with e_k the complex error of line k, R_kl = E[e_k·ē_l]/(2σ_kσ_l)
    /// = r_k·r_l·ρ_resp(d) + f_k·f_l·φ_k·φ̄_l·ρ_force(d), d the lag between the lines,
    /// r_k² and f_k² the shares of the response's and the force's noise in σ_k² and
    /// φ_k = H_k/|H_k| (the force's noise makes an error proportional to H). With
    /// z_k = J_re,k + j·J_im,k per column, (JᵀCJ)_ab = Re Σ_kl z̄_ka·R_kl·z_lb for
    /// circular errors. `None` when the correlation is not known.
    pub fn error_information(&self, jacobian: &DMatrix<f64>) -> Option<DMatrix<f64>> {
        let (z, correlated) = self.correlated_columns(jacobian)?;
        Some(DMatrix::from_fn(z.len(), z.len(), |a, b| {
            complex_inner(&z[a], &correlated[b])
        }))
    }

    /// Each column of the weighted Jacobian as complex z_k = J_re,k + j·J_im,k, and R·z
    /// (see [`error_information`](Self::error_information)); `None` when the
    /// correlation is not known.
    pub fn correlated_columns(&self, jacobian: &DMatrix<f64>) -> Option<ComplexColumns> {
        if self.correlation.is_empty() && !self.independent_scaled() {
            return None;
        }
        let n = self.omega.len();
        debug_assert_eq!(jacobian.nrows(), 2 * n);
        let (response, force) = self.shares();
        let z: Vec<Vec<Complex64>> = (0..jacobian.ncols())
            .map(|b| {
                (0..n)
                    .map(|k| Complex64::new(jacobian[(k, b)], jacobian[(n + k, b)]))
                    .collect()
            })
            .collect();
        let correlated = (z.iter())
            .map(|zb| self.correlate(zb, &response, &force))
            .collect();
        Some((z, correlated))
    }

    /// Whether the lines' errors are independent (no correlation known, one line of
    /// noise bandwidth, as a table's) with variances of their own
    /// ([`variance_scale`](Self::variance_scale)): C is then diagonal.
    pub fn independent_scaled(&self) -> bool {
        self.correlation.is_empty()
            && self.correlated_lines == 1.0
            && self.variance_scale.len() == self.omega.len()
    }

    /// r_k = √(1 − f_k²) and f_k·φ_k of every line: the response's and the force's parts
    /// of its weighted error (see [`error_information`](Self::error_information)), each
    /// times √v_k where the lines' variances differ ([`variance_scale`](Self::variance_scale)).
    pub fn shares(&self) -> (Vec<f64>, Vec<Complex64>) {
        let n = self.omega.len();
        let share = |k: usize| self.force_share.get(k).copied().unwrap_or(0.0);
        let scale = |k: usize| self.variance_scale.get(k).map_or(1.0, |v| v.sqrt());
        let response = (0..n).map(|k| scale(k) * (1.0 - share(k)).sqrt()).collect();
        let force = (0..n)
            .map(|k| match self.h[k].norm() {
                0.0 => Complex64::new(0.0, 0.0),
                norm => self.h[k] / norm * scale(k) * share(k).sqrt(),
            })
            .collect();
        (response, force)
    }

    /// R·z for one column z of the complex Jacobian (see
    /// [`error_information`](Self::error_information)).
    pub fn correlate(
        &self,
        z: &[Complex64],
        response: &[f64],
        force: &[Complex64],
    ) -> Vec<Complex64> {
        let kernels = [&self.correlation.response, &self.correlation.force];
        let reach = kernels.iter().map(|k| k.len()).max().unwrap_or(1).max(1) - 1;
        let n = z.len();
        let u: Vec<Complex64> = z.iter().zip(response).map(|(z, r)| z * r).collect();
        let v: Vec<Complex64> = z.iter().zip(force).map(|(z, f)| z * f.conj()).collect();
        (0..n)
            .map(|k| {
                let first = self.index.partition_point(|&i| i + reach < self.index[k]);
                let (mut to_response, mut to_force) = (Complex64::default(), Complex64::default());
                for l in first..n {
                    let d = self.index[l] as i64 - self.index[k] as i64;
                    if d > reach as i64 {
                        break;
                    }
                    to_response += LineCorrelation::at(kernels[0], d) * u[l];
                    to_force += LineCorrelation::at(kernels[1], d) * v[l];
                }
                to_response * response[k] + to_force * force[k]
            })
            .collect()
    }

    /// The normal matrix N whose inverse times s² is the covariance of a least-squares
    /// fit with this weighted Jacobian, and the count of residual degrees of freedom
    /// the fit takes: N = (JᵀJ)(JᵀCJ)⁻¹(JᵀJ) when the lines' correlation is known (the
    /// sandwich, inverted) with tr((JᵀJ)⁻¹JᵀCJ) taken (E\[SSE\] = σ²·(rows − that): p
    /// for independent lines, more when neighbouring lines' errors are alike), else
    /// JᵀJ/c with c [`correlated_lines`](Self::correlated_lines) (every line's errors
    /// correlated alike) and p. Formed with the columns scaled to unit norm.
    pub fn effective_normal(&self, jacobian: &DMatrix<f64>) -> (DMatrix<f64>, f64) {
        let normal = jacobian.transpose() * jacobian;
        let p = normal.nrows();
        let fallback = || (&normal / self.correlated_lines, p as f64);
        let Some(information) = self.error_information(jacobian) else {
            return fallback();
        };
        sandwich(&normal, &information).unwrap_or_else(fallback)
    }
}

impl Lines {
    /// The variance s² by which the fit's covariance scales the lines' σ², from the
    /// residuals' `sse` over `dof`, the degrees of freedom the fit leaves them: where the
    /// σ are the coherence's absolute variances (its noise model, two or more
    /// averages), at least 1 — the residuals may show more than the coherence does (a
    /// misfit, leakage) but, their errors correlated over many lines (the force
    /// window's), can show much less by chance: their SSE then holds only a few
    /// independent squares, and an s² from it alone would make some intervals many
    /// times too narrow.
    pub fn residual_variance(&self, sse: f64, dof: f64) -> f64 {
        let s2 = sse / dof;
        if self.noise_model.is_some() && self.averages >= 2 {
            s2.max(1.0)
        } else {
            s2
        }
    }
}

/// Columns of a Jacobian in complex form, and the same columns times R.
pub type ComplexColumns = (Vec<Vec<Complex64>>, Vec<Vec<Complex64>>);

/// Re Σ_k conj(a_k)·b_k: the real inner product of two columns in complex form.
#[inline]
pub fn complex_inner(a: &[Complex64], b: &[Complex64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| (a.conj() * b).re).sum()
}

/// (A·G⁻¹·A, tr(A⁻¹G)) for a normal matrix A = JᵀJ and the errors' information
/// G = JᵀCJ, in columns scaled to unit norm; `None` when either is not positive definite.
pub fn sandwich(normal: &DMatrix<f64>, information: &DMatrix<f64>) -> Option<(DMatrix<f64>, f64)> {
    let p = normal.nrows();
    let norms: Vec<f64> = (0..p)
        .map(|j| normal[(j, j)].sqrt().max(f64::MIN_POSITIVE))
        .collect();
    let scaled =
        |m: &DMatrix<f64>| DMatrix::from_fn(p, p, |r, c| m[(r, c)] / (norms[r] * norms[c]));
    let (a, g) = (scaled(normal), positive_part(scaled(information))?);
    let taken = a.clone().cholesky()?.solve(&g).trace();
    let inner = &a * g.cholesky()?.solve(&a);
    let normal = DMatrix::from_fn(p, p, |r, c| inner[(r, c)] * norms[r] * norms[c]);
    Some((normal, taken))
}

/// The symmetric `g` with its eigenvalues raised to at least 1e-12 of the largest: JᵀCJ
/// is positive semi-definite in exact arithmetic, but a correlation kernel cut at
/// [`MAX_LAG`](msd_signal::frf::MAX_LAG) and errors correlated over many lines (a force
/// window's, where the force's noise makes nearly all of it) can leave it singular or
/// slightly indefinite in some direction the parameters barely move. `None` when `g`
/// has no positive eigenvalue.
fn positive_part(g: DMatrix<f64>) -> Option<DMatrix<f64>> {
    if g.clone().cholesky().is_some() {
        return Some(g);
    }
    let eigen = g.symmetric_eigen();
    let largest = eigen.eigenvalues.max();
    if largest.is_nan() || largest <= 0.0 {
        return None;
    }
    let floor = 1e-12 * largest;
    let values = eigen.eigenvalues.map(|v| v.max(floor));
    Some(&eigen.eigenvectors * DMatrix::from_diagonal(&values) * eigen.eigenvectors.transpose())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lines::CoherenceNoise;

    /// A positive definite matrix is kept as it is; an indefinite one gets its negative
    /// eigenvalue raised to 1e-12 of the largest, its eigenvectors kept.
    #[test]
    fn positive_part_raises_only_what_is_not_positive() {
        let pd = DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0]);
        assert_eq!(positive_part(pd.clone()), Some(pd));
        // Eigenvalues 3 and −1, eigenvectors (1, 1)/√2 and (1, −1)/√2.
        let indefinite = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        let fixed = positive_part(indefinite).expect("a positive eigenvalue");
        let (big, small) = (3e-12 / 2.0, 3.0 / 2.0);
        let want =
            DMatrix::from_row_slice(2, 2, &[small + big, small - big, small - big, small + big]);
        assert!((fixed - want).abs().max() < 1e-12);
        assert_eq!(positive_part(-DMatrix::<f64>::identity(2, 2)), None);
    }

    /// s² from the residuals alone without a noise model; with one (absolute variances
    /// from two or more averages), at least 1.
    #[test]
    fn residual_variance_is_floored_by_the_coherences_own() {
        let mut lines = Lines::uniform(vec![1.0, 2.0], vec![Complex64::new(1.0, 0.0); 2]);
        assert_eq!(lines.residual_variance(0.5, 2.0), 0.25);
        lines.noise_model = Some(CoherenceNoise {
            force: 1e-5,
            response: 1e-6,
            force_standard_error: 1e-6,
            force_measured: false,
        });
        lines.averages = 5;
        assert_eq!(lines.residual_variance(0.5, 2.0), 1.0);
        assert_eq!(lines.residual_variance(8.0, 2.0), 4.0);
        lines.averages = 1;
        assert_eq!(lines.residual_variance(0.5, 2.0), 0.25);
    }
}
