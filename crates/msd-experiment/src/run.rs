//! One experiment shape: a config resolves to one [`ExperimentKind`]; its module runs it
//! into an outcome; one writer turns any outcome into the result folder (figures, CSV
//! tables, `report.md` and `report.html`, `results.json`), atomically, and the summary.
//!
//! The kinds sit below this module and know nothing of each other: the paper workflow
//! ([`paper`]), the lab setups ([`setup`]) and the
//! frequency response ([`frf`]). `plan` and `design` are commands of their own.

use crate::config::Config;
use crate::output::Staging;
use crate::progress::Progress;
use crate::{
    RunSummary, chain, error::Result, frf, options::RunOptions, paper, paper::Outcome, setup,
};
use serde_json::Value;
use std::path::Path;
use std::time::{Duration, Instant};

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
        if config.frequency_only() {
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

/// A finished run of any kind, as the writer takes it.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Finished<'a> {
    /// The paper's workflow.
    Paper(&'a Outcome),
    /// A lab setup.
    Setup(&'a setup::SetupOutcome),
    /// A frequency response.
    FrequencyResponse(&'a frf::FrfOutcome),
    /// A chain of masses.
    Chain(&'a chain::ChainOutcome),
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
            write(Finished::Paper(&outcome), &target, progress, started)
        }
        ExperimentKind::Setup => {
            let outcome = setup::run(config, config_path, options, progress)?;
            write(Finished::Setup(&outcome), &target, progress, started)
        }
        ExperimentKind::FrequencyResponse => {
            let outcome = frf::run_keeping(config, config_path, options)
                .map_err(|f| frf::write_failure(f, &target))?;
            let finished = Finished::FrequencyResponse(&outcome);
            write(finished, &target, progress, started)
        }
        ExperimentKind::Chain => {
            let outcome = chain::run(config, config_path, options, progress)?;
            write(Finished::Chain(&outcome), &target, progress, started)
        }
    }
}

/// Writes `run` into `target` atomically (nothing is left there if any part fails):
/// figures (PNG and SVG), CSV tables, `report.md`, `report.html`, `results.json`; then
/// the summary that the command prints. `started` is when the run began.
pub(crate) fn write(
    run: Finished<'_>,
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

impl Finished<'_> {
    fn config(&self) -> &Config {
        match self {
            Self::Paper(o) => &o.config,
            Self::Setup(o) => &o.config,
            Self::FrequencyResponse(o) => &o.config,
            Self::Chain(o) => &o.config,
        }
    }

    fn figures(&self, dir: &Path) -> Result<Vec<&'static str>> {
        match self {
            Self::Paper(o) => crate::paper::figures::write_all(o, dir),
            Self::Setup(o) => setup::figures(o, dir),
            Self::FrequencyResponse(o) => frf::figures(o, dir),
            Self::Chain(o) => chain::figures(o, dir),
        }
    }

    fn tables(&self) -> Vec<(String, String)> {
        match self {
            Self::Paper(o) => crate::paper::tables::csv_files(o)
                .into_iter()
                .map(|(name, text)| (name.to_string(), text))
                .collect(),
            Self::Setup(o) => setup::tables(o),
            Self::FrequencyResponse(_) => Vec::new(),
            Self::Chain(o) => chain::tables(o),
        }
    }

    fn report(
        &self,
        figures: &[&str],
        extra: &[(&'static str, Duration)],
        elapsed: Duration,
    ) -> String {
        match self {
            Self::Paper(o) => crate::paper::report::markdown(o, figures, extra, elapsed),
            Self::Setup(o) => setup::report(o, figures),
            Self::FrequencyResponse(o) => frf::report(o, figures),
            Self::Chain(o) => chain::report(o, figures),
        }
    }

    fn results(&self, extra: &[(&'static str, Duration)], total: Duration) -> Result<Value> {
        match self {
            Self::Paper(o) => Ok(crate::paper::results::to_json(o, extra, total)),
            Self::Setup(o) => setup::results(o, extra, total),
            Self::FrequencyResponse(o) => Ok(frf::to_json(o, extra, total)),
            Self::Chain(o) => chain::results(o, extra, total),
        }
    }

    fn summary(
        &self,
        extra: &[(&'static str, Duration)],
        total: Duration,
        target: &Path,
    ) -> String {
        match self {
            Self::Paper(o) => crate::paper::summary::text(o, extra, total, target),
            Self::Setup(o) => {
                format!("{}\nresults in {}\n", setup::summary(o), target.display())
            }
            Self::FrequencyResponse(o) => format!("{o}\nresults in {}\n", target.display()),
            Self::Chain(o) => {
                format!("{}results in {}\n", chain::summary(o), target.display())
            }
        }
    }
}

/// Writes the paper workflow's `outcome` (see [`write`]); `started` is when its
/// computing began.
pub(crate) fn write_paper(
    outcome: &Outcome,
    target: &Path,
    started: Instant,
) -> Result<RunSummary> {
    write(
        Finished::Paper(outcome),
        target,
        &Progress::hidden(),
        started,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

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
