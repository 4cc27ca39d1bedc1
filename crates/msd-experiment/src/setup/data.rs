//! The records of a `[setup]` run: generated from the synthetic plant (every channel
//! from the exact simulation, each with its own noise stream) or read from the measured
//! files (one record per file).

use crate::config::DataSection;
use crate::config::{Config, ExcitationKind, Plant, Response, SetupSection};
use crate::data::{ColumnSpec, overlap_note, read_columns, resolve_range};
use crate::error::{ExperimentError, Result};
use msd_signal::{Channel, Recording, gaussian_noise};
use std::path::{Path, PathBuf};

/// One record of a setup: the run as every engine reads it, with what only a synthetic
/// record knows.
#[derive(Debug, Clone, PartialEq)]
pub struct SetupRecord {
    /// The run on its uniform grid, in SI units: the drive as measured (a force, the
    /// base's motion or the imposed stroke, named as the record's file names it; no input
    /// for a free decay) and the response channels, in the order of `setup.responses`.
    /// Named `record-1`, … (synthetic) or after the file's stem (measured).
    pub recording: Recording,
    /// The noise-free channels (synthetic only).
    pub truth: Option<Vec<Vec<f64>>>,
    /// The stroke's frequency, Hz (synthetic test machine only; measured ones are
    /// estimated from the stroke).
    pub frequency: Option<f64>,
}

impl SetupRecord {
    /// Samples `[a, b)` of the record (a range [`resolve_range`] checked), named `name`.
    fn part(&self, name: String, [a, b]: [usize; 2]) -> Self {
        let recording = Recording {
            name,
            ..self.recording.slice(a, b)
        };
        let truth = (self.truth.as_ref()).map(|t| t.iter().map(|c| c[a..b].to_vec()).collect());
        Self {
            recording,
            truth,
            frequency: self.frequency,
        }
    }

    /// The record's name.
    pub fn name(&self) -> &str {
        &self.recording.name
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.recording.len()
    }

    /// Whether the record holds no sample.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The drive's samples (empty for a free decay).
    pub fn drive(&self) -> &[f64] {
        self.recording.input()
    }

    /// Response channel `i`'s samples (in the order of `setup.responses`).
    pub fn channel(&self, i: usize) -> &[f64] {
        &self.recording.channels[i].samples
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
    for r in &data.records {
        let grid = (r.len(), r.recording.t0, r.recording.dt);
        let range = |spec, key| {
            resolve_range(spec, grid, r.len(), 1, key).map_err(|m| {
                ExperimentError::config(config_path, format!("{m} (record `{}`)", r.name()))
            })
        };
        let est = range(&d.estimation, "data.estimation")?;
        records.push(r.part(r.name().to_string(), est));
        if let Some(spec) = &d.validation {
            let val = range(spec, "data.validation")?;
            let name = format!("{} (validation)", r.name());
            data.validation.push(r.part(name, val));
            if let Some(note) = overlap_note(est, val) {
                data.notes.push(format!("record `{}`: {note}", r.name()));
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
    let layout = Layout {
        specs,
        excitation: setup.excitation,
        channels,
    };
    let mut records = Vec::new();
    let mut files = Vec::new();
    let mut notes = Vec::new();
    for (i, file) in d.path.0.iter().enumerate() {
        records.push(read_record(
            config,
            d,
            &layout,
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
            validation.push(read_record(config, d, &layout, file, &key, &mut notes)?);
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

/// What a `[data]` file's record is read as: its columns (the drive's first, when
/// measured), the drive and the channels' descriptions.
struct Layout<'a> {
    specs: Vec<ColumnSpec>,
    excitation: ExcitationKind,
    channels: &'a [Response],
}

/// One measured record: the columns of `layout` from `file` (config key `key`), the
/// reader's notes added to `notes`.
fn read_record(
    config: &Config,
    d: &crate::config::DataSection,
    layout: &Layout<'_>,
    file: &Path,
    key: &str,
    notes: &mut Vec<String>,
) -> Result<SetupRecord> {
    let path = config.sources.path(file);
    let mut table = read_columns(d, &config.sources, &path, key, &layout.specs)?;
    let label = file.display();
    notes.extend(table.notes.drain(..).map(|n| format!("{label}: {n}")));
    let drive = d.input.as_ref().map(|_| table.columns.remove(0));
    let name = file
        .file_stem()
        .map_or_else(|| key.to_string(), |s| s.to_string_lossy().into());
    let recording = run_recording(
        name,
        (table.time[0], table.dt),
        layout.excitation,
        (drive, d.input_scale),
        table.columns,
        layout.channels,
    );
    recording
        .validate()
        .map_err(|e| ExperimentError::data(&path, e.to_string()))?;
    Ok(SetupRecord {
        recording,
        truth: None,
        frequency: None,
    })
}

/// The recording of one run: `drive` (none for a free decay) as the setup's measured
/// input, `drive_scale` the factor that took the file's numbers to it, and `samples` as
/// the channels `responses` describe.
fn run_recording(
    name: String,
    (t0, dt): (f64, f64),
    excitation: ExcitationKind,
    (drive, drive_scale): (Option<Vec<f64>>, f64),
    samples: Vec<Vec<f64>>,
    responses: &[Response],
) -> Recording {
    let mut recording = Recording::new(name, t0, dt);
    if let (Some(samples), Some(quantity)) = (drive, excitation.quantity()) {
        let input = Channel::new(excitation.channel_name(), quantity, samples);
        recording.inputs.push(Channel {
            scale: drive_scale,
            ..input
        });
    }
    recording.channels = (samples.into_iter().zip(responses))
        .map(|(samples, r)| Channel {
            scale: r.scale,
            ..Channel::new(r.channel_name(), r.quantity, samples).in_frame(r.frame)
        })
        .collect();
    recording
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
            let mut record = noisy(name, clean, setup, (channels, &sigmas), seed)?;
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
            input: input.as_ref().map(|x| x.samples().to_vec()),
            t0: time.start,
            dt: time.dt,
            channels: clean.clone(),
        };
        records.push(noisy(name, record, setup, (channels, &sigmas), seed)?);
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
    /// The drive's samples (none for a free decay).
    pub input: Option<Vec<f64>>,
    pub t0: f64,
    pub dt: f64,
    pub channels: Vec<Vec<f64>>,
}

/// Adds each channel's noise (stream `<record>/<channel index>`, of level `sigmas`)
/// and the drive's (stream `<record>/input`); the channels as `channels` describe them.
fn noisy(
    name: String,
    clean: Clean,
    setup: &SetupSection,
    (channels, sigmas): (&[Response], &[f64]),
    seed: u64,
) -> Result<SetupRecord> {
    let noise = |stream: String, sigma: f64, n: usize| {
        gaussian_noise(seed, &stream, sigma, n).map_err(|e| ExperimentError::run("data", e))
    };
    let mut noisy = Vec::with_capacity(clean.channels.len());
    for (j, (c, &sigma)) in clean.channels.iter().zip(sigmas).enumerate() {
        let e = noise(format!("{name}/{j}"), sigma, c.len())?;
        noisy.push(c.iter().zip(e).map(|(y, e)| y + e).collect());
    }
    let input = match clean.input {
        Some(x) if setup.input_sigma > 0.0 => {
            let e = noise(format!("{name}/input"), setup.input_sigma, x.len())?;
            Some(x.iter().zip(e).map(|(u, e)| u + e).collect())
        }
        other => other,
    };
    let recording = run_recording(
        name,
        (clean.t0, clean.dt),
        setup.excitation,
        (input, 1.0),
        noisy,
        channels,
    );
    recording
        .validate()
        .map_err(|e| ExperimentError::run("data", e))?;
    Ok(SetupRecord {
        recording,
        truth: Some(clean.channels),
        frequency: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use msd_signal::{Frame, Quantity};

    fn response(quantity: Quantity, frame: Frame) -> Response {
        Response {
            quantity,
            frame,
            sigma: None,
            column: None,
            scale: 9.80665,
            unit: Some("g".into()),
            name: None,
        }
    }

    /// Every drive's record is one the engine of its kind reads: msd-ident's records
    /// under the setup's drive, the test machine's inverse dynamics as stroke and
    /// force; the drive's scale and each channel's name, frame and scale kept.
    #[test]
    fn each_drives_recording_is_what_its_engine_reads() {
        let samples = |k: f64| {
            (0..64)
                .map(|i| (0.3 * k * i as f64).sin())
                .collect::<Vec<f64>>()
        };
        let cases = [
            (
                ExcitationKind::Force,
                Quantity::Acceleration,
                Frame::Absolute,
            ),
            (
                ExcitationKind::BaseAcceleration,
                Quantity::Displacement,
                Frame::Relative,
            ),
            (
                ExcitationKind::BaseDisplacement,
                Quantity::Displacement,
                Frame::Absolute,
            ),
            (ExcitationKind::None, Quantity::Velocity, Frame::Absolute),
            (
                ExcitationKind::ImposedDisplacement,
                Quantity::Force,
                Frame::Absolute,
            ),
        ];
        for (excitation, quantity, frame) in cases {
            let responses = [response(quantity, frame)];
            let drive = excitation.quantity().map(|_| samples(1.0));
            let r = run_recording(
                "run".into(),
                (0.5, 1e-3),
                excitation,
                (drive, 2.5),
                vec![samples(2.0)],
                &responses,
            );
            r.validate().expect("a valid recording");
            let channel = &r.channels[0];
            assert_eq!(
                (channel.name.as_str(), channel.frame, channel.scale),
                (responses[0].channel_name().as_str(), frame, 9.80665)
            );
            assert_eq!(
                r.inputs.iter().map(|c| c.scale).collect::<Vec<_>>(),
                match excitation {
                    ExcitationKind::None => vec![],
                    _ => vec![2.5],
                }
            );
            if excitation == ExcitationKind::ImposedDisplacement {
                let (stroke, force) =
                    msd_ident::dynamometer::stroke_and_force(&r).expect("stroke and force");
                assert_eq!((stroke, force), (&samples(1.0)[..], &samples(2.0)[..]));
                assert_eq!(r.inputs[0].name, "stroke");
            } else {
                let record =
                    msd_ident::Record::from_recording(&r, super::super::fit::drive(excitation))
                        .unwrap_or_else(|e| panic!("{excitation:?}: {e}"));
                assert_eq!(record.excitation.samples().len(), 64);
                assert_eq!(
                    r.input(),
                    excitation.quantity().map_or(vec![], |_| samples(1.0))
                );
            }
        }
    }
}
