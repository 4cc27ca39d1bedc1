//! Preprocessing of measured data: offsets, trends, smoothing, decimation, resampling.
//!
//! Every function checks its input first and refuses, with a specific [`SignalError`],
//! empty data, mismatched lengths, NaN or infinite samples (naming the index), time
//! stamps that repeat or go back, and windows longer than the data. None of them
//! panics on user input; each returns a new vector.
//!
//! ```
//! use msd_signal::{detrend_linear, moving_average, SignalError};
//!
//! let drift: Vec<f64> = (0..100).map(|i| 0.5 + 0.01 * i as f64).collect();
//! let flat = detrend_linear(&drift)?;
//! assert!(flat.iter().all(|v| v.abs() < 1e-12));
//!
//! let bad = [1.0, f64::NAN, 3.0];
//! assert!(matches!(moving_average(&bad, 3), Err(SignalError::NonFinite { index: 1, .. })));
//! # Ok::<(), SignalError>(())
//! ```

use std::f64::consts::PI;

use crate::error::{Result, SignalError, check_data, finite, positive, same_length};

/// Checks time stamps: non-empty, finite and strictly increasing.
pub(crate) fn check_times(name: &'static str, t: &[f64]) -> Result<()> {
    check_data(name, t)?;
    for (index, w) in t.windows(2).enumerate() {
        if w[1] <= w[0] {
            return Err(SignalError::NonMonotonicTime {
                index: index + 1,
                previous: w[0],
                current: w[1],
            });
        }
    }
    Ok(())
}

/// `x` minus its mean.
///
/// ```
/// let y = msd_signal::remove_mean(&[1.0, 2.0, 3.0])?;
/// assert_eq!(y, vec![-1.0, 0.0, 1.0]);
/// # Ok::<(), msd_signal::SignalError>(())
/// ```
pub fn remove_mean(x: &[f64]) -> Result<Vec<f64>> {
    check_data("x", x)?;
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    Ok(x.iter().map(|v| v - mean).collect())
}

/// `x` minus a known `offset` (e.g. a sensor zero measured before the test).
pub fn remove_offset(x: &[f64], offset: f64) -> Result<Vec<f64>> {
    check_data("x", x)?;
    finite(|| "offset".into(), offset)?;
    Ok(x.iter().map(|v| v - offset).collect())
}

/// Residual of the least-squares line through (a, x).
fn detrend_against(a: &[f64], x: &[f64]) -> Vec<f64> {
    let n = x.len() as f64;
    let am = a.iter().sum::<f64>() / n;
    let xm = x.iter().sum::<f64>() / n;
    let (mut sax, mut saa) = (0.0, 0.0);
    for (ai, xi) in a.iter().zip(x) {
        sax += (ai - am) * (xi - xm);
        saa += (ai - am) * (ai - am);
    }
    let slope = if saa > 0.0 { sax / saa } else { 0.0 };
    a.iter()
        .zip(x)
        .map(|(ai, xi)| xi - xm - slope * (ai - am))
        .collect()
}

/// `x` minus its least-squares straight line, for uniformly sampled data (the line is
/// fitted against the sample index). Needs at least 2 samples.
pub fn detrend_linear(x: &[f64]) -> Result<Vec<f64>> {
    check_data("x", x)?;
    if x.len() < 2 {
        return Err(SignalError::TooShort {
            name: "x",
            len: x.len(),
            min: 2,
        });
    }
    let index: Vec<f64> = (0..x.len()).map(|i| i as f64).collect();
    Ok(detrend_against(&index, x))
}

/// `x` minus its least-squares straight line in time `t` (any strictly increasing
/// stamps). Needs at least 2 samples.
pub fn detrend_linear_at(t: &[f64], x: &[f64]) -> Result<Vec<f64>> {
    check_times("t", t)?;
    check_data("x", x)?;
    same_length("t", t, "x", x)?;
    if x.len() < 2 {
        return Err(SignalError::TooShort {
            name: "x",
            len: x.len(),
            min: 2,
        });
    }
    Ok(detrend_against(t, x))
}

/// Centred moving average over an odd `window` of samples (i − h … i + h, h = window/2).
///
/// At the ends the window is cut to the samples that exist and the average is taken
/// over those, so the output has the input's length and a constant stays constant.
/// Zero phase (no delay). Errors if `window` is even or zero, or longer than the data.
///
/// ```
/// let y = msd_signal::moving_average(&[0.0, 3.0, 0.0, 3.0, 0.0], 3)?;
/// assert_eq!(y, vec![1.5, 1.0, 2.0, 1.0, 1.5]);
/// # Ok::<(), msd_signal::SignalError>(())
/// ```
pub fn moving_average(x: &[f64], window: usize) -> Result<Vec<f64>> {
    check_data("x", x)?;
    if window == 0 || window.is_multiple_of(2) {
        return Err(SignalError::InvalidParameter {
            parameter: "window".into(),
            value: window as f64,
            expected: "an odd number of samples >= 1",
        });
    }
    if window > x.len() {
        return Err(SignalError::WindowTooLong {
            window,
            len: x.len(),
        });
    }
    let h = window / 2;
    let n = x.len();
    Ok((0..n)
        .map(|i| {
            let lo = i.saturating_sub(h);
            let hi = (i + h).min(n - 1);
            x[lo..=hi].iter().sum::<f64>() / (hi - lo + 1) as f64
        })
        .collect())
}

/// Half-length (taps each side) of the decimation filter, per unit of factor.
const DECIMATE_HALF_TAPS_PER_FACTOR: usize = 8;
/// Cut-off of the decimation filter as a fraction of the new Nyquist frequency.
const DECIMATE_CUTOFF: f64 = 0.8;

/// Low-pass filters `x` and keeps every `factor`-th sample (`x[0]`, `x[factor]`, …).
///
/// ## The anti-alias filter
/// A zero-phase FIR low-pass: a Hamming-windowed sinc with cut-off at 0.8 × the new
/// Nyquist frequency (0.4·fs/factor) and 2·8·factor + 1 taps, normalised to unit DC
/// gain. Near the ends the taps that fall outside the data are dropped and the rest
/// renormalised, so a constant decimates to itself and there is no delay. It passes
/// components well below 0.4·fs/factor nearly unchanged and attenuates those above the
/// new Nyquist frequency by roughly 40 dB or more. `factor = 1` returns a copy.
///
/// ```
/// let x = vec![2.0; 100];
/// let y = msd_signal::decimate(&x, 4)?;
/// assert_eq!(y.len(), 25);
/// assert!(y.iter().all(|v| (v - 2.0).abs() < 1e-12));
/// # Ok::<(), msd_signal::SignalError>(())
/// ```
pub fn decimate(x: &[f64], factor: usize) -> Result<Vec<f64>> {
    check_data("x", x)?;
    if factor == 0 {
        return Err(SignalError::InvalidParameter {
            parameter: "factor".into(),
            value: 0.0,
            expected: "an integer >= 1",
        });
    }
    if factor == 1 {
        return Ok(x.to_vec());
    }
    if factor > x.len() {
        return Err(SignalError::WindowTooLong {
            window: factor,
            len: x.len(),
        });
    }
    let h = DECIMATE_HALF_TAPS_PER_FACTOR * factor;
    let fc = DECIMATE_CUTOFF * 0.5 / factor as f64; // cycles per sample
    let taps: Vec<f64> = (0..=2 * h)
        .map(|j| {
            let m = j as f64 - h as f64;
            let sinc = if m == 0.0 {
                2.0 * fc
            } else {
                (2.0 * PI * fc * m).sin() / (PI * m)
            };
            let hamming = 0.54 + 0.46 * (PI * m / h as f64).cos();
            sinc * hamming
        })
        .collect();
    let n = x.len();
    Ok((0..n)
        .step_by(factor)
        .map(|i| {
            let (mut acc, mut gain) = (0.0, 0.0);
            let lo = i.saturating_sub(h);
            let hi = (i + h).min(n - 1);
            for (k, xk) in x.iter().enumerate().take(hi + 1).skip(lo) {
                let w = taps[k + h - i];
                acc += w * xk;
                gain += w;
            }
            debug_assert!(gain > 0.0, "a truncated low-pass keeps a positive DC gain");
            acc / gain
        })
        .collect())
}

/// Linear interpolation of non-uniform samples (t, x) onto the uniform grid
/// t₀, t₀ + dt, t₀ + 2·dt, … up to the last stamp; returns `(t_new, x_new)`.
///
/// Each new point is interpolated on a straight line between the two neighbouring
/// samples, so a linear function is reproduced exactly (to rounding) and there is no
/// smoothing. The grid starts at the first stamp and ends at the last grid point not
/// after the last stamp (within 1e-9·dt). `t` must be strictly increasing.
///
/// ```
/// let (t, x) = msd_signal::resample_uniform(&[0.0, 0.3, 1.0], &[0.0, 3.0, 10.0], 0.25)?;
/// assert_eq!(t, vec![0.0, 0.25, 0.5, 0.75, 1.0]);
/// assert!((x[2] - 5.0).abs() < 1e-12);
/// # Ok::<(), msd_signal::SignalError>(())
/// ```
pub fn resample_uniform(t: &[f64], x: &[f64], dt: f64) -> Result<(Vec<f64>, Vec<f64>)> {
    check_times("t", t)?;
    check_data("x", x)?;
    same_length("t", t, "x", x)?;
    positive(|| "dt".into(), dt)?;
    let t0 = t[0];
    let t_last = t[t.len() - 1];
    let steps = ((t_last - t0) / dt + 1e-9).floor();
    if !steps.is_finite() || steps > 1e9 {
        return Err(SignalError::InvalidParameter {
            parameter: "dt".into(),
            value: dt,
            expected: "a step giving at most 1e9 grid points",
        });
    }
    let n_new = steps as usize + 1;
    let mut t_new = Vec::with_capacity(n_new);
    let mut x_new = Vec::with_capacity(n_new);
    let mut j = 0; // segment index: t[j] <= tau <= t[j+1]
    for i in 0..n_new {
        let tau = (t0 + i as f64 * dt).min(t_last);
        while j + 2 < t.len() && t[j + 1] < tau {
            j += 1;
        }
        let value = if t.len() == 1 {
            x[0]
        } else {
            let w = (tau - t[j]) / (t[j + 1] - t[j]);
            x[j] + w * (x[j + 1] - x[j])
        };
        t_new.push(tau);
        x_new.push(value);
    }
    Ok((t_new, x_new))
}
