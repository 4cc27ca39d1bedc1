//! The excitation-design rows (issue 22's speed target: `cargo xtask design` on the
//! paper plant, D-optimal, 60 lines, robust over 9 plants, ≤ 2 s): the shipped configs
//! `design-paper.toml` (the prior only) and `design-paper-robust.toml`, each designed
//! from its file as the command does (config, reference record, design, comparison;
//! nothing written).

use super::harness::{Budget, measure};
use super::report::{Row, Target};
use crate::{Result, project_root};
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
