//! The error variants that need a failing run rather than a bad argument, reached through
//! the public API: an estimator that cannot simulate anywhere it looks
//! (`EstimationFailed`, `Opt`), bad optimiser options (`Opt`) and bad signal parameters
//! (`Signal`).

use msd_ident::{
    Backend, DataSet, EstimationOptions, Excitation, IdentError, InitialState, Method, Parameters,
    SyntheticOptions, estimate, simulate, synthetic_data,
};
use msd_opt::{NelderMeadOptions, OptError};
use msd_signal::{Signal, SignalError};

/// The paper plant's noise-free response to a chirp, 10 s at 2 ms.
fn chirp_data() -> DataSet {
    let input = Signal::Chirp {
        amplitude: 2.0,
        f0: 0.2,
        f1: 3.0,
        duration: 10.0,
        phase: 0.0,
        sweep: msd_signal::Sweep::Linear,
        t_start: 0.0,
    };
    let exc = Excitation::from_signal(input, 0.0, 0.002, 5001).unwrap();
    let y = simulate(
        &Parameters::PAPER,
        &exc,
        InitialState::REST,
        &Backend::EXACT,
    )
    .unwrap();
    DataSet::new("chirp", exc, y).unwrap()
}

/// θ₀ absurdly stiff for the sampling interval: ωn·dt = √(k/m)·dt = 2e13, beyond what a
/// matrix exponential can take (a balanced ‖A·dt‖ of 1e12), at θ₀ and at every point of
/// Nelder–Mead's initial simplex (5 % away).
const ABSURD: Parameters = Parameters {
    mass: 1e-20,
    damping: 1.0,
    stiffness: 1e12,
};

#[test]
fn nelder_mead_that_cannot_simulate_anywhere_is_estimation_failed() {
    let options = EstimationOptions {
        method: Method::NelderMead,
        initial_guess: Some(ABSURD),
        ..EstimationOptions::default()
    };
    let err = estimate(&chirp_data(), &options).expect_err("no point can be simulated");
    match &err {
        IdentError::EstimationFailed { reason } => {
            assert!(
                reason.starts_with("the cost is not finite at any point tried"),
                "{reason}"
            );
            assert!(reason.contains("initial simplex"), "{reason}");
        }
        other => panic!("expected EstimationFailed, got {other:?}"),
    }
    assert!(err.to_string().starts_with("estimation failed: "), "{err}");
}

#[test]
fn levenberg_marquardt_that_cannot_start_is_an_opt_error() {
    let options = EstimationOptions {
        method: Method::LevenbergMarquardt,
        initial_guess: Some(ABSURD),
        ..EstimationOptions::default()
    };
    let err = estimate(&chirp_data(), &options).expect_err("θ₀ cannot be simulated");
    assert_eq!(
        err,
        IdentError::Opt(OptError::InitialResiduals { index: None }),
        "{err}"
    );
    assert!(
        err.to_string()
            .starts_with("residuals at the starting point are not finite"),
        "{err}"
    );
}

#[test]
fn invalid_optimiser_options_are_opt_errors_naming_the_option() {
    let options = EstimationOptions {
        method: Method::NelderMead,
        nelder_mead: NelderMeadOptions {
            x_tolerance: -1e-4,
            ..NelderMeadOptions::default()
        },
        ..EstimationOptions::fast()
    };
    let err = options.validate().expect_err("a negative TolX");
    assert!(
        matches!(
            err,
            IdentError::Opt(OptError::InvalidOption {
                name: "x_tolerance",
                ..
            })
        ),
        "{err:?}"
    );
    // estimate refuses it the same way, before any simulation.
    assert_eq!(estimate(&chirp_data(), &options).unwrap_err(), err);
    assert_eq!(
        err.to_string(),
        "option `x_tolerance` = -0.0001 is invalid: expected a finite number > 0"
    );
}

#[test]
fn bad_signal_parameters_are_signal_errors_naming_the_parameter() {
    let bad = Signal::Sum {
        terms: vec![
            Signal::Step {
                amplitude: 1.0,
                time: 0.5,
            },
            Signal::Step {
                amplitude: f64::NAN,
                time: 1.0,
            },
        ],
    };
    let err = Excitation::from_signal(bad, 0.0, 0.01, 100).unwrap_err();
    assert!(
        matches!(
            err,
            IdentError::Signal(SignalError::InvalidParameter { ref parameter, .. })
                if parameter == "terms[1].amplitude"
        ),
        "{err:?}"
    );
    assert_eq!(
        err.to_string(),
        "invalid parameter `terms[1].amplitude` = NaN: expected a finite value"
    );
}

/// A negative or NaN noise level is a mistake to report (with `sigma` named), not a
/// request for noise-free data.
#[test]
fn synthetic_data_refuses_a_negative_or_nan_noise_level() {
    for sigma in [-0.001, f64::NAN, f64::INFINITY] {
        let exc = Excitation::from_samples(0.0, 0.01, vec![1.0; 100]).unwrap();
        let result = synthetic_data(
            &Parameters::PAPER,
            exc,
            &SyntheticOptions {
                name: "x".into(),
                stream: "identification".into(),
                sigma,
                ..SyntheticOptions::default()
            },
        );
        assert!(
            matches!(
                result,
                Err(IdentError::InvalidParameter { name: "sigma", .. })
            ),
            "sigma = {sigma}: {:?}",
            result.map(|(data, _)| format!("Ok: {} samples", data.len()))
        );
    }
}

/// A PRBS whose chips are far shorter than the sampling interval cannot be represented on
/// the grid; Excitation::from_signal lists every chip edge first (span / clock of them:
/// 4e6 here, 4e9 for a 1 ns clock, where `cargo xtask experiment` hangs and grows).
/// msd-signal's `Signal::max_breakpoints` says how many there are before listing.
#[test]
fn a_prbs_far_faster_than_the_sampling_is_refused() {
    let prbs = msd_signal::Prbs::new(msd_signal::PrbsSpec {
        order: 10,
        clock_period: 1e-6,
        amplitude: 1.0,
        t_start: 0.0,
    })
    .unwrap();
    let signal = Signal::Prbs(prbs);
    assert!(signal.max_breakpoints(0.0, 4.0) > 1e6);
    let result = Excitation::from_signal(signal, 0.0, 0.005, 801);
    assert!(
        result
            .as_ref()
            .is_err_and(|e| e.to_string().contains("clock")),
        "{:?}",
        result.map(|e| e.breakpoints().len())
    );
}
