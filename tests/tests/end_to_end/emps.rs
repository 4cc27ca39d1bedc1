//! The EMPS benchmark (a real positioning axis: mass, viscous and Coulomb friction, an
//! offset; `cargo xtask fetch-data emps`) through the test machine for any stroke, at
//! default settings: within 3 % of the benchmark's reference model, and the validation
//! record's force predicted as well as the reference model predicts it.

use msd_ident::dynamometer::{InverseOptions, inverse_dynamics, machine_recording};
use msd_ident::law::DampingLaw;
use msd_signal::Recording;
use msd_tests::real_data;
use std::path::Path;

/// The benchmark's reference model (IDIM-LS): M, Fv, Fc, offset.
const REFERENCE: [(&str, f64); 4] = [
    ("mass", 95.1089),
    ("damping", 203.5034),
    ("coulomb_force", 20.3935),
    ("force_offset", -3.1648),
];

/// A record of the set: the measured position and the force gtau·vir.
fn record(path: &Path) -> Recording {
    let c = msd_files::read(path).unwrap();
    let values = |name: &str| c.channel(name).unwrap().values.clone();
    let gain = values("gtau")[0];
    let t = values("t");
    let name = path.file_name().unwrap().to_string_lossy();
    let dt = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    let force = values("vir").iter().map(|v| gain * v).collect();
    machine_recording(name, dt, values("qm"), force)
}

#[test]
fn emps_at_default_settings_is_within_three_percent_of_the_reference() {
    let Some(dir) = real_data("emps", "emps_at_default_settings") else {
        return;
    };
    let estimation = record(&dir.join("DATA_EMPS.mat"));
    let fit = inverse_dynamics(&[estimation], &InverseOptions::default()).unwrap();
    let best = &fit.laws[fit.best];
    assert_eq!(best.law, DampingLaw::CoulombViscous, "{fit}");
    for (name, reference) in REFERENCE {
        let value = best.value(name).unwrap();
        assert!(
            (value / reference - 1.0).abs() < 0.03,
            "{name} = {value} against the reference {reference}\n{fit}"
        );
    }
    eprintln!("{fit}");
    // Validation: the pulses record's force from its stroke, by this fit and by the
    // reference model under the same filter.
    let validation = record(&dir.join("DATA_EMPS_PULSES.mat"));
    let ours = fit.predict(fit.best, &validation).unwrap();
    let mut reference = fit.clone();
    for c in &mut reference.laws[reference.best].coefficients {
        let value = REFERENCE.iter().find(|(n, _)| *n == c.name).unwrap().1;
        c.estimate.value = value;
    }
    let theirs = reference.predict(reference.best, &validation).unwrap();
    eprintln!(
        "EMPS validation: RMS force error {:.3} N (reference model {:.3} N), RMS force {:.2} N",
        ours.rms_error, theirs.rms_error, ours.rms_force
    );
    assert!(ours.rms_error <= 1.05 * theirs.rms_error);
}

/// A positioning move written as a lab's CSV (stroke in mm, force in N): a `[setup]` with
/// `excitation = "imposed_displacement"` and nothing else finds it is not a sine stroke,
/// fits it by inverse dynamics and predicts the validation file's force.
#[test]
fn a_stroke_that_is_not_a_sine_is_found_and_fitted_by_inverse_dynamics() {
    let dir = tempfile::tempdir().unwrap();
    // Two tones (0.7 and 3.1 Hz): the acceleration is 38 % in the fundamental.
    let write = |name: &str, phase: f64| {
        let mut text = String::from("t,stroke_mm,force\n");
        for i in 0..20_000 {
            let t = i as f64 * 1e-3;
            let (w1, w2) = (
                2.0 * std::f64::consts::PI * 0.7,
                2.0 * std::f64::consts::PI * 3.1,
            );
            let x = 0.05 * (w1 * t).sin() + 0.01 * (w2 * t + phase).sin();
            let v = 0.05 * w1 * (w1 * t).cos() + 0.01 * w2 * (w2 * t + phase).cos();
            let a = -0.05 * w1 * w1 * (w1 * t).sin() - 0.01 * w2 * w2 * (w2 * t + phase).sin();
            let f = 20.0 * a + 150.0 * v + 12.0 * v.signum() - 2.0;
            text.push_str(&format!("{t:.3},{:.9},{f:.9}\n", 1e3 * x));
        }
        std::fs::write(dir.path().join(name), text).unwrap();
    };
    write("move.csv", 0.0);
    write("check.csv", 1.0);
    let config = dir.path().join("machine.toml");
    std::fs::write(
        &config,
        "name = \"machine\"\n[setup]\nexcitation = \"imposed_displacement\"\nresponses = [{ quantity = \"force\", column = \"force\" }]\n[data]\npath = \"move.csv\"\nvalidation_path = \"check.csv\"\ntime = \"t\"\ninput = \"stroke_mm\"\ninput_scale = 0.001\n",
    )
    .unwrap();
    let run = msd_tests::run_in_temp(&config, None, None).unwrap();
    for (name, truth) in [
        ("mass", 20.0),
        ("damping", 150.0),
        ("coulomb_force", 12.0),
        ("force_offset", -2.0),
    ] {
        let value = run.number(&format!("estimate.{name}.value"));
        assert!(
            (value / truth - 1.0).abs() < 2e-3,
            "{name} = {value}, truth {truth}"
        );
    }
    let predictions = &run.summary.results["any_stroke"]["predictions"];
    assert_eq!(predictions[1]["validation"], true);
    // Noise-free records: what is left is the same on both, the force's steps at each
    // reversal through the filter against the Coulomb term of the filtered velocity.
    let error = |k: usize| {
        predictions[k]["rms_error"].as_f64().unwrap()
            / predictions[k]["rms_force"].as_f64().unwrap()
    };
    eprintln!(
        "force error: fitted {:.4}, validation {:.4}",
        error(0),
        error(1)
    );
    assert!(
        error(1) < 1.5 * error(0) && error(1) < 0.03,
        "{} against {}",
        error(1),
        error(0)
    );
}
