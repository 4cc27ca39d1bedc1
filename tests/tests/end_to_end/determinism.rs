//! Determinism of the paper pipeline: the same config and seed give the same results,
//! bit for bit, on any number of threads; and the random streams are independent, so
//! drawing more from one (more Monte Carlo samples, another validation input) leaves the
//! identification data and the estimate exactly as they were.

use msd_tests::{Run, config, run_in_temp, without_timings};
use serde_json::Value;

/// Every number of `a` and `b` (JSON documents of the same shape) with equal bits, every
/// other value equal; the first difference is reported with its path.
fn assert_bitwise_equal(a: &Value, b: &Value, path: &str) {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            match (x.as_f64(), y.as_f64()) {
                (Some(p), Some(q)) => assert!(
                    p.to_bits() == q.to_bits(),
                    "{path}: {p:e} vs {q:e} ({:#x} vs {:#x})",
                    p.to_bits(),
                    q.to_bits()
                ),
                _ => assert_eq!(x, y, "{path}"),
            }
            // Integers and floats are not interchangeable either.
            assert_eq!(x.is_f64(), y.is_f64(), "{path}: {x} vs {y}");
        }
        (Value::Object(x), Value::Object(y)) => {
            let keys: Vec<&String> = x.keys().collect();
            assert_eq!(keys, y.keys().collect::<Vec<_>>(), "{path}: keys differ");
            for (k, v) in x {
                assert_bitwise_equal(v, &y[k], &format!("{path}.{k}"));
            }
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{path}: lengths differ");
            for (i, (v, w)) in x.iter().zip(y).enumerate() {
                assert_bitwise_equal(v, w, &format!("{path}[{i}]"));
            }
        }
        _ => assert_eq!(a, b, "{path}"),
    }
}

/// How many numbers a document holds (so a comparison is known not to be vacuous).
fn count_numbers(v: &Value) -> usize {
    match v {
        Value::Number(_) => 1,
        Value::Object(m) => m.values().map(count_numbers).sum(),
        Value::Array(a) => a.iter().map(count_numbers).sum(),
        _ => 0,
    }
}

#[test]
fn paper_results_are_bit_identical_on_1_2_and_4_threads_for_seeds_1_2_3() {
    let mut per_seed = Vec::new();
    for seed in [1u64, 2, 3] {
        let runs: Vec<Run> = [1usize, 2, 4]
            .iter()
            .map(|&threads| {
                run_in_temp(&config("paper.toml"), Some(seed), Some(threads)).expect("runs")
            })
            .collect();
        for (run, threads) in runs.iter().zip([1.0, 2.0, 4.0]) {
            msd_tests::assert_results_file_is(run.out(), &run.summary.results);
            assert_eq!(run.number("monte_carlo.threads"), threads);
            assert_eq!(run.number("experiment.seed"), seed as f64);
        }
        let reference = without_timings(&runs[0].summary.results);
        // About 480 numbers: the config, estimates, intervals, correlations, metrics,
        // correlation lags, the frequency check, the Monte Carlo summary.
        assert!(
            count_numbers(&reference) > 400,
            "{} numbers",
            count_numbers(&reference)
        );
        for (run, threads) in runs.iter().zip([1, 2, 4]).skip(1) {
            assert_bitwise_equal(
                &without_timings(&run.summary.results),
                &reference,
                &format!("seed {seed}, {threads} vs 1 threads: results"),
            );
            for file in ["identification.csv", "validation.csv", "frf.csv"] {
                let a = std::fs::read(runs[0].out().join(file)).unwrap();
                let b = std::fs::read(run.out().join(file)).unwrap();
                assert!(a == b, "seed {seed}: {file} differs on {threads} threads");
            }
        }
        per_seed.push(reference);
    }
    // Not vacuous: other seeds give other numbers.
    assert_ne!(per_seed[0]["estimate"], per_seed[1]["estimate"]);
    assert_ne!(per_seed[1]["monte_carlo"], per_seed[2]["monte_carlo"]);
}

/// The paper config with `from` replaced by `to`, written beside a temporary folder.
fn paper_variant(dir: &std::path::Path, from: &str, to: &str) -> std::path::PathBuf {
    let text = std::fs::read_to_string(config("paper.toml")).unwrap();
    assert!(text.contains(from), "paper.toml has no `{from}`");
    let path = dir.join("variant.toml");
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path
}

/// The columns of a CSV file up to (not including) the first whose name starts with
/// `stop`.
fn csv_columns_before(path: &std::path::Path, stop: &str) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let keep = header
        .iter()
        .position(|h| h.starts_with(stop))
        .unwrap_or(header.len());
    assert!(keep >= 4, "{}: {header:?}", path.display());
    text.lines()
        .map(|l| l.split(',').take(keep).collect::<Vec<_>>().join(","))
        .collect()
}

#[test]
fn more_monte_carlo_draws_or_another_validation_input_leave_the_identification_alone() {
    let dir = tempfile::tempdir().unwrap();
    let base = run_in_temp(&config("paper.toml"), Some(1), None).expect("runs");
    // Twice the Monte Carlo draws: the Monte Carlo stream is consumed twice as far.
    let more = paper_variant(dir.path(), "samples = 1000 ", "samples = 2000 ");
    let more = run_in_temp(&more, Some(1), None).expect("runs");
    assert_eq!(more.number("monte_carlo.samples"), 2000.0);
    assert_ne!(
        base.summary.results["monte_carlo"],
        more.summary.results["monte_carlo"]
    );
    for section in [
        "data",
        "estimate",
        "identification",
        "validation",
        "residuals",
        "frequency_check",
    ] {
        assert_bitwise_equal(
            &more.summary.results[section],
            &base.summary.results[section],
            &format!("2000 draws: {section}"),
        );
    }
    for file in ["identification.csv", "frf.csv"] {
        let a = std::fs::read(base.out().join(file)).unwrap();
        let b = std::fs::read(more.out().join(file)).unwrap();
        assert!(a == b, "2000 draws: {file} differs");
    }
    assert_eq!(
        csv_columns_before(&base.out().join("validation.csv"), "band_"),
        csv_columns_before(&more.out().join("validation.csv"), "band_"),
        "2000 draws: the validation record differs"
    );

    // Another validation input (its own noise stream, a different record): the
    // identification record, its noise and the estimate do not move.
    let other = paper_variant(
        dir.path(),
        "amplitude = 2.5    # N\nf0 = 0.2",
        "amplitude = 4.0    # N\nf0 = 0.2",
    );
    let other = run_in_temp(&other, Some(1), None).expect("runs");
    assert_ne!(
        other.summary.results["validation"],
        base.summary.results["validation"]
    );
    for section in ["estimate", "identification", "residuals"] {
        assert_bitwise_equal(
            &other.summary.results[section],
            &base.summary.results[section],
            &format!("other validation input: {section}"),
        );
    }
    let a = std::fs::read(base.out().join("identification.csv")).unwrap();
    let b = std::fs::read(other.out().join("identification.csv")).unwrap();
    assert!(a == b, "other validation input: identification.csv differs");
}

/// The comparison itself: one ulp anywhere, or an integer where a float was, is a
/// difference.
#[test]
fn the_comparison_sees_a_single_ulp() {
    let a = serde_json::json!({"x": [1.0, {"y": 0.1}], "n": 3});
    let next = f64::from_bits(0.1f64.to_bits() + 1);
    let b = serde_json::json!({"x": [1.0, {"y": next}], "n": 3});
    let caught = std::panic::catch_unwind(|| assert_bitwise_equal(&a, &b, "doc"));
    let message = caught.expect_err("one ulp differs");
    let text = message
        .downcast_ref::<String>()
        .cloned()
        .unwrap_or_default();
    assert!(text.starts_with("doc.x[1].y: "), "{text}");
    let c = serde_json::json!({"x": [1, {"y": 0.1}], "n": 3});
    assert!(std::panic::catch_unwind(|| assert_bitwise_equal(&a, &c, "doc")).is_err());
    assert_bitwise_equal(&a, &a.clone(), "doc");
}
