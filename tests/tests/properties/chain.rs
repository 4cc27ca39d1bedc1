//! Chain configs (issue 46 §4): the two-storey rig, shortened to 2 s, with one to three of
//! its numbers (the drive's rms, a sensor's σ, delay or filter cut-off, a mass, spring or
//! damper of the plant or the guess) multiplied by 1e-200 … 1e200, zeroed, negated or
//! made NaN. A success prints no NaN or infinity and holds no null in `results.json`
//! but the optional values' own; a refusal is one line with its class's exit status
//! (a config error naming the file), and leaves nothing behind.

use crate::{not_a_number, refused_cleanly, scaled_cases};
use msd_experiment::{RunOptions, run_experiment};
use msd_tests::config;
use proptest::prelude::*;
use toml::{Table, Value};

/// The numbers mutated: a dotted path with `[i]` for array items; a missing leaf is
/// inserted at `start` × the factor.
const NUMBERS: [(&str, f64); 9] = [
    ("identification.input.rms", 2.0),
    ("chain.sensors[0].sigma", 0.02),
    ("chain.sensors[1].delay", 0.006),
    ("chain.sensors[0].low_pass.cutoff_hz", 50.0),
    ("chain.plant.masses[0]", 2.0),
    ("chain.plant.springs[1]", 6000.0),
    ("chain.plant.dampers[0]", 3.0),
    ("chain.guess.masses[1]", 1.2),
    ("chain.guess.springs[0]", 10000.0),
];

/// The keys whose value may be null in `results.json`: optional values not set.
const OPTIONAL: [&str; 24] = [
    "noise_model",
    "delay",
    "low_pass",
    "delays",
    "cutoffs",
    "intervals",
    "mass_normalised_shape",
    "modal_mass",
    "stable_orders",
    "window_correction",
    "cost_ratio",
    "degrees_of_freedom",
    "input_noise_fraction",
    "input_noise_sigma",
    "likelihood_ratio",
    "p_value",
    "ljung_box_under_noise_model",
    "white_noise_uncertainty",
    "ideal_sensors",
    "mpc",
    "mpd_deg",
    "cluster_spread",
    "standard_error",
    "validation",
];

/// The number at `path` (created from `start` when missing) multiplied by `factor`.
fn scale(doc: &mut Table, path: &str, start: f64, factor: f64) {
    let mut parts: Vec<&str> = path.split('.').collect();
    let leaf = parts.pop().unwrap();
    let mut t = doc;
    for p in parts {
        let (key, index) = match p.split_once('[') {
            Some((k, i)) => (k, Some(i.trim_end_matches(']').parse::<usize>().unwrap())),
            None => (p, None),
        };
        let v = t.entry(key).or_insert_with(|| Value::Table(Table::new()));
        let v = match index {
            Some(i) => &mut v.as_array_mut().unwrap()[i],
            None => v,
        };
        t = v.as_table_mut().unwrap();
    }
    let (key, index) = match leaf.split_once('[') {
        Some((k, i)) => (k, Some(i.trim_end_matches(']').parse::<usize>().unwrap())),
        None => (leaf, None),
    };
    let slot = match index {
        Some(i) => &mut t.get_mut(key).unwrap().as_array_mut().unwrap()[i],
        None => t.entry(key).or_insert(Value::Float(start)),
    };
    let value = slot
        .as_float()
        .or_else(|| slot.as_integer().map(|i| i as f64))
        .unwrap();
    *slot = Value::Float(value * factor);
}

/// Every null of `v` whose key is not an optional value's, as a dotted path.
fn smuggled(v: &serde_json::Value, key: &str, path: &str, out: &mut Vec<String>) {
    match v {
        serde_json::Value::Null if !OPTIONAL.contains(&key) => out.push(path.to_string()),
        serde_json::Value::Object(m) => {
            for (k, x) in m {
                smuggled(x, k, &format!("{path}.{k}"), out);
            }
        }
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                smuggled(x, key, &format!("{path}[{i}]"), out);
            }
        }
        _ => {}
    }
}

proptest! {
    #![proptest_config(scaled_cases(12, 20))]

    #[test]
    fn mutated_chain_configs_run_with_finite_numbers_or_fail_cleanly(
        changes in prop::collection::vec(
            (
                0usize..NUMBERS.len(),
                prop::sample::select(vec![1e-200, 1e-6, 0.0, -1.0, 1e6, 1e200, f64::NAN]),
            ),
            1..3,
        ),
    ) {
        let shipped = std::fs::read_to_string(config("two-storey.toml")).unwrap();
        let mut doc: Table = toml::from_str(&shipped).unwrap();
        scale(&mut doc, "time.duration", 10.0, 0.2);
        for &(i, factor) in &changes {
            let (path, start) = NUMBERS[i];
            scale(&mut doc, path, start, factor);
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("chain.toml");
        std::fs::write(&path, toml::to_string(&doc).unwrap()).unwrap();
        let out = dir.path().join("out");
        let options = RunOptions { out: Some(out.clone()), ..RunOptions::default() };
        match run_experiment(&path, &options) {
            Ok(run) => {
                let mut found = Vec::new();
                smuggled(&run.results, "", "", &mut found);
                prop_assert!(found.is_empty(), "nulls at {found:?} for {changes:?}");
                for name in ["report.md", "record.csv"] {
                    let body = std::fs::read_to_string(out.join(name)).unwrap();
                    let bad = not_a_number(&body);
                    prop_assert!(bad.is_none(), "{name} holds {bad:?} for {changes:?}");
                }
            }
            Err(e) => refused_cleanly(&e, dir.path(), "chain.toml")?,
        }
    }
}
