//! What the noise model found, to be seen: each channel's residual spectrum against the
//! model's, smoothed over bands of DFT lines, with the range a band's mean takes when
//! the model is right.

use super::spectral::{Lines, SpectralModel, likelihood_lines};
use serde::Serialize;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// The fewest DFT lines a band averages.
const MIN_LINES: usize = 4;
/// A band reaches at least this factor above its first line's frequency (24 bands a
/// decade where the lines are dense).
const RATIO: f64 = 1.1;

/// One channel's residual spectrum against the noise model's: one-sided power spectral
/// densities in the channel's unit²/Hz, each averaged over a band of DFT lines (at least
/// four, and a tenth of the band's frequency wide), the mean line and the Nyquist line
/// left out.
///
/// Under the model the residual's DFT line k has the variance S_k = σ²_a + σ²_u·|G_k|²
/// (the sensor's white noise plus the drive's seen through the plant); a band's mean of
/// L lines is then S̄·χ²(2L)/(2L), and `lower`, `upper` are its 2.5 and 97.5 % points.
/// A residual outside that range over several bands is colour the model does not
/// explain. Near a resonance the residual may dip below the model: the fit absorbed part
/// of the noise there (its degrees of freedom, which the restricted likelihood counts).
/// Under the white treatment `drive` is zero and `sensor` the residual's mean level: the
/// flat spectrum the white-noise intervals assume.
///
/// ```
/// use msd_ident::records::ResidualSpectrum;
/// let s = ResidualSpectrum { frequency_hz: vec![1.0], lines: vec![4], residual: vec![2e-6],
///     sensor: 1e-6, drive: vec![1e-6], lower: vec![0.5e-6], upper: vec![4.4e-6] };
/// assert_eq!(s.model(), vec![2e-6]);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResidualSpectrum {
    /// Each band's mean frequency, Hz.
    pub frequency_hz: Vec<f64>,
    /// The number of DFT lines each band averages.
    pub lines: Vec<usize>,
    /// The residual's density averaged over each band.
    pub residual: Vec<f64>,
    /// The sensor's own white noise under the model, 2·σ²_a·Δt (flat).
    pub sensor: f64,
    /// The drive's noise through the plant, 2·σ²_u·|G(f)|²·Δt, averaged over each band.
    pub drive: Vec<f64>,
    /// The 2.5 % point of a band's residual mean under the model.
    pub lower: Vec<f64>,
    /// The 97.5 % point of a band's residual mean under the model.
    pub upper: Vec<f64>,
}

impl ResidualSpectrum {
    /// The model's density in each band: the sensor's plus the drive's.
    pub fn model(&self) -> Vec<f64> {
        self.drive.iter().map(|d| self.sensor + d).collect()
    }
}

/// Channel `ch` of `lines` (sampled every `dt` s) against `model` (the white level of
/// the residual itself without one), every density times `scale` (the square of the
/// unit the lines are in, when they are weighted).
pub(crate) fn residual_spectrum_bands(
    lines: &Lines,
    ch: usize,
    model: Option<&SpectralModel>,
    dt: f64,
    scale: f64,
) -> ResidualSpectrum {
    let density = 2.0 * dt * scale;
    let all = likelihood_lines(lines.size);
    let power = |k: usize| lines.residual[ch][k].norm_sqr();
    let (sensor, input) = match model {
        Some(m) => (m.sensor_variance[lines.groups[ch]], m.input_variance),
        None => (
            all.clone().map(power).sum::<f64>() / all.len().max(1) as f64,
            0.0,
        ),
    };
    let drive = |k: usize| match lines.transfer.get(ch) {
        Some(g) => input * g[k].norm_sqr(),
        None => 0.0,
    };
    let hz = 1.0 / (lines.size as f64 * dt);
    let mut out = ResidualSpectrum {
        frequency_hz: Vec::new(),
        lines: Vec::new(),
        residual: Vec::new(),
        sensor: density * sensor,
        drive: Vec::new(),
        lower: Vec::new(),
        upper: Vec::new(),
    };
    for band in bands(all) {
        let l = band.len();
        let mean = |f: &dyn Fn(usize) -> f64| band.clone().map(f).sum::<f64>() / l as f64;
        let d = mean(&drive);
        let (low, high) = chi_square_range(l);
        let expected = density * (sensor + d);
        out.frequency_hz.push(mean(&|k| k as f64 * hz));
        out.lines.push(l);
        out.residual.push(density * mean(&power));
        out.drive.push(density * d);
        out.lower.push(expected * low);
        out.upper.push(expected * high);
    }
    out
}

/// The 2.5 and 97.5 % points of χ²(2L)/(2L): the range of a mean of L independent
/// exponential variables of mean 1 (L periodogram lines of a flat spectrum).
fn chi_square_range(l: usize) -> (f64, f64) {
    let nu = 2.0 * l as f64;
    match ChiSquared::new(nu) {
        Ok(chi) => (chi.inverse_cdf(0.025) / nu, chi.inverse_cdf(0.975) / nu),
        Err(_) => (0.0, f64::INFINITY),
    }
}

/// The lines `all` cut into consecutive bands of at least [`MIN_LINES`] lines, each
/// reaching [`RATIO`] times its first line; a shorter tail joins the band before it.
fn bands(all: std::ops::Range<usize>) -> Vec<std::ops::Range<usize>> {
    let mut out: Vec<std::ops::Range<usize>> = Vec::new();
    let mut start = all.start;
    while start < all.end {
        let reach = (start as f64 * RATIO).ceil() as usize;
        let end = (start + MIN_LINES).max(reach).min(all.end);
        match out.last_mut() {
            Some(last) if end - start < MIN_LINES => last.end = end,
            _ => out.push(start..end),
        }
        start = end;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use rustfft::num_complex::Complex64;

    #[test]
    fn bands_cover_every_line_once_and_grow_geometrically() {
        let b = bands(1..1000);
        assert_eq!(b.first().map(|r| r.start), Some(1));
        assert_eq!(b.last().map(|r| r.end), Some(1000));
        for pair in b.windows(2) {
            assert_eq!(pair[0].end, pair[1].start);
        }
        assert!(b.iter().all(|r| r.len() >= MIN_LINES));
        // Past the dense start each band spans about a tenth of its frequency (the last
        // is cut at the last line).
        let wide = b[..b.len() - 1]
            .iter()
            .filter(|r| r.start > 100)
            .collect::<Vec<_>>();
        assert!(wide.iter().all(|r| r.end as f64 >= RATIO * r.start as f64));
        assert!(
            wide.iter()
                .all(|r| (r.end as f64) < 1.2 * r.start as f64 + 1.0)
        );
        // A record too short for one full band keeps its lines in one.
        assert_eq!(bands(1..3), vec![1..3]);
    }

    #[test]
    fn the_chi_square_range_is_the_mean_of_exponentials() {
        // L = 1: an exponential's quantiles, −ln(0.975) and −ln(0.025).
        let (low, high) = chi_square_range(1);
        assert!((low - -(0.975f64.ln())).abs() < 1e-9, "{low}");
        assert!((high - -(0.025f64.ln())).abs() < 1e-9, "{high}");
    }

    /// White noise of variance σ² sampled every dt: its one-sided density is 2σ²·dt, and
    /// each band's residual lies inside the band's 95 % range 95 % of the time.
    #[test]
    fn white_noise_lies_inside_its_range_95_percent_of_the_time() {
        let (n, dt, sigma) = (4096, 1e-3, 0.3);
        let model = SpectralModel {
            sensor_variance: vec![sigma * sigma],
            input_variance: 0.0,
            covariance: None,
            likelihood_ratio: 0.0,
            p_value: 1.0,
        };
        let (mut inside, mut bands) = (0, 0);
        for seed in 0..20 {
            let x = msd_signal::gaussian_noise(seed, "psd", sigma, n).unwrap();
            let lines = Lines {
                size: n,
                groups: vec![0],
                residual: vec![super::super::residual_spectrum(x.into_iter(), n)],
                transfer: vec![vec![Complex64::new(0.0, 0.0); n]],
            };
            let s = residual_spectrum_bands(&lines, 0, Some(&model), dt, 1.0);
            assert!((s.sensor - 2.0 * sigma * sigma * dt).abs() < 1e-15);
            assert_eq!(s.lines.iter().sum::<usize>(), n / 2 - 1);
            inside += (s.residual.iter().zip(s.lower.iter().zip(&s.upper)))
                .filter(|(r, (lo, hi))| lo <= r && r <= hi)
                .count();
            bands += s.residual.len();
            // Without a model the flat level is the residual's own mean.
            let white = residual_spectrum_bands(&lines, 0, None, dt, 1.0);
            assert!((white.sensor / s.sensor - 1.0).abs() < 0.1);
            assert!(white.drive.iter().all(|d| *d == 0.0));
        }
        // The bands are independent (so are white noise's DFT lines): the fraction's
        // standard error is √(0.95·0.05/bands), 0.007 for the 1000 bands; 3.5 of them.
        let fraction = inside as f64 / bands as f64;
        let se = (0.95 * 0.05 / bands as f64).sqrt();
        assert!(
            (fraction - 0.95).abs() < 3.5 * se,
            "{fraction} over {bands} bands"
        );
    }
}
