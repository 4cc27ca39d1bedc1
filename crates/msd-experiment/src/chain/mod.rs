//! A `[chain]` run: a chain of masses tested in the time domain. The records are
//! simulated through the sensors as tested (delays, filters, noise), msd-ident's
//! [`fit_chain`] fits every m, c, k (and the delays asked for),
//! and where a sensor has a delay or a filter the same records are fitted again as if it
//! had none, to show what ignoring it would have cost.

mod plots;
mod report;
mod validation;

use crate::config::{ChainSection, Config, Spec};
use crate::progress::Progress;
use crate::results::Header;
use crate::{
    error::{ExperimentError, Result},
    options::RunOptions,
};
use msd_ident::chain::{
    ChainFit, ChainOptions, ChainValidation, fit_chain, hold_out_chain, level_out_of_range,
    simulate_chain,
};
use msd_mc::{ChainBand, ChainBandOptions, chain_band};
use msd_signal::{Recording, gaussian_noise};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Everything a chain run produced, in memory.
#[derive(Debug, Clone)]
pub struct ChainOutcome {
    /// The config as read.
    pub config: Config,
    /// The config file as given.
    pub config_path: PathBuf,
    /// The config's `[chain]`.
    pub chain: ChainSection,
    /// The command that ran it, for the report.
    pub command: String,
    /// The seed used.
    pub seed: u64,
    /// The record: the drive and each sensor's noisy series.
    pub record: Recording,
    /// The fit with the sensors as configured.
    pub fit: ChainFit,
    /// The fitted model's reading of each sensor.
    pub fitted: Vec<Vec<f64>>,
    /// The fit that ignores every sensor's delay and filter (when there are any).
    pub ideal: Option<ChainFit>,
    /// The paper's robustness band around the fit: every m, c, k within ±10 %.
    pub band: ChainBand,
    /// The record's last fifth predicted by the chain fitted to the rest, or why it
    /// could not be.
    pub validation: std::result::Result<ChainValidation, String>,
    /// Wall time of each stage, in order.
    pub timings: Vec<(&'static str, Duration)>,
    /// Whether the estimates can be trusted, and why.
    pub verdict: crate::verdict::Verdict,
}

/// Runs the `[chain]` experiment of `spec`.
pub fn run(
    spec: Spec<ChainSection>,
    options: &RunOptions,
    progress: &Progress,
) -> Result<ChainOutcome> {
    let Spec {
        config,
        section: chain,
    } = spec;
    let config_path = config.sources.config_file().to_path_buf();
    let seed = options.seed.unwrap_or(config.seed);
    progress.stage("data");
    let t = Instant::now();
    let record = record(&config, &chain, seed)?;
    let dt = record.dt;
    let mut timings = vec![("data", t.elapsed())];
    progress.stage("estimation");
    let t = Instant::now();
    let fit = fit(&chain, &record)?;
    let fitted_setup = chain.fitted();
    let fit_options = fit_options(&chain);
    let mut reading = fitted_setup.clone();
    for (sensor, delay) in reading.sensors.iter_mut().zip(&fit.uncertainty.delays) {
        if let Some(d) = delay {
            sensor.delay = Some(d.value);
        }
    }
    let fitted = simulate_chain(&reading, &fit.parameters, record.input(), dt)
        .map_err(|e| ExperimentError::run("estimation", e))?;
    timings.push(("estimation", t.elapsed()));
    progress.stage("monte carlo");
    let t = Instant::now();
    // Every draw's response of every sensor is held for the percentiles: a long measured
    // record gets fewer draws (the report says how many), at least 20.
    let per_draw = (record.len() * record.channels.len().max(1)) as f64;
    let draws = (crate::budget::SAMPLES_HELD / per_draw).floor() as usize;
    let band_options = ChainBandOptions {
        seed,
        threads: options
            .threads
            .unwrap_or(ChainBandOptions::default().threads),
        samples: draws.clamp(20, ChainBandOptions::default().samples),
        ..ChainBandOptions::default()
    };
    let band = chain_band(&reading, &fit.parameters, &record, &band_options)
        .map_err(|e| ExperimentError::run("monte carlo", e))?;
    timings.push(("monte carlo", t.elapsed()));
    let t = Instant::now();
    let validation = hold_out_chain(&fitted_setup, &record, &chain.guess, &fit_options, HOLD_OUT)
        .map_err(|e| e.to_string());
    timings.push(("validation", t.elapsed()));
    let has_dynamics = chain
        .sensors
        .iter()
        .any(|s| s.delay.is_some() || s.low_pass.is_some());
    let ideal = if has_dynamics {
        let t = Instant::now();
        let ideal = fit_chain(
            &fitted_setup.with_ideal_sensors(),
            &record,
            &chain.guess,
            &fit_options,
        )
        .map_err(|e| ExperimentError::run("ideal-sensor refit", e))?;
        timings.push(("ideal-sensor refit", t.elapsed()));
        Some(ideal)
    } else {
        None
    };
    let mut outcome = ChainOutcome {
        command: options
            .command
            .clone()
            .unwrap_or_else(|| "msd run".to_string()),
        config,
        config_path,
        chain,
        seed,
        record,
        fit,
        fitted,
        ideal,
        band,
        validation,
        timings,
        verdict: crate::verdict::Verdict::of(Vec::new()),
    };
    outcome.verdict = validation::verdict(&outcome);
    Ok(outcome)
}

/// The synthetic record of `config` for `seed`: the drive from `[identification.input]`
/// on the `[time]` grid, each sensor's reading of the true chain (delays and filters
/// included) plus its noise (stream `chain/<sensor index>`).
pub(crate) fn record(config: &Config, chain: &ChainSection, seed: u64) -> Result<Recording> {
    let config_path = config.sources.config_file();
    if let Some(d) = &config.data {
        return measured_record(config, chain, d);
    }
    let plant = chain
        .plant
        .as_ref()
        .ok_or_else(|| ExperimentError::config(config_path, "chain.plant: missing: a [chain] config without [data] simulates its records from the true chain"))?;
    let input = crate::data::synthetic_input(config, config_path)?
        .ok_or_else(|| ExperimentError::config(config_path, "identification.input: missing"))?;
    let tested = chain.tested(chain.size());
    let clean = simulate_chain(&tested, plant, input.samples(), input.dt())
        .map_err(|e| ExperimentError::run("data", e))?;
    let mut outputs = Vec::with_capacity(clean.len());
    for (j, (y, sensor)) in clean.iter().zip(&chain.sensors).enumerate() {
        let noise = gaussian_noise(seed, &format!("chain/{j}"), sensor.sigma, y.len())
            .map_err(|e| ExperimentError::run("data", e))?;
        outputs.push(y.iter().zip(noise).map(|(a, b)| a + b).collect());
    }
    // The drive as its sensor reads it: the chain felt the exact one.
    let drive_noise = gaussian_noise(seed, "chain/drive", chain.drive_sigma, input.len())
        .map_err(|e| ExperimentError::run("data", e))?;
    let drive = (input.samples().iter().zip(drive_noise))
        .map(|(u, e)| u + e)
        .collect();
    let record = chain
        .fitted()
        .recording(config.name.as_str(), input.dt(), drive, outputs);
    match level_out_of_range(&record) {
        None => Ok(record),
        Some((which, level)) => Err(ExperimentError::config(
            config_path,
            match which {
                None => format!(
                    "identification.input: the drive it describes has RMS {level:e}: {LEVELS_EXPECTED}"
                ),
                Some(i) => format!(
                    "chain.sensors[{i}].sigma = {}: with the drive of identification.input, sensor {}'s record has RMS {level:e}: {LEVELS_EXPECTED}",
                    crate::config::show(chain.sensors[i].sigma),
                    i + 1
                ),
            },
        )),
    }
}

/// What a series' RMS must be, in a message.
const LEVELS_EXPECTED: &str = "expected between 1e-150 and 1e150 (outside, its squares leave double precision: a drive of zero, or of an absurd size)";

/// The measured record of `[data]`: the drive's column (`data.input`, scaled) and each
/// sensor's (`chain.sensors[i].column`, scaled), on the time column or sampling rate.
fn measured_record(
    config: &Config,
    chain: &ChainSection,
    d: &crate::config::DataSection,
) -> Result<Recording> {
    use crate::data::ColumnSpec;
    let path = config.sources.path(d.path.first());
    let missing = |key: String| {
        ExperimentError::data(
            &path,
            format!("{key}: missing: expected the column that holds it"),
        )
    };
    let mut specs = vec![ColumnSpec {
        role: "drive".into(),
        key: "data.input".into(),
        column: d
            .input
            .clone()
            .ok_or_else(|| missing("data.input".into()))?,
        scale: d.input_scale,
        scale_key: "data.input_scale".into(),
    }];
    for (i, s) in chain.sensors.iter().enumerate() {
        specs.push(ColumnSpec {
            role: format!("sensor {}", i + 1),
            key: format!("chain.sensors[{i}].column"),
            column: s
                .column
                .clone()
                .ok_or_else(|| missing(format!("chain.sensors[{i}].column")))?,
            scale: s.scale,
            scale_key: format!("chain.sensors[{i}].scale"),
        });
    }
    let mut table = crate::data::read_columns(d, &config.sources, &path, "data.path", &specs)?;
    let input = table.columns.remove(0);
    let mut record = chain
        .fitted()
        .recording(config.name.as_str(), table.dt, input, table.columns);
    // The channels keep the file's names and the factors that scaled them.
    for (channel, spec) in record.all_channels_mut().zip(&specs) {
        channel.name = spec.column.to_string();
        channel.scale = spec.scale;
    }
    match level_out_of_range(&record) {
        None => Ok(record),
        Some((which, level)) => {
            let spec = &specs[which.map_or(0, |i| i + 1)];
            Err(ExperimentError::data(
                &path,
                format!(
                    "{} (column {}, the {}): its series has RMS {level:e}: {LEVELS_EXPECTED}",
                    spec.key, spec.column, spec.role
                ),
            ))
        }
    }
}

/// The share of the record held out to check the fit on fresh data.
const HOLD_OUT: f64 = 0.2;

/// The fit options of `chain`: its known masses and noise model.
pub(crate) fn fit_options(chain: &ChainSection) -> ChainOptions {
    ChainOptions {
        known_masses: chain.known_masses.clone(),
        // Measured records: the drive's own noise is estimated unless chosen otherwise
        // (a load cell is never exact).
        noise_model: match (chain.noise_model, chain.plant.is_none()) {
            (None, true) => msd_ident::records::NoiseModel::InputNoise,
            _ => chain.noise_model(),
        },
        ..ChainOptions::default()
    }
}

/// `record` fitted as the run fits it: the sensors as configured, from the guess.
pub(crate) fn fit(chain: &ChainSection, record: &Recording) -> Result<ChainFit> {
    fit_chain(&chain.fitted(), record, &chain.guess, &fit_options(chain))
        .map_err(|e| ExperimentError::run("estimation", e))
}

/// `record.csv`: time, the drive, then each sensor measured and as fitted.
pub(crate) fn tables(o: &ChainOutcome) -> Vec<(String, String)> {
    let names = channel_names(o);
    let mut text = format!(
        "time,{}",
        if o.chain.drive == msd_ident::chain::ChainDrive::Force {
            "force"
        } else {
            "base_acceleration"
        }
    );
    for name in &names {
        text.push_str(&format!(",{name},{name}_fitted"));
    }
    text.push('\n');
    for k in 0..o.record.len() {
        text.push_str(&format!("{},{}", o.record.time(k), o.record.input()[k]));
        for (y, f) in o.record.responses().zip(&o.fitted) {
            text.push_str(&format!(",{},{}", y[k], f[k]));
        }
        text.push('\n');
    }
    vec![("record.csv".into(), text)]
}

/// "acceleration_2" and the like, one per sensor.
pub(crate) fn channel_names(o: &ChainOutcome) -> Vec<String> {
    o.chain
        .sensors
        .iter()
        .map(|s| {
            let q = serde_json::to_value(s.quantity)
                .ok()
                .and_then(|v| v.as_str().map(str::to_string))
                .unwrap_or_default();
            format!("{q}_{}", s.at)
        })
        .collect()
}

#[derive(Serialize)]
struct Results<'a> {
    experiment: Header<'a>,
    command: &'a str,
    verdict: &'a crate::verdict::Verdict,
    chain: &'a crate::config::ChainSection,
    fit: &'a ChainFit,
    #[serde(skip_serializing_if = "Option::is_none")]
    ideal_sensors: Option<&'a ChainFit>,
    monte_carlo: BandSummary<'a>,
    #[serde(skip_serializing_if = "Option::is_none")]
    validation: Option<&'a ChainValidation>,
    timings_ms: BTreeMap<&'static str, f64>,
}

/// The band in `results.json`: its draws and each sensor's coverage (not the band).
#[derive(Serialize)]
struct BandSummary<'a> {
    samples: usize,
    percent: f64,
    percentiles: [f64; 2],
    coverage: Option<&'a [f64]>,
}

/// The `results.json` value of `o`.
pub(crate) fn results(
    o: &ChainOutcome,
    extra: &[(&'static str, Duration)],
    total: Duration,
) -> Result<serde_json::Value> {
    let chain = &o.chain;
    let timings = crate::results::timings_ms(&o.timings, extra, total);
    let results = Results {
        experiment: Header::new(
            &o.config,
            &o.config_path,
            if chain.plant.is_some() {
                "synthetic"
            } else {
                "measured"
            },
            o.seed,
            None,
        ),
        command: &o.command,
        verdict: &o.verdict,
        chain,
        fit: &o.fit,
        ideal_sensors: o.ideal.as_ref(),
        monte_carlo: BandSummary {
            samples: o.band.samples,
            percent: ChainBandOptions::default().percent,
            percentiles: o.band.percentiles,
            coverage: o.band.coverage.as_deref(),
        },
        validation: o.validation.as_ref().ok(),
        timings_ms: timings,
    };
    serde_json::to_value(&results).map_err(|e| ExperimentError::run("write", e))
}

pub(crate) use plots::write_all as figures;
pub(crate) use report::{markdown as report, summary};

impl crate::finished::Finished for ChainOutcome {
    fn config(&self) -> &Config {
        &self.config
    }

    fn figures(&self, dir: &Path) -> Result<Vec<&'static str>> {
        figures(self, dir)
    }

    fn tables(&self) -> Vec<(String, String)> {
        tables(self)
    }

    fn timings(&self) -> &[(&'static str, Duration)] {
        &self.timings
    }

    fn report(&self, figures: &[&str]) -> String {
        report(self, figures)
    }

    fn results(
        &self,
        extra: &[(&'static str, Duration)],
        total: Duration,
    ) -> Result<serde_json::Value> {
        results(self, extra, total)
    }

    fn summary(&self) -> String {
        summary(self)
    }
}
