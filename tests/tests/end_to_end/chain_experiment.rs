//! The chain configs (issue 33): every parameter of the two-storey rig and the tuned
//! mass damper within 4 standard errors of the truth; the delayed sensor fitted with its
//! delay, and the bias of ignoring it measured; bad chains refused naming the key.

use msd_tests::{config, run_in_temp};
use serde_json::Value;

/// Every estimate of `results.json` against the config's truth, in standard errors.
fn worst_z(results: &Value) -> f64 {
    let truth = &results["chain"]["plant"];
    let intervals = &results["fit"]["intervals"];
    let mut worst = 0.0f64;
    for family in ["masses", "dampers", "springs"] {
        let t = truth[family].as_array().expect("the truth");
        let e = intervals[family].as_array().expect("identified");
        for (t, e) in t.iter().zip(e) {
            let se = e["standard_error"].as_f64().unwrap();
            if se > 0.0 {
                let z = (e["value"].as_f64().unwrap() - t.as_f64().unwrap()).abs() / se;
                worst = worst.max(z);
            }
        }
    }
    worst
}

#[test]
fn the_two_storey_rig_and_the_tuned_mass_damper_are_identified() {
    for name in ["two-storey.toml", "tuned-mass-damper.toml"] {
        for seed in [1, 2, 3] {
            let run = run_in_temp(&config(name), Some(seed), None).expect("runs");
            let z = worst_z(&run.summary.results);
            // 4 SE: a miss has probability 6e-5 per parameter.
            assert!(z < 4.0, "{name} seed {seed}: {z}");
            assert!(run.out().join("chain_fit.png").exists());
            for ext in ["png", "svg"] {
                assert!(
                    run.out()
                        .join(format!("chain_noise_spectrum.{ext}"))
                        .exists()
                );
            }
            assert!(run.out().join("record.csv").exists());
            let report = std::fs::read_to_string(run.out().join("report.md")).unwrap();
            assert!(report.contains("## Modes"));
            // The ±10 % band holds most of each measured record (the noise is small
            // beside the spread of ±10 % in every parameter).
            let coverage = run.summary.results["monte_carlo"]["coverage"]
                .as_array()
                .unwrap()
                .clone();
            assert!(
                coverage.iter().all(|c| c.as_f64().unwrap() > 0.5),
                "{coverage:?}"
            );
        }
    }
}

/// Issue 46 §2: delays asked of both two-storey accelerometers, whose true delay is 0
/// (on the bound): the fit stalled at its guess (m, c, k exactly 2.5, 2.0, 10000, … with
/// intervals 9–14 SE from the truth, exit 0). Now within 4 SE, each delay's interval
/// holding 0.
#[test]
fn delays_asked_of_sensors_without_one_do_not_stall_the_fit() {
    let shipped = std::fs::read_to_string(config("two-storey.toml")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("two-storey-delays.toml");
    let text = shipped.replace("sigma = 0.02 }", "sigma = 0.02, estimate_delay = true }");
    assert_eq!(text.matches("estimate_delay = true").count(), 2);
    std::fs::write(&path, text).unwrap();
    let run = run_in_temp(&path, None, None).expect("runs");
    let z = worst_z(&run.summary.results);
    assert!(z < 4.0, "{z}");
    let delays = run.summary.results["fit"]["delays"]
        .as_array()
        .expect("delays")
        .clone();
    for d in delays.iter().filter(|d| !d.is_null()) {
        let [low, high] = [0, 1].map(|i| d["ci95"][i].as_f64().unwrap());
        assert!(low <= 0.0 && 0.0 <= high, "{d}");
    }
}

/// A shipped config changed by `edits` (each `(from, to)` must match), run.
fn run_edited(name: &str, edits: &[(&str, &str)]) -> msd_tests::Run {
    let mut text = std::fs::read_to_string(config(name)).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{from}");
        text = text.replacen(from, to, 1);
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    run_in_temp(&path, None, None).expect("runs")
}

/// The modes of `results.json` each within 4 SE of the modes of `plant`.
fn modes_within_4_se(results: &Value, plant: &msd_ident::chain::ChainParameters) {
    let truth: Vec<f64> = (plant.modes().iter())
        .map(|m| m.natural_frequency_hz.value)
        .collect();
    let modes = results["fit"]["modes"].as_array().expect("modes");
    assert_eq!(modes.len(), truth.len());
    for (mode, want) in modes.iter().zip(&truth) {
        let f = &mode["natural_frequency_hz"];
        let (v, se) = (
            f["value"].as_f64().unwrap(),
            f["standard_error"].as_f64().unwrap(),
        );
        assert!((v - want).abs() < 4.0 * se, "{v} ± {se} against {want}");
    }
}

/// Issue 46 §3: layouts that cannot separate every parameter (the tuned mass damper
/// with no weighed mass; a ground spring beside spring 1) ran a parameter to 3e299 and
/// exited 1 "the fit fell into a wrong minimum". Now: exit 0, no m, c, k intervals, the
/// lost combination in words in the summary and results.json, the modes within 4 SE.
#[test]
fn layouts_that_lose_a_combination_say_which_and_report_the_modes() {
    let tmd = run_edited(
        "tuned-mass-damper.toml",
        &[("known_masses = [2]", "known_masses = []")],
    );
    let r = &tmd.summary.results;
    assert!(r["fit"]["intervals"].is_null());
    let lost = r["fit"]["unidentifiable"][0].as_str().unwrap();
    assert!(lost.contains("scaled by one factor"), "{lost}");
    assert!(
        tmd.summary
            .summary
            .contains("verdict        use with care: not everything is identified")
    );
    // The modes of the truth, damped as fitted (fn = |λ|/2π of the damped system).
    let plant = msd_ident::chain::ChainParameters {
        masses: vec![10.0, 0.5],
        dampers: vec![20.0, 7.6],
        springs: vec![40000.0, 1789.0],
        ..Default::default()
    };
    modes_within_4_se(r, &plant);

    let side = run_edited(
        "two-storey.toml",
        &[
            (
                "springs = [8000.0, 6000.0] }",
                "springs = [8000.0, 6000.0], ground_springs = [500.0, 0.0] }",
            ),
            (
                "springs = [10000.0, 5000.0] }",
                "springs = [10000.0, 5000.0], ground_springs = [600.0, 0.0] }",
            ),
        ],
    );
    let r = &side.summary.results;
    assert!(r["fit"]["intervals"].is_null());
    assert!(
        r["fit"]["unidentifiable"][0]
            .as_str()
            .unwrap()
            .contains("k1 + kg1")
    );
    let plant = msd_ident::chain::ChainParameters {
        masses: vec![2.0, 1.5],
        dampers: vec![3.0, 2.0],
        springs: vec![8000.0, 6000.0],
        ground_springs: vec![500.0, 0.0],
        ..Default::default()
    };
    modes_within_4_se(r, &plant);
}

/// Issue 46 §3: a ground spring estimated that the plant does not have ran to 1.5e-4
/// N/m and exited 1. Now it is dropped (or its interval reaches zero) and said; the rest
/// within 4 SE of the truth.
#[test]
fn a_ground_spring_the_plant_does_not_have_is_said_not_to_be_there() {
    let run = run_edited(
        "two-storey.toml",
        &[(
            "springs = [10000.0, 5000.0] }",
            "springs = [10000.0, 5000.0], ground_springs = [0.0, 600.0] }",
        )],
    );
    assert!(worst_z(&run.summary.results) < 4.0);
    let said = run
        .summary
        .summary
        .contains("the records show no spring from mass 2")
        || run.summary.summary.contains("kg2") && run.summary.summary.contains("reaches zero");
    assert!(said, "{}", run.summary.summary);
}

/// Issue 46 §2: a cut-off estimated beside the delay (configs/delayed-sensor.toml, a
/// 50 Hz first-order filter and 6 ms) ran to 3.6e9 ± 8.1e15 Hz with the interval
/// [0, inf]. The record cannot separate them: the fit says so, reports no cut-off, and
/// its delay is the sensor's whole lag — 6 ms plus the filter's low-frequency group
/// delay 1/(2π·50 Hz) = 3.18 ms (exact to 0.04 % over the excited 0.1–3 Hz) — within 4 SE.
#[test]
fn a_cutoff_the_record_cannot_separate_from_the_delay_is_said_and_not_reported() {
    let shipped = std::fs::read_to_string(config("delayed-sensor.toml")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("delayed-cutoff.toml");
    let text = shipped.replacen(
        "estimate_delay = true,",
        "estimate_delay = true, estimate_cutoff = true,",
        1,
    );
    assert!(text.contains("estimate_cutoff = true"));
    std::fs::write(&path, text).unwrap();
    let run = run_in_temp(&path, None, None).expect("runs");
    let fit = &run.summary.results["fit"];
    assert!(
        fit["cutoffs"]
            .as_array()
            .is_none_or(|c| c.iter().all(Value::is_null)),
        "{}",
        fit["cutoffs"]
    );
    assert!(
        run.summary
            .summary
            .contains("cannot separate a first-order filter from the sensor's delay")
    );
    let delay = &fit["delays"][0];
    let lag = 0.006 + 1.0 / (std::f64::consts::TAU * 50.0);
    let (value, se) = (
        delay["value"].as_f64().unwrap(),
        delay["standard_error"].as_f64().unwrap(),
    );
    assert!(
        (value - lag).abs() < 4.0 * se,
        "{value} ± {se} against {lag}"
    );
}

#[test]
fn the_delayed_sensor_is_fitted_with_its_delay_and_the_bias_of_ignoring_it_is_shown() {
    let run = run_in_temp(&config("delayed-sensor.toml"), None, None).expect("runs");
    let r = &run.summary.results;
    let c = &r["fit"]["intervals"]["dampers"][0];
    let (value, se) = (
        c["value"].as_f64().unwrap(),
        c["standard_error"].as_f64().unwrap(),
    );
    assert!((value - 1.8).abs() < 4.0 * se, "c = {value} ± {se}");
    let delay = &r["fit"]["delays"][0];
    let d = delay["value"].as_f64().unwrap();
    assert!(
        (d - 0.006).abs() < 4.0 * delay["standard_error"].as_f64().unwrap(),
        "{d}"
    );
    let zeta = &r["fit"]["modes"][0]["damping_ratio"];
    let true_zeta = 1.8 / (2.0 * (2.5f64 * 120.0).sqrt());
    let (z, zse) = (
        zeta["value"].as_f64().unwrap(),
        zeta["standard_error"].as_f64().unwrap(),
    );
    assert!((z - true_zeta).abs() < 4.0 * zse);
    // Ignoring the 6 ms delay and the filter's lag: c and ζ more than 3 SE off.
    let naive = r["ideal_sensors"]["intervals"]["dampers"][0]["value"]
        .as_f64()
        .unwrap();
    assert!((naive - 1.8).abs() > 3.0 * se, "{naive} vs 1.8 ± {se}");
    let naive_zeta = r["ideal_sensors"]["modes"][0]["damping_ratio"]["value"]
        .as_f64()
        .unwrap();
    assert!((naive_zeta - true_zeta).abs() > 3.0 * zse);
    let report = std::fs::read_to_string(run.out().join("report.md")).unwrap();
    assert!(report.contains("What ignoring the sensors' delay and filters costs"));
}

/// The two-storey config with `from` replaced by `to`, run into a temporary folder: the
/// refusal (exit 2, nothing written) must contain every fragment.
fn refuses(from: &str, to: &str, fragments: &[&str]) {
    let text = std::fs::read_to_string(config("two-storey.toml")).unwrap();
    assert!(text.contains(from), "two-storey.toml has no `{from}`");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    let options = msd_experiment::RunOptions {
        out: Some(dir.path().join("out")),
        ..Default::default()
    };
    let err = msd_experiment::run_experiment(&path, &options).expect_err("refused");
    assert_eq!(err.exit_code(), 2, "{err}");
    let message = err.to_string();
    for f in fragments {
        assert!(message.contains(f), "`{message}` lacks `{f}`");
    }
    assert!(!dir.path().join("out").exists());
}

#[test]
fn bad_chains_are_refused_naming_the_key() {
    // A spring of 0 leaves the masses unconnected.
    refuses(
        "springs = [8000.0, 6000.0]",
        "springs = [8000.0, 0.0]",
        &[
            "bad.toml:",
            "chain.plant.springs[1] = 0",
            "would not be connected",
        ],
    );
    refuses(
        "{ at = 2, quantity",
        "{ at = 3, quantity",
        &["chain.sensors[1].at = 3", "expected a mass from 1 to 2"],
    );
    refuses(
        "{ at = 2, quantity = \"acceleration\", sigma = 0.02 }",
        "{ at = 2, quantity = \"acceleration\", sigma = 0.02, delay = 12.0 }",
        &["chain.sensors[1].delay = 12", "half the record"],
    );
    refuses(
        "{ at = 2, quantity = \"acceleration\", sigma = 0.02 }",
        "{ at = 2, quantity = \"acceleration\", sigma = 0.02, low_pass = { cutoff_hz = -50.0 } }",
        &[
            "chain.sensors[1].low_pass.cutoff_hz = -50",
            "expected a finite frequency > 0",
        ],
    );
    refuses(
        "{ at = 2, quantity = \"acceleration\", sigma = 0.02 }",
        "{ at = 2, quantity = \"acceleration\", sigma = 0.02, estimate_cutoff = true }",
        &[
            "chain.sensors[1].estimate_cutoff = true",
            "expected a low_pass",
        ],
    );
    refuses(
        "force_at = 2 ",
        "force_at = 5 ",
        &["chain.force_at = 5", "expected a mass from 1 to 2"],
    );
    refuses(
        "masses = [2.0, 1.5]",
        "masses = [2.0, 1.5, 1.0]",
        &["chain.plant.dampers has 2 values", "one per mass (3)"],
    );
    refuses(
        "force_at = 2 ",
        "drive_sigma = -0.1\nforce_at = 2 ",
        &["chain.drive_sigma = -0.1", "expected a finite number ≥ 0"],
    );
}

/// Issue 46 §4: sizes a config can state but the fit cannot take exit 2 naming the key
/// (they exited 1 from inside the run, or 0 with inf in the report).
#[test]
fn absurd_sizes_are_refused_naming_the_key() {
    let sensor = "{ at = 2, quantity = \"acceleration\", sigma = 0.02 }";
    let with = |extra: &str| sensor.replace(" }", &format!(", {extra} }}"));
    for (extra, fragments) in [
        (
            "delay = -0.006, estimate_delay = true",
            ["chain.sensors[1].delay = -0.006", "≥ 0"],
        ),
        (
            "delay = nan, estimate_delay = true",
            ["chain.sensors[1].delay = NaN", "≥ 0"],
        ),
        (
            "low_pass = { cutoff_hz = 1e-6 }",
            [
                "chain.sensors[1].low_pass.cutoff_hz = 1e-6",
                "1/duration = 0.1 Hz",
            ],
        ),
    ] {
        refuses(sensor, &with(extra), &fragments);
    }
    refuses(
        sensor,
        &sensor.replace("0.02", "1e300"),
        &["chain.sensors[1].sigma = 1e300", "from 0 to 1e150"],
    );
    for (rms, level) in [
        ("0.0", "RMS 0e0"),
        ("1e-200", "RMS 0e0"),
        ("1e200", "RMS inf"),
    ] {
        refuses(
            "rms = 2.0",
            &format!("rms = {rms}"),
            &[
                "identification.input: the drive it describes has",
                level,
                "between 1e-150 and 1e150",
            ],
        );
    }
}

/// The two-storey rig with a load cell of 2 % noise (0.04 N on 2 N rms): the drive's
/// noise is found (σ̂_u within 4 of its standard errors, ~1/√(lines) relative, of 0.04 N
/// — here within 25 %), the intervals widen and hold the truth, the white-noise ones
/// are reported beside them, and `noise_model = "white"` gives those alone.
#[test]
fn a_noisy_load_cell_on_a_chain_widens_the_intervals_and_says_why() {
    let text = std::fs::read_to_string(config("two-storey.toml")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let run = |extra: &str, name: &str| {
        let path = dir.path().join(format!("{name}.toml"));
        let noisy = text.replacen("force_at = 2 ", &format!("{extra}\nforce_at = 2 "), 1);
        std::fs::write(&path, noisy).unwrap();
        let options = msd_experiment::RunOptions {
            out: Some(dir.path().join(name)),
            ..Default::default()
        };
        msd_experiment::run_experiment(&path, &options).expect("runs")
    };
    let treated = run("drive_sigma = 0.04", "treated");
    let r = &treated.results;
    let model = &r["fit"]["noise_model"];
    assert_eq!(model["treatment"], "input_noise");
    let sigma_u = model["input_noise_sigma"].as_f64().unwrap();
    assert!((sigma_u / 0.04 - 1.0).abs() < 0.25, "σ̂_u = {sigma_u}");
    assert!(model["p_value"].as_f64().unwrap() < 1e-6);
    assert!(worst_z(r) < 4.0);
    let white = &r["fit"]["white_noise_uncertainty"]["intervals"]["dampers"][0];
    let reported = &r["fit"]["intervals"]["dampers"][0];
    let se = |v: &Value| v["standard_error"].as_f64().unwrap();
    assert!(se(reported) > 2.0 * se(white), "{reported} vs {white}");
    let report = std::fs::read_to_string(treated.out_dir.join("report.md")).unwrap();
    assert!(report.contains("## Noise") && report.contains("would have reported"));
    assert!(
        treated.summary.contains("noise model    input_noise"),
        "{}",
        treated.summary
    );
    // The verdict comes first and says the drive's noise was accounted for.
    assert_eq!(r["verdict"]["trustworthy"], true, "{}", r["verdict"]);
    assert!(
        treated.summary.contains("verdict        trustworthy")
            && treated.summary.contains("the drive's own noise shows"),
        "{}",
        treated.summary
    );
    assert!(report.find("## In short").unwrap() < report.find("## Chain").unwrap());
    // The held-out residual is coloured by the drive's noise, and the report says so.
    assert!(report.contains("says nothing against the chain"));
    // The white fit: narrow intervals, and residuals flagged as coloured.
    let white_run = run("drive_sigma = 0.04\nnoise_model = \"white\"", "white");
    let w = &white_run.results["fit"];
    assert_eq!(w["noise_model"]["treatment"], "white");
    assert!((se(&w["intervals"]["dampers"][0]) / se(white) - 1.0).abs() < 1e-9);
    assert!(
        w["whiteness"]
            .as_array()
            .unwrap()
            .iter()
            .any(|c| c["passed"] == false),
        "{}",
        w["whiteness"]
    );
    // Its verdict says the residuals are coloured and the intervals may be too narrow.
    let verdict = &white_run.results["verdict"];
    assert_eq!(verdict["trustworthy"], false, "{verdict}");
    assert!(
        white_run.summary.contains("verdict        use with care")
            && white_run.summary.contains("intervals may be too narrow"),
        "{}",
        white_run.summary
    );
}

#[test]
fn the_plan_predicts_the_spread_and_the_coverage_of_simulated_records() {
    // 200 simulated records of each config, fitted as the run fits them. The sample SD
    // of 200 draws has a relative standard error of 1/√398 = 5 %: each SD/SE ratio
    // within 1 ± 0.2 (4 of those). Coverage pooled over the quantities: 95 ± 3 %.
    for name in ["two-storey.toml", "tuned-mass-damper.toml"] {
        let options = msd_experiment::plan::PlanOptions {
            verify: 200,
            ..Default::default()
        };
        let plan = msd_experiment::plan::plan(&config(name), &options).expect("plans");
        let mut covered = Vec::new();
        for q in &plan.quantities {
            let sd = q.simulated_standard_deviation.expect("verified");
            let ratio = sd / q.standard_error;
            assert!((0.8..1.2).contains(&ratio), "{name} {}: {ratio}", q.name);
            covered.push(q.coverage.expect("verified"));
        }
        let pooled = covered.iter().sum::<f64>() / covered.len() as f64;
        assert!((0.92..=0.98).contains(&pooled), "{name}: {pooled}");
        assert!(plan.quantity("k1").is_some() && plan.quantity("zeta2").is_some());
    }
}
