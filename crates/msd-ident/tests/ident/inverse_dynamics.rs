//! The test machine under any stroke (`inverse_dynamics`): exact on a noise-free record,
//! and intervals that cover the truth at their nominal rate when the load cell's noise is
//! coloured (an AR(1) process, as a filtered amplifier's is).

use msd_ident::dynamometer::{InverseOptions, inverse_dynamics, machine_recording};
use msd_ident::law::DampingLaw;
use msd_signal::Recording;
use std::f64::consts::PI;

const TRUTH: [(&str, f64); 4] = [
    ("mass", 20.0),
    ("damping", 150.0),
    ("coulomb_force", 12.0),
    ("force_offset", -2.0),
];

/// A two-tone stroke of `n` samples at 1 kHz and its exact force, plus AR(1) noise of
/// innovation σ `sigma` and pole `rho` from `seed`.
fn record(n: usize, seed: u64, sigma: f64, rho: f64) -> Recording {
    let dt = 1e-3;
    let (w1, w2) = (2.0 * PI * 0.7, 2.0 * PI * 3.1);
    let innovations = msd_signal::gaussian_noise(seed, "load cell", sigma, n).unwrap();
    let mut e = 0.0;
    let (mut stroke, mut force) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for (i, innovation) in innovations.iter().enumerate() {
        let t = i as f64 * dt;
        let x = 0.05 * (w1 * t).sin() + 0.01 * (w2 * t).sin();
        let v = 0.05 * w1 * (w1 * t).cos() + 0.01 * w2 * (w2 * t).cos();
        let a = -0.05 * w1 * w1 * (w1 * t).sin() - 0.01 * w2 * w2 * (w2 * t).sin();
        e = rho * e + innovation;
        stroke.push(x);
        force.push(20.0 * a + 150.0 * v + 12.0 * v.signum() - 2.0 + e);
    }
    machine_recording(format!("seed {seed}"), dt, stroke, force)
}

#[test]
fn a_noise_free_record_gives_the_coefficients_back() {
    let fit = inverse_dynamics(&[record(20_000, 0, 0.0, 0.0)], &InverseOptions::default()).unwrap();
    let best = &fit.laws[fit.best];
    assert_eq!(best.law, DampingLaw::CoulombViscous);
    // What is left: central differences (relative error (ω·dt)²/6 ≈ 1.6e-4 at 3.1 Hz),
    // the smoothed sign's width (v_s = 10⁻³ × RMS velocity) and the filter's ends.
    for (name, truth) in TRUTH {
        let value = best.value(name).unwrap();
        assert!(
            (value / truth - 1.0).abs() < 1e-3,
            "{name} = {value}, truth {truth}"
        );
    }
}

#[test]
fn intervals_cover_the_truth_under_coloured_force_noise() {
    // AR(1) with ρ = 0.98 (a correlation time of 50 samples) and a stationary σ of
    // 2 N (about 3 % of the force's RMS): the OLS standard errors would be ~7× too small.
    let options = InverseOptions {
        laws: vec![DampingLaw::CoulombViscous],
        ..InverseOptions::default()
    };
    let seeds = 100;
    let sigma = 2.0 * (1.0f64 - 0.98 * 0.98).sqrt();
    let mut covered = [0usize; 4];
    for seed in 0..seeds {
        let fit = inverse_dynamics(&[record(20_000, seed + 1, sigma, 0.98)], &options).unwrap();
        for (k, (name, truth)) in TRUTH.iter().enumerate() {
            let c = fit.laws[0]
                .coefficients
                .iter()
                .find(|c| c.name == *name)
                .unwrap();
            covered[k] += usize::from(c.estimate.contains(*truth));
        }
    }
    // 100 draws of a 95 % interval: below 89 has probability < 1 % (binomial).
    for (k, (name, _)) in TRUTH.iter().enumerate() {
        assert!(
            covered[k] >= 89,
            "{name}: {} of {seeds} intervals cover the truth",
            covered[k]
        );
    }
}
