//! Free decay: the textbook case, every sensor, coverage and the Cramér–Rao bound over
//! 200 noise seeds, and the refusals.

use msd_ident::{
    IdentError, KnownParameter, ResponseQuantity,
    free_decay::{FreeDecayOptions, free_decay},
};
use msd_signal::gaussian_noise;
use std::f64::consts::PI;

/// The textbook plant: m = 6 kg, k = 5400 N/m, successive peaks in ratio 3 : 2.
const M: f64 = 6.0;
const K: f64 = 5400.0;

fn textbook_zeta() -> f64 {
    let delta = 1.5f64.ln();
    delta / (4.0 * PI * PI + delta * delta).sqrt()
}

/// The response of `quantity` to a release from x0, v0 (plus `offset`), N samples of dt.
fn ring_down(
    quantity: ResponseQuantity,
    x0: f64,
    v0: f64,
    offset: f64,
    n: usize,
    dt: f64,
) -> Vec<f64> {
    let (wn, zeta) = ((K / M).sqrt(), textbook_zeta());
    let (s, wd) = (zeta * wn, wn * (1.0 - zeta * zeta).sqrt());
    let b = (v0 + s * x0) / wd;
    (0..n)
        .map(|i| {
            let t = i as f64 * dt;
            let e = (-s * t).exp();
            let (c, sn) = ((wd * t).cos(), (wd * t).sin());
            let x = e * (x0 * c + b * sn);
            let v = e * ((b * wd - s * x0) * c - (x0 * wd + s * b) * sn);
            let a = -wn * wn * x - 2.0 * s * v;
            offset
                + match quantity {
                    ResponseQuantity::Displacement => x,
                    ResponseQuantity::Velocity => v,
                    ResponseQuantity::Acceleration => a,
                }
        })
        .collect()
}

#[test]
fn textbook_decay_to_four_significant_digits_by_fit_and_decrement_for_every_sensor() {
    for quantity in [
        ResponseQuantity::Displacement,
        ResponseQuantity::Velocity,
        ResponseQuantity::Acceleration,
    ] {
        let y = ring_down(quantity, 0.01, 0.2, 0.5, 3000, 1e-3);
        let options = FreeDecayOptions {
            response: quantity,
            known: KnownParameter::Mass(M),
        };
        let fit = free_decay(1e-3, &y, &options).unwrap();
        let p = fit.parameters.unwrap();
        // δ = 0.4055, ζ = 0.0644, c = 23.18 N·s/m (the textbook's digits).
        assert!(
            (fit.classroom.log_decrement - 0.4055).abs() < 5e-5,
            "{quantity:?}: {fit}"
        );
        assert!(
            (fit.classroom.damping_ratio - 0.0644).abs() < 5e-5,
            "{quantity:?}: {fit}"
        );
        assert!(
            (fit.damping_ratio.value - 0.0644).abs() < 5e-5,
            "{quantity:?}: {fit}"
        );
        assert!(
            (p.damping.value - 23.18).abs() < 5e-3,
            "{quantity:?}: {fit}"
        );
        assert!(
            (p.stiffness.value / K - 1.0).abs() < 1e-6,
            "{quantity:?}: {fit}"
        );
        // The initial state and the offset, read back through the equation of motion.
        assert!(
            (fit.initial_displacement.value - 0.01).abs() < 1e-7,
            "{quantity:?}: {fit}"
        );
        assert!(
            (fit.initial_velocity.value - 0.2).abs() < 1e-5,
            "{quantity:?}: {fit}"
        );
        assert!((fit.offset.value - 0.5).abs() < 1e-7, "{quantity:?}: {fit}");
        let fd = fit.damped_frequency_hz.value;
        assert!(
            (fit.classroom.damped_frequency_hz / fd - 1.0).abs() < 1e-4,
            "{fit}"
        );
    }
}

#[test]
fn without_a_known_mass_only_the_natural_frequency_and_damping_ratio_are_given() {
    let y = ring_down(ResponseQuantity::Displacement, 0.01, 0.0, 0.0, 2000, 1e-3);
    let fit = free_decay(1e-3, &y, &FreeDecayOptions::default()).unwrap();
    assert!(fit.parameters.is_none());
    assert_eq!(fit.identifiable, ["natural_frequency_hz", "damping_ratio"]);
    assert!(
        fit.note
            .as_deref()
            .unwrap()
            .contains("not separately identifiable")
    );
    // A known static stiffness gives m and c instead.
    let options = FreeDecayOptions {
        known: KnownParameter::Stiffness(K),
        ..Default::default()
    };
    let p = free_decay(1e-3, &y, &options).unwrap().parameters.unwrap();
    assert!((p.mass.value / M - 1.0).abs() < 1e-7 && p.stiffness.standard_error == 0.0);
}

/// 200 seeds of a noisy ring-down (noise 2 % of the initial amplitude): each 95 %
/// interval covers the truth 95 ± 3 % of the time (binomial σ = 1.5 %, so 2σ), and the
/// spread of the estimates matches the Cramér–Rao bound the fit reports to within 10 %
/// (the relative standard error of a standard deviation from 200 draws is 1/√398 = 5 %).
#[test]
fn intervals_cover_and_the_spread_meets_the_cramer_rao_bound_over_200_seeds() {
    let clean = ring_down(ResponseQuantity::Displacement, 0.01, 0.0, 0.0, 2000, 1e-3);
    let options = FreeDecayOptions {
        known: KnownParameter::Mass(M),
        ..Default::default()
    };
    let truth = [
        (K / M).sqrt() / (2.0 * PI),
        textbook_zeta(),
        2.0 * textbook_zeta() * (K * M).sqrt(),
        K,
    ];
    let (mut covered, mut values, mut errors) = ([0usize; 4], vec![Vec::new(); 4], [0.0; 4]);
    let seeds = 200;
    for seed in 0..seeds {
        let noise = gaussian_noise(seed, "free decay", 2e-4, clean.len()).unwrap();
        let y: Vec<f64> = clean.iter().zip(&noise).map(|(c, n)| c + n).collect();
        let fit = free_decay(1e-3, &y, &options).unwrap();
        let p = fit.parameters.unwrap();
        let intervals = [
            fit.natural_frequency_hz,
            fit.damping_ratio,
            p.damping,
            p.stiffness,
        ];
        for (q, iv) in intervals.iter().enumerate() {
            covered[q] += usize::from(iv.contains(truth[q]));
            values[q].push(iv.value);
            errors[q] += iv.standard_error / seeds as f64;
        }
    }
    for q in 0..4 {
        let coverage = covered[q] as f64 / seeds as f64;
        assert!(
            (coverage - 0.95).abs() <= 0.03,
            "quantity {q}: coverage {coverage}"
        );
        let n = values[q].len() as f64;
        let mean = values[q].iter().sum::<f64>() / n;
        let sd = (values[q].iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        eprintln!(
            "quantity {q}: coverage {coverage}, sd / bound {}",
            sd / errors[q]
        );
        assert!(
            (sd / errors[q] - 1.0).abs() <= 0.10,
            "quantity {q}: sd {sd} vs bound {}",
            errors[q]
        );
    }
}

#[test]
fn records_that_do_not_ring_down_are_refused_with_the_reason() {
    let not_decaying = |y: &[f64]| {
        let err = free_decay(1e-3, y, &FreeDecayOptions::default()).unwrap_err();
        assert!(matches!(err, IdentError::NotIdentifiable { .. }), "{err}");
        err.to_string()
    };
    // Constant: nothing stands above the noise.
    let message = not_decaying(&vec![0.3; 500]);
    assert!(message.contains("at least two oscillations"), "{message}");
    // Growing oscillation: negative damping.
    let growing: Vec<f64> = (0..2000)
        .map(|i| {
            let t = i as f64 * 1e-3;
            (0.5 * t).exp() * (2.0 * PI * 5.0 * t).cos()
        })
        .collect();
    let message = not_decaying(&growing);
    assert!(message.contains("do not shrink"), "{message}");
    // Too short, a NaN, a bad known mass: located input errors.
    let y = ring_down(ResponseQuantity::Displacement, 0.01, 0.0, 0.0, 2000, 1e-3);
    assert!(matches!(
        free_decay(1e-3, &y[..10], &FreeDecayOptions::default()),
        Err(IdentError::TooFewSamples { got: 10, .. })
    ));
    let mut bad = y.clone();
    bad[7] = f64::NAN;
    assert!(matches!(
        free_decay(1e-3, &bad, &FreeDecayOptions::default()),
        Err(IdentError::NonFiniteSample { index: 7, .. })
    ));
    let options = FreeDecayOptions {
        known: KnownParameter::Mass(-1.0),
        ..Default::default()
    };
    let err = free_decay(1e-3, &y, &options).unwrap_err().to_string();
    assert!(err.contains("known mass = -1"), "{err}");
}

/// Issue 31, class 7: the classroom decrement under noise. The paper's plant released
/// from 10 mm with σ = 0.1 mm (configs/free-decay.toml): over 200 seeds the classroom δ
/// is on average within 2 % of the analytic 2πζ/√(1 − ζ²) (it was 13 % low over this
/// 10 s record: the peaks of noisy samples, lifted by the noise, entered the line fit of
/// the small swings with equal weight).
#[test]
fn the_classroom_decrement_is_unbiased_under_the_shipped_noise() {
    use msd_ident::free_decay::ClassroomEstimates;
    let (m, c, k) = (2.5f64, 1.8f64, 120.0f64);
    let wn = (k / m).sqrt();
    let zeta = c / (2.0 * (k * m).sqrt());
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let delta = 2.0 * PI * zeta / (1.0 - zeta * zeta).sqrt();
    let (dt, n) = (0.002, 5001);
    let clean: Vec<f64> = (0..n)
        .map(|i| {
            let t = i as f64 * dt;
            0.01 * (-zeta * wn * t).exp() * ((wd * t).cos() + zeta * wn / wd * (wd * t).sin())
        })
        .collect();
    let mut sum = 0.0;
    for seed in 0..200 {
        let e = gaussian_noise(seed, "classroom", 1e-4, n).expect("noise");
        let y: Vec<f64> = clean.iter().zip(&e).map(|(a, b)| a + b).collect();
        let estimate = ClassroomEstimates::from_record(dt, &y).expect("a ring-down");
        sum += estimate.log_decrement / delta - 1.0;
    }
    let mean = sum / 200.0;
    eprintln!("mean relative error of the classroom δ over 200 seeds: {mean:.4}");
    assert!(mean.abs() < 0.02, "mean relative error of δ: {mean:.4}");
}
