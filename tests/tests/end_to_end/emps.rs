//! The EMPS benchmark (a real positioning axis: mass, viscous and Coulomb friction, an
//! offset; `cargo xtask fetch-data emps`) through the test machine for any stroke, at
//! default settings: within 3 % of the benchmark's reference model, and the validation
//! record's force predicted as well as the reference model predicts it.

use msd_ident::dynamometer::{InverseOptions, StrokeRecord, inverse_dynamics};
use msd_ident::law::DampingLaw;
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
fn record(path: &Path) -> StrokeRecord {
    let c = msd_files::read(path).unwrap();
    let values = |name: &str| c.channel(name).unwrap().values.clone();
    let gain = values("gtau")[0];
    let t = values("t");
    StrokeRecord {
        name: path.file_name().unwrap().to_string_lossy().into(),
        dt: (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64,
        stroke: values("qm"),
        force: values("vir").iter().map(|v| gain * v).collect(),
    }
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
