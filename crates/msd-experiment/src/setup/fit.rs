//! The fit of a setup's records: msd-ident's joint fit of records and channels, or the
//! test machine's analysis.

use super::{SetupData, SetupOutcome, SetupRecord};
use crate::config::{Config, ExcitationKind, Frame, Response, SetupSection};
use crate::error::{ExperimentError, Result};
use crate::table::Table;
use msd_ident::records::NoiseModel;
use msd_ident::{
    KnownParameter, Record, RecordsFit, RecordsOptions, ResponseQuantity,
    dynamometer::{Condition, Dynamometer, DynamometerOptions, dynamometer},
    fit_records,
    free_decay::ClassroomEstimates,
    records::validate_records,
};
use std::path::{Path, PathBuf};

/// What a setup run estimated.
#[derive(Debug, Clone)]
pub enum SetupFit {
    /// Shared parameters over every record and channel.
    Records {
        /// The joint fit.
        fit: Box<RecordsFit>,
        /// A free decay's classroom estimates (logarithmic decrement, zero crossings) on
        /// the first record's first channel, for comparison with the fit.
        classroom: Option<Box<ClassroomEstimates>>,
    },
    /// A damper test machine's conditions and damping laws.
    Machine(Box<Dynamometer>),
    /// A test machine under any stroke: inverse dynamics.
    Stroke(Box<super::stroke::StrokeFit>),
}

/// Fits the records of `data` as `config` asks.
pub(crate) fn fit(config: &Config, config_path: &Path, data: &SetupData) -> Result<SetupFit> {
    let setup = &data.setup;
    // The data or the setup cannot give what is asked (a constant channel, records of
    // different rates, a record that does not decay): the user's to fix, exit 2. An
    // optimiser that fails on good data is the run's failure.
    let refused = |e: msd_ident::IdentError| match e {
        msd_ident::IdentError::EstimationFailed { reason } => {
            ExperimentError::run("estimation", reason)
        }
        // A measured record at fault is named by its file.
        msd_ident::IdentError::InvalidRecord { ref record, .. } => {
            let file = data
                .records
                .iter()
                .position(|r| r.name() == record)
                .and_then(|i| data.files.get(i));
            ExperimentError::data(
                file.map_or(config_path, PathBuf::as_path),
                format!("setup: {e}"),
            )
        }
        other if data.files.is_empty() => {
            ExperimentError::data(config_path, format!("setup: {other}"))
        }
        other => ExperimentError::data(
            config_path,
            format!(
                "setup: {other} (the records of {})",
                list_files(&data.files)
            ),
        ),
    };
    if setup.excitation == ExcitationKind::ImposedDisplacement
        && super::stroke::any_stroke(setup, data, config.data.is_some())
    {
        let result = super::stroke::fit(data).map_err(refused)?;
        return Ok(SetupFit::Stroke(Box::new(result)));
    }
    if setup.excitation == ExcitationKind::ImposedDisplacement {
        let result =
            dynamometer(&machine_conditions(data), &machine_options(setup)).map_err(refused)?;
        return Ok(SetupFit::Machine(Box::new(result)));
    }
    let records = ident_records(&data.records, setup.excitation)?;
    let mut options = records_options(config, setup);
    if !data.validation.is_empty() {
        options.hold_out = 0.0;
    }
    let mut fit = fit_records(&records, &options).map_err(refused)?;
    if !data.validation.is_empty() {
        let fresh = ident_records(&data.validation, setup.excitation)?;
        let validation = validate_records(&fit, &fresh, &options).map_err(refused)?;
        fit.validation = Some(validation);
    }
    // What the reader found (metadata, a units line, gaps filled) is said with the fit.
    fit.notes.extend(data.notes.iter().cloned());
    // The classroom's reading of the decay beside the fit (not a second fit of it).
    let classroom = match (setup.excitation, data.records.first()) {
        (ExcitationKind::None, Some(r)) => {
            ClassroomEstimates::from_record(r.recording.dt, r.channel(0))
                .ok()
                .map(Box::new)
        }
        _ => None,
    };
    Ok(SetupFit::Records {
        fit: Box::new(fit),
        classroom,
    })
}

/// Up to three file names, then how many more.
fn list_files(files: &[PathBuf]) -> String {
    let names: Vec<String> = files
        .iter()
        .take(3)
        .map(|f| f.display().to_string())
        .collect();
    match files.len() {
        n if n > 3 => format!("{} and {} more", names.join(", "), n - 3),
        _ => names.join(", "),
    }
}

/// The joint fit's options of a `[setup]` config: its drive, known mass or stiffness
/// and `[estimation]` (a free decay always estimates its initial state).
pub(crate) fn records_options(config: &Config, setup: &SetupSection) -> RecordsOptions {
    let excitation = setup.excitation;
    let known = match (setup.known_mass, setup.known_stiffness) {
        (Some(m), _) => KnownParameter::Mass(m),
        (None, Some(k)) => KnownParameter::Stiffness(k),
        _ => KnownParameter::None,
    };
    RecordsOptions {
        drive: drive(excitation),
        known,
        initial_guess: config.estimation.initial_guess,
        estimate_initial_state: config.estimation.estimate_initial_state
            || excitation == ExcitationKind::None,
        estimate_offset: config.estimation.estimate_offset,
        noise_model: noise_model(config, setup),
        residuals: config.residuals,
        hold_out: setup.hold_out.unwrap_or(RecordsOptions::default().hold_out),
        ..RecordsOptions::default()
    }
}

/// `[setup] noise_model`, or by default the drive's noise model on measured data and on
/// a synthetic drive with noise, white on a synthetic drive (exact by construction).
fn noise_model(config: &Config, setup: &SetupSection) -> NoiseModel {
    match setup.noise_model {
        Some(chosen) => chosen,
        None if config.data.is_none() && setup.input_sigma == 0.0 => NoiseModel::White,
        None => NoiseModel::InputNoise,
    }
}

/// The test machine's conditions: each record's stroke and force.
pub(crate) fn machine_conditions(data: &SetupData) -> Vec<Condition> {
    data.records
        .iter()
        .map(|r| Condition {
            recording: r.recording.clone(),
            frequency_hz: r.frequency,
        })
        .collect()
}

/// The test machine's analysis options of a `[setup]` config.
pub(crate) fn machine_options(setup: &crate::config::SetupSection) -> DynamometerOptions {
    DynamometerOptions {
        known_mass: setup.known_mass,
        ..DynamometerOptions::default()
    }
}

pub(crate) fn drive(kind: ExcitationKind) -> msd_ident::Drive {
    match kind {
        ExcitationKind::Force | ExcitationKind::ImposedDisplacement => msd_ident::Drive::Force,
        ExcitationKind::BaseAcceleration => msd_ident::Drive::BaseAcceleration,
        ExcitationKind::BaseDisplacement => msd_ident::Drive::BaseDisplacement,
        ExcitationKind::None => msd_ident::Drive::None,
    }
}

/// What a response measures and in which frame.
pub(crate) fn sensor(c: &Response) -> (ResponseQuantity, Frame) {
    let motion = c
        .quantity
        .motion()
        .unwrap_or(ResponseQuantity::Displacement);
    (motion, c.frame)
}

/// The records as msd-ident takes them under the setup's drive `excitation` (a free
/// decay's excitation is zero).
pub(crate) fn ident_records(
    records: &[SetupRecord],
    excitation: ExcitationKind,
) -> Result<Vec<Record>> {
    (records.iter())
        .map(|r| {
            Record::from_recording(&r.recording, drive(excitation))
                .map_err(|e| ExperimentError::run("estimation", e))
        })
        .collect()
}

/// One CSV file per record, `<record>.csv`: `t`, the drive (`force`,
/// `base_acceleration`, `base_displacement`, `stroke`), each channel by its name, and
/// the model's prediction of each as `model_<name>`.
pub(crate) fn record_files(o: &SetupOutcome) -> Vec<(String, String)> {
    let d = &o.data;
    let drive = d.setup.excitation.channel_name();
    d.records
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let mut t = Table::new();
            t.column("t", &r.recording.times());
            if let Some(x) = r.recording.inputs.first() {
                t.column(drive, &x.samples);
            }
            for (samples, c) in r.recording.responses().zip(&d.channels) {
                t.column(c.channel_name(), samples);
            }
            for (name, model) in models(o, i) {
                t.column(format!("model_{name}"), model);
            }
            (format!("{}.csv", r.name()), t.render())
        })
        .collect()
}

/// The model's prediction of each channel of record `i`, by channel name.
pub(crate) fn models(o: &SetupOutcome, i: usize) -> Vec<(String, &[f64])> {
    match &o.fit {
        SetupFit::Records { fit, .. } => fit.records[i]
            .channels
            .iter()
            .map(|c| (c.channel.clone(), c.model.as_slice()))
            .collect(),
        SetupFit::Machine(m) => {
            let best = &m.laws[m.best];
            vec![("force".to_string(), best.model_force[i].as_slice())]
        }
        SetupFit::Stroke(f) => f
            .predictions
            .get(i)
            .map(|p| ("force".to_string(), p.force.predicted.as_slice()))
            .into_iter()
            .collect(),
    }
}
