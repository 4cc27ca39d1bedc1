//! `cargo xtask`: the workspace's development tasks over the `msd-experiment` library:
//! `experiment` (the library's run, writing into `target/experiments/<name>/`) and
//! `bench` (one performance table, [`bench`](mod@bench)) and `noise-study` (the
//! intervals' coverage under a noisy drive, [`noise_study`]).
//!
//! ```no_run
//! let root = xtask::project_root();
//! assert!(root.join("configs/paper.toml").exists());
//! ```

pub mod bench;
pub mod check_report;
pub mod noise_study;
pub mod oma_study;

use msd_experiment::{ExperimentError, Result, RunOptions, config, fmt, paper, progress};
use std::path::{Path, PathBuf};

/// The workspace root (the folder above `xtask/`).
pub fn project_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."))
}

/// Where `cargo xtask experiment` writes `<name>/`: the workspace's `target/experiments`.
pub fn results_root() -> PathBuf {
    project_root().join("target").join("experiments")
}
