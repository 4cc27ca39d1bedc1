//! What a joint fit returns, and its table.

use super::intervals::PlantIntervals;
use super::validate::RecordsValidation;
use crate::input_noise::{NoiseModelFit, ResidualWhiteness};
use crate::plant::Drive;
use crate::residuals::ResidualAnalysis;
use crate::{free_decay::ClassroomEstimates, metrics::FitMetrics, params::InitialState};
use serde::Serialize;
use std::time::Duration;

/// One channel of one record: its offset, and how well the model follows it.
///
/// ```
/// use msd_ident::{FitMetrics, records::ChannelFit};
/// let model = vec![0.0, 1.0, 2.0];
/// let fit = ChannelFit { channel: "acc".into(), offset: 0.0,
///     fit: FitMetrics::new(&[0.0, 1.1, 1.9], &model), model };
/// assert!(serde_json::to_value(&fit)?.get("model").is_none()); // the samples stay out of JSON
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChannelFit {
    /// The channel's name.
    pub channel: String,
    /// The channel's estimated offset (0 when not estimated), in its unit.
    pub offset: f64,
    /// The model against the channel's samples.
    pub fit: FitMetrics,
    /// The model at every sample, offset included.
    #[serde(skip)]
    pub model: Vec<f64>,
}

/// One record of a joint fit.
///
/// ```
/// use msd_ident::{InitialState, records::RecordFit};
/// let record = RecordFit { name: "run 1".into(), initial_state: InitialState::REST, channels: vec![], classroom: None };
/// assert_eq!(serde_json::to_value(&record)?["initial_state"]["velocity"], 0.0);
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RecordFit {
    /// The record's name.
    pub name: String,
    /// The state at the first sample (at rest when not estimated): the mass's absolute
    /// displacement and velocity, relative to the base under a base acceleration.
    pub initial_state: InitialState,
    /// Each channel, in the record's order.
    pub channels: Vec<ChannelFit>,
    /// A free decay's classroom estimates (logarithmic decrement, damped frequency) from
    /// its first channel, for comparison with the fit; `None` for the other drives.
    pub classroom: Option<ClassroomEstimates>,
}

/// The estimated noise level of one sensor (over every record that has it).
///
/// ```
/// use msd_ident::records::ChannelNoise;
/// let noise = ChannelNoise { channel: "laser".into(), sigma: 1e-3, samples: 7501 };
/// assert_eq!(serde_json::to_value(&noise)?["sigma"], 1e-3);
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChannelNoise {
    /// The channel's name.
    pub channel: String,
    /// σ̂ = √(SSE / (N·(N_total − p)/N_total)), in the channel's unit: its share of the
    /// degrees of freedom.
    pub sigma: f64,
    /// Samples N of this channel over all records.
    pub samples: usize,
}

/// One record predicted by the plant fitted to the other records (its own initial state
/// and offsets fitted with that plant held).
///
/// ```
/// use msd_ident::records::LeftOut;
/// let left = LeftOut { record: "run 3".into(), natural_frequency_hz: 1.1, damping_ratio: 0.05,
///     channels: vec![], residual_analysis: vec![] };
/// assert_eq!(serde_json::to_value(&left)?["record"], "run 3");
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LeftOut {
    /// The record left out.
    pub record: String,
    /// fn of the plant fitted to the others, Hz.
    pub natural_frequency_hz: f64,
    /// ζ of the plant fitted to the others.
    pub damping_ratio: f64,
    /// The prediction of each channel.
    pub channels: Vec<ChannelFit>,
    /// Each channel's prediction residuals tested for whiteness and for correlation with
    /// the drive (25 lags, 99 %); `None` where the record is too short for the tests.
    pub residual_analysis: Vec<Option<ResidualAnalysis>>,
}

/// The result of [`fit_records`](crate::records::fit_records).
///
/// Serializes the plant's intervals at the top level (`identifiable`, `mass`, …,
/// `damping_ratio`), then the noise levels, the records, the leave-one-out predictions,
/// the counts and `wall_time_s`. Displays a compact table.
///
/// ```
/// use msd_ident::{fit_records, Channel, Drive, Excitation, Frame, InitialState, KnownParameter, Parameters, Quantity, Record, RecordsOptions, ResponseQuantity, records::simulate_response};
/// use msd_signal::gaussian_noise;
/// // Two plucks of the paper's plant, 4 s at 5 ms, a laser with σ = 0.1 mm, the mass weighed.
/// let grid = Excitation::from_samples(0.0, 0.005, vec![0.0; 801])?;
/// let pluck = |name: &str, x0: f64, seed: u64| -> msd_ident::Result<Record> {
///     let start = InitialState { displacement: x0, velocity: 0.0 };
///     let x = simulate_response(&Parameters::PAPER, Drive::None, &grid, start,
///         ResponseQuantity::Displacement, Frame::Absolute)?;
///     let noise = gaussian_noise(seed, "laser", 1e-4, x.len())?;
///     let samples = x.iter().zip(&noise).map(|(x, n)| x + n).collect();
///     Ok(Record { name: name.into(), excitation: grid.clone(),
///         channels: vec![Channel::new("laser", Quantity::Displacement, samples)] })
/// };
/// let options = RecordsOptions { drive: Drive::None, known: KnownParameter::Mass(2.5), ..Default::default() };
/// let fit = fit_records(&[pluck("1", 0.01, 1)?, pluck("2", -0.02, 2)?], &options)?;
/// let json = serde_json::to_value(&fit).expect("serializable");
/// assert_eq!(json["identifiable"][0], "natural_frequency_hz");
/// assert!(json["damping"]["ci95"].is_array() && json["records"][1]["channels"][0]["fit"]["r2"].is_number());
/// assert_eq!(fit.leave_one_out.as_ref().map(Vec::len), Some(2));
/// assert!(fit.to_string().contains("R² by others"));
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RecordsFit {
    /// What drove the plant.
    pub drive: Drive,
    /// What the setup identifies, with 95 % intervals.
    #[serde(flatten)]
    pub plant: PlantIntervals,
    /// σ̂ of each sensor, in order of first appearance.
    pub noise: Vec<ChannelNoise>,
    /// The noise model behind the intervals: white, or the drive's noise seen through
    /// the plant (errors-in-variables), with what it found.
    pub noise_model: NoiseModelFit,
    /// The intervals a white-noise fit would have reported, when the noise model changed
    /// them.
    pub white_noise_plant: Option<PlantIntervals>,
    /// The output-error estimate with its intervals under the noise model (the
    /// sandwich), when the weighted estimate replaced it (`noise_model.estimator`).
    pub output_error_plant: Option<PlantIntervals>,
    /// Each record's channels tested for whiteness, as fitted and under the noise model.
    pub whiteness: Vec<ResidualWhiteness>,
    /// Each record's initial state and channel fits.
    pub records: Vec<RecordFit>,
    /// Each record predicted by the others (with two records or more, when asked).
    pub leave_one_out: Option<Vec<LeftOut>>,
    /// A single record's held-out end predicted by the plant fitted to the rest (see
    /// [`RecordsOptions::hold_out`](super::RecordsOptions::hold_out)), or records given
    /// for validation ([`validate_records`](super::validate_records)).
    pub validation: Option<RecordsValidation>,
    /// Weighted least-squares passes (noise levels re-estimated between them).
    pub passes: usize,
    /// Levenberg–Marquardt iterations over all passes.
    pub iterations: usize,
    /// Residual evaluations (each one simulation of every record).
    pub evaluations: usize,
    /// What the reader should know (unconverged noise levels, failed leave-one-out fits).
    pub notes: Vec<String>,
    /// Wall-clock time (serialized as `wall_time_s`, in seconds).
    #[serde(rename = "wall_time_s", serialize_with = "crate::ser::seconds")]
    pub wall_time: Duration,
    /// The model's θ = (m, c, k) (m = 1 and c, k per unit mass where the drive cannot
    /// fix the mass), to predict fresh records.
    #[serde(skip)]
    pub(crate) theta: [f64; 3],
}

impl std::fmt::Display for RecordsFit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let plural = |n: usize| if n == 1 { "" } else { "s" };
        let (records, passes) = (self.records.len(), self.passes);
        writeln!(
            f,
            "{records} record{}, {}: {passes} pass{}, {} iterations, {:.1} ms",
            plural(records),
            self.drive,
            if passes == 1 { "" } else { "es" },
            self.iterations,
            self.wall_time.as_secs_f64() * 1e3
        )?;
        writeln!(f, "identifiable: {}", self.plant.identifiable.join(", "))?;
        writeln!(f, "{}", self.plant)?;
        writeln!(f, "{}", self.noise_model)?;
        for noise in &self.noise {
            writeln!(
                f,
                "σ̂ {} = {:.4e} ({} samples)",
                noise.channel, noise.sigma, noise.samples
            )?;
        }
        write!(
            f,
            "{:<16} {:<12} {:>9} {:>12}",
            "record", "channel", "R²", "offset"
        )?;
        if self.leave_one_out.is_some() {
            write!(f, " {:>12}", "R² by others")?;
        }
        for record in &self.records {
            let left_out = self
                .leave_one_out
                .as_ref()
                .and_then(|l| l.iter().find(|l| l.record == record.name));
            for (c, channel) in record.channels.iter().enumerate() {
                write!(
                    f,
                    "\n{:<16} {:<12} {:>9.5} {:>12.4e}",
                    record.name, channel.channel, channel.fit.r_squared, channel.offset
                )?;
                if let Some(prediction) = left_out.and_then(|l| l.channels.get(c)) {
                    write!(f, " {:>12.5}", prediction.fit.r_squared)?;
                }
            }
        }
        if let Some(v) = &self.validation {
            write!(f, "\nvalidation on {}:", v.source)?;
            for p in &v.predictions {
                for c in &p.channels {
                    write!(f, "\n  {} {}: {}", p.record, c.channel, c.fit)?;
                }
            }
        }
        for note in &self.notes {
            write!(f, "\nnote: {note}")?;
        }
        Ok(())
    }
}
