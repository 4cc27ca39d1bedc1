//! One mode fitted to a frequency response: m, c and k of H(ω) = 1/(k − mω² + jcω) by
//! weighted nonlinear least squares.

use msd_opt::{
    LeastSquaresProblem, LevenbergMarquardtOptions, LevenbergMarquardtResult, LmExit,
    levenberg_marquardt,
};
use msd_signal::{Complex64, FrequencyResponseEstimate, FrfKind};
use nalgebra::{DMatrix, Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{IdentError, Result};
use crate::params::Parameters;
use crate::uncertainty::{ResidualNoise, Uncertainty, from_normal_matrix};
use msd_modal_core::lines::{CONJUGATED, FrfWeighting, Lines, as_measured, check_band, prepare};
use msd_modal_core::{
    DominantPeak, HalfPower, InputNoise, NoiseCheck, WindowCorrection, dominant_peak, half_power,
};
use msd_opt::statistics::{Interval, t_975};

/// Options of [`fit_one_mode`] (in TOML: a table with any of these fields).
///
/// ```
/// use msd_ident::OneModeOptions;
/// use msd_modal_core::FrfWeighting;
/// let options: OneModeOptions = toml::from_str("band_hz = [0.5, 2.0]\nweighting = \"variance\"")?;
/// assert_eq!(options.band_hz, Some([0.5, 2.0]));
/// assert_eq!(options.weighting, FrfWeighting::Variance);
/// assert!(toml::from_str::<OneModeOptions>("band_hz = [2.0]").is_err());
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OneModeOptions {
    /// The band to fit in Hz. By default `None`: the band around the dominant resonance
    /// ([`dominant_peak`](msd_modal_core::dominant_peak): the highest peak, coherence
    /// weighted, ± 10 half-power bandwidths, cut at a valley before another peak), or
    /// every line above 0 Hz when no peak stands 10 dB above the median line.
    #[serde(default, deserialize_with = "msd_signal::pair::optional")]
    pub band_hz: Option<[f64; 2]>,
    /// How the lines are weighted. By default [`FrfWeighting::Coherence`].
    pub weighting: FrfWeighting,
}

impl OneModeOptions {
    /// Checks the band.
    pub fn validate(&self) -> Result<()> {
        Ok(check_band(self.band_hz)?)
    }
}

/// The result of [`fit_one_mode`]: m, c, k with fn and ζ in an [`Uncertainty`] (95 %
/// intervals), the gain, the classroom estimates beside them.
///
/// Displays the fit's summary line, the intervals, the gain, the window correction and
/// the half-power estimate; serializes with every field.
///
/// ```
/// use msd_ident::{fit_one_mode, OneModeOptions, Parameters, frequency::model_response};
/// use msd_modal_core::synthetic_frequency_response;
/// let f: Vec<f64> = (0..40).map(|i| 0.25 + 0.0577 * i as f64).collect();
/// let sweep = synthetic_frequency_response(&f, 0.01, 1, |f| {
///     model_response(&Parameters::PAPER, std::f64::consts::TAU * f)
/// })?;
/// let fit = fit_one_mode(&sweep, &OneModeOptions::default())?;
/// assert!(fit.uncertainty.stiffness.contains(120.0));
/// assert!(fit.to_string().starts_with("one mode fitted to 40 lines"));
/// let json = serde_json::to_value(&fit).expect("serializable");
/// assert_eq!(json["uncertainty"]["stiffness"]["value"], fit.parameters.stiffness);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OneModeFit {
    /// m, c, k (with an exponential window: corrected for it).
    pub parameters: Parameters,
    /// Their 95 % intervals, and fn and ζ by the delta method.
    pub uncertainty: Uncertainty,
    /// The gain A = 1/m of H = A/(ωn² − ω² + 2jζωnω): with fn and ζ, all the data
    /// determine when the force's scale is unknown (m, c, k scale with it). Negative for
    /// a mode with a negative modal constant (see `negative_modal_constant`).
    pub gain: Interval,
    /// Whether the mode's modal constant is negative (a transfer FRF whose two points
    /// move in opposition in this mode, or a sensor's sign): `parameters` are then the
    /// m, c, k of −H, which are physical only when the force's scale and sign are not
    /// known; fn, ζ and the (negative) gain hold either way.
    pub negative_modal_constant: bool,
    /// What an exponential window added and how it was taken off, if there was one.
    pub window_correction: Option<WindowCorrection>,
    /// Peak picking and half-power bandwidth in the same band, when they can be read.
    pub half_power: Option<HalfPower>,
    /// The first and last line fitted, Hz.
    pub band_hz: [f64; 2],
    /// The dominant resonance the band was chosen around, when no band was given.
    pub dominant_peak: Option<DominantPeak>,
    /// The quantity the data measure (and `relative_error` is in).
    pub kind: FrfKind,
    /// Whether the data's phase runs the other way (rising through the resonance: the
    /// e^(−jωt) convention, or H = S_xy/S_xx with MATLAB's `cpsd`): the fit was made on
    /// their complex conjugate, and [`response`](Self::response) gives the model as the
    /// data show it.
    pub conjugated: bool,
    /// The coherence within the mode's half-power band, when it is low enough to say so.
    pub low_coherence: Option<LowCoherence>,
    /// Lines fitted (each gives two residuals, real and imaginary).
    pub lines: usize,
    /// The weighting used (`coherence` where the coherence says nothing is `variance`
    /// or `uniform`).
    pub weighting: FrfWeighting,
    /// ‖H_model − H‖/‖H‖ over the lines (unweighted).
    pub relative_error: f64,
    /// The residuals against the frequency response's own noise, where the coherence
    /// gives it (records averaged over K ≥ 2 segments).
    pub noise_check: Option<NoiseCheck>,
    /// The force's noise the coherence shows on an H1 estimate, and the correction of
    /// the lines to the errors-in-variables estimate H_s (see [`InputNoise`]).
    pub input_noise: Option<InputNoise>,
    /// Levenberg–Marquardt iterations.
    pub iterations: usize,
    /// Residual evaluations.
    pub evaluations: usize,
    /// Why Levenberg–Marquardt stopped.
    pub exit: LmExit,
}

impl OneModeFit {
    /// The receptance of the model as fitted to the data, at `frequency_hz` (with an
    /// exponential window: the windowed response H(s + 1/τ), which the data show).
    ///
    /// ```
    /// # use msd_ident::{fit_one_mode, OneModeOptions, Parameters, frequency::model_response};
    /// # use msd_signal::FrequencyResponseEstimate;
    /// let f: Vec<f64> = (1..=40).map(|i| 0.06 * i as f64).collect();
    /// let h = f.iter().map(|f| model_response(&Parameters::PAPER, std::f64::consts::TAU * f)).collect();
    /// let fit = fit_one_mode(&FrequencyResponseEstimate::new(f, h)?, &OneModeOptions::default())?;
    /// let w = std::f64::consts::TAU * 1.1;
    /// assert!((fit.response(1.1) - model_response(&Parameters::PAPER, w)).norm() < 1e-9);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn response(&self, frequency_hz: f64) -> Complex64 {
        let a = self.window_correction.map_or(0.0, |c| 1.0 / c.decay_time);
        let sign = if self.negative_modal_constant {
            -1.0
        } else {
            1.0
        };
        let h = receptance(
            &windowed(self.parameters.to_array(), a),
            std::f64::consts::TAU * frequency_hz,
        ) * sign;
        as_measured(h, self.conjugated, self.kind)
    }
}

impl OneModeFit {
    /// The fitted mode's half-power band fn(1 ± ζ), Hz.
    pub fn half_power_band_hz(&self) -> [f64; 2] {
        let (f, z) = (
            self.uncertainty.natural_frequency_hz.value,
            self.uncertainty.damping_ratio.value,
        );
        [f * (1.0 - z), f * (1.0 + z)]
    }
}

impl std::fmt::Display for OneModeFit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (lines, band, iterations) = (self.lines, self.band_hz, self.iterations);
        msd_modal_core::lines::fit_line(
            f,
            "one mode",
            lines,
            band,
            self.weighting,
            iterations,
            self.relative_error,
        )?;
        writeln!(f, " in {}", self.kind)?;
        if let Some(peak) = &self.dominant_peak {
            writeln!(f, "fitted in {peak}")?;
        }
        if self.conjugated {
            writeln!(f, "{CONJUGATED}")?;
        }
        writeln!(f, "{}", self.uncertainty)?;
        if let Some(low) = &self.low_coherence {
            writeln!(f, "{low}")?;
        }
        if let Some(check) = &self.noise_check {
            writeln!(f, "{check}")?;
        }
        if let Some(noise) = &self.input_noise {
            writeln!(f, "{noise}")?;
        }
        write!(f, "gain 1/m = {}", self.gain)?;
        if let Some(c) = &self.window_correction {
            write!(f, "\n{c}")?;
        }
        if let Some(h) = &self.half_power {
            write!(f, "\nclassroom estimate: {h}")?;
        }
        Ok(())
    }
}

/// Fits one mode, m·x'' + c·x' + k·x = F, to `frf` (converted to receptance).
///
/// ## The algorithm
/// Without `options.band_hz` the band is that of the dominant resonance
/// ([`dominant_peak`](msd_modal_core::dominant_peak)), or every line when no peak stands out
/// 10 dB. Levy's linear least squares (1/H ≈ k − mω² + jcω, each line weighted by
/// |H|²/σ so its error approximates the error in H) gives the start (or, when it finds
/// no resonance on noisy lines, the highest line and its half-power width); Levenberg–Marquardt
/// (msd-opt, analytic Jacobian) minimises Σ |H(ω_k; m, c, k) − Ĥ_k|²/σ_k², real and
/// imaginary parts as separate residuals, σ_k from `options.weighting`. Weights relative
/// to |H| (coherence, relative) are then taken from the fitted model's |H| rather than
/// the measured one, and the fit is run once more: the measured |Ĥ_k| carries the noise,
/// and weighting by it favours the lines that came out low. Coherence weights are then
/// those of a noise model fitted to every line's coherence (white noise on the force and
/// on the response: Var Ĥ_k ∝ a·|H_k|² + b·ω_k^(−2p), see
/// [`Lines::smooth_coherence_weights`](msd_modal_core::lines::Lines::smooth_coherence_weights)):
/// with four averages one line's coherence has 6 degrees of freedom, and weights taken
/// from it line by line made the intervals 20 % too narrow. The covariance
/// is Gauss–Newton's s²(JᵀJ)⁻¹ with s² = SSE/(2K − 3), the intervals Student's t with
/// 2K − 3 degrees of freedom, fn and ζ by the delta method (as the time-domain
/// [`Uncertainty`]). The covariance is multiplied by the estimate's
/// [`noise_bandwidth`](FrequencyResponseEstimate::noise_bandwidth) (1 for a table, 1.5
/// for Hann, about T/(2τ) for an exponential window): a window correlates the errors of
/// that many neighbouring lines. With an exponential window (τ, a = 1/τ) the fit finds the windowed
/// m, c′ = c + 2am, k′ = k + ac + a²m, which are mapped back (a linear map, so the
/// covariance maps exactly).
///
/// When the data fit no mode as they are but their complex conjugate does (a phase that
/// rises through the resonance: the other sign convention), the conjugate is fitted and
/// [`OneModeFit::conjugated`] says so. The coherence over the mode's half-power band is
/// reported when it is low ([`LowCoherence`]).
///
/// Errors: too few lines (at least 4), a malformed band, `Variance` weighting without
/// variances, no resonance (Levy's start or the fit gives m ≤ 0 or k ≤ 0, or the window
/// correction c < 0), a fit that does not converge.
///
/// ```
/// use msd_ident::{fit_one_mode, OneModeOptions, Parameters, frequency::model_response};
/// use msd_signal::FrequencyResponseEstimate;
/// // A stepped sine on the paper's plant at 40 frequencies, exact.
/// let f: Vec<f64> = (1..=40).map(|i| 0.06 * i as f64).collect();
/// let h = f.iter().map(|f| model_response(&Parameters::PAPER, std::f64::consts::TAU * f)).collect();
/// let fit = fit_one_mode(&FrequencyResponseEstimate::new(f, h)?, &OneModeOptions::default())?;
/// assert!((fit.parameters.stiffness - 120.0).abs() < 1e-8);
/// assert!((fit.uncertainty.damping_ratio.value - 0.0519615).abs() < 1e-7);
/// println!("{fit}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn fit_one_mode(
    frf: &FrequencyResponseEstimate,
    options: &OneModeOptions,
) -> Result<OneModeFit> {
    options.validate()?;
    // No band: around the dominant resonance, or every line when none stands out.
    let dominant_peak = match options.band_hz {
        Some(_) => None,
        None => dominant_peak(frf).ok(),
    };
    let band = options.band_hz.or(dominant_peak.map(|d| d.band_hz));
    let mut fit = match fit_in_band(frf, band, options.weighting) {
        Ok(fit) => fit,
        // Data whose phase runs the other way fit no mode as they are; their conjugate
        // does when that is all that is wrong.
        Err(e) => match fit_in_band(&frf.conjugate(), band, options.weighting) {
            Ok(fit) => OneModeFit {
                conjugated: true,
                ..fit
            },
            Err(_) => return Err(e),
        },
    };
    fit.dominant_peak = dominant_peak;
    let [f1, f2] = fit.half_power_band_hz();
    fit.low_coherence = LowCoherence::within(frf, [f1, f2]);
    Ok(fit)
}

/// [`fit_one_mode`] in the band (or on every line above 0 Hz), the data as they are.
fn fit_in_band(
    frf: &FrequencyResponseEstimate,
    band_hz: Option<[f64; 2]>,
    weighting: FrfWeighting,
) -> Result<OneModeFit> {
    let mut lines = prepare(frf, band_hz, weighting, 4)?;
    let start = levy_start(&lines).or_else(|e| peak_start(&lines).ok_or(e))?;
    let first = least_squares(&lines, start)?;
    // Once more with |H| from the model, coherence weights from the noise model fitted
    // to every line's coherence (see Lines::smooth_coherence_weights).
    let own_noise = lines.smooth_coherence_weights(|w| receptance(&first.0, w));
    // Noise on the force biases H1 low: the lines become H_s, between H1 and H2.
    let input_noise = lines.correct_input_noise();
    let (fitted, fit) = least_squares(&lines, first.0)?;
    let noise_check = (own_noise.then(|| lines.noise_check(fit.cost, &fit.jacobian))).flatten();
    let a = lines.exponential_decay.map_or(0.0, |tau| 1.0 / tau);
    // A negative modal constant: m, c, k all negative, the mode of −H. J is the same at
    // ±θ (H² is), so the covariance of |θ| is that of θ.
    let negative_modal_constant = fitted.iter().all(|&x| x < 0.0);
    let sign = if negative_modal_constant { -1.0 } else { 1.0 };
    let theta = unwindowed(fitted.map(|x| sign * x), a);
    let parameters = Parameters::from_array(theta);
    if parameters.validate().is_err() {
        return Err(IdentError::NotIdentifiable {
            reason: format!(
                "the fit gives m = {:.4e}, c = {:.4e}, k = {:.4e}{}: no single mode in the band",
                theta[0],
                theta[1],
                theta[2],
                if a > 0.0 {
                    " after the window correction"
                } else {
                    ""
                }
            ),
        });
    }
    // ∂r/∂θ = ∂r/∂θ′·∂θ′/∂θ, with θ′ = windowed(θ). Lines whose errors are correlated
    // (the windows') hold less information than independent ones: the sandwich
    // covariance, as the normal matrix it is the inverse of.
    let jacobian = jacobian_at(&lines, &fitted) * window_map(a);
    let (normal, taken) = lines.effective_normal(&jacobian);
    let (rows, p) = jacobian.shape();
    // The residuals lose tr((JᵀJ)⁻¹JᵀCJ) degrees of freedom to the fit (p when the lines
    // are independent).
    let dof = ResidualNoise::independent(fit.cost, rows, p)?.dof + p as f64 - taken;
    let noise = ResidualNoise {
        // At least the coherence's own variance, where it gives one.
        sse: lines.residual_variance(fit.cost, dof) * dof,
        dof,
    };
    let uncertainty = from_normal_matrix(
        &normal,
        noise,
        Parameters::NAMES.to_vec(),
        theta.to_vec(),
        &parameters,
        [Some(0), Some(1), Some(2)],
    )?;
    let m = &uncertainty.mass;
    let gain = Interval::new(
        sign / m.value,
        m.standard_error / (m.value * m.value),
        t_975(uncertainty.degrees_of_freedom),
    );
    if gain.ci95[0] <= 0.0 && gain.ci95[1] >= 0.0 {
        return Err(IdentError::NotIdentifiable {
            reason: format!(
                "the fitted mode is not significant: its modal constant 1/m = {:.4e} has the 95 % interval [{:.4e}, {:.4e}], which holds 0 (no mode) — the data's noise could make this peak; measure more lines or averages near fn = {:.4} Hz",
                gain.value,
                gain.ci95[0],
                gain.ci95[1],
                parameters.natural_frequency_hz()
            ),
        });
    }
    let window_correction = lines.exponential_decay.map(|tau| {
        let windowed = Parameters::from_array(fitted.map(|x| sign * x));
        WindowCorrection {
            decay_time: tau,
            natural_frequency_hz_windowed: windowed.natural_frequency_hz(),
            damping_ratio_windowed: windowed.damping_ratio(),
            damping_ratio_added: windowed.damping_ratio() - parameters.damping_ratio(),
        }
    });
    let relative_error = lines.relative_error(|w| receptance(&fitted, w));
    if relative_error.is_nan() || relative_error >= EXPLAINS_NOTHING {
        return Err(IdentError::NotIdentifiable {
            reason: format!(
                "the fitted mode explains nothing of the data: relative error {:.1} % on the measured quantity (fn = {:.4} Hz, ζ = {:.4}); the band holds no resonance the lines resolve: check the band, that the lines carry force (coherence), and the weighting",
                100.0 * relative_error,
                parameters.natural_frequency_hz(),
                parameters.damping_ratio()
            ),
        });
    }
    Ok(OneModeFit {
        relative_error,
        noise_check,
        input_noise,
        half_power: half_power(frf, Some(lines.band_hz)).ok(),
        parameters,
        uncertainty,
        gain,
        negative_modal_constant,
        window_correction,
        band_hz: lines.band_hz,
        dominant_peak: None,
        kind: frf.kind,
        conjugated: false,
        low_coherence: None,
        lines: lines.omega.len(),
        weighting: lines.weighting,
        iterations: fit.iterations,
        evaluations: fit.evaluations,
        exit: fit.exit,
    })
}

/// Coherence γ² below this (the median over a mode's half-power band) is reported:
/// 0.8 is the usual floor of a good measurement.
const LOW_COHERENCE: f64 = 0.8;

/// The coherence over a mode's half-power band, reported when its median is below 0.8:
/// the lines that decide fn and ζ are noisy there.
///
/// ```
/// use msd_ident::frf::LowCoherence;
/// let low = LowCoherence { band_hz: [191.2, 193.6], lowest: 0.33, median: 0.44, highest: 0.49 };
/// assert!(low.to_string().contains("γ² = 0.33–0.49"));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LowCoherence {
    /// The half-power band fn(1 ± ζ) (or the line nearest fn), Hz.
    pub band_hz: [f64; 2],
    /// The lowest γ² there.
    pub lowest: f64,
    /// The median γ² there.
    pub median: f64,
    /// The highest γ² there.
    pub highest: f64,
}

impl LowCoherence {
    /// The coherence of `frf` within `band_hz` (the line nearest its centre when none
    /// lies inside), when the coherence says something and its median is below 0.8.
    pub fn within(frf: &FrequencyResponseEstimate, band_hz: [f64; 2]) -> Option<Self> {
        if !frf.has_coherence_in([0.0, f64::INFINITY]) {
            return None;
        }
        let mut g: Vec<f64> = (frf.frequency.iter().zip(&frf.coherence))
            .filter(|(f, _)| (band_hz[0]..=band_hz[1]).contains(*f))
            .map(|(_, &g)| g)
            .collect();
        if g.is_empty() {
            let centre = 0.5 * (band_hz[0] + band_hz[1]);
            let k = (0..frf.frequency.len())
                .min_by(|&a, &b| {
                    (frf.frequency[a] - centre)
                        .abs()
                        .total_cmp(&(frf.frequency[b] - centre).abs())
                })
                .unwrap_or(0);
            g.push(frf.coherence[k]);
        }
        g.sort_by(f64::total_cmp);
        let median = g[g.len() / 2];
        (median < LOW_COHERENCE).then(|| LowCoherence {
            band_hz,
            lowest: g[0],
            median,
            highest: g[g.len() - 1],
        })
    }
}

impl std::fmt::Display for LowCoherence {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "warning: the coherence is only γ² = {:.2}–{:.2} (median {:.2}) within the mode's half-power band {:.4}–{:.4} Hz: the lines that decide fn and ζ are noisy there, and the intervals are as wide as they make them. Where the noise is on the force (a shaker's force drops at resonance), H1 underestimates the peak and overestimates ζ: estimate H2 or Hv from the records, or average more",
            self.lowest, self.highest, self.median, self.band_hz[0], self.band_hz[1]
        )
    }
}

/// A fit whose relative error on the measured quantity reaches this (the model's
/// residual is 90 % of the data's norm: it explains under a fifth of its energy) is a
/// failure with its reason, never a result.
pub(crate) const EXPLAINS_NOTHING: f64 = 0.9;

/// Levenberg–Marquardt from `start`: the fitted θ and the solver's result.
fn least_squares(lines: &Lines, start: [f64; 3]) -> Result<([f64; 3], LevenbergMarquardtResult)> {
    let mut problem = OneMode {
        lines,
        scale: start,
    };
    let fit = levenberg_marquardt(
        &mut problem,
        &[1.0; 3],
        &LevenbergMarquardtOptions::default(),
    )?;
    if !fit.exit.is_success() {
        return Err(IdentError::EstimationFailed {
            reason: format!("the one-mode fit did not converge: {}", fit.exit),
        });
    }
    Ok((std::array::from_fn(|j| fit.x[j] * start[j]), fit))
}

/// H = 1/(k − mω² + jcω).
fn receptance(theta: &[f64; 3], w: f64) -> Complex64 {
    Complex64::new(1.0, 0.0) / Complex64::new(theta[2] - theta[0] * w * w, theta[1] * w)
}

/// The windowed parameters (m, c + 2am, k + ac + a²m): H(s + a) = 1/(m s² + c′s + k′).
fn windowed([m, c, k]: [f64; 3], a: f64) -> [f64; 3] {
    [m, c + 2.0 * a * m, k + a * c + a * a * m]
}

/// The inverse of [`windowed`]: (m, c′ − 2am, k′ − ac′ + a²m).
fn unwindowed([m, c, k]: [f64; 3], a: f64) -> [f64; 3] {
    [m, c - 2.0 * a * m, k - a * c + a * a * m]
}

/// ∂θ′/∂θ of [`windowed`].
fn window_map(a: f64) -> DMatrix<f64> {
    DMatrix::from_row_slice(3, 3, &[1.0, 0.0, 0.0, 2.0 * a, 1.0, 0.0, a * a, a, 1.0])
}

/// Levy's linear fit of 1/H ≈ k − mω² + jcω, weighted by |H|⁴/σ² (so that the error
/// approximates the weighted error in H); c at least 1 % of critical damping.
fn levy_start(lines: &Lines) -> Result<[f64; 3]> {
    let mut ata = Matrix3::<f64>::zeros();
    let mut atb = Vector3::<f64>::zeros();
    for ((&w, h), &s) in lines.omega.iter().zip(&lines.h).zip(&lines.sigma) {
        let weight = h.norm_sqr() * h.norm_sqr() / (s * s);
        let inverse = h.inv();
        let real = Vector3::new(-w * w, 0.0, 1.0);
        let imaginary = Vector3::new(0.0, w, 0.0);
        ata += weight * (real * real.transpose() + imaginary * imaginary.transpose());
        atb += weight * (real * inverse.re + imaginary * inverse.im);
    }
    let theta = ata
        .lu()
        .solve(&atb)
        .unwrap_or_else(|| Vector3::repeat(f64::NAN));
    let (m, c, k) = (theta[0], theta[1], theta[2]);
    // m and k of one sign: a resonance (both negative: a negative modal constant).
    if !(m * k > 0.0 && m.is_finite() && k.is_finite()) {
        return Err(IdentError::NotIdentifiable {
            reason: format!(
                "a linear fit of 1/H gives m = {m:.4e}, k = {k:.4e}: no resonance in the band to fit one mode to"
            ),
        });
    }
    let sign = m.signum();
    let floor = 0.02 * (k * m).sqrt();
    let c = if c.is_finite() {
        (sign * c).max(floor)
    } else {
        floor
    };
    Ok([m, sign * c, k])
}

/// A start read off the highest line (when Levy's fails on noisy lines): ωn there, ζ
/// from where |H| falls to 1/√2 of it on each side (at least a line; `None` when it
/// does not on both sides: no peak), c = 1/(|H|·ωn),
/// m = c/(2ζωn), k = mωn²; all negative when the peak's imaginary part is positive (a
/// negative modal constant).
fn peak_start(lines: &Lines) -> Option<[f64; 3]> {
    let n = lines.omega.len();
    let magnitude = |k: usize| lines.h[k].norm();
    let top = (0..n).max_by(|&a, &b| magnitude(a).total_cmp(&magnitude(b)))?;
    let half = magnitude(top) / std::f64::consts::SQRT_2;
    // A peak: |H| falls below 1/√2 of it on both sides.
    let low = (0..top).rev().find(|&k| magnitude(k) < half)?;
    let high = (top + 1..n).find(|&k| magnitude(k) < half)?;
    let wn = lines.omega[top];
    let spacing = (lines.omega[n - 1] - lines.omega[0]) / (n - 1) as f64;
    let zeta = ((lines.omega[high] - lines.omega[low]).max(spacing) / (2.0 * wn)).min(0.5);
    let c = 1.0 / (magnitude(top) * wn);
    let m = c / (2.0 * zeta * wn);
    let sign = if lines.h[top].im > 0.0 { -1.0 } else { 1.0 };
    let start = [m, c, m * wn * wn].map(|x| sign * x);
    start
        .iter()
        .all(|x| x.is_finite() && *x != 0.0)
        .then_some(start)
}

/// The Jacobian ∂r/∂θ (2K × 3: real parts, then imaginary parts) of the weighted
/// residuals r = (H(θ) − Ĥ)/σ.
fn jacobian_at(lines: &Lines, theta: &[f64; 3]) -> DMatrix<f64> {
    let n = lines.omega.len();
    let mut out = DMatrix::zeros(2 * n, 3);
    fill_jacobian(lines, theta, &[1.0; 3], &mut out);
    out
}

/// Writes ∂r/∂x into `out` for θ = x·scale (element-wise).
fn fill_jacobian(lines: &Lines, theta: &[f64; 3], scale: &[f64; 3], out: &mut DMatrix<f64>) {
    let n = lines.omega.len();
    for (k, (&w, &s)) in lines.omega.iter().zip(&lines.sigma).enumerate() {
        let h = receptance(theta, w);
        let h2 = h * h;
        // ∂H/∂m = ω²H², ∂H/∂c = −jωH², ∂H/∂k = −H².
        let d = [h2 * (w * w), h2 * Complex64::new(0.0, -w), -h2];
        for j in 0..3 {
            out[(k, j)] = d[j].re * scale[j] / s;
            out[(n + k, j)] = d[j].im * scale[j] / s;
        }
    }
}

/// The fit in scaled variables x = θ/θ₀ (θ₀ Levy's start), so that every x is near 1.
struct OneMode<'a> {
    lines: &'a Lines,
    scale: [f64; 3],
}

impl OneMode<'_> {
    fn theta(&self, x: &[f64]) -> [f64; 3] {
        std::array::from_fn(|j| x[j] * self.scale[j])
    }
}

impl LeastSquaresProblem for OneMode<'_> {
    fn residual_count(&self) -> usize {
        2 * self.lines.omega.len()
    }

    fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> bool {
        let theta = self.theta(x);
        self.lines
            .weighted_residuals(|w| receptance(&theta, w), out);
        true
    }

    fn jacobian(&mut self, x: &[f64], out: &mut DMatrix<f64>) -> bool {
        let theta = self.theta(x);
        fill_jacobian(self.lines, &theta, &self.scale, out);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_window_map_inverts_and_matches_the_shifted_response() {
        let (theta, a) = ([2.5, 1.8, 120.0], 0.7);
        let back = unwindowed(windowed(theta, a), a);
        for j in 0..3 {
            assert!((back[j] - theta[j]).abs() < 1e-12 * theta[j]);
        }
        // H(jω + a) of the plant = the windowed parameters' H(jω).
        let w = 3.0;
        let s = Complex64::new(a, w);
        let direct = Complex64::new(1.0, 0.0) / (s * s * theta[0] + s * theta[1] + theta[2]);
        assert!((receptance(&windowed(theta, a), w) - direct).norm() < 1e-15);
        let map = window_map(a);
        let (h, w2) = (1e-6, windowed(theta, a));
        let up = windowed([theta[0], theta[1], theta[2] + h], a);
        for i in 0..3 {
            assert!(((up[i] - w2[i]) / h - map[(i, 2)]).abs() < 1e-6);
        }
    }
}
