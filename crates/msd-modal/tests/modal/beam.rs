//! A simulated roving-hammer test on a simply supported beam with known modes: ten points,
//! the accelerometer at point 3, the hammer at every point, 1 Hz lines, 1 % noise. The
//! set's fit against the truth: every mode, fn, ζ, the shapes (MAC), the modal masses,
//! and the coverage of the 95 % intervals over 200 noise seeds.

use msd_modal::ModalOptions;
use msd_modal::{Dof, ModalParameters, SetMember, fit_mode_set, mac, synthetic_frequency_response};
use msd_signal::Complex64;

const POINTS: usize = 10;
const RESPONSE: usize = 3;
/// fn = 20 r² Hz (a simply supported beam), ζ falling with r, modal mass 0.5 kg for the
/// shapes sin(rπx/L).
const MODES: [(f64, f64); 5] = [
    (20.0, 0.01),
    (80.0, 0.005),
    (180.0, 0.003),
    (320.0, 0.002),
    (500.0, 0.0015),
];
const MODAL_MASS: f64 = 0.5;

/// sin(rπx_i/L) at the points x_i = i·L/11.
fn shape(r: usize) -> Vec<f64> {
    (1..=POINTS)
        .map(|i| ((r + 1) as f64 * std::f64::consts::PI * i as f64 / (POINTS + 1) as f64).sin())
        .collect()
}

/// The set with noise `relative_noise` from `seed`.
fn beam(relative_noise: f64, seed: u64) -> Vec<SetMember> {
    let f: Vec<f64> = (5..=600).map(|i| i as f64).collect();
    (1..=POINTS)
        .map(|hammer| {
            let terms: Vec<ModalParameters> = MODES
                .iter()
                .enumerate()
                .map(|(r, &(fn_hz, zeta))| ModalParameters {
                    natural_frequency_hz: fn_hz,
                    damping_ratio: zeta,
                    modal_constant: shape(r)[RESPONSE - 1] * shape(r)[hammer - 1] / MODAL_MASS,
                    modal_constant_imaginary: 0.0,
                })
                .collect();
            let frf =
                synthetic_frequency_response(&f, relative_noise, seed * 100 + hammer as u64, |f| {
                    terms.iter().map(|m| m.receptance(f)).sum()
                })
                .expect("a synthetic FRF");
            SetMember {
                frf,
                response: Dof {
                    node: RESPONSE as u32,
                    direction: 3,
                },
                reference: Dof {
                    node: hammer as u32,
                    direction: 3,
                },
            }
        })
        .collect()
}

#[test]
fn every_mode_and_shape_of_a_simulated_roving_hammer_test() {
    let fit = fit_mode_set(&beam(0.01, 1), &ModalOptions::default()).expect("a fit");
    assert_eq!(fit.modes.len(), MODES.len(), "{fit}");
    for (r, (mode, &(fn_hz, zeta))) in fit.modes.iter().zip(&MODES).enumerate() {
        let f = mode.natural_frequency_hz.value;
        assert!((f / fn_hz - 1.0).abs() < 1e-3, "mode {}: fn = {f}", r + 1);
        let z = mode.damping_ratio.value;
        assert!((z / zeta - 1.0).abs() < 0.05, "mode {}: ζ = {z}", r + 1);
        let estimated: Vec<Complex64> = mode
            .shape
            .iter()
            .map(|e| Complex64::new(e.re, e.im))
            .collect();
        let truth: Vec<Complex64> = shape(r).iter().map(|&x| Complex64::new(x, 0.0)).collect();
        let m = mac(&estimated, &truth);
        assert!(m >= 0.99, "mode {}: MAC {m}", r + 1);
        // The modal mass of the unit shape: m_r / max|φ|².
        let largest = shape(r).iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let expected = MODAL_MASS / (largest * largest);
        let got = mode.modal_mass.expect("a driving point");
        assert!(
            (got / expected - 1.0).abs() < 0.05,
            "mode {}: modal mass {got} vs {expected}",
            r + 1
        );
        assert!(mode.mpc > Some(0.99), "mode {}: MPC {:?}", r + 1, mode.mpc);
    }
}

/// The 95 % intervals of every fn and ζ over 200 seeds: 2,000 intervals, binomial
/// standard deviation 0.5 %, so 95 ± 3 % is six of them.
#[test]
fn the_intervals_of_a_set_cover_the_truth() {
    let (mut inside, mut total) = (0, 0);
    for seed in 0..200 {
        let fit = fit_mode_set(&beam(0.01, seed), &ModalOptions::default()).expect("a fit");
        assert_eq!(fit.modes.len(), MODES.len(), "seed {seed}: {fit}");
        for (mode, &(fn_hz, zeta)) in fit.modes.iter().zip(&MODES) {
            inside += usize::from(mode.natural_frequency_hz.contains(fn_hz));
            inside += usize::from(mode.damping_ratio.contains(zeta));
            total += 2;
        }
    }
    let coverage = inside as f64 / total as f64;
    eprintln!("coverage of fn and ζ over 200 seeds: {coverage}");
    assert!(
        (coverage - 0.95).abs() <= 0.03,
        "coverage {coverage} over {total} intervals"
    );
}
