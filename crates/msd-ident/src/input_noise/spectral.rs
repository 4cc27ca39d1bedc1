//! The residuals and impulse responses in the frequency domain, and the spectral model
//! S = D + σ²_u·G·Gᴴ fitted to them ([`super::scoring`] fits it).

use crate::correlation::autocorrelation;
use crate::fft;
use crate::residuals::{LjungBox, ljung_box};
use nalgebra::DMatrix;
use rustfft::num_complex::Complex64;

/// One record in the frequency domain: per channel the residual's DFT (scaled by 1/√N)
/// and the impulse response's, at the record's own N lines (independent for white
/// noise), and each channel's sensor group.
pub(crate) struct Lines {
    pub size: usize,
    pub groups: Vec<usize>,
    pub residual: Vec<Vec<Complex64>>,
    pub transfer: Vec<Vec<Complex64>>,
}

/// The fitted spectral model: σ²_a per sensor group and σ²_u, with the test.
pub(crate) struct SpectralModel {
    pub sensor_variance: Vec<f64>,
    pub input_variance: f64,
    /// The covariance of (σ²_u, σ²_a…) from the Whittle likelihood's Fisher
    /// information, `None` where it is singular.
    pub covariance: Option<DMatrix<f64>>,
    pub likelihood_ratio: f64,
    pub p_value: f64,
}

/// The residual's DFT at its own `size` lines, scaled by 1/√size.
pub(crate) fn residual_spectrum(r: impl Iterator<Item = f64>, size: usize) -> Vec<Complex64> {
    spectrum(r, size, 1.0 / (size as f64).sqrt())
}

/// The impulse response's DFT zero-padded (or cut) to `size` lines.
pub(crate) fn impulse_spectrum(g: impl Iterator<Item = f64>, size: usize) -> Vec<Complex64> {
    spectrum(g, size, 1.0)
}

/// The padded FFT length for a record of `len` samples.
pub(super) fn padded(len: usize) -> usize {
    (2 * len).next_power_of_two()
}

/// The DFT of `x` zero-padded to `size`, times `scale`.
pub(crate) fn spectrum(x: impl Iterator<Item = f64>, size: usize, scale: f64) -> Vec<Complex64> {
    let mut buffer = vec![Complex64::new(0.0, 0.0); size];
    for (b, v) in buffer.iter_mut().zip(x) {
        b.re = v * scale;
    }
    fft::forward(size).process(&mut buffer);
    buffer
}

/// The one-sided lines of an unpadded DFT used by the likelihood: no mean, no Nyquist.
pub(crate) fn likelihood_lines(size: usize) -> std::ops::Range<usize> {
    1..size.div_ceil(2)
}

/// Ljung–Box (`lags` lags) on channel `ch` of `lines` whitened by `model`:
/// S_aa(ω)^(−1/2) applied line by line, the mean dropped; `len` samples.
pub(crate) fn whitened_ljung_box(
    lines: &Lines,
    ch: usize,
    model: &SpectralModel,
    lags: usize,
    len: usize,
) -> LjungBox {
    let g = lines.groups[ch];
    let mut z: Vec<Complex64> = (0..lines.size)
        .map(|k| {
            let t = lines.transfer[ch][k];
            let s = model.sensor_variance[g] + model.input_variance * t.norm_sqr();
            lines.residual[ch][k] / s.max(f64::MIN_POSITIVE).sqrt()
        })
        .collect();
    z[0] = Complex64::new(0.0, 0.0);
    fft::inverse(lines.size).process(&mut z);
    let series: Vec<f64> = z.iter().map(|v| v.re).collect();
    ljung_box(&autocorrelation(&series, lags), len)
}
