//! The `[setup]` configs end to end: each shipped synthetic setup runs, its truth lies
//! inside the intervals of every quantity it identifies, its measured template runs on
//! the CSV files the synthetic run wrote, and bad setups are refused by key.

use msd_experiment::{RunOptions, run_experiment};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn config(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../configs")
        .join(name)
}

fn run(config_path: &Path, out: &Path) -> msd_experiment::Result<Value> {
    let options = RunOptions {
        out: Some(out.to_path_buf()),
        ..RunOptions::default()
    };
    run_experiment(config_path, &options).map(|r| r.results)
}

/// Every identifiable quantity's interval holds the truth of the synthetic plant.
fn assert_truth_inside(results: &Value, keys: &[&str]) {
    assert_covers(results, &results["truth"], keys);
}

/// The measured template's estimates agree with the synthetic run's on the same noise:
/// within 3 of the measured run's standard errors. The two differ by what estimating
/// the initial state and the offsets adds (at most their variances' difference; the
/// synthetic drive is its samples alone, as the CSV files hold it); a column read
/// wrongly or scaled wrongly is off by many.
fn assert_agree(measured: &Value, synthetic: &Value, keys: &[&str]) {
    for key in keys {
        let m = &measured["estimate"][*key];
        let s = synthetic["estimate"][*key]["value"].as_f64().unwrap();
        let (value, se) = (
            m["value"].as_f64().unwrap(),
            m["standard_error"].as_f64().unwrap(),
        );
        assert!(
            (value - s).abs() <= 3.0 * se,
            "{key}: measured {value} ± {se}, synthetic {s}"
        );
    }
}

/// Every identifiable quantity's interval in `results` holds its value in `truth`.
fn assert_covers(results: &Value, truth: &Value, keys: &[&str]) {
    let estimate = &results["estimate"];
    let identifiable: Vec<&str> = estimate["identifiable"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert_eq!(identifiable, keys, "{estimate}");
    for key in keys {
        let t = truth[*key]
            .as_f64()
            .unwrap_or_else(|| panic!("truth.{key}: {truth}"));
        let ci = &estimate[*key]["ci95"];
        let (lo, hi) = (ci[0].as_f64().unwrap(), ci[1].as_f64().unwrap());
        assert!(lo <= t && t <= hi, "{key}: truth {t} outside [{lo}, {hi}]");
        assert!(estimate[*key]["value"].is_f64());
    }
}

pub(crate) const ALL: [&str; 5] = [
    "mass",
    "damping",
    "stiffness",
    "natural_frequency_hz",
    "damping_ratio",
];

/// Runs the shipped synthetic config `name`, then its measured template (from
/// configs/templates/) on the CSV files that run wrote; returns both results.
fn synthetic_then_measured(name: &str) -> (Value, Value) {
    let dir = tempfile::tempdir().unwrap();
    let synthetic_out = dir.path().join("target/experiments").join(name);
    let synthetic = run(&config(&format!("{name}.toml")), &synthetic_out).unwrap();
    // The template reads ../../target/experiments/<name>/…, relative to itself.
    let templates = dir.path().join("configs/templates");
    std::fs::create_dir_all(&templates).unwrap();
    let template = templates.join(format!("{name}.toml"));
    std::fs::copy(config(&format!("templates/{name}.toml")), &template).unwrap();
    let measured = run(&template, &dir.path().join("measured")).unwrap();
    (synthetic, measured)
}

#[test]
fn accelerometer_and_laser_are_fitted_together_and_their_noise_estimated() {
    let (s, m) = synthetic_then_measured("accelerometer");
    assert_truth_inside(&s, &ALL);
    assert_eq!(s["setup"]["excitation"], "force");
    // The header every results.json opens with.
    assert_eq!(s["experiment"]["name"], "accelerometer");
    assert_eq!(s["experiment"]["kind"], "synthetic");
    assert_eq!(s["experiment"]["config_file"], "accelerometer.toml");
    assert_eq!(m["experiment"]["kind"], "measured");
    assert_eq!(s["setup"]["responses"].as_array().unwrap().len(), 2);
    let noise = s["noise"].as_array().unwrap();
    // σ̂ of 7501 samples: within 5 % of the truth (its relative SE is 1/√(2·7501) = 0.8 %).
    for (n, truth) in noise.iter().zip([0.0025, 0.05]) {
        let sigma = n["sigma"].as_f64().unwrap();
        assert!((sigma / truth - 1.0).abs() < 0.05, "{n}");
    }
    // The measured template reads the same numbers back, and its intervals hold the truth.
    assert_agree(&m, &s, &ALL);
    assert_covers(&m, &s["truth"], &ALL);
}

#[test]
fn repeats_give_one_row_per_record_and_leave_one_out() {
    let (s, m) = synthetic_then_measured("repeats");
    assert_truth_inside(&s, &ALL);
    assert_eq!(s["records"].as_array().unwrap().len(), 5);
    let loo = s["leave_one_out"].as_array().unwrap();
    assert_eq!(loo.len(), 5);
    for l in loo {
        let r2 = l["channels"][0]["fit"]["r2"].as_f64().unwrap();
        assert!(r2 > 0.99, "{l}");
    }
    assert_eq!(m["records"].as_array().unwrap().len(), 5);
    assert_agree(&m, &s, &ALL);
    assert_covers(&m, &s["truth"], &ALL);
}

#[test]
fn base_excitation_with_the_weighed_mass_gives_c_and_k() {
    let (s, m) = synthetic_then_measured("base-excitation");
    assert_truth_inside(&s, &ALL);
    assert_covers(&m, &s["truth"], &ALL);
}

#[test]
fn base_excitation_without_the_mass_gives_fn_and_zeta_only_and_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(config("base-excitation.toml"))
        .unwrap()
        .replace("known_mass = 2.5", "");
    let path = dir.path().join("base.toml");
    std::fs::write(&path, text).unwrap();
    let r = run(&path, &dir.path().join("out")).unwrap();
    assert_truth_inside(&r, &["natural_frequency_hz", "damping_ratio"]);
    let note = r["estimate"]["note"].as_str().unwrap();
    assert!(note.contains("mass"), "{note}");
    assert!(r["estimate"].get("mass").is_none());
}

#[test]
fn free_decay_gives_the_fit_and_the_classroom_estimates() {
    let (s, m) = synthetic_then_measured("free-decay");
    assert_truth_inside(&s, &ALL);
    // The classroom estimates sit beside the fit (their accuracy on clean records is
    // msd-ident's textbook test; on noisy late peaks they are biased, which is why the
    // fit is the estimate).
    let classroom = &s["free_decay"]["classroom"];
    assert!(s["free_decay"]["log_decrement"].as_f64().unwrap() > 0.0);
    assert!(classroom["damped_frequency_hz"].as_f64().unwrap() > 0.0);
    assert_covers(&m, &s["truth"], &ALL);
}

#[test]
fn the_test_machine_ranks_the_quadratic_law_first() {
    let (s, m) = synthetic_then_measured("damper-test-machine");
    let laws = s["dynamometer"]["laws"].as_array().unwrap();
    let first = laws.iter().find(|l| l["rank"] == 1).unwrap();
    assert_eq!(first["law"], "quadratic_viscous");
    // Every coefficient of the law ranked first covers the truth (the force offset's is 0).
    let estimate = &s["estimate"];
    for key in [
        "mass",
        "damping",
        "stiffness",
        "quadratic_damping",
        "force_offset",
    ] {
        let truth = s["truth"][key].as_f64().unwrap_or(0.0);
        let ci = &estimate[key]["ci95"];
        let (lo, hi) = (ci[0].as_f64().unwrap(), ci[1].as_f64().unwrap());
        assert!(
            lo <= truth && truth <= hi,
            "{key}: {truth} outside [{lo}, {hi}]"
        );
    }
    assert_eq!(s["dynamometer"]["conditions"].as_array().unwrap().len(), 10);
    // The verdict: the ranking and the conditions predicted by the others.
    assert_eq!(s["verdict"]["trustworthy"], true, "{}", s["verdict"]);
    let findings = s["verdict"]["findings"].to_string();
    assert!(
        findings.contains("ranks first") && findings.contains("worst R²"),
        "{findings}"
    );
    let first = m["dynamometer"]["laws"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["rank"] == 1)
        .unwrap()
        .clone();
    assert_eq!(first["law"], "quadratic_viscous");
}

/// A config text of the accelerometer setup with `from` replaced by `to`, refused with
/// every piece of `expected` in its message.
fn refused(base: &str, from: &str, to: &str, expected: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(config(base)).unwrap();
    assert!(text.contains(from), "{from}");
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    let err = run(&path, &dir.path().join("out")).unwrap_err();
    let message = err.to_string();
    for e in expected {
        assert!(message.contains(e), "{message}\nexpected: {e}");
    }
    assert_eq!(err.exit_code(), 2, "{message}");
    assert!(!dir.path().join("out").exists());
}

#[test]
fn bad_setups_are_refused_by_key() {
    refused(
        "accelerometer.toml",
        "{ quantity = \"acceleration\", sigma = 0.05 }",
        "{ quantity = \"acceleration\", frame = \"relative\", sigma = 0.05 }",
        &["setup.responses[1].quantity", "relative", "force"],
    );
    refused(
        "base-excitation.toml",
        "{ quantity = \"displacement\", frame = \"relative\", sigma = 0.0005 }",
        "{ quantity = \"velocity\", frame = \"absolute\", sigma = 0.0005 }",
        &["setup.responses[0].quantity", "base_acceleration"],
    );
    refused(
        "free-decay.toml",
        "known_mass = 2.5",
        "known_mass = 2.5\nknown_stiffness = 120.0",
        &["setup.known_stiffness", "at most one"],
    );
}

/// Writes `files` (name, CSV text) and a measured free-decay or force config reading
/// them; returns the run's error.
fn measured_error(setup: &str, files: &[(&str, String)]) -> msd_experiment::ExperimentError {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    let paths: Vec<String> = files.iter().map(|(n, _)| format!("{n:?}")).collect();
    let text = format!(
        "name = \"bad\"\n[setup]\n{setup}\n[data]\npath = [{}]\ntime = \"t\"\n{}",
        paths.join(", "),
        if setup.contains("\"none\"") {
            ""
        } else {
            "input = \"force\"\n"
        }
    );
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, text).unwrap();
    let err = run(&path, &dir.path().join("out")).unwrap_err();
    assert!(!dir.path().join("out").exists());
    err
}

fn csv(dt: f64, n: usize, f: impl Fn(f64) -> (f64, f64)) -> String {
    let mut s = String::from("t,force,x\n");
    for i in 0..n {
        let t = i as f64 * dt;
        let (u, x) = f(t);
        s.push_str(&format!("{t},{u},{x}\n"));
    }
    s
}

#[test]
fn bad_records_are_refused_with_their_names() {
    let force =
        "excitation = \"force\"\nresponses = [{ quantity = \"displacement\", column = \"x\" }]";
    let wave = |t: f64| {
        (
            (3.0 * t).sin(),
            0.01 * (2.0 * t).sin() + 1e-4 * (37.0 * t).cos(),
        )
    };
    let e = measured_error(
        force,
        &[
            ("a.csv", csv(0.002, 2000, wave)),
            ("b.csv", csv(0.004, 1000, wave)),
        ],
    );
    let message = e.to_string();
    assert_eq!(e.exit_code(), 2, "{message}");
    assert!(
        message.contains("b") && message.contains("0.004"),
        "{message}"
    );

    let e = measured_error(
        force,
        &[("flat.csv", csv(0.002, 2000, |t| ((3.0 * t).sin(), 0.0)))],
    );
    let message = e.to_string();
    assert_eq!(e.exit_code(), 2, "{message}");
    assert!(
        message.contains("constant") && message.contains("displacement"),
        "{message}"
    );

    let decay =
        "excitation = \"none\"\nresponses = [{ quantity = \"displacement\", column = \"x\" }]";
    let growing = |t: f64| {
        (
            0.0,
            0.01 * (0.5 * t).exp() * (2.0 * std::f64::consts::PI * 2.0 * t).cos(),
        )
    };
    let e = measured_error(decay, &[("grow.csv", csv(0.002, 2500, growing))]);
    let message = e.to_string();
    assert_eq!(e.exit_code(), 2, "{message}");
    assert!(message.contains("decay"), "{message}");
}

/// The measured accelerometer template validates on fresh data by default (its one
/// record's held-out end), and on the part `[data.validation]` names when given, fitted
/// on `[data.estimation]` only; `[residuals]` sets the tests' lags.
#[test]
fn a_measured_setup_validates_on_fresh_data() {
    let (_, held) = synthetic_then_measured("accelerometer");
    let v = &held["validation"];
    assert!(v["source"].as_str().unwrap().contains("last 20 %"), "{v}");
    let p = &v["predictions"][0];
    // The laser's σ is 2.5 mm: R² of the prediction about 1 − σ²/var(x).
    assert!(
        p["channels"][0]["fit"]["r2"].as_f64().unwrap() > 0.98,
        "{p}"
    );
    assert_eq!(p["channels"][0]["fit"]["samples"], 1500);
    assert_eq!(p["residual_analysis"][1]["cross_correlation_passed"], true);

    let dir = tempfile::tempdir().unwrap();
    let synthetic_out = dir.path().join("target/experiments/accelerometer");
    run(&config("accelerometer.toml"), &synthetic_out).unwrap();
    let templates = dir.path().join("configs/templates");
    std::fs::create_dir_all(&templates).unwrap();
    let text = std::fs::read_to_string(config("templates/accelerometer.toml")).unwrap();
    let parts = "\n[data.estimation]\ntime = [0.0, 10.0]\n[data.validation]\ntime = [10.0, 15.0]\n[residuals]\nmax_lag = 30\n";
    let template = templates.join("accelerometer.toml");
    std::fs::write(&template, format!("{text}{parts}")).unwrap();
    let out = dir.path().join("measured");
    let r = run(&template, &out).unwrap();
    let v = &r["validation"];
    assert!(
        v["source"]
            .as_str()
            .unwrap()
            .contains("given for validation"),
        "{v}"
    );
    let p = &v["predictions"][0];
    assert_eq!(p["record"], "record-1 (validation)");
    assert_eq!(p["channels"][0]["fit"]["samples"], 2500);
    assert_eq!(r["records"][0]["channels"][0]["fit"]["samples"], 5000);
    assert_eq!(r["whiteness"][0]["ljung_box"]["degrees_of_freedom"], 30);
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("## Validation on fresh data"), "{report}");

    // `[setup] hold_out = 0` turns the single record's check off; out of range, refused.
    let off = text.replace("[setup]\n", "[setup]\nhold_out = 0.0\n");
    std::fs::write(&template, &off).unwrap();
    assert!(run(&template, &out).unwrap().get("validation").is_none());
    let bad = text.replace("[setup]\n", "[setup]\nhold_out = 0.8\n");
    std::fs::write(&template, &bad).unwrap();
    let e = run(&template, &out).expect_err("refused");
    assert!(e.to_string().contains("setup.hold_out = 0.8"), "{e}");

    // A validation part that overlaps the estimation part is said to.
    let overlap = "\n[data.validation]\ntime = [8.0, 15.0]\n";
    std::fs::write(&template, format!("{text}{overlap}")).unwrap();
    run(&template, &out).unwrap();
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        report.contains("scores data the model was fitted to"),
        "{report}"
    );
}
