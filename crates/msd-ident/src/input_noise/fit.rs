//! What the noise model found, and each channel's whiteness under it.

use super::psd::ResidualSpectrum;
use crate::residuals::{CorrelationTest, LjungBox};
use serde::{Deserialize, Serialize};

/// Which noise model sets a joint fit's intervals.
///
/// ```
/// use msd_ident::records::NoiseModel;
/// assert_eq!(NoiseModel::default(), NoiseModel::InputNoise);
/// let read: NoiseModel = serde_json::from_value(serde_json::json!("white"))?;
/// assert_eq!(read, NoiseModel::White);
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NoiseModel {
    /// The drive's noise estimated with the sensors' and seen through the plant
    /// (errors-in-variables); the intervals are the sandwich under that model. A
    /// noise-free drive gets σ̂_u ≈ 0 and the white-noise intervals to within a per
    /// cent. A free decay has no drive: white. The default.
    #[default]
    InputNoise,
    /// White sensor noise only, the drive taken as exact (the paper's assumption).
    White,
}

/// What the noise model found, and which intervals were reported.
///
/// Displays one line: the treatment, then σ_u and the test when the model was fitted.
///
/// ```
/// use msd_ident::records::NoiseModelFit;
/// let fit = NoiseModelFit { treatment: "input_noise".into(), input_noise_sigma: Some(0.02),
///     input_noise_fraction: Some(0.01), sensor_sigmas: vec![0.05],
///     likelihood_ratio: Some(210.0), p_value: Some(1e-40), interval_ratio: 3.1,
///     degrees_of_freedom: Some(180.0),
///     efficiency: [("damping".to_string(), 0.8)].into_iter().collect(),
///     estimator: "output_error".into(), cost_ratio: None,
///     output_error_efficiency: Default::default() };
/// assert!(fit.to_string().starts_with("noise model: input_noise"));
/// assert_eq!(serde_json::to_value(&fit)?["input_noise_sigma"], 0.02);
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NoiseModelFit {
    /// `white` (the drive taken as exact) or `input_noise` (the sandwich covariance of
    /// the errors-in-variables model): what the intervals come from.
    pub treatment: String,
    /// σ̂_u, the drive's white noise in its unit; `None` when not fitted (a free decay,
    /// or `noise_model = "white"`).
    pub input_noise_sigma: Option<f64>,
    /// σ̂_u over the drive's rms.
    pub input_noise_fraction: Option<f64>,
    /// σ̂ of each sensor's own white noise under the model, in the order of the fit's
    /// `noise` (empty when not fitted).
    pub sensor_sigmas: Vec<f64>,
    /// 2·(ℓ(σ̂_u) − ℓ(0)) of the Whittle likelihood.
    pub likelihood_ratio: Option<f64>,
    /// P(χ² ≥ the ratio) under σ_u = 0 (half χ²₁: σ_u ≥ 0 is on the boundary).
    pub p_value: Option<f64>,
    /// The reported fn's standard error over the white-noise one (1 when white).
    pub interval_ratio: f64,
    /// The Student-t degrees of freedom of the intervals when the drive's noise shows
    /// (p < 0.01; Satterthwaite: the standard errors are estimated from σ̂_u and σ̂_a,
    /// whose own uncertainty widens the intervals); `None` otherwise (the samples'
    /// degrees of freedom).
    pub degrees_of_freedom: Option<f64>,
    /// Each estimated quantity's efficiency against the Cramér–Rao bound of the
    /// errors-in-variables model as fitted: the variance an estimator weighting each
    /// DFT line by its noise spectrum would reach (Pintelon and Schoukens' frequency-
    /// domain maximum likelihood) over the reported one, in (0, 1]. 1 under white
    /// noise (the output-error fit is then efficient); lower where the drive's noise
    /// makes the resonance's lines worth less than the fit counts them. Empty when
    /// the model was not fitted.
    pub efficiency: std::collections::BTreeMap<String, f64>,
    /// `output_error` (the fit weighting every sample alike, as the paper's) or
    /// `weighted` (where the drive's noise shows: the frequency-domain maximum-likelihood
    /// estimate, each line weighted by its noise spectrum; see `records::weighted`).
    pub estimator: String,
    /// The weighted estimate's cost over its expectation (near 1 when the noise model
    /// describes the residuals); `None` for the output-error estimate.
    pub cost_ratio: Option<f64>,
    /// The output-error estimate's efficiency, when the weighted one replaced it.
    pub output_error_efficiency: std::collections::BTreeMap<String, f64>,
}

impl std::fmt::Display for NoiseModelFit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "noise model: {}", self.treatment)?;
        if let (Some(s), Some(fr), Some(lr), Some(p)) = (
            self.input_noise_sigma,
            self.input_noise_fraction,
            self.likelihood_ratio,
            self.p_value,
        ) {
            write!(
                f,
                " (drive noise σ_u = {s:.3e}, {:.2} % of its rms; likelihood ratio {lr:.1}, p = {p:.2e}; intervals ×{:.2} the white-noise ones",
                100.0 * fr,
                self.interval_ratio
            )?;
            if let Some(nu) = self.degrees_of_freedom.filter(|nu| nu.is_finite()) {
                write!(f, ", t with {nu:.0} degrees of freedom")?;
            }
            if let Some(low) = self.efficiency.values().copied().reduce(f64::min) {
                write!(f, "; efficiency against the Cramér–Rao bound ≥ {low:.2}")?;
            }
            write!(f, ")")?;
        }
        Ok(())
    }
}

/// One channel's residual whiteness: as fitted, and under the noise model.
///
/// ```
/// use msd_ident::{records::ResidualWhiteness, residuals::ljung_box};
/// let lb = ljung_box(&[1.0, 0.01, -0.02], 10_000);
/// let check = ResidualWhiteness { record: "run 1".into(), channel: "acc".into(),
///     ljung_box: lb, ljung_box_under_noise_model: Some(lb), input_correlation: None, spectrum: None,
///     passed: true };
/// assert_eq!(serde_json::to_value(&check)?["passed"], true);
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResidualWhiteness {
    /// The record's name.
    pub record: String,
    /// The channel's name.
    pub channel: String,
    /// Ljung–Box on the residual as it is (25 lags): fails when the drive's noise
    /// colours it, as it should.
    pub ljung_box: LjungBox,
    /// Ljung–Box on the residual whitened by the noise model (its spectrum
    /// σ²_a + σ²_u·|G_a|²); `None` under the white model.
    pub ljung_box_under_noise_model: Option<LjungBox>,
    /// The residual's cross-correlation with the measured drive at lags −25…25, with the
    /// 99 % band (Bonferroni over the lags for the verdict); `None` for a free decay. A
    /// failure means part of the drive's effect is not explained (a missing mode, a
    /// delay, a nonlinearity); the drive's own noise adds a correlation of about
    /// −σ²_u·g(τ) that is small unless that noise is large.
    pub input_correlation: Option<CorrelationTest>,
    /// The residual's spectrum against the noise model's (the white level under the
    /// white treatment); `None` where it was not computed.
    pub spectrum: Option<ResidualSpectrum>,
    /// The residual is white under the model the intervals assume (p ≥ 0.01): when
    /// false, the model leaves colour unexplained (a missing dynamic, a nonlinearity, a
    /// coloured sensor noise) and the intervals may be too narrow.
    pub passed: bool,
}

impl NoiseModelFit {
    /// The white treatment: the drive taken as exact, nothing fitted.
    pub fn white() -> Self {
        Self {
            treatment: "white".into(),
            input_noise_sigma: None,
            input_noise_fraction: None,
            sensor_sigmas: Vec::new(),
            likelihood_ratio: None,
            p_value: None,
            interval_ratio: 1.0,
            degrees_of_freedom: None,
            efficiency: Default::default(),
            estimator: "output_error".into(),
            cost_ratio: None,
            output_error_efficiency: Default::default(),
        }
    }
}

/// What the reader should know about the noise: the drive's noise when it shows, and
/// each channel whose residual is not white under the model the intervals assume.
/// `white_key` names where the white-noise intervals are; `measured_drive` whether there
/// is a drive whose noise the model could account for.
pub(crate) fn notes(
    fit: &NoiseModelFit,
    whiteness: &[ResidualWhiteness],
    white_key: &str,
    measured_drive: bool,
) -> Vec<String> {
    let mut notes = Vec::new();
    if let (Some(sigma), Some(fraction), Some(p)) =
        (fit.input_noise_sigma, fit.input_noise_fraction, fit.p_value)
        && p < super::WHITENESS_LEVEL
    {
        let caveat = if whiteness.iter().any(|c| !c.passed) {
            "; the residuals stay coloured under this model, so σ̂_u may stand for what the model misses (a nonlinearity, a missing mode) rather than the drive's noise"
        } else {
            ""
        };
        notes.push(format!(
            "the drive's own noise shows in the residuals (σ̂_u = {sigma:.3e}, {:.2} % of its rms, p = {p:.1e}): the intervals are the errors-in-variables ones, {:.2}× the white-noise ones (`{white_key}`){caveat}",
            100.0 * fraction,
            fit.interval_ratio
        ));
    }
    for check in whiteness.iter() {
        let Some(test) = check.input_correlation.as_ref().filter(|t| !t.passed) else {
            continue;
        };
        notes.push(format!(
            "record `{}`, channel `{}`: the residual correlates with the drive ({test}): part of the drive's effect is not explained (a missing mode, a delay, a nonlinearity, a wrong drive or unit)",
            check.record, check.channel
        ));
    }
    for check in whiteness.iter().filter(|c| !c.passed) {
        let test = check.ljung_box_under_noise_model.unwrap_or(check.ljung_box);
        let hint = if measured_drive && check.ljung_box_under_noise_model.is_none() {
            "; with a measured drive, `noise_model = \"input_noise\"` accounts for its noise"
        } else {
            ""
        };
        notes.push(format!(
            "record `{}`, channel `{}`: the residual is not white under the noise model ({test}): the model leaves structure unexplained (a missing dynamic, a nonlinearity, a coloured sensor noise, a delay), so the intervals may be too narrow; look at the residuals and validate on another record{hint}",
            check.record, check.channel
        ));
    }
    notes
}
