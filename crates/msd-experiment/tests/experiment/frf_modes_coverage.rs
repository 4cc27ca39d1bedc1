//! Issue 42, item 3: the intervals of several modes fitted to an impact test's H1 hold
//! their 95 % — `configs/hammer-2dof.toml` (five hits, an exponential window of τ = 2 s
//! on 8 s records, noise on the response, and on the hammer or not) over 200 seeds. The window
//! correlates the response noise's errors over about T/τ = 4 lines, complex, and the
//! force window the force noise's over T/0.1 s = 80; a covariance that takes the lines
//! as independent (scaled by the window's noise bandwidth) covered mode 1's fn and ζ in
//! every seed (spread/SE 0.7) and mode 2's in 79 % (spread/SE 1.55) over 200 seeds.

use msd_experiment::RunOptions;
use msd_experiment::config::{Config, Spec};
use msd_experiment::frf;

const CONFIG: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../configs/hammer-2dof.toml"
);
const SEEDS: u64 = 200;
const NAMES: [&str; 4] = ["fn₁", "ζ₁", "fn₂", "ζ₂"];

#[test]
fn several_modes_from_an_impact_test_hold_their_coverage() {
    let config = Config::load(CONFIG.as_ref()).expect("valid");
    let mut quiet = config.clone();
    let hammer = (quiet.frequency_response.as_mut())
        .and_then(|f| f.hammer.as_mut())
        .expect("a hammer config");
    hammer.force_noise = 0.0;
    assert_honest(quiet, "no hammer noise");
    assert_honest(config, "hammer noise 0.5 N");
}

/// Each true mode's fn and ζ against the nearest fitted mode's, over the seeds.
fn assert_honest(config: Config, label: &str) {
    let mut z: [Vec<f64>; 4] = Default::default();
    let mut inside = [0usize; 4];
    let mut extra = 0;
    for seed in 1..=SEEDS {
        let options = RunOptions {
            seed: Some(seed),
            ..RunOptions::default()
        };
        let outcome =
            frf::run(Spec::new(config.clone()).expect("an FRF config"), &options).expect("fits");
        let truth = &outcome.truth.as_ref().expect("a plant").modes;
        let poles = outcome.fit.poles();
        assert!(
            poles.len() >= 2,
            "{label}, seed {seed}: {} modes",
            poles.len()
        );
        extra += usize::from(poles.len() > 2);
        // The summary compares every true mode, a spurious extra mode or not.
        let summary = outcome.to_string();
        assert!(
            summary.contains("inside the 95 % intervals: ") && summary.contains(" of 4 ("),
            "{label}, seed {seed}: {summary}"
        );
        for (m, mode) in truth.iter().enumerate() {
            let want = [mode.natural_frequency_hz, mode.damping_ratio];
            let distance =
                |p: &&(msd_ident::Interval, msd_ident::Interval)| (p.0.value - want[0]).abs();
            let (f, zeta) = poles
                .iter()
                .min_by(|a, b| distance(a).total_cmp(&distance(b)))
                .expect("modes");
            for (j, interval) in [f, zeta].into_iter().enumerate() {
                z[2 * m + j].push((interval.value - want[j]) / interval.standard_error);
                inside[2 * m + j] += usize::from(interval.contains(want[j]));
            }
        }
    }
    // A spurious third mode (noise the diagram found stable) in at most one seed: its
    // modal constant is tested against zero and the mode refused (without that test,
    // two of the 200 seeds without hammer noise kept one).
    eprintln!("{label}: a third mode in {extra} of {SEEDS} seeds");
    assert!(extra <= 1, "{label}: {extra} extra modes");
    // Over 200 seeds: the spread of z within 3 of its standard errors (1/√400 = 0.05)
    // of 1, the coverage within 3 binomial standard errors (0.046) of 0.95, the mean
    // of z within 3/√200 of 0.
    let n = SEEDS as f64;
    for j in 0..4 {
        let mean = z[j].iter().sum::<f64>() / n;
        let spread = (z[j].iter().map(|v| v * v).sum::<f64>() / n).sqrt();
        let coverage = inside[j] as f64 / n;
        eprintln!(
            "{label}, {}: mean z {mean:+.3}, spread/SE {spread:.3}, coverage {coverage:.3}",
            NAMES[j]
        );
        let name = NAMES[j];
        assert!(
            mean.abs() < 3.0 / n.sqrt(),
            "{label}, {name}: mean z {mean:.3}"
        );
        assert!(
            (spread - 1.0).abs() < 3.0 / (2.0 * n).sqrt(),
            "{label}, {name}: spread/SE {spread:.3}"
        );
        assert!(
            (coverage - 0.95).abs() < 3.0 * (0.95 * 0.05 / n).sqrt(),
            "{label}, {name}: coverage {coverage:.3}"
        );
    }
}
