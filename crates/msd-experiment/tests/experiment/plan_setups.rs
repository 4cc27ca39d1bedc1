//! `plan` on the `[setup]` configs: the Cramér–Rao prediction against 200 simulated
//! runs of each shipped setup, a setup that identifies ωn and ζ only, what reaches the
//! target, and the configs it refuses.

use crate::setups::ALL;
use msd_experiment::plan::{Plan, PlanOptions, plan};
use std::path::{Path, PathBuf};

fn config(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../configs")
        .join(name)
}

/// The config `name` with `from` replaced by `to`, written into `dir`.
fn edited(name: &str, from: &str, to: &str, dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(config(name)).unwrap();
    let changed = text.replace(from, to);
    assert_ne!(changed, text, "{name} holds {from:?}");
    let path = dir.join(name);
    std::fs::write(&path, changed).unwrap();
    path
}

const SEEDS: usize = 200;

/// The sample standard deviation s of N normal draws has a relative standard deviation
/// of 1/√(2(N − 1)) about σ (5.0 % for N = 200): s/σ within 3.5 of them (17.5 %) fails
/// by chance once in about 2000 quantities.
fn tolerance(seeds: usize) -> f64 {
    3.5 / (2.0 * (seeds as f64 - 1.0)).sqrt()
}

/// Every planned quantity's empirical standard deviation over `SEEDS` runs agrees with
/// its prediction.
fn assert_verified(plan: &Plan) {
    assert_eq!(plan.verified_with, SEEDS);
    for q in &plan.quantities {
        let sd = q.simulated_standard_deviation.unwrap();
        let ratio = sd / q.standard_error;
        assert!(
            (ratio - 1.0).abs() <= tolerance(SEEDS),
            "{} {}: empirical {sd:.4e}, predicted {:.4e} (ratio {ratio:.3})\n{plan}",
            plan.name,
            q.name,
            q.standard_error
        );
    }
    assert!(
        plan.to_string().contains(&format!("sd of {SEEDS}")),
        "{plan}"
    );
}

fn verified(path: &Path) -> Plan {
    let options = PlanOptions {
        verify: SEEDS,
        ..PlanOptions::default()
    };
    plan(path, &options).unwrap()
}

fn names(plan: &Plan) -> Vec<&str> {
    plan.quantities.iter().map(|q| q.name).collect()
}

#[test]
fn accelerometer_prediction_matches_200_runs() {
    let plan = verified(&config("accelerometer.toml"));
    assert_eq!(names(&plan), ALL);
    assert_eq!(plan.test.channels.len(), 2);
    assert_verified(&plan);
}

#[test]
fn base_excitation_prediction_matches_200_runs() {
    let plan = verified(&config("base-excitation.toml"));
    // The mass is weighed: c, k, fn and ζ estimated, m known.
    assert_eq!(names(&plan), ALL[1..]);
    assert!(plan.to_string().contains("mass known"), "{plan}");
    assert_verified(&plan);
}

#[test]
fn free_decay_prediction_matches_200_runs() {
    let plan = verified(&config("free-decay.toml"));
    assert_eq!(names(&plan), ALL[1..]);
    assert_eq!(
        (plan.test.drive, plan.test.peak_drive),
        ("initial state", 0.01)
    );
    assert_verified(&plan);
}

#[test]
fn repeats_prediction_matches_200_runs() {
    let plan = verified(&config("repeats.toml"));
    assert_eq!((names(&plan), plan.test.records), (ALL.to_vec(), 5));
    assert_verified(&plan);
}

#[test]
fn test_machine_prediction_matches_200_runs() {
    let plan = verified(&config("damper-test-machine.toml"));
    assert_eq!(
        names(&plan),
        [
            "mass",
            "damping",
            "stiffness",
            "quadratic_damping",
            "force_offset"
        ]
    );
    assert_verified(&plan);
}

/// Without the weighed mass, base excitation identifies ωn and ζ only: the plan says so
/// in the run's words, plans those two, and its check fits them alone.
#[test]
fn base_excitation_without_the_mass_plans_fn_and_zeta_only() {
    let dir = tempfile::tempdir().unwrap();
    let path = edited(
        "base-excitation.toml",
        "known_mass = 2.5",
        "# known_mass = 2.5",
        dir.path(),
    );
    let plan = verified(&path);
    assert_eq!(names(&plan), ["natural_frequency_hz", "damping_ratio"]);
    let text = plan.to_string();
    assert!(
        text.contains("m, c and k are not separately identifiable from a base acceleration")
            && text.contains("ωn and ζ are identified"),
        "{text}"
    );
    assert_verified(&plan);
}

/// Short of a tight target, each setup says what reaches it: the drive's amplitude,
/// a longer record, more records; the amplitude factor is the width over the target.
#[test]
fn what_reaches_the_target_follows_the_setup() {
    let options = PlanOptions {
        target: 1e-4,
        verify: 0,
        ..PlanOptions::default()
    };
    for (name, drive) in [
        ("free-decay.toml", "release from"),
        ("base-excitation.toml", "raise the base acceleration"),
        ("repeats.toml", "raise the force"),
    ] {
        let plan = plan(&config(name), &options).unwrap();
        let text = plan.to_string();
        let zeta = plan.quantity("damping_ratio").unwrap();
        assert!(
            text.contains("damping_ratio to ±0.01 %") && text.contains(drive),
            "{text}"
        );
        let factor = zeta.amplitude_factor.unwrap();
        assert!((factor - zeta.relative_half_width / 1e-4).abs() < 1e-12);
        // 1/√records: the records needed give the target.
        let records = zeta.repeats_needed.unwrap() as f64;
        let planned = plan.test.records as f64;
        let reached = zeta.relative_half_width * (planned / records).sqrt();
        assert!(
            reached <= 1e-4 && reached > 1e-4 * (1.0 - 1.0 / records),
            "{reached}"
        );
        assert!(text.contains("records (now"), "{text}");
    }
}

#[test]
fn bad_plans_are_refused_by_config_and_key() {
    let one = PlanOptions {
        verify: 1,
        ..PlanOptions::default()
    };
    let err = plan(&config("free-decay.toml"), &one).unwrap_err();
    assert_eq!(err.exit_code(), 2);
    let text = err.to_string();
    assert!(
        text.contains("free-decay.toml") && text.contains("--verify = 1"),
        "{text}"
    );
    // A measured template: no prior plant to plan from.
    let template = config("templates/free-decay.toml");
    let err = plan(&template, &PlanOptions::default()).unwrap_err();
    let text = err.to_string();
    assert_eq!(err.exit_code(), 2, "{text}");
    assert!(
        text.contains("templates/free-decay.toml") && text.contains("plant: missing"),
        "{text}"
    );
    // A noise-free channel: the Cramér–Rao bound is zero.
    let dir = tempfile::tempdir().unwrap();
    let path = edited(
        "accelerometer.toml",
        "sigma = 0.05 }",
        "sigma = 0.0 }",
        dir.path(),
    );
    let err = plan(&path, &PlanOptions::default()).unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("accelerometer.toml") && text.contains("setup.responses[1].sigma = 0"),
        "{text}"
    );
    let path = edited(
        "damper-test-machine.toml",
        "sigma = 2.0 }",
        "sigma = 0.0 }",
        dir.path(),
    );
    let text = plan(&path, &PlanOptions::default())
        .unwrap_err()
        .to_string();
    assert!(text.contains("setup.responses[0].sigma = 0"), "{text}");
}
