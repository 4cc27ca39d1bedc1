//! Coverage of output-only analysis's intervals over seeds (issue 43): pyOMA2's
//! five-storey shear building (25.91 kg floors on 10 kN/m storeys, ζ = 2 % in every mode,
//! white-noise forces, accelerations at 100 Hz with 10 % noise, 30,001 samples), analysed
//! by `ssi_cov` (or `--method ssi-dat` / `efdd`) at default settings; for each true mode, how often it is found (within
//! 2 %), how often the 95 % intervals of fn and ζ hold the truth, and the spread of the
//! estimates over their reported standard errors.

use msd_experiment::ExperimentError;
use msd_modal::{FddOptions, OmaMethod, OmaOptions, ShearBuilding, efdd, ssi_cov, ssi_dat};
use rayon::prelude::*;
use serde::Serialize;
use std::path::Path;

/// One true mode over the seeds.
#[derive(Debug, Clone, Serialize)]
pub struct ModeCoverage {
    /// The true natural frequency, Hz.
    pub true_hz: f64,
    /// Seeds whose fit reports it.
    pub found: usize,
    /// Share of those whose 95 % interval of fn holds the truth.
    pub coverage_fn: f64,
    /// Idem for ζ.
    pub coverage_zeta: f64,
    /// Standard deviation of (estimate − truth)/SE of fn over the seeds (1 when the
    /// standard errors are right; Student's t with 7 dof gives 1.18).
    pub z_sd_fn: f64,
    /// Idem for ζ.
    pub z_sd_zeta: f64,
}

/// The study: the seeds and every mode's coverage.
#[derive(Debug, Clone, Serialize)]
pub struct OmaStudy {
    /// Records analysed.
    pub seeds: usize,
    /// The method studied.
    pub method: String,
    /// Per true mode.
    pub modes: Vec<ModeCoverage>,
    /// Seeds whose fit reported a mode that is not a true one.
    pub seeds_with_extra_modes: usize,
}

/// Runs `seeds` records through `method` at default settings on `threads` workers.
pub fn run(seeds: usize, threads: usize, method: OmaMethod) -> Result<OmaStudy, ExperimentError> {
    let building = ShearBuilding {
        masses: vec![25.91; 5],
        stiffnesses: vec![10_000.0; 5],
        damping_ratio: 0.02,
    };
    let fail = |e: msd_modal::ModalError| ExperimentError::run("oma-study", e);
    let truth: Vec<f64> = building
        .modes()
        .map_err(fail)?
        .into_iter()
        .map(|(f, _)| f)
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.max(1))
        .build()
        .map_err(|e| ExperimentError::run("oma-study", e))?;
    // Per seed: for each true mode, (z of fn, z of ζ, fn inside, ζ inside) if found; and
    // whether an extra mode was reported.
    type Seed = (Vec<Option<(f64, f64, bool, bool)>>, bool);
    let per_seed: Vec<Result<Seed, ExperimentError>> = pool.install(|| {
        (0..seeds as u64)
            .into_par_iter()
            .map(|seed| {
                let mut draws = msd_signal::gaussian_noise(seed, "oma-study", 1.0, 30_001 * 10)
                    .map_err(|e| ExperimentError::run("oma-study", e))?
                    .into_iter();
                let record = building
                    .ambient_record(100.0, 30_001, 0.1, || draws.next().unwrap_or(0.0))
                    .map_err(fail)?;
                let fit = match method {
                    OmaMethod::SsiCov => ssi_cov(&record, &OmaOptions::default()),
                    OmaMethod::SsiDat => ssi_dat(&record, &OmaOptions::default()),
                    OmaMethod::Efdd => efdd(&record, &FddOptions::default()),
                }
                .map_err(fail)?;
                let found = truth
                    .iter()
                    .map(|&f| {
                        fit.modes
                            .iter()
                            .find(|m| (m.natural_frequency_hz.value / f - 1.0).abs() < 0.02)
                            .map(|m| {
                                let (fi, zi) = (&m.natural_frequency_hz, &m.damping_ratio);
                                (
                                    (fi.value - f) / fi.standard_error,
                                    (zi.value - 0.02) / zi.standard_error,
                                    fi.contains(f),
                                    zi.contains(0.02),
                                )
                            })
                    })
                    .collect();
                let extra = fit.modes.iter().any(|m| {
                    !truth
                        .iter()
                        .any(|&f| (m.natural_frequency_hz.value / f - 1.0).abs() < 0.02)
                });
                Ok((found, extra))
            })
            .collect()
    });
    let per_seed: Vec<Seed> = per_seed.into_iter().collect::<Result<_, _>>()?;
    let modes = truth
        .iter()
        .enumerate()
        .map(|(j, &true_hz)| {
            let hits: Vec<(f64, f64, bool, bool)> =
                per_seed.iter().filter_map(|(s, _)| s[j]).collect();
            let n = hits.len().max(1) as f64;
            let share = |pick: fn(&(f64, f64, bool, bool)) -> bool| {
                hits.iter().filter(|h| pick(h)).count() as f64 / n
            };
            let sd = |pick: fn(&(f64, f64, bool, bool)) -> f64| {
                let mean = hits.iter().map(pick).sum::<f64>() / n;
                (hits.iter().map(|h| (pick(h) - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0))
                    .sqrt()
            };
            ModeCoverage {
                true_hz,
                found: hits.len(),
                coverage_fn: share(|h| h.2),
                coverage_zeta: share(|h| h.3),
                z_sd_fn: sd(|h| h.0),
                z_sd_zeta: sd(|h| h.1),
            }
        })
        .collect();
    Ok(OmaStudy {
        method: method.to_string(),
        seeds,
        modes,
        seeds_with_extra_modes: per_seed.iter().filter(|s| s.1).count(),
    })
}

impl std::fmt::Display for OmaStudy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "{}, {} seeds", self.method, self.seeds)?;
        writeln!(
            f,
            "| true fn [Hz] | found | coverage fn | coverage ζ | sd of z, fn | sd of z, ζ |\n|---|---|---|---|---|---|"
        )?;
        for m in &self.modes {
            writeln!(
                f,
                "| {:.4} | {}/{} | {:.3} | {:.3} | {:.2} | {:.2} |",
                m.true_hz,
                m.found,
                self.seeds,
                m.coverage_fn,
                m.coverage_zeta,
                m.z_sd_fn,
                m.z_sd_zeta
            )?;
        }
        write!(
            f,
            "seeds with a mode that is not a true one: {}",
            self.seeds_with_extra_modes
        )
    }
}

/// Writes `study.json` into `dir`.
pub fn write(study: &OmaStudy, dir: &Path) -> Result<(), ExperimentError> {
    let fail = |e: std::io::Error| ExperimentError::run("oma-study", e);
    std::fs::create_dir_all(dir).map_err(fail)?;
    let json =
        serde_json::to_string_pretty(study).map_err(|e| ExperimentError::run("oma-study", e))?;
    std::fs::write(dir.join("study.json"), json).map_err(fail)
}
