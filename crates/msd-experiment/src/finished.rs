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
    /// Wall time of each stage the kind ran, in order.
    fn timings(&self) -> &[(&'static str, Duration)];
    /// `report.md` with the figures written, but for its timings, which the writer adds.
    fn report(&self, figures: &[&str]) -> String;
    /// The kind's `results.json` document (the writer adds `schema_version`).
    fn results(&self, extra: &[(&'static str, Duration)], total: Duration) -> Result<Value>;
    /// What the command prints, in the one format of every kind's summary, but for its
    /// footer (the stages' times, where the results are), which the writer adds.
    fn summary(&self) -> String;
}
