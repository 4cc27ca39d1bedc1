//! The mass–spring–damper identification experiment as a library: a TOML config (or
//! records you already hold in memory) in, a typed [`Outcome`] and a folder of results
//! out.
//!
//! A run reads a config ([`config`]), which is one kind of experiment
//! ([`config::Experiment`]): the paper's workflow ([`paper`]: estimation, validation,
//! residual diagnostics, frequency check, Monte Carlo, nonlinear models), a lab setup
//! ([`setup`]), a frequency response ([`frf`]), a chain of masses ([`chain`]) or
//! output-only modal analysis ([`operational`]). Its module generates or loads the data
//! and computes an outcome; one writer ([`run`]) turns any outcome into figures (in the
//! house style of [`plots`]), CSV tables, a report ([`page`] for its HTML) and
//! `results.json` ([`results`] for the shared header), in one folder atomically
//! ([`output`]). `plan` and `design` are commands of their own.
//!
//! The same library is the `msd` command (`cargo install --path crates/msd-experiment`,
//! then `msd run configs/paper.toml`) and `cargo xtask experiment` inside the workspace.
//!
//! ```no_run
//! use msd_experiment::{RunOptions, run_experiment};
//! let run = run_experiment("configs/paper.toml".as_ref(), &RunOptions::default())?;
//! println!("{}", run.summary);
//! # Ok::<(), msd_experiment::ExperimentError>(())
//! ```

pub mod budget;
pub mod chain;
pub mod cli;
pub mod config;
pub mod data;
pub mod design;
mod error;
pub mod fetch;
pub mod finished;
pub mod fmt;
pub mod frf;
pub mod init;
pub mod inspect;
mod noise_report;
pub mod operational;
pub mod options;
pub mod output;
pub mod page;
pub mod paper;
pub mod plan;
pub mod plots;
pub mod progress;
pub mod results;
pub mod run;
pub mod setup;
pub mod sources;
mod summary;
mod table;
pub mod verdict;

pub use error::{ExperimentError, Result};
pub use options::RunOptions;
pub use paper::{FrequencyStage, Outcome};

use config::Config;
use progress::Progress;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What a finished run leaves the caller.
#[derive(Debug, Clone)]
pub struct RunSummary {
    /// The folder the results were written to.
    pub out_dir: PathBuf,
    /// The summary text (what the command prints).
    pub summary: String,
    /// The contents of `results.json`.
    pub results: serde_json::Value,
}

/// The folder under which results go when neither `--out` nor `output.dir` says:
/// `msd-results` in the current folder.
pub const DEFAULT_RESULTS_ROOT: &str = "msd-results";

/// Where a run writes: `--out`, else the config's `output.dir` (relative to the config
/// file), else `<results_root>/<name>` (by default `msd-results/<name>` in the current
/// folder).
///
/// ```
/// use msd_experiment::{RunOptions, config::Config, output_dir};
/// use std::path::Path;
/// let text = "name = \"x\"\n[data]\npath = \"d.csv\"\ninput = 0\noutput = 1\nsample_rate = 10.0";
/// let config = Config::from_toml_str(text, "lab/x.toml")?;
/// let options = RunOptions::default();
/// assert_eq!(output_dir(&config, Path::new("lab/x.toml"), &options), Path::new("msd-results/x"));
/// # Ok::<(), msd_experiment::ExperimentError>(())
/// ```
pub fn output_dir(config: &Config, config_path: &Path, options: &RunOptions) -> PathBuf {
    if let Some(out) = &options.out {
        return out.clone();
    }
    if let Some(dir) = &config.output.dir {
        return config_path.parent().unwrap_or(Path::new("")).join(dir);
    }
    options
        .results_root
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_RESULTS_ROOT))
        .join(&config.name)
}

/// Runs the experiment of `config_path` and writes its results.
///
/// Nothing is written unless every stage succeeds: a bad config or bad data fails before
/// any folder is created, and a failure while writing removes the staging folder. The
/// one exception leaves the result folder alone too: a frequency-response run whose mode
/// selection fails writes the stabilization diagram it computed, with `failure.md`, into
/// `<results>-failed` beside it ([`ExperimentError::Kept`]), for the user to look at.
pub fn run_experiment(config_path: &Path, options: &RunOptions) -> Result<RunSummary> {
    run_config(Config::load(config_path)?, options)
}

/// Runs `config` as [`run_experiment`] runs a file: its data come from
/// `config.sources` ([`sources::Sources`]: the disk beside its config file, or files
/// given in memory, as bytes or named columns), so that a program that holds its
/// records runs any kind of experiment with no data file on disk.
///
/// ```no_run
/// use msd_experiment::{RunOptions, config::Config, run_config};
/// let mut config = Config::load("configs/templates/accelerometer.toml".as_ref())?;
/// let (t, force, accel) = (vec![0.0, 0.001], vec![0.0, 1.0], vec![0.0, 0.5]); // … held by the program
/// config.sources = config.sources.with_columns(
///     "data/accelerometer.csv",
///     vec![("t".into(), t), ("force".into(), force), ("accel".into(), accel)],
/// );
/// let run = run_config(config, &RunOptions::default())?;
/// # Ok::<(), msd_experiment::ExperimentError>(())
/// ```
pub fn run_config(config: Config, options: &RunOptions) -> Result<RunSummary> {
    let started = Instant::now();
    let config_path = config.sources.config_file().to_path_buf();
    let progress = Progress::new(options.progress);
    let result = run::run_and_write(config, &config_path, options, &progress, started);
    progress.finish();
    result
}

/// Runs the stages on records a Rust program already holds, with no file read: the
/// options come from `config` (built with [`Config::new`] and set in Rust, or read from
/// TOML; its data sections are not used), the records from `data`
/// ([`data::ExperimentData::in_memory`]). `options.seed` and `options.threads` override
/// the config's as on the command line. Write the outcome with [`write_outcome`].
///
/// ```
/// use msd_experiment::{RunOptions, config::Config, data::ExperimentData, run_in_memory};
/// // The paper's two records (m = 2.5 kg, c = 1.8 N·s/m, k = 120 N/m; σ = 2.5 mm).
/// let paper = msd_ident::PaperExperiment::generate(1)?;
/// let mut config = Config::new("paper-in-memory");
/// config.monte_carlo.samples = 50;
/// let data = ExperimentData::in_memory(paper.identification, paper.validation);
/// let outcome = run_in_memory(config, data, &RunOptions::default())?;
/// let [low, high] = outcome.estimate.uncertainty.mass.ci95;
/// assert!(low < 2.5 && 2.5 < high, "[{low}, {high}]");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn run_in_memory(
    config: Config,
    data: data::ExperimentData,
    options: &RunOptions,
) -> Result<Outcome> {
    config.check_options()?;
    let progress = Progress::new(options.progress);
    let outcome = paper::run_on_data(config, Path::new(""), data, options, &progress);
    progress.finish();
    outcome
}

/// Writes `outcome` into the folder `target` atomically (figures, CSV tables,
/// `report.md`, `report.html`, `results.json`; nothing is left behind if a write fails) and returns
/// the summary the command prints.
///
/// ```no_run
/// # fn outcome() -> msd_experiment::Outcome { unimplemented!() }
/// let run = msd_experiment::write_outcome(&outcome(), "results/bench".as_ref())?;
/// print!("{}", run.summary);
/// # Ok::<(), msd_experiment::ExperimentError>(())
/// ```
pub fn write_outcome(outcome: &Outcome, target: &Path) -> Result<RunSummary> {
    let computed: std::time::Duration = outcome.timings.iter().map(|(_, d)| *d).sum();
    let now = Instant::now();
    let started = now.checked_sub(computed).unwrap_or(now);
    run::write_paper(outcome, target, started)
}

#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeExamples;
