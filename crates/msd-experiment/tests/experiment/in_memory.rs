//! The Rust API on records held in memory gives the same numbers as the TOML path on the
//! same record written to a CSV file.

use msd_experiment::{
    RunOptions, config::Config, data::ExperimentData, run_experiment, run_in_memory,
};
use msd_ident::{Backend, DataSet, Excitation, InitialState, Parameters, simulate};
use msd_signal::{gaussian_noise, paper_identification_input};
use serde_json::Value;
use std::fmt::Write as _;

/// The paper's identification record (15 s at 2 ms, σ = 2.5 mm) as plain columns.
fn paper_columns() -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let (dt, n) = (0.002, 7501);
    let excitation = Excitation::from_signal(paper_identification_input(), 0.0, dt, n).unwrap();
    let mut x = simulate(
        &Parameters::PAPER,
        &excitation,
        InitialState::REST,
        &Backend::EXACT,
    )
    .unwrap();
    for (x, e) in x
        .iter_mut()
        .zip(gaussian_noise(1, "identification", 0.0025, n).unwrap())
    {
        *x += e;
    }
    let time = (0..n).map(|i| i as f64 * dt).collect();
    (time, excitation.samples().to_vec(), x)
}

const OPTIONS: &str = r#"
[monte_carlo]
samples = 100
"#;

/// The stage results of a results.json document: what both paths must share.
fn stages(results: &Value) -> Vec<(&'static str, Value)> {
    [
        "estimate",
        "validation",
        "residuals",
        "frequency_check",
        "monte_carlo",
    ]
    .into_iter()
    .map(|key| {
        let mut v = results[key].clone();
        if let Some(map) = v.as_object_mut() {
            map.remove("threads");
            map.remove("wall_time_ms");
        }
        (key, v)
    })
    .collect()
}

#[test]
fn in_memory_records_give_the_numbers_of_the_same_record_read_from_csv() {
    let (time, force, x) = paper_columns();

    // The TOML path: the columns written to a CSV file (shortest round-trip decimals, so
    // every value reads back exactly) and a measured config that names it.
    let dir = tempfile::tempdir().unwrap();
    let mut csv = String::from("t,force,displacement\n");
    for i in 0..time.len() {
        let _ = writeln!(csv, "{},{},{}", time[i], force[i], x[i]);
    }
    std::fs::write(dir.path().join("bench.csv"), csv).unwrap();
    let toml = format!(
        "name = \"bench\"\n[data]\npath = \"bench.csv\"\ninput = \"force\"\noutput = \"displacement\"\ntime = \"t\"\n{OPTIONS}"
    );
    std::fs::write(dir.path().join("bench.toml"), &toml).unwrap();
    let from_file = run_experiment(
        &dir.path().join("bench.toml"),
        &RunOptions {
            out: Some(dir.path().join("file")),
            ..RunOptions::default()
        },
    )
    .expect("the TOML path runs");

    // The Rust path: the same columns, the same options, no file read.
    let set = DataSet::from_columns("bench", &time, force, x).unwrap();
    let mut config = Config::new("bench");
    config.monte_carlo.samples = 100;
    let outcome = run_in_memory(
        config,
        ExperimentData::in_memory(set.clone(), set),
        &RunOptions::default(),
    )
    .expect("the in-memory path runs");
    let written = msd_experiment::write_outcome(&outcome, &dir.path().join("memory")).unwrap();

    assert_eq!(written.results["data"]["source"]["kind"], "in_memory");
    assert_eq!(from_file.results["data"]["source"]["kind"], "measured");
    // Without data.validation the validation part is the estimation part: said, once.
    let notes = from_file.results["data"]["notes"].as_array().unwrap();
    assert_eq!(notes.len(), 1, "{notes:?}");
    let note = notes[0].as_str().unwrap();
    assert!(note.contains("share 7501 samples (100 %)"), "{note}");
    assert!(
        from_file
            .summary
            .contains(&format!("warning        {note}"))
    );
    let f = &written.results["identification"]["f_test"];
    assert_eq!(f["significant"], true, "{f}");
    assert_eq!(f["degrees_of_freedom"][0], 3, "{f}");
    let m = &written.results["estimate"]["mass"];
    assert!(m["value"].as_f64().is_some(), "{m}");
    for ((key, a), (_, b)) in stages(&written.results)
        .into_iter()
        .zip(stages(&from_file.results))
    {
        assert!(a != Value::Null, "{key} missing");
        assert_eq!(a, b, "{key} differs between the in-memory and the CSV path");
    }
    assert!(written.out_dir.join("report.md").exists());
}

#[test]
fn a_config_built_in_rust_is_checked_by_field() {
    let (time, force, x) = paper_columns();
    let set = DataSet::from_columns("bench", &time, force, x).unwrap();
    let mut config = Config::new("bench");
    config.monte_carlo.spread = 1.5;
    let err = run_in_memory(
        config,
        ExperimentData::in_memory(set.clone(), set),
        &RunOptions::default(),
    )
    .unwrap_err();
    assert_eq!(err.exit_code(), 2);
    assert!(
        err.to_string().contains("monte_carlo.spread = 1.5"),
        "{err}"
    );
}
