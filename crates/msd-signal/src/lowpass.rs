//! Zero-phase low-pass filtering and differentiation of a sampled record: what inverse
//! dynamic identification needs to take a measured stroke's velocity and acceleration
//! (filter the position and the force alike, then central differences).

use crate::error::{Result, SignalError, check_data, positive};
use std::f64::consts::PI;

/// `x` sampled at `sample_rate` through a 4th-order Butterworth low-pass at `cutoff_hz`,
/// run forward and backward (MATLAB's and scipy's `filtfilt`): no phase shift, an 8th-
/// order roll-off, a gain of exactly 1/(1 + (tan(πf/fs)/tan(πf_c/fs))⁸) at f in steady
/// state (the bilinear transform's, prewarped at the cut-off).
///
/// The record is extended at both ends by its odd reflection (10 periods of the cut-off
/// long) and each pass starts in the steady state of its first sample, so a constant
/// or a ramp passes unchanged and the ends carry no start-up transient.
///
/// ```
/// let fs = 1000.0;
/// let x: Vec<f64> = (0..4000).map(|i| (2.0 * std::f64::consts::PI * 5.0 * i as f64 / fs).sin()).collect();
/// let y = msd_signal::lowpass_zero_phase(&x, fs, 50.0)?;
/// // 5 Hz under a 50 Hz cut-off: gain 1 − 1e-8, no delay.
/// assert!((y[2000] - x[2000]).abs() < 1e-6);
/// # Ok::<(), msd_signal::SignalError>(())
/// ```
pub fn lowpass_zero_phase(x: &[f64], sample_rate: f64, cutoff_hz: f64) -> Result<Vec<f64>> {
    check_data("x", x)?;
    positive(|| "sample_rate".into(), sample_rate)?;
    positive(|| "cutoff_hz".into(), cutoff_hz)?;
    if cutoff_hz >= 0.5 * sample_rate {
        return Err(SignalError::InvalidParameter {
            parameter: "cutoff_hz".into(),
            value: cutoff_hz,
            expected: "below the Nyquist frequency (half the sampling rate)",
        });
    }
    let sections = butterworth4(cutoff_hz / sample_rate);
    let n = x.len();
    let pad = ((10.0 * sample_rate / cutoff_hz).ceil() as usize).min(n - 1);
    // Odd reflection: 2·x₀ − x[pad..1], x, 2·x_{n−1} − x[n−2..n−1−pad].
    let mut y: Vec<f64> = (1..=pad).rev().map(|i| 2.0 * x[0] - x[i]).collect();
    y.extend_from_slice(x);
    y.extend((1..=pad).map(|i| 2.0 * x[n - 1] - x[n - 1 - i]));
    for _ in 0..2 {
        for s in &sections {
            s.run(&mut y);
        }
        y.reverse();
    }
    Ok(y[pad..pad + n].to_vec())
}

/// The derivative of `x` sampled every `dt` by central differences (one-sided at the
/// ends), as numpy's `gradient`: exact for a parabola inside, second-order accurate.
///
/// ```
/// let x: Vec<f64> = (0..5).map(|i| (i * i) as f64).collect();
/// assert_eq!(msd_signal::central_difference(&x, 1.0)?, vec![1.0, 2.0, 4.0, 6.0, 7.0]);
/// # Ok::<(), msd_signal::SignalError>(())
/// ```
pub fn central_difference(x: &[f64], dt: f64) -> Result<Vec<f64>> {
    check_data("x", x)?;
    positive(|| "dt".into(), dt)?;
    let n = x.len();
    if n < 2 {
        return Ok(vec![0.0; n]);
    }
    Ok((0..n)
        .map(|i| match i {
            0 => (x[1] - x[0]) / dt,
            _ if i == n - 1 => (x[n - 1] - x[n - 2]) / dt,
            _ => (x[i + 1] - x[i - 1]) / (2.0 * dt),
        })
        .collect())
}

/// One second-order section (transposed direct form II) with unit DC gain.
struct Biquad {
    b: [f64; 3],
    a: [f64; 2],
}

impl Biquad {
    /// Filters `y` in place, starting in the steady state of its first sample.
    fn run(&self, y: &mut [f64]) {
        let [b0, b1, b2] = self.b;
        let [a1, a2] = self.a;
        let u = y.first().copied().unwrap_or(0.0);
        let mut z2 = (b2 - a2) * u;
        let mut z1 = (b1 - a1) * u + z2;
        for v in y.iter_mut() {
            let x = *v;
            let out = b0 * x + z1;
            z1 = b1 * x - a1 * out + z2;
            z2 = b2 * x - a2 * out;
            *v = out;
        }
    }
}

/// The two sections of a 4th-order Butterworth low-pass at `f` cycles per sample, by
/// the bilinear transform prewarped at the cut-off.
fn butterworth4(f: f64) -> [Biquad; 2] {
    let k = (PI * f).tan();
    [0usize, 1].map(|i| {
        let q = 1.0 / (2.0 * (PI * (2 * i + 1) as f64 / 8.0).cos());
        let norm = 1.0 / (1.0 + k / q + k * k);
        let b0 = k * k * norm;
        Biquad {
            b: [b0, 2.0 * b0, b0],
            a: [2.0 * (k * k - 1.0) * norm, (1.0 - k / q + k * k) * norm],
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The steady-state gain at f against the bilinear Butterworth's squared magnitude,
    /// across the pass band, the cut-off and the stop band.
    #[test]
    fn the_gain_is_the_squared_butterworth_magnitude() {
        let (fs, fc) = (1000.0, 40.0);
        for f in [5.0, 20.0, 40.0, 60.0, 120.0] {
            let x: Vec<f64> = (0..20_000)
                .map(|i| (2.0 * PI * f * i as f64 / fs).sin())
                .collect();
            let y = lowpass_zero_phase(&x, fs, fc).unwrap();
            let ratio = ((PI * f / fs).tan() / (PI * fc / fs).tan()).powi(8);
            let gain = 1.0 / (1.0 + ratio);
            // Amplitude from the middle: the least-squares sine at f (zero phase: in
            // phase with x).
            let mid = 5000..15_000;
            let (xy, xx): (f64, f64) =
                mid.fold((0.0, 0.0), |(a, b), i| (a + x[i] * y[i], b + x[i] * x[i]));
            assert!(
                (xy / xx - gain).abs() < 1e-6,
                "f = {f}: {} against {gain}",
                xy / xx
            );
        }
    }

    #[test]
    fn a_ramp_passes_unchanged_to_its_ends() {
        let x: Vec<f64> = (0..500).map(|i| 0.3 + 0.01 * i as f64).collect();
        let y = lowpass_zero_phase(&x, 100.0, 5.0).unwrap();
        for (a, b) in x.iter().zip(&y) {
            assert!((a - b).abs() < 1e-9, "{a} against {b}");
        }
        assert!(lowpass_zero_phase(&x, 100.0, 60.0).is_err());
    }
}
