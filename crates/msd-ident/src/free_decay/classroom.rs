//! The classroom estimates of a free decay: the logarithmic decrement of successive
//! peaks and the damped frequency from zero crossings.

use crate::error::{IdentError, Result};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The textbook reading of a ring-down, beside the fit for comparison.
///
/// The peaks are the record's extremes (found on the record averaged over a tenth of a
/// half period, so that a noise spike is not taken for one, and each read off the
/// least-squares parabola through the raw samples within that tenth) where the
/// swing exceeds ten times the noise; the decrement δ comes from the peak-to-peak swings,
/// which do not depend on the sensor's offset: each half cycle shrinks them by
/// e^(−δ/2), so δ is −2 × the slope of their logarithm, each weighted by its square (the
/// inverse variance of ln s). Under the noise of `configs/free-decay.toml` (σ = 1 % of
/// the release) it is within 0.1 % of the analytic δ on average over 200 seeds (the
/// three-sample peaks it had before were lifted by the noise: 13 % low).
/// ζ = δ/√(4π² + δ²). The damped frequency comes from the crossings of the equilibrium
/// (half a period apart), the equilibrium read off successive extremes.
///
/// ```
/// use msd_ident::free_decay::ClassroomEstimates;
/// // Successive peaks in ratio 3 : 2.
/// let delta = 1.5f64.ln();
/// let (fd, dt) = (2.0, 1e-3);
/// let sigma = delta * fd;
/// let y: Vec<f64> = (0..3000)
///     .map(|i| { let t = i as f64 * dt; 1e-3 + (-sigma * t).exp() * (2.0 * std::f64::consts::PI * fd * t).cos() })
///     .collect();
/// let c = ClassroomEstimates::from_record(dt, &y)?;
/// assert!((c.log_decrement - delta).abs() < 1e-4, "{c}");
/// assert!((c.damped_frequency_hz - fd).abs() < 1e-3, "{c}");
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ClassroomEstimates {
    /// Extremes used (alternate peaks and troughs).
    pub peaks: usize,
    /// δ, the logarithmic decrement per period.
    pub log_decrement: f64,
    /// ζ = δ/√(4π² + δ²).
    pub damping_ratio: f64,
    /// Zero crossings counted.
    pub zero_crossings: usize,
    /// fd from the zero crossings, Hz.
    pub damped_frequency_hz: f64,
    /// fn = fd/√(1 − ζ²), Hz.
    pub natural_frequency_hz: f64,
}

impl std::fmt::Display for ClassroomEstimates {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "classroom: δ = {:.4} from {} peaks → ζ = {:.5}; fd = {:.5} Hz from {} zero crossings → fn = {:.5} Hz",
            self.log_decrement,
            self.peaks,
            self.damping_ratio,
            self.damped_frequency_hz,
            self.zero_crossings,
            self.natural_frequency_hz
        )
    }
}

impl ClassroomEstimates {
    /// Reads the decrement and the damped frequency off `y`, sampled every `dt` s.
    /// Refused when fewer than two oscillations stand above the noise, or when the swings
    /// do not shrink.
    pub fn from_record(dt: f64, y: &[f64]) -> Result<Self> {
        let noise = noise_level(y);
        let extremes = smoothed_extremes(y, noise);
        let swings: Vec<f64> = extremes
            .windows(2)
            .map(|w| (w[1].1 - w[0].1).abs())
            .take_while(|s| *s > 10.0 * noise)
            .collect();
        if swings.len() < 3 {
            return Err(not_decaying(format!(
                "{} half cycles stand above the noise (σ ≈ {noise:.3e}); at least two oscillations are needed",
                swings.len()
            )));
        }
        let log_decrement = -2.0 * weighted_slope(&swings);
        if !(log_decrement > 0.0 && log_decrement.is_finite()) {
            return Err(not_decaying(format!(
                "the swings do not shrink (δ = {log_decrement:.4})"
            )));
        }
        let used = &extremes[..=swings.len()];
        let reference = equilibrium(used);
        let crossings = zero_crossings(y, used, reference, dt);
        if crossings.len() < 2 {
            return Err(not_decaying("fewer than two zero crossings".into()));
        }
        let span = crossings[crossings.len() - 1] - crossings[0];
        let damped_frequency_hz = (crossings.len() - 1) as f64 / (2.0 * span);
        let damping_ratio = log_decrement / (4.0 * PI * PI + log_decrement.powi(2)).sqrt();
        Ok(Self {
            peaks: used.len(),
            log_decrement,
            damping_ratio,
            zero_crossings: crossings.len(),
            damped_frequency_hz,
            natural_frequency_hz: damped_frequency_hz / (1.0 - damping_ratio.powi(2)).sqrt(),
        })
    }
}

fn not_decaying(why: String) -> IdentError {
    IdentError::NotIdentifiable {
        reason: format!("the record is not a free decay that rings down: {why}"),
    }
}

/// The noise's standard deviation from the median absolute second difference (whose
/// variance is 6σ² for white noise on a smooth signal).
fn noise_level(y: &[f64]) -> f64 {
    let mut d2: Vec<f64> = y
        .windows(3)
        .map(|w| (w[2] - 2.0 * w[1] + w[0]).abs())
        .collect();
    let mid = d2.len() / 2;
    let median = *d2.select_nth_unstable_by(mid, f64::total_cmp).1;
    let range = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    (median / (0.6745 * 6f64.sqrt())).max(1e-12 * range)
}

/// Alternating extremes (time, value) with hysteresis `h`, refined by a parabola.
fn extremes(y: &[f64], h: f64) -> Vec<(f64, f64)> {
    let mut found = Vec::new();
    let mut best = 0;
    let mut looking_for_max = y.get(1).is_some_and(|v| *v >= y[0]);
    for i in 1..y.len() {
        let better = if looking_for_max {
            y[i] > y[best]
        } else {
            y[i] < y[best]
        };
        if better {
            best = i;
        } else if (y[i] - y[best]).abs() > h {
            found.push(refine(y, best));
            looking_for_max = !looking_for_max;
            best = i;
        }
    }
    found
}

/// The extremes of `y` (noise σ `noise`): found on the record averaged over a tenth of a
/// half period (the half period from a first pass on the raw record), where a noise spike
/// cannot pass for an extreme, then each re-read on the raw record ([`averaged`]). The
/// moving average scales every peak of a decay by one factor, so the ratios of the
/// swings stay unbiased.
fn smoothed_extremes(y: &[f64], noise: f64) -> Vec<(f64, f64)> {
    let raw = extremes(y, 6.0 * noise);
    let mut gaps: Vec<f64> = raw.windows(2).map(|w| w[1].0 - w[0].0).collect();
    if gaps.len() < 2 {
        return raw;
    }
    let mid = gaps.len() / 2;
    let half_period = *gaps.select_nth_unstable_by(mid, f64::total_cmp).1;
    let w = (0.1 * half_period).round().max(1.0) as usize;
    let mut prefix = vec![0.0; y.len() + 1];
    for (i, v) in y.iter().enumerate() {
        prefix[i + 1] = prefix[i] + v;
    }
    let smooth: Vec<f64> = (0..y.len())
        .map(|i| {
            let (a, b) = (i.saturating_sub(w), (i + w + 1).min(y.len()));
            (prefix[b] - prefix[a]) / (b - a) as f64
        })
        .collect();
    let found = extremes(&smooth, 6.0 * noise / ((2 * w + 1) as f64).sqrt());
    averaged(y, &found)
}

/// Each extreme re-read from the least-squares parabola through the samples within a
/// tenth of a half period of it, which averages the noise a three-sample vertex keeps
/// (the largest of many noisy samples lifts every peak by about two σ: a constant added
/// to every swing, which biases the decrement of a ring-down low). Every peak of a decay
/// has one shape, so what the parabola leaves of the cosine's top scales each swing
/// alike and does not bias their ratio. An extreme whose fit has the wrong curvature, or
/// a vertex outside the window, keeps its three-sample value.
fn averaged(y: &[f64], extremes: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut gaps: Vec<f64> = extremes.windows(2).map(|w| w[1].0 - w[0].0).collect();
    if gaps.is_empty() {
        return extremes.to_vec();
    }
    let mid = gaps.len() / 2;
    let half_period = *gaps.select_nth_unstable_by(mid, f64::total_cmp).1;
    let w = (0.1 * half_period).round().max(1.0) as usize;
    extremes
        .iter()
        .enumerate()
        .map(|(k, &(t, v))| {
            // A maximum stands above its neighbouring extremes, a minimum below them.
            let neighbour = extremes[if k == 0 { 1 } else { k - 1 }].1;
            let peak_sign = if v > neighbour { -1.0 } else { 1.0 };
            let i0 = t.round() as usize;
            let (from, to) = (i0.saturating_sub(w), (i0 + w).min(y.len() - 1));
            quadratic_vertex(y, i0, from, to)
                .filter(|&(u, _, c)| u.abs() <= w as f64 && c.signum() == peak_sign)
                .map_or((t, v), |(u, value, _)| (i0 as f64 + u, value))
        })
        .collect()
}

/// The vertex (offset from `i0`, value) and the curvature of the least-squares parabola
/// through samples `from..=to`; `None` when it is degenerate.
fn quadratic_vertex(y: &[f64], i0: usize, from: usize, to: usize) -> Option<(f64, f64, f64)> {
    let mut ata = nalgebra::Matrix3::<f64>::zeros();
    let mut atb = nalgebra::Vector3::<f64>::zeros();
    for (j, &value) in y.iter().enumerate().take(to + 1).skip(from) {
        let u = j as f64 - i0 as f64;
        let row = nalgebra::Vector3::new(1.0, u, u * u);
        ata += row * row.transpose();
        atb += row * value;
    }
    let [a, b, c] = ata.cholesky()?.solve(&atb).into();
    if c == 0.0 || !c.is_finite() {
        return None;
    }
    let u = -b / (2.0 * c);
    Some((u, a - b * b / (4.0 * c), c))
}

/// The vertex (fractional sample index, value) of the parabola through samples i−1, i, i+1.
fn refine(y: &[f64], i: usize) -> (f64, f64) {
    if i == 0 || i + 1 >= y.len() {
        return (i as f64, y[i]);
    }
    let (a, b, c) = (y[i - 1], y[i], y[i + 1]);
    let curvature = a - 2.0 * b + c;
    if curvature == 0.0 {
        return (i as f64, b);
    }
    let p = 0.5 * (a - c) / curvature;
    (i as f64 + p, b - 0.25 * (a - c) * p)
}

/// The equilibrium level: for three successive extremes e₀, e₁, e₂ of a decay around o,
/// e₁ − o = −r·(e₀ − o) and e₂ − o = −r·(e₁ − o), so o = (e₀e₂ − e₁²)/(e₀ + e₂ − 2e₁)
/// whatever the decay rate r; the median over all triples.
fn equilibrium(extremes: &[(f64, f64)]) -> f64 {
    let mut levels: Vec<f64> = extremes
        .windows(3)
        .map(|w| {
            let (e0, e1, e2) = (w[0].1, w[1].1, w[2].1);
            (e0 * e2 - e1 * e1) / (e0 + e2 - 2.0 * e1)
        })
        .filter(|o| o.is_finite())
        .collect();
    if levels.is_empty() {
        return extremes.iter().map(|e| e.1).sum::<f64>() / extremes.len().max(1) as f64;
    }
    let mid = levels.len() / 2;
    *levels.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// The times where `y` crosses `level` between successive `extremes`: one crossing
/// each, where the least-squares line through the samples within half the smaller swing
/// of the level meets it (noise near the level would otherwise cross it many times).
fn zero_crossings(y: &[f64], extremes: &[(f64, f64)], level: f64, dt: f64) -> Vec<f64> {
    extremes
        .windows(2)
        .filter_map(|w| {
            let half = 0.5 * (w[0].1 - level).abs().min((w[1].1 - level).abs());
            let (from, to) = (
                w[0].0.ceil() as usize,
                (w[1].0.floor() as usize).min(y.len() - 1),
            );
            let near: Vec<(f64, f64)> = (from..=to)
                .filter(|&i| (y[i] - level).abs() < half)
                .map(|i| (i as f64, y[i] - level))
                .collect();
            let (slope, intercept) = line(&near)?;
            (slope != 0.0).then(|| -intercept / slope * dt)
        })
        .collect()
}

/// The least-squares line (slope, intercept) through `points`; `None` for fewer than 2.
fn line(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    if points.len() < 2 {
        return None;
    }
    let n = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    (sxx > 0.0).then(|| (sxy / sxx, my - sxy / sxx * mx))
}

/// The slope of ln(swing) against the swing's index, each weighted by swing² (the
/// inverse variance of ln s when every swing carries the same noise): the small swings
/// near the noise, whose peaks the noise lifts, count as little as they inform.
fn weighted_slope(swings: &[f64]) -> f64 {
    let w: Vec<f64> = swings.iter().map(|s| s * s).collect();
    let total: f64 = w.iter().sum();
    let mean_i = w.iter().enumerate().map(|(i, w)| i as f64 * w).sum::<f64>() / total;
    let mean_v = w.iter().zip(swings).map(|(w, s)| w * s.ln()).sum::<f64>() / total;
    let (num, den) =
        w.iter()
            .zip(swings)
            .enumerate()
            .fold((0.0, 0.0), |(num, den), (i, (w, s))| {
                let di = i as f64 - mean_i;
                (num + w * di * (s.ln() - mean_v), den + w * di * di)
            });
    num / den
}
