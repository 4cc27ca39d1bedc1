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
        if self.correlation.is_empty() {
            return None;
        }
        let n = self.omega.len();
        debug_assert_eq!(jacobian.nrows(), 2 * n);
        let p = jacobian.ncols();
        let share = |k: usize| self.force_share.get(k).copied().unwrap_or(0.0);
        let response: Vec<f64> = (0..n).map(|k| (1.0 - share(k)).sqrt()).collect();
        let force: Vec<Complex64> = (0..n)
            .map(|k| match self.h[k].norm() {
                0.0 => Complex64::new(0.0, 0.0),
                norm => self.h[k] / norm * share(k).sqrt(),
            })
            .collect();
        let z: Vec<Vec<Complex64>> = (0..p)
            .map(|b| {
                (0..n)
                    .map(|k| Complex64::new(jacobian[(k, b)], jacobian[(n + k, b)]))
                    .collect()
            })
            .collect();
        let correlated: Vec<Vec<Complex64>> = z
            .iter()
            .map(|zb| self.correlate(zb, &response, &force))
            .collect();
        Some(DMatrix::from_fn(p, p, |a, b| {
            let sum: Complex64 = (z[a].iter().zip(&correlated[b]))
                .map(|(za, wb)| za.conj() * wb)
                .sum();
            sum.re
        }))
    }

    /// R·z for one column z of the complex Jacobian (see
    /// [`error_information`](Self::error_information)).
    fn correlate(&self, z: &[Complex64], response: &[f64], force: &[Complex64]) -> Vec<Complex64> {
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

/// (A·G⁻¹·A, tr(A⁻¹G)) for a normal matrix A = JᵀJ and the errors' information
/// G = JᵀCJ, in columns scaled to unit norm; `None` when either is not positive definite.
pub(crate) fn sandwich(
    normal: &DMatrix<f64>,
    information: &DMatrix<f64>,
) -> Option<(DMatrix<f64>, f64)> {
    let p = normal.nrows();
    let norms: Vec<f64> = (0..p)
        .map(|j| normal[(j, j)].sqrt().max(f64::MIN_POSITIVE))
        .collect();
    let scaled =
        |m: &DMatrix<f64>| DMatrix::from_fn(p, p, |r, c| m[(r, c)] / (norms[r] * norms[c]));
    let (a, g) = (scaled(normal), scaled(information));
    let taken = a.clone().cholesky()?.solve(&g).trace();
    let inner = &a * g.cholesky()?.solve(&a);
    let normal = DMatrix::from_fn(p, p, |r, c| inner[(r, c)] * norms[r] * norms[c]);
    Some((normal, taken))
}
