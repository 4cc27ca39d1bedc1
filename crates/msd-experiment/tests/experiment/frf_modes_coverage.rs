//! Issue 42, item 3: the intervals of several modes fitted to an impact test's H1 hold
//! their 95 % — `configs/hammer-2dof.toml` (five hits, an exponential window of τ = 2 s
//! on 8 s records, noise on the response, and on the hammer or not) over 200 seeds. The window
//! correlates the response noise's errors over about T/τ = 4 lines, complex, and the
//! force window the force noise's over T/0.1 s = 80; a covariance that takes the lines
//! as independent (scaled by the window's noise bandwidth) covered mode 1's fn and ζ in
//! every seed (spread/SE 0.7) and mode 2's in 79 % (spread/SE 1.55) over 200 seeds.
//!
//! The modal constants (A + jB of each mode) are checked too, since the simulated
//! hammer's force passes an anti-aliasing filter (before, a force taken as linear
//! between samples made H low by the first-order hold's sinc², A₂ by 0.19 %, 0.5 SE).

use msd_experiment::RunOptions;
use msd_experiment::config::{Config, Spec};
use msd_experiment::frf::{self, FrfFit, FrfOutcome};
use msd_modal::ModalParameters;

const CONFIG: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../configs/hammer-2dof.toml"
);
const SEEDS: u64 = 200;
const NAMES: [&str; 8] = ["fn₁", "ζ₁", "fn₂", "ζ₂", "A₁", "B₁", "A₂", "B₂"];

/// What is asserted of a quantity over the seeds.
#[derive(Clone, Copy, PartialEq)]
enum Check {
    /// Mean z, spread/SE and coverage (see [`assert_honest`]).
    All,
    /// Spread/SE and coverage, not the mean z.
    Unbiased,
    /// Coverage at least 0.95 (less three binomial standard errors) and spread/SE at
    /// most 1 (plus its tolerance): intervals that may be wider than needed.
    Conservative,
}

#[test]
fn several_modes_from_an_impact_test_hold_their_coverage() {
    use Check::{All, Conservative, Unbiased};
    let config = Config::load(CONFIG.as_ref()).expect("valid");
    // Response noise only. A₁'s mean z is −0.35: the 8 s records end with mode 1 at
    // e^(−T/τ′) = 3.4e-4 of its start (τ′ the windowed decay), whose leakage makes A₁
    // low by 0.035 % without noise (0.2 SE here).
    let quiet = with_noise(&config, 0.0, None);
    let checks = [All, All, All, All, Unbiased, All, All, All];
    assert_honest(quiet, "no hammer noise", checks);
    // The shipped config: 0.5 N on the hammer, 2 % of the peak on the response. The
    // force noise's share of each line's error is measured on the hammer channel after
    // the force window; fitted to the coherence instead (its force term resting on the
    // few lines at the two resonances, ten times too small in some seeds), A₁'s
    // intervals were too narrow: coverage 0.89, spread/SE 1.32.
    let checks = [All; 8];
    assert_honest(config.clone(), "hammer noise 0.5 N", checks);
    // The hammer's noise dominant (response noise 0.02 % of the peak): the force noise's
    // errors, correlated over 80 lines, make JᵀCJ nearly singular (taken as its positive
    // part) and the residuals' SSE a sum of few independent squares (the coherence's
    // own variance is then the floor of s²). Before both, coverage 0.57-0.81.
    let loud = with_noise(&config, 0.5, Some(2e-4));
    assert_honest(loud, "hammer noise dominant", [Conservative; 8]);
}

/// Two modes in the band and one fitted (`mode_count = 1`): the fit still runs, and its
/// residuals against the FRF's own noise say that the data contradict the model, first
/// in the verdict.
#[test]
fn a_mode_the_fit_lacks_fails_the_noise_check() {
    let mut config = Config::load(CONFIG.as_ref()).expect("valid");
    let modes = (config.frequency_response.as_mut())
        .and_then(|f| f.modes.as_mut())
        .expect("a modes section");
    modes.mode_count = Some(1);
    let outcome = frf::run(
        Spec::new(config).expect("an FRF config"),
        &RunOptions::default(),
    )
    .expect("fits");
    let FrfFit::Modes(fit) = &outcome.fit else {
        panic!("several modes expected")
    };
    assert_eq!(fit.modes.len(), 1);
    let check = fit.noise_check.expect("a coherence from five hits");
    assert!(!check.passed && check.variance_ratio > 10.0, "{check}");
    assert!(
        fit.to_string()
            .contains("warning: the model leaves more than the noise")
    );
    let verdict = &outcome.verdict;
    assert!(!verdict.trustworthy, "{verdict}");
    assert!(
        (verdict.to_string())
            .starts_with("use with care: the residual exceeds the FRF's own noise"),
        "{verdict}"
    );
}

/// `config` with `force_noise` on the hammer and, if given, `response_noise`.
fn with_noise(config: &Config, force_noise: f64, response_noise: Option<f64>) -> Config {
    let mut config = config.clone();
    let hammer = (config.frequency_response.as_mut())
        .and_then(|f| f.hammer.as_mut())
        .expect("a hammer config");
    hammer.force_noise = force_noise;
    if let Some(r) = response_noise {
        hammer.response_noise = r;
    }
    config
}

/// Each true mode's fn, ζ, A and B against the nearest fitted mode's, over the seeds.
fn assert_honest(config: Config, label: &str, checks: [Check; 8]) {
    let mut z: [Vec<f64>; 8] = Default::default();
    let mut inside = [0usize; 8];
    let mut extra = 0;
    let mut checks_seen = Vec::new();
    for seed in 1..=SEEDS {
        let options = RunOptions {
            seed: Some(seed),
            ..RunOptions::default()
        };
        let outcome =
            frf::run(Spec::new(config.clone()).expect("an FRF config"), &options).expect("fits");
        let FrfFit::Modes(fit) = &outcome.fit else {
            panic!("{label}, seed {seed}: several modes expected")
        };
        assert!(
            fit.modes.len() >= 2,
            "{label}, seed {seed}: {} modes",
            fit.modes.len()
        );
        extra += usize::from(fit.modes.len() > 2);
        checks_seen.push(fit.noise_check.expect("a coherence from five hits"));
        // The summary compares every true mode, a spurious extra mode or not.
        let summary = outcome.to_string();
        assert!(
            summary.contains("inside the 95 % intervals: ") && summary.contains(" of 4 ("),
            "{label}, seed {seed}: {summary}"
        );
        for (m, truth) in truth(&outcome).iter().enumerate() {
            for (j, (value, se, halfwidth, want)) in compared(fit, truth).into_iter().enumerate() {
                let q = if j < 2 { 2 * m + j } else { 4 + 2 * m + j - 2 };
                z[q].push((value - want) / se);
                inside[q] += usize::from((value - want).abs() <= halfwidth);
            }
        }
    }
    // A spurious third mode (noise the diagram found stable) in at most one seed: its
    // modal constant is tested against zero and the mode refused (without that test,
    // two of the 200 seeds without hammer noise kept one).
    eprintln!("{label}: a third mode in {extra} of {SEEDS} seeds");
    assert_noise_checks(&checks_seen, label);
    assert!(extra <= 1, "{label}: {extra} extra modes");
    for (j, check) in checks.into_iter().enumerate() {
        assert_statistics(&z[j], inside[j], check, &format!("{label}, {}", NAMES[j]));
    }
}

/// The true modes (eigenvalues and modal constants of the simulated plant).
fn truth(outcome: &FrfOutcome) -> Vec<ModalParameters> {
    outcome.truth.as_ref().expect("a plant").modes.clone()
}

/// (estimate, standard error, 95 % half-width, truth) of fn, ζ, A and B of the fitted
/// mode nearest to `truth` in frequency.
fn compared(fit: &msd_modal::ModalFit, truth: &ModalParameters) -> [(f64, f64, f64, f64); 4] {
    let distance =
        |m: &msd_modal::Mode| (m.natural_frequency_hz.value - truth.natural_frequency_hz).abs();
    let mode = (fit.modes.iter())
        .min_by(|a, b| distance(a).total_cmp(&distance(b)))
        .expect("modes");
    let (f, zeta) = (&mode.natural_frequency_hz, &mode.damping_ratio);
    // Student's t of the fit (the modal constants' intervals use the same).
    let t = (f.ci95[1] - f.value) / f.standard_error;
    let constant = &mode.modal_constants[0];
    let se = constant.standard_error.expect("standard errors");
    let interval = |i: &msd_ident::Interval, want: f64| {
        let half = if want > i.value {
            i.ci95[1] - i.value
        } else {
            i.value - i.ci95[0]
        };
        (i.value, i.standard_error, half, want)
    };
    [
        interval(f, truth.natural_frequency_hz),
        interval(zeta, truth.damping_ratio),
        (constant.re, se[0], t * se[0], truth.modal_constant),
        (
            constant.im,
            se[1],
            t * se[1],
            truth.modal_constant_imaginary,
        ),
    ]
}

/// Over 200 seeds: the spread of z within 3 of its standard errors (1/√400 = 0.05)
/// of 1, the coverage within 3 binomial standard errors (0.046) of 0.95, the mean of z
/// within 3/√200 of 0 — as far as `check` asks.
fn assert_statistics(z: &[f64], inside: usize, check: Check, name: &str) {
    let n = z.len() as f64;
    let mean = z.iter().sum::<f64>() / n;
    let spread = (z.iter().map(|v| v * v).sum::<f64>() / n).sqrt();
    let coverage = inside as f64 / n;
    eprintln!("{name}: mean z {mean:+.3}, spread/SE {spread:.3}, coverage {coverage:.3}");
    let (spread_tolerance, coverage_tolerance) =
        (3.0 / (2.0 * n).sqrt(), 3.0 * (0.95 * 0.05 / n).sqrt());
    match check {
        Check::Conservative => {
            assert!(
                spread < 1.0 + spread_tolerance,
                "{name}: spread/SE {spread:.3}"
            );
            assert!(
                coverage > 0.95 - coverage_tolerance,
                "{name}: coverage {coverage:.3}"
            );
        }
        Check::All | Check::Unbiased => {
            if check == Check::All {
                assert!(mean.abs() < 3.0 / n.sqrt(), "{name}: mean z {mean:.3}");
            }
            assert!(
                (spread - 1.0).abs() < spread_tolerance,
                "{name}: spread/SE {spread:.3}"
            );
            assert!(
                (coverage - 0.95).abs() < coverage_tolerance,
                "{name}: coverage {coverage:.3}"
            );
        }
    }
}

/// The residuals' check against the FRF's own noise, where the model is right: SSE/E[SSE]
/// averages 1 within 3 of its standard errors (each ratio's variance 2/h, h the
/// effective degrees of freedom), and the check fails (p < 0.01) in at most 7 of 200
/// seeds (P(X ≥ 8) ≈ 1e-3 for X ~ Binomial(200, 0.01)).
fn assert_noise_checks(checks: &[msd_modal::NoiseCheck], label: &str) {
    let n = checks.len() as f64;
    let mean = checks.iter().map(|c| c.variance_ratio).sum::<f64>() / n;
    let se = (checks
        .iter()
        .map(|c| 2.0 / c.degrees_of_freedom)
        .sum::<f64>())
    .sqrt()
        / n;
    let failed = checks.iter().filter(|c| !c.passed).count();
    let h = checks.iter().map(|c| c.degrees_of_freedom).sum::<f64>() / n;
    let spread = (checks
        .iter()
        .map(|c| (c.variance_ratio - mean).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    eprintln!(
        "{label}: SSE/E[SSE] mean {mean:.3} (± {se:.3}), spread {spread:.3} against √(2/h) {:.3}, h {h:.1}, failed {failed}",
        (2.0 / h).sqrt()
    );
    assert!(
        (mean - 1.0).abs() < 3.0 * se,
        "{label}: SSE/E[SSE] {mean:.3}"
    );
    assert!(
        failed <= 7,
        "{label}: the noise check failed in {failed} seeds"
    );
}
