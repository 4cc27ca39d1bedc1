//! Solver statistics of ode45 on the paper's identification experiment.
//!
//! `cargo run -p msd-ode --example paper_ode45`

use msd_ode::{Ode45Options, SVector, ode45};
use std::f64::consts::PI;

fn paper_input(t: f64) -> f64 {
    let step = if t >= 0.5 { 6.0 } else { 0.0 };
    let low = if (3.0..9.0).contains(&t) {
        3.0 * (2.0 * PI * 0.5 * t).sin()
    } else {
        0.0
    };
    let high = if (9.0..=15.0).contains(&t) {
        2.5 * (2.0 * PI * 1.4 * t).sin()
    } else {
        0.0
    };
    step + low + high
}

fn main() -> Result<(), msd_ode::OdeError> {
    let (m, c, k) = (2.5, 1.8, 120.0);
    let grid: Vec<f64> = (0..7501).map(|i| i as f64 * 0.002).collect();
    let mut rhs = |t: f64, y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| {
        d[0] = y[1];
        d[1] = (paper_input(t) - c * y[1] - k * y[0]) / m;
    };
    for rel_tol in [1e-3, 1e-6, 1e-9] {
        let options = Ode45Options {
            rel_tol,
            abs_tol: rel_tol * 1e-3,
            ..Ode45Options::default()
        };
        let sol = ode45(&mut rhs, &grid, &SVector::zeros(), &options)?;
        println!("RelTol {rel_tol:.0e}: {}", sol.stats);
    }
    Ok(())
}
