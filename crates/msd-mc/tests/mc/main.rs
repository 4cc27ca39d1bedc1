//! Integration tests of msd-mc: bands, determinism, errors, Sobol, the paper experiment.

mod all_samples_failed;
mod band;
mod coverage;
mod errors;
mod paper;
mod sobol;

use msd_ident::{Backend, Estimate, EstimationOptions, PaperExperiment, estimate};
use std::sync::OnceLock;

/// The paper experiment (seed 0) and its fast (exact Levenberg–Marquardt) estimate.
pub fn paper() -> &'static (PaperExperiment, Estimate) {
    static PAPER: OnceLock<(PaperExperiment, Estimate)> = OnceLock::new();
    PAPER.get_or_init(|| {
        let experiment = PaperExperiment::generate(0).expect("paper data");
        let fit =
            estimate(&experiment.identification, &EstimationOptions::fast()).expect("estimate");
        (experiment, fit)
    })
}

/// Options for the exact backend with `samples` samples.
pub fn exact(samples: usize) -> msd_mc::McOptions {
    msd_mc::McOptions {
        samples,
        backend: Backend::EXACT,
        ..msd_mc::McOptions::default()
    }
}
