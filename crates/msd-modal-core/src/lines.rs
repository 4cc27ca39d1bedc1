//! The lines of a frequency response prepared for a fit: receptance, in the band, each
//! with the standard deviation of its real and imaginary parts.

use std::f64::consts::TAU;

use msd_signal::{Complex64, Estimator, FrequencyResponseEstimate, FrfKind, LineCorrelation};
use serde::{Deserialize, Serialize};

use crate::error::{ModalError, Result};

/// The largest coherence γ² a line is weighted by: 1 − 10⁻⁶ (60 dB of signal over
/// noise). Above it the weight would grow without bound; a coherence there says only
/// that the line's noise is smaller still.
pub const COHERENCE_CEILING: f64 = 1.0 - 1e-6;

/// How the lines of a frequency response are weighted in a fit: each line's residual is
/// divided by the standard deviation σ_k this gives (up to a common factor, which the
/// fit estimates from the residuals).
///
/// ```
/// use msd_modal_core::FrfWeighting;
/// #[derive(serde::Deserialize)]
/// struct Options { weighting: FrfWeighting }
/// let options: Options = toml::from_str(r#"weighting = "relative""#)?;
/// assert_eq!(options.weighting, FrfWeighting::Relative);
/// assert_eq!(FrfWeighting::default(), FrfWeighting::Coherence);
/// assert_eq!(FrfWeighting::Relative.to_string(), "relative");
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrfWeighting {
    /// From the coherence: σ_k² ∝ (1 − γ_k²)/(K·γ_k²)·|H_k|², the variance of an H1
    /// estimate averaged over K segments (Bendat & Piersol, "Random Data", eq. 9.90),
    /// with γ² clamped to [1e-6, 1 − 1e-6]. Where the coherence says nothing (one
    /// segment, or γ² = 1 on every line of the band, as in a measured table or a UFF
    /// file) this is [`Variance`](Self::Variance) when the estimate has variances, else
    /// [`Uniform`](Self::Uniform): weights relative to |H| would let the
    /// anti-resonances, where |H| is smallest and the data least certain, dominate,
    /// and make lightly damped modes unstable in the diagram. The default.
    #[default]
    Coherence,
    /// The estimate's own variances ([`FrequencyResponseEstimate::variance`]).
    Variance,
    /// σ_k ∝ |H_k|: every line measured to the same relative accuracy.
    Relative,
    /// σ_k equal in the quantity measured (receptance, mobility or accelerance, as
    /// [`FrequencyResponseEstimate::kind`] says): the absolute complex error of the data
    /// as they were measured, whatever quantity the fit converts them to.
    Uniform,
}

impl std::fmt::Display for FrfWeighting {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            FrfWeighting::Coherence => "coherence",
            FrfWeighting::Variance => "variance",
            FrfWeighting::Relative => "relative",
            FrfWeighting::Uniform => "uniform",
        })
    }
}

/// The lines used by a fit.
#[derive(Debug, Clone)]
pub struct Lines {
    /// Angular frequencies ω_k (rad/s), increasing, > 0.
    pub omega: Vec<f64>,
    /// The receptance at ω_k.
    pub h: Vec<Complex64>,
    /// The standard deviation of Re H_k and of Im H_k (up to a common factor).
    pub sigma: Vec<f64>,
    /// The standard deviations the stabilization diagram weights the lines by: those of
    /// an informative coherence, else equal in the measured quantity. LSCF's linearised
    /// equation error weighted by 1/|H| (relative or variance weights) lets the
    /// anti-resonances dominate and leaves lightly damped modes unstable.
    pub diagram_sigma: Vec<f64>,
    /// For weights relative to |H| (coherence, relative): σ_k/|H_k|, so that a fit can
    /// take |H_k| from its model instead (see [`Lines::reweight`]); empty otherwise.
    relative_sigma: Vec<f64>,
    /// Under uniform weights, each line's variance relative to the others' (mean 1), as
    /// the residuals' own noise model gives it ([`Lines::residual_variances`]): the
    /// covariance takes it in; empty where the σ say it all (every line alike).
    pub variance_scale: Vec<f64>,
    /// The band in Hz: the first and last line used.
    pub band_hz: [f64; 2],
    /// The weighting applied ([`FrfWeighting::Coherence`] without information in the
    /// coherence becomes [`FrfWeighting::Variance`] or [`FrfWeighting::Uniform`]).
    pub weighting: FrfWeighting,
    /// Decay time τ of an exponential window on the records, if any.
    pub exponential_decay: Option<f64>,
    /// Over how many lines the errors are correlated (≥ 1): the factor by which a
    /// covariance computed as if the lines were independent is too small, where
    /// [`correlation`](Self::correlation) is not known.
    pub correlated_lines: f64,
    /// How the errors of the estimate's lines are correlated (empty: not known).
    pub correlation: LineCorrelation,
    /// Each line's position among the estimate's lines (the lag between two lines).
    pub index: Vec<usize>,
    /// The share of each line's variance that the force's noise makes, once
    /// [`smooth_coherence_weights`](Self::smooth_coherence_weights) has fitted the
    /// noise model; empty before (all of it taken as the response's).
    pub force_share: Vec<f64>,
    /// p of the measured quantity, (jω)^p × receptance: 0 receptance, 1 mobility,
    /// 2 accelerance. The fit error is reported on the measured quantity.
    pub measured_power: i32,
    /// Segments K averaged into the estimate (1 for a table without coherence, 0 when
    /// a table's coherence does not say over how many).
    pub averages: usize,
    /// The estimator that formed the lines (`None` for a measured table).
    pub estimator: Option<Estimator>,
    /// The coherence's noise model, once
    /// [`smooth_coherence_weights`](Self::smooth_coherence_weights) has fitted it.
    pub noise_model: Option<CoherenceNoise>,
    /// Each line's variance of H's relative error from the force's noise, where it was
    /// measured ([`FrequencyResponseEstimate::input_noise_variance`]); empty otherwise.
    pub input_noise: Vec<f64>,
    /// The force's term a_k of each line in the coherence's noise model (see
    /// [`CoherenceNoise`]), once [`smooth_coherence_weights`](Self::smooth_coherence_weights)
    /// has set it: the fitted a on every line, or (K − 1)/(2K)·v_k·(1 + (K − 1)·v_k)²
    /// from the measured [`input_noise`](Self::input_noise) (its scatter about the true H,
    /// which the lines show low by 1 + (K − 1)·v_k).
    pub force_noise: Vec<f64>,
}

/// The noise model fitted to the lines' coherence: q_k = (1 − γ̂_k²)/(2K·γ̂_k²)·|Ĥ_k|²
/// ≈ a·|H(ω_k)|² + b·ω_k^(−2p), a the force's noise and b the response's (each relative
/// to the force's power). Where the force's noise was measured (an impact test's force
/// channel after its window), a_k = (K − 1)/(2K)·v_k is known at every line and only b
/// is fitted.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CoherenceNoise {
    /// a: the force's noise (where measured, the a that fits a_k·|H_k|² best).
    pub force: f64,
    /// b: the response's noise (flat in the measured quantity).
    pub response: f64,
    /// The standard error of a, from the scatter of q about the model (0 where a was
    /// measured).
    pub force_standard_error: f64,
    /// Whether the force's noise was measured rather than fitted to the coherence.
    pub force_measured: bool,
}

/// Each line's leverage in a least-squares fit with the weighted Jacobian `jacobian`
/// (real parts' rows, then imaginary parts'): the mean of its two rows' diagonal of
/// J(JᵀJ)⁻¹Jᵀ; empty when JᵀJ is singular.
pub fn leverages(jacobian: &nalgebra::DMatrix<f64>) -> Vec<f64> {
    let n = jacobian.nrows() / 2;
    let Some(normal) = (jacobian.transpose() * jacobian).cholesky() else {
        return Vec::new();
    };
    let solved = normal.solve(&jacobian.transpose());
    let hat = |i: usize| jacobian.row(i).dot(&solved.column(i).transpose());
    (0..n).map(|k| (hat(k) + hat(n + k)) / 2.0).collect()
}

/// Checks that the estimate's arrays have one entry per line.
fn check_shape(frf: &FrequencyResponseEstimate) -> Result<()> {
    let lines = frf.frequency.len();
    let mut arrays = vec![("h", frf.h.len()), ("coherence", frf.coherence.len())];
    if let Some(v) = &frf.variance {
        arrays.push(("variance", v.len()));
    }
    if let Some(v) = &frf.input_noise_variance {
        arrays.push(("input_noise_variance", v.len()));
    }
    for (what, got) in arrays {
        if got != lines {
            return Err(ModalError::LengthMismatch {
                what,
                expected: lines,
                got,
            });
        }
    }
    Ok(())
}

/// Checks an optional band: finite, 0 ≤ low < high.
pub fn check_band(band_hz: Option<[f64; 2]>) -> Result<()> {
    let invalid = |name, value, expected| {
        Err(ModalError::InvalidParameter {
            name,
            value,
            expected,
        })
    };
    if let Some([low, high]) = band_hz {
        if !(low.is_finite() && low >= 0.0) {
            return invalid("band_hz[0]", low, "a finite frequency >= 0 Hz");
        }
        if !(high.is_finite() && high > low) {
            return invalid("band_hz[1]", high, "a finite frequency above band_hz[0]");
        }
    }
    Ok(())
}

/// The lines of `frf` above 0 Hz and inside `band_hz` (all lines above 0 Hz when
/// `None`), as receptance, weighted by `weighting`; lines without information (zero
/// response under relative weights, infinite variance) are left out. Errors when fewer
/// than `min_lines` remain.
pub fn prepare(
    frf: &FrequencyResponseEstimate,
    band_hz: Option<[f64; 2]>,
    weighting: FrfWeighting,
    min_lines: usize,
) -> Result<Lines> {
    check_shape(frf)?;
    check_band(band_hz)?;
    if weighting == FrfWeighting::Variance && frf.variance.is_none() {
        return Err(ModalError::InvalidParameter {
            name: "weighting",
            value: f64::NAN,
            expected: "\"variance\" only for a frequency response that has variances",
        });
    }
    let receptance = frf.to_kind(FrfKind::Receptance);
    let [low, high] = band_hz.unwrap_or([0.0, f64::INFINITY]);
    let inside = |f: f64| f > 0.0 && f >= low && f <= high;
    let informative = frf.has_coherence_in([low, high]);
    let weighting = match weighting {
        FrfWeighting::Coherence if !informative && frf.variance.is_some() => FrfWeighting::Variance,
        FrfWeighting::Coherence if !informative => FrfWeighting::Uniform,
        w => w,
    };
    let averages = frf.averages.max(1) as f64;
    let measured_power = frf.kind.power();
    let mut lines = Lines {
        omega: Vec::new(),
        h: Vec::new(),
        sigma: Vec::new(),
        diagram_sigma: Vec::new(),
        relative_sigma: Vec::new(),
        variance_scale: Vec::new(),
        band_hz: [0.0; 2],
        weighting,
        exponential_decay: frf.exponential_decay,
        correlated_lines: if frf.noise_bandwidth.is_finite() {
            frf.noise_bandwidth.max(1.0)
        } else {
            1.0
        },
        correlation: frf.line_correlation.clone(),
        index: Vec::new(),
        force_share: Vec::new(),
        measured_power,
        averages: frf.averages,
        estimator: frf.estimator,
        noise_model: None,
        input_noise: Vec::new(),
        force_noise: Vec::new(),
    };
    for (k, &f) in receptance.frequency.iter().enumerate() {
        if !inside(f) {
            continue;
        }
        let h = receptance.h[k];
        // Each part carries half the complex variance.
        let relative = match weighting {
            FrfWeighting::Coherence => {
                let g = receptance.coherence[k].clamp(1e-6, COHERENCE_CEILING);
                ((1.0 - g) / (averages * g) / 2.0).sqrt()
            }
            FrfWeighting::Relative => 0.5f64.sqrt(),
            FrfWeighting::Variance | FrfWeighting::Uniform => f64::NAN,
        };
        let sigma = match weighting {
            FrfWeighting::Variance => {
                (receptance.variance.as_ref().map_or(1.0, |v| v[k]) / 2.0).sqrt()
            }
            // σ of the measured quantity equal: ω^−p in receptance.
            FrfWeighting::Uniform => 0.5f64.sqrt() * (TAU * f).powi(-measured_power),
            FrfWeighting::Coherence | FrfWeighting::Relative => relative * h.norm(),
        };
        if !(sigma.is_finite() && sigma > 0.0) {
            continue;
        }
        lines.omega.push(TAU * f);
        lines.index.push(k);
        lines.h.push(h);
        lines.sigma.push(sigma);
        lines.diagram_sigma.push(match weighting {
            FrfWeighting::Coherence => sigma,
            _ => 0.5f64.sqrt() * (TAU * f).powi(-measured_power),
        });
        if relative.is_finite() {
            lines.relative_sigma.push(relative);
        }
        if let Some(v) = &receptance.input_noise_variance {
            lines.input_noise.push(v[k]);
        }
    }
    if lines.omega.len() < min_lines {
        return Err(ModalError::TooFewSamples {
            got: lines.omega.len(),
            needed: min_lines,
            why: "frequency lines in the band with a usable weight",
        });
    }
    lines.band_hz = [
        lines.omega[0] / TAU,
        lines.omega[lines.omega.len() - 1] / TAU,
    ];
    Ok(lines)
}

impl Lines {
    /// For weights relative to |H|: σ_k from the model's |H(ω_k)| instead of the
    /// measured |Ĥ_k|, whose noise would otherwise weigh in (a line measured high would
    /// count less, biasing the fit low by about the noise variance and widening the
    /// spread). Lines where the model is 0 keep their weight. No change for the other
    /// weightings.
    pub fn reweight(&mut self, model: impl Fn(f64) -> Complex64) {
        for ((s, &r), &w) in self
            .sigma
            .iter_mut()
            .zip(&self.relative_sigma)
            .zip(&self.omega)
        {
            let candidate = r * model(w).norm();
            if candidate.is_finite() && candidate > 0.0 {
                *s = candidate;
            }
        }
    }

    /// Coherence weights from a noise model instead of each line's own coherence: the
    /// variance of an H1 line is (σ²_in·|H|² + σ²_out)/(K·S_xx) for white noise on the
    /// input and the output, so q_k = (1 − γ̂²)/(K·γ̂²)·|Ĥ|² (what each line's coherence
    /// says of it) is fitted by a·|H(ω_k)|² + b·ω_k^(−2p) over the band (the output's
    /// noise flat in the measured quantity, (jω)^p·H) (a, b ≥ 0, each line
    /// weighted by its predicted variance: q_k scatters in proportion to it), |H| from
    /// `model`, and σ_k² = a·|H(ω_k)|² + b·ω_k^(−2p). With few averages each line's coherence is
    /// a noisy estimate (2K − 2 degrees of freedom): weights taken from it line by line
    /// favour the lines whose noise came out small and make the covariance too small;
    /// two numbers fitted to every line are not. Falls back to
    /// [`reweight`](Self::reweight) where the model cannot be fitted (no coherence
    /// weighting, too few lines). Assumes the input's power varies slowly over the band.
    /// Where the force's noise was measured ([`input_noise`](Self::input_noise), K ≥ 2),
    /// each line's a_k = (K − 1)/(2K)·v_k is taken as known and only b is fitted: the
    /// force's term then needs no lines where it dominates (under mixed noise, a few at
    /// the resonances, from which a fitted a came out ten times too small in some tests).
    ///
    /// Returns whether σ_k are then each line's own standard deviation (per real and
    /// imaginary part): the noise model applied with K ≥ 2 known, the coherence's
    /// residual power corrected by K/(K − 1) for the one complex response it was taken
    /// about, so that a fit's weighted SSE/(2L − p) is about 1 when its model leaves only
    /// noise. With K not known (0) the noise model sets the weights' shape only.
    pub fn smooth_coherence_weights(&mut self, model: impl Fn(f64) -> Complex64) -> bool {
        if self.weighting == FrfWeighting::Uniform {
            self.residual_variances(model, &[]);
            return false;
        }
        if self.weighting != FrfWeighting::Coherence
            || self.relative_sigma.len() != self.h.len()
            || self.averages == 1
        {
            self.reweight(model);
            return false;
        }
        let m: Vec<f64> = self.omega.iter().map(|&w| model(w).norm_sqr()).collect();
        let q: Vec<f64> = (self.relative_sigma.iter().zip(&self.h))
            .map(|(r, h)| r * r * h.norm_sqr())
            .collect();
        // The output's white noise is flat in the measured quantity, (jω)^p·H.
        let u: Vec<f64> = (self.omega.iter())
            .map(|&w| w.powi(-2 * self.measured_power))
            .collect();
        let k = self.averages as f64;
        // A coherence at the ceiling says only that the line's noise is below what it
        // can express: such lines (the peaks of a very clean FRF) are left out of the
        // fit of the noise model, which their clamped value would raise there.
        let ceiling = (1.0 - COHERENCE_CEILING) / (k.max(1.0) * COHERENCE_CEILING) / 2.0;
        let kept: Vec<usize> = (0..m.len())
            .filter(|&i| self.relative_sigma[i].powi(2) > ceiling * (1.0 + 1e-9))
            .collect();
        let pick = |v: &[f64]| kept.iter().map(|&i| v[i]).collect::<Vec<f64>>();
        let (km, ku, kq) = (pick(&m), pick(&u), pick(&q));
        let measured = self.averages >= 2 && self.input_noise.len() == self.h.len();
        // The force's noise scatters H1 by v_k·|H|² about the true H, which the lines
        // (and the model fitted to them) show low by 1 + (K − 1)·v_k: in the model's
        // |H|² its share is a_k = (K − 1)/(2K)·v_k·(1 + (K − 1)·v_k)².
        let plain: Vec<f64> = (self.input_noise.iter())
            .map(|v| v * (k - 1.0) / (2.0 * k))
            .collect();
        let fitted = if measured {
            let a: Vec<f64> = (plain.iter().zip(&self.input_noise))
                .map(|(a, v)| a * (1.0 + (k - 1.0) * v).powi(2))
                .collect();
            response_noise(&km, &ku, &kq, &pick(&a)).map(|b| (a, b))
        } else {
            noise_model(&km, &ku, &kq).map(|[a, b]| (vec![a; m.len()], b))
        };
        let Some((a, b)) = fitted else {
            self.reweight(model);
            return false;
        };
        self.noise_model = Some(if measured {
            CoherenceNoise {
                force: equivalent_force_noise(&m, &u, &plain, b),
                response: b,
                force_standard_error: 0.0,
                force_measured: true,
            }
        } else {
            CoherenceNoise {
                force: a[0],
                response: b,
                force_standard_error: standard_error_of_a(&km, &ku, &kq, [a[0], b]),
                force_measured: false,
            }
        });
        // K/(K − 1) for the one response the coherence was taken about; with K unknown
        // the weights are relative only (the fit's s² sets their scale).
        let variance = |i: usize| a[i] * m[i] + b * u[i];
        self.force_share = (0..m.len())
            .map(|i| match variance(i) {
                total if total > 0.0 => (a[i] * m[i] / total).clamp(0.0, 1.0),
                _ => 0.0,
            })
            .collect();
        for (i, s) in self.sigma.iter_mut().enumerate() {
            *s = if self.averages >= 2 {
                (variance(i) * k / (k - 1.0)).sqrt()
            } else {
                variance(i).sqrt()
            };
        }
        self.force_noise = a;
        self.averages >= 2
    }

    /// Under uniform weights, each line's variance as the residuals of `model` show it:
    /// v_k = a·|H(ω_k)|² + b·ω_k^(−2p), the coherence's two-term noise model (a the
    /// errors in proportion to H — a force's noise, leakage, a resonance that moved —,
    /// b those flat in the quantity measured) fitted to the squared residuals
    /// |Ĥ_k − H(ω_k)|² by iteratively reweighted least squares (each a sample of its
    /// line's variance on two degrees of freedom). The weights stay equal, and so the
    /// estimates; the covariance takes v_k/σ_k² (scaled to mean 1) as each line's
    /// variance ([`variance_scale`](Self::variance_scale)) and a·|H|²/v_k as the share
    /// in proportion to H ([`force_share`](Self::force_share)). Without it, errors that
    /// grow at the peaks made the poles' intervals many times too narrow: a simulated
    /// roving-hammer set with the force's noise dominant there covered fn and ζ 29 % of
    /// the time. Each squared residual is divided by 1 − h_k, h_k the line's leverage
    /// in the fit (`leverage`, empty: none known), which the fit's own columns take
    /// from it. Nothing where no positive model fits.
    pub fn residual_variances(&mut self, model: impl Fn(f64) -> Complex64, leverage: &[f64]) {
        let fitted: Vec<Complex64> = self.omega.iter().map(|&w| model(w)).collect();
        let m: Vec<f64> = fitted.iter().map(|h| h.norm_sqr()).collect();
        // A line the fit follows closely (leverage h_k, its two rows' mean) shows only
        // 1 − h_k of its variance in the residual.
        let kept = |k: usize| (1.0 - leverage.get(k).copied().unwrap_or(0.0)).max(0.05);
        let q: Vec<f64> = (self.h.iter().zip(&fitted).enumerate())
            .map(|(k, (h, f))| (h - f).norm_sqr() / 2.0 / kept(k))
            .collect();
        let u: Vec<f64> = (self.omega.iter())
            .map(|&w| w.powi(-2 * self.measured_power))
            .collect();
        let Some([a, b]) = noise_model(&m, &u, &q) else {
            return;
        };
        let v: Vec<f64> = (0..m.len()).map(|i| a * m[i] + b * u[i]).collect();
        if v.iter().any(|v| v.is_nan() || *v <= 0.0) {
            return;
        }
        let relative: Vec<f64> = (v.iter().zip(&self.sigma))
            .map(|(v, s)| v / (s * s))
            .collect();
        let mean = relative.iter().sum::<f64>() / relative.len() as f64;
        self.variance_scale = relative.iter().map(|r| r / mean).collect();
        self.force_share = (m.iter().zip(&v)).map(|(m, v)| a * m / v).collect();
    }

    /// The spacing of the lines around `frequency_hz`, Hz (0 with fewer than two).
    pub fn spacing_hz(&self, frequency_hz: f64) -> f64 {
        let n = self.omega.len();
        if n < 2 {
            return 0.0;
        }
        let k = (self.omega.partition_point(|&w| w < TAU * frequency_hz)).clamp(1, n - 1);
        (self.omega[k] - self.omega[k - 1]) / TAU
    }

    /// The weighted residuals (model − H)/σ of every line: real parts in the first half
    /// of `out`, imaginary parts in the second (the layout of both fits' Jacobians).
    pub fn weighted_residuals(&self, model: impl Fn(f64) -> Complex64, out: &mut [f64]) {
        let n = self.omega.len();
        debug_assert_eq!(out.len(), 2 * n);
        for (k, ((&w, h), &s)) in self.omega.iter().zip(&self.h).zip(&self.sigma).enumerate() {
            let e = (model(w) - h) / s;
            out[k] = e.re;
            out[n + k] = e.im;
        }
    }

    /// These lines with the response replaced by the summed magnitudes of `all` (lines on
    /// the same axis): where a set's modes show as peaks.
    pub fn summed_magnitudes(&self, all: &[Lines]) -> Lines {
        let mut out = self.clone();
        for (k, h) in out.h.iter_mut().enumerate() {
            *h = Complex64::new(all.iter().map(|l| l.h[k].norm()).sum(), 0.0);
        }
        out
    }

    /// Whether the data show a peak at the mode (fn, ζ): within fn ± max(1.5 line
    /// spacings, 3ζ·fn) the measured magnitude |(jω)^p·H| has a local maximum that
    /// stands at least √2 above the lowest line on each side of it in that window (and
    /// at least two lines on each side) (as a
    /// mode's peak stands above its half-power points). A pole of the model alone (noise,
    /// or the skirt of another mode) has none.
    pub fn has_peak(&self, natural_frequency_hz: f64, damping_ratio: f64) -> bool {
        let n = self.omega.len();
        if n < 3 {
            return true;
        }
        let magnitude = |k: usize| self.h[k].norm() * self.omega[k].powi(self.measured_power);
        let centre = TAU * natural_frequency_hz;
        let k0 = self.omega.partition_point(|&w| w < centre).clamp(1, n - 1);
        let spacing = self.omega[k0] - self.omega[k0 - 1];
        let half_width = (1.5 * spacing).max(3.0 * damping_ratio * centre);
        let first = self.omega.partition_point(|&w| w < centre - half_width);
        let last = self.omega.partition_point(|&w| w <= centre + half_width);
        let Some(peak) = (first.max(1)..last.min(n - 1))
            .filter(|&k| magnitude(k) >= magnitude(k - 1) && magnitude(k) >= magnitude(k + 1))
            .max_by(|&a, &b| magnitude(a).total_cmp(&magnitude(b)))
        else {
            return false;
        };
        let lowest = |range: std::ops::RangeInclusive<usize>| {
            range.map(magnitude).fold(f64::INFINITY, f64::min)
        };
        // At least two lines on each side: a peak between two lines lifts both.
        let left = lowest(first.min(peak.saturating_sub(2))..=peak - 1);
        let right = lowest(peak + 1..=(last.max(peak + 3) - 1).min(n - 1));
        if magnitude(peak) < std::f64::consts::SQRT_2 * left.max(right) {
            return false;
        }
        // A resolved mode (half-power band wider than 1.5 lines) is as wide as its ζ says:
        // within fn ± ζ·fn/2 a single mode stays above 1/√1.25 of its peak, so no line
        // there may fall below half of it (a heavily damped pole of the model near a sharp
        // peak of the data fails this).
        let half_band = damping_ratio * centre;
        if half_band > 1.5 * spacing {
            let inner = (self
                .omega
                .partition_point(|&w| w < centre - 0.5 * half_band)
                ..self
                    .omega
                    .partition_point(|&w| w <= centre + 0.5 * half_band))
                .map(magnitude)
                .fold(f64::INFINITY, f64::min);
            return inner >= 0.5 * magnitude(peak);
        }
        true
    }

    /// The normalised error ‖model − H‖/‖H‖ over the lines, in the measured quantity
    /// ((jω)^p × receptance).
    pub fn relative_error(&self, model: impl Fn(f64) -> Complex64) -> f64 {
        let (mut sse, mut energy) = (0.0, 0.0);
        for (&w, h) in self.omega.iter().zip(&self.h) {
            let scale = w.powi(2 * self.measured_power);
            sse += (model(w) - h).norm_sqr() * scale;
            energy += h.norm_sqr() * scale;
        }
        (sse / energy).sqrt()
    }
}

impl Lines {
    /// Lines at angular frequencies `omega` (rad/s, increasing) with uniform weights, as
    /// receptance: for a fit's own tests on exact data.
    pub fn uniform(omega: Vec<f64>, h: Vec<Complex64>) -> Self {
        let n = omega.len();
        Self {
            band_hz: [omega[0] / TAU, omega[n - 1] / TAU],
            weighting: FrfWeighting::Uniform,
            omega,
            h,
            sigma: vec![1.0; n],
            diagram_sigma: vec![1.0; n],
            relative_sigma: Vec::new(),
            variance_scale: Vec::new(),
            exponential_decay: None,
            correlated_lines: 1.0,
            correlation: LineCorrelation::default(),
            index: (0..n).collect(),
            force_share: Vec::new(),
            measured_power: 0,
            averages: 1,
            estimator: None,
            noise_model: None,
            input_noise: Vec::new(),
            force_noise: Vec::new(),
        }
    }
}

/// The receptance as data of quantity `kind` show it: r such that r·(jω)^p is the
/// conjugate of h·(jω)^p when they are `conjugated` (r = (−1)^p·h̄), else h.
///
/// ```
/// use msd_modal_core::lines::as_measured;
/// use msd_signal::{Complex64, FrfKind};
/// let h = Complex64::new(1.0, -2.0);
/// assert_eq!(as_measured(h, false, FrfKind::Mobility), h);
/// assert_eq!(as_measured(h, true, FrfKind::Accelerance), h.conj());
/// // Mobility: jω·r = conj(jω·h).
/// let jw = Complex64::new(0.0, 3.0);
/// assert!((jw * as_measured(h, true, FrfKind::Mobility) - (jw * h).conj()).norm() < 1e-12);
/// ```
pub fn as_measured(h: Complex64, conjugated: bool, kind: FrfKind) -> Complex64 {
    match (conjugated, kind.power() % 2) {
        (false, _) => h,
        (true, 0) => h.conj(),
        (true, _) => -h.conj(),
    }
}

/// What a fit on conjugated data says of them.
pub const CONJUGATED: &str = "warning: the data's phase rises through the resonances (the e^(−jωt) convention, or H = S_xy/S_xx as MATLAB's cpsd(x, y) gives it): no mode fits them as they are, so the fit was made on their complex conjugate; fn, ζ and |modal constants| hold, phases are the conjugate's";

/// The first line of a modal fit's display: what was fitted, to how many lines in which
/// band, the weighting, the iterations and the relative error.
pub fn fit_line(
    f: &mut std::fmt::Formatter<'_>,
    what: &str,
    lines: usize,
    band_hz: [f64; 2],
    weighting: FrfWeighting,
    iterations: usize,
    relative_error: f64,
) -> std::fmt::Result {
    write!(
        f,
        "{what} fitted to {lines} lines, {:.4}–{:.4} Hz ({weighting} weighting), {iterations} iterations; relative error {:.2} %",
        band_hz[0],
        band_hz[1],
        100.0 * relative_error
    )
}

/// a, b ≥ 0 of q ≈ a·m + b·u, in relative terms (each q_k weighted by
/// 1/(a·m_k + b·u_k)², four passes from an unweighted start); `None` when nothing
/// positive fits.
fn noise_model(m: &[f64], u: &[f64], q: &[f64]) -> Option<[f64; 2]> {
    let mut weight = vec![1.0; m.len()];
    let mut ab = None;
    let rows = || m.iter().zip(u).zip(q).map(|((&m, &u), &q)| (m, u, q));
    for _ in 0..4 {
        let [mut smm, mut smu, mut suu, mut smq, mut suq] = [0.0; 5];
        for ((m, u, q), &w) in rows().zip(&weight) {
            smm += w * m * m;
            smu += w * m * u;
            suu += w * u * u;
            smq += w * m * q;
            suq += w * u * q;
        }
        let det = smm * suu - smu * smu;
        let (a, b) = ((smq * suu - smu * suq) / det, (smm * suq - smu * smq) / det);
        // On the boundary when the free solution is not ≥ 0: the better of b alone and
        // a alone (weighted squared error).
        let [a, b] = if det > 0.0 && a >= 0.0 && b >= 0.0 {
            [a, b]
        } else {
            let sse = |[a, b]: [f64; 2]| -> f64 {
                (rows().zip(&weight))
                    .map(|((m, u, q), &w)| w * (q - a * m - b * u).powi(2))
                    .sum()
            };
            let (only_b, only_a) = ([0.0, suq / suu], [smq / smm, 0.0]);
            if sse(only_b) <= sse(only_a) {
                only_b
            } else {
                only_a
            }
        };
        if !(a.is_finite() && b.is_finite() && a + b > 0.0) {
            return ab;
        }
        ab = Some([a, b]);
        for (w, (m, u, _)) in weight.iter_mut().zip(rows()) {
            let p = a * m + b * u;
            *w = if p > 0.0 { 1.0 / (p * p) } else { 0.0 };
        }
    }
    ab
}

/// b ≥ 0 of q_k ≈ a_k·m_k + b·u_k with every a_k known, each line weighted by the
/// inverse square of its predicted q (iterated, as [`noise_model`]); `None` when no line
/// has a positive prediction.
fn response_noise(m: &[f64], u: &[f64], q: &[f64], a: &[f64]) -> Option<f64> {
    let mut b: f64 = 0.0;
    let mut found = None;
    for round in 0..4 {
        let (mut suu, mut sur) = (0.0, 0.0);
        for i in 0..m.len() {
            let p = a[i] * m[i] + b * u[i];
            let w = match round {
                0 => 1.0,
                _ if p > 0.0 => 1.0 / (p * p),
                _ => 0.0,
            };
            suu += w * u[i] * u[i];
            sur += w * u[i] * (q[i] - a[i] * m[i]);
        }
        b = (sur / suu).max(0.0);
        if !b.is_finite() || (0..m.len()).all(|i| a[i] * m[i] + b * u[i] <= 0.0) {
            return found;
        }
        found = Some(b);
    }
    found
}

/// The one a that fits the known a_k·m_k best in the fit's weights (for the report).
fn equivalent_force_noise(m: &[f64], u: &[f64], a: &[f64], b: f64) -> f64 {
    let (mut smm, mut sma) = (0.0, 0.0);
    for i in 0..m.len() {
        let p = a[i] * m[i] + b * u[i];
        if p > 0.0 {
            smm += m[i] * m[i] / (p * p);
            sma += m[i] * a[i] * m[i] / (p * p);
        }
    }
    if smm > 0.0 { sma / smm } else { 0.0 }
}

/// The standard error of a in q ≈ a·m + b·u fitted with weights 1/(a·m + b·u)²:
/// s²·[(XᵀWX)⁻¹]₀₀ with s² the weighted residual variance on L − 2 degrees of freedom.
fn standard_error_of_a(m: &[f64], u: &[f64], q: &[f64], [a, b]: [f64; 2]) -> f64 {
    let [mut smm, mut smu, mut suu, mut sse] = [0.0; 4];
    for ((&m, &u), &q) in m.iter().zip(u).zip(q) {
        let p = a * m + b * u;
        if p <= 0.0 {
            continue;
        }
        let w = 1.0 / (p * p);
        smm += w * m * m;
        smu += w * m * u;
        suu += w * u * u;
        sse += w * (q - p).powi(2);
    }
    let det = smm * suu - smu * smu;
    let dof = m.len().saturating_sub(2).max(1) as f64;
    let se = (sse / dof * suu / det).sqrt();
    if se.is_finite() { se } else { f64::INFINITY }
}

#[cfg(test)]
mod tests {
    use super::noise_model;

    /// Exact q = a·m + b·u gives a and b back; a q that needs a negative a gives the
    /// best b alone.
    #[test]
    fn the_noise_model_is_recovered_and_kept_non_negative() {
        let m: Vec<f64> = (1..=40)
            .map(|k| 1.0 / (1.0 + (k as f64 - 20.0).powi(2)))
            .collect();
        let u: Vec<f64> = (1..=40).map(|k| (k as f64).powi(-4)).collect();
        let q: Vec<f64> = m.iter().zip(&u).map(|(m, u)| 3e-4 * m + 2e-2 * u).collect();
        let [a, b] = noise_model(&m, &u, &q).expect("fits");
        assert!(
            (a / 3e-4 - 1.0).abs() < 1e-9 && (b / 2e-2 - 1.0).abs() < 1e-9,
            "{a} {b}"
        );
        let q: Vec<f64> = m.iter().zip(&u).map(|(m, u)| 2e-2 * u - 1e-6 * m).collect();
        let [a, b] = noise_model(&m, &u, &q).expect("fits");
        assert_eq!(a, 0.0);
        assert!(b > 0.0);
    }
}
