//! Output covariances R_k = E[y(t+k)·y_ref(t)ᵀ] of a record, summed block by block so
//! that the record's halves, or the record less one block, cost no second pass; and the
//! block Toeplitz matrix they form.

use msd_signal::Complex64;
use nalgebra::DMatrix;

/// The lagged products of a record, kept per block of samples.
#[derive(Debug, Clone)]
pub(crate) struct BlockCovariances {
    /// `sums[b][k - first]`: Σ y(t+k)·y_ref(t)ᵀ over the t of block b (channels ×
    /// references).
    sums: Vec<Vec<DMatrix<f64>>>,
    /// `counts[b][k - first]`: how many t of block b have t + k inside the record.
    counts: Vec<Vec<usize>>,
}

/// The lags a [`BlockCovariances`] holds: 1..=max (SSI's Toeplitz matrix) or 0..=max (a
/// spectral matrix).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Lags {
    /// The first lag, 0 or 1.
    pub first: usize,
    /// The last lag.
    pub last: usize,
}

impl BlockCovariances {
    /// The products at the lags `lags` of `channels` (each centred and scaled, of one
    /// length) against the channels `references`, in `blocks` blocks of nearly equal
    /// length. Each block's lagged products come from one FFT per channel (its samples,
    /// and the next `max_lag` for the lagged side, zero-padded) and one inverse FFT per
    /// channel and reference: the cost is linear in the record's length. FFTs by
    /// rustfft's scalar planner: the same numbers on every machine.
    pub(crate) fn with_lags(
        channels: &[Vec<f64>],
        references: &[usize],
        lags: Lags,
        blocks: usize,
    ) -> Self {
        let Lags {
            first,
            last: max_lag,
        } = lags;
        let n = channels[0].len();
        let bounds: Vec<usize> = (0..=blocks).map(|b| b * n / blocks).collect();
        let longest = (0..blocks)
            .map(|b| bounds[b + 1] - bounds[b])
            .max()
            .unwrap_or(0);
        let size = (longest + max_lag + 1).next_power_of_two();
        let mut planner = rustfft::FftPlannerScalar::new();
        let forward = planner.plan_fft_forward(size);
        let inverse = planner.plan_fft_inverse(size);
        let mut sums = Vec::with_capacity(blocks);
        let mut counts = Vec::with_capacity(blocks);
        for b in 0..blocks {
            let (t0, t1) = (bounds[b], bounds[b + 1]);
            let lagged: Vec<Vec<Complex64>> = channels
                .iter()
                .map(|c| transformed(&c[t0..(t1 + max_lag).min(n)], size, &*forward))
                .collect();
            let plain: Vec<Vec<Complex64>> = references
                .iter()
                .map(|&q| transformed(&channels[q][t0..t1], size, &*forward))
                .collect();
            let mut block_sums =
                vec![DMatrix::zeros(channels.len(), references.len()); max_lag + 1 - first];
            for (c, z) in lagged.iter().enumerate() {
                for (q, x) in plain.iter().enumerate() {
                    // Σ_s z[s + k]·x[s] = IFFT(Z·conj(X))[k] / size.
                    let mut product: Vec<Complex64> =
                        z.iter().zip(x).map(|(a, b)| a * b.conj()).collect();
                    inverse.process(&mut product);
                    for (k, sum) in block_sums.iter_mut().enumerate() {
                        sum[(c, q)] = product[k + first].re / size as f64;
                    }
                }
            }
            sums.push(block_sums);
            counts.push(
                (first..=max_lag)
                    .map(|k| t1.min(n.saturating_sub(k)).max(t0) - t0)
                    .collect(),
            );
        }
        Self { sums, counts }
    }

    /// How many blocks.
    pub(crate) fn blocks(&self) -> usize {
        self.sums.len()
    }

    /// The covariances R_first … R_last of the whole record less block `left_out` (of the
    /// whole record where it is `None`).
    pub(crate) fn covariances(&self, left_out: Option<usize>) -> Vec<DMatrix<f64>> {
        let lags = self.sums[0].len();
        (0..lags)
            .map(|k| {
                let mut sum = DMatrix::zeros(self.sums[0][k].nrows(), self.sums[0][k].ncols());
                let mut count = 0;
                for b in (0..self.blocks()).filter(|&b| Some(b) != left_out) {
                    sum += &self.sums[b][k];
                    count += self.counts[b][k];
                }
                sum / count.max(1) as f64
            })
            .collect()
    }
}

/// The block Toeplitz matrix of `i` block rows, row block a and column block b holding
/// R_{i+a−b}: R_i … R_1 on the first row, R_{2i−1} … R_i on the last
/// (`covariances[k - 1]` is R_k; at least 2i − 1 of them).
pub(crate) fn block_toeplitz(covariances: &[DMatrix<f64>], i: usize) -> DMatrix<f64> {
    let (l, r) = (covariances[0].nrows(), covariances[0].ncols());
    DMatrix::from_fn(i * l, i * r, |row, col| {
        let (a, c) = (row / l, row % l);
        let (b, q) = (col / r, col % r);
        covariances[i + a - b - 1][(c, q)]
    })
}

/// The matrix whose left singular vectors span the observability matrix: SSI-cov's
/// block Toeplitz matrix T of `i` block rows, or SSI-dat's T·L⁻ᵀ with L the Cholesky
/// factor of the past references' covariance matrix G (computed as T·G^{-1/2}) (the projection of the future outputs
/// on the past references, Y_f/Y_p^ref = L21·Q1ᵀ, has the left singular vectors of
/// L21 = T·L⁻ᵀ: the data-driven algorithm's QR done on the covariances; Peeters & De
/// Roeck 1999, Van Overschee & De Moor 1996 § 3.3). `covariances[k]` is R_k from lag 0;
/// `references` index the channels (the rows of R_k) that are references. `None` where
/// G's eigenvalues do not converge.
pub(crate) fn subspace_matrix(
    covariances: &[DMatrix<f64>],
    i: usize,
    references: &[usize],
    data_driven: bool,
) -> Option<DMatrix<f64>> {
    let t = block_toeplitz(&covariances[1..], i);
    if !data_driven {
        return Some(t);
    }
    let r = references.len();
    // Past block b holds y_ref(t + b): block (b, c) is E[y_ref(t+b)·y_ref(t+c)ᵀ] =
    // R_ref(b − c), R_ref(−k) = R_ref(k)ᵀ.
    let past = DMatrix::from_fn(i * r, i * r, |row, col| {
        let (b, p) = (row / r, row % r);
        let (c, q) = (col / r, col % r);
        if b >= c {
            covariances[b - c][(references[p], q)]
        } else {
            covariances[c - b][(references[q], p)]
        }
    });
    // T·L⁻ᵀ and T·G^{-1/2} (G = L·Lᵀ) differ by an orthogonal factor on the right: the
    // same left singular vectors. The symmetric root, as a pseudo-inverse, also holds
    // where G is singular to rounding (a reference's spectrum empty above the
    // anti-aliasing filter makes the long Toeplitz matrix so): directions below 1e-10 of
    // its largest eigenvalue carry no past to project on and are left out, as the QR of
    // the data would leave them.
    let eig = nalgebra::SymmetricEigen::try_new(past, 1e-14, 10_000)?;
    let largest = eig.eigenvalues.iter().copied().fold(0.0, f64::max);
    let root = DMatrix::from_diagonal(&eig.eigenvalues.map(|v| {
        if v > 1e-10 * largest {
            1.0 / v.sqrt()
        } else {
            0.0
        }
    }));
    Some(t * (&eig.eigenvectors * root * eig.eigenvectors.transpose()))
}

/// The FFT of `x` zero-padded to `size`.
fn transformed(x: &[f64], size: usize, fft: &dyn rustfft::Fft<f64>) -> Vec<Complex64> {
    let mut buffer: Vec<Complex64> = x.iter().map(|&v| Complex64::new(v, 0.0)).collect();
    buffer.resize(size, Complex64::new(0.0, 0.0));
    fft.process(&mut buffer);
    buffer
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn leaving_out_no_block_is_the_plain_average_and_blocks_add_up() {
        let x: Vec<f64> = (0..103).map(|t| (0.37 * t as f64).sin()).collect();
        let y: Vec<f64> = (0..103).map(|t| (0.11 * t as f64).cos()).collect();
        let channels = vec![x.clone(), y.clone()];
        let lags = Lags { first: 1, last: 3 };
        let one = BlockCovariances::with_lags(&channels, &[1], lags, 1);
        let five = BlockCovariances::with_lags(&channels, &[1], lags, 5);
        let direct: f64 = (0..103 - 2).map(|t| x[t + 2] * y[t]).sum::<f64>() / 101.0;
        for cov in [one.covariances(None), five.covariances(None)] {
            assert!((cov[1][(0, 0)] - direct).abs() < 1e-13); // FFT rounding: ε·log₂(size)·Σ|x||y|
        }
        // Less block 0 (samples 0..20): the products of t = 20..101.
        let less: f64 = (20..101).map(|t| x[t + 2] * y[t]).sum::<f64>() / 81.0;
        assert!((five.covariances(Some(0))[1][(0, 0)] - less).abs() < 1e-13);
    }

    #[test]
    fn the_toeplitz_matrix_holds_r_i_plus_a_minus_b() {
        let cov: Vec<DMatrix<f64>> = (1..=5)
            .map(|k| DMatrix::from_element(1, 1, k as f64))
            .collect();
        let t = block_toeplitz(&cov, 3);
        assert_eq!(
            t,
            DMatrix::from_row_slice(3, 3, &[3.0, 2.0, 1.0, 4.0, 3.0, 2.0, 5.0, 4.0, 3.0])
        );
    }
}
