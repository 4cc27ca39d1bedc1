//! Issue 45's scripted first hour: `msd init` on a lab's own file writes a config beside
//! it that runs, and whose intervals hold the truth — a force and an accelerometer in g
//! behind metadata lines with decimal commas, a displacement record in mm with a load
//! cell in kN (units in the column names), a ring-down; columns that cannot say what they are get a question back.
//!
//! "Hold the truth" is |estimate − truth| ≤ 4 standard errors for each quantity (a
//! correct interval misses that by chance with probability 6e-5), so that the test
//! checks the intervals' meaning without depending on a seed's luck.

use msd_experiment::init::{InitOptions, init};
use msd_ident::records::simulate_channels;
use msd_ident::{Drive, Excitation, Frame, InitialState, Parameters, ResponseQuantity};
use msd_tests::run_in_temp;
use std::path::Path;

/// The rig: m 1.7 kg, c 3.1 N·s/m, k 950 N/m (fn 3.76 Hz, ζ 3.9 %).
const TRUTH: Parameters = Parameters {
    mass: 1.7,
    damping: 3.1,
    stiffness: 950.0,
};
const DT: f64 = 1e-3;
const SAMPLES: usize = 12_000;

/// A multisine of 0.2–15 Hz (random phases from a fixed sequence), rms about 5 N.
fn force() -> Vec<f64> {
    let lines: Vec<f64> = (1..=75).map(|k| 0.2 * k as f64).collect();
    let amplitude = 5.0 * (2.0 / lines.len() as f64).sqrt();
    (0..SAMPLES)
        .map(|i| {
            let t = i as f64 * DT;
            lines
                .iter()
                .enumerate()
                .map(|(k, f)| {
                    let phase = (k * k) as f64 * std::f64::consts::PI / lines.len() as f64;
                    amplitude * (2.0 * std::f64::consts::PI * f * t + phase).sin()
                })
                .sum()
        })
        .collect()
}

/// The rig's exact response in `quantity` to `force` (SI), with white noise `sigma`.
fn response(force: &[f64], quantity: ResponseQuantity, sigma: f64, seed: u64) -> Vec<f64> {
    let excitation = Excitation::from_samples(0.0, DT, force.to_vec()).unwrap();
    let (drive, input) = if force.iter().all(|&f| f == 0.0) {
        (Drive::None, None)
    } else {
        (Drive::Force, Some(&excitation))
    };
    let initial = match drive {
        Drive::None => InitialState {
            displacement: 0.01,
            velocity: 0.0,
        },
        _ => InitialState::REST,
    };
    let channels = [(quantity, Frame::Absolute)];
    let clean = simulate_channels(&TRUTH, initial, drive, input, SAMPLES, DT, &channels).unwrap();
    let noise = msd_signal::gaussian_noise(seed, "init", sigma, SAMPLES).unwrap();
    clean[0].iter().zip(&noise).map(|(x, e)| x + e).collect()
}

/// Each named quantity of `results.json`'s estimate within 4 standard errors of `truth`.
fn assert_holds(results: &serde_json::Value, truth: &[(&str, f64)]) {
    for (name, value) in truth {
        let q = &results["estimate"][name];
        let (estimate, se) = (q["value"].as_f64(), q["standard_error"].as_f64());
        let (Some(estimate), Some(se)) = (estimate, se) else {
            panic!("{name}: no estimate in {}", results["estimate"]);
        };
        assert!(
            (estimate - value).abs() <= 4.0 * se,
            "{name}: {estimate} ± {se} against the truth {value}"
        );
    }
}

fn physical() -> [(&'static str, f64); 5] {
    [
        ("mass", TRUTH.mass),
        ("damping", TRUTH.damping),
        ("stiffness", TRUTH.stiffness),
        ("natural_frequency_hz", TRUTH.natural_frequency_hz()),
        ("damping_ratio", TRUTH.damping_ratio()),
    ]
}

/// Writes `text` at `dir/name` and runs `msd init` on it with `options`.
fn init_on(dir: &Path, name: &str, text: &str, options: &InitOptions) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    let done = init(&path, options).expect("msd init");
    assert_eq!(done.config_path, path.with_extension("toml"));
    assert!(done.summary.contains("msd run"), "{}", done.summary);
    done.text
}

#[test]
fn a_force_and_an_accelerometer_in_g_with_metadata_and_decimal_commas() {
    let dir = tempfile::tempdir().unwrap();
    let f = force();
    let a = response(&f, ResponseQuantity::Acceleration, 0.05, 11);
    let mut csv =
        String::from("Rig 2 shaker test\nOperator: A. N. Other\ntime;force;accel\ns;N;g\n");
    for i in 0..SAMPLES {
        let row = format!("{:.4};{:.6};{:.7e}\n", i as f64 * DT, f[i], a[i] / 9.80665);
        csv.push_str(&row.replace('.', ","));
    }
    let text = init_on(dir.path(), "shaker.csv", &csv, &InitOptions::default());
    for line in [
        "excitation = \"force\"",
        "column = \"accel\", scale = 9.80665",
        "delimiter = \";\"",
        "decimal = \",\"",
        "time = \"time\"",
        "input = \"force\"",
        "path = \"shaker.csv\"",
    ] {
        assert!(text.contains(line), "{line}:\n{text}");
    }
    let run = run_in_temp(&dir.path().join("shaker.toml"), None, None).expect("the config runs");
    assert_holds(&run.summary.results, &physical());
}

#[test]
fn a_displacement_in_mm_and_a_load_cell_in_kn_named_in_the_header() {
    let dir = tempfile::tempdir().unwrap();
    let f = force();
    let x = response(&f, ResponseQuantity::Displacement, 2e-5, 12);
    let mut csv = String::from("t [s],load [kN],laser [mm]\n");
    for i in 0..SAMPLES {
        let row = format!("{:.4},{:.9},{:.6}\n", i as f64 * DT, f[i] / 1e3, x[i] * 1e3);
        csv.push_str(&row);
    }
    let text = init_on(dir.path(), "laser.csv", &csv, &InitOptions::default());
    for line in [
        "quantity = \"displacement\", column = \"laser [mm]\", scale = 0.001",
        "input = \"load [kN]\"",
        "input_scale = 1000",
    ] {
        assert!(text.contains(line), "{line}:\n{text}");
    }
    let run = run_in_temp(&dir.path().join("laser.toml"), None, None).expect("the config runs");
    assert_holds(&run.summary.results, &physical());
}

#[test]
fn a_ring_down_is_a_free_decay() {
    let dir = tempfile::tempdir().unwrap();
    let x = response(
        &vec![0.0; SAMPLES],
        ResponseQuantity::Displacement,
        1e-5,
        13,
    );
    let mut csv = String::from("time [s],displacement\n");
    for (i, x) in x.iter().enumerate().take(4000) {
        csv.push_str(&format!("{:.4},{x:.8}\n", i as f64 * DT));
    }
    let text = init_on(dir.path(), "pluck.csv", &csv, &InitOptions::default());
    assert!(text.contains("excitation = \"none\""), "{text}");
    let run = run_in_temp(&dir.path().join("pluck.toml"), None, None).expect("the config runs");
    assert_holds(
        &run.summary.results,
        &[
            ("natural_frequency_hz", TRUTH.natural_frequency_hz()),
            ("damping_ratio", TRUTH.damping_ratio()),
        ],
    );
}

#[test]
fn columns_that_cannot_say_get_a_question_and_the_answer_runs() {
    let dir = tempfile::tempdir().unwrap();
    let f = force();
    let x = response(&f, ResponseQuantity::Displacement, 2e-5, 14);
    let mut csv = String::from("t,ch1,ch2\n");
    for i in 0..SAMPLES {
        csv.push_str(&format!("{:.4},{:.6},{:.8}\n", i as f64 * DT, f[i], x[i]));
    }
    let path = dir.path().join("daq.csv");
    std::fs::write(&path, csv).unwrap();
    let err = init(&path, &InitOptions::default()).unwrap_err();
    let message = err.to_string();
    assert_eq!(err.exit_code(), 2, "{message}");
    for text in ["daq.csv", "\"ch1\"", "\"ch2\"", "--input", "--output"] {
        assert!(message.contains(text), "{text}: {message}");
    }
    assert!(
        !path.with_extension("toml").exists(),
        "a config was written"
    );
    let options = InitOptions {
        input: Some("ch1".into()),
        outputs: vec!["ch2".into()],
        ..InitOptions::default()
    };
    init(&path, &options).expect("msd init with the columns named");
    let run = run_in_temp(&path.with_extension("toml"), None, None).expect("the config runs");
    assert_holds(&run.summary.results, &physical());
    // A second init does not overwrite the user's config.
    let err = init(&path, &options).unwrap_err().to_string();
    assert!(
        err.contains("--overwrite") && err.contains("daq.toml"),
        "{err}"
    );
}

/// A measurement nobody here made: the Silverbox's Schroeder multisine (an electronic
/// Duffing oscillator; the file is two voltages and no time, sampled at 10⁷/2¹⁴ Hz).
/// The columns say nothing, so `msd init` asks; with them named it writes a config
/// that runs, and the fitted resonance lies inside the data's own resonance peak (the
/// H1 estimate's dominant peak ± its half-power bandwidth).
#[test]
fn the_silverbox_through_msd_init() {
    let test = "the_silverbox_through_msd_init";
    let Some(data) = msd_tests::real_data("silverbox", test) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("Schroeder80mV.csv");
    std::fs::copy(data.join("Schroeder80mV.csv"), &path).unwrap();
    let err = init(&path, &InitOptions::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("--sample-rate"), "{err}");
    let rate = 1e7 / 16384.0;
    let options = InitOptions {
        input: Some("V1".into()),
        outputs: vec!["V2".into()],
        sample_rate_hz: Some(rate),
        ..InitOptions::default()
    };
    let text = init(&path, &options).expect("msd init").text;
    assert!(text.contains("sample_rate = 610.3515625"), "{text}");
    let run = run_in_temp(&path.with_extension("toml"), None, None).expect("the config runs");
    let fitted = run.number("estimate.natural_frequency_hz.value");

    let (mut u, mut y) = (Vec::new(), Vec::new());
    for line in std::fs::read_to_string(&path).unwrap().lines().skip(1) {
        // "Ovld2","Ovld1","V1","V2", with a trailing comma; the last line is empty.
        if let [_, _, v1, v2, ..] = line.split(',').collect::<Vec<_>>()[..] {
            u.push(v1.trim().parse::<f64>().unwrap());
            y.push(v2.trim().parse::<f64>().unwrap());
        }
    }
    let record = msd_signal::Record {
        input: &u,
        output: &y,
    };
    let options = msd_signal::FrfOptions {
        welch: msd_signal::WelchOptions {
            segment_length: Some(8192),
            ..Default::default()
        },
        ..Default::default()
    };
    let frf = msd_signal::frf_estimate(&[record], rate, &options).unwrap();
    let peak = msd_modal::dominant_peak(&frf).unwrap();
    assert!(
        (fitted - peak.peak_hz).abs() <= peak.half_power_bandwidth_hz,
        "fitted fn {fitted} Hz against the data's peak: {peak}"
    );
}
