//! Compares the three input holds of the exact simulator with ode45 on a smooth input.
//!
//! `cargo run -p msd-ode --example holds`

use msd_ode::{
    ExactSimulator, Hold, LtiModel, Ode45Options, SMatrix, SVector, SampledInput, ode45,
};
use std::f64::consts::PI;

fn main() -> Result<(), msd_ode::OdeError> {
    let (m, c, k) = (2.5, 1.8, 120.0);
    let dt = 0.002;
    let force = |t: f64| 2.5 * (2.0 * PI * 1.4 * t).sin() + 3.0 * (2.0 * PI * 0.5 * t).sin();
    let grid: Vec<f64> = (0..7501).map(|i| i as f64 * dt).collect();
    let samples: Vec<f64> = grid.iter().map(|&t| force(t)).collect();

    let mut rhs = |t: f64, y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| {
        d[0] = y[1];
        d[1] = (force(t) - c * y[1] - k * y[0]) / m;
    };
    let options = Ode45Options {
        rel_tol: 1e-12,
        abs_tol: 1e-15,
        ..Ode45Options::default()
    };
    let reference = ode45(&mut rhs, &grid, &SVector::zeros(), &options)?;
    let peak = reference.y.iter().map(|y| y[0].abs()).fold(0.0, f64::max);
    println!("reference: ode45 at RelTol 1e-12 ({})", reference.stats);

    let model = LtiModel {
        a: SMatrix::<f64, 2, 2>::new(0.0, 1.0, -k / m, -c / m),
        b: SVector::<f64, 2>::new(0.0, 1.0 / m),
    };
    for hold in [Hold::Zero, Hold::First, Hold::Cubic] {
        let x = ExactSimulator::new(&model, dt, hold)?
            .simulate(&SVector::zeros(), &SampledInput::smooth(&samples))?;
        let worst = x
            .iter()
            .zip(&reference.y)
            .map(|(a, b)| (a[0] - b[0]).abs())
            .fold(0.0, f64::max);
        println!("{hold:?} hold: max |error| / peak = {:.2e}", worst / peak);
    }
    Ok(())
}
