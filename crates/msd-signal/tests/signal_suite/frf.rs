//! H1, H2 and Hv on a known system with noise on either channel (the textbook bias
//! directions), the exponential window's exact pole shift, tables, conversions, errors.

use std::f64::consts::TAU;

use msd_signal::{
    Complex64, Estimator, FrequencyResponseEstimate, FrfKind, FrfOptions, ImpactWindows, Record,
    SignalError, WelchOptions, frf_estimate, gaussian_noise,
};

const FS: f64 = 100.0;

/// y_t = u_t − 0.5·u_{t−1}: H(f) = 1 − 0.5·e^{−2πif/fs}, |H| between 0.5 and 1.5.
fn fir(u: &[f64]) -> Vec<f64> {
    (0..u.len())
        .map(|t| u[t] - if t > 0 { 0.5 * u[t - 1] } else { 0.0 })
        .collect()
}

fn fir_response(f: f64) -> Complex64 {
    Complex64::new(1.0, 0.0) - Complex64::from_polar(0.5, -TAU * f / FS)
}

/// The estimates by all three estimators of the system from white input (σ = 1), with
/// white noise of std `input_noise` on the measured input and `output_noise` on the
/// measured output; 256-sample Hann segments of 2¹⁶ samples (K = 511).
fn estimates(input_noise: f64, output_noise: f64) -> [FrequencyResponseEstimate; 3] {
    let n = 1 << 16;
    let u = gaussian_noise(7, "frf.u", 1.0, n).expect("valid");
    let y = fir(&u);
    let add = |x: &[f64], stream: &str, sigma: f64| -> Vec<f64> {
        if sigma == 0.0 {
            return x.to_vec();
        }
        let e = gaussian_noise(7, stream, sigma, n).expect("valid");
        x.iter().zip(&e).map(|(a, b)| a + b).collect()
    };
    let (x, y) = (
        add(&u, "frf.m", input_noise),
        add(&y, "frf.n", output_noise),
    );
    [Estimator::H1, Estimator::H2, Estimator::Hv].map(|estimator| {
        let options = FrfOptions {
            estimator,
            welch: WelchOptions {
                segment_length: Some(256),
                ..WelchOptions::default()
            },
            ..FrfOptions::default()
        };
        frf_estimate(
            &[Record {
                input: &x,
                output: &y,
            }],
            FS,
            &options,
        )
        .expect("valid")
    })
}

/// The mean over the lines 1 … 127 of |Ĥ|/|H| divided by `expected(|H|²)`.
fn mean_ratio(frf: &FrequencyResponseEstimate, expected: impl Fn(f64) -> f64) -> f64 {
    let lines = 1..frf.h.len() - 1;
    let count = lines.len() as f64;
    lines
        .map(|k| {
            let h = fir_response(frf.frequency[k]);
            frf.h[k].norm() / h.norm() / expected(h.norm_sqr())
        })
        .sum::<f64>()
        / count
}

#[test]
fn without_noise_the_three_estimators_agree_and_the_coherence_is_one() {
    let [h1, h2, hv] = estimates(0.0, 0.0);
    assert_eq!(h1.averages, 511);
    assert!((h1.noise_bandwidth - 1.5).abs() < 1e-12); // Hann
    for k in 1..h1.h.len() - 1 {
        let exact = fir_response(h1.frequency[k]);
        for est in [&h1, &h2, &hv] {
            // What is left is the system's one-sample memory across the window: w_t·y_t
            // and the response to w_t·u_t differ by 0.5·u_{t−1}·(w_{t−1} − w_t), of
            // relative size π/L; averaged, it shows at the lowest lines only.
            assert!((est.h[k] - exact).norm() < 5e-3, "line {k}: {}", est.h[k]);
        }
        assert!(
            h1.coherence[k] > 0.998,
            "line {k}: γ² = {}",
            h1.coherence[k]
        );
    }
}

#[test]
fn output_noise_leaves_h1_unbiased_and_biases_h2_high() {
    // S_nn = σ² over S_uu = 1: H2 = H·(1 + σ²/|H|²) = H/γ², γ² = |H|²/(|H|² + σ²).
    let sigma2: f64 = 0.25;
    let [h1, h2, hv] = estimates(0.0, sigma2.sqrt());
    // Per line the relative random error is √((1 − γ²)/(2Kγ²)) ≤ 0.02; the mean of 127
    // lines is good to 0.2 %.
    let h1_ratio = mean_ratio(&h1, |_| 1.0);
    let h2_ratio = mean_ratio(&h2, |h2| 1.0 + sigma2 / h2);
    let h2_plain = mean_ratio(&h2, |_| 1.0);
    assert!((h1_ratio - 1.0).abs() < 0.01, "|H1|/|H| = {h1_ratio}");
    assert!((h2_ratio - 1.0).abs() < 0.01, "|H2|/(|H|/γ²) = {h2_ratio}");
    assert!(h2_plain > 1.2, "|H2|/|H| = {h2_plain}: biased high");
    let coherence_ratio: f64 = (1..128)
        .map(|k| {
            let h2 = fir_response(h1.frequency[k]).norm_sqr();
            h1.coherence[k] / (h2 / (h2 + sigma2))
        })
        .sum::<f64>()
        / 127.0;
    assert!(
        (coherence_ratio - 1.0).abs() < 0.01,
        "γ²/γ²_theory = {coherence_ratio}"
    );
    // |H1| ≤ |Hv| ≤ |H2| on every line, and H1/H2 = γ² (identities of the estimators).
    for k in 1..128 {
        assert!(h1.h[k].norm() <= hv.h[k].norm() * (1.0 + 1e-12));
        assert!(hv.h[k].norm() <= h2.h[k].norm() * (1.0 + 1e-12));
        assert!(((h1.h[k] / h2.h[k]).re - h1.coherence[k]).abs() < 1e-9);
    }
}

#[test]
fn input_noise_biases_h1_low_and_leaves_h2_unbiased() {
    // Measured input u + m, S_mm = σ²: H1 = H·S_uu/(S_uu + σ²) = 0.8·H.
    let sigma2: f64 = 0.25;
    let [h1, h2, _] = estimates(sigma2.sqrt(), 0.0);
    let h1_ratio = mean_ratio(&h1, |_| 1.0);
    let h2_ratio = mean_ratio(&h2, |_| 1.0);
    assert!(
        (h1_ratio - 1.0 / (1.0 + sigma2)).abs() < 0.01,
        "|H1|/|H| = {h1_ratio}"
    );
    assert!((h2_ratio - 1.0).abs() < 0.01, "|H2|/|H| = {h2_ratio}");
}

#[test]
fn hv_is_unbiased_with_equal_noise_on_both_channels() {
    // S_xx = S_uu + σ², S_yy = |H|²S_uu + σ², S_xy = H·S_uu: the formula gives H exactly.
    let [h1, h2, hv] = estimates(0.5, 0.5);
    let (r1, r2, rv) = (
        mean_ratio(&h1, |_| 1.0),
        mean_ratio(&h2, |_| 1.0),
        mean_ratio(&hv, |_| 1.0),
    );
    assert!((rv - 1.0).abs() < 0.01, "|Hv|/|H| = {rv}");
    assert!(r1 < 0.9 && r2 > 1.1, "H1 {r1}, H2 {r2}");
}

/// y_t = a·y_{t−1} + b·u_t: G(z) = b/(1 − a·z⁻¹), at z = e^{2πif/fs}.
fn first_order(a: f64, b: f64, f: f64) -> Complex64 {
    Complex64::new(b, 0.0) / (Complex64::new(1.0, 0.0) - Complex64::from_polar(a, -TAU * f / FS))
}

#[test]
fn the_exponential_window_moves_the_pole_left_by_exactly_one_over_tau() {
    // A hit (one sample, a flat spectrum) at 0.1 s on a first-order system with a 2 s time constant, 10 s records: the
    // response is not over by the end. Windowed by e^(−t/τ) on both channels, the records
    // are those of the system with a → a·e^(−Δt/τ), and the estimate its response.
    let n = 1000;
    let dt = 1.0 / FS;
    let a = (-dt / 2.0).exp();
    let force: Vec<f64> = (0..n).map(|t| if t == 10 { 50.0 } else { 0.0 }).collect();
    let mut response = vec![0.0; n];
    for t in 0..n {
        response[t] = a * if t > 0 { response[t - 1] } else { 0.0 } + 0.3 * force[t];
    }
    let options = FrfOptions {
        impact: Some(ImpactWindows::default()),
        ..FrfOptions::default()
    };
    let record = Record {
        input: &force,
        output: &response,
    };
    let frf = frf_estimate(&[record, record], FS, &options).expect("valid");
    let tau = frf.exponential_decay.expect("windowed");
    assert_eq!((tau, frf.averages), (2.5, 2)); // a quarter of the record; two hits
    // L·Σw²/(Σw)² of e^(−t/τ) over L samples, r = e^(−Δt/τ): L(1 − r)²(1 − r^2L)/((1 − r²)(1 − r^L)²)
    // ≈ T/(2τ) = 2 for T ≫ τ.
    let r = (-dt / tau).exp();
    let l = n as f64;
    let expected = l * (1.0 - r).powi(2) * (1.0 - r.powf(2.0 * l))
        / ((1.0 - r * r) * (1.0 - r.powf(l)).powi(2));
    assert!((frf.noise_bandwidth - expected).abs() < 1e-9 * expected);
    assert!(
        (frf.noise_bandwidth - 2.0).abs() < 0.1,
        "{}",
        frf.noise_bandwidth
    );
    let shifted = a * (-dt / tau).exp();
    for (k, &f) in frf.frequency.iter().enumerate() {
        let exact = first_order(shifted, 0.3, f);
        // What is left is the windowed response beyond the record, which wraps around
        // onto it: a free decay from e^(−9.9/2 − 9.9/2.5) ≈ 1.4e-4 of the start, the
        // same share of the response at every line (the hit's spectrum is flat).
        assert!(
            (frf.h[k] / exact - 1.0).norm() < 2e-4,
            "f = {f}: {}",
            frf.h[k] / exact
        );
    }
    // The first-order correction of the module docs: ζ_added = 1/(ωn·τ).
    assert!((frf.added_damping_ratio(1.0) - 1.0 / (TAU * 2.5)).abs() < 1e-15);
}

#[test]
fn a_receptance_table_converts_to_mobility_and_accelerance_and_back() {
    let f = [0.0, 0.5, 1.0, 2.0];
    let h = FrequencyResponseEstimate::from_magnitude_phase(
        &f,
        &[1.0, 2.0, 3.0, 4.0],
        &[0.0, -30.0, -90.0, -170.0],
    )
    .expect("valid")
    .with_variance(vec![1e-4; 4])
    .expect("valid");
    let mobility = h.to_kind(FrfKind::Mobility);
    let accelerance = mobility.to_kind(FrfKind::Accelerance);
    for (k, &fk) in f.iter().enumerate().skip(1) {
        let jw = Complex64::new(0.0, TAU * fk);
        assert!((mobility.h[k] - jw * h.h[k]).norm() < 1e-12);
        assert!((accelerance.h[k] - jw * jw * h.h[k]).norm() < 1e-12);
        let v = accelerance.variance.as_ref().expect("kept")[k];
        assert!((v - 1e-4 * (TAU * fk).powi(4)).abs() < 1e-15 * v.max(1.0));
    }
    let back = accelerance.to_kind(FrfKind::Receptance);
    assert_eq!(back.kind, FrfKind::Receptance);
    assert_eq!(
        (back.h[0], back.coherence[0]),
        (Complex64::new(0.0, 0.0), 0.0)
    );
    assert_eq!(back.variance.as_ref().expect("kept")[0], f64::INFINITY);
    for k in 1..4 {
        assert!((back.h[k] - h.h[k]).norm() < 1e-12 * h.h[k].norm());
    }
}

#[test]
fn bad_records_tables_and_options_are_refused_by_name() {
    let x = [1.0, -1.0, 2.0, 0.5];
    let impact = FrfOptions {
        impact: Some(ImpactWindows::default()),
        welch: WelchOptions {
            segment_length: Some(2),
            ..WelchOptions::default()
        },
        ..FrfOptions::default()
    };
    let record = Record {
        input: &x,
        output: &x,
    };
    let message =
        |r: Result<FrequencyResponseEstimate, SignalError>| r.map_err(|e| e.to_string()).err();
    assert_eq!(
        message(frf_estimate(&[record], 1.0, &impact)),
        Some("invalid parameter `welch.segment_length` = 2: expected none with impact windows (each hit is one record)".into())
    );
    let short = Record {
        input: &x[..3],
        output: &x[..3],
    };
    let ok = FrfOptions::default();
    assert_eq!(
        message(frf_estimate(&[record, short], 1.0, &ok)),
        Some("record 1 has 3 samples, the first record has 4".into())
    );
    assert!(matches!(
        frf_estimate(&[], 1.0, &ok),
        Err(SignalError::EmptyData { name: "records" })
    ));
    let bad_tau = FrfOptions {
        impact: Some(ImpactWindows {
            decay_time: Some(0.0),
            ..ImpactWindows::default()
        }),
        ..FrfOptions::default()
    };
    assert_eq!(
        message(frf_estimate(&[record], 1.0, &bad_tau)),
        Some("invalid parameter `impact.decay_time` = 0: expected a finite value > 0".into())
    );
    assert_eq!(
        message(FrequencyResponseEstimate::from_real_imaginary(&[1.0, 3.0, 2.0], &[1.0; 3], &[0.0; 3])),
        Some("frequencies not strictly increasing: frequency[2] = 2 Hz does not exceed the previous 3 Hz".into())
    );
    assert_eq!(
        message(FrequencyResponseEstimate::from_magnitude_phase(
            &[1.0],
            &[-1.0],
            &[0.0]
        )),
        Some("invalid parameter `magnitude[0]` = -1: expected a magnitude >= 0".into())
    );
    assert!(matches!(
        FrequencyResponseEstimate::from_real_imaginary(&[-1.0], &[1.0], &[0.0]),
        Err(SignalError::InvalidParameter { .. })
    ));
    assert!(matches!(
        FrequencyResponseEstimate::from_real_imaginary(&[1.0, 2.0], &[1.0], &[0.0]),
        Err(SignalError::LengthMismatch { .. })
    ));
}

#[test]
fn options_read_from_toml_with_defaults() {
    let options: FrfOptions = toml::from_str(
        r#"
        estimator = "H2"
        kind = "velocity"
        [impact]
        decay_time = 0.8
        "#,
    )
    .expect("valid");
    assert_eq!(options.estimator, Estimator::H2);
    assert_eq!(options.kind, FrfKind::Mobility);
    assert_eq!(
        options.impact,
        Some(ImpactWindows {
            force_width: None,
            decay_time: Some(0.8)
        })
    );
    assert_eq!(options.welch, WelchOptions::default());
    assert!(toml::from_str::<FrfOptions>("estimator = \"H3\"").is_err());
}

/// Four consecutive records of `len` samples of a multisine with a 128-sample period
/// (every line of the period excited with Schroeder phases) through the FIR system, in
/// steady state: at `len` = 256, two periods a record.
fn periodic_records(len: usize) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let period = 128;
    let lines = 1..64usize;
    let u: Vec<f64> = (0..5 * 256)
        .map(|t| {
            lines
                .clone()
                .map(|k| {
                    let phase = -std::f64::consts::PI * (k * (k - 1)) as f64 / 63.0;
                    (TAU * (k * t) as f64 / period as f64 + phase).cos()
                })
                .sum()
        })
        .collect();
    let y = fir(&u);
    // The first 256 samples (they hold y's start from rest) are left out.
    let cut = |x: &[f64]| {
        (0..4)
            .map(|r| x[256 + r * len..256 + (r + 1) * len].to_vec())
            .collect()
    };
    (cut(&u), cut(&y))
}

/// Record pairs of inputs `u` and outputs `y`.
fn pairs<'a>(u: &'a [Vec<f64>], y: &'a [Vec<f64>]) -> Vec<Record<'a>> {
    u.iter()
        .zip(y)
        .map(|(u, y)| Record {
            input: u,
            output: y,
        })
        .collect()
}

/// H1 of `records`, whole, with `window`.
fn whole_records(records: &[Record<'_>], window: msd_signal::Window) -> FrequencyResponseEstimate {
    let welch = WelchOptions {
        window,
        ..WelchOptions::default()
    };
    let options = FrfOptions {
        welch,
        ..FrfOptions::default()
    };
    frf_estimate(records, FS, &options).expect("valid")
}

#[test]
fn a_repeating_input_gets_a_rectangular_window_and_its_lines_stay_apart() {
    let (u, y) = periodic_records(256);
    let records = pairs(&u, &y);
    let estimate = |window| whole_records(&records, window);
    let auto = estimate(msd_signal::Window::Auto);
    assert_eq!(
        msd_signal::resolve_window(msd_signal::Window::Auto, &records, 256),
        msd_signal::Window::Rectangular
    );
    assert_eq!(auto.noise_bandwidth, 1.0);
    // The period's own lines (even bins) exact; the lines between them carry no force
    // and are left out (0, with coherence 0).
    for k in 1..128 {
        let (h, truth) = (auto.h[k], fir_response(auto.frequency[k]));
        if k % 2 == 0 {
            assert!(
                (h - truth).norm() < 1e-12 * truth.norm(),
                "line {k}: {h} vs {truth}"
            );
            assert!(auto.coherence[k] > 1.0 - 1e-12);
        } else {
            assert_eq!(
                (h, auto.coherence[k]),
                (Complex64::new(0.0, 0.0), 0.0),
                "line {k}"
            );
        }
    }
    // A Hann window smears each line into the lines between: those then hold a mixture
    // of their neighbours' responses with full coherence, nothing a fit could tell from H.
    let hann = estimate(msd_signal::Window::Hann);
    let worst = (1..128)
        .filter(|k| k % 2 == 1)
        .map(|k| {
            (hann.h[k] - fir_response(hann.frequency[k])).norm()
                / fir_response(hann.frequency[k]).norm()
        })
        .fold(0.0, f64::max);
    assert!(
        worst > 0.1,
        "the Hann window's in-between lines are {worst} off"
    );
}

#[test]
fn an_input_that_does_not_repeat_keeps_the_hann_window() {
    let n = 1024;
    let u: Vec<Vec<f64>> = (0..4)
        .map(|r| gaussian_noise(3, &format!("frf.random.{r}"), 1.0, n).expect("valid"))
        .collect();
    let y: Vec<Vec<f64>> = u.iter().map(|u| fir(u)).collect();
    let records = pairs(&u, &y);
    let with = |window| whole_records(&records, window);
    assert_eq!(
        with(msd_signal::Window::Auto),
        with(msd_signal::Window::Hann)
    );
    // A periodic input whose period the record does not hold whole does not repeat
    // from record to record either.
    let (u, y) = periodic_records(200);
    let shifted = pairs(&u, &y);
    assert_eq!(
        msd_signal::resolve_window(msd_signal::Window::Auto, &shifted, 200),
        msd_signal::Window::Hann
    );
}

/// A force that is zero, or constant, everywhere has no power at any line: refused, not
/// a response of 1e16 with coherence 1 (the paired transform left its spectrum at
/// rounding, 1e-32 of the response's).
#[test]
fn a_force_without_power_is_refused() {
    let y = gaussian_noise(5, "frf.zero.y", 1.0, 512).expect("valid");
    for level in [0.0, 3.0] {
        let force = vec![level; 512];
        let record = Record {
            input: &force,
            output: &y,
        };
        for options in [
            FrfOptions::default(),
            FrfOptions {
                impact: Some(ImpactWindows::default()),
                ..FrfOptions::default()
            },
        ] {
            assert!(matches!(
                frf_estimate(&[record, record], FS, &options),
                Err(SignalError::ZeroInputPower { name: "input" })
            ));
        }
    }
}
