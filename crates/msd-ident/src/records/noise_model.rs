//! The errors-in-variables noise model of a joint fit (see [`crate::input_noise`]): the
//! records' residuals and impulse responses handed to the shared spectral model, the
//! sandwich covariance of ln θ, and each channel's whiteness under the model.

use super::intervals::{Linearised, embed, linearise};
use super::problem::{Joint, RecordRows};
use super::spectra::{free_spectra, line_points, mirrored, transfer_spectra};
use super::weighted::{Weighted, refit};
use crate::correlation::autocorrelation;
use crate::error::{IdentError, Result};
use crate::input_noise::{
    Lines, MiddleRecord, NoiseModel, NoiseModelFit, ResidualWhiteness, Sensitivity, SpectralModel,
    WHITENESS_LEVEL, efficiency, middle_matrix, residual_spectrum, residual_spectrum_bands,
    restricted_fit, satterthwaite, whitened_ljung_box,
};
use crate::plant::{Drive, Plant};
use crate::residuals::{ResidualOptions, ljung_box, residual_analysis};
use msd_ode::{ExactSimulator, SVector, SampledInput};
use nalgebra::{DMatrix, DVector, Matrix3};
use rustfft::num_complex::Complex64;
use std::collections::BTreeMap;

/// What [`covariance`] gives: the estimate reported with its Cov(ln θ), the output-error
/// estimate's white-noise Cov(ln θ) (and its sandwich one when the weighted estimate
/// replaced it), the noise model and each channel's whiteness check.
pub(super) struct Treated {
    pub theta: [f64; 3],
    pub reported: Matrix3<f64>,
    pub white: Matrix3<f64>,
    /// The output-error estimate's sandwich Cov(ln θ) and its degrees of freedom.
    pub output_error: Option<(Matrix3<f64>, Option<f64>)>,
    pub fit: NoiseModelFit,
    pub whiteness: Vec<ResidualWhiteness>,
}

/// The estimate and covariance of ln θ the fit reports from the output-error estimate θ
/// (the problem prepared there), with what the noise model found and the residuals'
/// whiteness under it. Where the drive's noise shows (p < 0.01) the estimate is the
/// weighted one ([`refit`]); the problem is left prepared at the reported estimate.
pub(super) fn covariance(
    problem: &mut Joint<'_>,
    theta: [f64; 3],
    choice: NoiseModel,
    tests: &ResidualOptions,
) -> Result<Treated> {
    let linearised = linearise(problem, theta)?;
    let white = embed(problem, &linearised.inverse);
    let mut fit = NoiseModelFit::white();
    let model = match choice {
        NoiseModel::White => None,
        NoiseModel::InputNoise => fit_spectral_model(problem, theta, &linearised)?,
    };
    let Some(FittedModel {
        model,
        information,
        lines,
    }) = model
    else {
        return Ok(Treated {
            theta,
            reported: white,
            white,
            output_error: None,
            fit,
            whiteness: whiteness(problem, theta, None, tests)?,
        });
    };
    describe(&mut fit, problem, &model);
    let (reported, parts) = sandwich(
        problem,
        theta,
        &linearised.jacobian,
        &linearised.inverse,
        &model,
        false,
    )?;
    // Where the drive's noise shows (p < 0.01), its estimate's own uncertainty widens
    // the t; where it does not, σ̂_u sits at or near 0 and Satterthwaite's ν (which
    // treats σ̂_u as symmetric about a value it cannot go below) would widen exact
    // drives' intervals by up to a quarter: they keep the samples' degrees of freedom.
    let shows = model.p_value < WHITENESS_LEVEL;
    fit.degrees_of_freedom = (model.covariance.as_ref())
        .filter(|_| shows)
        .map(|cov| satterthwaite(&dynamic(&reported), &parts, cov, &directions()));
    fit.interval_ratio = fn_ratio(&reported, &white);
    if let Some(bound) = information.try_inverse() {
        let bound = dynamic(&embed(problem, &bound));
        fit.efficiency = efficiencies(&bound, &dynamic(&reported));
    }
    // The weighted estimate trusts the noise model to weigh each line: only where the
    // residuals are white under it (a model that leaves colour, a nonlinearity, keeps
    // the output-error estimate, the best prediction in the time domain).
    // Only the verdict is needed here; the whole check is taken where it is reported.
    let trusted = shows && whitened_passes(problem, theta, &lines, &model, tests)?;
    let Some(weighted) = trusted.then(|| refit(problem, theta, &model)).flatten() else {
        // Left where the output-error fit put it (a failed refit may have moved it).
        problem.prepare(theta);
        problem.solve_linear();
        return Ok(Treated {
            theta,
            reported,
            white,
            output_error: None,
            whiteness: whiteness(problem, theta, Some(&model), tests)?,
            fit,
        });
    };
    let whiteness = whiteness(problem, weighted.theta, Some(&model), tests)?;
    let treated = Treated {
        theta: weighted.theta,
        reported,
        white,
        output_error: None,
        whiteness,
        fit,
    };
    weighted_treatment(problem, treated, &weighted, &model)
}

/// The fit's noise levels and test from `model`.
fn describe(fit: &mut NoiseModelFit, problem: &Joint<'_>, model: &SpectralModel) {
    // The restricted likelihood's variances are those of the noise before the fit took
    // its degrees of freedom: no N/(N − p) inflation after it.
    let sigma_u = model.input_variance.sqrt();
    fit.treatment = "input_noise".into();
    fit.input_noise_sigma = Some(sigma_u);
    fit.input_noise_fraction = Some(sigma_u / drive_rms(problem));
    fit.sensor_sigmas = model.sensor_variance.iter().map(|d| d.sqrt()).collect();
    fit.likelihood_ratio = Some(model.likelihood_ratio);
    fit.p_value = Some(model.p_value);
}

/// The weighted estimate's covariance in place of the output-error one (`treated`
/// holds the latter): the sandwich of its estimating equations, with the efficiencies
/// against its bound and the degrees of freedom.
fn weighted_treatment(
    problem: &Joint<'_>,
    mut treated: Treated,
    weighted: &Weighted,
    model: &SpectralModel,
) -> Result<Treated> {
    let (reported, parts) = sandwich(
        problem,
        weighted.theta,
        &weighted.weights,
        &weighted.inverse,
        model,
        true,
    )?;
    let fit = &mut treated.fit;
    fit.estimator = "weighted".into();
    fit.cost_ratio = Some(weighted.cost_ratio);
    fit.interval_ratio = fn_ratio(&reported, &treated.white);
    let bound = dynamic(&embed(problem, &weighted.inverse));
    fit.output_error_efficiency = efficiencies(&bound, &dynamic(&treated.reported));
    fit.efficiency = efficiencies(&bound, &dynamic(&reported));
    let nu = (model.covariance.as_ref())
        .map(|cov| satterthwaite(&dynamic(&reported), &parts, cov, &directions()));
    let output_error_nu = std::mem::replace(&mut fit.degrees_of_freedom, nu);
    let output_error = std::mem::replace(&mut treated.reported, reported);
    treated.output_error = Some((output_error, output_error_nu));
    Ok(treated)
}

/// The sandwich A⁻¹·B·A⁻¹ (3×3, embedded) of an estimate whose first-order error is
/// A⁻¹·Jᵀ·W·r (`inverse` = A⁻¹; `jacobian`'s rows weighted by the channels' weights
/// unless `unweighted`), B under `model`; with its derivative in each variance (the
/// drive's first) for Satterthwaite.
fn sandwich(
    problem: &Joint<'_>,
    theta: [f64; 3],
    jacobian: &DMatrix<f64>,
    inverse: &DMatrix<f64>,
    model: &SpectralModel,
    unweighted: bool,
) -> Result<(Matrix3<f64>, Vec<DMatrix<f64>>)> {
    let mut records = middle_records(problem, theta)?;
    if unweighted {
        records.iter_mut().for_each(|r| r.weights.fill(1.0));
    }
    let middle = middle_matrix(&records, jacobian, problem.group_names.len());
    let reported = embed(problem, &(inverse * middle.total(model, 1.0) * inverse));
    let parts = std::iter::once(&middle.drive)
        .chain(&middle.sensors)
        .map(|b| dynamic(&embed(problem, &(inverse * b * inverse))))
        .collect();
    Ok((reported, parts))
}

fn dynamic(m: &Matrix3<f64>) -> DMatrix<f64> {
    DMatrix::from_column_slice(3, 3, m.as_slice())
}

/// The reported fn's standard error over the white-noise one.
fn fn_ratio(reported: &Matrix3<f64>, white: &Matrix3<f64>) -> f64 {
    let e = nalgebra::Vector3::new(-0.5, 0.0, 0.5);
    let variance = |c: &Matrix3<f64>| (e.transpose() * c * e)[(0, 0)].max(0.0);
    (variance(reported) / variance(white)).sqrt()
}

/// Each reported quantity's efficiency: the bound's variance over the reported one.
fn efficiencies(bound: &DMatrix<f64>, reported: &DMatrix<f64>) -> BTreeMap<String, f64> {
    let names = [
        "natural_frequency_hz",
        "damping_ratio",
        "mass",
        "damping",
        "stiffness",
    ];
    names
        .iter()
        .zip(directions())
        .filter_map(|(name, e)| efficiency(bound, reported, &e).map(|r| (name.to_string(), r)))
        .collect()
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
        let closed = (model.map(|_| closed_form(problem, rec, theta))).transpose()?;
        let lines = record_lines(problem, rec, closed.as_ref())?;
        let free = match &closed {
            Some(closed) => free_responses(rec, closed)?,
            None => vec![Vec::new(); rec.groups.len()],
        };
        for (ch, transient) in free.iter().enumerate() {
            let raw: Vec<f64> = (0..rec.len)
                .map(|i| rec.record.channels[ch].samples[i] - problem.model(rec, ch, i))
                .collect();
            // With a drive, one pass gives the residual's test and its correlation with
            // the drive.
            let analysis = (problem.drive != Drive::None)
                .then(|| {
                    let u = rec.record.excitation.samples();
                    residual_analysis(&raw, u, tests).ok()
                })
                .flatten();
            let raw_test = match &analysis {
                Some(a) => a.ljung_box,
                None => ljung_box(&autocorrelation(&raw, lags), rec.len),
            };
            let whitened =
                model.map(|m| whitened_ljung_box(&lines, ch, m, lags, rec.len, transient));
            let judged = whitened.unwrap_or(raw_test);
            let input_correlation = analysis.map(|a| a.cross_correlation);
            checks.push(ResidualWhiteness {
                record: rec.record.name.clone(),
                channel: rec.record.channels[ch].name.clone(),
                ljung_box: raw_test,
                ljung_box_under_noise_model: whitened,
                input_correlation,
                spectrum: Some(residual_spectrum_bands(&lines, ch, model, problem.dt, 1.0)),
                passed: judged.p_value >= 1.0 - tests.confidence,
            });
        }
    }
    Ok(checks)
}

/// Whether every channel's residual at θ (the problem prepared there, its `lines`
/// taken there) passes the Ljung–Box test under `model`: [`whiteness`]'s verdict alone.
fn whitened_passes(
    problem: &Joint<'_>,
    theta: [f64; 3],
    lines: &[Lines],
    model: &SpectralModel,
    tests: &ResidualOptions,
) -> Result<bool> {
    for (rec, lines) in problem.records.iter().zip(lines) {
        let free = free_responses(rec, &closed_form(problem, rec, theta)?)?;
        for (ch, transient) in free.iter().enumerate() {
            let test = whitened_ljung_box(lines, ch, model, tests.max_lag, rec.len, transient);
            if test.p_value < 1.0 - tests.confidence {
                return Ok(false);
            }
        }
    }
    Ok(true)
}

/// A record's plant at θ as the simulator discretises it, with its DFT's points
/// (lines 0..=N/2): what the closed-form spectra are taken from.
struct ClosedForm {
    sim: ExactSimulator<2>,
    points: Vec<Complex64>,
}

fn closed_form(problem: &Joint<'_>, rec: &RecordRows<'_>, theta: [f64; 3]) -> Result<ClosedForm> {
    Ok(ClosedForm {
        sim: plant(problem, theta).response(problem.dt, problem.hold)?,
        points: line_points(rec.len),
    })
}

/// The DFTs (scaled as the residual's, every line) of each channel's free responses
/// from a unit initial displacement and velocity.
fn free_responses(rec: &RecordRows<'_>, closed: &ClosedForm) -> Result<Vec<Vec<Vec<Complex64>>>> {
    let free =
        free_spectra(&closed.sim, &rec.maps, &closed.points, rec.len).ok_or_else(singular)?;
    Ok((free.into_iter())
        .map(|pair| pair.into_iter().map(|b| mirrored(b, rec.len)).collect())
        .collect())
}

/// The refusal where zI − Φ is singular at a line of a record's DFT.
fn singular() -> IdentError {
    IdentError::EstimationFailed {
        reason: "the plant's frequency response is singular on the record's lines".into(),
    }
}

/// The plant at θ under the problem's drive.
fn plant(problem: &Joint<'_>, theta: [f64; 3]) -> Plant {
    Plant {
        theta,
        drive: problem.drive,
    }
}

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

/// The spectral model with the Fisher information of ln θ under it and the records'
/// lines it was fitted to.
struct FittedModel {
    model: SpectralModel,
    information: DMatrix<f64>,
    lines: Vec<Lines>,
}

/// Fits the spectral model to the residuals of the prepared problem at θ, with the
/// Fisher information of ln θ under it (None for a free decay: no drive, no drive
/// noise).
/// The likelihood is the restricted one: each line's residual as the fit at
/// `linearised` left it.
fn fit_spectral_model(
    problem: &Joint<'_>,
    theta: [f64; 3],
    linearised: &Linearised,
) -> Result<Option<FittedModel>> {
    if problem.drive == Drive::None {
        return Ok(None);
    }
    let lines = problem
        .records
        .iter()
        .map(|rec| record_lines(problem, rec, Some(&closed_form(problem, rec, theta)?)))
        .collect::<Result<Vec<_>>>()?;
    let j = &linearised.jacobian;
    // The residual's sensitivities in the channels' own units: the fit's weighted,
    // projected Jacobian over each channel's weight.
    let fits: Vec<Sensitivity> = problem
        .records
        .iter()
        .map(|rec| Sensitivity {
            columns: (0..rec.maps.len())
                .map(|ch| {
                    let rows = rec.start + ch * rec.len..rec.start + (ch + 1) * rec.len;
                    (0..j.ncols())
                        .map(|c| rows.clone().map(|i| j[(i, c)] / rec.weights[ch]).collect())
                        .collect()
                })
                .collect(),
            nuisance: nuisance_columns(problem, rec),
            weights: rec.weights.clone(),
        })
        .collect();
    let groups = problem.group_names.len();
    let (model, information) = restricted_fit(&lines, &fits, &linearised.inverse, groups);
    Ok(Some(FittedModel {
        model,
        information,
        lines,
    }))
}

/// Per channel, the record's initial-state responses that the fit projected θ's
/// columns against (each channel's mean removed where its offset is estimated: the
/// offsets live on the mean line alone); none where the initial state is not estimated.
fn nuisance_columns(problem: &Joint<'_>, rec: &RecordRows<'_>) -> Vec<Vec<Vec<f64>>> {
    if !problem.state {
        return Vec::new();
    }
    (0..rec.maps.len())
        .map(|ch| {
            let rows = rec.start + ch * rec.len..rec.start + (ch + 1) * rec.len;
            (0..2)
                .map(|i| {
                    let column: Vec<f64> =
                        problem.basis[rows.clone()].iter().map(|b| b[i]).collect();
                    let mean = if problem.offset {
                        column.iter().sum::<f64>() / column.len() as f64
                    } else {
                        0.0
                    };
                    column.iter().map(|x| x - mean).collect()
                })
                .collect()
        })
        .collect()
}

/// A record's residual lines at the prepared θ, with each channel's transfer from
/// `closed` (none without it).
fn record_lines(
    problem: &Joint<'_>,
    rec: &RecordRows<'_>,
    closed: Option<&ClosedForm>,
) -> Result<Lines> {
    let size = rec.len;
    let residual = (0..rec.maps.len())
        .map(|ch| {
            let samples = &rec.record.channels[ch].samples;
            let r = (0..rec.len).map(|i| samples[i] - problem.model(rec, ch, i));
            residual_spectrum(r, size)
        })
        .collect();
    let transfer = if let Some(closed) = closed {
        let half = transfer_spectra(&closed.sim, &rec.maps, &closed.points);
        (half.ok_or_else(singular)?.into_iter())
            .map(|g| mirrored(g, size))
            .collect()
    } else {
        Vec::new()
    };
    Ok(Lines {
        size,
        groups: rec.groups.clone(),
        residual,
        transfer,
    })
}

/// Each record's impulse responses and rows of the projected Jacobian, for the middle
/// matrix.
fn middle_records(problem: &Joint<'_>, theta: [f64; 3]) -> Result<Vec<MiddleRecord>> {
    problem
        .records
        .iter()
        .map(|rec| {
            Ok(MiddleRecord {
                len: rec.len,
                impulse: impulse_responses(problem, rec, theta)?,
                rows: (0..rec.maps.len())
                    .map(|ch| rec.start + ch * rec.len..rec.start + (ch + 1) * rec.len)
                    .collect(),
                weights: rec.weights.clone(),
                groups: rec.groups.clone(),
            })
        })
        .collect()
}

/// The reported directions of ln θ whose degrees of freedom are checked: fn, ζ, each
/// parameter, c over k.
fn directions() -> Vec<DVector<f64>> {
    [
        [-0.5, 0.0, 0.5],
        [-0.5, 1.0, -0.5],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 1.0, -1.0],
    ]
    .iter()
    .map(|e| DVector::from_column_slice(e))
    .collect()
}

/// Each channel's response to one unit drive sample, `rec.len` samples from rest. The
/// sample stands at 4: a cubic hold's centred stencils reach back two samples, and the
/// first step's one-sided stencil (samples 0–3) must not reach it (at 3 it added a
/// spurious 1/24 of the sample, |G| 4 % high).
pub(super) fn impulse_responses(
    problem: &Joint<'_>,
    rec: &RecordRows<'_>,
    theta: [f64; 3],
) -> Result<Vec<Vec<f64>>> {
    let sim = plant(problem, theta).response(problem.dt, problem.hold)?;
    let mut impulse = vec![0.0; rec.len + 4];
    impulse[4] = 1.0;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input_noise::spectrum;
    use crate::records::setup::{Record, RecordsOptions};
    use crate::records::{model::OutputKind, simulate_channels};
    use crate::{Excitation, InitialState, Parameters};
    use msd_signal::{Channel, Frame, ResponseQuantity, gaussian_noise};

    /// The FFT middle matrix equals Jᵀ·W·Σ·W·J with Σ the covariance of the modelled
    /// noise written out entry by entry (to rounding: the padding makes the circular
    /// correlations the linear ones).
    #[test]
    fn the_middle_matrix_is_the_time_domain_one() {
        let (dt, n) = (1e-2, 400);
        let record = two_channel_record(dt, n);
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
        let records = middle_records(&problem, theta).expect("impulse responses");
        let fast = middle_matrix(&records, &j, 2).total(&model, 1.0);
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

    /// The time-domain impulse responses (the middle matrix's) and the closed-form
    /// transfer (the spectral model's) are one plant: over a record long enough for the
    /// response to die out (40 s, e^(−ζωn·t) ≈ 1e-16), the DFT of the response to the unit
    /// sample at 4 is G·z⁻⁴ on every line. With the sample at 3 the cubic hold's first
    /// step added 1/24 of it: |G| 4 % high.
    #[test]
    fn the_impulse_responses_dft_is_the_transfer() {
        let (dt, n) = (1e-2, 4000);
        let record = two_channel_record(dt, n);
        let kinds = vec![vec![OutputKind::Acceleration, OutputKind::Displacement]];
        let options = RecordsOptions::default();
        let mut problem = Joint::new(&[&record], &kinds, &options, [None; 3]);
        let theta = [1.7, 3.1, 950.0];
        assert!(problem.prepare(theta));
        problem.solve_linear();
        let rec = &problem.records[0];
        let g = impulse_responses(&problem, rec, theta).expect("impulse");
        let closed = closed_form(&problem, rec, theta).expect("discretised");
        let lines = record_lines(&problem, rec, Some(&closed)).expect("lines");
        for (ch, g) in g.iter().enumerate() {
            let dft = spectrum(g.iter().copied(), n, 1.0);
            let peak = dft.iter().map(|v| v.norm()).fold(0.0, f64::max);
            for (k, (d, t)) in dft.iter().zip(&lines.transfer[ch]).enumerate() {
                let shift =
                    Complex64::from_polar(1.0, -8.0 * std::f64::consts::PI * k as f64 / n as f64);
                assert!(
                    (d - t * shift).norm() < 1e-9 * peak,
                    "channel {ch}, line {k}: {d} against {}",
                    t * shift
                );
            }
        }
    }

    /// A record of the plant (1.7 kg, 3.1 N·s/m, 950 N/m) under a random force, with an
    /// accelerometer and a displacement sensor, noise-free.
    /// The sensitivity system's output derivatives are the central differences of the
    /// model's response from the same initial state (to their O(h²) and rounding), at a
    /// θ other than the one the problem was prepared at: the outputs are taken at θ.
    #[test]
    fn the_output_sensitivities_are_the_responses_derivatives() {
        let (dt, n) = (1e-2, 400);
        let record = two_channel_record(dt, n);
        let kinds = vec![vec![OutputKind::Acceleration, OutputKind::Displacement]];
        let options = RecordsOptions::default();
        let mut problem = Joint::new(&[&record], &kinds, &options, [None; 3]);
        assert!(problem.prepare([1.2, 2.0, 700.0]));
        let (theta, state) = ([1.7, 3.1, 950.0], [2e-3, -0.04]);
        let exact =
            (problem.output_sensitivities(&problem.records[0], theta, state)).expect("simulated");
        let h = 1e-5;
        for (p, exact) in exact.iter().enumerate() {
            let mut response = |sign: f64| {
                let mut shifted = theta;
                shifted[p] *= (sign * h).exp();
                assert!(problem.prepare(shifted));
                let g = |row: usize| problem.basis[row];
                (0..2 * n)
                    .map(|row| problem.forced[row] + g(row)[0] * state[0] + g(row)[1] * state[1])
                    .collect::<Vec<f64>>()
            };
            let (up, down) = (response(1.0), response(-1.0));
            for (ch, exact) in exact.iter().enumerate() {
                let size = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for (t, v) in exact.iter().enumerate() {
                    let row = ch * n + t;
                    let difference = (up[row] - down[row]) / (2.0 * h);
                    assert!(
                        (difference - v).abs() < 1e-7 * size,
                        "θ_{p}, channel {ch}, sample {t}: {v} against {difference}"
                    );
                }
            }
        }
    }

    fn two_channel_record(dt: f64, n: usize) -> Record {
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
            .map(|((samples, name), (quantity, frame))| {
                Channel::new(name, quantity.into(), samples).in_frame(frame)
            })
            .collect();
        Record {
            name: "r".into(),
            excitation,
            channels,
        }
    }
}
