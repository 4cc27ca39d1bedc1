//! The first run as a new user meets it (issue 34): `git clone` of this checkout's
//! committed state into a temporary folder, then `cargo xtask experiment
//! configs/paper.toml` there with its own target folder (the crates already downloaded:
//! `--offline`), timed from the clone to the report.

use super::report::load_average;
use crate::{Result, project_root};
use msd_experiment::ExperimentError;
use std::process::Command;
use std::time::Instant;

/// What one first run took.
#[derive(Debug, Clone, PartialEq)]
pub struct FirstRun {
    /// Wall time from the clone to the report, s.
    pub seconds: f64,
    /// The load average (1, 5, 15 min) before and after.
    pub load: (String, String),
}

impl std::fmt::Display for FirstRun {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "first run from a fresh clone: {:.1} s (git clone, then cargo xtask experiment configs/paper.toml with its own target folder, offline); load average {} before, {} after",
            self.seconds, self.load.0, self.load.1
        )
    }
}

/// Clones the committed checkout into a temporary folder and times the paper command's
/// first run there (the clone is removed afterwards).
pub fn first_run() -> Result<FirstRun> {
    let fail = |why: String| ExperimentError::run("bench-first-run", why);
    let dir = std::env::temp_dir().join(format!("msd-first-run-{}", std::process::id()));
    let clone = dir.join("clone");
    let load = load_average();
    let started = Instant::now();
    let result = (|| {
        run(
            Command::new("git")
                .args(["clone", "-q"])
                .arg(project_root())
                .arg(&clone),
            "git clone",
        )?;
        run(
            Command::new("cargo")
                .args(["--offline", "xtask", "experiment", "configs/paper.toml"])
                .current_dir(&clone)
                .env_remove("CARGO_TARGET_DIR"),
            "cargo xtask experiment configs/paper.toml",
        )
    })();
    let seconds = started.elapsed().as_secs_f64();
    let _ = std::fs::remove_dir_all(&dir);
    result.map_err(fail)?;
    Ok(FirstRun {
        seconds,
        load: (load, load_average()),
    })
}

fn run(command: &mut Command, what: &str) -> std::result::Result<(), String> {
    let status = command
        .stdout(std::process::Stdio::null())
        .status()
        .map_err(|e| format!("{what}: {e}"))?;
    match status.success() {
        true => Ok(()),
        false => Err(format!("{what} failed ({status})")),
    }
}
