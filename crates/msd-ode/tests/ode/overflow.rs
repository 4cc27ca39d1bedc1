//! An exact simulation whose state overflows is an error naming the first sample, not a
//! result full of infinities (found by the property tests in tests/tests/properties).

use msd_ode::{ExactSimulator, Hold, LtiModel, OdeError, SMatrix, SVector, SampledInput};

/// x' = x: x(t) = x0·e^t. From x0 = 1 with dt = 100, sample i holds e^(100 i), finite up
/// to i = 7 (e^700 ≈ 1e304) and infinite from i = 8 (e^800): the error is at t = 8·dt.
#[test]
fn an_unstable_model_that_overflows_names_the_first_infinite_sample() {
    let model = LtiModel {
        a: SMatrix::<f64, 2, 2>::new(1.0, 0.0, 0.0, -1.0),
        b: SVector::<f64, 2>::new(0.0, 1.0),
    };
    let sim = ExactSimulator::new(&model, 100.0, Hold::Zero).unwrap();
    let input = vec![0.0; 20];
    let mut seen = 0;
    let err = sim
        .simulate_with(
            &SVector::<f64, 2>::new(1.0, 0.0),
            &SampledInput::smooth(&input),
            |_, _| seen += 1,
        )
        .unwrap_err();
    assert_eq!(
        err,
        OdeError::NonFiniteState {
            t: 800.0,
            component: 0
        }
    );
    assert_eq!(seen, 20, "the output saw every sample before the error");
    // The same with 8 samples (last finite at i = 7) succeeds.
    let x = sim
        .simulate(
            &SVector::<f64, 2>::new(1.0, 0.0),
            &SampledInput::smooth(&input[..8]),
        )
        .unwrap();
    assert!((x[7][0].ln() - 700.0).abs() < 1e-9);
}

/// A stable model driven by an input too large for it overflows too.
#[test]
fn a_huge_input_that_overflows_the_state_is_an_error() {
    let (m, c, k) = (1e-300, 1e-300, 1e-299);
    let model = LtiModel {
        a: SMatrix::<f64, 2, 2>::new(0.0, 1.0, -k / m, -c / m),
        b: SVector::<f64, 2>::new(0.0, 1.0 / m),
    };
    let sim = ExactSimulator::new(&model, 0.01, Hold::Cubic).unwrap();
    let input = vec![1e300; 50];
    let err = sim
        .simulate(&SVector::zeros(), &SampledInput::smooth(&input))
        .unwrap_err();
    assert!(
        matches!(err, OdeError::NonFiniteState { t, .. } if t > 0.0 && t <= 0.49),
        "{err:?}"
    );
}
