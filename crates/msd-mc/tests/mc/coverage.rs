//! The intervals' coverage under a noisy load cell (issue 42's test, with fewer seeds
//! than `cargo xtask noise-study`'s 400).
//!
//! Tolerances: with n seeds and correct standard errors, z = (estimate − truth)/SE is
//! about standard normal, so Σz²/n ~ χ²ₙ/n, whose standard deviation is √(2/n); the
//! bounds are ±3 of those around 1 for rms z. The white-noise fit must fall outside them
//! (the issue measured its rms z at 2–5 with 1 % noise), else the test would not tell.

use msd_ident::records::NoiseModel;
use msd_mc::coverage::{CoverageOptions, Setup, coverage_study};

fn bounds(seeds: usize) -> (f64, f64) {
    let sd = (2.0 / seeds as f64).sqrt();
    ((1.0 - 3.0 * sd).max(0.0).sqrt(), (1.0 + 3.0 * sd).sqrt())
}

/// `setup` at 1 % drive noise over `seeds` seeds: `count` quantities, each rms z within
/// the bounds, the noise detected; returns the white-noise fit's study and the upper bound.
fn covers(setup: Setup, seeds: usize, count: usize) -> (msd_mc::coverage::CoverageStudy, f64) {
    let options = CoverageOptions {
        setup,
        drive_noise: 0.01,
        seeds,
        ..CoverageOptions::default()
    };
    let study = coverage_study(&options).expect("study");
    let (low, high) = bounds(seeds);
    assert_eq!(study.quantities.len(), count, "{study}");
    for q in &study.quantities {
        assert!(q.rms_z > low && q.rms_z < high, "{study}");
    }
    assert!(study.drive_noise_detected > 0.9, "{study}");
    let white = coverage_study(&CoverageOptions {
        noise_model: NoiseModel::White,
        ..options
    })
    .expect("study");
    (white, high)
}

#[test]
fn a_noisy_load_cell_gets_intervals_that_cover() {
    let (white, high) = covers(Setup::Accelerometer, 30, 5);
    let damping = white
        .quantities
        .iter()
        .find(|q| q.name == "damping")
        .expect("c");
    assert!(
        damping.rms_z > high,
        "the white fit's intervals are too narrow: {white}"
    );
}

#[test]
fn the_study_is_the_same_for_any_thread_count() {
    let options = CoverageOptions {
        setup: Setup::Repeats,
        seeds: 3,
        threads: 1,
        ..CoverageOptions::default()
    };
    let one = coverage_study(&options).expect("study");
    let two = coverage_study(&CoverageOptions {
        threads: 2,
        ..options
    })
    .expect("study");
    assert_eq!(one.quantities, two.quantities);
}

/// The two-storey chain under a load cell with 1 % noise: every m, c, k, fn and ζ within
/// the bounds; the white-noise fit's far outside (rms z 7–20 measured).
#[test]
fn a_noisy_load_cell_on_a_chain_gets_intervals_that_cover() {
    let (white, high) = covers(Setup::TwoStorey, 40, 10);
    assert!(
        white.quantities.iter().all(|q| q.rms_z > high),
        "the white fit's intervals are too narrow: {white}"
    );
}

/// The chain under a load cell with 3 % noise: the drive's noise found without bias
/// (the mean σ̂_u within 3 standard errors of the mean of 3 %; the likelihood of the
/// noise itself, before the restricted correction, gives 2.86 % ± 0.02 % here, 10
/// standard errors low), and the intervals hold.
#[test]
fn a_chains_drive_noise_is_estimated_without_bias() {
    let seeds = 40;
    let study = coverage_study(&CoverageOptions {
        setup: Setup::TwoStorey,
        drive_noise: 0.03,
        seeds,
        ..CoverageOptions::default()
    })
    .expect("study");
    let se = study.sd_drive_noise_estimate / (seeds as f64).sqrt();
    assert!(
        (study.mean_drive_noise_estimate - 0.03).abs() < 3.0 * se,
        "σ̂_u {} ± {se}: {study}",
        study.mean_drive_noise_estimate
    );
    let (low, high) = bounds(seeds);
    for q in &study.quantities {
        assert!(q.rms_z > low && q.rms_z < high, "{study}");
    }
}
