//! The complex eigenpairs of a real matrix (one of each conjugate pair, Im μ > 0) from its
//! real Schur form: A = Q·T·Qᵀ, T quasi-triangular; T's eigenvector by back-substitution
//! through its 1×1 and 2×2 diagonal blocks (as LAPACK's `trevc`), then ψ = Q·x.

use msd_signal::Complex64;
use nalgebra::{DMatrix, Schur};

/// The eigenvalues μ with Im μ > 0 of `a` and their eigenvectors (unit norm); `None`
/// where the Schur iteration does not converge.
pub(crate) fn complex_eigenpairs(a: DMatrix<f64>) -> Option<Vec<(Complex64, Vec<Complex64>)>> {
    let n = a.nrows();
    let scale = a.amax().max(f64::MIN_POSITIVE);
    let (q, t) = Schur::try_new(a, f64::EPSILON, 100 * n.max(10))?.unpack();
    let mut pairs = Vec::new();
    let mut k = 0;
    while k + 1 < n {
        if t[(k + 1, k)] == 0.0 {
            k += 1;
            continue;
        }
        let (a11, a12, a21, a22) = (t[(k, k)], t[(k, k + 1)], t[(k + 1, k)], t[(k + 1, k + 1)]);
        let half = 0.5 * (a11 - a22);
        let discriminant = a12 * a21 + half * half;
        if discriminant < 0.0 {
            let mu = Complex64::new(0.5 * (a11 + a22), (-discriminant).sqrt());
            let x = triangular_eigenvector(&t, k, mu, 1e-14 * scale);
            let psi: Vec<Complex64> = (0..n)
                .map(|r| (0..=k + 1).map(|c| x[c] * q[(r, c)]).sum())
                .collect();
            let norm = psi.iter().map(|v| v.norm_sqr()).sum::<f64>().sqrt();
            pairs.push((mu, psi.into_iter().map(|v| v / norm).collect()));
        }
        k += 2;
    }
    Some(pairs)
}

/// The eigenvector x of quasi-triangular `t` for `mu`, an eigenvalue of its 2×2 block at
/// rows k, k+1: x is zero below the block; `floor` keeps a pivot off zero.
fn triangular_eigenvector(t: &DMatrix<f64>, k: usize, mu: Complex64, floor: f64) -> Vec<Complex64> {
    let mut x = vec![Complex64::new(0.0, 0.0); k + 2];
    x[k] = Complex64::new(t[(k, k + 1)], 0.0);
    x[k + 1] = mu - t[(k, k)];
    let rhs = |x: &[Complex64], row: usize, from: usize| -> Complex64 {
        -(from..x.len())
            .map(|c| x[c] * t[(row, c)])
            .sum::<Complex64>()
    };
    let pivot = |v: Complex64| {
        if v.norm() < floor {
            Complex64::new(floor, 0.0)
        } else {
            v
        }
    };
    let mut j = k;
    while j > 0 {
        let row = j - 1;
        if row > 0 && t[(row, row - 1)] != 0.0 {
            // A 2×2 block at rows row − 1, row: solve it whole (Cramer's rule).
            let top = row - 1;
            let (b0, b1) = (rhs(&x, top, row + 1), rhs(&x, row, row + 1));
            let (m00, m01) = (t[(top, top)] - mu, Complex64::new(t[(top, row)], 0.0));
            let (m10, m11) = (Complex64::new(t[(row, top)], 0.0), t[(row, row)] - mu);
            let det = pivot(m00 * m11 - m01 * m10);
            x[top] = (b0 * m11 - m01 * b1) / det;
            x[row] = (m00 * b1 - m10 * b0) / det;
            j -= 2;
        } else {
            x[row] = rhs(&x, row, row + 1) / pivot(t[(row, row)] - mu);
            j -= 1;
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigenpairs_satisfy_a_psi_equals_mu_psi() {
        // A random-looking 7×7 matrix (full rank, distinct eigenvalues, complex pairs).
        let a = DMatrix::from_fn(7, 7, |r, c| (((r * 7 + c) as f64).powi(2) * 0.37).sin());
        let pairs = complex_eigenpairs(a.clone()).expect("converges");
        assert!(!pairs.is_empty());
        let ac = a.map(|v| Complex64::new(v, 0.0));
        for (mu, psi) in pairs {
            assert!(mu.im > 0.0);
            let v = nalgebra::DVector::from_vec(psi);
            let residual = (&ac * &v - &v * mu).norm();
            assert!(residual < 1e-10, "residual {residual} for {mu}");
        }
    }
}
