//! Welch PSD of white noise, H1 of an exactly simulated 2nd-order system, errors.

use std::f64::consts::TAU;

use msd_signal::{
    Complex64, DftPair, SignalError, WelchOptions, coherence, cross_spectrum, gaussian_noise,
    h1_estimate, welch_psd,
};

#[test]
fn welch_psd_of_white_noise_is_two_sigma_squared_over_fs() {
    let (sigma, fs, n, l) = (0.8, 250.0, 1 << 16, 256);
    let x = gaussian_noise(5, "welch", sigma, n).expect("valid");
    let opts = WelchOptions {
        segment_length: Some(l),
        ..Default::default()
    };
    let psd = welch_psd(&x, fs, &opts).expect("valid");
    let k = psd.averages;
    assert_eq!(k, (n - l) / (l / 2) + 1);
    assert_eq!(psd.frequency.len(), l / 2 + 1);
    assert!((psd.frequency[1] - fs / l as f64).abs() < 1e-12);
    let expected = 2.0 * sigma * sigma / fs;
    // Each interior bin is a mean of K periodograms, each χ²₂/2-distributed about the PSD.
    // With a Hann window at 50 % overlap neighbouring segments correlate (ρ² ≈ 0.028),
    // so Var(P̂)/P² ≈ (1 + 2ρ²)/K (Welch 1967).
    let rel_sd = ((1.0 + 2.0 * 0.028) / k as f64).sqrt();
    let interior = &psd.values[1..l / 2];
    for (i, p) in interior.iter().enumerate() {
        assert!(
            (p / expected - 1.0).abs() < 5.0 * rel_sd,
            "bin {}: ratio {}",
            i + 1,
            p / expected
        );
    }
    // Averaged over the bins (nearly independent for Hann: adjacent-bin correlation ≲ ½),
    // the standard error shrinks by √(bins/2) at least.
    let mean = interior.iter().sum::<f64>() / interior.len() as f64;
    assert!((mean / expected - 1.0).abs() < 5.0 * rel_sd / ((interior.len() / 2) as f64).sqrt());
}

#[test]
fn psd_satisfies_parseval_with_one_segment() {
    // Rectangular window, one segment: Σ P·Δf = mean square exactly.
    let x = gaussian_noise(8, "parseval", 1.3, 1000).expect("valid");
    let opts = WelchOptions {
        window: msd_signal::Window::Rectangular,
        detrend: msd_signal::Detrend::None,
        ..Default::default()
    };
    let fs = 50.0;
    let psd = welch_psd(&x, fs, &opts).expect("valid");
    let power: f64 = psd.values.iter().sum::<f64>() * fs / 1000.0;
    let ms = x.iter().map(|v| v * v).sum::<f64>() / 1000.0;
    assert!((power - ms).abs() < 1e-12 * ms);
    assert_eq!(psd.averages, 1);
}

/// Zero-order-hold discretisation of m·x'' + c·x' + k·x = u (output x), exact.
struct Zoh {
    ad: [[f64; 2]; 2],
    bd: [f64; 2],
}

impl Zoh {
    fn new(m: f64, c: f64, k: f64, h: f64) -> Self {
        let wn = (k / m).sqrt();
        let s = c / (2.0 * m);
        let wd = (wn * wn - s * s).sqrt();
        let e = (-s * h).exp();
        let (sn, cs) = ((wd * h).sin(), (wd * h).cos());
        let ad = [
            [e * (cs + s / wd * sn), e * sn / wd],
            [-e * wn * wn / wd * sn, e * (cs - s / wd * sn)],
        ];
        // Bd = A⁻¹(Ad − I)B with B = (0, 1/m), A⁻¹ = [[−2s, −1], [wn², 0]]/wn².
        let (g0, g1) = (ad[0][1] / m, (ad[1][1] - 1.0) / m);
        let bd = [(-2.0 * s * g0 - g1) / (wn * wn), g0];
        Zoh { ad, bd }
    }

    fn simulate(&self, u: &[f64]) -> Vec<f64> {
        let mut x = [0.0, 0.0];
        u.iter()
            .map(|&uk| {
                let y = x[0];
                x = [
                    self.ad[0][0] * x[0] + self.ad[0][1] * x[1] + self.bd[0] * uk,
                    self.ad[1][0] * x[0] + self.ad[1][1] * x[1] + self.bd[1] * uk,
                ];
                y
            })
            .collect()
    }

    /// H(z) = C (zI − Ad)⁻¹ Bd at z = e^{iωh}.
    fn frf(&self, f: f64, h: f64) -> Complex64 {
        let z = Complex64::from_polar(1.0, TAU * f * h);
        let a = &self.ad;
        let det = (z - a[0][0]) * (z - a[1][1]) - a[0][1] * a[1][0];
        ((z - a[1][1]) * self.bd[0] + a[0][1] * self.bd[1]) / det
    }
}

#[test]
fn h1_matches_the_analytic_frf_of_an_exactly_simulated_second_order_system() {
    let (fs, n, l) = (100.0, 1 << 16, 1024);
    let h = 1.0 / fs;
    // fn = 5 Hz, ζ = 0.1: a 1 Hz half-power band, ten bins wide at fs/L ≈ 0.1 Hz.
    let (m, wn, zeta) = (1.0, TAU * 5.0, 0.1);
    let sys = Zoh::new(m, 2.0 * zeta * wn * m, wn * wn * m, h);
    let u = gaussian_noise(21, "h1.input", 1.0, n).expect("valid");
    let clean = sys.simulate(&u);
    let e = gaussian_noise(21, "h1.output_noise", 1e-5, n).expect("valid");
    let y: Vec<f64> = clean.iter().zip(&e).map(|(a, b)| a + b).collect();
    let opts = WelchOptions {
        segment_length: Some(l),
        ..Default::default()
    };
    let est = h1_estimate(&u, &y, fs, &opts).expect("valid");
    let nd = est.averages as f64 / (1.0 + 2.0 * 0.028); // equivalent independent averages
    let mut checked = 0;
    for (i, &f) in est.frequency.iter().enumerate() {
        let g2 = est.coherence[i];
        if !(f > 0.5 && f < 45.0 && g2 > 0.9) {
            continue;
        }
        checked += 1;
        let exact = sys.frf(f, h);
        let ratio = est.h[i] / exact;
        // Random error of |H1| and of its phase (radians): √(1 − γ²)/(|γ|·√(2·n_d))
        // (Bendat & Piersol); leakage bias of a Hann window over a band B_r = 1 Hz with
        // B_e = 1.5·fs/L: ≈ (B_e/B_r)²/3 ≈ 0.7 %, allowed as 2 %.
        let random = ((1.0 - g2) / (g2 * 2.0 * nd)).sqrt();
        let tol = 5.0 * random + 0.02;
        assert!(
            (ratio.norm() - 1.0).abs() < tol,
            "f = {f}: |H1/H| = {}, tol {tol}",
            ratio.norm()
        );
        assert!(
            ratio.arg().abs() < tol,
            "f = {f}: phase error {}",
            ratio.arg()
        );
    }
    assert!(checked > 200, "only {checked} bins with high coherence");
    // Near the resonance the output noise is negligible; what is left of 1 − γ² is the
    // leakage of the system's memory across segment edges, of order τ/T with the decay
    // time τ = 1/(ζ·ωn) ≈ 0.32 s and the segment T = 10.24 s: ≈ 3 %.
    let peak = est
        .frequency
        .iter()
        .position(|&f| f >= 5.0)
        .expect("5 Hz in range");
    let tau_over_t = 1.0 / (zeta * wn) / (l as f64 / fs);
    assert!(
        est.coherence[peak] > 1.0 - tau_over_t,
        "γ² = {}",
        est.coherence[peak]
    );
}

#[test]
fn one_segment_coherence_is_identically_one_and_cross_spectrum_is_consistent() {
    let u = gaussian_noise(4, "u", 1.0, 500).expect("valid");
    let y = gaussian_noise(4, "unrelated", 1.0, 500).expect("valid");
    let opts = WelchOptions::default();
    let g = coherence(&u, &y, 10.0, &opts).expect("valid");
    assert!(g.values[1..].iter().all(|v| (v - 1.0).abs() < 1e-9));
    let sxy = cross_spectrum(&u, &u, 10.0, &opts).expect("valid");
    let sxx = welch_psd(&u, 10.0, &opts).expect("valid");
    for (a, b) in sxy.values.iter().zip(&sxx.values) {
        assert!(
            (a.re - b).abs() <= 1e-12 * b.abs().max(1e-300)
                && a.im.abs() <= 1e-12 * b.abs().max(1e-300)
        );
    }
    // With averaging, unrelated records have low coherence: E[γ²] = 1/n_d.
    let u = gaussian_noise(4, "u", 1.0, 1 << 14).expect("valid");
    let y = gaussian_noise(4, "unrelated", 1.0, 1 << 14).expect("valid");
    let g = coherence(
        &u,
        &y,
        10.0,
        &WelchOptions {
            segment_length: Some(128),
            ..Default::default()
        },
    )
    .expect("valid");
    let mean = g.values[1..64].iter().sum::<f64>() / 63.0;
    assert!(
        mean < 5.0 / g.averages as f64,
        "mean coherence {mean} with {} averages",
        g.averages
    );
}

#[test]
fn spectral_errors_are_specific() {
    let x = vec![1.0, 2.0, 0.5, 3.0];
    let ok = WelchOptions::default();
    assert!(matches!(
        welch_psd(&[], 1.0, &ok),
        Err(SignalError::EmptyData { .. })
    ));
    assert!(
        matches!(welch_psd(&x, 0.0, &ok), Err(SignalError::InvalidParameter { ref parameter, .. }) if parameter == "fs")
    );
    assert!(matches!(
        welch_psd(&x, f64::NAN, &ok),
        Err(SignalError::InvalidParameter { .. })
    ));
    let bad_overlap = WelchOptions {
        overlap: 1.0,
        ..Default::default()
    };
    assert!(
        matches!(welch_psd(&x, 1.0, &bad_overlap), Err(SignalError::InvalidParameter { ref parameter, .. }) if parameter == "overlap")
    );
    let long = WelchOptions {
        segment_length: Some(8),
        ..Default::default()
    };
    assert!(matches!(
        welch_psd(&x, 1.0, &long),
        Err(SignalError::WindowTooLong { window: 8, len: 4 })
    ));
    let tiny = WelchOptions {
        segment_length: Some(1),
        ..Default::default()
    };
    assert!(matches!(
        tiny.validate(),
        Err(SignalError::InvalidParameter { .. })
    ));
    assert!(matches!(
        h1_estimate(&x, &x[..3], 1.0, &ok),
        Err(SignalError::LengthMismatch { .. })
    ));
    assert!(matches!(
        h1_estimate(&[2.0; 4], &x, 1.0, &ok),
        Err(SignalError::ZeroInputPower { .. })
    ));
    assert!(matches!(
        h1_estimate(&x, &[0.0, f64::NAN, 0.0, 0.0], 1.0, &ok),
        Err(SignalError::NonFinite {
            name: "y",
            index: 1,
            ..
        })
    ));
}

/// The pair's DFTs are the direct sums X_k = Σ_t (x_t − x̄)·e^{−2πikt/N}, on an odd and an
/// even length (the mirrored bin N − k of the shared FFT, and k = 0 and N/2).
#[test]
fn dft_pair_equals_the_direct_sums_of_the_mean_removed_records() {
    for n in [7, 12] {
        let x = gaussian_noise(4, "pair.x", 1.0, n).expect("valid");
        let y: Vec<f64> = gaussian_noise(4, "pair.y", 2.0, n)
            .expect("valid")
            .iter()
            .map(|v| v + 3.0)
            .collect();
        let pair = DftPair::new(&x, &y).expect("valid");
        let dft = |r: &[f64], k: usize| {
            let mean = r.iter().sum::<f64>() / n as f64;
            r.iter()
                .enumerate()
                .fold(Complex64::new(0.0, 0.0), |s, (t, v)| {
                    s + Complex64::from_polar(v - mean, -TAU * (k * t) as f64 / n as f64)
                })
        };
        for k in 0..n {
            assert!(
                (pair.input[k] - dft(&x, k)).norm() < 1e-13,
                "n {n}, bin {k}"
            );
            assert!(
                (pair.output[k] - dft(&y, k)).norm() < 1e-13,
                "n {n}, bin {k}"
            );
        }
    }
}

/// The H1 from the pair's DFTs (the Hann window applied in frequency) is `h1_estimate`
/// with one Hann segment up to FFT rounding, line for line up to the asked frequency,
/// on an exactly simulated lightly damped plant (ζ = 0.05 at 1.1 Hz, 7500 samples at
/// 500 Hz, as the paper's). The bound is the normwise FFT error c·ε·log₂N·√N·‖x‖₂
/// (c = 10) of both transforms, carried through H = Y/U.
#[test]
fn hann_h1_from_the_dfts_equals_the_one_segment_h1_estimate() {
    let (fs, n) = (500.0, 7500);
    let (m, wn, zeta) = (2.5, TAU * 1.1, 0.05);
    let sys = Zoh::new(m, 2.0 * zeta * wn * m, wn * wn * m, 1.0 / fs);
    let u = gaussian_noise(7, "hann.input", 3.0, n).expect("valid");
    let e = gaussian_noise(7, "hann.noise", 1e-4, n).expect("valid");
    let y: Vec<f64> = sys
        .simulate(&u)
        .iter()
        .zip(&e)
        .map(|(a, b)| a + b)
        .collect();
    let direct = h1_estimate(&u, &y, fs, &WelchOptions::default()).expect("valid");
    let pair = DftPair::new(&u, &y).expect("valid");
    let f_max = 10.0;
    let ours = pair.hann_h1(fs, f_max).expect("valid");
    assert_eq!(ours.frequency.len(), 151); // 0 … 10 Hz every 1/15 Hz
    assert_eq!(ours.frequency[..], direct.frequency[..151]);
    assert_eq!(ours.averages, 1);
    let norm = |x: &[f64]| x.iter().map(|v| v * v).sum::<f64>().sqrt();
    let fft_error =
        |x: &[f64]| 10.0 * f64::EPSILON * (n as f64).log2() * (n as f64).sqrt() * norm(x);
    for k in 1..151 {
        // |U_w[k]| from the one-segment Hann H1's own input: the windowed DFT.
        let below = pair.input[k - 1];
        let u_w = (pair.input[k] * 0.5 - (below + pair.input[k + 1]) * 0.25).norm();
        let h = direct.h[k];
        let allowed = 2.0 * (fft_error(&y) + h.norm() * fft_error(&u)) / u_w;
        assert!(
            (ours.h[k] - h).norm() <= allowed,
            "line {k}: {} vs {h}, allowed {allowed:e}",
            ours.h[k]
        );
        // One segment: both coherences are 1 up to rounding.
        assert!(
            (ours.coherence[k] - direct.coherence[k]).abs() < 1e-12,
            "line {k}"
        );
    }
    // The whole one-sided range, and the Nyquist line of an even length.
    let all = pair.hann_h1(fs, f64::INFINITY).expect("valid");
    assert_eq!(all.frequency.len(), n / 2 + 1);
    assert_eq!(all.frequency[n / 2], fs / 2.0);
}

#[test]
fn dft_pair_errors_are_specific() {
    let x = [1.0, 2.0, 0.5, 3.0];
    assert_eq!(
        DftPair::new(&x, &x[..3]),
        Err(SignalError::LengthMismatch {
            left: "input",
            left_len: 4,
            right: "output",
            right_len: 3
        })
    );
    assert_eq!(
        DftPair::new(&[], &[]),
        Err(SignalError::EmptyData { name: "input" })
    );
    assert!(matches!(
        DftPair::new(&x, &[0.0, f64::INFINITY, 0.0, 0.0]),
        Err(SignalError::NonFinite {
            name: "output",
            index: 1,
            ..
        })
    ));
    let pair = DftPair::new(&x, &x).expect("valid");
    assert!(matches!(
        pair.hann_h1(0.0, 1.0),
        Err(SignalError::InvalidParameter { ref parameter, value, .. }) if parameter == "fs" && value == 0.0
    ));
    assert_eq!(
        pair.hann_h1(1.0, f64::NAN).map_err(|e| e.to_string()),
        Err("invalid parameter `max_frequency` = NaN: expected a frequency >= 0 Hz".into())
    );
    assert!(matches!(
        pair.hann_h1(1.0, -0.5),
        Err(SignalError::InvalidParameter { ref parameter, .. }) if parameter == "max_frequency"
    ));
    let flat = DftPair::new(&[2.0; 4], &x).expect("valid");
    assert_eq!(
        flat.hann_h1(1.0, 1.0),
        Err(SignalError::ZeroInputPower { name: "input" })
    );
    // Two samples: the Hann kernel wraps around both ways.
    let two = DftPair::new(&[1.0, -1.0], &[2.0, -2.0]).expect("valid");
    let h1 = two.hann_h1(1.0, 1.0).expect("valid");
    assert_eq!(h1.frequency, [0.0, 0.5]);
    assert!((h1.h[1] - Complex64::new(2.0, 0.0)).norm() < 1e-15);
}
