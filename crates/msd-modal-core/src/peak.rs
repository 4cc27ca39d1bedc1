//! The dominant resonance of a frequency response, and the band a one-mode fit takes
//! around it when none is given.

use msd_signal::FrequencyResponseEstimate;
use serde::Serialize;

use crate::error::{ModalError, Result};

/// Half-power bandwidths taken on each side of the peak.
pub const BANDWIDTHS: f64 = 10.0;

/// Lines taken on each side of the peak at least (a peak narrower than a line), before
/// any valley.
const MIN_SIDE_LINES: usize = 8;

/// How far the peak's power must stand above the median line's (10 dB): the highest of
/// a thousand three-line averages of noise alone stands about 5 times above it.
pub const PROMINENCE: f64 = 10.0;

/// The dominant resonance of a frequency response (see [`dominant_peak`]).
///
/// ```
/// use msd_modal_core::{ModalParameters, dominant_peak};
/// use msd_signal::FrequencyResponseEstimate;
/// let modes = [(40.0, 0.01, 1.0), (90.0, 0.01, 2.0)].map(|(f, z, a)| ModalParameters {
///     natural_frequency_hz: f, damping_ratio: z, modal_constant: a, modal_constant_imaginary: 0.0 });
/// let f: Vec<f64> = (0..=1000).map(|i| 0.125 * i as f64).collect();
/// let h = f.iter().map(|&f| modes.iter().map(|m| m.receptance(f)).sum()).collect();
/// let peak = dominant_peak(&FrequencyResponseEstimate::new(f, h)?)?;
/// // The 40 Hz mode stands highest in receptance (its modal constant over ζω²).
/// assert!((peak.peak_hz - 40.0).abs() <= 0.125);
/// assert!((peak.half_power_bandwidth_hz - 0.8).abs() < 0.1);
/// assert!(peak.band_hz[0] >= 31.0 && peak.band_hz[1] <= 49.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DominantPeak {
    /// The highest line of the peak, Hz.
    pub peak_hz: f64,
    /// Its half-power bandwidth as the data show it (where the magnitude falls to 1/√2
    /// of the peak's on each side), at least one line spacing, Hz.
    pub half_power_bandwidth_hz: f64,
    /// The band around it: the peak ± [`BANDWIDTHS`] half-power bandwidths, cut at a
    /// valley before another peak and at the data's ends (at least 8 lines each side
    /// where the data have them).
    pub band_hz: [f64; 2],
    /// Whether the band was cut at a valley on the low and the high side.
    pub cut_at_valley: [bool; 2],
}

impl std::fmt::Display for DominantPeak {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the band {:.4}–{:.4} Hz around the dominant resonance, peak at {:.4} Hz with a half-power bandwidth of {:.4} Hz (±{BANDWIDTHS} bandwidths",
            self.band_hz[0], self.band_hz[1], self.peak_hz, self.half_power_bandwidth_hz
        )?;
        match self.cut_at_valley {
            [true, true] => write!(f, ", cut at the valleys on both sides)"),
            [true, false] => write!(f, ", cut at the valley below)"),
            [false, true] => write!(f, ", cut at the valley above)"),
            [false, false] => write!(f, ")"),
        }
    }
}

/// The dominant resonance of `frf` in its measured quantity: of the lines that stand
/// above both their sides (the magnitude, averaged over three lines, falls to 1/√2 of
/// it on each side before rising above it), the one where the coherence-weighted power
/// γ²·|H|² is largest (γ² = 1 where the coherence says nothing), so that a spike where
/// the force had no power (γ² near 0) does not win. Its half-power bandwidth is read
/// where the averaged power falls to half on each side; the band is the peak ±
/// [`BANDWIDTHS`] bandwidths, cut at a valley where the averaged power, once below a
/// tenth of the peak's, rises four times above its lowest since the peak (another mode,
/// or the floor's noise); at least 8 lines each side where the data have them.
///
/// Errors when no such line stands [`PROMINENCE`] times (10 dB) above the median line's
/// power: the data hold no resonance that noise could not make (a heavily damped mode
/// may not stand out so far: give its band).
pub fn dominant_peak(frf: &FrequencyResponseEstimate) -> Result<DominantPeak> {
    let lines: Vec<usize> = (0..frf.frequency.len())
        .filter(|&k| frf.frequency[k] > 0.0 && frf.h[k].norm().is_finite())
        .collect();
    let n = lines.len();
    let power: Vec<f64> = lines.iter().map(|&k| frf.h[k].norm_sqr()).collect();
    let informative = frf.has_coherence_in([0.0, f64::INFINITY]);
    let weight: Vec<f64> = (lines.iter())
        .map(|&k| if informative { frf.coherence[k] } else { 1.0 })
        .collect();
    let smooth = |v: &[f64]| -> Vec<f64> {
        (0..n)
            .map(|k| {
                let (a, b) = (k.saturating_sub(1), (k + 1).min(n - 1));
                v[a..=b].iter().sum::<f64>() / (b - a + 1) as f64
            })
            .collect()
    };
    let s = smooth(&power);
    let weighted: Vec<f64> = power.iter().zip(&weight).map(|(p, w)| p * w).collect();
    let rank = smooth(&weighted);
    let mut maxima: Vec<usize> = (1..n.saturating_sub(1))
        .filter(|&k| s[k] >= s[k - 1] && s[k] > s[k + 1])
        .collect();
    maxima.sort_by(|&a, &b| rank[b].total_cmp(&rank[a]));
    let mut sorted = s.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted.get(n / 2).copied().unwrap_or(0.0);
    let Some((k, [left, right])) = maxima
        .iter()
        .filter(|&&k| s[k] >= PROMINENCE * median)
        .find_map(|&k| Some((k, [half_power(&s, k, false)?, half_power(&s, k, true)?])))
    else {
        return Err(ModalError::NotIdentifiable {
            reason: format!(
                "no resonance stands out: none of the {n} lines above 0 Hz stands above both its sides (the magnitude, averaged over three lines, falling to 1/√2 of it on each side before rising above it) and {PROMINENCE} times above the median line's power"
            ),
        });
    };
    let f = |i: usize| frf.frequency[lines[i]];
    let top = (k - 1..=k + 1)
        .max_by(|&a, &b| power[a].total_cmp(&power[b]))
        .unwrap_or(k);
    let spacing = (f(k + 1) - f(k - 1)) / 2.0;
    let crossing = |j: usize, inner: usize| {
        let t = (s[inner] - s[k] / 2.0) / (s[inner] - s[j]);
        f(inner) + t.clamp(0.0, 1.0) * (f(j) - f(inner))
    };
    let bandwidth = (crossing(right, right - 1) - crossing(left, left + 1)).max(spacing);
    let reach = (BANDWIDTHS * bandwidth).max(MIN_SIDE_LINES as f64 * spacing);
    let (low, low_cut) = band_edge(&s, k, left, false, |j| f(top) - f(j) > reach);
    let (high, high_cut) = band_edge(&s, k, right, true, |j| f(j) - f(top) > reach);
    Ok(DominantPeak {
        peak_hz: f(top),
        half_power_bandwidth_hz: bandwidth,
        band_hz: [f(low), f(high)],
        cut_at_valley: [low_cut, high_cut],
    })
}

/// The first line from the maximum `k` of `s` (towards higher lines when `up`) where
/// `s` falls to half of `s[k]`; `None` when it rises above `s[k]` first or the data end.
fn half_power(s: &[f64], k: usize, up: bool) -> Option<usize> {
    let mut j = k;
    loop {
        j = if up { j + 1 } else { j.checked_sub(1)? };
        let v = *s.get(j)?;
        if v > s[k] {
            return None;
        }
        if v <= s[k] / 2.0 {
            return Some(j);
        }
    }
}

/// The band's last line on one side of the maximum `k`, walking out from the half-power
/// line `start` until `beyond(j)` or the data's end, or cut at a valley; and whether it
/// was cut.
fn band_edge(
    s: &[f64],
    k: usize,
    start: usize,
    up: bool,
    beyond: impl Fn(usize) -> bool,
) -> (usize, bool) {
    let (mut last, mut lowest) = (start, start);
    let mut j = start;
    loop {
        let next = if up { j + 1 } else { j.wrapping_sub(1) };
        if next >= s.len() || beyond(next) {
            return (last, false);
        }
        j = next;
        if j.abs_diff(k) > MIN_SIDE_LINES && s[lowest] < s[k] / 10.0 && s[j] > 4.0 * s[lowest] {
            return (lowest, true);
        }
        if s[j] < s[lowest] {
            lowest = j;
        }
        last = j;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use msd_signal::Complex64;

    /// Noise alone (no line stands above both sides by √2 after averaging, or if one
    /// does, it is found) never panics; a flat response has no resonance.
    #[test]
    fn a_flat_response_has_no_resonance() {
        let f: Vec<f64> = (0..100).map(f64::from).collect();
        let frf = FrequencyResponseEstimate::new(f, vec![Complex64::new(1.0, 0.0); 100]).unwrap();
        let e = dominant_peak(&frf).unwrap_err();
        assert!(e.to_string().contains("no resonance"), "{e}");
    }

    /// A spike on one line where the coherence is 0 loses to the mode.
    #[test]
    fn the_coherence_outweighs_an_unexcited_spike() {
        let f: Vec<f64> = (0..=400).map(|i| 0.25 * i as f64).collect();
        let mode = crate::ModalParameters {
            natural_frequency_hz: 60.0,
            damping_ratio: 0.02,
            modal_constant: 1.0,
            modal_constant_imaginary: 0.0,
        };
        let mut h: Vec<Complex64> = f.iter().map(|&f| mode.receptance(f)).collect();
        let mut frf = FrequencyResponseEstimate::new(f, h.clone()).unwrap();
        let peak = h[240].norm();
        h[19..=21].fill(Complex64::new(20.0 * peak, 0.0));
        frf.coherence[19..=21].fill(0.0);
        frf.h = h;
        frf.averages = 10;
        let p = dominant_peak(&frf).unwrap();
        assert!((p.peak_hz - 60.0).abs() <= 0.25, "{p}");
    }
}
