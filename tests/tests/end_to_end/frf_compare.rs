//! The frequency-domain estimate beside the time-domain one: `configs/frf-records.toml`
//! end to end (both estimates cover the truth and agree), the two-mass hammer test
//! (no single-mode time model: said, not compared), and the simulated sources'
//! estimator settings refused where they cannot work.

use msd_experiment::{RunOptions, run_experiment};
use msd_tests::{assert_results_file_is, config, run_in_temp};

/// Each quantity of `configs/frf-records.toml` (m, c, k, fn, ζ) is estimated twice from
/// the same four records: by the one-mode fit of H1 (q̂_f, standard error SE_f) and by
/// the joint time-domain fit (q̂_t, SE_t). Each 95 % interval covers the truth.
///
/// They agree within their combined intervals: d = (q̂_f − q̂_t)/√(SE_f² + SE_t²) has
/// |d| ≤ 1.96. Why that is the right bound: both estimates are consistent, and the
/// time-domain fit is the maximum-likelihood fit of white output noise (the force is
/// noiseless, the model exact), hence efficient; Hausman (1978) then gives
/// Cov(q̂_f, q̂_t) = Var(q̂_t), so Var(q̂_f − q̂_t) = SE_f² − SE_t² ≤ SE_f² + SE_t², and
/// P(|d| > 1.96) ≤ 5 % per quantity. Over the five quantities of a run the test uses
/// the Bonferroni bound |d| ≤ 2.58 (P ≤ 1 % each, ≤ 5 % that any of them passes it), so
/// that a correct change of the noise stream fails it at most one time in twenty (over
/// 20 seeds the largest |d| of any quantity was 1.74).
#[test]
fn the_frf_records_config_agrees_with_the_time_domain_fit_and_covers_the_truth() {
    let run = run_in_temp(&config("frf-records.toml"), None, None).expect("runs");
    let r = &run.summary.results;
    assert_eq!(run.number("data.averages"), 4.0);
    assert_eq!(r["experiment"]["kind"], "frequency_response");
    assert_eq!(r["experiment"]["config_file"], "frf-records.toml");
    // The lines above the multisine's band carry no force (coherence 0); the key is the
    // fitted band's lowest, which the report states too.
    let coherence = run.number("data.min_coherence");
    assert!(coherence > 0.0 && coherence <= 1.0, "{coherence}");
    let comparison = r["time_domain"]["comparison"]
        .as_array()
        .expect("a comparison");
    let names: Vec<&str> = comparison
        .iter()
        .map(|c| c["quantity"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "mass",
            "damping",
            "stiffness",
            "natural_frequency_hz",
            "damping_ratio"
        ]
    );
    for c in comparison {
        let name = c["quantity"].as_str().unwrap();
        let truth = c["truth"].as_f64().expect("a synthetic plant");
        for domain in ["frequency_domain", "time_domain"] {
            let ci = &c[domain]["ci95"];
            let (low, high) = (ci[0].as_f64().unwrap(), ci[1].as_f64().unwrap());
            assert!(
                low <= truth && truth <= high,
                "{name}, {domain}: {truth} not in [{low}, {high}]"
            );
        }
        // The same numbers as the two estimates elsewhere in the file.
        assert_eq!(c["frequency_domain"], r["estimate"][name]);
        assert_eq!(c["time_domain"], r["time_domain"]["estimate"][name]);
        let (f, t) = (&c["frequency_domain"], &c["time_domain"]);
        let se = |v: &serde_json::Value| v["standard_error"].as_f64().unwrap();
        let d = (f["value"].as_f64().unwrap() - t["value"].as_f64().unwrap()) / se(f).hypot(se(t));
        assert!((c["difference_se"].as_f64().unwrap() - d).abs() <= 1e-12 * d.abs().max(1.0));
        assert!(d.abs() <= 2.58, "{name}: the estimates differ by {d} SE");
    }
    assert_eq!(run.number("time_domain.records"), 4.0);
    assert_eq!(r["time_domain"]["hold"], "cubic");
    let report = std::fs::read_to_string(run.out().join("report.md")).expect("report");
    assert!(report.contains("## Frequency domain and time domain"));
    assert!(report.contains("| m [kg] | 2."), "{report}");
    assert!(
        run.summary
            .summary
            .contains("time domain    (4 records): largest difference")
    );
    assert_results_file_is(run.out(), r);
}

#[test]
fn a_two_mass_hammer_test_says_why_it_is_not_compared() {
    let run = run_in_temp(&config("hammer-2dof.toml"), None, None).expect("runs");
    let reason = run.summary.results["time_domain"]["reason"]
        .as_str()
        .expect("a reason");
    assert!(reason.starts_with("2 modes were fitted"), "{reason}");
    let report = std::fs::read_to_string(run.out().join("report.md")).expect("report");
    assert!(
        report.contains("Not compared: 2 modes were fitted"),
        "{report}"
    );
}

/// A one-mass plant hit by the hammer: the records are compared too (the time-domain
/// fit holds the force as a cubic between samples: the simulated force passed an
/// anti-aliasing filter, a smooth signal rather than a line).
#[test]
fn a_one_mass_hammer_test_is_compared() {
    let dir = tempfile::tempdir().expect("a folder");
    let td = time_domain_of(dir.path(), HAMMER_1DOF);
    assert_eq!(td["hold"], "cubic");
    assert_agreement(&td);
}

/// The `time_domain` section of the run of `config`, written into `dir`.
fn time_domain_of(dir: &std::path::Path, config: &str) -> serde_json::Value {
    let path = dir.join("config.toml");
    std::fs::write(&path, config).expect("written");
    let options = RunOptions {
        out: Some(dir.join("out")),
        ..RunOptions::default()
    };
    let run = run_experiment(&path, &options).expect("runs");
    run.results["time_domain"].clone()
}

/// Every quantity's |d| ≤ 2.58 (see the first test) and the time-domain interval
/// covers the truth.
fn assert_agreement(td: &serde_json::Value) {
    for c in td["comparison"].as_array().expect("compared") {
        let d = c["difference_se"].as_f64().unwrap();
        println!("{}: {d:+.2} combined SE", c["quantity"]);
        assert!(d.abs() <= 2.58, "{}: {d}", c["quantity"]);
        let ci = &c["time_domain"]["ci95"];
        let truth = c["truth"].as_f64().unwrap();
        assert!(
            ci[0].as_f64() <= Some(truth) && Some(truth) <= ci[1].as_f64(),
            "{c}"
        );
    }
}

const HAMMER_1DOF: &str = r#"
name = "hammer-1dof"
[frequency_response.plant]
masses = [2.5]
springs = [120.0]
dampers = [1.8]
[frequency_response.hammer]
hits = 5
sample_rate = 50.0
duration = 20.0
pulse_width = 0.1
force_peak = 20.0
force_noise = 0.0
[frequency_response.estimator]
impact = { force_width = 0.5, decay_time = 10.0 }
[frequency_response.one_mode]
band_hz = [0.2, 5.0]
"#;

#[test]
fn the_simulated_sources_refuse_estimator_settings_that_cannot_work() {
    let dir = tempfile::tempdir().expect("a folder");
    let refused = |name: &str, text: &str, fragments: &[&str]| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).expect("written");
        let err = msd_experiment::config::Config::load(&path).expect_err("refused");
        let message = err.to_string();
        assert!(!message.contains('\n'), "one line: {message}");
        for f in fragments {
            assert!(message.contains(f), "`{message}` lacks `{f}`");
        }
    };
    let hammer = HAMMER_1DOF.replace(
        "impact = { force_width = 0.5, decay_time = 10.0 }",
        "IMPACT",
    );
    refused(
        "kind.toml",
        &hammer.replace("IMPACT", "kind = \"jerk\"\nimpact = {}"),
        &["kind.toml", "jerk", "displacement"],
    );
    // The default window, and Hann by name: each named as given.
    refused(
        "auto.toml",
        &hammer.replace("IMPACT", "estimator = \"H1\""),
        &[
            "auto.toml",
            "frequency_response.estimator.welch.window = \"auto\"",
            "expected `impact` windows",
        ],
    );
    refused(
        "hann.toml",
        &hammer.replace("IMPACT", "welch = { window = \"hann\" }"),
        &[
            "hann.toml",
            "frequency_response.estimator.welch.window = \"hann\"",
            "expected `impact` windows",
        ],
    );
    refused(
        "segments.toml",
        &hammer.replace(
            "IMPACT",
            "welch = { window = \"rectangular\", segment_length = 256 }",
        ),
        &[
            "frequency_response.estimator.welch.segment_length = 256",
            "each hit is one record",
        ],
    );
    refused(
        "width.toml",
        &hammer.replace("IMPACT", "impact = { force_width = 0.1 }"),
        &[
            "frequency_response.estimator.impact.force_width = 0.1 s",
            "from trigger + pulse_width (0.05 + 0.1 s) to duration (20 s)",
        ],
    );
    refused(
        "decay.toml",
        &hammer.replace("IMPACT", "impact = { decay_time = -1.0 }"),
        &["frequency_response.estimator", "decay_time", "-1"],
    );
    let shaker = "name = \"s\"\n[frequency_response.plant]\nmasses = [2.5]\nsprings = [120.0]\ndampers = [1.8]\n[frequency_response.shaker]\nrecords = 0\nsample_rate = 50.0\nduration = 20.0\nforce = { kind = \"sine\", amplitude = 1.0, frequency = 1.0 }\n";
    refused(
        "records.toml",
        shaker,
        &["frequency_response.shaker.records = 0", "at least 1"],
    );
    refused(
        "force.toml",
        &shaker
            .replace("records = 0", "records = 2")
            .replace("frequency = 1.0", "frequency = -1.0"),
        &["frequency_response.shaker.force", "frequency"],
    );
    let fine = shaker.replace("records = 0", "records = 2");
    refused(
        "long.toml",
        &fine.replace("duration = 20.0", "duration = 200000.0"),
        &[
            "frequency_response.shaker.duration = 200000",
            "the largest accepted is 55555",
        ],
    );
    refused(
        "impact.toml",
        &format!("{fine}[frequency_response.estimator]\nimpact = {{ decay_time = 1.0 }}\n"),
        &["frequency_response.estimator.impact", "with a shaker"],
    );
}

/// Measured records read from CSV are compared too, the force cubic between samples
/// (as a measured force is held). Two periods of a multisine (0.05–5 Hz) on the paper's
/// plant, sampled at 200 Hz after the transient, displacement with 1 % noise; simulated
/// with the force linear between samples, which differs from the fit's cubic hold and
/// from the continuous H by O((π·f/fs)²) ≈ 1e-4 at fn, well inside the intervals.
#[test]
fn measured_records_are_compared_with_a_cubic_hold() {
    use msd_experiment::config::ChainPlant;
    use msd_signal::{FrfKind, Multisine, MultisineSpec, PhaseScheme, Signal, gaussian_noise};
    let plant = ChainPlant::one_mass(2.5, 1.8, 120.0);
    let force = Signal::Multisine(
        Multisine::new(MultisineSpec {
            base_frequency: 0.05,
            f_min: 0.05,
            f_max: 5.0,
            rms: 2.0,
            phases: PhaseScheme::Random,
            seed: 3,
            ..MultisineSpec::default()
        })
        .expect("a multisine"),
    );
    let (fs, per, skip) = (200.0, 4000, 8000);
    let f: Vec<f64> = (0..skip + 2 * per)
        .map(|i| force.value(i as f64 / fs))
        .collect();
    let x = plant
        .sampled_response(&f, 1.0 / fs, FrfKind::Receptance)
        .expect("a valid plant and force");
    let rms = (x[skip..].iter().map(|v| v * v).sum::<f64>() / (2 * per) as f64).sqrt();
    let noise = gaussian_noise(5, "laser", 0.01 * rms, 2 * per).expect("noise");
    let mut csv = String::from("f1,x1,f2,x2\n");
    for i in 0..per {
        let (a, b) = (skip + i, skip + per + i);
        csv.push_str(&format!(
            "{},{},{},{}\n",
            f[a],
            x[a] + noise[i],
            f[b],
            x[b] + noise[per + i]
        ));
    }
    let dir = tempfile::tempdir().expect("a folder");
    std::fs::write(dir.path().join("records.csv"), csv).expect("written");
    let td = time_domain_of(
        dir.path(),
        "name = \"r\"\n[frequency_response.records]\npath = \"records.csv\"\nsample_rate = 200.0\nforce = [\"f1\", \"f2\"]\nresponse = [\"x1\", \"x2\"]\n[frequency_response.estimator]\nwelch = { window = \"rectangular\" }\n[frequency_response.one_mode]\nband_hz = [0.05, 5.0]\n[frequency_response.plant]\nmasses = [2.5]\nsprings = [120.0]\ndampers = [1.8]\n",
    );
    assert_eq!(td["hold"], "cubic");
    assert_eq!(td["records"], 2);
    assert_agreement(&td);
}
