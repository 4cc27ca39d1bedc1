//! Residual diagnostics: whiteness and independence from the input, as MATLAB's `resid`.
//!
//! ## The tests
//! - Autocorrelation rₖ = Σₜ (eₜ − ē)(eₜ₋ₖ − ē) / Σₜ (eₜ − ē)² for k = 0…L, shown with the
//!   band ±z/√N (z = 2.576 for 99 %), inside which about 99 % of the lags of white noise
//!   fall.
//! - Ljung–Box: Q = N(N + 2) Σₖ₌₁ᴸ rₖ²/(N − k), compared with χ² on L degrees of freedom
//!   (no correction for fitted parameters: the model is not a time-series model of the
//!   residuals). Whiteness passes when the p-value is at least 1 − confidence (0.01).
//! - Cross-correlation ρ(τ) = Σₜ (eₜ − ē)(uₜ₋τ − ū) / √(Σ(e − ē)² Σ(u − ū)²) for
//!   τ = −L…L (τ > 0: the residual against past inputs), with the same band. For white
//!   residuals each lag has variance 1/N whatever the input's colour (Bartlett), so the
//!   band holds. Because 2L + 1 lags are judged at once, the verdict uses the
//!   Bonferroni-corrected band z' = Φ⁻¹(1 − (1 − confidence)/(2(2L + 1)))/√N, which keeps
//!   the chance of a false alarm at 1 − confidence; the lags outside the plain band are
//!   still counted and reported.

pub mod sandwich;

use crate::error::{IdentError, Result};
use serde::{Deserialize, Serialize};
use statrs::distribution::{ChiSquared, ContinuousCDF, Normal};

/// Options of [`residual_analysis`].
///
/// By default L = 25 lags and 99 % confidence, as MATLAB's `resid`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ResidualOptions {
    /// Largest lag L. By default 25.
    pub max_lag: usize,
    /// Confidence level of the bands and tests, in (0, 1). By default 0.99.
    pub confidence: f64,
}

impl Default for ResidualOptions {
    fn default() -> Self {
        Self {
            max_lag: 25,
            confidence: 0.99,
        }
    }
}

impl ResidualOptions {
    /// Checks the options.
    pub fn validate(&self) -> Result<()> {
        if self.max_lag == 0 {
            return Err(IdentError::InvalidParameter {
                name: "max_lag",
                value: 0.0,
                expected: "an integer >= 1",
            });
        }
        if !(self.confidence > 0.0 && self.confidence < 1.0) {
            return Err(IdentError::InvalidParameter {
                name: "confidence",
                value: self.confidence,
                expected: "a number strictly between 0 and 1",
            });
        }
        Ok(())
    }
}

/// Correlation coefficients at a range of lags with their confidence band.
///
/// Displays the largest |value|, the lags outside the band and the outcome, e.g.
/// `max |ρ| = 0.031, 2 of 51 lags outside ±0.030: passed`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CorrelationTest {
    /// The lags.
    pub lags: Vec<i64>,
    /// The correlation coefficient at each lag.
    pub values: Vec<f64>,
    /// Half-width of the pointwise band, z/√N.
    pub bound: f64,
    /// Lags (other than 0 for the autocorrelation) outside the pointwise band.
    pub outside: usize,
    /// The largest |value| over the judged lags.
    pub max_abs: f64,
    /// Whether the test passed.
    pub passed: bool,
}

impl std::fmt::Display for CorrelationTest {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "max |ρ| = {:.3}, {} of {} lags outside ±{:.3}: {}",
            self.max_abs,
            self.outside,
            self.lags.len(),
            self.bound,
            if self.passed { "passed" } else { "failed" }
        )
    }
}

/// The Ljung–Box portmanteau statistic.
///
/// Displays as `Ljung–Box Q = 15.9 (25 dof), p = 0.917`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LjungBox {
    /// Q = N(N + 2) Σ rₖ²/(N − k).
    pub q: f64,
    /// Degrees of freedom L.
    pub degrees_of_freedom: usize,
    /// P(χ²_L ≥ Q).
    pub p_value: f64,
}

impl std::fmt::Display for LjungBox {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "Ljung–Box Q = {:.1} ({} dof), p = {:.3}",
            self.q, self.degrees_of_freedom, self.p_value
        )
    }
}

/// Whiteness and input-independence of a model's residuals.
///
/// Displays the two tests, one line each, then the verdict.
///
/// ```
/// use msd_ident::{residual_analysis, ResidualOptions};
/// use msd_signal::gaussian_noise;
/// let e = gaussian_noise(3, "residuals", 1.0, 5000)?;
/// let u = gaussian_noise(3, "input", 1.0, 5000)?;
/// let a = residual_analysis(&e, &u, &ResidualOptions::default())?;
/// let text = a.to_string();
/// assert!(text.starts_with("whiteness: Ljung–Box Q = "), "{text}");
/// assert!(text.ends_with(&a.verdict));
/// let json = serde_json::to_value(&a).expect("serializable");
/// assert_eq!(json["ljung_box"]["degrees_of_freedom"], 25);
/// assert_eq!(json["autocorrelation"]["lags"].as_array().map(Vec::len), Some(26));
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResidualAnalysis {
    /// Autocorrelation at lags 0…L (lag 0 is 1).
    pub autocorrelation: CorrelationTest,
    /// Residual–input cross-correlation at lags −L…L.
    pub cross_correlation: CorrelationTest,
    /// Ljung–Box test on the autocorrelation.
    pub ljung_box: LjungBox,
    /// Residuals judged white (Ljung–Box p ≥ 1 − confidence).
    pub whiteness_passed: bool,
    /// Residuals judged independent of the input.
    pub cross_correlation_passed: bool,
    /// The verdict in words.
    pub verdict: String,
}

impl std::fmt::Display for ResidualAnalysis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let verdict = |passed| if passed { "passed" } else { "failed" };
        writeln!(
            f,
            "whiteness: {}: {}",
            self.ljung_box,
            verdict(self.whiteness_passed)
        )?;
        writeln!(
            f,
            "residual–input cross-correlation: {}",
            self.cross_correlation
        )?;
        write!(f, "{}", self.verdict)
    }
}

/// Ljung–Box statistic of the autocorrelation `r` (with `r[0] = 1`) of a series of length `n`.
///
/// ```
/// let lb = msd_ident::residuals::ljung_box(&[1.0, 0.5, 0.25], 4);
/// // Q = 4·6·(0.25/3 + 0.0625/2) = 2.75
/// assert!((lb.q - 2.75).abs() < 1e-12);
/// assert_eq!(lb.degrees_of_freedom, 2);
/// ```
pub fn ljung_box(r: &[f64], n: usize) -> LjungBox {
    let lags = r.len().saturating_sub(1);
    let nf = n as f64;
    let q = nf
        * (nf + 2.0)
        * (1..=lags)
            .map(|k| r[k] * r[k] / (nf - k as f64))
            .sum::<f64>();
    let p_value = ChiSquared::new(lags as f64)
        .map(|d| d.sf(q))
        .unwrap_or(f64::NAN);
    LjungBox {
        q,
        degrees_of_freedom: lags,
        p_value,
    }
}

/// Runs the whiteness and cross-correlation tests on `residuals` against `input`.
///
/// ```
/// use msd_ident::{residual_analysis, ResidualOptions};
/// use msd_signal::gaussian_noise;
/// let e = gaussian_noise(3, "residuals", 1.0, 5000)?;
/// let u = gaussian_noise(3, "input", 1.0, 5000)?;
/// let a = residual_analysis(&e, &u, &ResidualOptions::default())?;
/// assert!(a.whiteness_passed && a.cross_correlation_passed);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn residual_analysis(
    residuals: &[f64],
    input: &[f64],
    options: &ResidualOptions,
) -> Result<ResidualAnalysis> {
    options.validate()?;
    if residuals.len() != input.len() {
        return Err(IdentError::LengthMismatch {
            what: "input for the residual analysis",
            expected: residuals.len(),
            got: input.len(),
        });
    }
    let n = residuals.len();
    // 4·max_lag + 1 without overflow: a huge max_lag is simply too many lags.
    let needed = options
        .max_lag
        .checked_mul(4)
        .and_then(|v| v.checked_add(1))
        .unwrap_or(usize::MAX);
    if n < needed {
        return Err(IdentError::TooFewSamples {
            got: n,
            needed,
            why: "residual correlations need at least 4·max_lag + 1 samples",
        });
    }
    crate::data::check_finite("residual", residuals)?;
    crate::data::check_finite("input", input)?;
    let normal = Normal::standard();
    let alpha = 1.0 - options.confidence;
    let z = normal.inverse_cdf(1.0 - alpha / 2.0);
    let bound = z / (n as f64).sqrt();

    let (r, rho) = crate::correlation::correlations(residuals, input, options.max_lag);
    let lb = ljung_box(&r, n);
    let whiteness_passed = lb.p_value >= alpha;
    let auto_outside = r.iter().skip(1).filter(|v| v.abs() > bound).count();
    let auto_max = r.iter().skip(1).fold(0.0f64, |m, v| m.max(v.abs()));

    let judged = rho.len() as f64;
    let z_family = normal.inverse_cdf(1.0 - alpha / (2.0 * judged));
    let family_bound = z_family / (n as f64).sqrt();
    let cross_max = rho.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let cross_outside = rho.iter().filter(|v| v.abs() > bound).count();
    let cross_correlation_passed = cross_max <= family_bound;
    let l = options.max_lag as i64;

    let verdict = match (whiteness_passed, cross_correlation_passed) {
        (true, true) => format!(
            "The residuals look like white noise (Ljung–Box p = {:.3}) and are uncorrelated with the input: the model is adequate.",
            lb.p_value
        ),
        (false, true) => format!(
            "The residuals are correlated in time (Ljung–Box p = {:.2e}, {auto_outside} of {} lags outside the band) but not with the input: the dynamics are captured, the noise is coloured (or an unmodelled disturbance acts).",
            lb.p_value, options.max_lag
        ),
        (true, false) => format!(
            "The residuals are white but correlated with the input (max |ρ| = {cross_max:.3} > {family_bound:.3}): part of the input's effect is not explained: the model is not adequate."
        ),
        (false, false) => format!(
            "The residuals are correlated in time (Ljung–Box p = {:.2e}) and with the input (max |ρ| = {cross_max:.3}): the model misses dynamics: it is not adequate.",
            lb.p_value
        ),
    };
    Ok(ResidualAnalysis {
        autocorrelation: CorrelationTest {
            lags: (0..=l).collect(),
            values: r,
            bound,
            outside: auto_outside,
            max_abs: auto_max,
            passed: whiteness_passed,
        },
        cross_correlation: CorrelationTest {
            lags: (-l..=l).collect(),
            values: rho,
            bound,
            outside: cross_outside,
            max_abs: cross_max,
            passed: cross_correlation_passed,
        },
        ljung_box: lb,
        whiteness_passed,
        cross_correlation_passed,
        verdict,
    })
}
