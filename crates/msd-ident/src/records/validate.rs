//! Validation on fresh data: the fitted plant predicts samples it was not fitted to.
//!
//! Three sources of fresh data, one procedure:
//! - several records: each predicted by the plant fitted to the others (`loo.rs`);
//! - one record: its last share ([`RecordsOptions::hold_out`], a fifth by default)
//!   predicted by the plant refitted to the rest, the reported estimates still from
//!   the whole record;
//! - records given for validation: [`validate_records`].
//!
//! As MATLAB's `compare`, each predicted record's initial state and offsets are fitted
//! with the plant held (they are the record's, not the plant's); R², fit % and the RMS
//! error score the prediction, and its residuals are tested for whiteness (Ljung–Box)
//! and for correlation with the drive, as the paper's validation does.

use super::model::OutputKind;
use super::problem::Joint;
use super::setup::{Record, RecordsOptions};
use super::{LeftOut, RecordsFit, channel_fits, check::check_records, fixed_parameters};
use crate::error::Result;
use crate::residuals::residual_analysis;
use msd_opt::levenberg_marquardt;
use serde::Serialize;

/// The plant's predictions of data it was not fitted to.
///
/// ```
/// use msd_ident::records::RecordsValidation;
/// let v = RecordsValidation { source: "the last 20 % of `run 1`".into(), predictions: vec![] };
/// assert_eq!(serde_json::to_value(&v)?["source"], "the last 20 % of `run 1`");
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RecordsValidation {
    /// What the fresh data are and which plant predicts them, in words.
    pub source: String,
    /// Each predicted record: the predicting plant's fn and ζ, each channel's R², fit %
    /// and RMS error, and its residuals' tests.
    pub predictions: Vec<LeftOut>,
}

/// `left` predicted by the plant at the free log-parameters `x` (its initial state and
/// offsets fitted with the plant held), or why it cannot be.
pub(super) fn predict(
    left: &Record,
    kinds: &[OutputKind],
    options: &RecordsOptions,
    x: &[f64],
    sigma: impl Fn(&str) -> f64 + Copy,
) -> std::result::Result<LeftOut, String> {
    // A fresh record's initial state is its own, whatever the fit assumed of its records
    // (a held-out end starts mid-motion).
    let options = &RecordsOptions {
        estimate_initial_state: true,
        ..options.clone()
    };
    let mut one = Joint::new(
        &[left],
        &[kinds.to_vec()],
        options,
        fixed_parameters(options),
    );
    one.set_sigmas(sigma);
    let theta = one.theta(x);
    if !one.prepare(theta) {
        return Err("the plant cannot be simulated on it".into());
    }
    one.solve_linear();
    let channels = channel_fits(&one, &one.records[0]);
    let drive = left.excitation.samples();
    let residual_analysis = left
        .channels
        .iter()
        .zip(&channels)
        .map(|(c, fit)| {
            let e: Vec<f64> = c
                .samples
                .iter()
                .zip(&fit.model)
                .map(|(y, m)| y - m)
                .collect();
            residual_analysis(&e, drive, &options.residuals).ok()
        })
        .collect();
    let [m, c, k] = theta;
    Ok(LeftOut {
        record: left.name.clone(),
        natural_frequency_hz: (k / m).sqrt() / (2.0 * std::f64::consts::PI),
        damping_ratio: c / (2.0 * (k * m).sqrt()),
        channels,
        residual_analysis,
    })
}

/// `record`'s last `fraction` predicted by the plant refitted (from `x`) to the rest.
pub(super) fn hold_out(
    record: &Record,
    kinds: &[OutputKind],
    options: &RecordsOptions,
    x: &[f64],
    sigma: impl Fn(&str) -> f64 + Copy,
) -> std::result::Result<RecordsValidation, String> {
    let n = record.excitation.len();
    let held = (options.hold_out * n as f64).round() as usize;
    // Each part long enough for the residual tests (4 × lags + 1 samples).
    let fewest = 4 * options.residuals.max_lag + 1;
    if held < fewest || n - held < fewest {
        return Err(format!(
            "{n} samples are too few to hold {:.0} % of them out (each part needs {fewest})",
            100.0 * options.hold_out
        ));
    }
    let part = |range: std::ops::Range<usize>, name: String| -> Result<Record> {
        Ok(Record {
            name,
            excitation: record.excitation.slice(range.start, range.end)?,
            channels: (record.channels.iter())
                .map(|c| msd_signal::Channel {
                    samples: c.samples[range.clone()].to_vec(),
                    ..c.clone()
                })
                .collect(),
        })
    };
    let percent = 100.0 * held as f64 / n as f64;
    let head = part(0..n - held, record.name.clone()).map_err(|e| e.to_string())?;
    let tail = part(
        n - held..n,
        format!("{} (last {percent:.0} %)", record.name),
    )
    .map_err(|e| e.to_string())?;
    let mut rest = Joint::new(
        &[&head],
        &[kinds.to_vec()],
        options,
        fixed_parameters(options),
    );
    rest.set_sigmas(sigma);
    let refit = levenberg_marquardt(&mut rest, x, &options.levenberg_marquardt)
        .map_err(|e| format!("the fit of the first {:.0} % failed: {e}", 100.0 - percent))?;
    Ok(RecordsValidation {
        source: format!(
            "the last {percent:.0} % of `{}` ({held} samples), predicted by the plant fitted to the first {:.0} % (the estimates above use the whole record)",
            record.name,
            100.0 - percent
        ),
        predictions: vec![predict(&tail, kinds, options, &refit.x, sigma)?],
    })
}

/// Predicts `records` (fresh data, the same sensors and drive as the fitted ones) by
/// the plant of `fit`, each record's initial state and offsets fitted with the plant
/// held, as MATLAB's `compare`; the channels are weighted by `fit`'s noise levels.
///
/// ```
/// use msd_ident::{fit_records, Channel, Drive, Excitation, Frame, InitialState, Parameters, Quantity, Record, RecordsOptions, ResponseQuantity, records::{simulate_response, validate_records}};
/// use msd_signal::{gaussian_noise, paper_identification_input, paper_validation_input};
/// let record = |name: &str, signal, seed| -> msd_ident::Result<Record> {
///     let force = Excitation::from_signal(signal, 0.0, 0.002, 7501)?;
///     let x = simulate_response(&Parameters::PAPER, Drive::Force, &force, InitialState::REST,
///         ResponseQuantity::Displacement, Frame::Absolute)?;
///     let noise = gaussian_noise(seed, name, 1e-4, x.len())?;
///     let samples = x.iter().zip(&noise).map(|(x, n)| x + n).collect();
///     Ok(Record { name: name.into(), excitation: force,
///         channels: vec![Channel::new("laser", Quantity::Displacement, samples)] })
/// };
/// let options = RecordsOptions::default();
/// let fit = fit_records(&[record("step and sines", paper_identification_input(), 1)?], &options)?;
/// let fresh = validate_records(&fit, &[record("chirp", paper_validation_input(), 2)?], &options)?;
/// let chirp = &fresh.predictions[0];
/// assert!(chirp.channels[0].fit.r_squared > 0.99);
/// assert!(chirp.residual_analysis[0].as_ref().is_some_and(|a| a.cross_correlation_passed));
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
///
/// Refused as [`fit_records`](super::fit_records) refuses records (naming the record
/// and the channel), and when the plant cannot be simulated on a record.
pub fn validate_records(
    fit: &RecordsFit,
    records: &[Record],
    options: &RecordsOptions,
) -> Result<RecordsValidation> {
    let kinds = check_records(records, options)?;
    let refs: Vec<&Record> = records.iter().collect();
    let x = Joint::new(&refs, &kinds, options, fixed_parameters(options)).pack(fit.theta);
    let sigma = |name: &str| {
        (fit.noise.iter())
            .find(|n| n.channel == name)
            .map_or(1.0, |n| n.sigma)
    };
    let predictions = records
        .iter()
        .zip(&kinds)
        .map(|(r, k)| {
            predict(r, k, options, &x, sigma).map_err(|reason| crate::IdentError::InvalidRecord {
                record: r.name.clone(),
                channel: None,
                reason,
            })
        })
        .collect::<Result<_>>()?;
    let names: Vec<&str> = records.iter().map(|r| r.name.as_str()).collect();
    Ok(RecordsValidation {
        source: format!(
            "{} given for validation (`{}`), predicted by the fitted plant",
            if records.len() == 1 {
                "one record"
            } else {
                "records"
            },
            names.join("`, `")
        ),
        predictions,
    })
}

/// What the reader should know about predictions of fresh data: each channel the plant
/// does not predict (R² < 0.5 with an error above 1.5 σ̂ of the channel's noise — the
/// quiet end of a free decay has a low R² because there is little left to predict, not
/// because the plant is wrong) and each whose residual correlates with the drive.
pub(super) fn notes<'a>(
    predictions: impl Iterator<Item = &'a LeftOut>,
    sigma: impl Fn(&str) -> f64,
) -> Vec<String> {
    let mut notes = Vec::new();
    for p in predictions {
        for (c, a) in p.channels.iter().zip(&p.residual_analysis) {
            if c.fit.r_squared < 0.5 && c.fit.residual_rms > 1.5 * sigma(&c.channel) {
                notes.push(format!(
                    "validation: record `{}`, channel `{}`: R² = {:.3} on fresh data, its error {:.3e} well above the channel's noise {:.3e}: the plant does not predict it",
                    p.record,
                    c.channel,
                    c.fit.r_squared,
                    c.fit.residual_rms,
                    sigma(&c.channel)
                ));
            }
            if let Some(a) = a.as_ref().filter(|a| !a.cross_correlation_passed) {
                notes.push(format!(
                    "validation: record `{}`, channel `{}`: the residual correlates with the drive on fresh data ({}): part of the drive's effect is not explained (a missing mode, a delay, a nonlinearity)",
                    p.record, c.channel, a.cross_correlation
                ));
            }
        }
    }
    notes
}
