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

/// The DFTs of real sequences zero-padded to `size`, times `scale`, two to each complex
/// FFT: z = x + i·y transforms to Z, split into X and Y by [`fft::split`].
/// Half the transforms of [`spectrum`] for the same lines to rounding (the smaller of
/// a pair carries the larger's rounding, 1e-16 of it).
pub(crate) fn spectra<I: Iterator<Item = f64>>(
    sequences: impl IntoIterator<Item = I>,
    size: usize,
    scale: f64,
) -> Vec<Vec<Complex64>> {
    let mut sequences = sequences.into_iter();
    let mut out = Vec::new();
    while let Some(x) = sequences.next() {
        let Some(y) = sequences.next() else {
            out.push(spectrum(x, size, scale));
            break;
        };
        let mut z = vec![Complex64::new(0.0, 0.0); size];
        for (z, v) in z.iter_mut().zip(x) {
            z.re = v * scale;
        }
        for (z, v) in z.iter_mut().zip(y) {
            z.im = v * scale;
        }
        fft::forward(size).process(&mut z);
        let (x, y): (Vec<_>, Vec<_>) = (0..size)
            .map(|k| fft::split(z[k], z[(size - k) % size]))
            .unzip();
        out.extend([x, y]);
    }
    out
}

/// The inverse DFTs (unnormalised) of conjugate-symmetric spectra of length `size`,
/// real sequences, two to each complex FFT: the inverse of X + i·Y is x + i·y.
pub(crate) fn real_inverses(
    spectra: impl IntoIterator<Item = Vec<Complex64>>,
    size: usize,
) -> Vec<Vec<f64>> {
    let mut spectra = spectra.into_iter();
    let mut out = Vec::new();
    while let Some(mut z) = spectra.next() {
        let second = spectra.next();
        if let Some(y) = &second {
            for (z, y) in z.iter_mut().zip(y) {
                *z += Complex64::new(-y.im, y.re);
            }
        }
        fft::inverse(size).process(&mut z);
        out.push(z.iter().map(|v| v.re).collect());
        if second.is_some() {
            out.push(z.iter().map(|v| v.im).collect());
        }
    }
    out
}

/// The one-sided lines of an unpadded DFT used by the likelihood: no mean, no Nyquist.
pub(crate) fn likelihood_lines(size: usize) -> std::ops::Range<usize> {
    1..size.div_ceil(2)
}

/// Ljung–Box (`lags` lags) on channel `ch` of `lines` whitened by `model`:
/// S_aa(ω)^(−1/2) applied line by line, the mean dropped; `len` samples.
///
/// `transient` holds the DFTs (scaled as the residual's) of the channel's free
/// responses: from a unit initial displacement and velocity for one mass, from the
/// states an impulse reaches for a chain, or nothing. The DFT takes the record
/// as one period of a periodic series, so the state the noise leaves at its end, x_N,
/// wraps round to its start: a term C·(I − e^(−iω)·A)⁻¹·(x₀ − x_N) at every line,
/// which lies in the span of those two free responses and which S does not hold. It
/// decays as 1/ω where a displacement's drive noise decays as 1/ω², so a displacement
/// sensor under a noisy drive saw a coloured residual where there was none (Q in the
/// hundreds in a third of simulated 3 % records). Its two real coefficients are
/// projected out of the whitened lines (as the weighted estimate concentrates each
/// record's initial state out) before the test.
pub(crate) fn whitened_ljung_box(
    lines: &Lines,
    ch: usize,
    model: &SpectralModel,
    lags: usize,
    len: usize,
    transient: &[Vec<Complex64>],
) -> LjungBox {
    let g = lines.groups[ch];
    let roots: Vec<f64> = (0..lines.size)
        .map(|k| {
            let t = lines.transfer[ch][k];
            let s = model.sensor_variance[g] + model.input_variance * t.norm_sqr();
            s.max(f64::MIN_POSITIVE).sqrt()
        })
        .collect();
    let whiten = |x: &[Complex64]| -> Vec<Complex64> {
        let mut z: Vec<Complex64> = x.iter().zip(&roots).map(|(x, r)| x / r).collect();
        z[0] = Complex64::new(0.0, 0.0);
        z
    };
    let mut z = whiten(&lines.residual[ch]);
    if let [b0, b1] = transient {
        z = concentrate(z, &[whiten(b0), whiten(b1)]).0;
    } else if !transient.is_empty() {
        let columns: Vec<Vec<Complex64>> = transient.iter().map(|b| whiten(b)).collect();
        project_out(&mut z, &columns);
    }
    fft::inverse(lines.size).process(&mut z);
    let series: Vec<f64> = z.iter().map(|v| v.re).collect();
    ljung_box(&autocorrelation(&series, lags), len)
}

/// z − B·β̂ with β̂ real, by least squares on the lines: any number of `columns` (a
/// chain's free responses, more than its states: dependent directions, below 1e-10 of
/// the largest singular value of their Gram matrix, are dropped) projected out.
fn project_out(z: &mut [Complex64], columns: &[Vec<Complex64>]) {
    let dot = |a: &[Complex64], b: &[Complex64]| -> f64 {
        a.iter().zip(b).map(|(x, y)| (x.conj() * y).re).sum()
    };
    let q = columns.len();
    let gram = DMatrix::from_fn(q, q, |i, j| dot(&columns[i], &columns[j]));
    let right = nalgebra::DVector::from_fn(q, |i, _| dot(&columns[i], z));
    let svd = gram.svd(true, true);
    let largest = svd.singular_values.max();
    let Ok(beta) = svd.solve(&right, 1e-10 * largest) else {
        return;
    };
    for (b, column) in beta.iter().zip(columns) {
        for (v, x) in z.iter_mut().zip(column) {
            *v -= x * b;
        }
    }
}

/// ε_R − ε_B·x̂ with x̂ real, by least squares on the whitened lines, and x̂: the two
/// columns `b0`, `b1` (a record's free responses, whitened as `e` is) projected out.
pub(crate) fn concentrate(
    mut e: Vec<Complex64>,
    [b0, b1]: &[Vec<Complex64>; 2],
) -> (Vec<Complex64>, [f64; 2]) {
    let dot = |a: &[Complex64], b: &[Complex64]| -> f64 {
        a.iter().zip(b).map(|(x, y)| (x.conj() * y).re).sum()
    };
    let (a00, a01, a11) = (dot(b0, b0), dot(b0, b1), dot(b1, b1));
    let (r0, r1) = (dot(b0, &e), dot(b1, &e));
    let det = a00 * a11 - a01 * a01;
    if det <= 0.0 {
        return (e, [0.0; 2]);
    }
    let x0 = (a11 * r0 - a01 * r1) / det;
    let x1 = (a00 * r1 - a01 * r0) / det;
    for ((v, p), q) in e.iter_mut().zip(b0).zip(b1) {
        *v -= p * x0 + q * x1;
    }
    (e, [x0, x1])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paired inverses give back the sequences the paired transforms took.
    #[test]
    fn paired_inverses_undo_the_paired_transforms() {
        let sequences: Vec<Vec<f64>> = (0..3)
            .map(|s| {
                (0..9)
                    .map(|t| ((t * (s + 2)) as f64 * 0.3).cos() - s as f64)
                    .collect()
            })
            .collect();
        let transformed = spectra(sequences.iter().map(|x| x.iter().copied()), 9, 1.0);
        let back = real_inverses(transformed, 9);
        assert_eq!(back.len(), 3);
        for (x, y) in sequences.iter().zip(&back) {
            for (a, b) in x.iter().zip(y) {
                assert!((a - b / 9.0).abs() < 1e-13, "{a} against {}", b / 9.0);
            }
        }
    }

    /// Two at a time, an odd one left over, odd and even lengths, padded: each is its
    /// own transform to rounding.
    #[test]
    fn paired_spectra_are_each_sequences_own() {
        for (len, size) in [(7usize, 7usize), (10, 10), (5, 16)] {
            let sequences: Vec<Vec<f64>> = (0..3)
                .map(|s| {
                    (0..len)
                        .map(|t| ((t * (s + 3)) as f64 * 0.7).sin() + s as f64)
                        .collect()
                })
                .collect();
            let paired = spectra(sequences.iter().map(|x| x.iter().copied()), size, 0.5);
            assert_eq!(paired.len(), 3);
            for (x, pair) in sequences.iter().zip(&paired) {
                let own = spectrum(x.iter().copied(), size, 0.5);
                for (a, b) in pair.iter().zip(&own) {
                    assert!((a - b).norm() < 1e-13, "{len} {size}: {a} against {b}");
                }
            }
        }
    }

    /// Whatever lies in the span of the two free responses leaves the test unmoved (it
    /// is projected out), and without them the same term colours the residual.
    #[test]
    fn the_end_states_wrap_round_is_projected_out() {
        let n = 512;
        let free = |phase: f64| -> Vec<f64> {
            (0..n)
                .map(|t| (-0.01 * t as f64).exp() * (0.3 * t as f64 + phase).cos())
                .collect()
        };
        let scale = 1.0 / (n as f64).sqrt();
        let transient: Vec<Vec<Complex64>> = [0.0, 1.2]
            .iter()
            .map(|&phase| spectrum(free(phase).into_iter(), n, scale))
            .collect();
        // A white residual, then the same plus a large multiple of the free responses.
        let white = msd_signal::gaussian_noise(3, "residual", 1.0, n).expect("noise");
        let lines_of = |x: &[f64]| Lines {
            size: n,
            groups: vec![0],
            residual: vec![residual_spectrum(x.iter().copied(), n)],
            transfer: vec![vec![Complex64::new(0.0, 0.0); n]],
        };
        let model = SpectralModel {
            sensor_variance: vec![1.0],
            input_variance: 0.0,
            covariance: None,
            likelihood_ratio: 0.0,
            p_value: 1.0,
        };
        let wrapped: Vec<f64> = (white.iter().zip(free(0.0)).zip(free(1.2)))
            .map(|((w, a), b)| w + 3.0 * a - 2.0 * b)
            .collect();
        let test =
            |x: &[f64], t: &[Vec<Complex64>]| whitened_ljung_box(&lines_of(x), 0, &model, 20, n, t);
        let (plain, moved) = (test(&white, &transient), test(&wrapped, &transient));
        assert!(
            (plain.q - moved.q).abs() < 1e-9 * plain.q,
            "{plain:?} {moved:?}"
        );
        assert!(plain.p_value > 0.01, "{plain:?}");
        assert!(test(&wrapped, &[]).p_value < 1e-6);
    }
}
