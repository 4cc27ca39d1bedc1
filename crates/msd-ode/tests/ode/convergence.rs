//! Observed convergence of ode45 under tolerance reduction.
//!
//! For a pair of orders 5(4) with local extrapolation the controller chooses steps with
//! h⁵ ∝ RelTol (the error estimate is that of the fourth-order formula, O(h⁵) per step),
//! and the propagated fifth-order solution has global error O(h⁵). So the global error
//! is proportional to RelTol: each 10× tightening reduces it by about 10× (slope 1 on a
//! log–log plot). A method of order p would give slope p/5; with a broken fifth-order
//! formula (order 4) the slope would drop to 0.8 and below.

use crate::common::Plant;
use msd_ode::{Ode45Options, SVector, ode45};

#[test]
fn global_error_is_proportional_to_rel_tol() {
    let plant = Plant::PAPER;
    let omega = 1.4 * 2.0 * std::f64::consts::PI;
    let (x0, v0) = plant.steady_sine(2.5, omega, 0.0);
    let grid: Vec<f64> = (0..=1500).map(|i| i as f64 * 0.01).collect();
    let mut log_tol = Vec::new();
    let mut log_err = Vec::new();
    for e in 5..=10 {
        let rel_tol = 10f64.powi(-e);
        let mut rhs = |t: f64, y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| {
            d[0] = y[1];
            d[1] = (2.5 * (omega * t).sin() - plant.c * y[1] - plant.k * y[0]) / plant.m;
        };
        let opts = Ode45Options {
            rel_tol,
            abs_tol: rel_tol * 1e-3,
            ..Ode45Options::default()
        };
        let sol = ode45(&mut rhs, &grid, &SVector::<f64, 2>::new(x0, v0), &opts).expect("solves");
        let err = sol
            .t
            .iter()
            .zip(&sol.y)
            .map(|(t, y)| (y[0] - plant.steady_sine(2.5, omega, *t).0).abs())
            .fold(0.0, f64::max);
        log_tol.push(rel_tol.log10());
        log_err.push(err.log10());
    }
    // Least-squares slope of log(err) against log(tol).
    let n = log_tol.len() as f64;
    let mt = log_tol.iter().sum::<f64>() / n;
    let me = log_err.iter().sum::<f64>() / n;
    let sxy: f64 = log_tol
        .iter()
        .zip(&log_err)
        .map(|(x, y)| (x - mt) * (y - me))
        .sum();
    let sxx: f64 = log_tol.iter().map(|x| (x - mt).powi(2)).sum();
    let slope = sxy / sxx;
    assert!(
        (0.85..=1.15).contains(&slope),
        "slope {slope}, errors {log_err:?}"
    );
    // Each single decade also reduces the error by 10^(1 ± 0.35).
    for w in log_err.windows(2) {
        let decade = w[0] - w[1];
        assert!(
            (0.65..=1.35).contains(&decade),
            "decade reduction 10^{decade}: {log_err:?}"
        );
    }
}
