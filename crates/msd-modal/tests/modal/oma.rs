//! Output-only analysis (SSI-cov/ref) of a simulated five-storey shear building — pyOMA2's
//! example: 25.91 kg floors on 10 kN/m storeys, ζ = 2 % in every mode, white-noise forces,
//! accelerations at 100 Hz with 10 % noise, 30,001 samples — at default settings, and bad
//! records refused by name.

use crate::building::{building, record};
use msd_modal::{
    FddOptions, ModalError, OmaFit, OmaOptions, OutputRecord, efdd, mac, ssi_cov, ssi_dat,
};
use msd_signal::Complex64;

#[test]
fn every_mode_of_the_building_is_found_at_defaults_within_half_a_percent() {
    every_mode_found(ssi_cov);
}

#[test]
fn data_driven_ssi_finds_every_mode_of_the_building_at_defaults() {
    every_mode_found(ssi_dat);
}

/// `method` at defaults on the building: all five modes, fn within 0.5 % and four
/// standard errors, ζ within four, shapes MAC > 0.99, every selected pole marked.
fn every_mode_found(method: fn(&OutputRecord, &OmaOptions) -> Result<OmaFit, ModalError>) {
    let truth = building().modes().expect("valid");
    let fit = method(&record(1), &OmaOptions::default()).expect("fits");
    assert_eq!(fit.modes.len(), 5, "{fit}");
    for (mode, (f, shape)) in fit.modes.iter().zip(&truth) {
        let fn_hz = &mode.natural_frequency_hz;
        // The criterion, and the estimate within four standard errors (t with 7
        // degrees of freedom: p ≈ 0.005 for each of the ten).
        assert!((fn_hz.value / f - 1.0).abs() < 0.005, "{fn_hz} against {f}");
        assert!(
            (fn_hz.value - f).abs() < 4.0 * fn_hz.standard_error,
            "{fn_hz} against {f}"
        );
        let zeta = &mode.damping_ratio;
        assert!(
            (zeta.value - 0.02).abs() < 4.0 * zeta.standard_error,
            "{zeta}"
        );
        let truth: Vec<Complex64> = shape.iter().map(|&v| Complex64::new(v, 0.0)).collect();
        assert!(mac(&mode.shape_values(), &truth) > 0.99, "{mode}");
        assert!(mode.shape.iter().all(|e| e.standard_error.is_some()));
    }
    // Every selected pole is marked with its mode in the diagram.
    let marked = fit
        .diagram
        .orders
        .iter()
        .flat_map(|o| &o.poles)
        .filter(|p| p.mode.is_some())
        .count();
    let members: usize = fit.modes.iter().filter_map(|m| m.stable_orders).sum();
    assert_eq!(marked, members);
}

/// Coverage of the 95 % intervals of fn and ζ over 24 records (240 intervals): within
/// three binomial standard errors of 0.95 (0.91–0.99; the records' ten intervals are
/// nearly independent: the modes are well apart).
#[test]
fn the_intervals_cover_the_truth_about_95_percent_of_the_time() {
    coverage(ssi_cov);
}

/// As SSI-cov's (200 seeds by `cargo xtask oma-study --method ssi-dat`: 0.940–0.980).
#[test]
fn data_driven_intervals_cover_the_truth_about_95_percent_of_the_time() {
    coverage(ssi_dat);
}

fn coverage(method: fn(&OutputRecord, &OmaOptions) -> Result<OmaFit, ModalError>) {
    let truth = building().modes().expect("valid");
    let (mut inside, mut total) = (0, 0);
    for seed in 100..124 {
        let fit = method(&record(seed), &OmaOptions::default()).expect("fits");
        for (f, _) in &truth {
            let Some(mode) = fit
                .modes
                .iter()
                .find(|m| (m.natural_frequency_hz.value / f - 1.0).abs() < 0.02)
            else {
                total += 2;
                continue;
            };
            inside += usize::from(mode.natural_frequency_hz.contains(*f));
            inside += usize::from(mode.damping_ratio.contains(0.02));
            total += 2;
        }
    }
    let coverage = inside as f64 / total as f64;
    let se = (0.95 * 0.05 / total as f64).sqrt();
    assert!(
        (coverage - 0.95).abs() < 3.0 * se,
        "coverage {coverage} of {total}"
    );
}

#[test]
fn bad_records_are_refused_by_name() {
    let good = record(2);
    let mut nan = good.clone();
    nan.recording.channels[2].samples[17] = f64::NAN;
    let err = ssi_cov(&nan, &OmaOptions::default()).unwrap_err();
    assert!(
        matches!(&err, ModalError::BadChannel { channel, .. } if channel == "a3"),
        "{err}"
    );
    assert!(err.to_string().contains("sample 17 is NaN"), "{err}");

    let mut dead = good.clone();
    dead.recording.channels[4]
        .samples
        .iter_mut()
        .for_each(|v| *v = 0.25);
    let err = ssi_cov(&dead, &OmaOptions::default()).unwrap_err();
    assert!(
        err.to_string().contains("channel a5") && err.to_string().contains("constant"),
        "{err}"
    );

    // What a recording may hold that an output-only analysis cannot read: a force, a
    // channel at no DOF, a measured input.
    let mut force = good.clone();
    force.recording.channels[1].quantity = msd_modal::Quantity::Force;
    let err = ssi_cov(&force, &OmaOptions::default()).unwrap_err();
    assert!(
        err.to_string().contains("channel a2") && err.to_string().contains("force"),
        "{err}"
    );
    let mut nowhere = good.clone();
    nowhere.recording.channels[0].dof = None;
    let err = efdd(&nowhere, &FddOptions::default()).unwrap_err();
    assert!(
        err.to_string().contains("channel a1") && err.to_string().contains("no DOF"),
        "{err}"
    );
    let mut driven = good.clone();
    let hammer =
        msd_modal::Channel::new("hammer", msd_modal::Quantity::Force, vec![0.0; good.len()]);
    driven.recording.inputs.push(hammer);
    let err = ssi_cov(&driven, &OmaOptions::default()).unwrap_err();
    assert!(
        err.to_string().contains("channel hammer") && err.to_string().contains("measured input"),
        "{err}"
    );

    let mut one = good.clone();
    one.recording.channels.truncate(1);
    let err = ssi_cov(&one, &OmaOptions::default()).unwrap_err();
    assert!(err.to_string().contains("channels"), "{err}");

    let bad_ref = OutputRecord {
        references: vec![0, 7],
        ..good.clone()
    };
    let err = ssi_cov(&bad_ref, &OmaOptions::default()).unwrap_err();
    assert!(
        matches!(err, ModalError::InvalidParameter { name: "references", value, .. } if value == 7.0)
    );

    let mut short = good.clone();
    short.recording.channels[1].samples.pop();
    let err = ssi_cov(&short, &OmaOptions::default()).unwrap_err();
    assert!(
        matches!(
            err,
            ModalError::LengthMismatch {
                got: 30_000,
                expected: 30_001,
                ..
            }
        ),
        "{err}"
    );

    let above = OmaOptions {
        band_hz: Some([60.0, 80.0]),
        ..OmaOptions::default()
    };
    let err = ssi_cov(&good, &above).unwrap_err();
    assert!(
        matches!(
            err,
            ModalError::InvalidParameter {
                name: "band_hz[0]",
                ..
            }
        ),
        "{err}"
    );

    let too_high = OmaOptions {
        block_rows: Some(10),
        orders: [2, 60],
        ..OmaOptions::default()
    };
    let err = ssi_cov(
        &OutputRecord {
            references: vec![0, 1],
            ..good.clone()
        },
        &too_high,
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            ModalError::InvalidParameter {
                name: "orders[1]",
                ..
            }
        ),
        "{err}"
    );

    let tiny = OmaOptions {
        block_rows: Some(2000),
        orders: [2, 20],
        ..OmaOptions::default()
    };
    let err = ssi_cov(&good, &tiny).unwrap_err();
    assert!(matches!(err, ModalError::TooFewSamples { .. }), "{err}");
}

#[test]
fn the_numbers_do_not_depend_on_the_thread_count() {
    let record = record(3);
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a pool")
            .install(|| ssi_cov(&record, &OmaOptions::default()).expect("fits"))
    };
    assert_eq!(on(1), on(2));
}

/// Two setups of the building: floors 1, 2 and 5, then floors 3, 4 and 5 (floor 5 the
/// reference, measured in both), each its own record; merged, every mode's shape over the
/// five floors as close to the truth as its standard errors allow, and fn within 0.5 %.
#[test]
fn two_setups_with_a_shared_reference_merge_into_the_whole_shape() {
    let truth = building().modes().expect("valid");
    let pick = |seed: u64, floors: [usize; 3]| {
        let mut full = record(seed);
        full.recording.channels = floors
            .iter()
            .map(|&f| full.recording.channels[f].clone())
            .collect();
        full.with_references(vec![2])
    };
    let records = [pick(11, [0, 1, 4]), pick(12, [2, 3, 4])];
    let fits: Vec<_> = records
        .iter()
        .map(|r| ssi_cov(r, &OmaOptions::default()).expect("fits"))
        .collect();
    let setups: Vec<msd_modal::Setup<'_>> = records
        .iter()
        .zip(&fits)
        .map(|(record, fit)| msd_modal::Setup { record, fit })
        .collect();
    let merged = msd_modal::merge_setups(&setups, 0.01).expect("merges");
    assert_eq!(
        merged.reference_dofs,
        [msd_modal::Dof {
            node: 5,
            direction: 1
        }]
    );
    for (f, shape) in &truth {
        let mode = merged
            .modes
            .iter()
            .find(|m| (m.natural_frequency_hz.value / f - 1.0).abs() < 0.005)
            .unwrap_or_else(|| panic!("{f} Hz not merged"));
        let mut by_floor = mode.shape.clone();
        by_floor.sort_by_key(|e| e.node);
        assert_eq!(by_floor.len(), 5, "{mode}");
        let true_shape: Vec<Complex64> = shape.iter().map(|&v| Complex64::new(v, 0.0)).collect();
        let values: Vec<Complex64> = by_floor.iter().map(|e| e.value()).collect();
        // The MAC's deficit from noise: each entry off by up to 3 of its standard errors,
        // and the second setup's half scaled through the reference entry, off by 3 of its
        // relative standard errors δ (a half scaled by 1 + 3δ loses (3δ)²/4).
        let energy: f64 = values.iter().map(|v| v.norm_sqr()).sum();
        let noise: f64 = by_floor
            .iter()
            .filter_map(|e| e.standard_error)
            .map(|[a, b]| 9.0 * (a * a + b * b))
            .sum();
        let reference = by_floor
            .iter()
            .find(|e| e.node == 5)
            .expect("the reference");
        let delta = reference
            .standard_error
            .map_or(0.0, |[a, _]| a / reference.value().norm());
        let bound = noise / energy + (3.0 * delta).powi(2) / 4.0;
        assert!(
            1.0 - mac(&values, &true_shape) < bound,
            "{f} Hz: 1 − MAC = {} ≥ {bound}: {mode}",
            1.0 - mac(&values, &true_shape)
        );
    }
}
