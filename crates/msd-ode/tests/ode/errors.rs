//! Every invalid option and every failure returns its documented error; none panics.

use msd_ode::{
    Breakpoint, ExactSimulator, Hold, LtiModel, Ode45Options, OdeError, SMatrix, SVector,
    SampledInput, ode45,
};

fn decay() -> impl FnMut(f64, &SVector<f64, 1>, &mut SVector<f64, 1>) {
    |_t, y, d| d[0] = -y[0]
}

fn one() -> SVector<f64, 1> {
    SVector::<f64, 1>::new(1.0)
}

fn solve_with(options: Ode45Options) -> Result<(), OdeError> {
    ode45(&mut decay(), &[0.0, 1.0], &one(), &options).map(|_| ())
}

#[test]
fn invalid_options_name_the_option() {
    let d = Ode45Options::default;
    let cases: Vec<(Ode45Options, &str)> = vec![
        (
            Ode45Options {
                rel_tol: 0.0,
                ..d()
            },
            "rel_tol",
        ),
        (
            Ode45Options {
                rel_tol: -1e-3,
                ..d()
            },
            "rel_tol",
        ),
        (
            Ode45Options {
                rel_tol: f64::NAN,
                ..d()
            },
            "rel_tol",
        ),
        (
            Ode45Options {
                rel_tol: 1e-16,
                ..d()
            },
            "rel_tol",
        ),
        (
            Ode45Options {
                abs_tol: 0.0,
                ..d()
            },
            "abs_tol",
        ),
        (
            Ode45Options {
                abs_tol: f64::INFINITY,
                ..d()
            },
            "abs_tol",
        ),
        (
            Ode45Options {
                max_step: Some(-0.1),
                ..d()
            },
            "max_step",
        ),
        (
            Ode45Options {
                max_step: Some(f64::NAN),
                ..d()
            },
            "max_step",
        ),
        (
            Ode45Options {
                initial_step: Some(0.0),
                ..d()
            },
            "initial_step",
        ),
        (Ode45Options { refine: 0, ..d() }, "refine"),
        (
            Ode45Options {
                max_steps: 0,
                ..d()
            },
            "max_steps",
        ),
    ];
    for (options, expected) in cases {
        match solve_with(options) {
            Err(OdeError::InvalidOption { name, .. }) => assert_eq!(name, expected),
            other => panic!("{expected}: expected InvalidOption, got {other:?}"),
        }
    }
}

#[test]
fn invalid_error_text_is_specific() {
    let err = Ode45Options {
        abs_tol: -2.0,
        ..Ode45Options::default()
    }
    .validate()
    .unwrap_err();
    assert_eq!(
        err.to_string(),
        "invalid option abs_tol = -2: expected a finite number > 0"
    );
}

#[test]
fn invalid_time_spans() {
    let opts = Ode45Options::default();
    let cases: [(&[f64], usize); 5] = [
        (&[], 0),
        (&[0.0], 0),
        (&[0.0, f64::NAN, 1.0], 1),
        (&[0.0, 0.0], 1),
        (&[0.0, 0.5, 0.4, 1.0], 2),
    ];
    for (span, expected_index) in cases {
        match ode45(&mut decay(), span, &one(), &opts) {
            Err(OdeError::InvalidTimeSpan { index, .. }) => {
                assert_eq!(index, expected_index, "{span:?}")
            }
            other => panic!("{span:?}: {other:?}"),
        }
    }
}

#[test]
fn non_finite_initial_state() {
    let y0 = SVector::<f64, 2>::new(0.0, f64::NAN);
    let mut rhs = |_t: f64, y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| *d = *y;
    let err = ode45(&mut rhs, &[0.0, 1.0], &y0, &Ode45Options::default()).unwrap_err();
    assert!(
        matches!(err, OdeError::NonFiniteInitialState { index: 1, .. }),
        "{err:?}"
    );
}

#[test]
fn blow_up_gives_step_size_underflow_near_the_singularity() {
    // y' = y², y(0) = 1 has y = 1/(1 − t): it blows up at t = 1.
    let mut rhs = |_t: f64, y: &SVector<f64, 1>, d: &mut SVector<f64, 1>| d[0] = y[0] * y[0];
    let err = ode45(&mut rhs, &[0.0, 2.0], &one(), &Ode45Options::default()).unwrap_err();
    match err {
        OdeError::StepSizeUnderflow { t, step } => {
            assert!((t - 1.0).abs() < 1e-3, "t = {t}");
            assert!(step <= 16.0 * f64::EPSILON * 2.0);
        }
        other => panic!("expected StepSizeUnderflow, got {other:?}"),
    }
}

#[test]
fn non_finite_right_hand_side_is_reported_at_its_time() {
    let mut rhs = |t: f64, y: &SVector<f64, 1>, d: &mut SVector<f64, 1>| {
        d[0] = if t > 0.5 { f64::NAN } else { -y[0] };
    };
    let err = ode45(&mut rhs, &[0.0, 1.0], &one(), &Ode45Options::default()).unwrap_err();
    match err {
        OdeError::NonFiniteState { t, component } => {
            assert!((0.45..=0.5).contains(&t), "t = {t}");
            assert_eq!(component, 0);
        }
        other => panic!("expected NonFiniteState, got {other:?}"),
    }
    // Non-finite at the very start.
    let mut bad = |_t: f64, _y: &SVector<f64, 1>, d: &mut SVector<f64, 1>| d[0] = f64::INFINITY;
    let err = ode45(&mut bad, &[0.0, 1.0], &one(), &Ode45Options::default()).unwrap_err();
    assert!(matches!(err, OdeError::NonFiniteState { t, .. } if t == 0.0));
}

#[test]
fn step_budget_is_enforced() {
    let opts = Ode45Options {
        max_steps: 3,
        rel_tol: 1e-10,
        ..Ode45Options::default()
    };
    let err = ode45(&mut decay(), &[0.0, 10.0], &one(), &opts).unwrap_err();
    assert!(
        matches!(err, OdeError::TooManySteps { steps: 3, .. }),
        "{err:?}"
    );
}

fn model() -> LtiModel<2> {
    LtiModel {
        a: SMatrix::<f64, 2, 2>::new(0.0, 1.0, -48.0, -0.72),
        b: SVector::<f64, 2>::new(0.0, 0.4),
    }
}

#[test]
fn exact_simulator_rejects_bad_setup() {
    for dt in [0.0, -0.002, f64::NAN, f64::INFINITY] {
        let err = ExactSimulator::new(&model(), dt, Hold::Cubic).unwrap_err();
        assert!(
            matches!(err, OdeError::InvalidOption { name: "dt", .. }),
            "{err:?}"
        );
    }
    let mut bad = model();
    bad.a[(1, 0)] = f64::NAN;
    let err = ExactSimulator::new(&bad, 0.002, Hold::Cubic).unwrap_err();
    assert!(
        matches!(
            err,
            OdeError::NonFiniteModel {
                name: "a",
                row: 1,
                col: 0,
                ..
            }
        ),
        "{err:?}"
    );
    // Absurdly stiff: ‖A·dt‖ ~ 1e80 would make scaling and squaring run forever.
    let stiff = LtiModel {
        a: SMatrix::<f64, 2, 2>::new(0.0, 1.0, -1e83, -1.0),
        b: SVector::<f64, 2>::new(0.0, 1.0),
    };
    let err = ExactSimulator::new(&stiff, 0.002, Hold::Cubic).unwrap_err();
    assert!(
        matches!(err, OdeError::ExponentialOutOfRange { .. }),
        "{err:?}"
    );
    // Very stiff but representable (k/m = 1e11) still works.
    let very_stiff = LtiModel {
        a: SMatrix::<f64, 2, 2>::new(0.0, 1.0, -1e11, -10.0),
        b: SVector::<f64, 2>::new(0.0, 1.0),
    };
    let sim = ExactSimulator::new(&very_stiff, 0.002, Hold::Cubic).expect("stiff but fine");
    assert!(sim.transition().iter().all(|v| v.is_finite()));
    let mut bad = model();
    bad.b[1] = f64::INFINITY;
    let err = ExactSimulator::new(&bad, 0.002, Hold::Cubic).unwrap_err();
    assert!(
        matches!(
            err,
            OdeError::NonFiniteModel {
                name: "b",
                row: 1,
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn exact_simulator_rejects_bad_input() {
    let sim = ExactSimulator::new(&model(), 0.002, Hold::Cubic).expect("valid");
    let x0 = SVector::<f64, 2>::zeros();
    let values = [0.0, 1.0, f64::NAN, 1.0];
    let err = sim
        .simulate(&x0, &SampledInput::smooth(&values))
        .unwrap_err();
    assert!(
        matches!(err, OdeError::InvalidInput { index: 2, .. }),
        "{err:?}"
    );

    let err = sim.simulate(&x0, &SampledInput::smooth(&[])).unwrap_err();
    assert!(
        matches!(err, OdeError::InvalidInput { index: 0, .. }),
        "{err:?}"
    );

    let values = [0.0; 10];
    let out_of_range = [Breakpoint {
        index: 10,
        left: 0.0,
        right: 1.0,
    }];
    let err = sim
        .simulate(
            &x0,
            &SampledInput {
                values: &values,
                breakpoints: &out_of_range,
            },
        )
        .unwrap_err();
    assert!(
        matches!(err, OdeError::InvalidInput { index: 10, .. }),
        "{err:?}"
    );

    let unsorted = [
        Breakpoint {
            index: 5,
            left: 0.0,
            right: 1.0,
        },
        Breakpoint {
            index: 5,
            left: 1.0,
            right: 0.0,
        },
    ];
    let err = sim
        .simulate(
            &x0,
            &SampledInput {
                values: &values,
                breakpoints: &unsorted,
            },
        )
        .unwrap_err();
    assert!(
        matches!(err, OdeError::InvalidInput { index: 5, .. }),
        "{err:?}"
    );

    let nan_jump = [Breakpoint {
        index: 3,
        left: f64::NAN,
        right: 1.0,
    }];
    let err = sim
        .simulate(
            &x0,
            &SampledInput {
                values: &values,
                breakpoints: &nan_jump,
            },
        )
        .unwrap_err();
    assert!(
        matches!(err, OdeError::InvalidInput { index: 3, .. }),
        "{err:?}"
    );

    let err = sim
        .simulate(
            &SVector::<f64, 2>::new(f64::NAN, 0.0),
            &SampledInput::smooth(&values),
        )
        .unwrap_err();
    assert!(
        matches!(err, OdeError::NonFiniteInitialState { index: 0, .. }),
        "{err:?}"
    );

    let mut short = vec![SVector::<f64, 2>::zeros(); 3];
    let err = sim
        .simulate_into(&x0, &SampledInput::smooth(&values), &mut short)
        .unwrap_err();
    assert_eq!(
        err,
        OdeError::LengthMismatch {
            expected: 10,
            got: 3
        }
    );
}

#[test]
fn single_sample_and_edge_breakpoints_are_fine() {
    let sim = ExactSimulator::new(&model(), 0.002, Hold::Cubic).expect("valid");
    let x0 = SVector::<f64, 2>::new(0.01, 0.0);
    let x = sim
        .simulate(&x0, &SampledInput::smooth(&[3.0]))
        .expect("one sample");
    assert_eq!(x, vec![x0]);
    let values = [1.0; 6];
    let edges = [
        Breakpoint {
            index: 0,
            left: -5.0,
            right: 1.0,
        },
        Breakpoint {
            index: 5,
            left: 1.0,
            right: 9.0,
        },
    ];
    let with = sim
        .simulate(
            &x0,
            &SampledInput {
                values: &values,
                breakpoints: &edges,
            },
        )
        .expect("ok");
    let without = sim
        .simulate(&x0, &SampledInput::smooth(&values))
        .expect("ok");
    // The left value at the first sample and the right value at the last are irrelevant.
    assert_eq!(with, without);
}
