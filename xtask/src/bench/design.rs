//! The excitation-design rows (issue 22's speed target: `cargo xtask design` on the
//! paper plant, D-optimal, 60 lines, robust over 9 plants, ≤ 2 s): the shipped configs
//! `design-paper.toml` (the prior only) and `design-paper-robust.toml`, each designed
//! from its file as the command does (config, reference record, design, comparison;
//! nothing written); and `design-paper.toml` with its record lengthened to 10⁴, 10⁵ and
//! 10⁶ samples (issue 34: ≤ 10 s at 10⁶).

use super::harness::{Budget, measure};
use super::report::{Row, Target};
use crate::{Result, project_root};
use msd_experiment::ExperimentError;
use msd_experiment::design::{DesignRunOptions, design};

/// One row per shipped D-optimal config: the prior only, and robust over 9 plants.
pub fn design_rows(budget: &Budget) -> Result<Vec<Row>> {
    let mut rows = Vec::new();
    for (file, what) in [
        ("design-paper.toml", "the prior only"),
        ("design-paper-robust.toml", "robust over 9 plants"),
    ] {
        let path = project_root().join("configs").join(file);
        let options = DesignRunOptions::default();
        let report = design(&path, &options)?;
        let d = &report.design;
        rows.push(
            Row::new(
                "design",
                format!(
                    "{file}: D-optimal, {} lines, {what}",
                    d.frequencies_hz.len()
                ),
                measure(budget, || design(&path, &options).ok()),
            )
            .target(Target::Seconds(2.0))
            .note(format!(
                "det ratio {:.3} on the prior, {} L-BFGS iterations",
                d.comparison.determinant_ratio, d.iterations
            )),
        );
    }
    Ok(rows)
}

/// `design-paper.toml` with its records lengthened to 10⁴, 10⁵ and 10⁶ samples (written
/// into `dir`): the design's cost against the record's length. At most three
/// repetitions (one in a quick run): the longest takes seconds.
pub fn design_scaling(budget: &Budget, dir: &std::path::Path) -> Result<Vec<Row>> {
    let shipped = project_root().join("configs").join("design-paper.toml");
    let text = std::fs::read_to_string(&shipped)
        .map_err(|e| ExperimentError::run("bench: design-paper.toml", e))?;
    std::fs::create_dir_all(dir).map_err(|e| ExperimentError::run("bench: write", e))?;
    let budget = super::growth::few(budget);
    let mut rows = Vec::new();
    for samples in [10_000usize, 100_000, 1_000_000] {
        let duration = (samples - 1) as f64 * 0.002;
        let path = dir.join(format!("design-paper-{samples}.toml"));
        let config = text.replace("duration = 15.0", &format!("duration = {duration}"));
        std::fs::write(&path, config).map_err(|e| ExperimentError::run("bench: write", e))?;
        let options = DesignRunOptions::default();
        let report = design(&path, &options)?;
        let target = (samples == 1_000_000).then_some(Target::Seconds(10.0));
        let mut row = Row::new(
            "design",
            format!("design-paper.toml, {samples} samples"),
            measure(&budget, || design(&path, &options).ok()),
        )
        .note(format!(
            "det ratio {:.3}, {} evaluations",
            report.design.comparison.determinant_ratio, report.design.evaluations
        ));
        if let Some(target) = target {
            row = row.target(target);
        }
        rows.push(row);
    }
    Ok(rows)
}
