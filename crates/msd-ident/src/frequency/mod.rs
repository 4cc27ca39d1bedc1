//! Frequency-consistency check: the data's frequency response beside the model's.
//!
//! ## The method
//! - For the Bode plot, the H1 estimate Ŝ_yu/Ŝ_uu over the whole record (one
//!   Hann-windowed segment, mean removed: a lightly damped mode's half-power bandwidth,
//!   2ζfn ≈ 0.11 Hz for the paper's plant, is below the resolution of any Welch
//!   segmentation of a 15 s record, so averaging is not an option): msd-signal's
//!   [`DftPair::hann_h1`](msd_signal::DftPair::hann_h1), which equals its `h1_estimate`
//!   with one periodic-Hann segment and mean detrending, computed from the same single
//!   FFT ([`DftPair`]) as the fit below. With one segment the
//!   coherence is 1 by construction and says nothing; it is reported for completeness.
//! - For ωn and ζ, a parametric single-mode fit to the record's DFT (rectangular window,
//!   no averaging): Y(ω) = (G·U(ω) + a + j·b·ω) / (ωn² − ω² + 2jζωnω). The numerator term
//!   a + jbω models the leakage of the transient (the record starts at rest and ends
//!   mid-oscillation; Pintelon & Schoukens, "System Identification: A Frequency Domain
//!   Approach", ch. 6), which otherwise broadens the peak and inflates ζ several-fold.
//!   For fixed (ωn, ζ) the fit is linear in (G, a, b) and solved exactly; (ln ωn, ln ζ)
//!   are found by Nelder–Mead from the peak of |Y/U|. The fit uses the band where the
//!   input carries at least `power_threshold` of its peak DFT power.
//! - The record: its first N' samples, N' the largest length ≤ N whose prime factors are
//!   2, 3, 5 and 7, so the FFT runs at full speed (the paper's 7501 = 13·577 samples take
//!   five times longer to transform than 7500). At most a few per cent of the record is
//!   left out (7501 → 7500; under 4 % for N ≥ 1000, under 2 % for N ≥ 10 000); [`FrequencyCheck::samples_used`] says
//!   how many samples were used.
//! - Limits: the resolution 1/T (0.067 Hz for 15 s) against the bandwidth 2ζfn; the fit
//!   assumes one mode and a linear plant; the continuous-time form of the transient term
//!   is accurate while ω·dt ≪ 1.
//! - Verdict: consistent when the fitted fn and ζ agree with the model's within
//!   `frequency_tolerance` and `damping_tolerance` (relative; ζ relative to the larger of
//!   the model's ζ and the resolution floor 1/(2·fn·T), so that a lightly or un-damped
//!   model compares finitely), and the model explains the DFT in the band (normalised
//!   output error below `max_relative_error`).
//! - Refusals ([`IdentError::NotIdentifiable`]): an input without power above DC (or
//!   below the FFT's rounding of the output), and data without a resonance (an
//!   over-damped plant: the fit runs off to ζ ≥ 1, or outside the fitted frequency lines
//!   to a mode narrower than their spacing, 2ζ·fn < 1/T, such as fn → 0 with ζ → 0).

mod mode_fit;

use crate::{
    data::DataSet,
    error::{IdentError, Result},
    params::Parameters,
    uncertainty::Uncertainty,
};
use mode_fit::{SingleModeFit, transient_for};
use msd_opt::{NelderMeadOptions, nelder_mead};
use msd_signal::{Complex64, DftPair};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Options of [`frequency_check`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FrequencyCheckOptions {
    /// Fit band in Hz; `None` picks it from the input's power. By default `None`.
    #[serde(default, deserialize_with = "msd_signal::pair::optional")]
    pub band_hz: Option<[f64; 2]>,
    /// Share of the input's peak DFT power that marks a frequency as excited.
    /// By default 0.01.
    pub power_threshold: f64,
    /// Allowed relative difference of fn between data and model. By default 0.01.
    pub frequency_tolerance: f64,
    /// Allowed relative difference of ζ between data and model. By default 0.2 (the
    /// resolution limit of a short record).
    pub damping_tolerance: f64,
    /// Allowed normalised output error of the model in the band. By default 0.25.
    pub max_relative_error: f64,
}

impl Default for FrequencyCheckOptions {
    fn default() -> Self {
        Self {
            band_hz: None,
            power_threshold: 0.01,
            frequency_tolerance: 0.01,
            damping_tolerance: 0.2,
            max_relative_error: 0.25,
        }
    }
}

impl FrequencyCheckOptions {
    /// Checks every option.
    pub fn validate(&self) -> Result<()> {
        let invalid = |name, value, expected| {
            Err(IdentError::InvalidParameter {
                name,
                value,
                expected,
            })
        };
        if let Some([low, high]) = self.band_hz {
            if !(low.is_finite() && low >= 0.0) {
                return invalid("band_hz[0]", low, "a finite frequency >= 0 Hz");
            }
            if !(high.is_finite() && high > low) {
                return invalid("band_hz[1]", high, "a finite frequency above band_hz[0]");
            }
        }
        if !(self.power_threshold > 0.0 && self.power_threshold <= 1.0) {
            return invalid(
                "power_threshold",
                self.power_threshold,
                "a share of the peak power in (0, 1]",
            );
        }
        for (name, value) in [
            ("frequency_tolerance", self.frequency_tolerance),
            ("damping_tolerance", self.damping_tolerance),
            ("max_relative_error", self.max_relative_error),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return invalid(name, value, "a finite number > 0");
            }
        }
        Ok(())
    }
}

/// The result of [`frequency_check`].
///
/// Displays the data's and the model's fn and ζ with the outcome, then the verdict.
///
/// ```
/// use msd_ident::{frequency::{frequency_check, FrequencyCheckOptions}, PaperExperiment, Parameters};
/// let experiment = PaperExperiment::generate(1)?;
/// let check = frequency_check(&experiment.validation, &Parameters::PAPER, None, &FrequencyCheckOptions::default())?;
/// assert!(check.to_string().starts_with("data fn = 1.10"), "{check}");
/// let json = serde_json::to_value(&check).expect("serializable");
/// assert_eq!(json["consistent"], true);
/// assert_eq!(json["band_hz"].as_array().map(Vec::len), Some(2));
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrequencyCheck {
    /// Frequencies of the arrays below (Hz), up to 3× the band's upper edge.
    pub frequency_hz: Vec<f64>,
    /// |H1| from the data.
    pub empirical_magnitude: Vec<f64>,
    /// ∠H1 in degrees.
    pub empirical_phase_deg: Vec<f64>,
    /// Coherence of the H1 estimate (1 with a single segment).
    pub coherence: Vec<f64>,
    /// |H| of the identified model.
    pub model_magnitude: Vec<f64>,
    /// ∠H of the identified model in degrees.
    pub model_phase_deg: Vec<f64>,
    /// The band of the single-mode fit, Hz.
    pub band_hz: [f64; 2],
    /// fn from the single-mode fit to the data, Hz.
    pub natural_frequency_hz: f64,
    /// ζ from the single-mode fit to the data.
    pub damping_ratio: f64,
    /// fn of the identified model, Hz.
    pub model_natural_frequency_hz: f64,
    /// ζ of the identified model.
    pub model_damping_ratio: f64,
    /// Standard error of the model's fn, when known.
    pub model_natural_frequency_se: Option<f64>,
    /// Standard error of the model's ζ, when known.
    pub model_damping_ratio_se: Option<f64>,
    /// Normalised output error of the model in the band, ‖Y − H U‖/‖Y‖ (transient removed).
    pub model_relative_error: f64,
    /// Samples of the record used: the largest 7-smooth length ≤ N (see the module docs).
    pub samples_used: usize,
    /// Whether data and model agree.
    pub consistent: bool,
    /// The verdict in words.
    pub verdict: String,
}

impl std::fmt::Display for FrequencyCheck {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "data fn = {:.4} Hz, ζ = {:.4}; model fn = {:.4} Hz, ζ = {:.4}: {}",
            self.natural_frequency_hz,
            self.damping_ratio,
            self.model_natural_frequency_hz,
            self.model_damping_ratio,
            if self.consistent {
                "consistent"
            } else {
                "inconsistent"
            }
        )?;
        write!(f, "{}", self.verdict)
    }
}

/// Compares the frequency response in `data` with that of `parameters`.
///
/// ```
/// use msd_ident::{frequency::{frequency_check, FrequencyCheckOptions}, PaperExperiment, Parameters};
/// let experiment = PaperExperiment::generate(1)?;
/// let check = frequency_check(&experiment.validation, &Parameters::PAPER, None, &FrequencyCheckOptions::default())?;
/// assert!(check.consistent, "{}", check.verdict);
/// assert!((check.natural_frequency_hz / 1.1027 - 1.0).abs() < 0.01);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn frequency_check(
    data: &DataSet,
    parameters: &Parameters,
    uncertainty: Option<&Uncertainty>,
    options: &FrequencyCheckOptions,
) -> Result<FrequencyCheck> {
    parameters.validate()?;
    options.validate()?;
    let n = smooth_length(data.len());
    let dt = data.excitation.dt();
    let fs = 1.0 / dt;
    let u = &data.excitation.samples()[..n];
    let y = &data.output[..n];
    let spectra = DftPair::new(u, y)?;
    let (uf, yf) = (&spectra.input, &spectra.output);
    // uf, yf: the DFTs of the mean-removed records (bin 0 is 0; the other bins are the raw
    // records' DFT), so H1's mean detrending comes free.
    let df = fs / n as f64;
    let half = n / 2;
    let power: Vec<f64> = uf[..=half].iter().map(|c| c.norm_sqr()).collect();
    let peak_power = peak_input_power(&power, u, y)?;
    let band = fit_band(options, &power, peak_power, df);
    let bins: Vec<usize> = (1..=half)
        .filter(|&k| (band[0]..=band[1]).contains(&(k as f64 * df)))
        .collect();
    if bins.len() < 8 {
        return Err(IdentError::TooFewSamples {
            got: bins.len(),
            needed: 8,
            why: "frequency lines in the fit band (record too short or band too narrow)",
        });
    }
    let omega: Vec<f64> = bins.iter().map(|&k| 2.0 * PI * k as f64 * df).collect();
    let ub: Vec<Complex64> = bins.iter().map(|&k| uf[k]).collect();
    let yb: Vec<Complex64> = bins.iter().map(|&k| yf[k]).collect();

    let (wn, zeta) = fit_data_mode(&omega, &ub, &yb, options.power_threshold * peak_power)?;
    let natural_frequency_hz = wn / (2.0 * PI);
    // The fit sees the response only at its lines, f_lo … f_hi (below Nyquist). A mode
    // with ζ ≥ 1 has no resonance. A mode outside the lines is measured through its skirt,
    // which shows its damping only if its bandwidth 2ζ·fn spans at least one line
    // spacing 1/T; narrower (fn → 0 with ζ → 0 on an over-damped record), it is where the
    // optimiser ran off to, not a resonance.
    let lines = [bins[0] as f64 * df, bins[bins.len() - 1] as f64 * df];
    let inside = lines[0] <= natural_frequency_hz && natural_frequency_hz <= lines[1];
    let resolved = 2.0 * zeta * natural_frequency_hz >= df;
    let reaches = inside || resolved;
    if !(zeta < 1.0 && wn > 0.0 && wn < PI * fs && reaches) {
        let reason = no_resonance(
            lines,
            natural_frequency_hz,
            zeta,
            df,
            parameters.damping_ratio(),
        );
        return Err(IdentError::NotIdentifiable { reason });
    }

    // The model's output error in the band, with the transient term fitted for it.
    let model_h: Vec<Complex64> = omega
        .iter()
        .map(|&w| model_response(parameters, w))
        .collect();
    let model_relative_error = model_relative_error(parameters, &omega, &ub, &yb, &model_h);

    // Bode arrays: H1 over the whole record, periodic Hann window, from the same FFT.
    let f_max = (3.0 * band[1]).min(fs / 2.0);
    let h1 = spectra.hann_h1(fs, f_max)?;
    let keep: Vec<usize> = (1..h1.frequency.len())
        .filter(|&k| h1.frequency[k] <= f_max)
        .collect();
    let frequency_hz: Vec<f64> = keep.iter().map(|&k| h1.frequency[k]).collect();
    let model_curve: Vec<Complex64> = frequency_hz
        .iter()
        .map(|&f| model_response(parameters, 2.0 * PI * f))
        .collect();
    check_finite(&model_h, &model_curve, model_relative_error)?;

    let model_fn = parameters.natural_frequency_hz();
    let model_zeta = parameters.damping_ratio();
    let frequency_error = (natural_frequency_hz - model_fn) / model_fn;
    // Relative to the model's ζ, but never below the resolution floor ζ_res = 1/(2·fn·T),
    // whose half-power bandwidth is one DFT line (so an undamped model, ζ = 0, compares
    // finitely).
    let record_seconds = n as f64 * dt;
    let damping_floor = 1.0 / (2.0 * model_fn * record_seconds);
    let damping_error = (zeta - model_zeta) / model_zeta.max(damping_floor);
    let consistent = frequency_error.abs() <= options.frequency_tolerance
        && damping_error.abs() <= options.damping_tolerance
        && model_relative_error <= options.max_relative_error;
    let verdict = verdict(
        consistent,
        [natural_frequency_hz, zeta],
        [model_fn, model_zeta],
        [frequency_error, damping_error, model_relative_error],
        options,
    );
    Ok(FrequencyCheck {
        empirical_magnitude: keep.iter().map(|&k| h1.h[k].norm()).collect(),
        empirical_phase_deg: unwrap_degrees(keep.iter().map(|&k| h1.h[k].arg())),
        coherence: keep.iter().map(|&k| h1.coherence[k]).collect(),
        model_magnitude: model_curve.iter().map(|h| h.norm()).collect(),
        model_phase_deg: unwrap_degrees(model_curve.iter().map(|h| h.arg())),
        frequency_hz,
        band_hz: band,
        natural_frequency_hz,
        damping_ratio: zeta,
        model_natural_frequency_hz: model_fn,
        model_damping_ratio: model_zeta,
        model_natural_frequency_se: uncertainty.map(|u| u.natural_frequency_hz.standard_error),
        model_damping_ratio_se: uncertainty.map(|u| u.damping_ratio.standard_error),
        model_relative_error,
        samples_used: n,
        consistent,
        verdict,
    })
}

/// (ωn, ζ) of the single mode that fits the data's lines best (Nelder–Mead in ln ωn,
/// ln ζ), started at the peak of |Y/U| among the lines whose input power is at least
/// `min_power`.
fn fit_data_mode(
    omega: &[f64],
    ub: &[Complex64],
    yb: &[Complex64],
    min_power: f64,
) -> Result<(f64, f64)> {
    let start_bin = (0..omega.len())
        .filter(|&i| ub[i].norm_sqr() >= min_power)
        .max_by(|&a, &b| (yb[a] / ub[a]).norm().total_cmp(&(yb[b] / ub[b]).norm()))
        .unwrap_or(0);
    let x0 = [omega[start_bin].ln(), 0.05f64.ln()];
    let mode_fit = SingleModeFit::new(omega.to_vec(), ub.to_vec(), yb.to_vec());
    let objective = |v: &[f64]| -> f64 {
        mode_fit
            .sse(v[0].exp(), v[1].exp())
            .unwrap_or(f64::INFINITY)
    };
    // 1e-6 relative in (ln ωn, ln ζ) is far below the statistical spread of ζ (≈ 0.5 %).
    let nm = NelderMeadOptions {
        x_tolerance: 1e-6,
        f_tolerance: 1e-10,
        relative_tolerances: true,
        ..NelderMeadOptions::default()
    };
    let fit = nelder_mead(objective, &x0, &nm)?;
    Ok((fit.x[0].exp(), fit.x[1].exp()))
}

/// The input's largest line power above DC (`power` from bin 0 to Nyquist), refused
/// when the input carries none beyond the FFT's own rounding.
fn peak_input_power(power: &[f64], u: &[f64], y: &[f64]) -> Result<f64> {
    let n = u.len();
    let peak_power = power[1..].iter().fold(0.0f64, |m, &p| m.max(p));
    // Relative to the signal's energy (Parseval: Σ|U_k|² = N Σu²), so FFT rounding of a
    // constant input does not count as excitation.
    let energy: f64 = u.iter().map(|v| v * v).sum::<f64>() * n as f64;
    // The shared FFT leaks rounding of the output into the input's spectrum: at most
    // c·ε·log₂N·√N·‖z‖₂ per line (normwise FFT error, c = 10), z = (u − ū) + i(y − ȳ).
    let centred = |x: &[f64]| {
        let mean = x.iter().sum::<f64>() / n as f64;
        x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>()
    };
    let leak = 10.0
        * f64::EPSILON
        * (n as f64).log2().max(1.0)
        * (n as f64).sqrt()
        * (centred(u) + centred(y)).sqrt();
    if peak_power.is_nan() || peak_power <= 1e-24 * energy || peak_power <= leak * leak {
        return Err(IdentError::NotIdentifiable {
            reason: "the input has no power above DC: no frequency response can be measured".into(),
        });
    }
    Ok(peak_power)
}

/// The fit band: the configured one, or the lines where the input's power is at least
/// `power_threshold` of its peak.
fn fit_band(options: &FrequencyCheckOptions, power: &[f64], peak_power: f64, df: f64) -> [f64; 2] {
    let half = power.len() - 1;
    match options.band_hz {
        Some(b) => b,
        None => {
            let excited: Vec<usize> = (1..=half)
                .filter(|&k| power[k] >= options.power_threshold * peak_power)
                .collect();
            [
                excited[0] as f64 * df,
                excited[excited.len() - 1] as f64 * df,
            ]
        }
    }
}

/// Absurd (valid but huge) parameters overflow k − mω²: say so rather than print NaN.
fn check_finite(
    model_h: &[Complex64],
    model_curve: &[Complex64],
    model_relative_error: f64,
) -> Result<()> {
    if let Some(bad) = model_h
        .iter()
        .chain(model_curve)
        .find(|h| !(h.re.is_finite() && h.im.is_finite()))
    {
        return Err(IdentError::InvalidParameter {
            name: "parameters (model frequency response)",
            value: if bad.re.is_finite() { bad.im } else { bad.re },
            expected: "m, c, k whose response 1/(k − mω² + jcω) is finite over the band",
        });
    }
    if !model_relative_error.is_finite() {
        return Err(IdentError::InvalidParameter {
            name: "parameters (model relative error)",
            value: model_relative_error,
            expected: "a model whose prediction of the record's spectrum is finite",
        });
    }
    Ok(())
}

/// Why the single-mode fit found no resonance at the fitted `lines` (Hz, `df` apart):
/// it ran off to ζ ≥ 1, or to a mode outside the lines narrower than their spacing.
fn no_resonance(
    lines: [f64; 2],
    natural_frequency_hz: f64,
    zeta: f64,
    df: f64,
    model: f64,
) -> String {
    let number = |v: f64| match v.abs() {
        a if !a.is_finite() => "unbounded".to_string(),
        a if (1e-3..1e4).contains(&a) => format!("{v:.4}"),
        _ => format!("{v:.3e}"),
    };
    let (f, z) = (number(natural_frequency_hz), number(zeta));
    let (lo, hi) = (lines[0], lines[1]);
    if zeta >= 1.0 || !zeta.is_finite() {
        format!(
            "no resonance in the data: the single-mode fit at {lo:.4}–{hi:.4} Hz ran off to ζ = {z} ≥ 1 (fn = {f} Hz), an over-damped response (the model's ζ is {model:.3})"
        )
    } else {
        format!(
            "no resonance at the fitted frequencies {lo:.4}–{hi:.4} Hz: the fit ran off to fn = {f} Hz, ζ = {z}, a mode outside them and narrower (2ζ·fn) than their spacing {df:.4} Hz (the model's ζ is {model:.3}); excite the resonance or widen the band"
        )
    }
}

/// The model's output error in the band, relative to the data's energy there, with the
/// transient term a + jbω over the model's own denominator fitted for it.
fn model_relative_error(
    parameters: &Parameters,
    omega: &[f64],
    ub: &[Complex64],
    yb: &[Complex64],
    model_h: &[Complex64],
) -> f64 {
    let denominators: Vec<Complex64> = omega
        .iter()
        .map(|&w| {
            Complex64::new(
                parameters.stiffness - parameters.mass * w * w,
                parameters.damping * w,
            )
        })
        .collect();
    let mut sse = 0.0;
    let mut energy = 0.0;
    // Remove the transient a + jbω over the model's own denominator by least squares.
    let (a, b) = transient_for(omega, ub, yb, model_h, &denominators);
    for i in 0..omega.len() {
        let predicted = model_h[i] * ub[i] + Complex64::new(a, b * omega[i]) / denominators[i];
        sse += (yb[i] - predicted).norm_sqr();
        energy += yb[i].norm_sqr();
    }
    (sse / energy).sqrt()
}

/// The check's verdict in words: the two resonances, their differences against the
/// tolerances, and how much of the spectrum the model explains.
fn verdict(
    consistent: bool,
    [natural_frequency_hz, zeta]: [f64; 2],
    [model_fn, model_zeta]: [f64; 2],
    [frequency_error, damping_error, model_relative_error]: [f64; 3],
    options: &FrequencyCheckOptions,
) -> String {
    if consistent {
        format!(
            "Consistent: the data's resonance is at {natural_frequency_hz:.4} Hz with ζ = {zeta:.4}, the model's at {model_fn:.4} Hz with ζ = {model_zeta:.4} ({:+.2} % and {:+.1} %); the model explains the measured spectrum to {:.1} %.",
            100.0 * frequency_error,
            100.0 * damping_error,
            100.0 * model_relative_error
        )
    } else {
        format!(
            "Inconsistent: the data's resonance is at {natural_frequency_hz:.4} Hz with ζ = {zeta:.4}, the model's at {model_fn:.4} Hz with ζ = {model_zeta:.4} ({:+.2} % and {:+.1} %, allowed ±{:.0} % and ±{:.0} %); the model leaves {:.1} % of the measured spectrum unexplained (allowed {:.0} %).",
            100.0 * frequency_error,
            100.0 * damping_error,
            100.0 * options.frequency_tolerance,
            100.0 * options.damping_tolerance,
            100.0 * model_relative_error,
            100.0 * options.max_relative_error
        )
    }
}

/// H(jω) = 1/(k − mω² + jcω) of the displacement per unit force.
pub fn model_response(parameters: &Parameters, omega: f64) -> Complex64 {
    Complex64::new(1.0, 0.0)
        / Complex64::new(
            parameters.stiffness - parameters.mass * omega * omega,
            parameters.damping * omega,
        )
}

fn unwrap_degrees(phases: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for p in phases {
        let mut value = p.to_degrees();
        if let Some(&last) = out.last() {
            while value - last > 180.0 {
                value -= 360.0;
            }
            while value - last < -180.0 {
                value += 360.0;
            }
        }
        out.push(value);
    }
    out
}

/// The largest n' ≤ n whose only prime factors are 2, 3, 5 and 7 (n ≥ 1).
fn smooth_length(n: usize) -> usize {
    let is_smooth = |mut m: usize| {
        for p in [2, 3, 5, 7] {
            while m.is_multiple_of(p) {
                m /= p;
            }
        }
        m == 1
    };
    (1..=n).rev().find(|&m| is_smooth(m)).unwrap_or(n)
}

#[cfg(test)]
mod tests {
    use super::smooth_length;

    #[test]
    fn smooth_lengths() {
        assert_eq!(smooth_length(7501), 7500);
        assert_eq!(smooth_length(7500), 7500);
        assert_eq!(smooth_length(11), 10);
        assert_eq!(smooth_length(1), 1);
        // What the module docs promise: under 4 % left out from 1000 samples on, under
        // 2 % from 10 000 on (checked up to 2·10⁵).
        for n in 1000..200_000 {
            let m = smooth_length(n);
            let share = if n < 10_000 { 0.04 } else { 0.02 };
            assert!(m <= n && (n - m) as f64 <= share * n as f64, "{n} → {m}");
        }
    }
}
