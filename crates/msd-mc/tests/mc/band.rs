//! Percentiles against a known distribution, determinism, covariance sampling, progress.

use crate::{exact, paper};
use msd_ident::{Excitation, Parameters};
use msd_mc::{Band, McOptions, Sampling, monte_carlo_band, monte_carlo_band_with_progress};
use std::sync::atomic::{AtomicUsize, Ordering};

/// A unit force held from rest on a critically damped plant (ωn = 20 rad/s) settles to
/// x = 1/k within 3 s (e^(−ζωn·t) < e^(−40) for every draw), so the last point is 1/k
/// with k ~ U(k₀(1 − p), k₀(1 + p)). Its q-quantile is 1/k at the k-quantile 1 − q, the
/// density of x is f(x) = k²/(2pk₀), and the sample quantile has standard error
/// √(q(1 − q)/N)/f; allow 5 standard errors plus the interpolation step 1/(N·f).
#[test]
fn percentiles_of_the_static_response_follow_the_uniform_stiffness() {
    let k0 = 400.0;
    let plant = Parameters::new(1.0, 40.0, k0).unwrap();
    let step = Excitation::from_samples(0.0, 0.01, vec![1.0; 301]).unwrap();
    let (n, p) = (4000, 0.2);
    let options = McOptions {
        sampling: Sampling::Uniform { percent: 100.0 * p },
        percentiles: vec![5.0, 25.0, 50.0, 75.0, 95.0],
        ..exact(n)
    };
    let band = monte_carlo_band(&plant, &step, None, &options).unwrap();
    assert_eq!(band.failed_samples, 0);
    for (level, values) in &band.percentiles {
        let q = level / 100.0;
        let k = k0 * (1.0 - p + 2.0 * p * (1.0 - q));
        let density = k * k / (2.0 * p * k0);
        let bound = 5.0 * (q * (1.0 - q) / n as f64).sqrt() / density + 1.0 / (n as f64 * density);
        let got = values[300];
        assert!(
            (got - 1.0 / k).abs() < bound,
            "P{level}: {got} vs {}",
            1.0 / k
        );
    }
    assert_eq!(band.median(), band.percentile(50.0));
    let width = band.upper()[300] - band.lower()[300];
    assert_eq!(band.width[300], width);
}

fn paper_band(threads: usize, seed: u64, max_buffer_bytes: usize) -> Band {
    let (experiment, fit) = paper();
    let options = McOptions {
        threads,
        seed,
        max_buffer_bytes,
        ..exact(200)
    };
    let v = &experiment.validation;
    monte_carlo_band(&fit.parameters, &v.excitation, Some(&v.output), &options).unwrap()
}

/// Everything but the bookkeeping (threads, memory plan) must agree to the bit.
fn assert_same(a: &Band, b: &Band) {
    assert_eq!(a.percentiles, b.percentiles);
    assert_eq!(a.width, b.width);
    assert_eq!(a.coverage, b.coverage);
    assert_eq!(a.nominal, b.nominal);
    assert_eq!(a.natural_frequency_hz, b.natural_frequency_hz);
    assert_eq!(a.damping_ratio, b.damping_ratio);
    assert_eq!(a.failed_samples, b.failed_samples);
}

#[test]
fn identical_for_1_2_and_8_threads_any_chunking_and_repeated_runs() {
    let reference = paper_band(1, 5, 256 << 20);
    for threads in [2, 8] {
        assert_same(&reference, &paper_band(threads, 5, 256 << 20));
    }
    // 100 columns per chunk (200 samples are 4 groups of 64, 1408 bytes each a column):
    // 76 chunks, where the default makes 41; and one column per chunk: 7501.
    assert_eq!(reference.memory.chunks, 41);
    let chunked = paper_band(2, 5, 1408 * 4 * 100);
    assert_eq!(chunked.memory.chunks, 76);
    assert_same(&reference, &chunked);
    let column_by_column = paper_band(2, 5, 1408 * 4);
    assert_eq!(column_by_column.memory.chunks, 7501);
    assert_same(&reference, &column_by_column);
    assert_same(&reference, &paper_band(1, 5, 256 << 20));
    let other_seed = paper_band(2, 6, 256 << 20);
    assert_ne!(reference.percentiles, other_seed.percentiles);
}

/// Normal draws from the estimated covariance: the spread of fn matches the delta-method
/// standard error (the relative standard error of a sample std is ≈ 1/√(2N); allow 5).
#[test]
fn covariance_sampling_reproduces_the_estimated_spread() {
    let (experiment, fit) = paper();
    let n = 1000;
    let options = McOptions {
        sampling: Sampling::from_uncertainty(&fit.uncertainty, 1.0),
        ..exact(n)
    };
    let v = &experiment.validation;
    let band = monte_carlo_band(&fit.parameters, &v.excitation, None, &options).unwrap();
    let expected = fit.uncertainty.natural_frequency_hz.standard_error;
    let got = band.natural_frequency_hz.std;
    assert!(
        (got / expected - 1.0).abs() < 5.0 / (2.0 * n as f64).sqrt(),
        "{got} vs {expected}"
    );
    let mean = band.natural_frequency_hz.mean;
    let fnat = fit.parameters.natural_frequency_hz();
    assert!((mean - fnat).abs() < 5.0 * expected / (n as f64).sqrt());
}

/// With a damping standard deviation of 2c, about a third of the raw draws have c < 0;
/// they are redrawn, so every kept sample is physical and none fails.
#[test]
fn non_physical_covariance_draws_are_redrawn() {
    let plant = Parameters::PAPER;
    let c = plant.damping;
    let covariance = [[0.0, 0.0, 0.0], [0.0, 4.0 * c * c, 0.0], [0.0, 0.0, 0.0]];
    let step = Excitation::from_samples(0.0, 0.01, vec![1.0; 100]).unwrap();
    let options = McOptions {
        sampling: Sampling::Covariance {
            covariance,
            scale: 1.0,
        },
        ..exact(500)
    };
    let band = monte_carlo_band(&plant, &step, None, &options).unwrap();
    assert_eq!(band.failed_samples, 0);
    assert!(band.damping_ratio.min >= 0.0);
    assert!(band.natural_frequency_hz.std < 1e-12); // m and k fixed (rounding only)
}

/// Progress counts samples × chunks: one call per block of 8 samples per chunk, ending
/// at the total.
#[test]
fn progress_reports_every_block_and_chunk() {
    let step = Excitation::from_samples(0.0, 0.01, vec![1.0; 100]).unwrap();
    let options = McOptions {
        max_buffer_bytes: 1408 * 5 * 30, // 300 samples are 5 groups: 30 columns a chunk
        ..exact(300)
    };
    let calls = AtomicUsize::new(0);
    let last = AtomicUsize::new(0);
    let progress = |done: usize, total: usize| {
        assert_eq!(total, 1200);
        assert!(done <= total);
        calls.fetch_add(1, Ordering::Relaxed);
        last.fetch_max(done, Ordering::Relaxed);
    };
    let band = monte_carlo_band_with_progress(&Parameters::PAPER, &step, None, &options, &progress)
        .unwrap();
    assert_eq!(band.memory.chunks, 4);
    assert_eq!(calls.into_inner(), 300usize.div_ceil(8) * 4);
    assert_eq!(last.into_inner(), 1200);
}

#[test]
fn display_names_the_run() {
    let step = Excitation::from_samples(0.0, 0.01, vec![1.0; 100]).unwrap();
    let band = monte_carlo_band(&Parameters::PAPER, &step, Some(&[0.0; 100]), &exact(50)).unwrap();
    let text = band.to_string();
    assert!(
        text.starts_with(
            "Monte Carlo band: 50 samples (0 failed), 2 threads, exact backend, 1 time chunk(s)"
        ),
        "{text}"
    );
    assert!(text.contains("percentiles: 5, 50, 95 %"));
    assert!(text.contains("coverage: "));
}

/// A band serializes whole: its percentile curves as (level, values) pairs, its
/// summaries, its settings and its memory plan.
#[test]
fn a_band_serializes_its_curves_summaries_and_settings() -> Result<(), Box<dyn std::error::Error>> {
    let (experiment, fit) = paper();
    let validation = &experiment.validation;
    let options = exact(20);
    let band = monte_carlo_band(
        &fit.parameters,
        &validation.excitation,
        Some(&validation.output),
        &options,
    )?;
    let json = serde_json::to_value(&band)?;
    assert_eq!(json["samples"], 20);
    assert_eq!(
        json["percentiles"][0][0],
        serde_json::json!(options.percentiles[0])
    );
    assert_eq!(
        json["percentiles"][0][1].as_array().map(Vec::len),
        Some(validation.len())
    );
    assert_eq!(
        json["natural_frequency_hz"]["mean"],
        serde_json::json!(band.natural_frequency_hz.mean)
    );
    assert_eq!(json["backend"]["kind"], "exact");
    assert_eq!(json["memory"]["points"], validation.len());
    assert_eq!(serde_json::from_value::<Band>(json)?, band);
    Ok(())
}
