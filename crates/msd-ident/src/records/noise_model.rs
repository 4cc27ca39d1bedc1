//! The errors-in-variables noise model of a joint fit: white sensor noise on every
//! channel plus white noise on the measured drive, seen through the plant.
//!
//! ## Why
//! The output-error fit assumes the residuals are white. When the drive is measured with
//! noise (a load cell, a base accelerometer), the plant feels u = u_m − n while the model
//! is driven by u_m, so each channel's residual is v = e − g∗n: its sensor's white noise
//! plus the drive's noise filtered by the plant, largest near resonance and shared by
//! the channels of one record. The white-noise covariance then understates the spread of
//! c and ζ several times over (1 % force noise: 2–5×).
//!
//! ## The method
//! At θ̂, each channel's impulse response g (the model's response to one unit drive
//! sample, hold included) gives G_a(ω). The residuals' cross-spectrum is modelled as
//! S_ab(ω) = δ_ab·σ²_a + σ²_u·G_a(ω)·G_b(ω)*, one σ_a per sensor name and one σ_u for the
//! drive. σ²_a and σ²_u maximise the Whittle likelihood of the residuals' DFTs at the
//! record's own lines (independent for stationary noise; a one-factor model per line).
//! A likelihood-ratio test against σ_u = 0 says whether the drive's noise shows. The
//! covariance of ln θ is the sandwich A⁻¹·B·A⁻¹ of the Gauss–Newton matrix A = JᵀJ of
//! the projected weighted Jacobian and B = Jᵀ·W·Σ·W·J, computed line by line in the
//! frequency domain (zero-padded to ≥ 2N so that the circular products are the linear
//! ones): the intervals of the estimate that was made, under the noise it was made
//! with. With σ̂_u = 0 it is the white-noise covariance. The estimate itself is
//! unchanged: the drive's noise biases it at second order (σ²_u over the drive's power
//! per line), negligible against its spread at a few per cent of noise.
//!
//! Over 40 simulated load-cell records (1.7 kg, 950 N/m, ζ 0.04, a 0.2–15 Hz multisine
//! at 1 kHz, an accelerometer at 0.05 m/s²) the 95 % intervals of m, c, k cover the
//! truth 0.93–0.95 at 1 % and 3 % force noise, where the white-noise ones cover
//! 0.23–0.48 (`cargo xtask noise-study` repeats this over 400 seeds and more setups).

use super::intervals::{embed, linearise};
use super::problem::{Joint, RecordRows};
use super::satterthwaite::{fisher, satterthwaite};
use super::setup::NoiseModel;
use crate::correlation::autocorrelation;
use crate::error::Result;
use crate::fft;
use crate::plant::{Drive, Plant};
use crate::residuals::{CorrelationTest, LjungBox, ResidualOptions, ljung_box, residual_analysis};
use msd_ode::{SVector, SampledInput};
use msd_opt::{NelderMeadOptions, nelder_mead};
use nalgebra::{DMatrix, Matrix3};
use rustfft::num_complex::Complex64;
use serde::Serialize;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// What the noise model found, and which intervals were reported.
///
/// Displays one line: the treatment, then σ_u and the test when the model was fitted.
///
/// ```
/// use msd_ident::records::NoiseModelFit;
/// let fit = NoiseModelFit { treatment: "input_noise".into(), input_noise_sigma: Some(0.02),
///     input_noise_fraction: Some(0.01), sensor_sigmas: vec![0.05],
///     likelihood_ratio: Some(210.0), p_value: Some(1e-40), interval_ratio: 3.1,
///     degrees_of_freedom: Some(180.0) };
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
            write!(f, ")")?;
        }
        Ok(())
    }
}

/// What [`covariance`] gives: the reported and the white-noise Cov(ln θ), the noise
/// model and each channel's whiteness check.
pub(super) struct Treated {
    pub reported: Matrix3<f64>,
    pub white: Matrix3<f64>,
    pub fit: NoiseModelFit,
    pub whiteness: Vec<ResidualWhiteness>,
}

/// The covariance of ln θ the fit reports at θ (the problem prepared), with what the
/// noise model found and the residuals' whiteness under it.
pub(super) fn covariance(
    problem: &Joint<'_>,
    theta: [f64; 3],
    choice: NoiseModel,
    tests: &ResidualOptions,
    dof: usize,
) -> Result<Treated> {
    let linearised = linearise(problem, theta)?;
    let white = embed(problem, &linearised.inverse);
    let mut fit = NoiseModelFit {
        treatment: "white".into(),
        input_noise_sigma: None,
        input_noise_fraction: None,
        sensor_sigmas: Vec::new(),
        likelihood_ratio: None,
        p_value: None,
        interval_ratio: 1.0,
        degrees_of_freedom: None,
    };
    let model = match choice {
        NoiseModel::White => None,
        NoiseModel::InputNoise => fit_spectral_model(problem, theta)?,
    };
    let whiteness = whiteness(problem, theta, model.as_ref(), tests)?;
    let Some(model) = model else {
        return Ok(Treated {
            reported: white,
            white,
            fit,
            whiteness,
        });
    };
    // The white-noise covariance divides by N − p, not N: the same correction here.
    let inflation = problem.rows as f64 / dof as f64;
    let sigma_u = (model.input_variance * inflation).sqrt();
    fit.input_noise_sigma = Some(sigma_u);
    fit.input_noise_fraction = Some(sigma_u / drive_rms(problem));
    fit.sensor_sigmas = model
        .sensor_variance
        .iter()
        .map(|d| (d * inflation).sqrt())
        .collect();
    fit.likelihood_ratio = Some(model.likelihood_ratio);
    fit.p_value = Some(model.p_value);
    let inverse = &linearised.inverse;
    let middle = middle_matrix(problem, theta, &linearised.jacobian)?;
    let reported = embed(
        problem,
        &(inverse * middle.total(&model, inflation) * inverse),
    );
    let parts: Vec<Matrix3<f64>> = std::iter::once(&middle.drive)
        .chain(&middle.sensors)
        .map(|b| embed(problem, &(inverse * b * inverse)) * inflation)
        .collect();
    // Where the drive's noise shows (p < 0.01), its estimate's own uncertainty widens
    // the t; where it does not, σ̂_u sits at or near 0 and Satterthwaite's ν (which
    // treats σ̂_u as symmetric about a value it cannot go below) would widen exact
    // drives' intervals by up to a quarter: they keep the samples' degrees of freedom.
    fit.degrees_of_freedom = model
        .covariance
        .as_ref()
        .filter(|_| model.p_value < WHITENESS_LEVEL)
        .map(|cov| satterthwaite(&reported, &parts, cov));
    let e = nalgebra::Vector3::new(-0.5, 0.0, 0.5);
    let variance = |c: &Matrix3<f64>| (e.transpose() * c * e)[(0, 0)].max(0.0);
    fit.interval_ratio = (variance(&reported) / variance(&white)).sqrt();
    fit.treatment = "input_noise".into();
    Ok(Treated {
        reported,
        white,
        fit,
        whiteness,
    })
}

/// Each channel's residual tested for whiteness (Ljung–Box, 25 lags) as it is and
/// whitened by the noise model: S_aa(ω)^(−1/2) applied line by line.
fn whiteness(
    problem: &Joint<'_>,
    theta: [f64; 3],
    model: Option<&SpectralModel>,
    tests: &ResidualOptions,
) -> Result<Vec<ResidualWhiteness>> {
    let lags = tests.max_lag;
    let mut checks = Vec::new();
    for rec in &problem.records {
        let lines = record_lines(problem, rec, theta, model.is_some())?;
        for (ch, &g) in rec.groups.iter().enumerate() {
            let raw: Vec<f64> = (0..rec.len)
                .map(|i| rec.record.channels[ch].samples[i] - problem.model(rec, ch, i))
                .collect();
            let raw_test = ljung_box(&autocorrelation(&raw, lags), rec.len);
            let whitened = model.map(|m| {
                let mut z: Vec<Complex64> = (0..lines.size)
                    .map(|k| {
                        let t = lines.transfer[ch][k];
                        let s = m.sensor_variance[g] + m.input_variance * t.norm_sqr();
                        lines.residual[ch][k] / s.max(f64::MIN_POSITIVE).sqrt()
                    })
                    .collect();
                z[0] = Complex64::new(0.0, 0.0);
                fft::inverse(lines.size).process(&mut z);
                let series: Vec<f64> = z.iter().map(|v| v.re).collect();
                ljung_box(&autocorrelation(&series, lags), rec.len)
            });
            let judged = whitened.unwrap_or(raw_test);
            let input_correlation = (problem.drive != Drive::None)
                .then(|| {
                    let u = rec.record.excitation.samples();
                    residual_analysis(&raw, u, tests).ok()
                })
                .flatten()
                .map(|a| a.cross_correlation);
            checks.push(ResidualWhiteness {
                record: rec.record.name.clone(),
                channel: rec.record.channels[ch].name.clone(),
                ljung_box: raw_test,
                ljung_box_under_noise_model: whitened,
                input_correlation,
                passed: judged.p_value >= 1.0 - tests.confidence,
            });
        }
    }
    Ok(checks)
}

/// The level of the test for the drive's noise (and of the whiteness tests by default).
const WHITENESS_LEVEL: f64 = 0.01;

/// The rms of every record's drive samples.
fn drive_rms(problem: &Joint<'_>) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for rec in &problem.records {
        sum += rec
            .record
            .excitation
            .samples()
            .iter()
            .map(|u| u * u)
            .sum::<f64>();
        count += rec.len;
    }
    (sum / count.max(1) as f64).sqrt()
}

/// One channel's residual whiteness: as fitted, and under the noise model.
///
/// ```
/// use msd_ident::{records::ResidualWhiteness, residuals::ljung_box};
/// let lb = ljung_box(&[1.0, 0.01, -0.02], 10_000);
/// let check = ResidualWhiteness { record: "run 1".into(), channel: "acc".into(),
///     ljung_box: lb, ljung_box_under_noise_model: Some(lb), input_correlation: None, passed: true };
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
    /// The residual is white under the model the intervals assume (p ≥ 0.01): when
    /// false, the model leaves colour unexplained (a missing dynamic, a nonlinearity, a
    /// coloured sensor noise) and the intervals may be too narrow.
    pub passed: bool,
}

/// The fitted spectral model: σ²_a per sensor group and σ²_u, with the test.
pub(super) struct SpectralModel {
    pub sensor_variance: Vec<f64>,
    pub input_variance: f64,
    /// The covariance of (σ²_u, σ²_a…) from the Whittle likelihood's Fisher
    /// information, `None` where it is singular.
    pub covariance: Option<DMatrix<f64>>,
    pub likelihood_ratio: f64,
    pub p_value: f64,
}

/// One record in the frequency domain: per channel the residual's DFT (scaled by 1/√N)
/// and the impulse response's, at the record's own N lines (independent for white
/// noise).
pub(super) struct Lines {
    pub size: usize,
    pub residual: Vec<Vec<Complex64>>,
    pub transfer: Vec<Vec<Complex64>>,
}

/// Fits the spectral model to the residuals of the prepared problem at θ (None for a
/// free decay: no drive, no drive noise).
pub(super) fn fit_spectral_model(
    problem: &Joint<'_>,
    theta: [f64; 3],
) -> Result<Option<SpectralModel>> {
    if problem.drive == Drive::None {
        return Ok(None);
    }
    let lines = problem
        .records
        .iter()
        .map(|rec| record_lines(problem, rec, theta, true))
        .collect::<Result<Vec<_>>>()?;
    Ok(Some(maximise(problem, &lines)))
}

/// The padded FFT length for a record of `len` samples.
fn padded(len: usize) -> usize {
    (2 * len).next_power_of_two()
}

fn record_lines(
    problem: &Joint<'_>,
    rec: &RecordRows<'_>,
    theta: [f64; 3],
    transfer: bool,
) -> Result<Lines> {
    let size = rec.len;
    let scale = 1.0 / (rec.len as f64).sqrt();
    let residual = (0..rec.maps.len())
        .map(|ch| {
            let samples = &rec.record.channels[ch].samples;
            let r = (0..rec.len).map(|i| samples[i] - problem.model(rec, ch, i));
            spectrum(r, size, scale)
        })
        .collect();
    let transfer = if transfer {
        impulse_responses(problem, rec, theta)?
            .into_iter()
            .map(|g| spectrum(g.into_iter(), size, 1.0))
            .collect()
    } else {
        Vec::new()
    };
    Ok(Lines {
        size,
        residual,
        transfer,
    })
}

/// The DFT of `x` zero-padded to `size`, times `scale`.
fn spectrum(x: impl Iterator<Item = f64>, size: usize, scale: f64) -> Vec<Complex64> {
    let mut buffer = vec![Complex64::new(0.0, 0.0); size];
    for (b, v) in buffer.iter_mut().zip(x) {
        b.re = v * scale;
    }
    fft::forward(size).process(&mut buffer);
    buffer
}

/// Each channel's response to one unit drive sample (at sample 3, so that a cubic hold's
/// reach back is kept), `rec.len` samples from rest.
fn impulse_responses(
    problem: &Joint<'_>,
    rec: &RecordRows<'_>,
    theta: [f64; 3],
) -> Result<Vec<Vec<f64>>> {
    let plant = Plant {
        theta,
        drive: problem.drive,
    };
    let sim = plant.response(problem.dt, problem.hold)?;
    let mut impulse = vec![0.0; rec.len + 3];
    impulse[3] = 1.0;
    let mut g = vec![Vec::with_capacity(rec.len); rec.maps.len()];
    sim.simulate_with(
        &SVector::zeros(),
        &SampledInput::smooth(&impulse),
        |i, s| {
            if i < rec.len {
                for (out, map) in g.iter_mut().zip(&rec.maps) {
                    out.push(map.value([s[0], s[1]], impulse[i]));
                }
            }
        },
    )?;
    Ok(g)
}

/// The one-sided lines of an unpadded DFT used by the likelihood: no mean, no Nyquist.
pub(super) fn likelihood_lines(size: usize) -> std::ops::Range<usize> {
    1..size.div_ceil(2)
}

/// σ²_a and σ²_u maximising the Whittle likelihood (Nelder–Mead in ln σ²_a and
/// ψ = σ_u/σ_ref, σ²_ref the drive noise that matches the first sensor's at the
/// largest gain), then the likelihood ratio against σ_u = 0.
fn maximise(problem: &Joint<'_>, lines: &[Lines]) -> SpectralModel {
    let white = white_variances(problem, lines);
    let groups = white.len();
    let peak = likelihood_lines(lines[0].size)
        .map(|k| lines[0].transfer[0][k].norm_sqr())
        .fold(0.0, f64::max);
    let reference = white[0] / peak.max(f64::MIN_POSITIVE);
    let unpack = |x: &[f64]| {
        let d: Vec<f64> = x[..groups].iter().map(|v| v.exp()).collect();
        (d, reference * x[groups] * x[groups])
    };
    let cost = |x: &[f64]| {
        let (d, s_u) = unpack(x);
        -log_likelihood(problem, lines, &d, s_u)
    };
    let mut x0: Vec<f64> = white.iter().map(|d| d.ln()).collect();
    x0.push(0.5);
    let options = NelderMeadOptions {
        x_tolerance: 1e-6,
        f_tolerance: 1e-6,
        max_evaluations: Some(1000 * (groups + 1)),
        max_iterations: Some(1000 * (groups + 1)),
        ..NelderMeadOptions::default()
    };
    let white_cost = -log_likelihood(problem, lines, &white, 0.0);
    let (d, s_u, best) = match nelder_mead(cost, &x0, &options) {
        Ok(fit) if fit.cost < white_cost => {
            let (d, s_u) = unpack(&fit.x);
            (d, s_u, fit.cost)
        }
        _ => (white.clone(), 0.0, white_cost),
    };
    let likelihood_ratio = 2.0 * (white_cost - best);
    let p_value = 0.5
        * ChiSquared::new(1.0)
            .map(|c| c.sf(likelihood_ratio))
            .unwrap_or(1.0);
    let covariance = fisher(problem, lines, &d, s_u).try_inverse();
    SpectralModel {
        sensor_variance: d,
        input_variance: s_u,
        covariance,
        likelihood_ratio,
        p_value,
    }
}

/// Each group's mean line power: the white model's variances.
fn white_variances(problem: &Joint<'_>, lines: &[Lines]) -> Vec<f64> {
    let groups = problem.group_names.len();
    let (mut power, mut members) = (vec![0.0; groups], vec![0.0; groups]);
    for (rec, l) in problem.records.iter().zip(lines) {
        for (ch, &g) in rec.groups.iter().enumerate() {
            for k in likelihood_lines(l.size) {
                power[g] += l.residual[ch][k].norm_sqr();
                members[g] += 1.0;
            }
        }
    }
    power
        .iter()
        .zip(&members)
        .map(|(p, m)| (p / m).max(f64::MIN_POSITIVE))
        .collect()
}

/// a = Gᴴ·D⁻¹·G and b = Gᴴ·D⁻¹·R at line k.
fn projections(rec: &RecordRows<'_>, l: &Lines, k: usize, d: &[f64]) -> (f64, Complex64) {
    let (mut a, mut b) = (0.0, Complex64::new(0.0, 0.0));
    for (ch, &g) in rec.groups.iter().enumerate() {
        let t = l.transfer[ch][k];
        a += t.norm_sqr() / d[g];
        b += t.conj() * l.residual[ch][k] / d[g];
    }
    (a, b)
}

/// The Whittle log-likelihood −Σ (ln det S + Rᴴ·S⁻¹·R), S = D + σ²_u·G·Gᴴ.
fn log_likelihood(problem: &Joint<'_>, lines: &[Lines], d: &[f64], s_u: f64) -> f64 {
    let mut total = 0.0;
    for (rec, l) in problem.records.iter().zip(lines) {
        let log_det_d: f64 = rec.groups.iter().map(|&g| d[g].ln()).sum();
        for k in likelihood_lines(l.size) {
            let (a, b) = projections(rec, l, k, d);
            let quadratic: f64 = rec
                .groups
                .iter()
                .enumerate()
                .map(|(ch, &g)| l.residual[ch][k].norm_sqr() / d[g])
                .sum();
            total -=
                log_det_d + (1.0 + s_u * a).ln() + quadratic - s_u * b.norm_sqr() / (1.0 + s_u * a);
        }
    }
    total
}

/// The parts of B = Jᵀ·W·Σ·W·J (p×p) of the projected weighted Jacobian `jacobian`,
/// per unit variance of the drive and of each sensor group. The drive's noise starts with the record (the
/// plant felt the true drive before it): Σ = σ²_u·Gₐ·G_bᵀ + δ_ab·σ²_a with Gₐ the
/// record's lower-triangular convolution by gₐ, so B's drive part is σ²_u·HᵀH with
/// H = Σₐ Gₐᵀ·Wₐ·Jₐ, each column one zero-padded FFT correlation.
fn middle_matrix(problem: &Joint<'_>, theta: [f64; 3], jacobian: &DMatrix<f64>) -> Result<Middle> {
    let p = jacobian.ncols();
    let mut middle = Middle {
        drive: DMatrix::zeros(p, p),
        sensors: vec![DMatrix::zeros(p, p); problem.group_names.len()],
    };
    for rec in &problem.records {
        let size = padded(rec.len);
        let transfer: Vec<Vec<Complex64>> = impulse_responses(problem, rec, theta)?
            .into_iter()
            .map(|g| spectrum(g.into_iter(), size, 1.0))
            .collect();
        let rows = |ch: usize| rec.start + ch * rec.len..rec.start + (ch + 1) * rec.len;
        let h: Vec<Vec<f64>> = (0..p)
            .map(|c| {
                let mut sum = vec![Complex64::new(0.0, 0.0); size];
                for (ch, g) in transfer.iter().enumerate() {
                    let column = jacobian.column(c);
                    let x = spectrum(
                        column.rows_range(rows(ch)).iter().copied(),
                        size,
                        rec.weights[ch],
                    );
                    for ((s, x), g) in sum.iter_mut().zip(&x).zip(g) {
                        *s += g.conj() * x;
                    }
                }
                fft::inverse(size).process(&mut sum);
                sum[..rec.len].iter().map(|v| v.re / size as f64).collect()
            })
            .collect();
        for r in 0..p {
            for c in 0..p {
                middle.drive[(r, c)] += h[r].iter().zip(&h[c]).map(|(a, b)| a * b).sum::<f64>();
                for (ch, &g) in rec.groups.iter().enumerate() {
                    let (x, y) = (jacobian.column(r), jacobian.column(c));
                    let dot: f64 = rows(ch).map(|i| x[i] * y[i]).sum();
                    middle.sensors[g][(r, c)] += rec.weights[ch].powi(2) * dot;
                }
            }
        }
    }
    Ok(middle)
}

/// B's parts, each per unit variance: the drive's (σ²_u) and each sensor group's (σ²_a).
struct Middle {
    drive: DMatrix<f64>,
    sensors: Vec<DMatrix<f64>>,
}

impl Middle {
    /// B under `model`, its variances scaled by `inflation`.
    fn total(&self, model: &SpectralModel, inflation: f64) -> DMatrix<f64> {
        let mut b = &self.drive * model.input_variance;
        for (part, d) in self.sensors.iter().zip(&model.sensor_variance) {
            b += part * *d;
        }
        b * inflation
    }
}

/// What the reader should know about the noise: the drive's noise when it shows, and
/// each channel whose residual is not white under the model the intervals assume.
pub(super) fn notes(
    fit: &NoiseModelFit,
    whiteness: &[ResidualWhiteness],
    drive: Drive,
) -> Vec<String> {
    let mut notes = Vec::new();
    if let (Some(sigma), Some(fraction), Some(p)) =
        (fit.input_noise_sigma, fit.input_noise_fraction, fit.p_value)
        && p < WHITENESS_LEVEL
    {
        let caveat = if whiteness.iter().any(|c| !c.passed) {
            "; the residuals stay coloured under this model, so σ̂_u may stand for what the model misses (a nonlinearity, a missing mode) rather than the drive's noise"
        } else {
            ""
        };
        notes.push(format!(
            "the drive's own noise shows in the residuals (σ̂_u = {sigma:.3e}, {:.2} % of its rms, p = {p:.1e}): the intervals are the errors-in-variables ones, {:.2}× the white-noise ones (`white_noise_plant`){caveat}",
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
        let hint = if drive != Drive::None && check.ljung_box_under_noise_model.is_none() {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::setup::{Channel, Record, RecordsOptions};
    use crate::records::{model::OutputKind, simulate_channels};
    use crate::{Excitation, Frame, InitialState, Parameters};
    use msd_signal::{ResponseQuantity, gaussian_noise};

    /// The FFT middle matrix equals Jᵀ·W·Σ·W·J with Σ the covariance of the modelled
    /// noise written out entry by entry (to rounding: the padding makes the circular
    /// correlations the linear ones).
    #[test]
    fn the_middle_matrix_is_the_time_domain_one() {
        let (dt, n) = (1e-2, 400);
        let plant = Parameters {
            mass: 1.7,
            damping: 3.1,
            stiffness: 950.0,
        };
        let force = gaussian_noise(1, "force", 5.0, n).expect("noise");
        let excitation = Excitation::from_samples(0.0, dt, force).expect("valid");
        let kinds = [
            (ResponseQuantity::Acceleration, Frame::Absolute),
            (ResponseQuantity::Displacement, Frame::Absolute),
        ];
        let clean = simulate_channels(
            &plant,
            InitialState::REST,
            Drive::Force,
            Some(&excitation),
            n,
            dt,
            &kinds,
        )
        .expect("simulated");
        let channels = clean
            .into_iter()
            .zip(["acc", "lvdt"])
            .zip(kinds)
            .map(|((samples, name), (quantity, frame))| Channel {
                name: name.into(),
                quantity,
                frame,
                samples,
            })
            .collect();
        let record = Record {
            name: "r".into(),
            excitation,
            channels,
        };
        let options = RecordsOptions::default();
        let kinds = vec![vec![OutputKind::Acceleration, OutputKind::Displacement]];
        let mut problem = Joint::new(&[&record], &kinds, &options, [None; 3]);
        problem.set_sigmas(|g| if g == "acc" { 0.05 } else { 1e-5 });
        let theta = [1.7, 3.1, 950.0];
        assert!(problem.prepare(theta));
        problem.solve_linear();
        let j = linearise(&problem, theta).expect("linearised").jacobian;
        let model = SpectralModel {
            sensor_variance: vec![0.05f64.powi(2), 1e-10],
            input_variance: 0.05f64.powi(2),
            covariance: None,
            likelihood_ratio: 0.0,
            p_value: 1.0,
        };
        let fast = middle_matrix(&problem, theta, &j)
            .expect("middle")
            .total(&model, 1.0);
        let rec = &problem.records[0];
        let g = impulse_responses(&problem, rec, theta).expect("impulse");
        let w = &rec.weights;
        // Σ_ab(t, s) = σ²_u·Σ_{i ≤ min(t, s)} g_a(t − i)·g_b(s − i) + δ_ab·δ_ts·σ²_a.
        let mut slow = DMatrix::<f64>::zeros(3, 3);
        for a in 0..2 {
            for b in 0..2 {
                for t in 0..n {
                    for s in 0..n {
                        let shared: f64 = (0..=t.min(s)).map(|i| g[a][t - i] * g[b][s - i]).sum();
                        let mut c = model.input_variance * shared;
                        if a == b && t == s {
                            c += model.sensor_variance[a];
                        }
                        let c = w[a] * c * w[b];
                        for p in 0..3 {
                            let x = j[(a * n + t, p)] * c;
                            for q in 0..3 {
                                slow[(p, q)] += x * j[(b * n + s, q)];
                            }
                        }
                    }
                }
            }
        }
        let scale = slow.abs().max();
        assert!((fast - &slow).abs().max() < 1e-9 * scale, "{slow}");
    }
}
