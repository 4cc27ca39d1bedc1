//! The lines' error correlation an estimate reports ([`LineCorrelation`]) against the
//! correlation of its errors over many noise draws: an impact test's exponential window
//! (the response's noise and the force's) and random excitation under Hann windows.

use std::f64::consts::PI;

use msd_signal::{
    Complex64, FrfOptions, ImpactWindows, LineCorrelation, Record, WelchOptions, Window,
    frf_estimate, gaussian_noise,
};

const FS: f64 = 128.0;
const DRAWS: u64 = 300;

/// A half-sine hit of 20 ms at 0.1 s in a record of `n` samples.
fn hit(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let t = i as f64 / FS - 0.1;
            if (0.0..0.02).contains(&t) {
                (PI * t / 0.02).sin()
            } else {
                0.0
            }
        })
        .collect()
}

/// The empirical ρ(d) of the errors `e` (one vector per draw) over the lines `band`.
fn empirical(errors: &[Vec<Complex64>], band: std::ops::Range<usize>, d: usize) -> Complex64 {
    let (mut cross, mut a, mut b) = (Complex64::new(0.0, 0.0), 0.0, 0.0);
    for e in errors {
        for k in band.clone() {
            cross += e[k] * e[k + d].conj();
            a += e[k].norm_sqr();
            b += e[k + d].norm_sqr();
        }
    }
    cross / (a * b).sqrt()
}

/// Over 300 draws of about 60 lines with about 4 correlated: 1/√(300·60/4) ≈ 0.015
/// standard error per part; 4 of them.
const TOLERANCE: f64 = 0.06;

fn assert_matches(kernel: &[Complex64], errors: &[Vec<Complex64>], band: std::ops::Range<usize>) {
    for d in 0..6 {
        let want = LineCorrelation::at(kernel, d as i64);
        let got = empirical(errors, band.clone(), d);
        assert!(
            (got - want).norm() < TOLERANCE,
            "lag {d}: measured {got:.3}, reported {want:.3}"
        );
    }
}

/// Five hits of 8 s per estimate under a force window of 0.5 s and an exponential
/// window of τ = 2 s, each draw's records as (input, output) from `records` (the draw,
/// the hit): the reported kernel (`force` or the response's) and each draw's H − `h`.
fn impact_study(
    records: impl Fn(u64, usize) -> (Vec<f64>, Vec<f64>),
    h: f64,
    force: bool,
) -> (Vec<Complex64>, Vec<Vec<Complex64>>) {
    let options = FrfOptions {
        impact: Some(ImpactWindows {
            force_width: Some(0.5),
            decay_time: Some(2.0),
        }),
        ..FrfOptions::default()
    };
    let mut errors = Vec::new();
    let mut kernel = Vec::new();
    for draw in 0..DRAWS {
        let pairs: Vec<(Vec<f64>, Vec<f64>)> = (0..5).map(|i| records(draw, i)).collect();
        let records: Vec<Record<'_>> = pairs
            .iter()
            .map(|(input, output)| Record { input, output })
            .collect();
        let frf = frf_estimate(&records, FS, &options).expect("an estimate");
        let c = frf.line_correlation;
        kernel = if force { c.force } else { c.response };
        errors.push(frf.h.iter().map(|v| v - h).collect());
    }
    (kernel, errors)
}

/// ρ(d) ≈ e^(−jω_d·t_hit)/(1 − jπdτ/T) (ω_d = 2πd/T) for the response's noise (the
/// output is noise alone, so H1 is its error).
#[test]
fn an_impact_tests_response_noise_is_correlated_as_reported() {
    let n = (8.0 * FS) as usize;
    let (kernel, errors) = impact_study(
        |draw, i| {
            let noise = gaussian_noise(draw, &format!("response {i}"), 1.0, n).expect("noise");
            (hit(n), noise)
        },
        0.0,
        false,
    );
    // The window's 1/(1 − jπdτ/T), turned by the hit's delay (its centre at 0.11 s).
    let want =
        Complex64::from_polar(1.0, -2.0 * PI * 0.11 / 8.0) / Complex64::new(1.0, -PI * 2.0 / 8.0);
    assert!((kernel[1] - want).norm() < 0.05, "{} vs {want}", kernel[1]);
    assert_matches(&kernel, &errors, 8..200);
}

/// The same hits measured by a noisy load cell, the output the true force (H = 1): the
/// relative error −Σ conj(X)·M/S_xx is correlated through the force's window.
#[test]
fn an_impact_tests_force_noise_is_correlated_as_reported() {
    let n = (8.0 * FS) as usize;
    let (kernel, errors) = impact_study(
        |draw, i| {
            let m = gaussian_noise(draw, &format!("force {i}"), 0.002, n).expect("noise");
            let measured = hit(n).iter().zip(m).map(|(f, m)| f + m).collect();
            (measured, hit(n))
        },
        1.0,
        true,
    );
    // The force window keeps 0.5 s of 8: the errors are correlated over about 16 lines.
    assert!(
        LineCorrelation::sum(&kernel) > 8.0,
        "{}",
        LineCorrelation::sum(&kernel)
    );
    assert_matches(&kernel, &errors, 8..200);
}

/// Random force and response noise, Hann windows, half-overlapping segments: the
/// response's noise correlates neighbouring lines by about (2/3)² through both windows.
#[test]
fn random_excitation_under_hann_windows_is_correlated_as_reported() {
    let n = 4096;
    let options = FrfOptions {
        welch: WelchOptions {
            segment_length: Some(512),
            window: Window::Hann,
            ..WelchOptions::default()
        },
        ..FrfOptions::default()
    };
    let mut errors = Vec::new();
    let mut kernels = Vec::new();
    for draw in 0..DRAWS {
        let force = gaussian_noise(draw, "force", 1.0, n).expect("noise");
        let noise = gaussian_noise(draw, "response", 1.0, n).expect("noise");
        let frf = frf_estimate(
            &[Record {
                input: &force,
                output: &noise,
            }],
            FS,
            &options,
        )
        .expect("an estimate");
        kernels.push(frf.line_correlation.response.clone());
        errors.push(frf.h);
    }
    let mean: Vec<Complex64> = (0..3)
        .map(|d| kernels.iter().map(|k| k[d]).sum::<Complex64>() / DRAWS as f64)
        .collect();
    assert!((mean[1].re - 4.0 / 9.0).abs() < 0.05, "{}", mean[1]);
    assert_matches(&mean, &errors, 8..200);
}
