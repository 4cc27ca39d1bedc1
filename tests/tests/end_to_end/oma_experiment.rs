//! Output-only modal analysis from the command's side (issue 43): the simulated shear
//! building at defaults against its truth; a CSV record with a dead channel, refused or
//! left out as asked; bad records and options refused naming the key or column; and the
//! real steel frame, every shared setup at default settings against the origin's own
//! merged result.

use msd_tests::{config, real_data, run_in_temp};
use serde_json::Value;
use std::path::Path;

fn modes(results: &Value) -> Vec<(f64, [f64; 2], f64, [f64; 2])> {
    results["modes"]
        .as_array()
        .expect("modes[]")
        .iter()
        .map(|m| {
            let pair = |v: &Value| [v[0].as_f64().unwrap(), v[1].as_f64().unwrap()];
            let (f, z) = (&m["natural_frequency_hz"], &m["damping_ratio"]);
            (
                f["value"].as_f64().unwrap(),
                pair(&f["ci95"]),
                z["value"].as_f64().unwrap(),
                pair(&z["ci95"]),
            )
        })
        .collect()
}

/// A simulated run's true natural frequencies, Hz.
fn true_frequencies(results: &Value) -> Vec<f64> {
    results["truth"]
        .as_array()
        .expect("truth[]")
        .iter()
        .map(|t| t["natural_frequency_hz"].as_f64().unwrap())
        .collect()
}

#[test]
fn the_shear_building_is_found_at_defaults_with_intervals_on_every_mode() {
    let run = run_in_temp(&config("shear-building.toml"), None, None).expect("runs");
    let r = &run.summary.results;
    let truth = true_frequencies(r);
    let found = modes(r);
    assert_eq!(found.len(), 5, "{found:?}");
    for ((f, _, z, [z0, z1]), t) in found.iter().zip(&truth) {
        assert!((f / t - 1.0).abs() < 0.005, "{f} against {t}");
        assert!(z0 < z && z < z1);
    }
    assert_eq!(
        r["verdict"]["trustworthy"],
        Value::Bool(true),
        "{}",
        r["verdict"]
    );
    let shape = r["modes"][0]["shape"].as_array().unwrap();
    assert_eq!(shape.len(), 5);
    assert!(shape.iter().all(|e| e["standard_error"].is_array()));
    let report = std::fs::read_to_string(run.out().join("report.md")).unwrap();
    for section in [
        "## In short",
        "## Record",
        "## Modes",
        "### Shapes",
        "## Method",
        "oma_stabilization.png",
    ] {
        assert!(report.contains(section), "report.md lacks {section}");
    }
    assert!(run.out().join("oma_stabilization.svg").exists());
    let csv = std::fs::read_to_string(run.out().join("modes.csv")).unwrap();
    assert_eq!(csv.lines().count(), 6);
    let uff = msd_uff::read(run.out().join("modes.uff")).expect("modes.uff reads back");
    assert_eq!(uff.data_at_nodes.len(), 5);
}

/// The quick look: `method = "efdd"` on the shipped building, every mode within 1 % (the
/// close upper pair pulls each other by up to 0.4 %: msd-modal's tests/modal/efdd.rs), the
/// singular values drawn, EFDD's lags in results.json.
#[test]
fn efdd_finds_the_shear_building_from_the_command() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(config("shear-building.toml")).unwrap();
    let text = text.replace("method = \"ssi-cov\"", "method = \"efdd\"");
    assert!(text.contains("method = \"efdd\""));
    let path = dir.path().join("building-efdd.toml");
    std::fs::write(&path, text).unwrap();
    let run = run_in_temp(&path, None, None).expect("runs");
    let r = &run.summary.results;
    assert_eq!(r["method"], "EFDD");
    assert!(r["lags"].as_u64().is_some() && r["block_rows"].is_null());
    let truth = true_frequencies(r);
    let found = modes(r);
    assert_eq!(found.len(), 5, "{found:?}");
    for ((f, _, z, [z0, z1]), t) in found.iter().zip(&truth) {
        assert!((f / t - 1.0).abs() < 0.01, "{f} against {t}");
        assert!(z0 < z && z < z1);
    }
    assert!(run.out().join("oma_singular_values.png").exists());
    let report = std::fs::read_to_string(run.out().join("report.md")).unwrap();
    assert!(report.contains("EFDD: the spectral matrix"), "{report}");
}

/// Three floors of a simulated building as a CSV file (time, a1, a2, a3 in m/s²), with
/// `edit` applied to each data row's cells, and a config reading it.
fn csv_case(dir: &Path, edit: impl Fn(usize, &mut Vec<String>), extra: &str) -> std::path::PathBuf {
    write_building_csv(&dir.join("ambient.csv"), 7, edit);
    let config = format!(
        r#"name = "ambient"
[operational.record]
path = "ambient.csv"
time = "t"
{CHANNELS}{extra}"#
    );
    let path = dir.join("ambient.toml");
    std::fs::write(&path, config).unwrap();
    path
}

/// The three channels of [`write_building_csv`]'s files, floors 1 and 3 the references.
const CHANNELS: &str = r#"[[operational.channels]]
column = "a1"
node = 1
direction = 1
reference = true
[[operational.channels]]
column = "a2"
node = 2
direction = 1
[[operational.channels]]
column = "a3"
node = 3
direction = 1
reference = true
"#;

/// A three-floor building's accelerations (noise stream `seed`) as a CSV file, `edit`
/// applied to each data row's cells.
fn write_building_csv(path: &Path, seed: u64, edit: impl Fn(usize, &mut Vec<String>)) {
    let building = msd_modal::ShearBuilding {
        masses: vec![30.0; 3],
        stiffnesses: vec![12_000.0; 3],
        damping_ratio: 0.02,
    };
    let mut draws = msd_signal::gaussian_noise(seed, "test", 1.0, 20_000 * 8)
        .unwrap()
        .into_iter();
    let record = building
        .ambient_record(50.0, 20_000, 0.05, || draws.next().unwrap())
        .unwrap();
    let mut text = String::from("t,a1,a2,a3\n");
    for t in 0..record.len() {
        let mut cells = vec![format!("{}", t as f64 / 50.0)];
        cells.extend(
            record
                .channels()
                .iter()
                .map(|c| format!("{}", c.samples[t])),
        );
        edit(t, &mut cells);
        text += &(cells.join(",") + "\n");
    }
    std::fs::write(path, text).unwrap();
}

/// Hourly records of a monitored structure (here two of the same building, different
/// ambient noise; fn within 1 % as for one such record above): each analysed alone, every mode tracked from record to record, the
/// combined modes, `tracks.csv`, the figure and `modes.uff`; one record, or a missing
/// file, refused naming the key or the file.
#[test]
fn several_records_are_tracked_and_combined() {
    let dir = tempfile::tempdir().unwrap();
    write_building_csv(&dir.path().join("hour1.csv"), 7, |_, _| {});
    write_building_csv(&dir.path().join("hour2.csv"), 8, |_, _| {});
    // The floors on a line up the z axis, drawn from the ground (node 0).
    std::fs::write(
        dir.path().join("nodes.txt"),
        "node x y z\n0 0 0 0\n1 0 0 3\n2 0 0 6\n3 0 0 9\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("lines.txt"), "0 1\n1 2\n2 3\n").unwrap();
    let write = |files: &[&str]| {
        let records: String = files
            .iter()
            .map(|f| {
                let label = f.trim_end_matches(".csv");
                format!(
                    "[[operational.records]]\npath = \"{f}\"\ntime = \"t\"\nlabel = \"{label}\"\n"
                )
            })
            .collect();
        let path = dir.path().join("monitor.toml");
        let geometry = "[operational.geometry]\nnodes = \"nodes.txt\"\nlines = \"lines.txt\"\n";
        std::fs::write(
            &path,
            format!("name = \"monitor\"\n{records}{CHANNELS}{geometry}"),
        )
        .unwrap();
        path
    };
    let summary = run(&write(&["hour1.csv", "hour2.csv"])).expect("runs");
    let r = &summary.results;
    let truth = msd_modal::ShearBuilding {
        masses: vec![30.0; 3],
        stiffnesses: vec![12_000.0; 3],
        damping_ratio: 0.02,
    }
    .modes()
    .unwrap();
    let found = modes(r);
    assert_eq!(found.len(), 3, "{found:?}");
    for ((f, [f0, f1], ..), (t, _)) in found.iter().zip(&truth) {
        assert!(
            (f / t - 1.0).abs() < 0.01 && f0 < f && f < f1,
            "{f} against {t}"
        );
    }
    assert_eq!(r["records"].as_array().unwrap().len(), 2);
    let out = dir.path().join("out");
    let tracks = std::fs::read_to_string(out.join("tracks.csv")).unwrap();
    assert_eq!(tracks.lines().count(), 1 + 3 * 2, "{tracks}");
    assert!(tracks.contains("\"hour2\""), "{tracks}");
    let uff = msd_uff::read(out.join("modes.uff")).expect("modes.uff reads back");
    assert_eq!(uff.data_at_nodes.len(), 3);
    assert!(out.join("oma_tracks.png").exists() && out.join("oma_shapes.svg").exists());
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("## Modes over the records"), "{report}");

    let err = run(&write(&["hour1.csv"])).expect_err("one record");
    assert_eq!(err.exit_code(), 2);
    assert!(err.to_string().contains("operational.records"), "{err}");
    let err = run(&write(&["hour1.csv", "hour9.csv"])).expect_err("a missing file");
    assert_eq!(err.exit_code(), 2);
    assert!(err.to_string().contains("hour9.csv"), "{err}");
    std::fs::write(dir.path().join("lines.txt"), "0 1\n1 2\n2 7\n").unwrap();
    let err = run(&write(&["hour1.csv", "hour2.csv"])).expect_err("an unknown node");
    assert_eq!(err.exit_code(), 2);
    assert!(
        err.to_string().contains("lines.txt") && err.to_string().contains("line 3: node 7"),
        "{err}"
    );
}

fn run(path: &Path) -> Result<msd_experiment::RunSummary, msd_experiment::ExperimentError> {
    let options = msd_experiment::RunOptions {
        out: Some(path.parent().unwrap().join("out")),
        ..Default::default()
    };
    msd_experiment::run_experiment(path, &options)
}

#[test]
fn a_csv_record_runs_and_a_dead_channel_is_left_out_or_refused_as_asked() {
    let dir = tempfile::tempdir().unwrap();
    let truth = msd_modal::ShearBuilding {
        masses: vec![30.0; 3],
        stiffnesses: vec![12_000.0; 3],
        damping_ratio: 0.02,
    }
    .modes()
    .unwrap();
    let ok = run(&csv_case(dir.path(), |_, _| {}, "")).expect("runs");
    let found = modes(&ok.results);
    for (t, _) in &truth {
        assert!(
            found.iter().any(|(f, _, _, _)| (f / t - 1.0).abs() < 0.01),
            "{t} not in {found:?}"
        );
    }
    // A dead second channel (constant 0.5): left out by default, and said so.
    let dead = tempfile::tempdir().unwrap();
    let run_dead = run(&csv_case(
        dead.path(),
        |_, cells| cells[2] = "0.5".into(),
        "",
    ))
    .expect("runs without it");
    let left = &run_dead.results["record"]["left_out"];
    assert_eq!(left[0]["name"], "a2", "{left}");
    assert!(left[0]["reason"].as_str().unwrap().contains("constant"));
    assert_eq!(
        run_dead.results["record"]["channels"]
            .as_array()
            .unwrap()
            .len(),
        2
    );
    let report = std::fs::read_to_string(run_dead.out_dir.join("report.md")).unwrap();
    assert!(report.contains("Left out: **a2**"), "{report}");
    // Refused when asked: exit 2 naming the channel, nothing written.
    let refuse = tempfile::tempdir().unwrap();
    let path = csv_case(
        refuse.path(),
        |_, cells| cells[2] = "0.5".into(),
        "[operational]\ndead_channels = \"refuse\"\n",
    );
    let err = run(&path).expect_err("refused");
    assert_eq!(err.exit_code(), 2, "{err}");
    assert!(err.to_string().contains("channel a2: constant"), "{err}");
    assert!(!refuse.path().join("out").exists());
}

#[test]
fn bad_records_and_options_are_refused_naming_the_key_or_column() {
    let refused = |edit: &dyn Fn(usize, &mut Vec<String>), extra: &str, fragments: &[&str]| {
        let dir = tempfile::tempdir().unwrap();
        let err = run(&csv_case(dir.path(), edit, extra)).expect_err("refused");
        assert_eq!(err.exit_code(), 2, "{err}");
        for f in fragments {
            assert!(err.to_string().contains(f), "`{err}` lacks `{f}`");
        }
        assert!(!dir.path().join("out").exists());
    };
    // A NaN cell: the file, its line and column.
    refused(
        &|t, cells| {
            if t == 99 {
                cells[3] = "nan".into()
            }
        },
        "",
        &["ambient.csv", "line 101", "a3"],
    );
    // A band above the Nyquist frequency (25 Hz).
    refused(
        &|_, _| {},
        "[operational.ssi]\nband_hz = [30.0, 40.0]\n",
        &["operational.ssi.band_hz[0] = 30", "Nyquist"],
    );
    // A model order the references cannot hold.
    refused(
        &|_, _| {},
        "[operational.ssi]\nblock_rows = 10\norders = [2, 60]\n",
        &["operational.ssi.orders[1] = 60", "block_rows"],
    );
    // An unknown option.
    refused(
        &|_, _| {},
        "[operational.ssi]\norder = [2, 60]\n",
        &["order"],
    );
    // A force channel: an output-only analysis reads motions.
    refused(
        &|_, _| {},
        "[[operational.channels]]\ncolumn = \"a2\"\nnode = 4\nquantity = \"force\"\n",
        &["operational.channels[3].quantity = \"force\"", "motions"],
    );
}

#[test]
fn a_single_channel_or_a_missing_column_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = csv_case(dir.path(), |_, _| {}, "");
    let text = std::fs::read_to_string(&path).unwrap();
    let one = text
        .split("[[operational.channels]]")
        .take(2)
        .collect::<Vec<_>>()
        .join("[[operational.channels]]");
    std::fs::write(&path, one).unwrap();
    let err = run(&path).expect_err("refused");
    assert!(
        err.to_string().contains("operational.channels")
            && err.to_string().contains("at least two"),
        "{err}"
    );
    std::fs::write(&path, text.replace("column = \"a3\"", "column = \"a9\"")).unwrap();
    let err = run(&path).expect_err("refused");
    assert_eq!(err.exit_code(), 2);
    assert!(err.to_string().contains("a9"), "{err}");
}

/// The origin's merged result (SOURCE.md): fn [Hz] and ζ [%] of its eleven modes.
const REFERENCE: [(f64, f64); 11] = [
    (1.2283, 0.250),
    (1.4358, 0.189),
    (2.1000, 0.227),
    (4.0175, 0.189),
    (4.7704, 0.182),
    (6.6824, 0.190),
    (7.6157, 0.185),
    (9.6653, 0.194),
    (12.1663, 0.195),
    (12.5979, 0.200),
    (13.8545, 0.223),
];

/// The shipped steel-frame config for another setup (its number in the path, and
/// nothing else changed), written into `dir` with the data folder's absolute path.
fn setup_config(dir: &Path, setup: usize) -> std::path::PathBuf {
    let text = std::fs::read_to_string(config("steel-frame.toml")).unwrap();
    let data = format!("{}/", msd_tests::root().join("data").display());
    let path = dir.join(format!("steel-frame-{setup}.toml"));
    let text = text
        .replace("measurement_1", &format!("measurement_{setup}"))
        .replace("../data/", &data);
    std::fs::write(&path, text).unwrap();
    path
}

/// The modes of one steel-frame setup by `method` at defaults, each checked to be a
/// reference mode (nothing reported that the reference does not have: the unconfirmed
/// columns are listed apart).
fn steel_setup_modes(
    dir: &Path,
    setup: usize,
    method: &str,
) -> Vec<(f64, [f64; 2], f64, [f64; 2])> {
    let path = setup_config(dir, setup);
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text.replace("method = \"ssi-cov\"", &format!("method = \"{method}\""));
    assert!(text.contains(&format!("method = \"{method}\"")));
    std::fs::write(&path, text).unwrap();
    let options = msd_experiment::RunOptions {
        out: Some(dir.join(setup.to_string())),
        ..Default::default()
    };
    let found = modes(
        &msd_experiment::run_experiment(&path, &options)
            .expect("runs")
            .results,
    );
    for (g, ..) in &found {
        assert!(
            REFERENCE.iter().any(|(f, _)| (g / f - 1.0).abs() < 0.005),
            "setup {setup}: {g} Hz is not a reference mode"
        );
    }
    found
}

#[test]
fn every_steel_frame_setup_finds_ten_of_the_eleven_reference_modes_at_defaults() {
    let Some(_) = real_data("steel-frame", "oma: the steel frame") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // Data-driven SSI, measured: 9–11 per setup (two setups lose ζ of two modes
    // beyond 2×), nothing the reference lacks.
    for (method, least) in [("ssi-cov", 10), ("ssi-dat", 9)] {
        for setup in 1..=10 {
            let found = steel_setup_modes(dir.path(), setup, method);
            let matched = REFERENCE
                .iter()
                .filter(|(f, z)| {
                    found.iter().any(|(g, _, w, _)| {
                        (g / f - 1.0).abs() < 0.005 && (0.5..=2.0).contains(&(100.0 * w / z))
                    })
                })
                .count();
            assert!(
                matched >= least,
                "{method}, setup {setup}: {matched} of 11 in {found:?}"
            );
        }
    }
}

/// EFDD at defaults on every setup (measured: 9–10 of the 11 reference modes within 0.5 %
/// per setup, 7–10 with ζ within 0.5–2×; the 1.43 Hz mode, 17 % above the first, is
/// lost in two setups and 13.85 Hz, under the others' flanks, in all): at least nine,
/// nothing the reference lacks.
#[test]
fn efdd_finds_nine_of_the_eleven_modes_on_every_steel_frame_setup() {
    let Some(_) = real_data("steel-frame", "oma: EFDD on the steel frame") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    for setup in 1..=10 {
        let found = steel_setup_modes(dir.path(), setup, "efdd");
        let matched = REFERENCE
            .iter()
            .filter(|(f, _)| found.iter().any(|(g, ..)| (g / f - 1.0).abs() < 0.005))
            .count();
        assert!(matched >= 9, "setup {setup}: {matched} of 11 in {found:?}");
    }
}

/// The shipped ten-setup config: every reference mode found in every setup and merged
/// within 0.5 % of the origin's merged fn, the merged shapes written as UFF 55.
#[test]
fn the_shipped_ten_setup_config_merges_every_reference_mode() {
    let Some(_) = real_data("steel-frame", "oma: the ten setups in one config") else {
        return;
    };
    let run = run_in_temp(&config("steel-frame-setups.toml"), None, None).expect("runs");
    let r = &run.summary.results;
    let found = modes(r);
    assert_eq!(found.len(), REFERENCE.len(), "{found:?}");
    for ((g, ..), (f, _)) in found.iter().zip(&REFERENCE) {
        assert!((g / f - 1.0).abs() < 0.005, "{g} against {f}");
    }
    for found_in in r["merged"]["found"].as_array().unwrap() {
        assert!(found_in.as_array().unwrap().iter().all(|i| i.is_u64()));
    }
    let uff = msd_uff::read(run.out().join("modes.uff")).expect("modes.uff reads back");
    assert_eq!(uff.data_at_nodes.len(), REFERENCE.len());
}

#[test]
fn the_ten_steel_frame_setups_merge_into_global_shapes() {
    let Some(_) = real_data("steel-frame", "oma: the steel frame's setups merged") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let progress = msd_experiment::progress::Progress::new(false);
    let outcomes: Vec<_> = (1..=10)
        .map(|setup| {
            let path = setup_config(dir.path(), setup);
            let config = msd_experiment::config::Config::load(&path).unwrap();
            msd_experiment::operational::run(
                msd_experiment::config::Spec::new(config).expect("an operational config"),
                &Default::default(),
                &progress,
            )
            .expect("runs")
        })
        .collect();
    let setups: Vec<msd_modal::Setup<'_>> = outcomes
        .iter()
        .map(|o| msd_modal::Setup {
            record: &o.record,
            fit: &o.fit,
        })
        .collect();
    let merged = msd_modal::merge_setups(&setups, 0.01).expect("merges");
    // The references: node 24 in x and y, measured in every setup.
    assert_eq!(
        merged.reference_dofs.len(),
        2,
        "{:?}",
        merged.reference_dofs
    );
    let global: Vec<f64> = merged
        .modes
        .iter()
        .map(|m| m.natural_frequency_hz.value)
        .collect();
    for (f, _) in REFERENCE {
        let mode = merged
            .modes
            .iter()
            .find(|m| (m.natural_frequency_hz.value / f - 1.0).abs() < 0.005);
        let Some(mode) = mode else {
            panic!("{f} Hz not among {global:?}")
        };
        // Found in most setups, the roving nodes as x, y, z components.
        assert!(
            mode.stable_orders.unwrap() >= 8,
            "{f} Hz in {} setups",
            mode.stable_orders.unwrap()
        );
        assert!(
            mode.shape.len() >= 2 + 3 * 8,
            "{f} Hz: {} DOFs",
            mode.shape.len()
        );
    }
}
