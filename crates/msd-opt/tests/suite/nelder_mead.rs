//! Nelder–Mead: golden values from MATLAB's documentation, each move through the
//! driver on hand-computed one-dimensional simplices, every stopping rule, bounds
//! and bad input.

use std::cell::Cell;

use msd_opt::{Bounds, NelderMeadExit, NelderMeadOptions, OptError, Step, nelder_mead};

fn rosenbrock(x: &[f64]) -> f64 {
    100.0 * (x[1] - x[0] * x[0]).powi(2) + (1.0 - x[0]).powi(2)
}

fn stop_after(iterations: usize) -> NelderMeadOptions {
    NelderMeadOptions {
        max_iterations: Some(iterations),
        trace: true,
        ..Default::default()
    }
}

#[test]
fn rosenbrock_matches_fminsearch_documentation() {
    // MATLAB's fminsearch page: from [-1.2, 1] the final value is 8.17766e-10
    // (optimplotfval title); the classic output struct reports 85 iterations and
    // 159 function evaluations.
    let r = nelder_mead(rosenbrock, &[-1.2, 1.0], &NelderMeadOptions::default()).unwrap();
    assert_eq!(r.exit, NelderMeadExit::Converged);
    assert_eq!((r.iterations, r.evaluations), (85, 159));
    assert!((r.cost - 8.17766e-10).abs() <= 0.5e-15, "{}", r.cost);
}

#[test]
fn banana_from_minus_1_9_matches_fminsearch_documentation() {
    // MATLAB example "Banana Function Minimization": x0 = [-1.9, 2],
    // 210 function evaluations and 114 iterations.
    let r = nelder_mead(rosenbrock, &[-1.9, 2.0], &NelderMeadOptions::default()).unwrap();
    assert_eq!(r.exit, NelderMeadExit::Converged);
    assert_eq!((r.iterations, r.evaluations), (114, 210));
}

#[test]
fn trace_starts_like_display_iter() {
    let r = nelder_mead(rosenbrock, &[-1.2, 1.0], &stop_after(1000)).unwrap();
    assert_eq!(r.trace.len(), r.iterations + 1);
    let first = r.trace[0];
    assert_eq!(
        (first.iteration, first.evaluations, first.step),
        (0, 1, Step::Start)
    );
    // f(-1.2, 1) = 100·0.44² + 2.2² = 24.2
    assert!((first.best_cost - 24.2).abs() < 1e-12);
    let second = r.trace[1];
    assert_eq!(
        (second.iteration, second.evaluations, second.step),
        (1, 3, Step::InitialSimplex)
    );
    let last = r.trace.last().unwrap();
    assert_eq!(
        (last.iteration, last.evaluations),
        (r.iterations, r.evaluations)
    );
    assert_eq!(last.best_cost, r.cost);
}

#[test]
fn expansion_through_the_driver() {
    // Simplex {1, 1.05} on x²: xbar = 1, xr = 0.95 beats the best, xe = 3 − 2·1.05
    // beats xr.
    let r = nelder_mead(|x| x[0] * x[0], &[1.0], &stop_after(2)).unwrap();
    assert_eq!(r.trace[2].step, Step::Expand);
    assert_eq!(r.x[0], 3.0 * 1.0 - 2.0 * (1.05 * 1.0));
    assert_eq!(r.evaluations, 4);
}

#[test]
fn reflection_through_the_driver() {
    // On (x − 0.95)²: xr = 2 − 1.05 is (nearly) the minimum, xe = 3 − 2.1 is worse.
    let r = nelder_mead(|x| (x[0] - 0.95).powi(2), &[1.0], &stop_after(2)).unwrap();
    assert_eq!(r.trace[2].step, Step::Reflect);
    assert_eq!(r.x[0], 2.0 * 1.0 - 1.05 * 1.0);
}

#[test]
fn inside_contraction_through_the_driver() {
    // On (x − 1.03)² the sorted simplex is {1.05, 1}; xr = 2·1.05 − 1 = 1.1 is worse
    // than the worst, xcc = 0.5·1.05 + 0.5·1 = 1.025 is the new best.
    let r = nelder_mead(|x| (x[0] - 1.03).powi(2), &[1.0], &stop_after(2)).unwrap();
    assert_eq!(r.trace[2].step, Step::ContractInside);
    assert_eq!(r.x[0], 0.5 * 1.05 + 0.5 * 1.0);
}

#[test]
fn outside_contraction_through_the_driver() {
    // On (x − 1.07)²: sorted {1.05, 1}; xr = 1.1 lies between best and worst, the
    // outside contraction 1.5·1.05 − 0.5·1 = 1.075 is the new best.
    let r = nelder_mead(|x| (x[0] - 1.07).powi(2), &[1.0], &stop_after(2)).unwrap();
    assert_eq!(r.trace[2].step, Step::ContractOutside);
    assert_eq!(r.x[0], 1.5 * 1.05 - 0.5 * 1.0);
}

#[test]
fn shrink_through_the_driver() {
    // A non-convex cost: best at 1, the reflection 0.95 and the inside contraction
    // 1.025 are both worse than the worst vertex, so the simplex shrinks:
    // 1 + 0.5·(1.05 − 1) = 1.025 (one more evaluation, n = 1).
    let visited = std::cell::RefCell::new(Vec::new());
    let cost = |x: &[f64]| {
        visited.borrow_mut().push(x[0]);
        if x[0] == 1.0 {
            0.0
        } else if x[0] > 1.04 {
            1.0
        } else if x[0] < 0.99 {
            2.0
        } else {
            3.0
        }
    };
    let r = nelder_mead(cost, &[1.0], &stop_after(2)).unwrap();
    assert_eq!(r.trace[2].step, Step::Shrink);
    assert_eq!(r.evaluations, 5);
    let v = visited.borrow();
    assert_eq!(v[3], 0.5 * 1.0 + 0.5 * 1.05); // inside contraction
    assert_eq!(v[4], 1.0 + 0.5 * (1.05 - 1.0)); // shrunk vertex
    assert_eq!(r.x[0], 1.0);
}

#[test]
fn initial_simplex_includes_zero_rule() {
    let visited = std::cell::RefCell::new(Vec::new());
    let cost = |x: &[f64]| {
        visited.borrow_mut().push(x.to_vec());
        x.iter().map(|v| v * v).sum::<f64>()
    };
    nelder_mead(cost, &[2.0, 0.0], &stop_after(1)).unwrap();
    let v = visited.borrow();
    assert_eq!(v.len(), 3);
    assert_eq!(v[0], [2.0, 0.0]);
    assert_eq!(v[1], [1.05 * 2.0, 0.0]);
    assert_eq!(v[2], [2.0, 0.00025]);
}

#[test]
fn iteration_limit_stops_the_search() {
    let r = nelder_mead(rosenbrock, &[-1.2, 1.0], &stop_after(10)).unwrap();
    assert_eq!(r.exit, NelderMeadExit::MaxIterations);
    assert_eq!(r.iterations, 10);
    assert_eq!(r.exit.exitflag(), 0);
}

#[test]
fn evaluation_limit_stops_the_search() {
    let options = NelderMeadOptions {
        max_evaluations: Some(20),
        ..Default::default()
    };
    let r = nelder_mead(rosenbrock, &[-1.2, 1.0], &options).unwrap();
    assert_eq!(r.exit, NelderMeadExit::MaxEvaluations);
    // fminsearch checks the count before each iteration, which may use up to n + 2
    // evaluations (reflect, contract, shrink n).
    assert!(
        (20..20 + 2 + 2).contains(&r.evaluations),
        "{}",
        r.evaluations
    );
}

#[test]
fn default_limits_are_200_n() {
    // A plane has no minimum: the simplex keeps expanding (two evaluations per
    // iteration), so MaxFunEvals = 200·3 = 600 is reached before MaxIter = 600.
    let plane = |x: &[f64]| x[0] + x[1] + x[2];
    let r = nelder_mead(plane, &[1.0, 1.0, 1.0], &NelderMeadOptions::default()).unwrap();
    assert_eq!(r.exit, NelderMeadExit::MaxEvaluations);
    assert!(r.evaluations >= 600 && r.evaluations < 600 + 3 + 2);
    assert!(r.iterations < 600);
    // With MaxFunEvals raised, MaxIter = 600 stops it.
    let options = NelderMeadOptions {
        max_evaluations: Some(100_000),
        ..Default::default()
    };
    let r = nelder_mead(plane, &[1.0, 1.0, 1.0], &options).unwrap();
    assert_eq!(r.exit, NelderMeadExit::MaxIterations);
    assert_eq!(r.iterations, 600);
}

#[test]
fn converged_exit_satisfies_both_tolerances() {
    let options = NelderMeadOptions {
        x_tolerance: 1e-6,
        f_tolerance: 1e-6,
        ..Default::default()
    };
    let r = nelder_mead(|x| (x[0] - 2.0).powi(2) + 3.0, &[0.0], &options).unwrap();
    assert_eq!(r.exit, NelderMeadExit::Converged);
    assert_eq!(r.exit.exitflag(), 1);
    // Every vertex within 1e-6 of the best: the minimiser is within 1e-6 too up
    // to the simplex spread, and f − 3 = (x − 2)².
    assert!((r.x[0] - 2.0).abs() < 2e-3);
    assert!(r.cost - 3.0 < 1e-6);
}

#[test]
fn relative_tolerances_scale_with_the_cost() {
    let cost = |x: &[f64]| 1e6 + (x[0] - 1.0).powi(2) + (x[1] + 2.0).powi(2);
    let absolute = nelder_mead(cost, &[3.0, 3.0], &NelderMeadOptions::default()).unwrap();
    let relative = NelderMeadOptions {
        relative_tolerances: true,
        ..Default::default()
    };
    let rel = nelder_mead(cost, &[3.0, 3.0], &relative).unwrap();
    assert_eq!(rel.exit, NelderMeadExit::Converged);
    // TolFun·|f| = 100 is far looser than 1e-4, so the relative run stops sooner.
    assert!(rel.evaluations < absolute.evaluations);
}

#[test]
fn adaptive_coefficients_converge_in_higher_dimension() {
    let n = 8;
    let cost = |x: &[f64]| {
        x.iter()
            .enumerate()
            .map(|(i, v)| (i as f64 + 1.0) * (v - 1.0).powi(2))
            .sum::<f64>()
    };
    let options = NelderMeadOptions {
        adaptive: true,
        max_evaluations: Some(20_000),
        max_iterations: Some(20_000),
        ..Default::default()
    };
    let r = nelder_mead(cost, &vec![0.0; n], &options).unwrap();
    assert_eq!(r.exit, NelderMeadExit::Converged);
    assert!(r.cost < 1e-4);
}

#[test]
fn non_finite_cost_everywhere_is_an_exit_reason() {
    let r = nelder_mead(|_| f64::NAN, &[1.0, 2.0], &NelderMeadOptions::default()).unwrap();
    assert_eq!(r.exit, NelderMeadExit::NonFiniteCost);
    assert_eq!(r.cost, f64::INFINITY);
    assert_eq!((r.iterations, r.evaluations), (1, 3));
    assert_eq!(r.x, [1.0, 2.0]);
}

#[test]
fn simplex_walks_away_from_infinite_cost() {
    // Infinite for x ≤ 0 (as a non-physical parameter region), NaN at exactly 0.5.
    let cost = |x: &[f64]| {
        if x[0] <= 0.0 {
            f64::INFINITY
        } else if x[0] == 0.5 {
            f64::NAN
        } else {
            (x[0] - 0.1).powi(2) + (x[1] - 1.0).powi(2)
        }
    };
    let r = nelder_mead(cost, &[0.0, 3.0], &NelderMeadOptions::default()).unwrap();
    assert_eq!(r.exit, NelderMeadExit::Converged);
    assert!(r.cost.is_finite() && r.cost < 1e-6);
    assert!(r.x[0] > 0.0);
}

#[test]
fn bounds_are_never_violated_and_a_minimum_on_a_bound_is_found() {
    // Rosenbrock with x1 ≤ 0.5: the minimum is (0.5, 0.25) with f = 0.25, since
    // (1 − x1)² ≥ 0.25 there and the valley term vanishes at x2 = x1².
    let bounds = Bounds::new(vec![-2.0, f64::NEG_INFINITY], vec![0.5, 2.0]).unwrap();
    let inside = Cell::new(true);
    let cost = |x: &[f64]| {
        if !bounds.contains(x) {
            inside.set(false);
        }
        rosenbrock(x)
    };
    let options = NelderMeadOptions {
        bounds: Some(bounds.clone()),
        x_tolerance: 1e-8,
        f_tolerance: 1e-10,
        max_evaluations: Some(2000),
        max_iterations: Some(2000),
        ..Default::default()
    };
    let r = nelder_mead(cost, &[-1.2, 1.0], &options).unwrap();
    assert!(inside.get());
    assert!(bounds.contains(&r.x));
    assert_eq!(r.exit, NelderMeadExit::Converged);
    assert!((r.cost - 0.25).abs() < 1e-8, "{}", r.cost);
    assert!(
        (r.x[0] - 0.5).abs() < 1e-6 && (r.x[1] - 0.25).abs() < 1e-4,
        "{:?}",
        r.x
    );
}

#[test]
fn lower_bound_only_and_start_outside_is_projected() {
    let bounds = Bounds::new(vec![1.0], vec![f64::INFINITY]).unwrap();
    let options = NelderMeadOptions {
        bounds: Some(bounds),
        ..Default::default()
    };
    let r = nelder_mead(|x| x[0] * x[0], &[-5.0], &options).unwrap();
    assert!(r.x[0] >= 1.0);
    assert!((r.x[0] - 1.0).abs() < 1e-4);
}

#[test]
fn bad_input_is_a_specific_error() {
    let d = NelderMeadOptions::default();
    let f = |x: &[f64]| x[0];
    assert!(matches!(nelder_mead(f, &[], &d), Err(OptError::EmptyStart)));
    assert!(matches!(
        nelder_mead(f, &[1.0, f64::INFINITY], &d),
        Err(OptError::NonFiniteStart { index: 1, .. })
    ));
    for (name, options) in [
        (
            "x_tolerance",
            NelderMeadOptions {
                x_tolerance: 0.0,
                ..d.clone()
            },
        ),
        (
            "x_tolerance",
            NelderMeadOptions {
                x_tolerance: f64::NAN,
                ..d.clone()
            },
        ),
        (
            "f_tolerance",
            NelderMeadOptions {
                f_tolerance: -1e-4,
                ..d.clone()
            },
        ),
        (
            "max_iterations",
            NelderMeadOptions {
                max_iterations: Some(0),
                ..d.clone()
            },
        ),
        (
            "max_evaluations",
            NelderMeadOptions {
                max_evaluations: Some(0),
                ..d.clone()
            },
        ),
    ] {
        let err = nelder_mead(f, &[1.0], &options).unwrap_err();
        assert!(
            matches!(err, OptError::InvalidOption { name: n, .. } if n == name),
            "{err}"
        );
    }
    let inverted = NelderMeadOptions {
        bounds: Some(Bounds {
            lower: vec![2.0],
            upper: vec![1.0],
        }),
        ..d.clone()
    };
    assert!(matches!(
        nelder_mead(f, &[1.0], &inverted),
        Err(OptError::InvertedBounds { index: 0, .. })
    ));
    let short = NelderMeadOptions {
        bounds: Some(Bounds {
            lower: vec![0.0],
            upper: vec![1.0],
        }),
        ..d
    };
    assert!(matches!(
        nelder_mead(f, &[1.0, 2.0], &short),
        Err(OptError::LengthMismatch {
            expected: 2,
            found: 1,
            ..
        })
    ));
    let err = NelderMeadOptions {
        f_tolerance: 0.0,
        ..Default::default()
    }
    .validate()
    .unwrap_err();
    assert_eq!(
        err.to_string(),
        "option `f_tolerance` = 0 is invalid: expected a finite number > 0"
    );
}

#[test]
fn options_deserialize_with_defaults_and_reject_unknown_fields() {
    let o: NelderMeadOptions = toml::from_str("x_tolerance = 1e-6\nadaptive = true").unwrap();
    assert_eq!(
        o,
        NelderMeadOptions {
            x_tolerance: 1e-6,
            adaptive: true,
            ..Default::default()
        }
    );
    let bounded: NelderMeadOptions =
        toml::from_str("[bounds]\nlower = [0.0, -inf]\nupper = [1.0, inf]").unwrap();
    assert_eq!(bounded.bounds.unwrap().upper[1], f64::INFINITY);
    assert!(toml::from_str::<NelderMeadOptions>("tolx = 1e-6").is_err());
    let lm: msd_opt::LevenbergMarquardtOptions = toml::from_str("g_tolerance = 1e-10").unwrap();
    assert_eq!(lm.g_tolerance, 1e-10);
    assert_eq!(lm.initial_step_bound, 100.0);
    let ms: msd_opt::MultistartOptions = toml::from_str("sampling = \"Halton\"").unwrap();
    assert_eq!((ms.starts, ms.threads), (16, 2));
}

#[test]
fn mgh_problems_end_with_the_documented_exit_reason() {
    // fminsearch's defaults on f = Σ rᵢ². Where the method converges to a
    // published minimum the value is within TolFun = 1e-4 of it; where it stops on
    // a limit, or stagnates away from the minimum (helical valley, Box 3-D are
    // known Nelder–Mead stagnations under TolX = 1e-4), it still improves on f(x0).
    use NelderMeadExit::{Converged, MaxEvaluations};
    let expected = [
        ("Rosenbrock", Converged, true),
        ("Freudenstein-Roth", Converged, true),
        ("Powell badly scaled", MaxEvaluations, true),
        ("Brown badly scaled", Converged, true),
        ("Beale", Converged, true),
        ("Helical valley", Converged, false),
        ("Bard", Converged, true),
        ("Meyer", MaxEvaluations, false),
        ("Box 3-D", Converged, false),
        ("Powell singular", Converged, true),
    ];
    for (p, (name, exit, reaches)) in crate::mgh::problems().iter().zip(expected) {
        assert_eq!(p.name, name);
        let r = nelder_mead(
            |x| p.sum_of_squares(x),
            &p.x0,
            &NelderMeadOptions::default(),
        )
        .unwrap();
        assert_eq!(r.exit, exit, "{name}");
        assert!(r.cost < p.sum_of_squares(&p.x0), "{name}");
        if reaches {
            let nearest = p
                .minima
                .iter()
                .map(|s| (r.cost - s).abs())
                .fold(f64::INFINITY, f64::min);
            assert!(nearest <= 1e-4, "{name}: f = {}", r.cost);
        }
    }
}
