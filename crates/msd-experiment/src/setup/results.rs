//! `results.json` of a setup run: `experiment` (as every run's), `verdict` (whether the
//! estimates can be trusted, and why), `setup` (excitation, responses), `estimate`
//! (`identifiable` and `<name>.value` / `.ci95` of each identifiable quantity), and what
//! each setup adds: `noise` (per channel), `noise_model` (the treatment behind the
//! intervals), `white_noise_estimate` (the white-noise intervals, when they differ),
//! `whiteness[]` (each channel's Ljung–Box and drive-correlation tests), `records[]`,
//! `leave_one_out` and `validation` (predictions of fresh data with their residual tests),
//! `free_decay.log_decrement`, `dynamometer.conditions[]` and `.laws[]`; `truth` for
//! synthetic data.

use super::report::estimates;
use super::{SetupFit, SetupOutcome};
use crate::config::{Plant, Response};
use crate::error::{ExperimentError, Result};
use crate::results::Header;
use msd_ident::Interval;
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::Duration;

#[derive(Serialize)]
struct Results<'a> {
    experiment: Header<'a>,
    command: &'a str,
    verdict: &'a crate::verdict::Verdict,
    setup: SetupInfo<'a>,
    estimate: Estimate,
    #[serde(skip_serializing_if = "Option::is_none")]
    noise: Option<&'a [msd_ident::records::ChannelNoise]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    noise_model: Option<&'a msd_ident::records::NoiseModelFit>,
    #[serde(skip_serializing_if = "Option::is_none")]
    white_noise_estimate: Option<&'a msd_ident::records::PlantIntervals>,
    #[serde(skip_serializing_if = "Option::is_none")]
    output_error_estimate: Option<&'a msd_ident::records::PlantIntervals>,
    #[serde(skip_serializing_if = "Option::is_none")]
    whiteness: Option<&'a [msd_ident::records::ResidualWhiteness]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    records: Option<&'a [msd_ident::records::RecordFit]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    leave_one_out: Option<&'a [msd_ident::records::LeftOut]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    validation: Option<&'a msd_ident::records::RecordsValidation>,
    #[serde(skip_serializing_if = "Option::is_none")]
    free_decay: Option<FreeDecaySection<'a>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    dynamometer: Option<&'a msd_ident::dynamometer::Dynamometer>,
    #[serde(skip_serializing_if = "Option::is_none")]
    any_stroke: Option<&'a super::stroke::StrokeFit>,
    #[serde(skip_serializing_if = "Option::is_none")]
    truth: Option<Truth<'a>>,
    timings_ms: BTreeMap<&'static str, f64>,
}

#[derive(Serialize)]
struct SetupInfo<'a> {
    excitation: &'static str,
    responses: &'a [Response],
    records: usize,
    files: Vec<String>,
    known_mass: Option<f64>,
    known_stiffness: Option<f64>,
}

#[derive(Serialize)]
struct Estimate {
    identifiable: Vec<&'static str>,
    #[serde(flatten)]
    quantities: BTreeMap<&'static str, Interval>,
    #[serde(skip_serializing_if = "Option::is_none")]
    note: Option<String>,
}

#[derive(Serialize)]
struct FreeDecaySection<'a> {
    log_decrement: f64,
    classroom: &'a msd_ident::free_decay::ClassroomEstimates,
}

#[derive(Serialize)]
struct Truth<'a> {
    #[serde(flatten)]
    plant: &'a Plant,
    natural_frequency_hz: f64,
    damping_ratio: f64,
}

/// The `results.json` value of `o`.
pub(crate) fn to_json(
    o: &SetupOutcome,
    extra: &[(&'static str, Duration)],
    total: Duration,
) -> Result<serde_json::Value> {
    let rows = estimates(o);
    let (noise, records, leave_one_out, free_decay, dynamometer, note) = match &o.fit {
        SetupFit::Records { fit, classroom } => (
            Some(fit.noise.as_slice()),
            Some(fit.records.as_slice()),
            fit.leave_one_out.as_deref(),
            classroom.as_deref().map(|c| FreeDecaySection {
                log_decrement: c.log_decrement,
                classroom: c,
            }),
            None,
            fit.plant.note.clone(),
        ),
        SetupFit::Machine(m) => (None, None, None, None, Some(m.as_ref()), None),
        SetupFit::Stroke(_) => (None, None, None, None, None, None),
    };
    let records_fit = match &o.fit {
        SetupFit::Records { fit, .. } => Some(fit.as_ref()),
        SetupFit::Machine(_) | SetupFit::Stroke(_) => None,
    };
    let any_stroke = match &o.fit {
        SetupFit::Stroke(f) => Some(f.as_ref()),
        _ => None,
    };
    let timings = crate::results::timings_ms(&o.timings, extra, total);
    let setup = &o.data.setup;
    let results = Results {
        experiment: Header::new(
            &o.config,
            &o.config_path,
            if o.data.files.is_empty() {
                "synthetic"
            } else {
                "measured"
            },
            o.seed,
            None,
        ),
        command: &o.command,
        verdict: &o.verdict,
        setup: SetupInfo {
            excitation: setup.excitation.name(),
            responses: &o.data.channels,
            records: o.data.records.len(),
            files: o
                .data
                .files
                .iter()
                .map(|f| f.display().to_string())
                .collect(),
            known_mass: setup.known_mass,
            known_stiffness: setup.known_stiffness,
        },
        estimate: Estimate {
            identifiable: rows.iter().map(|r| r.0).collect(),
            quantities: rows.iter().map(|r| (r.0, r.2)).collect(),
            note,
        },
        noise,
        noise_model: records_fit.map(|f| &f.noise_model),
        white_noise_estimate: records_fit.and_then(|f| f.white_noise_plant.as_ref()),
        output_error_estimate: records_fit.and_then(|f| f.output_error_plant.as_ref()),
        whiteness: records_fit.map(|f| f.whiteness.as_slice()),
        records,
        leave_one_out,
        validation: records_fit.and_then(|f| f.validation.as_ref()),
        free_decay,
        dynamometer,
        any_stroke,
        truth: o.data.truth.as_ref().map(|p| Truth {
            plant: p,
            natural_frequency_hz: p.parameters().natural_frequency_hz(),
            damping_ratio: p.parameters().damping_ratio(),
        }),
        timings_ms: timings,
    };
    serde_json::to_value(&results).map_err(|e| ExperimentError::run("write", e))
}
