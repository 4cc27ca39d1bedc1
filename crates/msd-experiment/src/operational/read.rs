//! An output-only record from its file: a NumPy `.npy` array (samples × channels) with
//! pyOMA's `channel_dofs.txt` and `setup_info.txt`, or a CSV file with named channels;
//! or simulated (a shear building). Dead channels are left out or refused, as asked.

use crate::config::{
    Column, DataSection, DeadChannels, OperationalSection, OutputChannelSection, Paths, Range,
    RecordSource, SimulatedBuilding,
};
use crate::data::csv::{ColumnSpec, read_columns};
use crate::error::{ExperimentError, Result};
use crate::sources::Sources;
use msd_modal::{Dof, OutputRecord, ShearBuilding, direction_from_angles};
use msd_signal::{Channel, Quantity, Recording};
use std::path::{Path, PathBuf};

/// The record to analyse, the channels left out (name and why) and, for a simulated
/// building, the true modes (fn, shape over the floors).
pub(crate) struct Loaded {
    pub record: OutputRecord,
    pub left_out: Vec<(String, String)>,
    pub truth: Option<Vec<(f64, Vec<f64>)>>,
    pub files: Vec<PathBuf>,
}

/// Loads the section's record (simulated with `seed`).
pub(crate) fn load(section: &OperationalSection, sources: &Sources, seed: u64) -> Result<Loaded> {
    if let Some(b) = &section.simulate {
        return simulate(b, seed);
    }
    let Some(source) = &section.record else {
        return Err(ExperimentError::config(
            sources.config_file(),
            "operational: no record and no simulate",
        ));
    };
    load_source(source, section, sources)
}

/// Loads every `[[operational.records]]` entry, in order.
pub(crate) fn load_records(section: &OperationalSection, sources: &Sources) -> Result<Vec<Loaded>> {
    section
        .records
        .iter()
        .map(|source| load_source(source, section, sources))
        .collect()
}

/// One record file with the section's channels, dead channels handled.
fn load_source(
    source: &RecordSource,
    section: &OperationalSection,
    sources: &Sources,
) -> Result<Loaded> {
    let csv = source
        .path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    let (record, files) = if csv {
        (
            read_csv(source, &section.channels, sources)?,
            vec![sources.path(&source.path)],
        )
    } else {
        read_npy(source, &section.channels, sources)?
    };
    let (record, left_out) = without_dead(record, section.dead_channels, &source.path)?;
    Ok(Loaded {
        record,
        left_out,
        truth: None,
        files,
    })
}

fn simulate(b: &SimulatedBuilding, seed: u64) -> Result<Loaded> {
    let building = ShearBuilding {
        masses: b.masses.clone(),
        stiffnesses: b.stiffnesses.clone(),
        damping_ratio: b.damping_ratio,
    };
    let noise = msd_signal::gaussian_noise(
        seed,
        "operational/simulate",
        1.0,
        b.samples * (2 * b.masses.len() + 1),
    )
    .map_err(|e| ExperimentError::run("data", e))?;
    let mut draws = noise.into_iter();
    let record = building
        .ambient_record(b.sample_rate_hz, b.samples, b.noise, || {
            draws.next().unwrap_or(0.0)
        })
        .map_err(|e| ExperimentError::run("data", e))?;
    let truth = building
        .modes()
        .map_err(|e| ExperimentError::run("data", e))?;
    Ok(Loaded {
        record,
        left_out: Vec::new(),
        truth: Some(truth),
        files: Vec::new(),
    })
}

/// Channels that are NaN somewhere or constant throughout, left out (named, with the
/// reason) or refused; the references renumbered.
fn without_dead(
    record: OutputRecord,
    dead: DeadChannels,
    path: &Path,
) -> Result<(OutputRecord, Vec<(String, String)>)> {
    let mut kept = Vec::new();
    let mut references = Vec::new();
    let mut left_out = Vec::new();
    let named = record.reference_indices();
    for (i, channel) in record.recording.channels.into_iter().enumerate() {
        let why = if let Some(t) = channel.samples.iter().position(|v| !v.is_finite()) {
            Some(format!("sample {t} is {}", channel.samples[t]))
        } else if channel.samples.iter().all(|&v| v == channel.samples[0]) {
            Some(format!(
                "constant ({}) throughout: a dead sensor",
                channel.samples[0]
            ))
        } else {
            None
        };
        match (why, dead) {
            (Some(why), DeadChannels::Refuse) => {
                return Err(ExperimentError::data(
                    path,
                    format!(
                        "channel {}: {why} (operational.dead_channels = \"refuse\"; \"leave_out\" analyses the others)",
                        channel.name
                    ),
                ));
            }
            (Some(why), DeadChannels::LeaveOut) => left_out.push((channel.name, why)),
            (None, _) => {
                if named.contains(&i) {
                    references.push(kept.len());
                }
                kept.push(channel);
            }
        }
    }
    if references.is_empty() && !kept.is_empty() {
        return Err(ExperimentError::data(
            path,
            "every reference channel is dead: name others (reference = true)",
        ));
    }
    Ok((
        OutputRecord {
            recording: Recording {
                channels: kept,
                ..record.recording
            },
            references,
        },
        left_out,
    ))
}

/// A `.npy` record and its channel and setup files (or the channels given).
fn read_npy(
    source: &RecordSource,
    given: &[OutputChannelSection],
    sources: &Sources,
) -> Result<(OutputRecord, Vec<PathBuf>)> {
    let path = sources.path(&source.path);
    let bytes = sources.bytes(&path, "operational.record.path")?;
    let columns = npy_columns(&bytes).map_err(|why| ExperimentError::data(&path, why))?;
    let beside = |name: &str| source.path.parent().unwrap_or(Path::new("")).join(name);
    let mut files = vec![path.clone()];
    let (channels, references, fs) = if given.is_empty() {
        let dofs_path = source
            .channel_dofs
            .clone()
            .unwrap_or_else(|| beside("channel_dofs.txt"));
        let info_path = source
            .setup_info
            .clone()
            .unwrap_or_else(|| beside("setup_info.txt"));
        let dofs_text = text(sources, &dofs_path, "operational.record.channel_dofs")?;
        let info_text = text(sources, &info_path, "operational.record.setup_info")?;
        files.extend([sources.path(&dofs_path), sources.path(&info_path)]);
        let dofs = super::pyoma::channel_dofs(&dofs_text)
            .map_err(|why| ExperimentError::data(sources.path(&dofs_path), why))?;
        let info = super::pyoma::setup_info(&info_text)
            .map_err(|why| ExperimentError::data(sources.path(&info_path), why))?;
        let mut channels = Vec::new();
        let mut references = Vec::new();
        for d in dofs.iter().filter(|d| !info.deleted.contains(&d.channel)) {
            let samples = columns.get(d.channel).cloned().ok_or_else(|| {
                ExperimentError::data(
                    &path,
                    format!(
                        "channel {} of channel_dofs.txt: the array has {} columns",
                        d.channel,
                        columns.len()
                    ),
                )
            })?;
            if info.references.contains(&d.channel) {
                references.push(channels.len());
            }
            channels.push(oriented(
                d.name.clone(),
                d.node,
                direction_from_angles(d.azimuth_deg, d.elevation_deg),
                info.quantity(d.channel),
                samples,
            ));
        }
        let present: Vec<usize> = dofs
            .iter()
            .filter(|d| !info.deleted.contains(&d.channel))
            .map(|d| d.channel)
            .collect();
        if let Some(r) = info.references.iter().find(|r| !present.contains(r)) {
            return Err(ExperimentError::data(
                sources.path(&info_path),
                format!(
                    "Reference Channels: {r} is not a channel of the record (channels {present:?} in channel_dofs.txt, less the deleted ones)"
                ),
            ));
        }
        (channels, references, info.sample_rate_hz)
    } else {
        let (channels, references) = picked(given, &columns, &path)?;
        (channels, references, 0.0)
    };
    let fs = source.sample_rate_hz.unwrap_or(fs);
    if !(fs.is_finite() && fs > 0.0) {
        return Err(ExperimentError::data(
            &path,
            "no sampling rate: give operational.record.sample_rate_hz (or a setup_info.txt)",
        ));
    }
    Ok((
        OutputRecord::new(fs, channels).with_references(references),
        files,
    ))
}

pub(crate) fn text(sources: &Sources, path: &Path, key: &str) -> Result<String> {
    let resolved = sources.path(path);
    let bytes = sources.bytes(&resolved, key)?;
    String::from_utf8(bytes)
        .map_err(|e| ExperimentError::data(&resolved, format!("not UTF-8 text: {e}")))
}

/// The columns of a 2-D float array (samples × channels), in either memory order.
fn npy_columns(bytes: &[u8]) -> std::result::Result<Vec<Vec<f64>>, String> {
    let npy = npyz::NpyFile::new(bytes).map_err(|e| format!("not a NumPy .npy array: {e}"))?;
    let shape = npy.shape().to_vec();
    let [rows, cols] = shape[..] else {
        return Err(format!(
            "an array of shape {shape:?}: expected two dimensions (samples × channels)"
        ));
    };
    let (rows, cols) = (rows as usize, cols as usize);
    let fortran = npy.order() == npyz::Order::Fortran;
    let values: Vec<f64> = match npy.dtype() {
        npyz::DType::Plain(t) if t.type_char() == npyz::TypeChar::Float && t.size_field() == 4 => {
            npy.into_vec::<f32>()
                .map_err(|e| e.to_string())?
                .into_iter()
                .map(f64::from)
                .collect()
        }
        _ => npy
            .into_vec::<f64>()
            .map_err(|e| format!("{e}: expected float64 (or float32) values"))?,
    };
    Ok((0..cols)
        .map(|c| {
            (0..rows)
                .map(|r| values[if fortran { c * rows + r } else { r * cols + c }])
                .collect()
        })
        .collect())
}

/// The channels named in the config, from the array's columns (by index).
fn picked(
    given: &[OutputChannelSection],
    columns: &[Vec<f64>],
    path: &Path,
) -> Result<(Vec<Channel>, Vec<usize>)> {
    let mut channels = Vec::new();
    for (i, c) in given.iter().enumerate() {
        let Column::Index(k) = c.column else {
            return Err(ExperimentError::data(
                path,
                format!(
                    "operational.channels[{i}].column = {}: a .npy array's columns have no names: give the 0-based index",
                    c.column
                ),
            ));
        };
        let samples = columns.get(k).ok_or_else(|| {
            ExperimentError::data(
                path,
                format!(
                    "operational.channels[{i}].column = {k}: the array has {} columns",
                    columns.len()
                ),
            )
        })?;
        channels.push(channel_of(c, samples.iter().map(|v| v * c.scale).collect()));
    }
    Ok((channels, references_of(given)))
}

/// A CSV record's channels.
fn read_csv(
    source: &RecordSource,
    given: &[OutputChannelSection],
    sources: &Sources,
) -> Result<OutputRecord> {
    let d = DataSection {
        path: Paths(vec![source.path.clone()]),
        input: None,
        output: None,
        time: source.time.clone(),
        sample_rate: source.sample_rate_hz,
        delimiter: source.delimiter,
        decimal: source.decimal,
        header: source.header,
        skip_lines: source.skip_lines,
        missing: source.missing,
        input_unit: String::new(),
        output_unit: String::new(),
        input_scale: 1.0,
        output_scale: 1.0,
        preprocessing: Vec::new(),
        estimation: Range::default(),
        validation: None,
        validation_path: None,
    };
    let specs: Vec<ColumnSpec> = given
        .iter()
        .enumerate()
        .map(|(i, c)| ColumnSpec {
            role: "channel".into(),
            key: format!("operational.channels[{i}].column"),
            column: c.column.clone(),
            scale: c.scale,
            scale_key: format!("operational.channels[{i}].scale"),
        })
        .collect();
    let table = read_columns(
        &d,
        sources,
        &sources.path(&source.path),
        "operational.record.path",
        &specs,
    )?;
    let channels = given
        .iter()
        .zip(table.columns)
        .map(|(c, samples)| channel_of(c, samples))
        .collect();
    let name = source.path.display().to_string();
    Ok(OutputRecord {
        recording: Recording {
            channels,
            ..Recording::new(name, 0.0, table.dt)
        },
        references: references_of(given),
    })
}

fn references_of(given: &[OutputChannelSection]) -> Vec<usize> {
    (0..given.len()).filter(|&i| given[i].reference).collect()
}

fn channel_of(c: &OutputChannelSection, samples: Vec<f64>) -> Channel {
    let name = match &c.column {
        Column::Name(n) => n.clone(),
        Column::Index(i) => format!("column {i}"),
    };
    match (c.direction, c.azimuth_deg, c.elevation_deg) {
        (_, Some(az), Some(el)) => oriented(
            name,
            c.node,
            direction_from_angles(az, el),
            c.quantity,
            samples,
        ),
        (direction, _, _) => Channel::new(name, c.quantity, samples).at(Dof {
            node: c.node,
            direction: direction.unwrap_or(1),
        }),
    }
}

/// A channel along `unit`: its DOF the axis it lies on (±1, ±2, ±3), else direction 0
/// with the oblique vector kept.
fn oriented(
    name: String,
    node: u32,
    unit: [f64; 3],
    quantity: Quantity,
    samples: Vec<f64>,
) -> Channel {
    let axis = (0..3).find(|&a| unit[a].abs() > 1.0 - 1e-9);
    let direction = axis.map_or(0, |a| (a as i32 + 1) * unit[a].signum() as i32);
    Channel {
        direction: axis.is_none().then_some(unit),
        ..Channel::new(name, quantity, samples).at(Dof { node, direction })
    }
}
