//! What the writer needs of a finished run of any kind. Each kind's outcome implements
//! [`Finished`] in its own module (`paper`, `setup`, `frf`, `chain`); the writer
//! (`run.rs`) takes any of them, so a new kind plugs in here and in
//! [`Experiment`](crate::config::Experiment), nowhere else.

use crate::config::Config;
use crate::error::Result;
use serde_json::Value;
use std::path::Path;
use std::time::Duration;

/// A finished run of any kind, as the writer takes it.
pub trait Finished {
    /// The config as run.
    fn config(&self) -> &Config;
    /// Writes the figures (PNG and SVG) into `dir`; their names.
    fn figures(&self, dir: &Path) -> Result<Vec<&'static str>>;
    /// The CSV tables, by file name.
    fn tables(&self) -> Vec<(String, String)> {
        Vec::new()
    }
    /// `report.md`: with the figures written, the writer's `extra` stage times and the
    /// time since the run began.
    fn report(
        &self,
        figures: &[&str],
        extra: &[(&'static str, Duration)],
        elapsed: Duration,
    ) -> String;
    /// The kind's `results.json` document (the writer adds `schema_version`).
    fn results(&self, extra: &[(&'static str, Duration)], total: Duration) -> Result<Value>;
    /// What the command prints, ending with where the results are (`target`).
    fn summary(&self, extra: &[(&'static str, Duration)], total: Duration, target: &Path)
    -> String;
}
