//! A chain's check on fresh data: the record's last share predicted by the chain fitted
//! to the rest, as [`fit_records`](crate::fit_records) checks a single record.
//!
//! A chain's record starts at rest, so the fitted chain (its delays included) is
//! simulated over the whole record from rest and only the held-out samples are scored:
//! a genuine prediction of samples the fit never saw. Each sensor's prediction residual
//! is tested as the paper's (Ljung–Box whiteness, residual–drive cross-correlation).

use super::fit::{ChainOptions, fit_chain};
use super::setup::{ChainParameters, ChainSetup};
use crate::error::Result;
use crate::input_noise::NoiseModel;
use crate::metrics::FitMetrics;
use crate::residuals::{ResidualAnalysis, ResidualOptions, residual_analysis};
use msd_signal::Recording;
use serde::Serialize;

/// One sensor's prediction of the held-out samples.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainPrediction {
    /// R², fit % and RMS error of the prediction, in the sensor's unit.
    pub fit: FitMetrics,
    /// Its residuals' whiteness and correlation with the drive; `None` when the
    /// held-out part is too short for the tests.
    pub residual_analysis: Option<ResidualAnalysis>,
}

/// The chain fitted without the record's end, and its prediction of that end.
///
/// ```
/// use msd_ident::chain::{ChainValidation, ChainParameters};
/// let v = ChainValidation { source: "the last 20 %".into(), held_out: 100,
///     parameters: ChainParameters::default(), sensors: vec![] };
/// assert_eq!(serde_json::to_value(&v)?["held_out"], 100);
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainValidation {
    /// What was held out and how it was predicted, in words.
    pub source: String,
    /// Samples held out at the record's end.
    pub held_out: usize,
    /// The chain fitted to the rest.
    pub parameters: ChainParameters,
    /// Each sensor's prediction, in the setup's order.
    pub sensors: Vec<ChainPrediction>,
}

/// Fits `setup` to all but the last `fraction` of `record` (as [`fit_chain`], from
/// `guess`) and predicts the rest from rest through the whole record.
///
/// ```
/// use msd_ident::chain::{ChainOptions, ChainParameters, ChainSetup, hold_out_chain, simulate_chain};
/// use msd_signal::{gaussian_noise, paper_identification_input};
/// let p = ChainParameters { masses: vec![2.5], dampers: vec![1.8], springs: vec![120.0], ..ChainParameters::default() };
/// let input = paper_identification_input().sample(0.0, 0.002, 7501);
/// let clean = simulate_chain(&ChainSetup::default(), &p, &input, 0.002)?;
/// let noise = gaussian_noise(1, "x", 1e-4, input.len())?;
/// let y = clean[0].iter().zip(&noise).map(|(y, n)| y + n).collect();
/// let record = ChainSetup::default().recording("test", 0.002, input, vec![y]);
/// let v = hold_out_chain(&ChainSetup::default(), &record, &p, &ChainOptions::default(), 0.2)?;
/// assert_eq!(v.held_out, 1500);
/// assert!((v.sensors[0].fit.residual_rms / 1e-4 - 1.0).abs() < 0.1);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
///
/// Errors: a fraction outside (0, 0.5], a part too short for the residual tests, and
/// what [`fit_chain`] refuses.
pub fn hold_out_chain(
    setup: &ChainSetup,
    record: &Recording,
    guess: &ChainParameters,
    options: &ChainOptions,
    fraction: f64,
) -> Result<ChainValidation> {
    let n = record.len();
    let held = (fraction * n as f64).round() as usize;
    let tests = ResidualOptions::default();
    let fewest = 4 * tests.max_lag + 1;
    if !(fraction > 0.0 && fraction <= 0.5) || held < fewest || n - held < fewest {
        return Err(crate::error::IdentError::InvalidParameter {
            name: "hold_out",
            value: fraction,
            expected: "a share in (0, 0.5] leaving both parts at least 101 samples",
        });
    }
    let head = record.prefix(n - held);
    // Only the estimate is used: the white model spares the noise treatment's cost.
    let estimate_only = ChainOptions {
        noise_model: NoiseModel::White,
        ..options.clone()
    };
    let fit = fit_chain(setup, &head, guess, &estimate_only)?;
    let mut reading = setup.clone();
    for (sensor, delay) in reading.sensors.iter_mut().zip(&fit.uncertainty.delays) {
        if let Some(d) = delay {
            sensor.delay = Some(d.value);
        }
    }
    let predicted = super::simulate_chain(&reading, &fit.parameters, record.input(), record.dt)?;
    let drive = &record.input()[n - held..];
    let sensors = record
        .responses()
        .zip(&predicted)
        .map(|(y, p)| {
            let (y, p) = (&y[n - held..], &p[n - held..]);
            let e: Vec<f64> = y.iter().zip(p).map(|(y, p)| y - p).collect();
            ChainPrediction {
                fit: FitMetrics::new(y, p),
                residual_analysis: residual_analysis(&e, drive, &tests).ok(),
            }
        })
        .collect();
    let percent = 100.0 * held as f64 / n as f64;
    Ok(ChainValidation {
        source: format!(
            "the last {percent:.0} % of the record ({held} samples), predicted from rest through the whole record by the chain fitted to the first {:.0} % (the estimates above use the whole record)",
            100.0 - percent
        ),
        held_out: held,
        parameters: fit.parameters,
        sensors,
    })
}
