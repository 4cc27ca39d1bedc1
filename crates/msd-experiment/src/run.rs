//! One experiment shape: a config resolves once to an [`Experiment`] (its kind's section
//! typed and required, [`ExperimentKind::of`]'s rule); its kind's module runs it into an
//! outcome; one writer turns any outcome into the result folder (figures, CSV tables,
//! `report.md` and `report.html`, `results.json`), atomically, and the summary.
//!
//! The kinds sit below this module and know nothing of each other: the paper workflow
//! ([`paper`]), the lab setups ([`setup`]), the frequency response ([`frf`]), the chain
//! of masses ([`chain`]) and output-only modal analysis ([`operational`]); each outcome
//! implements [`Finished`], the writer's only view of it. `plan` and `design` are
//! commands of their own.

use crate::config::{Config, Experiment};
use crate::finished::Finished;
use crate::output::Staging;
use crate::progress::Progress;
use crate::{
    RunSummary, chain, error::Result, frf, operational, options::RunOptions, paper, paper::Outcome,
    setup,
};
use std::path::Path;
use std::time::Instant;

#[cfg(doc)]
use crate::config::ExperimentKind;

/// Runs `config` (read from `config_path`) and writes its results (see [`write`]).
pub(crate) fn run_and_write(
    config: Config,
    config_path: &Path,
    options: &RunOptions,
    progress: &Progress,
    started: Instant,
) -> Result<RunSummary> {
    let target = crate::output_dir(&config, config_path, options);
    crate::output::check_target(&target)?;
    let outcome: Box<dyn Finished> = match Experiment::from(config) {
        Experiment::Paper(config) => {
            Box::new(paper::run_stages(*config, config_path, options, progress)?)
        }
        Experiment::Setup(spec) => Box::new(setup::run(*spec, options, progress)?),
        Experiment::FrequencyResponse(spec) => {
            Box::new(frf::run_keeping(*spec, options).map_err(|f| frf::write_failure(f, &target))?)
        }
        Experiment::Chain(spec) => Box::new(chain::run(*spec, options, progress)?),
        Experiment::Operational(spec) => Box::new(operational::run(*spec, options, progress)?),
        Experiment::OperationalSeries(spec) => {
            Box::new(operational::run_records(*spec, options, progress)?)
        }
    };
    write(outcome.as_ref(), &target, progress, started)
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
    let mut report = run.report(&figures);
    crate::results::report_timings(&mut report, run.timings(), &extra, started.elapsed());
    crate::page::write_pages(&staging, &report, &run.config().name)?;
    extra.push(("report", t.elapsed()));

    let total = started.elapsed();
    let json = crate::results::versioned(run.results(&extra, total)?);
    crate::results::write_json(&staging, &json)?;
    staging.commit()?;
    let mut summary = run.summary();
    crate::summary::footer(&mut summary, run.timings(), &extra, total, target);
    Ok(RunSummary {
        out_dir: target.to_path_buf(),
        summary,
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
    use crate::config::ExperimentKind;

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

    /// The shipped config `name`.
    fn shipped(name: &str) -> Config {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../configs")
            .join(name);
        Config::load(&path).expect("a shipped config")
    }

    #[test]
    fn each_shipped_kind_is_recognised() {
        let kind = |name: &str| Experiment::from(shipped(name)).kind();
        assert_eq!(kind("paper.toml"), ExperimentKind::Paper);
        assert_eq!(kind("repeats.toml"), ExperimentKind::Setup);
        assert_eq!(kind("frf-uff.toml"), ExperimentKind::FrequencyResponse);
        assert_eq!(kind("two-storey.toml"), ExperimentKind::Chain);
        assert_eq!(kind("shear-building.toml"), ExperimentKind::Operational);
    }

    /// Resolving keeps the config whole and hands each kind its own section; a series
    /// of output-only records is its own variant (its own outcome).
    #[test]
    fn a_resolved_config_carries_its_section() {
        let config = shipped("two-storey.toml");
        match Experiment::from(config.clone()) {
            Experiment::Chain(spec) => {
                assert_eq!(Some(&spec.section), config.chain.as_ref());
                assert_eq!(spec.config, config);
            }
            other => panic!("{:?}", other.kind()),
        }
        let series = Experiment::from(shipped("steel-frame-setups.toml"));
        assert!(matches!(series, Experiment::OperationalSeries(_)));
        assert_eq!(series.kind(), ExperimentKind::Operational);
        let paper = shipped("paper.toml");
        assert_eq!(Experiment::from(paper.clone()).config(), &paper);
    }
}
