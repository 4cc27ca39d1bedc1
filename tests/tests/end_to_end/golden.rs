//! Golden results: every shipped config (`configs/*.toml` and `configs/templates/*.toml`)
//! run as `experiment`, `plan` (a synthetic config) and `design` (a config with
//! `[design]`), every number of `results.json`, `plan` and `design` and every cell of every
//! CSV the run writes compared with the files in `tests/golden/`, to 1e-12 relative (the
//! CSV files through fingerprints: see [`fingerprint`]).
//!
//! These pin what the toolkit computes while its code is restructured (issue 29): a change
//! that moves a number past 1e-12 is a change of arithmetic, and must be explained and the
//! files written anew with `MSD_BLESS_GOLDEN=1 cargo test -p msd-tests --test end_to_end
//! golden`. Wall times, thread counts and paths (which differ between machines and runs)
//! are left out. Each run's `report.md` and printed summary are pinned as text too, so
//! that their rendering can be restructured safely. The templates read the files their
//! synthetic runs wrote, as shipped.

use msd_experiment::{RunOptions, run_experiment};
use msd_tests::{real_data, root, without_timings};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// Relative tolerance: a restructuring keeps the arithmetic, so numbers agree to the last
/// few bits (serde_json's float parser may be off by one ulp).
const RELATIVE: f64 = 1e-12;

fn golden_root() -> PathBuf {
    root().join("tests").join("golden")
}

fn bless() -> bool {
    std::env::var_os("MSD_BLESS_GOLDEN").is_some()
}

/// The shipped configs of a folder, sorted.
fn configs_in(dir: &Path) -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("a folder entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    paths.sort();
    paths
}

fn stem(path: &Path) -> String {
    path.file_stem()
        .expect("a file name")
        .to_string_lossy()
        .into_owned()
}

/// The real data set a config reads, if any (skipped when it is not fetched).
fn real_set(path: &Path) -> Option<&'static str> {
    let text = std::fs::read_to_string(path).ok()?;
    ["silverbox", "impact-frf", "steel-frame", "emps"]
        .into_iter()
        .find(|set| text.contains(&format!("data/{set}/")))
}

/// `results.json` without what differs between runs and machines: wall times, threads,
/// and every absolute path in a string.
fn normalised(results: &Value) -> Value {
    let mut v = without_timings(results);
    strip_volatile(&mut v);
    v
}

fn strip_volatile(v: &mut Value) {
    match v {
        Value::Object(map) => {
            map.retain(|k, _| !VOLATILE_KEYS.contains(&k.as_str()));
            for value in map.values_mut() {
                strip_volatile(value);
            }
        }
        Value::Array(items) => items.iter_mut().for_each(strip_volatile),
        Value::String(s) if s.contains('/') => {
            let words: Vec<&str> = s
                .split(' ')
                .map(|w| if absolute(w) { "<path>" } else { w })
                .collect();
            *s = words.join(" ");
        }
        _ => {}
    }
}

/// A report or summary without what differs between runs and machines: the timings
/// (the rows of a `| stage |` table, a summary's `time [ms]` line), the worker threads,
/// the command line and absolute paths.
fn normalised_text(text: &str) -> String {
    let mut out = String::new();
    let mut in_timings = false;
    for line in text.lines() {
        in_timings = (in_timings && line.starts_with('|')) || line.starts_with("| stage |");
        let volatile = ["| worker threads |", "| command |"]
            .iter()
            .any(|p| line.starts_with(p))
            || line.contains("time [ms]");
        if in_timings || volatile {
            continue;
        }
        let words: Vec<&str> = line
            .split(' ')
            .map(|w| if absolute(w) { "<path>" } else { w })
            .collect();
        out.push_str(&words.join(" "));
        out.push('\n');
    }
    out
}

/// Whether a word of a message is an absolute path (possibly quoted).
fn absolute(word: &str) -> bool {
    word.trim_start_matches(['`', '(', '"', '\''])
        .starts_with('/')
}

/// Checks (or, blessing, writes) one golden text, line by line.
fn check_text(file: &Path, now: &str, out: &mut Vec<String>) {
    if bless() {
        return write(file, now);
    }
    let Some(golden) = read(file) else {
        return out.push(format!("{}: no golden file (bless to write it)", rel(file)));
    };
    let (g, n): (Vec<&str>, Vec<&str>) = (golden.lines().collect(), now.lines().collect());
    for (i, (a, b)) in g
        .iter()
        .zip(&n)
        .enumerate()
        .filter(|(_, (a, b))| a != b)
        .take(5)
    {
        out.push(format!(
            "{} line {}: golden `{a}`, now `{b}`",
            rel(file),
            i + 1
        ));
    }
    if g.len() != n.len() {
        out.push(format!(
            "{}: {} lines golden, {} now",
            rel(file),
            g.len(),
            n.len()
        ));
    }
}

/// Keys whose values are wall times or machine facts.
const VOLATILE_KEYS: [&str; 4] = ["design_seconds", "seconds", "elapsed_ms", "version"];

/// Compares two JSON documents; every difference is pushed with its path.
fn compare_json(a: &Value, b: &Value, path: &str, out: &mut Vec<String>) {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => match (x.as_f64(), y.as_f64()) {
            (Some(p), Some(q)) if close(p, q) => {}
            _ => out.push(format!("{path}: golden {x}, now {y}")),
        },
        (Value::Object(x), Value::Object(y)) => {
            for (k, v) in x {
                match y.get(k) {
                    Some(w) if k == "covariance" && compare_covariance(v, w) => {}
                    Some(w) => compare_json(v, w, &format!("{path}.{k}"), out),
                    None => out.push(format!("{path}.{k}: missing now")),
                }
            }
            for k in y.keys().filter(|k| !x.contains_key(*k)) {
                out.push(format!("{path}.{k}: new (not in the golden file)"));
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            for (i, (v, w)) in x.iter().zip(y).enumerate() {
                compare_json(v, w, &format!("{path}[{i}]"), out);
            }
        }
        _ if a == b => {}
        _ => out.push(format!("{path}: golden {a}, now {b}")),
    }
}

/// Whether two covariance matrices agree, each entry to [`RELATIVE`] of √(Σᵢᵢ·Σⱼⱼ): the
/// scale of a covariance is its variances' (an entry near zero against them, as between
/// orthogonal regressors, is rounding noise and carries no digits of its own).
fn compare_covariance(a: &Value, b: &Value) -> bool {
    let matrix = |v: &Value| -> Option<Vec<Vec<f64>>> {
        v.as_array()?
            .iter()
            .map(|row| row.as_array()?.iter().map(Value::as_f64).collect())
            .collect()
    };
    let (Some(a), Some(b)) = (matrix(a), matrix(b)) else {
        return false;
    };
    let n = a.len();
    let square = |m: &[Vec<f64>]| m.iter().all(|row| row.len() == n);
    if b.len() != n || !square(&a) || !square(&b) {
        return false;
    }
    (0..n).all(|i| {
        (0..n).all(|j| {
            let scale = (a[i][i] * a[j][j]).abs().sqrt();
            a[i][j] == b[i][j] || (a[i][j] - b[i][j]).abs() <= RELATIVE * scale
        })
    })
}

fn close(p: f64, q: f64) -> bool {
    p == q || (p - q).abs() <= RELATIVE * p.abs().max(q.abs()) || (p.is_nan() && q.is_nan())
}

/// Rows sampled from each column of a CSV file for its fingerprint.
const SAMPLED_ROWS: usize = 100;

/// A CSV file's fingerprint: its header, its length and, per column, the SHA-256 of the
/// cells' text, the sums Σx, Σ|x| and Σ(i/n)·x, and about [`SAMPLED_ROWS`] cells at even
/// intervals. (The files themselves would take 69 MB.)
fn fingerprint(text: &str) -> Value {
    use sha2::{Digest, Sha256};
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let n = rows.len();
    let step = n.div_ceil(SAMPLED_ROWS).max(1);
    let columns: Vec<Value> = (0..header.split(',').count())
        .map(|c| {
            let cells: Vec<&str> = rows
                .iter()
                .map(|r| r.get(c).copied().unwrap_or(""))
                .collect();
            let numbers: Vec<f64> = cells.iter().filter_map(|x| x.parse().ok()).collect();
            let mut hash = Sha256::new();
            cells.iter().for_each(|x| hash.update(format!("{x}\n")));
            let digest: String = hash.finalize().iter().map(|b| format!("{b:02x}")).collect();
            let weight = |i: usize| i as f64 / n.max(1) as f64;
            serde_json::json!({
                "sha256": digest,
                "numbers": numbers.len(),
                "sum": numbers.iter().sum::<f64>(),
                "abs_sum": numbers.iter().map(|x| x.abs()).sum::<f64>(),
                "ramp_sum": numbers.iter().enumerate().map(|(i, x)| weight(i) * x).sum::<f64>(),
                "samples": cells.iter().step_by(step).collect::<Vec<_>>(),
            })
        })
        .collect();
    serde_json::json!({ "header": header, "rows": n, "columns": columns })
}

/// Compares two CSV fingerprints: a column whose text is not the same must have the
/// same sampled cells to [`RELATIVE`], and sums within [`RELATIVE`] of Σ|x|.
fn compare_fingerprints(golden: &Value, now: &Value, name: &str, out: &mut Vec<String>) {
    if golden["header"] != now["header"] || golden["rows"] != now["rows"] {
        out.push(format!(
            "{name}: header/rows golden {} {}, now {} {}",
            golden["header"], golden["rows"], now["header"], now["rows"]
        ));
        return;
    }
    let empty = Vec::new();
    let columns = |v: &Value| v["columns"].as_array().unwrap_or(&empty).clone();
    for (c, (g, n)) in columns(golden).iter().zip(columns(now).iter()).enumerate() {
        if g["sha256"] == n["sha256"] {
            continue;
        }
        let column = format!("{name} column {c}");
        let number = |v: &Value, key: &str| v[key].as_f64().unwrap_or(f64::NAN);
        let scale = number(g, "abs_sum").max(number(n, "abs_sum"));
        for key in ["sum", "abs_sum", "ramp_sum"] {
            let (a, b) = (number(g, key), number(n, key));
            if !((a - b).abs() <= RELATIVE * scale || a == b) {
                out.push(format!("{column}: {key} golden {a:e}, now {b:e}"));
            }
        }
        let cells = |v: &Value| v["samples"].as_array().unwrap_or(&empty).clone();
        for (i, (a, b)) in cells(g).iter().zip(cells(n).iter()).enumerate() {
            let (a, b) = (a.as_str().unwrap_or(""), b.as_str().unwrap_or(""));
            let same = a == b
                || matches!((a.parse::<f64>(), b.parse::<f64>()), (Ok(u), Ok(v)) if close(u, v));
            if !same {
                out.push(format!("{column}, sample {i}: golden `{a}`, now `{b}`"));
            }
        }
    }
}

/// Checks (or, blessing, writes) one golden JSON document.
fn check_json(file: &Path, now: &Value, out: &mut Vec<String>) {
    if bless() {
        write(
            file,
            &(serde_json::to_string_pretty(now).expect("JSON") + "\n"),
        );
        return;
    }
    match read(file) {
        Some(text) => {
            let golden: Value = serde_json::from_str(&text).expect("a golden JSON file");
            compare_json(&golden, now, &rel(file), out);
        }
        None => out.push(format!("{}: no golden file (bless to write it)", rel(file))),
    }
}

fn rel(file: &Path) -> String {
    file.strip_prefix(golden_root())
        .unwrap_or(file)
        .display()
        .to_string()
}

fn read(file: &Path) -> Option<String> {
    std::fs::read_to_string(file).ok()
}

fn write(file: &Path, text: &str) {
    std::fs::create_dir_all(file.parent().expect("a parent")).expect("a golden folder");
    std::fs::write(file, text).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
}

/// The CSV files of a result folder, sorted by name.
fn csv_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .map(|e| e.expect("a folder entry").path())
                .filter(|p| p.extension().is_some_and(|x| x == "csv"))
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    files
}

/// Runs `config` as `experiment` into `out` and checks results.json and every CSV
/// against `golden/<case>/experiment/`.
fn check_experiment(config: &Path, out: &Path, case: &str, problems: &mut Vec<String>) {
    let dir = golden_root().join(case).join("experiment");
    let options = RunOptions {
        out: Some(out.to_path_buf()),
        ..RunOptions::default()
    };
    let summary = match run_experiment(config, &options) {
        Ok(summary) => summary,
        Err(e) => {
            let now = Value::String(format!("error: {e}"));
            return check_json(&dir.join("error.json"), &normalised(&now), problems);
        }
    };
    check_json(
        &dir.join("results.json"),
        &normalised(&summary.results),
        problems,
    );
    let report = read(&out.join("report.md")).unwrap_or_default();
    check_text(&dir.join("report.md"), &normalised_text(&report), problems);
    check_text(
        &dir.join("summary.txt"),
        &normalised_text(&summary.summary),
        problems,
    );
    let fingerprints: serde_json::Map<String, Value> = csv_files(out)
        .iter()
        .map(|file| {
            let name = file
                .file_name()
                .expect("a name")
                .to_string_lossy()
                .into_owned();
            (name, fingerprint(&read(file).expect("a CSV file")))
        })
        .collect();
    let file = dir.join("csv.json");
    if bless() {
        return check_json(&file, &Value::Object(fingerprints), problems);
    }
    let Some(golden) = read(&file) else {
        return problems.push(format!(
            "{}: no golden file (bless to write it)",
            rel(&file)
        ));
    };
    let golden: serde_json::Map<String, Value> =
        serde_json::from_str(&golden).expect("a golden JSON file");
    let names = |m: &serde_json::Map<String, Value>| m.keys().cloned().collect::<Vec<_>>();
    if names(&golden) != names(&fingerprints) {
        problems.push(format!(
            "{case}: CSV files golden {:?}, now {:?}",
            names(&golden),
            names(&fingerprints)
        ));
    }
    for (name, g) in &golden {
        if let Some(n) = fingerprints.get(name) {
            compare_fingerprints(g, n, &format!("{case}/{name}"), problems);
        }
    }
}

/// `plan` with its default options on a synthetic config (an error is golden too).
fn check_plan(config: &Path, case: &str, problems: &mut Vec<String>) {
    let plan = msd_experiment::plan::plan(config, &Default::default());
    let now = match plan {
        Ok(plan) => serde_json::to_value(&plan).expect("a plan serialises"),
        Err(e) => Value::String(format!("error: {e}")),
    };
    check_json(
        &golden_root().join(case).join("plan.json"),
        &normalised(&now),
        problems,
    );
}

/// `design` (without verification) on a config with `[design]`.
fn check_design(config: &Path, case: &str, problems: &mut Vec<String>) {
    let report = msd_experiment::design::design(config, &Default::default());
    let now = match report {
        Ok(report) => serde_json::to_value(&report).expect("a design serialises"),
        Err(e) => Value::String(format!("error: {e}")),
    };
    check_json(
        &golden_root().join(case).join("design.json"),
        &normalised(&now),
        problems,
    );
}

fn has_section(config: &Path, section: &str) -> bool {
    std::fs::read_to_string(config)
        .is_ok_and(|t| t.lines().any(|l| l.trim_start().starts_with(section)))
}

/// Every config of `configs/`: experiment, plan, design.
fn check_config(config: &Path, out_root: &Path, problems: &mut Vec<String>) {
    let case = stem(config);
    check_experiment(config, &out_root.join(&case), &case, problems);
    if has_section(config, "[plant]") || has_section(config, "[pilot]") {
        check_plan(config, &case, problems);
    }
    if has_section(config, "[design]") {
        check_design(config, &case, problems);
    }
}

/// A template, copied beside the synthetic runs' outputs so that it reads them.
fn check_template(template: &Path, out_root: &Path, problems: &mut Vec<String>) {
    let case = format!("templates-{}", stem(template));
    let text = read(template).expect("a template");
    let folder = out_root.join("templates");
    std::fs::create_dir_all(&folder).expect("a folder");
    let copy = folder.join(template.file_name().expect("a name"));
    let runs = format!("{}/", out_root.display());
    std::fs::write(&copy, text.replace("../../target/experiments/", &runs)).expect("a copy");
    check_experiment(&copy, &out_root.join(&case), &case, problems);
}

#[test]
fn every_shipped_config_computes_the_golden_numbers() {
    let temp = tempfile::tempdir().expect("a temporary folder");
    let fetched = |set: &str| real_data(set, &format!("golden: the {set} configs")).is_some();
    let available = [
        ("silverbox", fetched("silverbox")),
        ("impact-frf", fetched("impact-frf")),
        ("steel-frame", fetched("steel-frame")),
        ("emps", fetched("emps")),
    ];
    let mut problems = Vec::new();
    let mut checked = 0;
    for config in configs_in(&root().join("configs")) {
        if let Some(set) = real_set(&config)
            && !available.iter().any(|&(s, ok)| s == set && ok)
        {
            continue;
        }
        check_config(&config, temp.path(), &mut problems);
        checked += 1;
    }
    for template in configs_in(&root().join("configs").join("templates")) {
        check_template(&template, temp.path(), &mut problems);
        checked += 1;
    }
    assert!(checked >= 20, "only {checked} configs found");
    let mut cases: Vec<&str> = problems
        .iter()
        .filter_map(|p| p.split('/').next())
        .collect();
    cases.dedup();
    assert!(
        problems.is_empty(),
        "{} differences from tests/golden/ in {} (the first 40):\n{}",
        problems.len(),
        cases.join(", "),
        problems
            .iter()
            .take(40)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n")
    );
}
