//! The records of a `[setup]` run: generated from the synthetic plant (every channel
//! from the exact simulation, each with its own noise stream) or read from the measured
//! files (one record per file).

use crate::config::DataSection;
use crate::config::{Config, ExcitationKind, Plant, Response, SetupSection};
use crate::data::{ColumnSpec, overlap_note, read_columns, resolve_range};
use crate::error::{ExperimentError, Result};
use msd_ident::Excitation;
use msd_signal::gaussian_noise;
use std::path::{Path, PathBuf};

/// One record: the drive as measured (none for a free decay) and the response
/// channels, in SI units, on one uniform grid.
#[derive(Debug, Clone, PartialEq)]
pub struct SetupRecord {
    /// `record-1`, … (synthetic) or the file's stem (measured).
    pub name: String,
    /// The drive: force, base motion or the imposed stroke (None for a free decay).
    pub input: Option<Excitation>,
    /// Time of each sample, s.
    pub time: Vec<f64>,
    /// Time of the first sample, s.
    pub t0: f64,
    /// Sampling interval, s.
    pub dt: f64,
    /// The channels, in the order of `setup.responses`.
    pub channels: Vec<Vec<f64>>,
    /// The noise-free channels (synthetic only).
    pub truth: Option<Vec<Vec<f64>>>,
    /// The stroke's frequency, Hz (synthetic test machine only; measured ones are
    /// estimated from the stroke).
    pub frequency: Option<f64>,
}

impl SetupRecord {
    /// Samples `[a, b)` of the record, named `name`.
    fn part(&self, name: String, [a, b]: [usize; 2]) -> std::result::Result<Self, String> {
        let input = match &self.input {
            Some(x) => Some(x.slice(a, b).map_err(|e| e.to_string())?),
            None => None,
        };
        Ok(SetupRecord {
            name,
            input,
            time: self.time[a..b].to_vec(),
            t0: self.time[a],
            dt: self.dt,
            channels: self.channels.iter().map(|c| c[a..b].to_vec()).collect(),
            truth: (self.truth.as_ref()).map(|t| t.iter().map(|c| c[a..b].to_vec()).collect()),
            frequency: self.frequency,
        })
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.channels.first().map_or(0, Vec::len)
    }

    /// Whether the record holds no sample.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The records of a setup run and where they came from.
#[derive(Debug, Clone, PartialEq)]
pub struct SetupData {
    /// The setup, its channels filled in.
    pub setup: SetupSection,
    /// The channels' descriptions, in order.
    pub channels: Vec<Response>,
    /// The records (each cut to `data.estimation` when given).
    pub records: Vec<SetupRecord>,
    /// Each record's `data.validation` part, fresh data for the fitted plant to
    /// predict (measured only; empty when not given).
    pub validation: Vec<SetupRecord>,
    /// What the reader should know about the parts (a validation part that overlaps
    /// the estimation part).
    pub notes: Vec<String>,
    /// The true plant (synthetic only).
    pub truth: Option<Plant>,
    /// The files read (measured only).
    pub files: Vec<PathBuf>,
}

/// Generates or reads the records of `config`'s `setup`.
pub fn load(config: &Config, setup: &SetupSection, seed: u64) -> Result<SetupData> {
    let config_path = config.sources.config_file();
    let setup = setup.clone();
    let channels = setup.channels();
    let Measured {
        records,
        files,
        notes,
        validation,
    } = match &config.data {
        Some(_) => measured(config, &setup, &channels)?,
        None => Measured {
            records: synthetic(config, config_path, &setup, &channels, seed)?,
            ..Measured::default()
        },
    };
    let mut data = SetupData {
        truth: config.data.is_none().then_some(config.plant).flatten(),
        setup,
        channels,
        records,
        validation,
        notes,
        files,
    };
    if let Some(d) = &config.data {
        split(&mut data, d, config_path)?;
    }
    Ok(data)
}

/// Cuts each measured record to `data.estimation` and takes its `data.validation`
/// part aside, with a note where the two overlap.
fn split(data: &mut SetupData, d: &DataSection, config_path: &Path) -> Result<()> {
    let whole = crate::config::Range::default();
    if d.estimation == whole && d.validation.is_none() {
        return Ok(());
    }
    let mut records = Vec::with_capacity(data.records.len());
    for (i, r) in data.records.iter().enumerate() {
        let grid = (r.len(), r.t0, r.dt);
        let range = |spec, key| {
            resolve_range(spec, grid, r.len(), 1, key).map_err(|m| {
                ExperimentError::config(config_path, format!("{m} (record `{}`)", r.name))
            })
        };
        let est = range(&d.estimation, "data.estimation")?;
        let failed = |e: String| ExperimentError::data(&data.files[i], e);
        records.push(r.part(r.name.clone(), est).map_err(failed)?);
        if let Some(spec) = &d.validation {
            let val = range(spec, "data.validation")?;
            let name = format!("{} (validation)", r.name);
            data.validation.push(r.part(name, val).map_err(failed)?);
            if let Some(note) = overlap_note(est, val) {
                data.notes.push(format!("record `{}`: {note}", r.name));
            }
        }
    }
    data.records = records;
    Ok(())
}

/// The measured records of `config`'s `[data]`: the files of `path` (fitted) and of
/// `validation_path` (predicted, returned apart), their files and the reader's notes.
fn measured(config: &Config, setup: &SetupSection, channels: &[Response]) -> Result<Measured> {
    let Some(d) = &config.data else {
        return Ok(Measured::default());
    };
    let mut specs: Vec<ColumnSpec> = Vec::new();
    if let Some(column) = &d.input {
        specs.push(ColumnSpec {
            role: setup.excitation.name().into(),
            key: "data.input".into(),
            column: column.clone(),
            scale: d.input_scale,
            scale_key: "data.input_scale".into(),
        });
    }
    for (i, r) in channels.iter().enumerate() {
        specs.push(ColumnSpec {
            role: r.channel_name(),
            key: format!("setup.responses[{i}].column"),
            column: r.column.clone().unwrap_or(crate::config::Column::Index(0)),
            scale: r.scale,
            scale_key: format!("setup.responses[{i}].scale"),
        });
    }
    let mut records = Vec::new();
    let mut files = Vec::new();
    let mut notes = Vec::new();
    for (i, file) in d.path.0.iter().enumerate() {
        records.push(read_record(
            config,
            d,
            &specs,
            file,
            &d.path.key(i),
            &mut notes,
        )?);
        files.push(config.sources.path(file));
    }
    let mut validation = Vec::new();
    if let Some(paths) = &d.validation_path {
        for (i, file) in paths.0.iter().enumerate() {
            let key = format!("data.validation_path[{i}]");
            validation.push(read_record(config, d, &specs, file, &key, &mut notes)?);
            files.push(config.sources.path(file));
        }
    }
    Ok(Measured {
        records,
        files,
        notes,
        validation,
    })
}

/// A `[data]` section's records: fitted, their files, the reader's notes, and the
/// validation records.
#[derive(Default)]
struct Measured {
    records: Vec<SetupRecord>,
    files: Vec<PathBuf>,
    notes: Vec<String>,
    validation: Vec<SetupRecord>,
}

/// One measured record: the columns of `specs` from `file` (config key `key`), the
/// reader's notes added to `notes`.
fn read_record(
    config: &Config,
    d: &crate::config::DataSection,
    specs: &[ColumnSpec],
    file: &Path,
    key: &str,
    notes: &mut Vec<String>,
) -> Result<SetupRecord> {
    let path = config.sources.path(file);
    let mut table = read_columns(d, &config.sources, &path, key, specs)?;
    let label = file.display();
    notes.extend(table.notes.drain(..).map(|n| format!("{label}: {n}")));
    let input = match d.input {
        Some(_) => {
            let samples = table.columns.remove(0);
            Some(
                Excitation::from_samples(table.time[0], table.dt, samples)
                    .map_err(|e| ExperimentError::data(&path, format!("data.input: {e}")))?,
            )
        }
        None => None,
    };
    let name = file
        .file_stem()
        .map_or_else(|| key.to_string(), |s| s.to_string_lossy().into());
    Ok(SetupRecord {
        name,
        input,
        t0: table.time[0],
        time: table.time.clone(),
        dt: table.dt,
        channels: table.columns,
        truth: None,
        frequency: None,
    })
}

fn synthetic(
    config: &Config,
    config_path: &Path,
    setup: &SetupSection,
    channels: &[Response],
    seed: u64,
) -> Result<Vec<SetupRecord>> {
    let missing =
        |what: &str| ExperimentError::config(config_path, format!("{what}: missing section"));
    let plant = config.plant.ok_or_else(|| missing("plant"))?;
    let time = config.time.ok_or_else(|| missing("time"))?;
    let sigmas = channel_sigmas(config, channels);
    let mut records = Vec::new();
    if setup.excitation == ExcitationKind::ImposedDisplacement {
        for (i, c) in setup.conditions.iter().enumerate() {
            let name = format!("condition-{}", i + 1);
            let clean = super::machine::stroke_record(&plant, c, setup.cycles, time.dt)
                .map_err(|e| ExperimentError::run("data", e))?;
            let mut record = noisy(name, clean, &sigmas, setup.input_sigma, seed)?;
            record.frequency = Some(c.frequency);
            records.push(record);
        }
        return Ok(records);
    }
    let n = time.samples();
    let input = crate::data::synthetic_input(config, config_path)?;
    let sensors: Vec<_> = channels.iter().map(super::fit::sensor).collect();
    let clean = msd_ident::records::simulate_channels(
        &plant.parameters(),
        plant.initial_state,
        super::fit::drive(setup.excitation),
        input.as_ref(),
        n,
        time.dt,
        &sensors,
    )
    .map_err(|e| ExperimentError::run("data", e))?;
    for r in 0..setup.records {
        let name = format!("record-{}", r + 1);
        let record = Clean {
            input: input.clone(),
            t0: time.start,
            dt: time.dt,
            channels: clean.clone(),
        };
        records.push(noisy(name, record, &sigmas, setup.input_sigma, seed)?);
    }
    Ok(records)
}

/// Each channel's noise level: its own `sigma`, else `[noise] sigma`, else 0.
pub(crate) fn channel_sigmas(config: &Config, channels: &[Response]) -> Vec<f64> {
    let default_sigma = config.noise.map_or(0.0, |n| n.sigma);
    channels
        .iter()
        .map(|r| r.sigma.unwrap_or(default_sigma))
        .collect()
}

/// A noise-free record.
pub(crate) struct Clean {
    pub input: Option<Excitation>,
    pub t0: f64,
    pub dt: f64,
    pub channels: Vec<Vec<f64>>,
}

/// Adds each channel's noise (stream `<record>/<channel index>`) and the drive's
/// (stream `<record>/input`).
fn noisy(
    name: String,
    clean: Clean,
    sigmas: &[f64],
    input_sigma: f64,
    seed: u64,
) -> Result<SetupRecord> {
    let noise = |stream: String, sigma: f64, n: usize| {
        gaussian_noise(seed, &stream, sigma, n).map_err(|e| ExperimentError::run("data", e))
    };
    let mut channels = Vec::with_capacity(clean.channels.len());
    for (j, (c, &sigma)) in clean.channels.iter().zip(sigmas).enumerate() {
        let e = noise(format!("{name}/{j}"), sigma, c.len())?;
        channels.push(c.iter().zip(e).map(|(y, e)| y + e).collect());
    }
    let input = match clean.input {
        Some(x) if input_sigma > 0.0 => {
            let e = noise(format!("{name}/input"), input_sigma, x.len())?;
            let samples = x.samples().iter().zip(e).map(|(u, e)| u + e).collect();
            Some(
                Excitation::from_samples(x.t0(), x.dt(), samples)
                    .map_err(|e| ExperimentError::run("data", e))?,
            )
        }
        other => other,
    };
    let n = clean.channels.first().map_or(0, Vec::len);
    Ok(SetupRecord {
        name,
        input,
        time: (0..n).map(|i| clean.t0 + i as f64 * clean.dt).collect(),
        t0: clean.t0,
        dt: clean.dt,
        channels,
        truth: Some(clean.channels),
        frequency: None,
    })
}
