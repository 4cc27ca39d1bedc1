//! `cargo xtask`: the task runner of the msd toolkit, as a library (so tests can run
//! tasks in-process) and a thin binary.
//!
//! The one task is `experiment`: read a TOML config ([`config`]), generate or load the
//! data ([`data`]), run the stages ([`pipeline`]: estimation, validation, residual
//! diagnostics, frequency check, Monte Carlo, and nonlinear models ([`nonlinear`]) when
//! asked), and write figures ([`plots`]), CSV
//! tables ([`tables`]), a report ([`report`]) and `results.json` ([`results`]) into
//! `target/experiments/<name>/` atomically ([`output`]).
//!
//! ```no_run
//! use xtask::{RunOptions, run_experiment};
//! let run = run_experiment("configs/paper.toml".as_ref(), &RunOptions::default())?;
//! println!("{}", run.summary);
//! # Ok::<(), xtask::XtaskError>(())
//! ```

pub mod bench;
pub mod config;
pub mod data;
mod error;
pub mod fmt;
pub mod nonlinear;
pub mod output;
pub mod pipeline;
pub mod plots;
pub mod progress;
pub mod report;
pub mod results;
pub mod summary;
pub mod tables;

pub use error::{Result, XtaskError};
pub use pipeline::{Outcome, RunOptions};

use config::Config;
use output::Staging;
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

/// The workspace root (the folder above `xtask/`).
pub fn project_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."))
}

/// Where a run writes: `--out`, else the config's `output.dir` (relative to the config
/// file), else `target/experiments/<name>` in the workspace.
pub fn output_dir(config: &Config, config_path: &Path, options: &RunOptions) -> PathBuf {
    if let Some(out) = &options.out {
        return out.clone();
    }
    if let Some(dir) = &config.output.dir {
        return config_path.parent().unwrap_or(Path::new("")).join(dir);
    }
    project_root()
        .join("target")
        .join("experiments")
        .join(&config.name)
}

/// Runs the experiment of `config_path` and writes its results.
///
/// Nothing is written unless every stage succeeds: a bad config or bad data fails before
/// any folder is created, and a failure while writing removes the staging folder.
pub fn run_experiment(config_path: &Path, options: &RunOptions) -> Result<RunSummary> {
    let started = Instant::now();
    let config = Config::load(config_path)?;
    let progress = Progress::new(options.progress);
    let result = run_and_write(config, config_path, options, &progress, started);
    progress.finish();
    result
}

fn run_and_write(
    config: Config,
    config_path: &Path,
    options: &RunOptions,
    progress: &Progress,
    started: Instant,
) -> Result<RunSummary> {
    let target = output_dir(&config, config_path, options);
    let outcome = pipeline::run_stages(config, config_path, options, progress)?;

    progress.stage("figures");
    let staging = Staging::new(&target)?;
    let t = Instant::now();
    let figures = plots::write_all(&outcome, staging.path())?;
    let mut extra = vec![("figures", t.elapsed())];

    progress.stage("report");
    let t = Instant::now();
    for (name, text) in tables::csv_files(&outcome) {
        staging.write(name, text.as_bytes())?;
    }
    let report = report::markdown(&outcome, &figures, &extra, started.elapsed());
    staging.write("report.md", report.as_bytes())?;
    extra.push(("report", t.elapsed()));

    let total = started.elapsed();
    let json = results::to_json(&outcome, &extra, total);
    let text = serde_json::to_string_pretty(&json).map_err(|e| XtaskError::run("write", e))?;
    staging.write("results.json", format!("{text}\n").as_bytes())?;
    staging.commit()?;
    let summary = summary::text(&outcome, &extra, total, &target);
    Ok(RunSummary {
        out_dir: target,
        summary,
        results: json,
    })
}
