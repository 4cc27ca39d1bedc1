//! A set's residuals against its members' own noise: the simulated beam of `beam.rs`
//! measured as accelerance with flat noise on the response, each member carrying the
//! coherence that noise gives over K averages. Where the model is complete the check's
//! SSE/E\[SSE\] averages 1 and it fails about 1 % of the time, with independent lines
//! and with lines whose errors are correlated (a moving average, as a window makes
//! them); a set fitted with a mode too few fails it. A roving-accelerometer set whose
//! members read one force record shares its force noise: the poles' intervals and the
//! check take that in, and members measured one after another are told apart from it.

use msd_modal::{
    Dof, FrfWeighting, ModalOptions, ModalParameters, NoiseCheck, SetMember, fit_mode_set,
    fit_modes,
};
use msd_signal::{
    Complex64, Estimator, FrequencyResponseEstimate, FrfKind, LineCorrelation, gaussian_noise,
};

const POINTS: usize = 6;
const RESPONSE: usize = 2;
const MODES: [(f64, f64); 3] = [(20.0, 0.01), (80.0, 0.005), (180.0, 0.003)];
const AVERAGES: usize = 20;
/// The response's noise, flat in accelerance: E|e|² = σ² at every line.
const SIGMA: f64 = 0.02;

/// sin(rπx_i/L) at the points x_i = i·L/(POINTS + 1).
fn shape(r: usize) -> Vec<f64> {
    (1..=POINTS)
        .map(|i| ((r + 1) as f64 * std::f64::consts::PI * i as f64 / (POINTS + 1) as f64).sin())
        .collect()
}

/// How a simulated set is measured.
#[derive(Debug, Clone, Copy, Default)]
struct Test {
    /// θ of the lines' errors, a moving average u_k + θ·u_(k−1) (0: independent).
    theta: f64,
    /// v: the force's noise on each line, relative to H (0: none).
    force_noise: f64,
    /// Whether the response roves (the force at point `RESPONSE`), else the hammer.
    roving_response: bool,
    /// Whether every member has the same draw of the force's noise (one force record).
    shared: bool,
    /// Whether v is given as the estimate's `input_noise_variance` (measured, as
    /// msd-signal measures it on an impact test), else left to the coherence.
    measured: bool,
}

/// The beam's set from `seed`, each member's coherence the one its noise gives over K
/// averages. With v > 0 each member is an H1 estimate under force noise: its lines low
/// by the factor 1 + (K − 1)·v and scattered by E|ΔĤ|² = v·|H|².
fn set(seed: u64, test: Test) -> Vec<SetMember> {
    let f: Vec<f64> = (5..=300).map(|i| i as f64).collect();
    let n = f.len();
    let (theta, v) = (test.theta, test.force_noise);
    (1..=POINTS)
        .map(|point| {
            let (response, reference) = match test.roving_response {
                true => (point, RESPONSE),
                false => (RESPONSE, point),
            };
            let terms: Vec<ModalParameters> = (MODES.iter().enumerate())
                .map(|(r, &(fn_hz, zeta))| ModalParameters {
                    natural_frequency_hz: fn_hz,
                    damping_ratio: zeta,
                    modal_constant: 2.0 * shape(r)[response - 1] * shape(r)[reference - 1],
                    modal_constant_imaginary: 0.0,
                })
                .collect();
            let stream = seed * 100 + point as u64;
            let force_stream = if test.shared { seed * 100 } else { stream };
            let part = |s: u64, name: &str| gaussian_noise(s, name, 1.0, n + 1).expect("noise");
            let (re, im) = (part(stream, "re"), part(stream, "im"));
            let (fre, fim) = (
                part(force_stream, "force.re"),
                part(force_stream, "force.im"),
            );
            let k = AVERAGES as f64;
            let scale = SIGMA / (2.0 * (1.0 + theta * theta)).sqrt();
            let mut h = Vec::with_capacity(n);
            let mut coherence = Vec::with_capacity(n);
            for (j, &fk) in f.iter().enumerate() {
                let w = std::f64::consts::TAU * fk;
                let exact: Complex64 =
                    -w * w * terms.iter().map(|m| m.receptance(fk)).sum::<Complex64>();
                let u = |i: usize| Complex64::new(re[i], im[i]);
                let relative = (v / 2.0).sqrt() * Complex64::new(fre[j], fim[j]);
                let low = exact / (1.0 + (k - 1.0) * v);
                let measured = low + exact * relative + scale * (u(j + 1) + theta * u(j));
                h.push(measured);
                // The coherence whose (1 − γ²)/(K·γ²)·|Ĥ|² is (K − 1)/K·σ² at every line,
                // as a coherence estimated from the same K averages gives it on average
                // (the fit scales it back by K/(K − 1)): the check is tested given the
                // noise's level.
                let power = measured.norm_sqr();
                let total = SIGMA * SIGMA + v * exact.norm_sqr();
                coherence.push(power / (power + (k - 1.0) * total));
            }
            let mut frf = FrequencyResponseEstimate::new(f.clone(), h).expect("an FRF");
            frf.kind = FrfKind::Accelerance;
            frf.coherence = coherence;
            frf.averages = AVERAGES;
            if v > 0.0 {
                frf.estimator = Some(Estimator::H1);
            }
            if test.measured {
                frf.input_noise_variance = Some(vec![v; n]);
            }
            if theta != 0.0 {
                let rho = theta / (1.0 + theta * theta);
                frf.line_correlation = LineCorrelation {
                    response: vec![Complex64::new(1.0, 0.0), Complex64::new(rho, 0.0)],
                    force: Vec::new(),
                };
            }
            let dof = |node: usize| Dof {
                node: node as u32,
                direction: 3,
            };
            SetMember {
                frf,
                response: dof(response),
                reference: dof(reference),
            }
        })
        .collect()
}

/// The roving hammer's set from `seed` (see [`set`]); with v > 0, measured.
fn beam(seed: u64, theta: f64, force_noise: f64) -> Vec<SetMember> {
    let test = Test {
        theta,
        force_noise,
        measured: force_noise > 0.0,
        ..Test::default()
    };
    set(seed, test)
}

/// The set's check, and the z = (estimate − truth)/SE of its fn and ζ.
fn check(members: &[SetMember], options: &ModalOptions) -> (NoiseCheck, Vec<f64>) {
    let fit = fit_mode_set(members, options).expect("a fit");
    assert_eq!(fit.modes.len(), MODES.len(), "{fit}");
    let z = (fit.modes.iter().zip(&MODES))
        .flat_map(|(m, &(fn_hz, zeta))| {
            let (f, d) = (&m.natural_frequency_hz, &m.damping_ratio);
            [
                (f.value - fn_hz) / f.standard_error,
                (d.value - zeta) / d.standard_error,
            ]
        })
        .collect();
    let check = fit.noise_check;
    (check.expect("every member's coherence from 20 averages"), z)
}

/// Over 150 seeds: the intervals of fn and ζ hold the truth 95 % of the time (rms z 1), the mean of
/// SSE/E\[SSE\] is within 3 of its standard errors of 1, its spread Satterthwaite's, and
/// at most 6 failures at the 1 % level (1.5 expected; P(≥ 6) ≈ 0.4 %).
fn calibrated(theta: f64) {
    let options = ModalOptions::default();
    let (checks, z): (Vec<NoiseCheck>, Vec<Vec<f64>>) = (0..150)
        .map(|seed| check(&beam(seed, theta, 0.0), &options))
        .unzip();
    // 900 intervals of fn and ζ (t ≈ 1.96 at thousands of dof): binomial standard
    // deviation 0.73 %, so 95 ± 3 % is four; their rms z within 3/√(2·900) of 1.
    let z: Vec<f64> = z.concat();
    let coverage = z.iter().filter(|z| z.abs() <= 1.96).count() as f64 / z.len() as f64;
    let rms = (z.iter().map(|z| z * z).sum::<f64>() / z.len() as f64).sqrt();
    eprintln!("θ = {theta}: coverage of fn and ζ {coverage:.3}, rms z {rms:.3}");
    assert!((coverage - 0.95).abs() <= 0.03, "coverage {coverage}");
    assert!(
        (rms - 1.0).abs() <= 3.0 / (2.0 * z.len() as f64).sqrt(),
        "rms z {rms}"
    );
    let ratios: Vec<f64> = checks.iter().map(|c| c.variance_ratio).collect();
    let n = ratios.len() as f64;
    let mean = ratios.iter().sum::<f64>() / n;
    let sd = (ratios.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    let failed = checks.iter().filter(|c| !c.passed).count();
    let h = checks[0].degrees_of_freedom;
    eprintln!(
        "θ = {theta}: SSE/E[SSE] {mean:.4} ± {:.4}, spread {sd:.4} (√(2/h) {:.4}, h {h:.1}), {failed} of 150 failed",
        sd / n.sqrt(),
        (2.0 / h).sqrt()
    );
    assert!(
        (mean - 1.0).abs() < 3.0 * sd / n.sqrt(),
        "mean {mean}, sd {sd}"
    );
    // The spread is Satterthwaite's √(2/h), within 3 of its standard errors (1/√(2(n − 1))).
    let spread = sd / (2.0 / h).sqrt();
    assert!(
        (spread - 1.0).abs() < 3.0 / (2.0 * (n - 1.0)).sqrt(),
        "spread {spread}"
    );
    assert!(failed <= 6, "{failed} of 150 failed");
}

#[test]
fn a_complete_set_leaves_only_its_members_noise() {
    calibrated(0.0);
}

#[test]
fn with_correlated_lines_too() {
    calibrated(0.5);
}

#[test]
fn a_set_fitted_with_a_mode_too_few_fails_the_check() {
    let options = ModalOptions {
        mode_count: Some(2),
        ..ModalOptions::default()
    };
    let fit = fit_mode_set(&beam(1, 0.0, 0.0), &options).expect("a fit");
    assert_eq!(fit.modes.len(), 2, "{fit}");
    let check = fit.noise_check.expect("a check");
    assert!(!check.passed && check.variance_ratio > 2.0, "{check}");
    assert!(
        fit.to_string()
            .contains("warning: the model leaves more than the noise"),
        "{fit}"
    );
}

/// Members whose H1 carries measured force noise (v = 2e-3 a line over 20 averages: low
/// by 3.8 %): each is raised by its own (K − 1)·v, so the driving point's modal constants
/// come out unbiased (their mean ratio to the truth within 3 of its standard errors of 1,
/// over 60 sets), and the residual still passes its check.
#[test]
fn measured_force_noise_is_taken_off_each_member() {
    let mut ratios = Vec::new();
    let mut failed = 0;
    for seed in 0..60 {
        let fit = fit_mode_set(&beam(seed, 0.0, 2e-3), &ModalOptions::default()).expect("a fit");
        assert_eq!(fit.modes.len(), MODES.len(), "{fit}");
        let noise = fit.members[RESPONSE - 1].input_noise.expect("measured");
        assert!(noise.measured && noise.corrected && (noise.h1_bias - 19.0 * 2e-3).abs() < 1e-12);
        failed += usize::from(!fit.noise_check.expect("a check").passed);
        for (r, mode) in fit.modes.iter().enumerate() {
            let a = mode.modal_constants[RESPONSE - 1];
            ratios.push(a.re / (2.0 * shape(r)[RESPONSE - 1].powi(2)));
        }
    }
    let n = ratios.len() as f64;
    let mean = ratios.iter().sum::<f64>() / n;
    let sd = (ratios.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    eprintln!(
        "driving point's A over the truth: {mean:.5} ± {:.5}, {failed} of 60 checks failed",
        sd / n.sqrt()
    );
    assert!(
        (mean - 1.0).abs() < 3.0 * sd / n.sqrt(),
        "mean {mean}, sd {sd}"
    );
    assert!(failed <= 4, "{failed} of 60 failed");
}

/// Over 100 roving-accelerometer sets with the force's noise (v = 2e-3: ten times the
/// response's at the resonances) shared or not: the intervals of fn and ζ hold the truth
/// 95 ± 3 % of the time (600 intervals, binomial standard deviation 0.9 %) and their rms
/// z is within 3/√(2·600) of 1; the check fails at most 5 times at its 1 % level
/// (P(≥ 5) ≈ 0.3 %). Returns the estimated common fraction κ̂ of every set and their
/// mean standard error.
fn roving_calibrated(shared: bool, measured: bool) -> (Vec<f64>, f64) {
    let (mut z, mut failed, mut kappa, mut se) = (Vec::new(), 0, Vec::new(), 0.0);
    for seed in 0..100 {
        let test = Test {
            force_noise: 2e-3,
            roving_response: true,
            shared,
            measured,
            ..Test::default()
        };
        let members = set(seed, test);
        let fit = fit_mode_set(&members, &ModalOptions::default()).expect("a fit");
        let found = fit
            .shared_force
            .expect("every member's coherence has a noise model");
        kappa.push(found.fraction);
        se += found.standard_error / 100.0;
        let (check, found_z) = check(&members, &ModalOptions::default());
        failed += usize::from(!check.passed);
        z.extend(found_z);
    }
    let coverage = z.iter().filter(|z| z.abs() <= 1.96).count() as f64 / z.len() as f64;
    let rms = (z.iter().map(|z| z * z).sum::<f64>() / z.len() as f64).sqrt();
    eprintln!(
        "shared {shared}: coverage of fn and ζ {coverage:.3}, rms z {rms:.3}, {failed} of 100 checks failed, κ̂ {:.3} (SE {se:.3}), {:.3}–{:.3}",
        kappa.iter().sum::<f64>() / 100.0,
        kappa.iter().fold(1.0f64, |a, &b| a.min(b)),
        kappa.iter().fold(0.0f64, |a, &b| a.max(b)),
    );
    assert!((coverage - 0.95).abs() <= 0.03, "coverage {coverage}");
    assert!(
        (rms - 1.0).abs() <= 3.0 / (2.0 * z.len() as f64).sqrt(),
        "rms z {rms}"
    );
    assert!(failed <= 5, "{failed} of 100 failed");
    (kappa, se)
}

/// Taken as independent, these sets' intervals held the truth 59 % of the time (rms z
/// 2.4 ≈ √6) and the check failed 17 times in 100: every set must find its common noise.
#[test]
fn members_reading_one_force_record_share_its_noise() {
    let (kappa, _) = roving_calibrated(true, false);
    assert!(kappa.iter().all(|&k| k > 0.5), "{kappa:?}");
}

/// Each member its own force record, its noise measured: κ̂ clamped at 0 averages about
/// 0.4 of its standard error (a half-normal's mean); at most 2.
#[test]
fn members_measured_one_after_another_do_not() {
    let (kappa, se) = roving_calibrated(false, true);
    let mean = kappa.iter().sum::<f64>() / kappa.len() as f64;
    assert!(mean < 2.0 * se, "κ̂ {mean}, SE {se}");
}

/// `members` as a file without coherence gives them (a table, a UFF file): every line's
/// coherence 1, one average, no estimator; the fit weights them by the residuals.
fn without_coherence(mut members: Vec<SetMember>) -> Vec<SetMember> {
    for m in &mut members {
        m.frf.coherence = vec![1.0; m.frf.frequency.len()];
        (m.frf.averages, m.frf.estimator) = (1, None);
    }
    members
}

/// Without coherence, over 100 sets whose errors at the peaks are mostly in proportion
/// to H (the force's noise, v = 2e-3): roving-hammer sets, roving-accelerometer sets
/// that read one force record, and every set's first FRF fitted alone. The lines keep
/// their equal weights (the default's fallback) and the estimates do not change; the
/// covariance takes each line's variance from the residuals' own noise model
/// ([`Lines::residual_variances`]). With every line's variance taken alike, as it was,
/// the intervals of fn and ζ held the truth 29 % and 14 % of the time for the sets (rms
/// z 7.8 and 19), 34 % and 38 % for the first FRF alone (rms z 8.4 and 7.4). Now: the
/// roving-hammer sets 95 ± 3 % (600 intervals), rms z within 3/√(2·600) of 1; the rest
/// as measured and said below.
///
/// [`Lines::residual_variances`]: msd_modal::lines::Lines::residual_variances
#[test]
fn without_coherence_the_residuals_give_each_line_its_variance() {
    for (shared, roving_response) in [(false, false), (true, true)] {
        let (mut z, mut alone) = (Vec::new(), Vec::new());
        for seed in 0..100 {
            let test = Test {
                force_noise: 2e-3,
                roving_response,
                shared,
                ..Test::default()
            };
            let members = without_coherence(set(seed, test));
            let fit = fit_mode_set(&members, &ModalOptions::default()).expect("a set fit");
            assert_eq!(fit.weighting, FrfWeighting::Uniform);
            assert_eq!(fit.modes.len(), MODES.len(), "{fit}");
            z.extend(pole_z(
                fit.modes
                    .iter()
                    .map(|m| (m.natural_frequency_hz, m.damping_ratio)),
            ));
            let one = fit_modes(&members[0].frf, &ModalOptions::default()).expect("a fit");
            assert_eq!(one.modes.len(), MODES.len(), "{one}");
            alone.extend(pole_z(
                one.modes
                    .iter()
                    .map(|m| (m.natural_frequency_hz, m.damping_ratio)),
            ));
        }
        for (what, z) in [("set", &z), ("first FRF alone", &alone)] {
            let coverage = z.iter().filter(|z| z.abs() <= 1.96).count() as f64 / z.len() as f64;
            let rms = (z.iter().map(|z| z * z).sum::<f64>() / z.len() as f64).sqrt();
            eprintln!(
                "no coherence, shared {shared}, {what}: coverage of fn and ζ {coverage:.3}, rms z {rms:.3}"
            );
            if shared && what == "set" {
                // One force record without coherence: measured 0.655, rms z 2.06 (was
                // 0.14 and 19) — not yet honest. The common error at the peaks moves
                // the poles of an equally weighted fit and so leaves its residuals:
                // the common fraction found from them is too small. A guard only.
                assert!(
                    coverage >= 0.6 && rms <= 2.2,
                    "{what}: {coverage}, rms z {rms}"
                );
                continue;
            }
            assert!(
                (coverage - 0.95).abs() <= 0.03,
                "{what}: coverage {coverage}"
            );
            // A set: within 3/√(2·600) of 1. One FRF alone measured 1.12 and 1.33
            // (coverage 0.923 and 0.952): its equally weighted estimate leans on the
            // peaks' few lines, whose variance the model, fitted to residuals the fit
            // partly absorbs there (the leverage taken off), still puts low in some
            // sets. Bounded at 1.4 so that it cannot slide back towards the 7–8 of
            // equal variances unseen.
            let bound = match what {
                "set" => 3.0 / (2.0 * z.len() as f64).sqrt(),
                _ => 0.4,
            };
            assert!((rms - 1.0).abs() <= bound, "{what}: rms z {rms}");
        }
    }
}

/// z = (estimate − truth)/SE of every mode's fn and ζ, in the order of `MODES`.
fn pole_z(
    modes: impl Iterator<Item = (msd_opt::statistics::Interval, msd_opt::statistics::Interval)>,
) -> Vec<f64> {
    modes
        .zip(&MODES)
        .flat_map(|((f, d), &(fn_hz, zeta))| {
            [
                (f.value - fn_hz) / f.standard_error,
                (d.value - zeta) / d.standard_error,
            ]
        })
        .collect()
}
