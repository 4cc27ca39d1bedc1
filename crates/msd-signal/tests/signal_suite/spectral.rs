//! Welch PSD of white noise, H1 of an exactly simulated 2nd-order system, errors.

use std::f64::consts::TAU;

use msd_signal::{
    Complex64, SignalError, WelchOptions, coherence, cross_spectrum, gaussian_noise, h1_estimate,
    welch_psd,
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
