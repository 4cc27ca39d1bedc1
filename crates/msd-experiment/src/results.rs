//! `results.json`, the parts every kind of experiment shares: the `experiment` header
//! (name, kind, config file, seed, crate version) and the writing of the file. Each
//! kind's module builds the rest of its document.
//!
//! The file is deterministic: the same config and seed give the same bytes, whatever
//! the thread count, apart from `timings_ms` (wall times) and the recorded thread
//! counts. Keys are sorted.

use crate::config::Config;
use serde::Serialize;
use std::path::Path;
use std::time::Duration;

/// The version of the toolkit that wrote a results file.
pub const CRATE_VERSION: &str = env!("CARGO_PKG_VERSION");

/// The layout of `results.json`: raised whenever a key is renamed or moved (the
/// CHANGELOG lists each change). 2: one `Mode` for every kind (issue 41).
pub const SCHEMA_VERSION: u32 = 2;

/// A duration in milliseconds, rounded to the microsecond.
pub(crate) fn ms(d: Duration) -> f64 {
    (d.as_secs_f64() * 1e6).round() / 1e3
}

/// The `experiment` section every results.json opens with (paper, frequency-response
/// and setup runs alike).
#[derive(Serialize)]
pub(crate) struct Header<'a> {
    name: &'a str,
    description: &'a str,
    kind: &'static str,
    config_file: String,
    seed: u64,
    #[serde(skip_serializing_if = "Option::is_none")]
    threads: Option<usize>,
    crate_version: &'static str,
    #[serde(rename = "crate")]
    toolkit: &'static str,
}

impl<'a> Header<'a> {
    /// The section of a run of `config` (read from `config_path`) of `kind` with `seed`
    /// (and the Monte Carlo's `threads`, where there is one).
    pub(crate) fn new(
        config: &'a Config,
        config_path: &Path,
        kind: &'static str,
        seed: u64,
        threads: Option<usize>,
    ) -> Self {
        Self {
            name: &config.name,
            description: &config.description,
            kind,
            config_file: config_path
                .file_name()
                .map(|f| f.to_string_lossy().into_owned())
                .unwrap_or_default(),
            seed,
            threads,
            crate_version: CRATE_VERSION,
            toolkit: "msd-experiment (msd-toolkit)",
        }
    }
}

/// A kind's results document with its `schema_version` ([`SCHEMA_VERSION`]).
pub(crate) fn versioned(mut json: serde_json::Value) -> serde_json::Value {
    if let Some(object) = json.as_object_mut() {
        object.insert("schema_version".into(), SCHEMA_VERSION.into());
    }
    json
}

/// Writes `json` as `results.json` (pretty, with a final newline) into `staging`.
pub(crate) fn write_json(
    staging: &crate::output::Staging,
    json: &serde_json::Value,
) -> crate::error::Result<()> {
    let text =
        serde_json::to_string_pretty(json).map_err(|e| crate::ExperimentError::run("write", e))?;
    staging.write("results.json", format!("{text}\n").as_bytes())
}

/// The `timings_ms` of a run: each stage's wall time in ms, then `total`.
pub(crate) fn timings_ms(
    stages: &[(&'static str, std::time::Duration)],
    extra: &[(&'static str, std::time::Duration)],
    total: std::time::Duration,
) -> std::collections::BTreeMap<&'static str, f64> {
    let mut timings: std::collections::BTreeMap<&'static str, f64> = stages
        .iter()
        .chain(extra)
        .map(|(n, d)| (*n, d.as_secs_f64() * 1e3))
        .collect();
    timings.insert("total", total.as_secs_f64() * 1e3);
    timings
}

/// The head of every kind's report: its name and description, what the run identifies
/// from what (`what`, one sentence), and how it was run — the config, the command, the
/// seed where the run draws random numbers (synthetic data, a Monte Carlo band), the
/// toolkit's version and the kind's own `rows` (a method, the worker threads).
pub(crate) fn report_head(
    s: &mut String,
    run: (&crate::config::Config, &std::path::Path, &str),
    what: &str,
    seed: Option<u64>,
    rows: &[(&str, String)],
) -> std::fmt::Result {
    use std::fmt::Write;
    let (config, config_path, command) = run;
    writeln!(s, "# Experiment `{}`\n", config.name)?;
    if !config.description.is_empty() {
        writeln!(s, "{}\n", config.description.trim())?;
    }
    writeln!(s, "{}.\n", crate::fmt::capitalised(what))?;
    writeln!(s, "| run | |\n|---|---|")?;
    match config_path.file_name() {
        None => writeln!(s, "| config | built by the calling program (Rust API) |")?,
        Some(file) => {
            writeln!(s, "| config | `{}` |", file.to_string_lossy())?;
            writeln!(s, "| command | `{command} {}` |", config_path.display())?;
        }
    }
    if let Some(seed) = seed {
        writeln!(s, "| seed | {seed} |")?;
    }
    writeln!(s, "| toolkit version | {CRATE_VERSION} |")?;
    for (name, value) in rows {
        writeln!(s, "| {name} | {value} |")?;
    }
    writeln!(s)
}

/// The report's last section, the same for every kind: each stage's wall time (the
/// kind's `stages`, then the writer's `extra`) and the time since the run began.
pub(crate) fn report_timings(
    s: &mut String,
    stages: &[(&'static str, std::time::Duration)],
    extra: &[(&'static str, std::time::Duration)],
    elapsed: std::time::Duration,
) {
    use crate::fmt::millis;
    use std::fmt::Write;
    let _ = writeln!(s, "## Timings\n\n| stage | time [ms] |\n|---|---|");
    for (name, d) in stages.iter().chain(extra) {
        let _ = writeln!(
            s,
            "| {} | {} |",
            crate::summary::stage_label(name),
            millis(*d)
        );
    }
    let _ = writeln!(s, "| total before this report | {} |", millis(elapsed));
}
