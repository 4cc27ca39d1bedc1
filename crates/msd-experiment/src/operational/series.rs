//! Several records of one structure in one `[operational]` run (`[[operational.records]]`):
//! each analysed alone by the chosen method, then combined by msd-modal's
//! [`merge_setups`] — setups with a roving sensor and shared references merged into
//! global shapes (PoSER), or the records of a monitored structure tracked from record to
//! record (every DOF shared). The report follows each mode over the records.

use super::read::{Loaded, load_records};
use super::{analyse, oma_error};
use crate::config::{Config, OperationalSection, Spec};
use crate::error::{ExperimentError, Result};
use crate::options::RunOptions;
use crate::progress::Progress;
use crate::verdict::{Finding, Verdict};
use msd_modal::{MergedFit, OmaFit, OutputRecord, Setup, merge_setups};
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// One record of a series, analysed.
#[derive(Debug, Clone)]
pub struct AnalysedRecord {
    /// The record file as the config names it.
    pub path: PathBuf,
    /// Its label: the config's, or its number from 1.
    pub label: String,
    /// The record analysed (dead channels left out).
    pub record: OutputRecord,
    /// The channels left out, each with why.
    pub left_out: Vec<(String, String)>,
    /// The files read.
    pub files: Vec<PathBuf>,
    /// Its modes.
    pub fit: OmaFit,
}

/// Everything a run over several records produced, in memory.
#[derive(Debug, Clone)]
pub struct SeriesOutcome {
    /// The config as read.
    pub config: Config,
    /// The config file as given.
    pub config_path: PathBuf,
    /// The command that ran it, for the report.
    pub command: String,
    /// Every record with its fit, in the config's order.
    pub records: Vec<AnalysedRecord>,
    /// The modes over the records: fn and ζ from the records that found each, shapes over
    /// every DOF, which record found which mode and how well its references agree.
    pub merged: MergedFit,
    /// The structure's geometry, where the config gives it.
    pub geometry: Option<super::Geometry>,
    /// Wall time of each stage, in order.
    pub timings: Vec<(&'static str, Duration)>,
    /// Whether the modes can be trusted, and why.
    pub verdict: Verdict,
}

/// Runs the `[[operational.records]]` of `config`.
pub fn run(
    spec: Spec<OperationalSection>,
    options: &RunOptions,
    progress: &Progress,
) -> Result<SeriesOutcome> {
    let Spec { config, section } = spec;
    let config_path = config.sources.config_file().to_path_buf();
    progress.stage("data");
    let t = Instant::now();
    let loaded = load_records(&section, &config.sources)?;
    let geometry = super::geometry::of(&section, &config.sources)?;
    let mut timings = vec![("data", t.elapsed())];
    progress.stage("estimation");
    let t = Instant::now();
    let mut records = Vec::with_capacity(loaded.len());
    for (k, (source, loaded)) in section.records.iter().zip(loaded).enumerate() {
        let Loaded {
            record,
            left_out,
            files,
            ..
        } = loaded;
        let path = config.sources.path(&source.path);
        let fit = analyse(&section, &record)
            .map_err(|e| oma_error(e, section.options_table(), &config_path, &path))?;
        records.push(AnalysedRecord {
            path: source.path.clone(),
            label: source.label.clone().unwrap_or_else(|| (k + 1).to_string()),
            record,
            left_out,
            files,
            fit,
        });
    }
    let setups: Vec<Setup<'_>> = records
        .iter()
        .map(|r| Setup {
            record: &r.record,
            fit: &r.fit,
        })
        .collect();
    let merged = merge_setups(&setups, section.merge_tolerance).map_err(|e| {
        ExperimentError::config(
            &config_path,
            format!("operational.records: the records cannot be combined: {e}"),
        )
    })?;
    timings.push(("estimation", t.elapsed()));
    let verdict = verdict(&records, &merged);
    Ok(SeriesOutcome {
        command: options
            .command
            .clone()
            .unwrap_or_else(|| "msd run".to_string()),
        config,
        config_path,
        records,
        merged,
        geometry,
        timings,
        verdict,
    })
}

/// The smallest MAC a mode's references show against the first record that found it,
/// over the records (`None` where one record alone found it).
pub(crate) fn lowest_reference_mac(merged: &MergedFit, mode: usize) -> Option<f64> {
    merged.reference_mac[mode]
        .iter()
        .flatten()
        .copied()
        .reduce(f64::min)
}

/// The verdict: every record gave modes, how many records found each mode, whether the
/// references agree (the rescaling and the tracking hold), dead channels.
fn verdict(records: &[AnalysedRecord], merged: &MergedFit) -> Verdict {
    let n = records.len();
    let mut findings = vec![Finding {
        checked: true,
        passed: !merged.modes.is_empty(),
        text: format!(
            "{} records analysed one by one ({}), {} modes over them",
            n,
            records
                .first()
                .map_or(String::new(), |r| r.fit.method.to_string()),
            merged.modes.len()
        ),
    }];
    let once: Vec<String> = (0..merged.modes.len())
        .filter(|&m| merged.found[m].iter().flatten().count() == 1)
        .map(|m| format!("{:.4} Hz", merged.modes[m].natural_frequency_hz.value))
        .collect();
    if !once.is_empty() {
        findings.push(Finding {
            checked: true,
            passed: false,
            text: format!(
                "found in one record only (its interval is that record's own; no other confirms it): {}",
                once.join(", ")
            ),
        });
    }
    let poor: Vec<String> = (0..merged.modes.len())
        .filter_map(|m| {
            let mac = lowest_reference_mac(merged, m)?;
            (mac < 0.9).then(|| {
                format!(
                    "{:.4} Hz (MAC {mac:.2})",
                    merged.modes[m].natural_frequency_hz.value
                )
            })
        })
        .collect();
    findings.push(Finding {
        checked: true,
        passed: poor.is_empty(),
        text: if poor.is_empty() {
            "every mode's reference entries agree between the records (MAC ≥ 0.9): the shapes join and the modes track".into()
        } else {
            format!(
                "reference entries that disagree between records (MAC < 0.9: a different mode, or references that see it poorly): {}",
                poor.join(", ")
            )
        },
    });
    let dead: Vec<String> = records
        .iter()
        .flat_map(|r| {
            r.left_out
                .iter()
                .map(move |(name, _)| format!("{name} (record {})", r.label))
        })
        .collect();
    if !dead.is_empty() {
        findings.push(Finding {
            checked: true,
            passed: false,
            text: format!("dead channels left out: {}", dead.join(", ")),
        });
    }
    Verdict::of(findings)
}
