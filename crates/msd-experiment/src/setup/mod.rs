//! A `[setup]` run: the tests a vibration lab runs beyond a force and one displacement
//! channel — accelerometers and several channels at once, base excitation, free decay,
//! a damper test machine, repeated records fitted together.
//!
//! The records ([`data`]) are fitted by msd-ident's [`fit_records`](msd_ident::fit_records)
//! (shared m, c, k or ωn, ζ over every record and channel, each channel's noise level
//! estimated, leave-one-record-out validation) or, for a test machine, by its
//! [`dynamometer`](msd_ident::dynamometer::dynamometer()) analysis; the report, the figures, the CSV
//! files and `results.json` follow the setup.

pub mod data;
pub(crate) mod fit;
pub(crate) mod machine;
mod plots;
mod report;
mod report_machine;
mod report_validation;
mod results;
pub mod stroke;

pub use data::{SetupData, SetupRecord};
pub use fit::SetupFit;

use crate::config::{Config, SetupSection, Spec};
use crate::progress::Progress;
use crate::{error::Result, options::RunOptions};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Everything a setup run produced, in memory.
#[derive(Debug, Clone)]
pub struct SetupOutcome {
    /// The config as read.
    pub config: Config,
    /// The config file as given.
    pub config_path: PathBuf,
    /// The command that ran it, for the report.
    pub command: String,
    /// The seed used.
    pub seed: u64,
    /// The records.
    pub data: SetupData,
    /// The fit.
    pub fit: SetupFit,
    /// Wall time of each stage, in order.
    pub timings: Vec<(&'static str, Duration)>,
    /// Whether the estimates can be trusted, and why.
    pub verdict: crate::verdict::Verdict,
}

/// Runs the setup experiment of `spec`.
pub fn run(
    spec: Spec<SetupSection>,
    options: &RunOptions,
    progress: &Progress,
) -> Result<SetupOutcome> {
    let Spec { config, section } = spec;
    let config_path = config.sources.config_file().to_path_buf();
    let seed = options.seed.unwrap_or(config.seed);
    progress.stage("data");
    let t = Instant::now();
    let data = data::load(&config, &section, seed)?;
    let mut timings = vec![("data", t.elapsed())];
    progress.stage("estimation");
    let t = Instant::now();
    let fit = fit::fit(&config, &config_path, &data)?;
    timings.push(("estimation", t.elapsed()));
    let verdict = report_validation::verdict(&fit);
    Ok(SetupOutcome {
        command: options
            .command
            .clone()
            .unwrap_or_else(|| "msd run".to_string()),
        config,
        config_path,
        seed,
        data,
        fit,
        timings,
        verdict,
    })
}

// The parts the writer (`crate::run`) takes: figures, one CSV file per record (the
// columns a measured config of the same setup reads back), the report, results.json and
// the summary.
pub(crate) use fit::record_files as tables;
pub(crate) use plots::write_all as figures;
pub(crate) use report::{markdown as report, summary};
pub(crate) use results::to_json as results;

impl crate::finished::Finished for SetupOutcome {
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
