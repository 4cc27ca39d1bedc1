//! Validation on fresh data for the joint fit: a single record's held-out end, each of
//! several records by the others, records given for validation; each prediction's
//! residuals tested, and a model the data contradict caught on data it was not fitted to.

use msd_ident::records::{simulate_response, validate_records};
use msd_ident::{
    Channel, Drive, Excitation, Frame, InitialState, Parameters, Quantity, Record, RecordsOptions,
    ResponseQuantity, fit_records,
};
use msd_signal::{gaussian_noise, paper_identification_input, paper_validation_input};

/// The paper's plant driven by `signal` (15 s at 2 ms), a laser with σ = 0.1 mm whose
/// samples lag the force by `delay` samples.
fn record(name: &str, signal: msd_signal::Signal, seed: u64, delay: usize) -> Record {
    let force = Excitation::from_signal(signal, 0.0, 0.002, 7501).expect("valid");
    let x = simulate_response(
        &Parameters::PAPER,
        Drive::Force,
        &force,
        InitialState::REST,
        ResponseQuantity::Displacement,
        Frame::Absolute,
    )
    .expect("simulated");
    let noise = gaussian_noise(seed, name, 1e-4, x.len()).expect("noise");
    let samples = (0..x.len())
        .map(|i| i.checked_sub(delay).map_or(0.0, |j| x[j]) + noise[i])
        .collect();
    Record {
        name: name.into(),
        excitation: force,
        channels: vec![Channel::new("laser", Quantity::Displacement, samples)],
    }
}

/// One record: its last fifth predicted by the plant fitted to the rest, as well as the
/// whole record's fit predicts it, with residuals that pass the paper's tests.
#[test]
fn a_single_record_is_validated_on_its_held_out_end() {
    let fit = fit_records(
        &[record("run", paper_identification_input(), 1, 0)],
        &RecordsOptions::default(),
    )
    .expect("fitted");
    let v = fit.validation.as_ref().expect("held out by default");
    assert!(v.source.contains("last 20 %"), "{}", v.source);
    let p = &v.predictions[0];
    assert_eq!(p.channels[0].model.len(), 1500);
    // The noise is white at σ = 0.1 mm: the prediction's RMS error is σ to within the
    // estimate's own wobble (the refit's error adds O(p/N) of σ²).
    let rms = p.channels[0].fit.residual_rms;
    assert!((rms / 1e-4 - 1.0).abs() < 0.1, "rms {rms:.3e}");
    let tests = p.residual_analysis[0].as_ref().expect("long enough");
    assert!(
        tests.whiteness_passed && tests.cross_correlation_passed,
        "{tests}"
    );
    // fn of the refit within 4 SE of the full fit's (a fifth fewer samples).
    let full = fit.plant.natural_frequency_hz;
    assert!((p.natural_frequency_hz - full.value).abs() < 4.0 * full.standard_error);
    assert!(
        fit.to_string().contains("validation on the last 20 %"),
        "{fit}"
    );
}

/// A sensor that lags by 20 ms: the one-mass model cannot follow it, and its residuals
/// on the held-out end correlate with the force: the fit says so in a note.
#[test]
fn a_delayed_sensor_fails_the_cross_correlation_test_on_fresh_data() {
    let fit = fit_records(
        &[record("run", paper_identification_input(), 2, 10)],
        &RecordsOptions::default(),
    )
    .expect("fitted");
    let p = &fit.validation.as_ref().expect("held out").predictions[0];
    let tests = p.residual_analysis[0].as_ref().expect("long enough");
    assert!(!tests.cross_correlation_passed, "{tests}");
    assert!(
        fit.notes
            .iter()
            .any(|n| n.contains("validation") && n.contains("correlates with the drive")),
        "{:?}",
        fit.notes
    );
    // The fitted record's own check says it too.
    assert!(
        fit.whiteness[0]
            .input_correlation
            .as_ref()
            .is_some_and(|t| !t.passed)
    );
}

/// Several records: the leave-one-out predictions carry the residual tests, and no
/// held-out end is taken; `hold_out = 0` turns the single record's check off.
#[test]
fn repeats_are_validated_on_each_other_and_hold_out_can_be_off() {
    let runs = [
        record("a", paper_identification_input(), 3, 0),
        record("b", paper_identification_input(), 4, 0),
    ];
    let fit = fit_records(&runs, &RecordsOptions::default()).expect("fitted");
    assert!(fit.validation.is_none());
    let loo = fit.leave_one_out.as_ref().expect("two records");
    assert!(loo.iter().all(|l| l.residual_analysis[0].is_some()));
    let off = RecordsOptions {
        hold_out: 0.0,
        ..RecordsOptions::default()
    };
    let one = fit_records(&runs[..1], &off).expect("fitted");
    assert!(one.validation.is_none());
    let bad = RecordsOptions {
        hold_out: 0.7,
        ..RecordsOptions::default()
    };
    let e = fit_records(&runs[..1], &bad).expect_err("refused");
    assert!(e.to_string().contains("hold_out"), "{e}");
}

/// Records given for validation: the chirp the paper validates on, predicted by the
/// plant of the step-and-sines fit, R² as the paper's validation reports it.
#[test]
fn records_given_for_validation_are_predicted_by_the_fitted_plant() {
    let options = RecordsOptions::default();
    let fit = fit_records(
        &[record("id", paper_identification_input(), 5, 0)],
        &options,
    )
    .expect("fitted");
    let fresh = validate_records(
        &fit,
        &[record("chirp", paper_validation_input(), 6, 0)],
        &options,
    )
    .expect("validated");
    assert!(fresh.source.contains("`chirp`"), "{}", fresh.source);
    let c = &fresh.predictions[0].channels[0];
    assert!(c.fit.r_squared > 0.99, "{}", c.fit);
    assert!((c.fit.residual_rms / 1e-4 - 1.0).abs() < 0.1, "{}", c.fit);
    // A record the plant cannot take is refused by name.
    let mut wrong = record("short", paper_validation_input(), 7, 0);
    wrong.channels[0].samples.truncate(100);
    let e = validate_records(&fit, &[wrong], &options).expect_err("refused");
    assert!(e.to_string().contains("short"), "{e}");
}

/// A fit that takes its records to start at rest still predicts a held-out end from
/// that end's own initial state (it starts mid-motion).
#[test]
fn a_held_out_end_gets_its_own_initial_state() {
    let options = RecordsOptions {
        estimate_initial_state: false,
        estimate_offset: false,
        ..RecordsOptions::default()
    };
    let fit = fit_records(
        &[record("run", paper_identification_input(), 8, 0)],
        &options,
    )
    .expect("fitted");
    let p = &fit.validation.as_ref().expect("held out").predictions[0];
    let rms = p.channels[0].fit.residual_rms;
    assert!((rms / 1e-4 - 1.0).abs() < 0.1, "rms {rms:.3e}");
}

/// A chain's held-out end: predicted to the noise by the chain fitted to the rest; a
/// sensor that lags by 20 ms, fitted as if it did not, fails the cross-correlation test
/// there.
#[test]
fn a_chain_is_checked_on_its_held_out_end() {
    use msd_ident::chain::{
        ChainOptions, ChainParameters, ChainSensor, ChainSetup, hold_out_chain, simulate_chain,
    };
    let p = ChainParameters {
        masses: vec![2.5],
        dampers: vec![1.8],
        springs: vec![120.0],
        ..ChainParameters::default()
    };
    let input = paper_identification_input().sample(0.0, 0.002, 7501);
    let lagging = ChainSetup {
        sensors: vec![ChainSensor {
            delay: Some(0.02),
            ..ChainSensor::default()
        }],
        ..ChainSetup::default()
    };
    let record = |setup: &ChainSetup| {
        let clean = simulate_chain(setup, &p, &input, 0.002).expect("simulated");
        let noise = gaussian_noise(9, "chain", 1e-4, input.len()).expect("noise");
        let y = clean[0].iter().zip(&noise).map(|(y, n)| y + n).collect();
        ChainSetup::default().recording("test", 0.002, input.clone(), vec![y])
    };
    let plain = ChainSetup::default();
    let options = ChainOptions::default();
    let good = hold_out_chain(&plain, &record(&plain), &p, &options, 0.2).expect("fits");
    let tests = good.sensors[0]
        .residual_analysis
        .as_ref()
        .expect("long enough");
    assert!(tests.cross_correlation_passed, "{tests}");
    assert!((good.sensors[0].fit.residual_rms / 1e-4 - 1.0).abs() < 0.1);
    let bad = hold_out_chain(&plain, &record(&lagging), &p, &options, 0.2).expect("fits");
    let tests = bad.sensors[0]
        .residual_analysis
        .as_ref()
        .expect("long enough");
    assert!(!tests.cross_correlation_passed, "{tests}");
    assert!(hold_out_chain(&plain, &record(&plain), &p, &options, 0.9).is_err());
}

/// A free decay recorded until it has rung down: its held-out end is noise, its R² near
/// 0, and the prediction's error is the noise's — no note that the plant fails there.
#[test]
fn the_quiet_end_of_a_free_decay_is_not_a_failed_prediction() {
    let grid = Excitation::from_samples(0.0, 0.005, vec![0.0; 12_001]).expect("valid");
    let start = InitialState {
        displacement: 0.01,
        velocity: 0.0,
    };
    let x = simulate_response(
        &Parameters::PAPER,
        Drive::None,
        &grid,
        start,
        ResponseQuantity::Displacement,
        Frame::Absolute,
    )
    .expect("simulated");
    let noise = gaussian_noise(4, "laser", 1e-5, x.len()).expect("noise");
    let record = Record {
        name: "pluck".into(),
        excitation: grid,
        channels: vec![Channel::new(
            "laser",
            Quantity::Displacement,
            x.iter().zip(&noise).map(|(x, n)| x + n).collect(),
        )],
    };
    let options = RecordsOptions {
        drive: Drive::None,
        known: msd_ident::KnownParameter::Mass(2.5),
        ..RecordsOptions::default()
    };
    let fit = fit_records(&[record], &options).expect("fitted");
    let c = &fit.validation.as_ref().expect("held out").predictions[0].channels[0];
    // 48–60 s: the decay is e^(−ζωn·48 s) ≈ 5e-8 of 1 cm, far below the 10 µm noise.
    assert!(c.fit.r_squared < 0.5, "{}", c.fit);
    assert!((c.fit.residual_rms / 1e-5 - 1.0).abs() < 0.1, "{}", c.fit);
    assert!(
        !fit.notes.iter().any(|n| n.contains("does not predict")),
        "{:?}",
        fit.notes
    );
}
