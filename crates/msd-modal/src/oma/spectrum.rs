//! The output spectral matrix of a record by the correlogram (its covariances at lags
//! 0 … N − 1 under an exponential lag window, Fourier-transformed), and its singular
//! values line by line: the CMIF of frequency domain decomposition.
//!
//! The exponential window w(k) = e^{−βk}, falling to 1 % at lag N, keeps the spectral
//! matrix positive semi-definite (its transform is positive) and adds a known decay β to
//! every mode's correlation function, which EFDD divides out again (Brincker & Ventura,
//! *Introduction to Operational Modal Analysis*, 2015, § 8.4; pyOMA2's "cor" estimate).

use msd_signal::Complex64;
use nalgebra::{DMatrix, SymmetricEigen};
use serde::Serialize;

use super::covariance::{BlockCovariances, Lags};
use super::horizon::lowest_peak_hz;
use super::record::OutputRecord;
use msd_modal_core::error::{ModalError, Result};

/// The singular values of a record's output spectral matrix by frequency (the complex
/// mode indicator function): peaks of the first are modes, a second rising with it marks
/// close modes. Channels scaled to unit variance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SingularSpectrum {
    /// The lines' frequencies, Hz.
    pub frequency_hz: Vec<f64>,
    /// The first singular values (up to three), each a curve over the lines, 1/Hz.
    pub singular_values: Vec<Vec<f64>>,
    /// The covariance lags N the spectrum was formed from (the line spacing is
    /// fs / 2N).
    pub lags: usize,
    /// The peaks frequency domain decomposition picked, Hz (empty for SSI).
    pub peaks_hz: Vec<f64>,
}

/// The singular values of a record's output spectral matrix (see [`efdd`](crate::efdd)
/// for the estimate), at `lags` lags or the default (40 periods of the lowest mode of
/// `band_hz`, else of the record): the CMIF drawn behind a stabilization diagram.
///
/// Errors: a bad record ([`OutputRecord::check`]); fewer samples than four times the
/// lags.
pub fn singular_spectrum(
    record: &OutputRecord,
    lags: Option<usize>,
    band_hz: Option<[f64; 2]>,
) -> Result<SingularSpectrum> {
    record.check()?;
    let (scaled, _) = record.standardised();
    let fs = record.sample_rate_hz();
    let lags = lags.unwrap_or_else(|| default_lags(&scaled, fs, band_hz));
    if record.len() < 4 * lags.max(16) {
        return Err(ModalError::TooFewSamples {
            got: record.len(),
            needed: 4 * lags.max(16),
            why: "the record must hold at least four times the spectral matrix's lags",
        });
    }
    let all: Vec<usize> = (0..scaled.len()).collect();
    let range = Lags {
        first: 0,
        last: lags - 1,
    };
    let blocks = (record.len() / (4 * lags)).clamp(1, 64);
    let covariances = BlockCovariances::with_lags(&scaled, &all, range, blocks);
    let lines: Vec<Line> = spectral_matrix(&covariances.covariances(None), fs)
        .iter()
        .map(decompose)
        .collect();
    Ok(SingularSpectrum::of(&lines, fs, lags, Vec::new()))
}

impl SingularSpectrum {
    /// The first (up to three) singular values of decomposed lines.
    pub(crate) fn of(lines: &[Line], fs: f64, lags: usize, peaks_hz: Vec<f64>) -> Self {
        let df = fs / (2 * lags) as f64;
        Self {
            frequency_hz: (0..lines.len()).map(|j| j as f64 * df).collect(),
            singular_values: (0..lines[0].values.len().min(3))
                .map(|s| lines.iter().map(|line| line.values[s]).collect())
                .collect(),
            lags,
            peaks_hz,
        }
    }
}

/// The lag window's decay per lag, β = ln 100 / N.
pub(crate) fn window_decay(lags: usize) -> f64 {
    100f64.ln() / lags as f64
}

/// The default lags: 40 periods of the lowest mode (the band's lower edge, else the
/// record's lowest clear spectral peak) as a power of two, at least 256 and at most a
/// quarter of the record.
pub(crate) fn default_lags(scaled: &[Vec<f64>], fs: f64, band: Option<[f64; 2]>) -> usize {
    let n = scaled.first().map_or(0, Vec::len);
    let low = match band {
        Some([low, _]) if low > 0.0 => Some(low),
        _ => lowest_peak_hz(scaled, fs),
    };
    let wanted = low.map_or(1024, |f| (40.0 * fs / f).ceil() as usize);
    let most = prev_power_of_two((n / 4).max(16));
    wanted.max(256).next_power_of_two().min(most)
}

fn prev_power_of_two(n: usize) -> usize {
    1 << (usize::BITS - 1 - n.leading_zeros())
}

/// The spectral matrix G(f_j) = Σ_{|k|<N} w(|k|)·R_k·e^{−iω_j k}, R_{−k} = R_kᵀ, at the
/// lines f_j = j·fs/2N, j = 0 … N, from the covariances R_0 … R_{N−1} (channels ×
/// channels). One FFT of length 2N per channel pair.
pub(crate) fn spectral_matrix(covariances: &[DMatrix<f64>], fs: f64) -> Vec<DMatrix<Complex64>> {
    let n = covariances.len();
    let l = covariances[0].nrows();
    let beta = window_decay(n);
    let size = 2 * n;
    let fft = rustfft::FftPlannerScalar::new().plan_fft_forward(size);
    let mut lines = vec![DMatrix::zeros(l, l); n + 1];
    let zero = Complex64::new(0.0, 0.0);
    for p in 0..l {
        for q in 0..l {
            let mut a = vec![zero; size];
            a[0] = Complex64::new(covariances[0][(p, q)], 0.0);
            for k in 1..n {
                let w = (-beta * k as f64).exp();
                a[k] = Complex64::new(w * covariances[k][(p, q)], 0.0);
                a[size - k] = Complex64::new(w * covariances[k][(q, p)], 0.0);
            }
            fft.process(&mut a);
            for (j, line) in lines.iter_mut().enumerate() {
                line[(p, q)] = a[j] / fs;
            }
        }
    }
    lines
}

/// One line's decomposition: the singular values (the Hermitian matrix's eigenvalues,
/// largest first) and the first singular vector.
#[derive(Debug, Clone)]
pub(crate) struct Line {
    /// The singular values, largest first.
    pub values: Vec<f64>,
    /// The first singular vector.
    pub first: Vec<Complex64>,
}

/// The singular values and first vector of a Hermitian spectral matrix.
pub(crate) fn decompose(g: &DMatrix<Complex64>) -> Line {
    let hermitian = (g + g.adjoint()) * Complex64::new(0.5, 0.0);
    let eig = SymmetricEigen::new(hermitian);
    let mut order: Vec<usize> = (0..eig.eigenvalues.len()).collect();
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    Line {
        values: order.iter().map(|&k| eig.eigenvalues[k].max(0.0)).collect(),
        first: eig.eigenvectors.column(order[0]).iter().copied().collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_correlogram_of_white_noise_is_flat_and_a_sine_peaks_at_its_line() {
        // R_0 = I, R_k = 0: G = I/fs at every line; singular values 1/fs.
        let mut cov = vec![DMatrix::zeros(2, 2); 64];
        cov[0] = DMatrix::identity(2, 2);
        let lines = spectral_matrix(&cov, 10.0);
        assert_eq!(lines.len(), 65);
        for g in &lines {
            let line = decompose(g);
            assert!((line.values[0] - 0.1).abs() < 1e-15 && (line.values[1] - 0.1).abs() < 1e-15);
        }
        // A cosine's covariance cos(ω k) on both channels, in phase: rank one, peak at its
        // line (j = 16 of 64: ω = π·16/64), first vector (1, 1)/√2.
        let w = std::f64::consts::PI * 16.0 / 64.0;
        let cov: Vec<DMatrix<f64>> = (0..64)
            .map(|k| DMatrix::from_element(2, 2, (w * k as f64).cos()))
            .collect();
        let lines: Vec<Line> = spectral_matrix(&cov, 10.0).iter().map(decompose).collect();
        let peak = (0..lines.len())
            .max_by(|&a, &b| lines[a].values[0].total_cmp(&lines[b].values[0]))
            .unwrap();
        assert_eq!(peak, 16);
        assert!(lines[peak].values[1] < 1e-12 * lines[peak].values[0]);
        let v = &lines[peak].first;
        assert!((v[0].norm() - v[1].norm()).abs() < 1e-12 && (v[0] / v[1] - 1.0).norm() < 1e-12);
    }

    #[test]
    fn default_lags_span_forty_periods_of_the_band_edge_within_a_quarter_of_the_record() {
        let record = vec![vec![0.0; 100_000]; 2];
        assert_eq!(default_lags(&record, 100.0, Some([2.0, 10.0])), 2048); // 2000 → 2048
        assert_eq!(default_lags(&record, 100.0, Some([0.1, 10.0])), 16384); // 40 000 > n/4
        assert_eq!(default_lags(&record, 100.0, Some([40.0, 45.0])), 256); // at least 256
    }
}
