//! Faults inside a multistart: a local run that panics on a rayon worker is caught and
//! returned as a specific error, on any thread count; nothing unwinds into the caller.

use msd_opt::{
    Bounds, LevenbergMarquardtOptions, MultistartOptions, NelderMeadOptions, OptError, ResidualFn,
    levenberg_marquardt, multistart, nelder_mead,
};

fn bowl(x: &[f64]) -> f64 {
    x.iter().map(|v| (v - 0.3) * (v - 0.3)).sum()
}

fn bounds() -> Bounds {
    Bounds::new(vec![-1.0, -1.0], vec![1.0, 1.0]).unwrap()
}

/// A cost that panics (as a buggy model would, e.g. an index out of range) for points
/// in the left half of the box, on every thread count: the error names the lowest
/// such start and the panic's message, and the call returns normally.
#[test]
fn a_panicking_cost_on_a_worker_is_a_worker_panicked_error() {
    for threads in [1, 2, 4] {
        let options = MultistartOptions {
            starts: 12,
            seed: 5,
            threads,
            ..Default::default()
        };
        let points = msd_opt::starting_points(&bounds(), &options).unwrap();
        let first_bad = points
            .iter()
            .position(|p| p[0] < 0.0)
            .expect("a left point");
        let result = multistart(&bounds(), &options, |x0| {
            nelder_mead(
                |x: &[f64]| {
                    if x0[0] < 0.0 {
                        let data: Vec<f64> = Vec::new();
                        return data[x.len()]; // panics: index out of bounds
                    }
                    bowl(x)
                },
                x0,
                &NelderMeadOptions::default(),
            )
        });
        match result {
            Err(OptError::WorkerPanicked { start, message }) => {
                assert_eq!(start, first_bad, "{threads} threads");
                assert!(
                    message.contains("index out of bounds"),
                    "{threads} threads: {message}"
                );
            }
            other => panic!("{threads} threads: expected WorkerPanicked, got {other:?}"),
        }
    }
}

/// A `String` payload (`panic!("{}", …)`) is reported too, through Levenberg–Marquardt,
/// and the error's text says which start and why.
#[test]
fn a_formatted_panic_in_a_residual_function_is_reported_with_its_message() {
    let options = MultistartOptions {
        starts: 4,
        seed: 1,
        threads: 2,
        ..Default::default()
    };
    let err = multistart(&bounds(), &options, |x0| {
        let mut problem = ResidualFn::new(2, |x: &[f64], r: &mut [f64]| {
            if x[1] > 2.0 {
                panic!("model diverged at x1 = {}", x[1]);
            }
            r[0] = x[0] - 0.3;
            r[1] = 10.0 * (x[1] - 5.0); // pulls x1 past 2: every start panics
            true
        });
        levenberg_marquardt(&mut problem, x0, &LevenbergMarquardtOptions::default())
    })
    .expect_err("every start panics");
    assert!(
        matches!(err, OptError::WorkerPanicked { start: 0, ref message } if message.starts_with("model diverged at x1 = ")),
        "{err:?}"
    );
    assert!(
        err.to_string()
            .starts_with("multistart: the local run of start 0 panicked: model diverged at x1 = "),
        "{err}"
    );
}

/// The pool survives: after a caught panic the same closure type runs normally, and a
/// start that fails with an error (not a panic) is still a `LocalSolver` error.
#[test]
fn after_a_caught_panic_multistart_still_works_and_errors_keep_their_kind() {
    let options = MultistartOptions {
        starts: 6,
        seed: 2,
        threads: 2,
        ..Default::default()
    };
    let panicking = multistart(
        &bounds(),
        &options,
        |_x0| -> Result<msd_opt::NelderMeadResult, OptError> { panic!("boom") },
    );
    assert!(matches!(
        panicking,
        Err(OptError::WorkerPanicked { start: 0, .. })
    ));
    let ranked = multistart(&bounds(), &options, |x0| {
        nelder_mead(bowl, x0, &NelderMeadOptions::default())
    })
    .expect("a healthy run");
    assert!((ranked[0].result.x[0] - 0.3).abs() < 1e-3);
    let failing = multistart(&bounds(), &options, |x0| {
        nelder_mead(bowl, &[x0[0], f64::NAN], &NelderMeadOptions::default())
    });
    assert!(
        matches!(failing, Err(OptError::LocalSolver { start: 0, ref source }) if matches!(**source, OptError::NonFiniteStart { index: 1, .. })),
        "{failing:?}"
    );
}
