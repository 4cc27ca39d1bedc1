//! How the cost grows (issue 34): the shipped `repeats.toml` with 10, 20, 40, 80 and 200
//! records (data and estimation, the leave-one-record-out included; ≤ 5 s at 200), and
//! `plan --target 1e-5` on `paper.toml` with its record lengthened to 10⁴, 10⁵ and 10⁶
//! samples (≤ 2 s at 10⁶). Each variant is the shipped file with one key changed,
//! written into the bench folder.

use super::harness::{Budget, measure};
use super::report::{Row, Target};
use crate::config::Config;
use crate::progress::Progress;
use crate::{Result, project_root};
use msd_experiment::ExperimentError;
use msd_experiment::plan::{PlanOptions, plan_config};
use std::path::{Path, PathBuf};

/// At most three repetitions (one in a quick run): the largest sizes take seconds.
pub(super) fn few(budget: &Budget) -> Budget {
    Budget {
        time: std::time::Duration::ZERO,
        min_reps: budget.min_reps.min(3),
        max_reps: budget.min_reps.min(3),
    }
}

/// `configs/<file>` with its first line starting `key =` set to `key = value`, written
/// into `dir` as `<stem>-<tag>.toml`.
fn variant(dir: &Path, file: &str, key: &str, value: &str, tag: usize) -> Result<PathBuf> {
    let shipped = project_root().join("configs").join(file);
    let fail = |e: std::io::Error| ExperimentError::run("bench: growth", e);
    let text = std::fs::read_to_string(&shipped).map_err(fail)?;
    let mut done = false;
    let lines: Vec<String> = text
        .lines()
        .map(|line| match line.trim_start().strip_prefix(key) {
            Some(rest) if !done && rest.trim_start().starts_with('=') => {
                done = true;
                format!("{key} = {value}")
            }
            _ => line.to_string(),
        })
        .collect();
    if !done {
        return Err(ExperimentError::run(
            "bench: growth",
            format!("no `{key} =` in {}", shipped.display()),
        ));
    }
    std::fs::create_dir_all(dir).map_err(fail)?;
    let stem = file.trim_end_matches(".toml");
    let path = dir.join(format!("{stem}-{tag}.toml"));
    std::fs::write(&path, lines.join("\n") + "\n").map_err(fail)?;
    Ok(path)
}

/// The repeats and plan rows.
pub fn growth_rows(budget: &Budget, dir: &Path) -> Result<Vec<Row>> {
    let budget = few(budget);
    let mut rows = Vec::new();
    let (options, progress) = (crate::RunOptions::default(), Progress::new(false));
    for records in [10usize, 20, 40, 80, 200] {
        let path = variant(
            dir,
            "repeats.toml",
            "records",
            &records.to_string(),
            records,
        )?;
        let config = Config::load(&path)?;
        let run = || {
            msd_experiment::setup::run(
                msd_experiment::config::Spec::new(config.clone())?,
                &options,
                &progress,
            )
        };
        run()?;
        let row = Row::new(
            "growth",
            format!("repeats.toml, {records} records: data and joint fit, leave-one-out"),
            measure(&budget, || run().ok()),
        );
        rows.push(match records {
            200 => row.target(Target::Seconds(5.0)),
            _ => row,
        });
    }
    let plan = PlanOptions {
        target: 1e-5,
        ..PlanOptions::default()
    };
    for samples in [10_000usize, 100_000, 1_000_000] {
        let duration = format!("{}", (samples - 1) as f64 * 0.002);
        let path = variant(dir, "paper.toml", "duration", &duration, samples)?;
        let config = Config::load(&path)?;
        plan_config(&config, &path, &plan)?;
        let row = Row::new(
            "growth",
            format!("plan --target 1e-5, paper.toml with {samples} samples"),
            measure(&budget, || plan_config(&config, &path, &plan).ok()),
        );
        rows.push(match samples {
            1_000_000 => row.target(Target::Seconds(2.0)),
            _ => row,
        });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The variants the rows time are the shipped files with the one key changed, and
    /// they load.
    #[test]
    fn the_variants_change_one_key_and_load() {
        let dir = tempfile::tempdir().unwrap();
        let path = variant(dir.path(), "paper.toml", "duration", "19.998", 10_000).unwrap();
        let config = Config::load(&path).unwrap();
        assert_eq!(config.time.map(|t| t.samples()), Some(10_000));
        let path = variant(dir.path(), "repeats.toml", "records", "10", 10).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text.lines().filter(|l| *l == "records = 10").count(), 1);
        Config::load(&path).unwrap();
        assert!(variant(dir.path(), "paper.toml", "no_such_key", "1", 1).is_err());
    }
}
