//! `cargo xtask noise-study`: msd-mc's coverage study over every setup and drive-noise
//! level, with the default noise model and the white one, as one table.

use msd_experiment::{ExperimentError, Result};
use msd_ident::records::NoiseModel;
use msd_mc::coverage::{CoverageOptions, CoverageStudy, Setup, coverage_study};
use std::fmt::Write as _;
use std::path::Path;

/// The drive-noise levels of the study, fractions of the drive's rms.
pub const LEVELS: [f64; 4] = [0.0, 0.003, 0.01, 0.03];

/// Runs every setup (of `setups`) × level (of `levels`) × noise model with `seeds` seeds, calling `each` as each
/// study ends.
pub fn run(
    seeds: usize,
    threads: usize,
    levels: &[f64],
    setups: &[Setup],
    mut each: impl FnMut(&CoverageStudy),
) -> Result<Vec<CoverageStudy>> {
    let mut studies = Vec::new();
    for &setup in setups {
        for &drive_noise in levels {
            for noise_model in [NoiseModel::InputNoise, NoiseModel::White] {
                let options = CoverageOptions {
                    setup,
                    drive_noise,
                    seeds,
                    noise_model,
                    threads,
                    ..CoverageOptions::default()
                };
                let study =
                    coverage_study(&options).map_err(|e| ExperimentError::run("noise-study", e))?;
                each(&study);
                studies.push(study);
            }
        }
    }
    Ok(studies)
}

/// The setups named (snake_case, as in `study.json`), or all of them when none is.
pub fn setups(names: &[String]) -> Result<Vec<Setup>> {
    if names.is_empty() {
        return Ok(Setup::ALL.to_vec());
    }
    let name_of = |s: &Setup| {
        serde_json::to_value(s)
            .ok()
            .and_then(|v| v.as_str().map(String::from))
    };
    names
        .iter()
        .map(|name| {
            Setup::ALL
                .into_iter()
                .find(|s| name_of(s).as_deref() == Some(name.as_str()))
                .ok_or_else(|| {
                    let known: Vec<String> = Setup::ALL.iter().filter_map(name_of).collect();
                    ExperimentError::run(
                        "noise-study",
                        format!("--setups {name}: expected one of {}", known.join(", ")),
                    )
                })
        })
        .collect()
}

/// The studies as a Markdown table: one row per study, coverage and rms z per quantity.
pub fn markdown(studies: &[CoverageStudy]) -> String {
    let mut s = String::from(
        "| setup | drive noise | noise model | quantity | coverage | rms z | spread/SE | detected | flagged |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for study in studies {
        let o = &study.options;
        for q in &study.quantities {
            let _ = writeln!(
                s,
                "| {} | {:.1} % | {:?} | {} | {:.3} | {:.2} | {:.2} | {:.2} | {:.2} |",
                o.setup.name(),
                100.0 * o.drive_noise,
                o.noise_model,
                q.name,
                q.coverage,
                q.rms_z,
                q.spread_over_se,
                study.drive_noise_detected,
                study.whiteness_flagged
            );
        }
    }
    s
}

/// Writes `study.json` and `study.md` into `dir`.
pub fn write(studies: &[CoverageStudy], dir: &Path) -> Result<()> {
    let fail = |path: &Path, e: std::io::Error| {
        ExperimentError::run("noise-study: write", format!("{}: {e}", path.display()))
    };
    std::fs::create_dir_all(dir).map_err(|e| fail(dir, e))?;
    let json = serde_json::to_string_pretty(studies)
        .map_err(|e| ExperimentError::run("noise-study", e))?;
    let path = dir.join("study.json");
    std::fs::write(&path, json).map_err(|e| fail(&path, e))?;
    let path = dir.join("study.md");
    std::fs::write(&path, markdown(studies)).map_err(|e| fail(&path, e))
}
