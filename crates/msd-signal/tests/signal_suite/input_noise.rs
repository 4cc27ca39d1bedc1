//! The force channel's noise measured after an impact test's force window, and the
//! per-line variance of H1's relative error it predicts, against the scatter and the
//! bias of H1 over many simulated tests.

use msd_signal::{Complex64, FrfOptions, ImpactWindows, Record, frf_estimate, gaussian_noise};

const FS: f64 = 256.0;
const N: usize = 1024;
const HITS: usize = 5;

/// `HITS` half-sine hits (10 ms, 100 N ± 20 %) at 0.05 s with force-channel noise of
/// `sigma` N on every sample; the response is the clean force times 2 (a gain: every
/// window cancels in H = X/F, so H1's error is the force noise's alone).
fn hits(seed: u64, sigma: f64) -> Vec<(Vec<f64>, Vec<f64>)> {
    let spread = gaussian_noise(seed, "peaks", 0.2, HITS).unwrap();
    (0..HITS)
        .map(|h| {
            let clean: Vec<f64> = (0..N)
                .map(|i| {
                    let t = i as f64 / FS - 0.05;
                    match (0.0..0.01).contains(&t) {
                        true => 100.0 * (1.0 + spread[h]) * (std::f64::consts::PI * t / 0.01).sin(),
                        false => 0.0,
                    }
                })
                .collect();
            let noise = gaussian_noise(seed, &format!("force.{h}"), sigma, N).unwrap();
            let force = clean.iter().zip(&noise).map(|(c, e)| c + e).collect();
            (force, clean.iter().map(|c| 2.0 * c).collect())
        })
        .collect()
}

fn options() -> FrfOptions {
    FrfOptions {
        impact: Some(ImpactWindows {
            force_width: Some(0.1),
            decay_time: Some(1.0),
        }),
        ..FrfOptions::default()
    }
}

/// Over 300 simulated tests, at the lines below the pulse's first zero (150 Hz;
/// 1.5–100 Hz here), |Ĥ/H − 1|²/v_k averages 1 and (Ĥ/H − 1)/v_k averages −(K − 1)
/// (H1 low by the force noise's share of the force's power, less the one part in K
/// that the noise correlated with the hits' own spectra gives back: to second order,
/// E[Ĥ1/H] = 1 − (K − 1)·v). The force window correlates the lines' errors over about
/// T/0.1 s = 40 lines, so the 300 × 394 ratios hold about 3000 independent values: the
/// first mean's standard deviation is about 1/√3000 ≈ 0.02 (0.08 allowed), the second's
/// 1/((K − 1)·√(2v)·√3000) ≈ 0.11 of itself at v ≈ 8e-4 (1 N of noise; 0.4 allowed).
#[test]
fn the_measured_force_noise_predicts_h1s_scatter_and_bias() {
    let (seeds, sigma) = (300u64, 1.0);
    let (mut scatter, mut bias, mut count) = (0.0, 0.0, 0.0);
    for seed in 0..seeds {
        let records = hits(seed, sigma);
        let pairs: Vec<Record<'_>> = (records.iter())
            .map(|(input, output)| Record { input, output })
            .collect();
        let frf = frf_estimate(&pairs, FS, &options()).unwrap();
        let v = frf.input_noise_variance.as_ref().expect("measured");
        for ((&f, h), &v) in frf.frequency.iter().zip(&frf.h).zip(v) {
            if !(1.5..=100.0).contains(&f) {
                continue;
            }
            let e = h / Complex64::new(2.0, 0.0) - 1.0;
            scatter += e.norm_sqr() / v;
            bias += e.re / ((HITS - 1) as f64 * v);
            count += 1.0;
        }
    }
    let (scatter, bias) = (scatter / count, bias / count);
    assert!((scatter - 1.0).abs() < 0.08, "E|ε|²/v = {scatter}");
    assert!((bias + 1.0).abs() < 0.4, "E[ε]/((K − 1)·v) = {bias}");
}

/// σ is measured within its sampling error (MAD of 5 × 998 samples: about 1.17/√(2n)
/// ≈ 1.2 %), unmoved by an offset on the force channel; a channel without noise after
/// the window says nothing (`None`), and so does a force window reaching the records' end.
#[test]
fn the_force_noise_is_measured_after_the_window_or_not_at_all() {
    let records = hits(4, 0.3);
    let offset: Vec<(Vec<f64>, Vec<f64>)> = (records.iter())
        .map(|(f, r)| (f.iter().map(|v| v + 7.0).collect(), r.clone()))
        .collect();
    for rs in [&records, &offset] {
        let pairs: Vec<Record<'_>> = (rs.iter())
            .map(|(input, output)| Record { input, output })
            .collect();
        let sigma = msd_signal::force_channel_noise(&pairs, 26).expect("measured");
        assert!((sigma / 0.3 - 1.0).abs() < 0.05, "σ = {sigma}");
    }
    let clean = hits(4, 0.0);
    let pairs: Vec<Record<'_>> = (clean.iter())
        .map(|(input, output)| Record { input, output })
        .collect();
    let frf = frf_estimate(&pairs, FS, &options()).unwrap();
    assert_eq!(frf.input_noise_variance, None);
    let whole = FrfOptions {
        impact: Some(ImpactWindows {
            force_width: Some(10.0),
            decay_time: None,
        }),
        ..FrfOptions::default()
    };
    let pairs: Vec<Record<'_>> = (records.iter())
        .map(|(input, output)| Record { input, output })
        .collect();
    assert_eq!(
        frf_estimate(&pairs, FS, &whole)
            .unwrap()
            .input_noise_variance,
        None
    );
}
