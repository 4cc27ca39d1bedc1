//! ode45 against the analytic solutions of m x'' + c x' + k x = F.
//!
//! The asserted bound comes from the error control: every accepted step keeps the local
//! error estimate below RelTol·max(|y|, |y_new|, AbsTol/RelTol) in each component, and the
//! propagated fifth-order solution is (asymptotically) more accurate than that
//! fourth-order estimate. A stable linear flow amplifies a local error made at any time by
//! at most K = sup ‖e^{At}‖∞. Hence
//!
//!   ‖global error‖∞ ≤ K · accepted_steps · RelTol · max(max‖y‖∞, AbsTol/RelTol),
//!
//! and the dense-output interpolant (fourth order, error of the same size) adds at most one
//! more such term.

use crate::common::Plant;
use msd_ode::{Ode45Options, SVector, ode45};

fn options(rel_tol: f64) -> Ode45Options {
    Ode45Options {
        rel_tol,
        abs_tol: rel_tol * 1e-3,
        ..Ode45Options::default()
    }
}

/// Solves the plant under `force` from `y0` on `grid` and checks against `exact`.
fn check(
    plant: Plant,
    force: impl Fn(f64) -> f64,
    y0: (f64, f64),
    exact: impl Fn(f64) -> (f64, f64),
    rel_tol: f64,
) -> f64 {
    let grid: Vec<f64> = (0..=1000).map(|i| i as f64 * 0.01).collect();
    let mut rhs = |t: f64, y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| {
        d[0] = y[1];
        d[1] = (force(t) - plant.c * y[1] - plant.k * y[0]) / plant.m;
    };
    let opts = options(rel_tol);
    let sol = ode45(&mut rhs, &grid, &SVector::<f64, 2>::new(y0.0, y0.1), &opts).expect("solves");
    let mut worst = 0.0f64;
    let mut scale = opts.abs_tol / opts.rel_tol;
    for (t, y) in sol.t.iter().zip(&sol.y) {
        let (x, v) = exact(*t);
        worst = worst.max((y[0] - x).abs()).max((y[1] - v).abs());
        scale = scale.max(x.abs()).max(v.abs());
    }
    let k = plant.amplification(10.0);
    let bound = k * (sol.stats.accepted_steps as f64 + 1.0) * rel_tol * scale;
    assert!(
        worst <= bound,
        "error {worst:e} exceeds the derived bound {bound:e} ({})",
        sol.stats
    );
    // The bound is loose; the solution should also be far better than the tolerance's
    // order of magnitude would allow over a single step.
    worst / (rel_tol * scale)
}

#[test]
fn free_decay_under_critically_and_over_damped() {
    for zeta in [0.05, 0.3, 1.0, 2.5] {
        let plant = Plant::with_damping_ratio(zeta);
        for rel_tol in [1e-3, 1e-6, 1e-9] {
            check(
                plant,
                |_| 0.0,
                (0.1, 0.0),
                |t| plant.free_decay(0.1, t),
                rel_tol,
            );
        }
    }
}

#[test]
fn step_response() {
    for zeta in [Plant::PAPER.zeta(), 1.0, 4.0] {
        let plant = Plant::with_damping_ratio(zeta);
        for rel_tol in [1e-3, 1e-6, 1e-9] {
            check(
                plant,
                |_| 6.0,
                (0.0, 0.0),
                |t| plant.step_response(6.0, t),
                rel_tol,
            );
        }
    }
}

#[test]
fn steady_state_sinusoid_below_at_and_above_resonance() {
    let plant = Plant::PAPER;
    let wn = plant.omega_n();
    for omega in [0.3 * wn, wn, 3.0 * wn] {
        let (x0, v0) = plant.steady_sine(3.0, omega, 0.0);
        for rel_tol in [1e-3, 1e-6, 1e-9] {
            check(
                plant,
                |t| 3.0 * (omega * t).sin(),
                (x0, v0),
                |t| plant.steady_sine(3.0, omega, t),
                rel_tol,
            );
        }
    }
}

#[test]
fn two_point_span_returns_every_step_refined() {
    let plant = Plant::PAPER;
    let mut rhs = |_t: f64, y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| {
        d[0] = y[1];
        d[1] = (-plant.c * y[1] - plant.k * y[0]) / plant.m;
    };
    let sol = ode45(
        &mut rhs,
        &[0.0, 2.0],
        &SVector::<f64, 2>::new(0.1, 0.0),
        &Ode45Options::default(),
    )
    .expect("solves");
    // One initial point plus `refine` = 4 points per accepted step, as MATLAB.
    assert_eq!(sol.t.len(), 1 + 4 * sol.stats.accepted_steps);
    assert_eq!(*sol.t.last().unwrap(), 2.0);
    assert!(sol.t.windows(2).all(|w| w[1] > w[0]));
    // Six evaluations per attempted step plus the initial one.
    let attempts = sol.stats.accepted_steps + sol.stats.rejected_steps;
    assert_eq!(sol.stats.rhs_evaluations, 1 + 6 * attempts);
}

#[test]
fn backwards_integration_matches_forward() {
    let plant = Plant::PAPER;
    let mut rhs = |_t: f64, y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| {
        d[0] = y[1];
        d[1] = (-plant.c * y[1] - plant.k * y[0]) / plant.m;
    };
    let (x1, v1) = plant.free_decay(0.1, 1.0);
    let opts = options(1e-10);
    let sol = ode45(
        &mut rhs,
        &[1.0, 0.5, 0.0],
        &SVector::<f64, 2>::new(x1, v1),
        &opts,
    )
    .expect("solves");
    assert_eq!(sol.t, vec![1.0, 0.5, 0.0]);
    let back = sol.y[2];
    // Backwards the flow amplifies by e^{ζωn t}; a bound as above with K = e^{ζωn·1}.
    let k = (plant.zeta() * plant.omega_n()).exp() * plant.amplification(1.0);
    let bound = k * (sol.stats.accepted_steps as f64 + 1.0) * 1e-10 * 1.0;
    assert!(
        (back[0] - 0.1).abs() <= bound && back[1].abs() <= bound,
        "{back:?}"
    );
}
