//! Every rejected input gives its specific error.

use crate::exact;
use msd_ident::{Excitation, IdentError, Parameters};
use msd_mc::{
    Distribution, McError, McOptions, Sampling, SobolOptions, monte_carlo_band, sobol_indices,
};

fn run(options: &McOptions) -> Result<msd_mc::Band, McError> {
    let step = Excitation::from_samples(0.0, 0.01, vec![1.0; 50]).unwrap();
    monte_carlo_band(&Parameters::PAPER, &step, None, options)
}

#[test]
fn bad_band_options_are_rejected_with_their_reason() {
    let with = |f: &dyn Fn(&mut McOptions)| {
        let mut o = exact(10);
        f(&mut o);
        run(&o).unwrap_err()
    };
    assert_eq!(with(&|o| o.samples = 0), McError::ZeroSamples);
    assert_eq!(with(&|o| o.threads = 0), McError::ZeroThreads);
    for percent in [0.0, -5.0, 100.0, 150.0, f64::NAN] {
        let err = with(&|o| o.sampling = Sampling::Uniform { percent });
        assert!(
            matches!(err, McError::InvalidPercent { .. }),
            "{percent}: {err}"
        );
    }
    assert_eq!(
        with(&|o| o.sampling = Sampling::Uniform { percent: 100.0 }).to_string(),
        "invalid uniform half-width 100 %: expected 0 < p < 100"
    );
    assert_eq!(
        with(&|o| o.percentiles = vec![5.0, 101.0]),
        McError::PercentileOutOfRange {
            index: 1,
            value: 101.0
        }
    );
    assert_eq!(
        with(&|o| o.percentiles = vec![-1.0]),
        McError::PercentileOutOfRange {
            index: 0,
            value: -1.0
        }
    );
    let err = with(&|o| o.percentiles = vec![5.0, 95.0, 50.0]);
    assert_eq!(
        err,
        McError::UnorderedPercentiles {
            index: 2,
            previous: 95.0,
            value: 50.0
        }
    );
    assert_eq!(
        err.to_string(),
        "percentiles must be strictly increasing: 95 is followed by 50 at 2"
    );
    assert_eq!(
        with(&|o| o.percentiles = vec![50.0, 50.0]),
        McError::UnorderedPercentiles {
            index: 1,
            previous: 50.0,
            value: 50.0
        }
    );
    assert_eq!(with(&|o| o.percentiles.clear()), McError::NoPercentiles);
    assert_eq!(
        with(&|o| o.sampling = Sampling::Covariance {
            covariance: [[1.0; 3]; 3],
            scale: 0.0
        }),
        McError::InvalidScale { scale: 0.0 }
    );
    let indefinite = [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]];
    assert!(matches!(
        with(&|o| o.sampling = Sampling::Covariance {
            covariance: indefinite,
            scale: 1.0
        }),
        McError::NotPositiveSemidefinite { pivot: 1, .. }
    ));
    assert_eq!(
        with(&|o| o.max_buffer_bytes = 1407),
        McError::BudgetTooSmall {
            budget: 1407,
            samples: 10,
            needed: 1408 // a group of 64: 64 values and 24 envelope values, twice
        }
    );
}

#[test]
fn bad_data_are_rejected() {
    let step = Excitation::from_samples(0.0, 0.01, vec![1.0; 50]).unwrap();
    let err =
        monte_carlo_band(&Parameters::PAPER, &step, Some(&[0.0; 49]), &exact(10)).unwrap_err();
    assert_eq!(
        err,
        McError::LengthMismatch {
            what: "measurements",
            expected: 50,
            got: 49
        }
    );
    let bad = Parameters {
        mass: -1.0,
        ..Parameters::PAPER
    };
    let err = monte_carlo_band(&bad, &step, None, &exact(10)).unwrap_err();
    assert!(matches!(
        err,
        McError::Ident(IdentError::InvalidParameter { name: "mass", .. })
    ));
}

#[test]
fn bad_sobol_options_are_rejected() {
    let inputs = [Distribution::Uniform {
        low: 0.0,
        high: 1.0,
    }];
    let model = |x: &[f64]| vec![x[0]];
    let with = |f: &dyn Fn(&mut SobolOptions)| {
        let mut o = SobolOptions {
            samples: 20,
            bootstrap: 10,
            ..SobolOptions::default()
        };
        f(&mut o);
        sobol_indices(model, &inputs, &["y"], &o).unwrap_err()
    };
    assert_eq!(with(&|o| o.samples = 0), McError::ZeroSamples);
    assert_eq!(with(&|o| o.threads = 0), McError::ZeroThreads);
    assert!(matches!(
        with(&|o| o.bootstrap = 3),
        McError::InvalidOption {
            name: "bootstrap",
            ..
        }
    ));
    assert!(matches!(
        with(&|o| o.confidence = 1.0),
        McError::InvalidOption {
            name: "confidence",
            ..
        }
    ));
    let options = SobolOptions {
        samples: 20,
        bootstrap: 10,
        ..SobolOptions::default()
    };
    let flat = [Distribution::Uniform {
        low: 1.0,
        high: 1.0,
    }];
    assert!(matches!(
        sobol_indices(model, &flat, &["y"], &options),
        Err(McError::InvalidOption {
            name: "uniform width",
            ..
        })
    ));
    assert_eq!(
        sobol_indices(|_: &[f64]| vec![1.0, 2.0], &inputs, &["y"], &options),
        Err(McError::ModelOutputLength {
            evaluation: 0,
            expected: 1,
            got: 2
        })
    );
    assert!(matches!(
        sobol_indices(
            |x: &[f64]| vec![1.0 / (x[0] - x[0])],
            &inputs,
            &["y"],
            &options
        ),
        Err(McError::NonFiniteOutput {
            evaluation: 0,
            quantity: 0,
            ..
        })
    ));
}

/// A panic in the caller's model inside a worker becomes `WorkerPanicked`, naming the
/// lowest row that panicked whatever the thread count, instead of tearing down the pool.
#[test]
fn a_panicking_model_is_an_error_not_a_crash() {
    let inputs = [Distribution::Uniform {
        low: 0.0,
        high: 1.0,
    }; 2];
    let model = |x: &[f64]| -> Vec<f64> {
        assert!(x[0] < 0.95, "model blew up at x0 = {}", x[0]);
        vec![x[0] + x[1]]
    };
    let mut rows = Vec::new();
    for threads in [1, 2] {
        let options = SobolOptions {
            samples: 200,
            threads,
            ..SobolOptions::default()
        };
        match sobol_indices(model, &inputs, &["y"], &options) {
            Err(McError::WorkerPanicked { row, message }) => {
                assert!(message.contains("model blew up"), "{message}");
                rows.push(row);
            }
            other => panic!("{threads} threads: {other:?}"),
        }
    }
    assert_eq!(rows[0], rows[1]);
    // The pool is still usable afterwards.
    let fine = sobol_indices(
        |x: &[f64]| vec![x[0]],
        &inputs,
        &["y"],
        &SobolOptions::default(),
    );
    assert!(fine.is_ok());
}
