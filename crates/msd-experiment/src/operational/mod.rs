//! An `[operational]` run: output-only modal analysis of a record with no measured
//! input (a structure under wind, traffic, a fan or its own operation). The record is
//! read (a pyOMA `.npy` setup, a CSV file) or simulated (a shear building with a known
//! truth), dead channels are left out or refused, and msd-modal's [`ssi_cov`] finds the
//! modes with their intervals and the stabilization diagram.

mod geometry;
mod plots;
mod pyoma;
mod read;
mod report;
mod series;
mod series_report;
mod shapes_plot;

pub use geometry::Geometry;
pub use series::{AnalysedRecord, SeriesOutcome, run as run_records};

use crate::config::{Config, OperationalSection, Spec};
use crate::error::{ExperimentError, Result};
use crate::options::RunOptions;
use crate::progress::Progress;
use crate::results::Header;
use crate::verdict::{Finding, Verdict};
use msd_modal::{OmaFit, OmaMethod, OutputRecord, efdd, ssi_cov, ssi_dat};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Everything an operational run produced, in memory.
#[derive(Debug, Clone)]
pub struct OperationalOutcome {
    /// The config as read.
    pub config: Config,
    /// The config file as given.
    pub config_path: PathBuf,
    /// The config's `[operational]`.
    pub section: OperationalSection,
    /// The command that ran it, for the report.
    pub command: String,
    /// The seed used (a simulated record's noise).
    pub seed: u64,
    /// The record analysed (dead channels left out).
    pub record: OutputRecord,
    /// The channels left out, each with why.
    pub left_out: Vec<(String, String)>,
    /// A simulated building's true modes: fn (Hz) and the shape over the floors.
    pub truth: Option<Vec<(f64, Vec<f64>)>>,
    /// The files read.
    pub files: Vec<PathBuf>,
    /// The modes, the diagram and the settings.
    pub fit: OmaFit,
    /// The structure's geometry, where the config gives it.
    pub geometry: Option<Geometry>,
    /// Wall time of each stage, in order.
    pub timings: Vec<(&'static str, Duration)>,
    /// Whether the modes can be trusted, and why.
    pub verdict: Verdict,
}

/// Runs the `[operational]` experiment of `config`.
pub fn run(
    spec: Spec<OperationalSection>,
    options: &RunOptions,
    progress: &Progress,
) -> Result<OperationalOutcome> {
    let Spec { config, section } = spec;
    let config_path = config.sources.config_file().to_path_buf();
    let seed = options.seed.unwrap_or(config.seed);
    progress.stage("data");
    let t = Instant::now();
    let loaded = read::load(&section, &config.sources, seed)?;
    let geometry = geometry::of(&section, &config.sources)?;
    let mut timings = vec![("data", t.elapsed())];
    progress.stage("estimation");
    let t = Instant::now();
    let record_path = section.record.as_ref().map_or_else(
        || config_path.to_path_buf(),
        |r| config.sources.path(&r.path),
    );
    let fit = analyse(&section, &loaded.record)
        .map_err(|e| oma_error(e, section.options_table(), &config_path, &record_path))?;
    timings.push(("estimation", t.elapsed()));
    let verdict = verdict(&fit, &loaded.left_out, loaded.truth.as_deref());
    Ok(OperationalOutcome {
        command: options
            .command
            .clone()
            .unwrap_or_else(|| "msd run".to_string()),
        config,
        config_path,
        section,
        seed,
        record: loaded.record,
        left_out: loaded.left_out,
        truth: loaded.truth,
        files: loaded.files,
        fit,
        geometry,
        timings,
        verdict,
    })
}

/// The section's method on one record.
pub(crate) fn analyse(
    section: &OperationalSection,
    record: &OutputRecord,
) -> std::result::Result<OmaFit, msd_modal::ModalError> {
    match section.method {
        OmaMethod::SsiCov => ssi_cov(record, &section.ssi),
        OmaMethod::SsiDat => ssi_dat(record, &section.ssi),
        OmaMethod::Efdd => efdd(record, &section.efdd),
    }
}

/// msd-modal's refusal as the run's error: a bad option names its key under
/// `operational.<table>.`, a record too short or with a bad channel is the record's
/// (exit 2); what the analysis could not find is the run's (exit 1).
pub(crate) fn oma_error(
    e: msd_modal::ModalError,
    table: &str,
    config_path: &Path,
    record: &Path,
) -> ExperimentError {
    use msd_modal::ModalError as E;
    match e {
        E::InvalidParameter {
            name,
            value,
            expected,
        } => ExperimentError::config(
            config_path,
            format!("operational.{table}.{name} = {value}: expected {expected}"),
        ),
        E::BadChannel { .. } | E::LengthMismatch { .. } | E::TooFewSamples { .. } => {
            ExperimentError::data(record, e.to_string())
        }
        other => ExperimentError::run("estimation", other),
    }
}

/// The verdict: modes found, every one confirmed by the jackknife, dead channels, and
/// against a simulated truth.
fn verdict(
    fit: &OmaFit,
    left_out: &[(String, String)],
    truth: Option<&[(f64, Vec<f64>)]>,
) -> Verdict {
    let mut findings = Vec::new();
    let found = !fit.modes.is_empty();
    findings.push(Finding {
        checked: true,
        passed: found,
        text: match (found, fit.method) {
            (true, OmaMethod::SsiCov | OmaMethod::SsiDat) => format!("{} modes stable across the model orders, each with 95 % intervals from the record's own scatter (jackknife over {} blocks)", fit.modes.len(), fit.blocks),
            (true, OmaMethod::Efdd) => format!("{} modes at peaks of the first singular value, each with 95 % intervals from the record's own scatter (jackknife over {} blocks)", fit.modes.len(), fit.blocks),
            (false, OmaMethod::SsiCov | OmaMethod::SsiDat) => "no mode is stable across the model orders: widen operational.ssi.orders, or check the record (a band with no mode, or noise alone)".into(),
            (false, OmaMethod::Efdd) => "no peak of the first singular value gave a decaying correlation function: lower operational.efdd.min_correlation, or try method = \"ssi-cov\"".into(),
        },
    });
    if !fit.unconfirmed.is_empty() {
        let list: Vec<String> = fit
            .unconfirmed
            .iter()
            .map(|c| format!("{:.4} Hz", c.natural_frequency_hz))
            .collect();
        findings.push(Finding {
            checked: true,
            passed: true,
            text: format!("{} more columns of the diagram ({}) are not reported as modes: the record less one block lost them, or they split a reported mode (within 1 % and MAC ≥ 0.9 of it)", list.len(), list.join(", ")),
        });
    }
    if !left_out.is_empty() {
        let names: Vec<String> = left_out
            .iter()
            .map(|(n, why)| format!("{n} ({why})"))
            .collect();
        findings.push(Finding {
            checked: true,
            passed: false,
            text: format!(
                "dead channels left out: {}; their DOFs have no shape entries",
                names.join(", ")
            ),
        });
    }
    if let Some(truth) = truth {
        let missed: Vec<String> = truth
            .iter()
            .filter(|(f, _)| {
                !fit.modes
                    .iter()
                    .any(|m| (m.natural_frequency_hz.value / f - 1.0).abs() < 0.01)
            })
            .map(|(f, _)| format!("{f:.4} Hz"))
            .collect();
        findings.push(Finding {
            checked: true,
            passed: missed.is_empty(),
            text: if missed.is_empty() {
                format!(
                    "every one of the {} true modes found within 1 %",
                    truth.len()
                )
            } else {
                format!("true modes not found within 1 %: {}", missed.join(", "))
            },
        });
    }
    Verdict::of(findings)
}

#[derive(Serialize)]
struct RecordSummary<'a> {
    sample_rate_hz: f64,
    samples: usize,
    channels: Vec<ChannelSummary<'a>>,
    left_out: Vec<LeftOut<'a>>,
    files: Vec<String>,
}

#[derive(Serialize)]
struct ChannelSummary<'a> {
    name: &'a str,
    dof: Option<msd_modal::Dof>,
    #[serde(skip_serializing_if = "Option::is_none")]
    oblique_direction: Option<[f64; 3]>,
    quantity: msd_modal::Quantity,
    reference: bool,
}

#[derive(Serialize)]
struct LeftOut<'a> {
    name: &'a str,
    reason: &'a str,
}

#[derive(Serialize)]
struct TrueMode<'a> {
    natural_frequency_hz: f64,
    damping_ratio: f64,
    shape: &'a [f64],
}

#[derive(Serialize)]
struct Results<'a> {
    experiment: Header<'a>,
    command: &'a str,
    verdict: &'a Verdict,
    record: RecordSummary<'a>,
    method: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    block_rows: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    lags: Option<usize>,
    blocks: usize,
    references: &'a [String],
    modes: &'a [msd_modal::Mode],
    unconfirmed: &'a [msd_modal::StableColumn],
    #[serde(skip_serializing_if = "Option::is_none")]
    truth: Option<Vec<TrueMode<'a>>>,
    options: Options<'a>,
    diagram: &'a msd_modal::StabilizationDiagram,
    timings_ms: BTreeMap<&'static str, f64>,
}

/// The chosen method's options.
#[derive(Serialize)]
#[serde(untagged)]
enum Options<'a> {
    Ssi(&'a msd_modal::OmaOptions),
    Efdd(&'a msd_modal::FddOptions),
}

/// The `results.json` value of `o`.
pub(crate) fn results(
    o: &OperationalOutcome,
    extra: &[(&'static str, Duration)],
    total: Duration,
) -> Result<serde_json::Value> {
    let section = &o.section;
    let refs = o.record.reference_indices();
    let damping = section.simulate.as_ref().map_or(0.0, |b| b.damping_ratio);
    let results = Results {
        experiment: Header::new(
            &o.config,
            &o.config_path,
            if o.truth.is_some() {
                "synthetic"
            } else {
                "measured"
            },
            o.seed,
            None,
        ),
        command: &o.command,
        verdict: &o.verdict,
        record: RecordSummary {
            sample_rate_hz: o.record.sample_rate_hz(),
            samples: o.record.len(),
            channels: o
                .record
                .channels()
                .iter()
                .enumerate()
                .map(|(i, c)| ChannelSummary {
                    name: &c.name,
                    dof: c.dof,
                    oblique_direction: c.direction,
                    quantity: c.quantity,
                    reference: refs.contains(&i),
                })
                .collect(),
            left_out: o
                .left_out
                .iter()
                .map(|(name, reason)| LeftOut { name, reason })
                .collect(),
            files: o.files.iter().map(|f| f.display().to_string()).collect(),
        },
        method: o.fit.method.to_string(),
        block_rows: o.fit.block_rows,
        lags: o.fit.spectrum.as_ref().map(|s| s.lags),
        blocks: o.fit.blocks,
        references: &o.fit.references,
        modes: &o.fit.modes,
        unconfirmed: &o.fit.unconfirmed,
        truth: o.truth.as_ref().map(|t| {
            t.iter()
                .map(|(f, shape)| TrueMode {
                    natural_frequency_hz: *f,
                    damping_ratio: damping,
                    shape,
                })
                .collect()
        }),
        options: match section.method {
            OmaMethod::SsiCov | OmaMethod::SsiDat => Options::Ssi(&section.ssi),
            OmaMethod::Efdd => Options::Efdd(&section.efdd),
        },
        diagram: &o.fit.diagram,
        timings_ms: crate::results::timings_ms(&o.timings, extra, total),
    };
    serde_json::to_value(&results).map_err(|e| ExperimentError::run("write", e))
}

/// `modes.csv` (one line per mode: fn and ζ with standard errors and intervals) and
/// `shapes.csv` (one line per mode and DOF).
pub(crate) fn tables(o: &OperationalOutcome) -> Vec<(String, String)> {
    mode_tables(&o.fit.modes)
}

/// `modes.csv` and `shapes.csv` of `modes`.
pub(crate) fn mode_tables(modes: &[msd_modal::Mode]) -> Vec<(String, String)> {
    let mut table = String::from(
        "mode,natural_frequency_hz,standard_error_hz,ci95_low_hz,ci95_high_hz,damping_ratio,damping_standard_error,damping_ci95_low,damping_ci95_high,mpc,stable_orders\n",
    );
    let mut shapes =
        String::from("mode,node,direction,re,im,standard_error_re,standard_error_im\n");
    for (k, m) in modes.iter().enumerate() {
        let (f, z) = (&m.natural_frequency_hz, &m.damping_ratio);
        table += &format!(
            "{},{},{},{},{},{},{},{},{},{},{}\n",
            k + 1,
            f.value,
            f.standard_error,
            f.ci95[0],
            f.ci95[1],
            z.value,
            z.standard_error,
            z.ci95[0],
            z.ci95[1],
            m.mpc.unwrap_or(f64::NAN),
            m.stable_orders.unwrap_or(0)
        );
        for e in &m.shape {
            let [sr, si] = e.standard_error.unwrap_or([f64::NAN; 2]);
            shapes += &format!(
                "{},{},{},{},{},{sr},{si}\n",
                k + 1,
                e.node,
                e.direction,
                e.re,
                e.im
            );
        }
    }
    vec![("modes.csv".into(), table), ("shapes.csv".into(), shapes)]
}

/// Writes `modes` as `modes.uff` (datasets 55; x, y, z entries only: a node's oblique
/// channels resolved first).
pub(crate) fn write_uff(name: &str, modes: &[msd_modal::Mode], dir: &Path) -> Result<()> {
    let file = msd_uff::UffFile {
        data_at_nodes: modes
            .iter()
            .enumerate()
            .map(|(r, mode)| crate::frf::uff_out::shape_dataset(name, r, mode))
            .collect(),
        ..msd_uff::UffFile::default()
    };
    let path = dir.join("modes.uff");
    msd_uff::write(&path, &file, &Default::default())
        .map_err(|e| ExperimentError::data(&path, e.to_string()))
}

impl crate::finished::Finished for OperationalOutcome {
    fn config(&self) -> &Config {
        &self.config
    }

    fn figures(&self, dir: &Path) -> Result<Vec<&'static str>> {
        let xyz: Vec<msd_modal::Mode> = self
            .fit
            .modes
            .iter()
            .map(|m| msd_modal::Mode {
                shape: msd_modal::node_components(&self.record, &m.shape),
                ..m.clone()
            })
            .collect();
        write_uff(&self.config.name, &xyz, dir)?;
        plots::write_all(self, dir)
    }

    fn tables(&self) -> Vec<(String, String)> {
        tables(self)
    }

    fn timings(&self) -> &[(&'static str, Duration)] {
        &self.timings
    }

    fn report(&self, figures: &[&str]) -> String {
        report::markdown(self, figures)
    }

    fn results(
        &self,
        extra: &[(&'static str, Duration)],
        total: Duration,
    ) -> Result<serde_json::Value> {
        results(self, extra, total)
    }

    fn summary(&self) -> String {
        report::summary(self)
    }
}
