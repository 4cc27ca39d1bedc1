//! The poles and shapes of every model order from one block Toeplitz matrix of output
//! covariances: its SVD T = U·S·Vᵀ gives the observability matrix O = U_n·S_n^½, the
//! state matrix A = O↑⁺·O↓ by the shift of O's block rows, and C = O's first block row.
//!
//! A is similar to Ã = U↑⁺·U↓ (U_n's rows without the last / the first block row) and
//! C·ψ = U_n[first block]·ψ̃ for Ã's eigenvector ψ̃, so S never enters; and since U's
//! columns are orthonormal, Ã_n = G_n⁻¹·M_n with G = U↑ᵀU↑, M = U↑ᵀU↓ formed once for the
//! largest order and cut to n × n for each smaller one.

use msd_signal::Complex64;
use nalgebra::DMatrix;

use super::eigen::complex_eigenpairs;

/// One pole of one model order: the discrete eigenvalue μ, the continuous pole
/// λ = ln μ · fs, and the shape over the channels (in the scaled channels' units).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Pole {
    /// λ, rad/s (Im λ > 0).
    pub lambda: Complex64,
    /// C·ψ: one entry per channel.
    pub shape: Vec<Complex64>,
}

impl Pole {
    /// fn = |λ|/2π.
    pub fn frequency_hz(&self) -> f64 {
        self.lambda.norm() / std::f64::consts::TAU
    }

    /// ζ = −Re λ/|λ|.
    pub fn damping_ratio(&self) -> f64 {
        -self.lambda.re / self.lambda.norm()
    }
}

/// The column space of a block Toeplitz matrix up to the largest order.
pub(crate) struct Subspace {
    /// U's first block row (l × n_max).
    first_rows: DMatrix<f64>,
    /// U↑ᵀ·U↑ (n_max × n_max).
    gram: DMatrix<f64>,
    /// U↑ᵀ·U↓ (n_max × n_max).
    shift: DMatrix<f64>,
    /// The singular values, largest first.
    pub singular_values: Vec<f64>,
}

impl Subspace {
    /// From the Toeplitz matrix `t` of `l` channels per block row, up to order `n_max`
    /// (at most `t`'s smaller dimension); `None` where the SVD does not converge.
    pub(crate) fn new(t: DMatrix<f64>, l: usize, n_max: usize) -> Option<Self> {
        let rows = t.nrows();
        let (u, singular_values) = left_singular(&t, n_max)?;
        let up = u.rows(0, rows - l);
        let down = u.rows(l, rows - l);
        Some(Self {
            first_rows: u.rows(0, l).into_owned(),
            gram: up.transpose() * up,
            shift: up.transpose() * down,
            singular_values,
        })
    }

    /// The poles with Im λ > 0 of order `n` at `sample_rate_hz`, with their shapes
    /// (empty where the order's state matrix cannot be formed).
    pub(crate) fn poles(&self, n: usize, sample_rate_hz: f64) -> Vec<Pole> {
        let gram = self.gram.view((0, 0), (n, n)).into_owned();
        let shift = self.shift.view((0, 0), (n, n)).into_owned();
        let Some(a) = gram.cholesky().map(|c| c.solve(&shift)) else {
            return Vec::new();
        };
        let Some(pairs) = complex_eigenpairs(a) else {
            return Vec::new();
        };
        let c = self.first_rows.columns(0, n);
        pairs
            .into_iter()
            .filter(|(mu, _)| mu.norm() > 0.0)
            .map(|(mu, psi)| Pole {
                lambda: mu.ln() * sample_rate_hz,
                shape: (0..c.nrows())
                    .map(|r| (0..n).map(|j| psi[j] * c[(r, j)]).sum())
                    .collect(),
            })
            .collect()
    }
}

/// The leading `n` left singular vectors of `t` and all its singular values (largest
/// first); `None` where the SVD does not converge. (The symmetric eigenproblem of tᵀt
/// was tried: no faster with nalgebra's, and it loses the small singular values.)
fn left_singular(t: &DMatrix<f64>, n: usize) -> Option<(DMatrix<f64>, Vec<f64>)> {
    let svd = nalgebra::SVD::try_new(t.clone(), true, false, f64::EPSILON, 0)?;
    let u = svd.u?.columns(0, n).into_owned();
    Some((u, svd.singular_values.iter().copied().collect()))
}
