//! The memory bound, measured on a real run rather than on the plan: a band of
//! N = 100 000 samples of the paper's 7501-point validation response — 6.0 GB were the
//! responses stored — runs in well under 1 GiB.
//!
//! This file holds one test so that its process runs nothing else: the process's peak
//! resident memory (`VmHWM`, Linux) is then the band's.

use msd_ident::{Backend, PaperExperiment, Parameters};
use msd_mc::{McOptions, monte_carlo_band};

/// Peak resident memory of this process in bytes (Linux), `None` elsewhere.
fn peak_resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

#[test]
fn a_hundred_thousand_samples_of_the_paper_response_run_in_well_under_a_gibibyte() {
    let experiment = PaperExperiment::generate(0).expect("the paper experiment");
    let validation = &experiment.validation;
    let options = McOptions {
        samples: 100_000,
        backend: Backend::EXACT,
        ..McOptions::default()
    };
    let band = monte_carlo_band(
        &Parameters::PAPER,
        &validation.excitation,
        Some(&validation.output),
        &options,
    )
    .expect("the band");
    assert_eq!((band.samples, band.failed_samples), (100_000, 0));
    assert_eq!(band.lower().len(), 7501);
    // What the plan promises, and what the process took (the test binary and the
    // paper data included).
    assert!(band.memory.peak_bytes < 256 << 20, "{:?}", band.memory);
    if let Some(peak) = peak_resident_bytes() {
        assert!(peak < 512 << 20, "peak resident memory {} MiB", peak >> 20);
    }
    // A sane band: the 5th percentile below the 95th everywhere after the start.
    assert!(
        band.lower()[1..]
            .iter()
            .zip(&band.upper()[1..])
            .all(|(l, u)| l < u)
    );
}
