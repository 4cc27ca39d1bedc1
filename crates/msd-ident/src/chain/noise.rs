//! A chain's residuals under the errors-in-variables noise model ([`crate::input_noise`]):
//! the drive (a load cell's force, a base accelerometer's acceleration) measured with
//! white noise that reaches every sensor through the chain, its delay and its filter.
//! Everything here is in the fit's weighted units (each channel divided by its σ̂), so
//! each sensor is its own group and the Jacobian is the solver's.

use super::problem::ChainProblem;
use super::setup::rms;
use crate::correlation::autocorrelation;
use crate::input_noise::{
    Lines, MiddleRecord, NoiseModel, NoiseModelFit, ResidualWhiteness, Sensitivity, SpectralModel,
    WHITENESS_LEVEL, efficiency, impulse_spectrum, middle_matrix, residual_spectrum,
    residual_spectrum_bands, restricted_fit, satterthwaite, spectrum, whitened_ljung_box,
};
use crate::residuals::{ResidualOptions, ljung_box, residual_analysis};
use msd_opt::statistics::Linearization;
use msd_signal::Recording;
use nalgebra::{DMatrix, DVector};
use rustfft::num_complex::Complex64;

/// What [`treat`] gives: the covariance of θ to report (`None`: the white one), what
/// the noise model found, each sensor's whiteness, and the t's degrees of freedom.
pub(super) struct Treated {
    pub covariance: Option<DMatrix<f64>>,
    pub fit: NoiseModelFit,
    pub whiteness: Vec<ResidualWhiteness>,
    pub t_dof: usize,
}

/// The noise treatment of a chain fit at θ: `jacobian` and `residuals` weighted by the
/// final noise levels (`problem.noise`), `dof` the samples' degrees of freedom.
pub(super) fn treat(
    problem: &ChainProblem<'_>,
    theta: &[f64],
    jacobian: &DMatrix<f64>,
    residuals: &[f64],
    dof: usize,
    choice: NoiseModel,
    tests: &ResidualOptions,
) -> Treated {
    let record = problem.record;
    let len = record.len();
    let channels = record.channels.len();
    let rows = |ch: usize| ch * len..(ch + 1) * len;
    let mut whiteness = as_fitted(record, residuals, &problem.noise, tests);
    let white = Treated {
        covariance: None,
        fit: NoiseModelFit::white(),
        whiteness: whiteness.clone(),
        t_dof: dof,
    };
    let inverse = match Linearization::new(jacobian) {
        Ok(lin) => lin.covariance(1.0),
        Err(_) => return white,
    };
    let Some(Responses { impulse, free }) = (choice == NoiseModel::InputNoise)
        .then(|| impulse_and_free(problem, theta))
        .flatten()
    else {
        return white;
    };
    let lines = Lines {
        size: len,
        groups: (0..channels).collect(),
        residual: (0..channels)
            .map(|ch| residual_spectrum(residuals[rows(ch)].iter().copied(), len))
            .collect(),
        transfer: impulse
            .iter()
            .map(|g| impulse_spectrum(g.iter().copied(), len))
            .collect(),
    };
    let middle = middle_matrix(
        &[MiddleRecord {
            len,
            impulse,
            rows: (0..channels).map(rows).collect(),
            weights: vec![1.0; channels],
            groups: (0..channels).collect(),
        }],
        jacobian,
        channels,
    );
    let parts: Vec<DMatrix<f64>> = std::iter::once(&middle.drive)
        .chain(&middle.sensors)
        .map(|b| &inverse * b * &inverse)
        .collect();
    // The restricted likelihood: the variances of the noise the fit left (unbiased for
    // the degrees of freedom it took, so no N/(N − p) inflation after it).
    let (model, information) = noise_fit(&lines, jacobian, &inverse);
    let inflation = 1.0;
    let reported = &inverse * middle.total(&model, inflation) * &inverse;
    let p = jacobian.ncols();
    let directions: Vec<DVector<f64>> = (0..p)
        .map(|j| DVector::from_fn(p, |i, _| if i == j { 1.0 } else { 0.0 }))
        .collect();
    // As the joint fit's: Satterthwaite only where the drive's noise shows.
    let nu = model
        .covariance
        .as_ref()
        .filter(|_| model.p_value < WHITENESS_LEVEL)
        .map(|cov| satterthwaite(&reported, &parts, cov, &directions));
    let s2 = residuals.iter().map(|r| r * r).sum::<f64>() / dof as f64;
    let ratio = (0..p)
        .map(|j| (reported[(j, j)] / (s2 * inverse[(j, j)])).max(0.0).sqrt())
        .fold(0.0, f64::max);
    let sigma_u = (model.input_variance * inflation).sqrt();
    let under = Under {
        lines: &lines,
        model: &model,
        free: &free,
    };
    under.judge(&mut whiteness, problem, tests);
    let fit = NoiseModelFit {
        treatment: "input_noise".into(),
        input_noise_sigma: Some(sigma_u),
        input_noise_fraction: Some(sigma_u / rms(record.input())),
        sensor_sigmas: model
            .sensor_variance
            .iter()
            .zip(&problem.noise)
            .map(|(d, sigma)| (d * inflation).sqrt() * sigma)
            .collect(),
        likelihood_ratio: Some(model.likelihood_ratio),
        p_value: Some(model.p_value),
        interval_ratio: ratio,
        degrees_of_freedom: nu,
        efficiency: information
            .try_inverse()
            .map(|bound| {
                (0..p)
                    .filter_map(|j| {
                        efficiency(&bound, &reported, &directions[j])
                            .map(|r| (problem.layout.name(j), r))
                    })
                    .collect()
            })
            .unwrap_or_default(),
        ..NoiseModelFit::white()
    };
    let t_dof = match nu {
        Some(nu) if nu.is_finite() => (nu.floor() as usize).clamp(1, dof),
        _ => dof,
    };
    Treated {
        covariance: Some(reported),
        fit,
        whiteness,
        t_dof,
    }
}

/// A record's lines under the fitted model, with each sensor's free responses.
struct Under<'a> {
    lines: &'a Lines,
    model: &'a SpectralModel,
    free: &'a [Vec<Vec<Complex64>>],
}

impl Under<'_> {
    /// Each sensor's whiteness under the model, which decides its verdict, and its
    /// residual spectrum against the model's in the sensor's unit.
    fn judge(
        &self,
        whiteness: &mut [ResidualWhiteness],
        problem: &ChainProblem<'_>,
        tests: &ResidualOptions,
    ) {
        let (len, dt) = (self.lines.size, problem.record.dt);
        for (ch, check) in whiteness.iter_mut().enumerate() {
            let (lines, model) = (self.lines, Some(self.model));
            let test =
                whitened_ljung_box(lines, ch, self.model, tests.max_lag, len, &self.free[ch]);
            let scale = problem.noise[ch].powi(2);
            check.spectrum = Some(residual_spectrum_bands(lines, ch, model, dt, scale));
            check.ljung_box_under_noise_model = Some(test);
            check.passed = test.p_value >= 1.0 - tests.confidence;
        }
    }
}

/// The spectral model fitted by the restricted likelihood to the record `lines` of a fit
/// with the weighted `jacobian` (each sensor its own group) and normal-matrix inverse
/// `inverse`, with the Fisher information of θ under it.
fn noise_fit(
    lines: &Lines,
    jacobian: &DMatrix<f64>,
    inverse: &DMatrix<f64>,
) -> (SpectralModel, DMatrix<f64>) {
    let (channels, len) = (lines.groups.len(), lines.size);
    let sensitivity = Sensitivity {
        columns: (0..channels)
            .map(|ch| {
                (0..jacobian.ncols())
                    .map(|j| {
                        jacobian
                            .column(j)
                            .rows(ch * len, len)
                            .iter()
                            .copied()
                            .collect()
                    })
                    .collect()
            })
            .collect(),
        // A chain's records start from rest: no initial state projected out.
        nuisance: Vec::new(),
        weights: vec![1.0; channels],
    };
    restricted_fit(
        std::slice::from_ref(lines),
        std::slice::from_ref(&sensitivity),
        inverse,
        channels,
    )
}

/// Each sensor's residual tested as fitted: Ljung–Box, the correlation with the drive
/// and its spectrum against the white level (`noise`: each sensor's σ̂, the residuals'
/// unit).
fn as_fitted(
    record: &Recording,
    residuals: &[f64],
    noise: &[f64],
    tests: &ResidualOptions,
) -> Vec<ResidualWhiteness> {
    let len = record.len();
    (0..record.channels.len())
        .map(|ch| {
            let r = &residuals[ch * len..(ch + 1) * len];
            let ljung = ljung_box(&autocorrelation(r, tests.max_lag), len);
            let lines = Lines {
                size: len,
                groups: vec![0],
                residual: vec![residual_spectrum(r.iter().copied(), len)],
                transfer: Vec::new(),
            };
            let spectrum = residual_spectrum_bands(&lines, 0, None, record.dt, noise[ch].powi(2));
            ResidualWhiteness {
                record: "record".into(),
                channel: format!("sensor {}", ch + 1),
                ljung_box: ljung,
                ljung_box_under_noise_model: None,
                input_correlation: residual_analysis(r, record.input(), tests)
                    .ok()
                    .map(|a| a.cross_correlation),
                spectrum: Some(spectrum),
                passed: ljung.p_value >= 1.0 - tests.confidence,
            }
        })
        .collect()
}

/// Each sensor's impulse response over the record and the DFTs of its free responses.
struct Responses {
    impulse: Vec<Vec<f64>>,
    free: Vec<Vec<Vec<Complex64>>>,
}

/// [`impulse_responses`] over the record, and the [`free_responses`] from their tails.
fn impulse_and_free(problem: &ChainProblem<'_>, theta: &[f64]) -> Option<Responses> {
    let (len, count) = (problem.record.len(), free_count(problem));
    let mut impulse = impulse_responses(problem, theta, count + FREE_AFTER)?;
    let free = (impulse.iter())
        .map(|g| free_responses(g, len, count))
        .collect();
    for g in &mut impulse {
        g.truncate(len);
    }
    Some(Responses { impulse, free })
}

/// The samples after an impulse from which its response is a free one (the hold's ramp
/// up and down has passed).
const FREE_AFTER: usize = 2;

/// How many free responses span a chain's end state: two per mass, and a margin for the
/// sensors' filters.
fn free_count(problem: &ChainProblem<'_>) -> usize {
    2 * problem.setup.masses + 4
}

/// The DFTs (scaled as a residual's) of `count` free responses of one channel, its
/// impulse response `g` shifted by FREE_AFTER, FREE_AFTER + 1, …: the states an impulse
/// reaches span the chain's state space, so these span the wrap-round of the state the
/// drive's noise leaves at the record's end (`whitened_ljung_box`).
fn free_responses(g: &[f64], len: usize, count: usize) -> Vec<Vec<Complex64>> {
    let scale = 1.0 / (len as f64).sqrt();
    (0..count)
        .map(|j| {
            let start = FREE_AFTER + j;
            spectrum(g[start..start + len].iter().copied(), len, scale)
        })
        .collect()
}

/// Each sensor's response to one unit drive sample, from rest, divided by its noise
/// level (the fit's weighted units), the record's length and `extra` samples more;
/// `None` where the chain cannot be simulated. The drive is linear between samples, so
/// one sample's drive is a triangle over two intervals: the unit sample stands at the
/// second instant, and the response is read from there.
fn impulse_responses(
    problem: &ChainProblem<'_>,
    theta: &[f64],
    extra: usize,
) -> Option<Vec<Vec<f64>>> {
    let len = problem.record.len() + extra;
    let mut input = vec![0.0; len + 1];
    input[1] = 1.0;
    let record = problem
        .setup
        .recording("impulse", problem.record.dt, input, Vec::new());
    let impulse = ChainProblem {
        record: &record,
        noise: problem.noise.clone(),
        ..*problem
    };
    let sim = impulse.simulate(theta, None)?;
    Some(
        problem
            .noise
            .iter()
            .enumerate()
            .map(|(ch, sigma)| {
                sim.outputs[ch * (len + 1) + 1..(ch + 1) * (len + 1)]
                    .iter()
                    .map(|g| g / sigma)
                    .collect()
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chain::problem::Layout;
    use crate::chain::{ChainParameters, ChainSensor, ChainSetup, simulate_chain};
    use msd_signal::{ResponseQuantity, gaussian_noise};

    /// The model driven by a noisy drive differs from the model driven by the exact one
    /// by the drive's noise convolved with the impulse responses the treatment uses (a
    /// delayed accelerometer and a displacement sensor, weighted).
    #[test]
    fn a_drive_noise_reaches_each_sensor_through_its_impulse_response() {
        let setup = ChainSetup {
            masses: 2,
            force_at: 2,
            sensors: vec![
                ChainSensor {
                    at: 1,
                    quantity: ResponseQuantity::Acceleration,
                    delay: Some(0.004),
                    ..ChainSensor::default()
                },
                ChainSensor {
                    at: 2,
                    quantity: ResponseQuantity::Displacement,
                    ..ChainSensor::default()
                },
            ],
            ..ChainSetup::default()
        };
        let truth = ChainParameters {
            masses: vec![2.0, 1.5],
            dampers: vec![3.0, 2.0],
            springs: vec![8000.0, 6000.0],
            ..ChainParameters::default()
        };
        let (n, dt) = (600, 2e-3);
        // The record's first sample drives only the half triangle after it: the
        // convolution holds from a first sample of 0 (an edge effect of one sample).
        let mut noise = gaussian_noise(3, "drive", 1.0, n).expect("noise");
        noise[0] = 0.0;
        let quiet = vec![0.0; n];
        let response = simulate_chain(&setup, &truth, &noise, dt).expect("simulated");
        let record = setup.recording("quiet", dt, quiet, response.clone());
        let layout = Layout::new(&setup, &[], &truth);
        let delays = [0.004, 0.0];
        let theta = layout.theta(&truth, &delays);
        let problem = ChainProblem {
            setup: &setup,
            record: &record,
            layout: &layout,
            base: &truth,
            delays: &delays,
            noise: vec![0.5, 2.0],
        };
        let g = impulse_responses(&problem, &theta, 0).expect("impulse responses");
        for (ch, sigma) in [0.5, 2.0].iter().enumerate() {
            let scale = response[ch].iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for t in 0..n {
                let conv: f64 = (0..=t).map(|i| g[ch][t - i] * sigma * noise[i]).sum();
                assert!(
                    (conv - response[ch][t]).abs() < 1e-9 * scale,
                    "sensor {ch}, sample {t}: {conv} vs {}",
                    response[ch][t]
                );
            }
        }
    }
}
