//! One experiment shape: a config resolves to one [`ExperimentKind`]; its module runs it
//! into an outcome; one writer turns any outcome into the result folder (figures, CSV
//! tables, `report.md` and `report.html`, `results.json`), atomically, and the summary.
//!
//! The kinds sit below this module and know nothing of each other: the paper workflow
//! ([`paper`]), the lab setups ([`setup`]), the frequency response ([`frf`]) and the
//! chain of masses ([`chain`]); each outcome implements [`Finished`], the writer's only
//! view of it. `plan` and `design` are commands of their own.

use crate::config::Config;
use crate::finished::Finished;
use crate::output::Staging;
use crate::progress::Progress;
use crate::{
    RunSummary, chain, error::Result, frf, options::RunOptions, paper, paper::Outcome, setup,
};
use std::path::Path;
use std::time::Instant;

/// What a config runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExperimentKind {
    /// The paper's workflow: identification, validation, residuals, frequency check,
    /// Monte Carlo, nonlinear models.
    Paper,
    /// A lab setup (`[setup]`): any drive, several sensors and records, a test machine.
    Setup,
    /// A frequency response (`[frequency_response]` and no time-domain data).
    FrequencyResponse,
    /// A chain of masses in the time domain (`[chain]`).
    Chain,
    /// Output-only modal analysis (`[operational]`).
    Operational,
}

impl ExperimentKind {
    /// The kind of `config`.
    ///
    /// ```
    /// use msd_experiment::{config::Config, run::ExperimentKind};
    /// let config = Config::load("../../configs/free-decay.toml".as_ref())?;
    /// assert_eq!(ExperimentKind::of(&config), ExperimentKind::Setup);
    /// # Ok::<(), msd_experiment::ExperimentError>(())
    /// ```
    pub fn of(config: &Config) -> Self {
        if config.operational.is_some() {
            Self::Operational
        } else if config.frequency_only() {
            Self::FrequencyResponse
        } else if config.chain.is_some() {
            Self::Chain
        } else if config.setup.is_some() {
            Self::Setup
        } else {
            Self::Paper
        }
    }
}

/// Runs the config at `config_path` and writes its results (see [`write`]).
pub(crate) fn run_and_write(
    config: Config,
    config_path: &Path,
    options: &RunOptions,
    progress: &Progress,
    started: Instant,
) -> Result<RunSummary> {
    let target = crate::output_dir(&config, config_path, options);
    crate::output::check_target(&target)?;
    match ExperimentKind::of(&config) {
        ExperimentKind::Paper => {
            let outcome = paper::run_stages(config, config_path, options, progress)?;
            write(&outcome, &target, progress, started)
        }
        ExperimentKind::Setup => {
            let outcome = setup::run(config, config_path, options, progress)?;
            write(&outcome, &target, progress, started)
        }
        ExperimentKind::FrequencyResponse => {
            let outcome = frf::run_keeping(config, config_path, options)
                .map_err(|f| frf::write_failure(f, &target))?;
            write(&outcome, &target, progress, started)
        }
        ExperimentKind::Chain => {
            let outcome = chain::run(config, config_path, options, progress)?;
            write(&outcome, &target, progress, started)
        }
        ExperimentKind::Operational
            if config
                .operational
                .as_ref()
                .is_some_and(|o| !o.records.is_empty()) =>
        {
            let outcome = crate::operational::run_records(config, config_path, options, progress)?;
            write(&outcome, &target, progress, started)
        }
        ExperimentKind::Operational => {
            let outcome = crate::operational::run(config, config_path, options, progress)?;
            write(&outcome, &target, progress, started)
        }
    }
}

/// Writes `run` into `target` atomically (nothing is left there if any part fails):
/// figures (PNG and SVG), CSV tables, `report.md`, `report.html`, `results.json`; then
/// the summary that the command prints. `started` is when the run began.
pub(crate) fn write(
    run: &dyn Finished,
    target: &Path,
    progress: &Progress,
    started: Instant,
) -> Result<RunSummary> {
    progress.stage("figures");
    let staging = Staging::new(target)?;
    let t = Instant::now();
    let figures = run.figures(staging.path())?;
    let mut extra = vec![("figures", t.elapsed())];

    progress.stage("report");
    let t = Instant::now();
    for (name, text) in run.tables() {
        staging.write(&name, text.as_bytes())?;
    }
    let report = run.report(&figures, &extra, started.elapsed());
    crate::page::write_pages(&staging, &report, &run.config().name)?;
    extra.push(("report", t.elapsed()));

    let total = started.elapsed();
    let json = crate::results::versioned(run.results(&extra, total)?);
    crate::results::write_json(&staging, &json)?;
    staging.commit()?;
    Ok(RunSummary {
        out_dir: target.to_path_buf(),
        summary: run.summary(&extra, total, target),
        results: json,
    })
}

/// Writes the paper workflow's `outcome` (see [`write`]); `started` is when its
/// computing began.
pub(crate) fn write_paper(
    outcome: &Outcome,
    target: &Path,
    started: Instant,
) -> Result<RunSummary> {
    write(outcome, target, &Progress::hidden(), started)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_run_help_names_every_kind() {
        // One section per kind that is not the paper's (ExperimentKind::of's rule).
        for section in [
            "[setup]",
            "[frequency_response]",
            "[chain]",
            "[operational]",
        ] {
            assert!(crate::cli::RUN_HELP.contains(section), "{section}");
        }
        assert!(crate::cli::RUN_HELP.contains("msd init FILE"));
    }

    #[test]
    fn each_shipped_kind_is_recognised() {
        let kind = |name: &str| {
            let path = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../../configs")
                .join(name);
            ExperimentKind::of(&Config::load(&path).expect("a shipped config"))
        };
        assert_eq!(kind("paper.toml"), ExperimentKind::Paper);
        assert_eq!(kind("repeats.toml"), ExperimentKind::Setup);
        assert_eq!(kind("frf-uff.toml"), ExperimentKind::FrequencyResponse);
    }
}
