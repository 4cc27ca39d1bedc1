//! A band in which no sample can be used is an error that names the count and the
//! first sample's reason, never an empty or NaN band.

use msd_ident::{Backend, Excitation, Parameters};
use msd_mc::{MAX_REDRAWS, McError, McOptions, SampleFailure, Sampling, monte_carlo_band};

/// A covariance of (m, c, k) in which m and k are perfectly anti-correlated with a
/// standard deviation of 1e10 around m = 2.5, k = 120: a draw is physical only if
/// −2.5e-10 < z < 1.2e-8 for its standard normal z, probability ≈ 5e-9 per draw. With
/// 1 + MAX_REDRAWS draws per sample, no sample of a few dozen gets a physical draw
/// (odds ≈ 1e-5 of a single one; the seed is fixed, so the outcome is too).
fn hopeless_covariance() -> Sampling {
    let s2 = 1e20;
    Sampling::Covariance {
        covariance: [[s2, 0.0, -s2], [0.0, 0.0, 0.0], [-s2, 0.0, s2]],
        scale: 1.0,
    }
}

#[test]
fn no_physical_draw_in_any_sample_is_all_samples_failed() {
    let excitation = Excitation::from_samples(0.0, 0.01, vec![1.0; 200]).unwrap();
    for threads in [1, 2] {
        let options = McOptions {
            samples: 24,
            sampling: hopeless_covariance(),
            threads,
            seed: 3,
            backend: Backend::EXACT,
            ..McOptions::default()
        };
        let err = monte_carlo_band(&Parameters::PAPER, &excitation, None, &options)
            .expect_err("no sample is physical");
        assert_eq!(
            err,
            McError::AllSamplesFailed {
                samples: 24,
                first: SampleFailure::NonPhysical {
                    redraws: MAX_REDRAWS
                },
            },
            "{threads} threads"
        );
        assert_eq!(
            err.to_string(),
            format!(
                "all 24 samples failed; the first: non-physical draw after {MAX_REDRAWS} redraws"
            )
        );
    }
}

/// The same covariance with a sensible scale gives a band: the failure above is the
/// covariance's doing, not the setup's.
#[test]
fn the_same_setup_with_a_narrow_covariance_gives_a_band() {
    let excitation = Excitation::from_samples(0.0, 0.01, vec![1.0; 200]).unwrap();
    let options = McOptions {
        samples: 24,
        sampling: Sampling::Covariance {
            covariance: [[1e-4, 0.0, -1e-4], [0.0, 0.0, 0.0], [-1e-4, 0.0, 1e-4]],
            scale: 1.0,
        },
        threads: 2,
        seed: 3,
        backend: Backend::EXACT,
        ..McOptions::default()
    };
    let band = monte_carlo_band(&Parameters::PAPER, &excitation, None, &options)
        .expect("a narrow covariance gives a band");
    assert_eq!(band.failed_samples, 0);
    assert!(band.lower().iter().all(|v| v.is_finite()));
}
