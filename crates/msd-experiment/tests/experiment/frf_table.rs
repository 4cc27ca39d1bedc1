//! The table `configs/frf-table.toml` reads is the one the `frf_table` example writes,
//! and the config fits it: m, c and k of the plant it was simulated on inside their
//! 95 % intervals.

use msd_experiment::config::{Config, Spec};
use msd_experiment::frf::{self, FrfFit};

#[path = "../../examples/frf_table.rs"]
mod example;

const CONFIG: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../configs/frf-table.toml");

#[test]
fn the_shipped_table_is_what_the_example_writes() {
    let shipped = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/data/stepped-sine-table.csv"
    );
    let text = std::fs::read_to_string(shipped).expect("the shipped file");
    assert!(
        text == example::stepped_sine_table(),
        "configs/data/stepped-sine-table.csv differs: run the example again"
    );
}

#[test]
fn the_table_config_fits_the_plant_it_was_simulated_on() {
    let config = Config::load(CONFIG.as_ref()).expect("valid");
    let outcome = frf::run(
        Spec::new(config).expect("a frequency response"),
        &Default::default(),
    )
    .expect("fits");
    assert_eq!(outcome.data.frequency.len(), 30);
    assert!(outcome.time_domain.is_none(), "a table has no time records");
    let FrfFit::OneMode(fit) = &outcome.fit else {
        panic!("one mode")
    };
    let u = &fit.uncertainty;
    for (name, interval, truth) in [
        ("m", u.mass, 2.5),
        ("c", u.damping, 1.8),
        ("k", u.stiffness, 120.0),
    ] {
        assert!(interval.contains(truth), "{name}: {interval:?}");
    }
    // No coherence: the residual check cannot be made, and the verdict says so
    // instead of calling the intervals trustworthy (or saying nothing).
    let v = &outcome.verdict;
    assert!(!v.trustworthy && v.unchecked, "{v}");
    assert!(
        v.to_string()
            .starts_with("unchecked: the FRF carries no coherence"),
        "{v}"
    );
    let json = frf::to_json(&outcome, &[], Default::default());
    assert_eq!(json["verdict"]["unchecked"], true, "{}", json["verdict"]);
    assert_eq!(json["verdict"]["findings"][0]["checked"], false);
}

/// Issue 31, class 3: what the config or the data get wrong is exit 2, naming the key
/// (or the file and line) with the data's range, not a fit failure (exit 1).
#[test]
fn bad_bands_sizes_and_scales_are_config_errors() {
    let dir = tempfile::tempdir().expect("a folder");
    let shipped = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/data/stepped-sine-table.csv"
    );
    let text = std::fs::read_to_string(shipped).expect("the shipped table");
    let run = |table: &str, extra: &str| {
        std::fs::write(dir.path().join("t.csv"), table).expect("written");
        let config = format!(
            "name = \"t\"\n[frequency_response.table]\npath = \"t.csv\"\nfrequency = \"frequency_hz\"\nmagnitude = \"magnitude_m_per_n\"\nphase = \"phase_deg\"\n{extra}"
        );
        let path = dir.path().join("t.toml");
        std::fs::write(&path, config).expect("written");
        let config = Config::load(&path)?;
        frf::run(
            Spec::new(config).expect("a frequency response"),
            &Default::default(),
        )
    };
    let expect = |result: Result<frf::FrfOutcome, msd_experiment::ExperimentError>,
                  parts: &[&str]| {
        let err = result.expect_err("refused");
        assert_eq!(err.exit_code(), 2, "{err}");
        for part in parts {
            assert!(err.to_string().contains(part), "`{part}` not in: {err}");
        }
    };
    // A band outside the data (0.3–3 Hz).
    expect(
        run(
            &text,
            "[frequency_response.one_mode]\nband_hz = [10.0, 20.0]",
        ),
        &[
            "frequency_response.one_mode.band_hz",
            "0.3–3 Hz",
            "at least 4",
        ],
    );
    // A table of three lines.
    // (two comment lines and the header, then the rows)
    let three: String = text.lines().take(6).map(|l| format!("{l}\n")).collect();
    expect(
        run(&three, ""),
        &["frequency_response.one_mode.band_hz", "3 lines"],
    );
    // More modes asked for than the data hold.
    expect(
        run(
            &text,
            "[frequency_response.modes]\norders = [2, 10]\nmode_count = 3",
        ),
        &["frequency_response.modes.mode_count"],
    );
    // A band with no peak (the mode is at 1.1 Hz): the section named, the keys to change
    // and the data's range in the message.
    expect(
        run(
            &text,
            "[frequency_response.modes]\nband_hz = [2.0, 3.0]\norders = [2, 4]",
        ),
        &["frequency_response.modes:", "band_hz", "0.3–3 Hz"],
    );
    // Magnitudes × 1e300 and × 1e-300, and all zero: refused where they are read (the
    // first row is the file's line 4).
    for (factor, part) in [(1e300, "line 4"), (1e-300, "line 4"), (0.0, "every one")] {
        let scaled: String = text
            .lines()
            .map(|l| {
                if l.starts_with('#') || l.starts_with("frequency") {
                    return format!("{l}\n");
                }
                let mut cells: Vec<String> = l.split(',').map(str::to_string).collect();
                let m: f64 = cells[1].parse().expect("a magnitude");
                cells[1] = format!("{:e}", m * factor);
                format!("{}\n", cells.join(","))
            })
            .collect();
        expect(run(&scaled, ""), &["t.csv", part]);
    }
}

/// Issue 31, class 5: columns by number count from 0, as the configs say; a number past
/// the row says how the row's columns are numbered.
#[test]
fn columns_by_number_count_from_zero() {
    let dir = tempfile::tempdir().expect("a folder");
    let shipped = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/data/stepped-sine-table.csv"
    );
    std::fs::copy(shipped, dir.path().join("t.csv")).expect("copied");
    let run = |columns: &str| {
        let path = dir.path().join("t.toml");
        let text = format!(
            "name = \"t\"\n[frequency_response.table]\npath = \"t.csv\"\n{columns}\n[frequency_response.one_mode]\nweighting = \"relative\"\n"
        );
        std::fs::write(&path, text).expect("written");
        let config = Config::load(&path)?;
        frf::run(
            Spec::new(config).expect("a frequency response"),
            &Default::default(),
        )
    };
    let by_name = run(
        "frequency = \"frequency_hz\"\nmagnitude = \"magnitude_m_per_n\"\nphase = \"phase_deg\"",
    )
    .expect("by name");
    let by_number = run("frequency = 0\nmagnitude = 1\nphase = 2").expect("by number");
    assert_eq!(by_name.data.h, by_number.data.h);
    let err = run("frequency = 1\nmagnitude = 2\nphase = 3").expect_err("no column #3");
    assert!(
        err.to_string().contains("no column #3") && err.to_string().contains("#0 … #2"),
        "{err}"
    );
}

/// Issue 30: a failed mode selection leaves its stabilization diagram to look at, in a
/// folder of its own beside the results, and any previous result untouched.
#[test]
fn a_failed_selection_keeps_its_diagram() {
    let dir = tempfile::tempdir().expect("a folder");
    let shipped = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/data/stepped-sine-table.csv"
    );
    std::fs::copy(shipped, dir.path().join("t.csv")).expect("copied");
    let path = dir.path().join("t.toml");
    let write = |modes: &str| {
        let text = format!(
            "name = \"t\"\n[frequency_response.table]\npath = \"t.csv\"\nfrequency = \"frequency_hz\"\nmagnitude = \"magnitude_m_per_n\"\nphase = \"phase_deg\"\n[frequency_response.modes]\norders = [2, 10]\n{modes}"
        );
        std::fs::write(&path, text).expect("written");
    };
    let results = dir.path().join("out");
    let options = msd_experiment::RunOptions {
        out: Some(results.clone()),
        ..Default::default()
    };
    write("");
    msd_experiment::run_experiment(&path, &options).expect("one mode found");
    let before = std::fs::read(results.join("results.json")).expect("a result");

    write("mode_count = 3");
    let err = msd_experiment::run_experiment(&path, &options).expect_err("only one mode");
    assert_eq!(err.exit_code(), 2, "{err}");
    let msd_experiment::ExperimentError::Kept { error, kept } = &err else {
        panic!("{err}")
    };
    assert!(
        error
            .to_string()
            .contains("frequency_response.modes.mode_count"),
        "{error}"
    );
    let failed = dir.path().join("out-failed");
    assert_eq!(kept, &failed.join("frf_stabilization.png"));
    for file in [
        "frf_stabilization.png",
        "frf_stabilization.svg",
        "failure.md",
    ] {
        let bytes = std::fs::read(failed.join(file)).expect(file);
        assert!(bytes.len() > 100, "{file}: {} bytes", bytes.len());
    }
    let note = std::fs::read_to_string(failed.join("failure.md")).expect("the note");
    assert!(note.contains("3 were asked for"), "{note}");
    assert!(err.to_string().contains("kept for inspection"), "{err}");
    let after = std::fs::read(results.join("results.json")).expect("still there");
    assert_eq!(before, after, "the previous result is untouched");
}

/// Issue 31, class 3: a shaker whose force is zero, or records whose force columns are
/// constant, are exit 2 naming the key or the file (they were exit 1).
#[test]
fn a_source_without_force_is_refused_by_name() {
    let dir = tempfile::tempdir().expect("a folder");
    let shipped = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/frf-records.toml"
    );
    let text = std::fs::read_to_string(shipped).expect("the shipped config");
    let silent = text.replace("rms = 2.0", "rms = 0.0");
    assert_ne!(silent, text, "the config sets the force's rms");
    let path = dir.path().join("silent.toml");
    std::fs::write(&path, silent).expect("written");
    let config = Config::load(&path).expect("valid");
    let err = frf::run(
        Spec::new(config).expect("a frequency response"),
        &Default::default(),
    )
    .expect_err("no force");
    assert_eq!(err.exit_code(), 2, "{err}");
    assert!(
        err.to_string().contains("frequency_response.shaker.force"),
        "{err}"
    );

    let rows: String = (0..256)
        .map(|i| format!("0,{}\n", (0.37 * f64::from(i)).sin()))
        .collect();
    std::fs::write(dir.path().join("r.csv"), format!("f,x\n{rows}")).expect("written");
    let path = dir.path().join("records.toml");
    std::fs::write(
        &path,
        "name = \"r\"\n[frequency_response.records]\npath = \"r.csv\"\nsample_rate = 100.0\nforce = [\"f\"]\nresponse = [\"x\"]\n",
    )
    .expect("written");
    let config = Config::load(&path).expect("valid");
    let err = frf::run(
        Spec::new(config).expect("a frequency response"),
        &Default::default(),
    )
    .expect_err("no force");
    assert_eq!(err.exit_code(), 2, "{err}");
    let text = err.to_string();
    assert!(
        text.contains("r.csv") && text.contains("frequency_response.records.force"),
        "{text}"
    );
}

/// Issue 34: records of two periods of a multisine with the default window. A Hann
/// window smeared every line of the force into the lines between (the fit explained
/// nothing, or gave c = 1.369 ± 0.061 against 1.8); `window = "auto"` sees the force
/// repeat from record to record, takes each record whole with a rectangular window, and
/// the truth is inside every interval.
#[test]
fn two_periods_a_record_take_a_rectangular_window_by_default() {
    let dir = tempfile::tempdir().expect("a folder");
    let shipped = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/frf-records.toml"
    );
    let text = std::fs::read_to_string(shipped).expect("the shipped config");
    let two = text
        .replace("duration = 20.0", "duration = 40.0")
        .replace("welch = { window = \"rectangular\" }\n", "");
    assert!(
        two.contains("duration = 40.0") && !two.contains("welch"),
        "{two}"
    );
    let run = |text: &str| {
        let path = dir.path().join("two.toml");
        std::fs::write(&path, text).expect("written");
        let config = Config::load(&path).expect("valid");
        frf::run(
            Spec::new(config).expect("a frequency response"),
            &Default::default(),
        )
    };
    let outcome = run(&two).expect("fits");
    assert!(outcome.chose_rectangular_window());
    assert_eq!(outcome.data.noise_bandwidth, 1.0);
    let FrfFit::OneMode(fit) = &outcome.fit else {
        panic!("one mode")
    };
    let u = &fit.uncertainty;
    for (name, interval, truth) in [
        ("m", u.mass, 2.5),
        ("c", u.damping, 1.8),
        ("k", u.stiffness, 120.0),
    ] {
        assert!(
            interval.ci95[0] <= truth && truth <= interval.ci95[1],
            "{name} = {} ± {}: {truth} outside {:?}",
            interval.value,
            interval.standard_error,
            interval.ci95
        );
    }
    // The half-power estimate reads the excited lines only (the lines between, without
    // force, are no data): within 0.005 of ζ = 0.0520 (its crossings are
    // interpolated between lines 0.05 Hz apart, a band of 0.115 Hz).
    let classroom = outcome.classroom[0]
        .as_ref()
        .expect("a half-power estimate");
    assert!(
        (classroom.damping_ratio - 0.052).abs() < 0.005,
        "{classroom:?}"
    );

    // Asked for by name, the Hann window smears the lines: the fit refuses.
    let hann = two.replace(
        "[frequency_response.estimator]\n",
        "[frequency_response.estimator]\nwelch = { window = \"hann\" }\n",
    );
    assert!(hann.contains("window = \"hann\""));
    let err = run(&hann).expect_err("a smeared FRF");
    assert!(err.to_string().contains("explains nothing"), "{err}");
}
