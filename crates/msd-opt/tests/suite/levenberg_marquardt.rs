//! Levenberg–Marquardt on the MGH problems, bounds, call order and bad input.

use std::cell::RefCell;

use msd_opt::{
    Bounds, FiniteDifference, LeastSquaresProblem, LevenbergMarquardtOptions, LmExit, OptError,
    ResidualFn, levenberg_marquardt,
};
use nalgebra::DMatrix;

use crate::mgh::{Mgh, problems};

/// Published minima are given to six significant digits (MGH 1981); zero minima
/// are reached to rounding level: f ≤ 1e-20 (‖r‖ ≤ 1e-10).
fn check(p: &Mgh, f: f64) {
    let tolerance = if p.minima.iter().all(|&s| s == 0.0) {
        1e-20
    } else {
        1e-5
    };
    assert!(p.error(f) <= tolerance, "{}: f = {f:e}", p.name);
}

#[test]
fn mgh_problems_reach_published_minima_with_analytic_jacobians() {
    for mut p in problems() {
        let x0 = p.x0.clone();
        let r = levenberg_marquardt(&mut p, &x0, &LevenbergMarquardtOptions::default()).unwrap();
        check(&p, r.cost);
        // Powell singular has a singular Jacobian at the solution: MINPACK ends it
        // on a "tolerance too small" test with f at rounding level.
        if p.name != "Powell singular" {
            assert!(r.exit.is_success(), "{}: {}", p.name, r.exit);
        }
        assert!((r.residual_norm * r.residual_norm - r.cost).abs() <= 1e-15 * r.cost.max(1e-300));
    }
}

#[test]
fn mgh_counts_match_minpack_lmder() {
    // MINPACK's lmder test driver (Moré, Garbow & Hillstrom, 1980) reports
    // NFEV/NJEV 21/16 for Rosenbrock and 126/116 for Meyer from the standard start.
    let all = problems();
    for (name, nfev, njev) in [("Rosenbrock", 21, 16), ("Meyer", 126, 116)] {
        let mut p = all.iter().find(|p| p.name == name).unwrap().clone();
        let x0 = p.x0.clone();
        let r = levenberg_marquardt(&mut p, &x0, &LevenbergMarquardtOptions::default()).unwrap();
        assert_eq!(
            (r.evaluations, r.jacobian_evaluations),
            (nfev, njev),
            "{name}"
        );
    }
}

#[test]
fn mgh_problems_with_finite_differences() {
    for mut p in problems() {
        p.analytic = false;
        let x0 = p.x0.clone();
        let options = LevenbergMarquardtOptions {
            max_evaluations: Some(2000),
            ..Default::default()
        };
        let r = levenberg_marquardt(&mut p, &x0, &options).unwrap();
        check(&p, r.cost);
        assert!(r.finite_difference_evaluations >= x0.len() * r.jacobian_evaluations);
    }
}

#[test]
fn central_differences_reach_the_minimum() {
    let mut p = problems().into_iter().find(|p| p.name == "Bard").unwrap();
    p.analytic = false;
    let options = LevenbergMarquardtOptions {
        finite_difference: FiniteDifference::Central,
        ..Default::default()
    };
    let x0 = p.x0.clone();
    let r = levenberg_marquardt(&mut p, &x0, &options).unwrap();
    check(&p, r.cost);
    assert_eq!(
        r.finite_difference_evaluations,
        2 * 3 * r.jacobian_evaluations
    );
}

#[test]
fn result_carries_the_jacobian_at_the_solution() {
    for mut p in problems() {
        let x0 = p.x0.clone();
        let r = levenberg_marquardt(&mut p, &x0, &LevenbergMarquardtOptions::default()).unwrap();
        let mut j = DMatrix::zeros(p.m, x0.len());
        (p.jacobian)(&r.x, &mut j);
        assert_eq!(r.jacobian, j, "{}", p.name);
        let mut res = vec![0.0; p.m];
        (p.residuals)(&r.x, &mut res);
        assert_eq!(r.residuals, res, "{}", p.name);
    }
}

/// Records the order of calls, to check that `jacobian(x)` always follows
/// `residuals(x)` at the same x.
struct Recorder {
    inner: Mgh,
    calls: RefCell<Vec<(char, Vec<f64>)>>,
}

impl LeastSquaresProblem for Recorder {
    fn residual_count(&self) -> usize {
        self.inner.m
    }
    fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> bool {
        self.calls.borrow_mut().push(('r', x.to_vec()));
        self.inner.residuals(x, out)
    }
    fn jacobian(&mut self, x: &[f64], out: &mut DMatrix<f64>) -> bool {
        self.calls.borrow_mut().push(('j', x.to_vec()));
        self.inner.jacobian(x, out)
    }
}

#[test]
fn jacobian_is_requested_right_after_residuals_at_the_same_point() {
    for p in problems() {
        let x0 = p.x0.clone();
        let mut rec = Recorder {
            inner: p,
            calls: RefCell::new(Vec::new()),
        };
        levenberg_marquardt(&mut rec, &x0, &LevenbergMarquardtOptions::default()).unwrap();
        let calls = rec.calls.borrow();
        assert_eq!(calls[0].0, 'r');
        for w in calls.windows(2) {
            if w[1].0 == 'j' {
                assert_eq!(w[0].0, 'r', "{}", rec.inner.name);
                assert_eq!(w[0].1, w[1].1, "{}", rec.inner.name);
            }
        }
    }
}

fn rosenbrock_bounded(bounds: Bounds, analytic: bool) -> (Vec<f64>, f64, bool) {
    let mut p = problems().remove(0);
    p.analytic = analytic;
    let inside = RefCell::new(true);
    let b2 = bounds.clone();
    let mut rec = ResidualFn::new(2, |x: &[f64], r: &mut [f64]| {
        if !b2.contains(x) {
            *inside.borrow_mut() = false;
        }
        (p.residuals)(x, r);
        true
    });
    let options = LevenbergMarquardtOptions {
        bounds: Some(bounds),
        ..Default::default()
    };
    let r = levenberg_marquardt(&mut rec, &[-1.2, 1.0], &options).unwrap();
    (r.x, r.cost, inside.into_inner())
}

#[test]
fn bounds_are_never_violated_and_a_minimum_on_a_bound_is_found() {
    // Rosenbrock with x1 ≤ 0.5: minimum (0.5, 0.25), f = 0.25 (see the Nelder–Mead
    // test). Finite differences near the bound must stay inside as well.
    let bounds = Bounds::new(vec![-2.0, -2.0], vec![0.5, 2.0]).unwrap();
    let (x, f, inside) = rosenbrock_bounded(bounds.clone(), false);
    assert!(inside);
    assert!(bounds.contains(&x));
    assert!((f - 0.25).abs() < 1e-12, "{f}");
    assert!(
        (x[0] - 0.5).abs() < 1e-12 && (x[1] - 0.25).abs() < 1e-8,
        "{x:?}"
    );
}

#[test]
fn a_start_outside_the_box_is_projected() {
    let bounds = Bounds::new(vec![2.0, -10.0], vec![3.0, 10.0]).unwrap();
    let (x, f, inside) = rosenbrock_bounded(bounds, false);
    assert!(inside);
    // x1 = 2 on its lower bound, x2 = 4 = x1²: f = (1 − 2)² = 1.
    assert!(
        (x[0] - 2.0).abs() < 1e-12 && (x[1] - 4.0).abs() < 1e-8,
        "{x:?}"
    );
    assert!((f - 1.0).abs() < 1e-12);
}

#[test]
fn non_finite_residuals_are_rejected_steps() {
    // Fit y = exp(−b·t) with b = 2, with residuals undefined for b < 0.5: the solver
    // must step back from the undefined region.
    let t: Vec<f64> = (1..=8).map(|i| i as f64 * 0.25).collect();
    let failures = RefCell::new(0);
    let mut p = ResidualFn::new(t.len(), |x: &[f64], r: &mut [f64]| {
        if x[0] < 0.5 {
            *failures.borrow_mut() += 1;
            r.iter_mut().for_each(|v| *v = f64::NAN);
            return x[0] > 0.4; // sometimes "ok" with NaN inside: still rejected
        }
        for (ri, ti) in r.iter_mut().zip(&t) {
            *ri = (-x[0] * ti).exp() - (-2.0 * ti).exp();
        }
        true
    });
    let r = levenberg_marquardt(&mut p, &[0.6], &LevenbergMarquardtOptions::default()).unwrap();
    assert!(r.exit.is_success(), "{}", r.exit);
    assert!((r.x[0] - 2.0).abs() < 1e-8);
    assert!(r.cost.is_finite() && r.residuals.iter().all(|v| v.is_finite()));
}

#[test]
fn evaluation_limit_is_an_exit_reason() {
    let mut p = problems().into_iter().find(|p| p.name == "Meyer").unwrap();
    let options = LevenbergMarquardtOptions {
        max_evaluations: Some(20),
        ..Default::default()
    };
    let x0 = p.x0.clone();
    let r = levenberg_marquardt(&mut p, &x0, &options).unwrap();
    assert_eq!(r.exit, LmExit::MaxEvaluations);
    assert_eq!(r.evaluations, 20);
    assert!(r.cost < p.sum_of_squares(&x0));
}

#[test]
fn bad_input_is_a_specific_error() {
    let mut p = problems().remove(0);
    let d = LevenbergMarquardtOptions::default();
    assert!(matches!(
        levenberg_marquardt(&mut p, &[], &d),
        Err(OptError::EmptyStart)
    ));
    assert!(matches!(
        levenberg_marquardt(&mut p, &[f64::NAN, 1.0], &d),
        Err(OptError::NonFiniteStart { index: 0, .. })
    ));
    assert!(matches!(
        levenberg_marquardt(&mut p, &[1.0, 1.0, 1.0], &d),
        Err(OptError::TooFewResiduals {
            residuals: 2,
            parameters: 3
        })
    ));
    for (name, options) in [
        (
            "f_tolerance",
            LevenbergMarquardtOptions {
                f_tolerance: -1.0,
                ..d.clone()
            },
        ),
        (
            "x_tolerance",
            LevenbergMarquardtOptions {
                x_tolerance: f64::NAN,
                ..d.clone()
            },
        ),
        (
            "g_tolerance",
            LevenbergMarquardtOptions {
                g_tolerance: f64::INFINITY,
                ..d.clone()
            },
        ),
        (
            "max_evaluations",
            LevenbergMarquardtOptions {
                max_evaluations: Some(0),
                ..d.clone()
            },
        ),
        (
            "initial_step_bound",
            LevenbergMarquardtOptions {
                initial_step_bound: 0.0,
                ..d.clone()
            },
        ),
        (
            "finite_difference_step",
            LevenbergMarquardtOptions {
                finite_difference_step: Some(-1e-8),
                ..d.clone()
            },
        ),
        (
            "diagonal",
            LevenbergMarquardtOptions {
                diagonal: Some(vec![1.0, 0.0]),
                ..d.clone()
            },
        ),
    ] {
        let err = levenberg_marquardt(&mut p, &[1.0, 1.0], &options).unwrap_err();
        assert!(
            matches!(err, OptError::InvalidOption { name: n, .. } if n == name),
            "{err}"
        );
    }
    let short_diag = LevenbergMarquardtOptions {
        diagonal: Some(vec![1.0]),
        ..d.clone()
    };
    assert!(matches!(
        levenberg_marquardt(&mut p, &[1.0, 1.0], &short_diag),
        Err(OptError::LengthMismatch {
            expected: 2,
            found: 1,
            ..
        })
    ));
    let inverted = LevenbergMarquardtOptions {
        bounds: Some(Bounds {
            lower: vec![0.0, 2.0],
            upper: vec![1.0, 1.0],
        }),
        ..d.clone()
    };
    assert!(matches!(
        levenberg_marquardt(&mut p, &[1.0, 1.0], &inverted),
        Err(OptError::InvertedBounds { index: 1, .. })
    ));
    let mut failing = ResidualFn::new(2, |_: &[f64], _: &mut [f64]| false);
    assert!(matches!(
        levenberg_marquardt(&mut failing, &[1.0], &d),
        Err(OptError::InitialResiduals { index: None })
    ));
    let mut nan = ResidualFn::new(2, |_: &[f64], r: &mut [f64]| {
        r[0] = 1.0;
        r[1] = f64::NAN;
        true
    });
    assert!(matches!(
        levenberg_marquardt(&mut nan, &[1.0], &d),
        Err(OptError::InitialResiduals { index: Some(1) })
    ));
    // Residuals fine at x0 but undefined at every finite-difference point.
    let mut cliff = ResidualFn::new(1, |x: &[f64], r: &mut [f64]| {
        r[0] = x[0];
        x[0] == 1.0
    });
    assert!(matches!(
        levenberg_marquardt(&mut cliff, &[1.0], &d),
        Err(OptError::InitialJacobian { row: 0, column: 0 })
    ));
}
