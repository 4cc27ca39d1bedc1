//! The residuals and impulse responses in the frequency domain, and the Whittle
//! likelihood of the spectral model S = D + σ²_u·G·Gᴴ fitted to them.

use super::restricted::{Expected, line_log_likelihood};
use crate::correlation::autocorrelation;
use crate::fft;
use crate::residuals::{LjungBox, ljung_box};
use msd_opt::{NelderMeadOptions, nelder_mead};
use nalgebra::DMatrix;
use rustfft::num_complex::Complex64;
use statrs::distribution::{ChiSquared, ContinuousCDF};

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

/// σ²_a (one per group, `groups` of them) and σ²_u maximising the Whittle likelihood
/// (Nelder–Mead in ln σ²_a and ψ = σ_u/σ_ref, σ²_ref the drive noise that matches the
/// first group's at the first record's largest gain), then the likelihood ratio against
/// σ_u = 0.
///
/// With `expected` (one per record), the likelihood is the restricted one: each line's
/// residual cross-spectrum as the fit left it ([`super::restricted`]).
pub(crate) fn maximise(
    lines: &[Lines],
    groups: usize,
    expected: Option<&[Expected]>,
) -> SpectralModel {
    let white = white_variances(lines, groups);
    let peak = likelihood_lines(lines[0].size)
        .map(|k| lines[0].transfer[0][k].norm_sqr())
        .fold(0.0, f64::max);
    let reference = white[0] / peak.max(f64::MIN_POSITIVE);
    let unpack = |x: &[f64]| {
        let d: Vec<f64> = x[..groups].iter().map(|v| v.exp()).collect();
        (d, reference * x[groups] * x[groups])
    };
    let cost = |x: &[f64]| {
        let (d, s_u) = unpack(x);
        -log_likelihood(lines, &d, s_u, expected)
    };
    let mut x0: Vec<f64> = white.iter().map(|d| d.ln()).collect();
    x0.push(0.5);
    let options = NelderMeadOptions {
        x_tolerance: 1e-6,
        f_tolerance: 1e-6,
        max_evaluations: Some(1000 * (groups + 1)),
        max_iterations: Some(1000 * (groups + 1)),
        ..NelderMeadOptions::default()
    };
    let white_cost = -log_likelihood(lines, &white, 0.0, expected);
    let (d, s_u, best) = match nelder_mead(cost, &x0, &options) {
        Ok(fit) if fit.cost < white_cost => {
            let (d, s_u) = unpack(&fit.x);
            (d, s_u, fit.cost)
        }
        _ => (white.clone(), 0.0, white_cost),
    };
    let likelihood_ratio = 2.0 * (white_cost - best);
    let p_value = 0.5
        * ChiSquared::new(1.0)
            .map(|c| c.sf(likelihood_ratio))
            .unwrap_or(1.0);
    let covariance = fisher(lines, &d, s_u).try_inverse();
    SpectralModel {
        sensor_variance: d,
        input_variance: s_u,
        covariance,
        likelihood_ratio,
        p_value,
    }
}

/// Each group's mean line power: the white model's variances.
fn white_variances(lines: &[Lines], groups: usize) -> Vec<f64> {
    let (mut power, mut members) = (vec![0.0; groups], vec![0.0; groups]);
    for l in lines {
        for (ch, &g) in l.groups.iter().enumerate() {
            for k in likelihood_lines(l.size) {
                power[g] += l.residual[ch][k].norm_sqr();
                members[g] += 1.0;
            }
        }
    }
    power
        .iter()
        .zip(&members)
        .map(|(p, m)| (p / m).max(f64::MIN_POSITIVE))
        .collect()
}

/// a = Gᴴ·D⁻¹·G and b = Gᴴ·D⁻¹·R at line k.
fn projections(l: &Lines, k: usize, d: &[f64]) -> (f64, Complex64) {
    let (mut a, mut b) = (0.0, Complex64::new(0.0, 0.0));
    for (ch, &g) in l.groups.iter().enumerate() {
        let t = l.transfer[ch][k];
        a += t.norm_sqr() / d[g];
        b += t.conj() * l.residual[ch][k] / d[g];
    }
    (a, b)
}

/// The Whittle log-likelihood −Σ (ln det S + Rᴴ·S⁻¹·R), S = D + σ²_u·G·Gᴴ; with
/// `expected`, S is each line's expected residual cross-spectrum (where that is not
/// positive definite, the line keeps S).
fn log_likelihood(lines: &[Lines], d: &[f64], s_u: f64, expected: Option<&[Expected]>) -> f64 {
    let mut total = 0.0;
    let variances: Vec<f64> = std::iter::once(s_u).chain(d.iter().copied()).collect();
    let mut work = Vec::new();
    let mut residual = Vec::new();
    for (r, l) in lines.iter().enumerate() {
        let log_det_d: f64 = l.groups.iter().map(|&g| d[g].ln()).sum();
        for (i, k) in likelihood_lines(l.size).enumerate() {
            if let Some(matrices) = expected.and_then(|e| e[r].lines[i].as_ref()) {
                residual.clear();
                residual.extend((0..l.groups.len()).map(|ch| l.residual[ch][k]));
                if let Some(v) = line_log_likelihood(matrices, &variances, &residual, &mut work) {
                    total += v;
                    continue;
                }
            }
            let (a, b) = projections(l, k, d);
            let quadratic: f64 = l
                .groups
                .iter()
                .enumerate()
                .map(|(ch, &g)| l.residual[ch][k].norm_sqr() / d[g])
                .sum();
            total -=
                log_det_d + (1.0 + s_u * a).ln() + quadratic - s_u * b.norm_sqr() / (1.0 + s_u * a);
        }
    }
    total
}

/// The Fisher information of (σ²_u, σ²_a…) in the Whittle likelihood:
/// F_ij = Σ tr(S⁻¹·∂ᵢS·S⁻¹·∂ⱼS) over the records' lines, S = D + σ²_u·G·Gᴴ.
fn fisher(lines: &[Lines], d: &[f64], s_u: f64) -> DMatrix<f64> {
    let q = 1 + d.len();
    let mut f = DMatrix::<f64>::zeros(q, q);
    for l in lines {
        let c = l.groups.len();
        for k in likelihood_lines(l.size) {
            let g = nalgebra::DVector::from_fn(c, |ch, _| l.transfer[ch][k]);
            let mut s = &g * g.adjoint() * Complex64::new(s_u, 0.0);
            for (ch, &group) in l.groups.iter().enumerate() {
                s[(ch, ch)] += d[group];
            }
            let Some(inverse) = s.try_inverse() else {
                continue;
            };
            // S⁻¹·∂S for σ²_u, then for each group.
            let mut m = vec![&inverse * &g * g.adjoint()];
            for group in 0..d.len() {
                let mut part = DMatrix::<Complex64>::zeros(c, c);
                for (ch, &of) in l.groups.iter().enumerate() {
                    if of == group {
                        part.set_column(ch, &inverse.column(ch));
                    }
                }
                m.push(part);
            }
            for i in 0..q {
                for j in i..q {
                    let t = (&m[i] * &m[j]).trace().re;
                    f[(i, j)] += t;
                    if i != j {
                        f[(j, i)] += t;
                    }
                }
            }
        }
    }
    f
}
