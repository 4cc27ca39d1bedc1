//! `[nonlinear]` end to end (issue 11): the Silverbox comparison ranks a cubic-stiffness
//! model first with a validation RMS far below the linear model's; the synthetic
//! nonlinear plant is recovered and its structure selected; one model can be asked
//! for; results, report, CSV and figure are written; configs without the section are
//! unaffected; and every bad form of the section is refused before anything is written.

use msd_experiment::{RunOptions, run_experiment};
use msd_tests::{Run, config, decode_png, lookup, parse_svg, run_in_temp, without_timings};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// configs/paper-nonlinear.toml (quadratic damping + cubic spring, all six compared),
/// run once for the tests here.
fn synthetic() -> &'static Run {
    static RUN: OnceLock<Run> = OnceLock::new();
    RUN.get_or_init(|| {
        run_in_temp(&config("paper-nonlinear.toml"), None, None)
            .expect("the paper-nonlinear config runs")
    })
}

fn nonlinear(run: &Run) -> &Value {
    run.summary
        .results
        .get("nonlinear")
        .expect("results.json has a `nonlinear` object")
}

fn rows(run: &Run) -> &Vec<Value> {
    nonlinear(run)["rows"].as_array().expect("nonlinear.rows")
}

fn row<'a>(run: &'a Run, model: &str) -> &'a Value {
    rows(run)
        .iter()
        .find(|r| r["model"] == model)
        .unwrap_or_else(|| panic!("no row for {model}"))
}

fn num(v: &Value, path: &str) -> f64 {
    lookup(v, path)
        .and_then(Value::as_f64)
        .unwrap_or_else(|| panic!("no number at {path} in {v}"))
}

/// Rows ranked 1, 2, … by increasing BIC, ΔBIC measured from the first, and every
/// parameter's interval around its value.
fn check_ranking(run: &Run) {
    let rows = rows(run);
    let best_bic = num(&rows[0], "bic");
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r["rank"], i + 1);
        let bic = num(r, "bic");
        assert!((num(r, "delta_bic") - (bic - best_bic)).abs() <= 1e-9 * bic.abs());
        if i > 0 {
            assert!(bic >= num(&rows[i - 1], "bic"), "not sorted by BIC");
        }
        let p = num(r, "estimated");
        let n = num(r, "samples");
        let sse = num(r, "sse");
        let log_term = n * (sse / n).ln();
        assert!((num(r, "bic") - (log_term + p * n.ln())).abs() < 1e-6 * log_term.abs());
        assert!((num(r, "aic") - (log_term + 2.0 * p)).abs() < 1e-6 * log_term.abs());
        for (name, iv) in r["parameters"].as_object().expect("parameters") {
            let (v, se) = (num(iv, "value"), num(iv, "standard_error"));
            let ci = iv["ci95"].as_array().expect("ci95");
            let (lo, hi) = (ci[0].as_f64().unwrap(), ci[1].as_f64().unwrap());
            assert!(se > 0.0 && lo < v && v < hi, "{}: {name} {iv}", r["model"]);
        }
    }
}

#[test]
fn silverbox_comparison_ranks_a_cubic_spring_first_with_a_far_lower_validation_rms() {
    let test = "silverbox_comparison_ranks_a_cubic_spring_first_with_a_far_lower_validation_rms";
    if msd_tests::real_data("silverbox", test).is_none() {
        return;
    }
    let run = run_in_temp(&config("silverbox-models.toml"), None, None)
        .expect("the silverbox-models config runs");
    let n = nonlinear(&run);
    assert_eq!(n["mode"], "comparison");
    assert_eq!(n["failures"], serde_json::json!([]));
    check_ranking(&run);
    let models: Vec<&str> = rows(&run)
        .iter()
        .map(|r| r["model"].as_str().unwrap())
        .collect();
    assert_eq!(models.len(), 3, "{models:?}");
    for m in ["viscous+linear", "viscous+cubic", "quadratic_viscous+cubic"] {
        assert!(models.contains(&m), "{m} missing from {models:?}");
    }
    let best = &rows(&run)[0];
    assert_eq!(best["stiffness"], "cubic", "{models:?}");
    assert_eq!(n["best"], best["model"]);
    let linear = row(&run, "viscous+linear");
    assert_eq!(linear["rank"], 3, "the linear model ranks last");
    // The benchmark's validation rule: 50 samples set the initial state, not scored.
    assert_eq!(linear["validation"]["scored_from_sample"], 50);
    let linear_rms = num(linear, "validation.residual_rms");
    for model in ["viscous+cubic", "quadratic_viscous+cubic"] {
        let r = row(&run, model);
        let rms = num(r, "validation.residual_rms");
        assert!(
            rms < 0.5 * linear_rms,
            "{model}: validation RMS {rms} V vs linear {linear_rms} V"
        );
        // A hardening spring, its k₃ many standard errors from zero.
        let k3 = &r["parameters"]["cubic_stiffness"];
        assert!(num(k3, "value") > 10.0 * num(k3, "standard_error"), "{k3}");
    }
    // The cubic spring's evidence over the linear model on the BIC scale: very strong.
    assert!(num(linear, "delta_bic") > 10.0);
    let verdict = n["verdict"].as_str().unwrap();
    assert!(verdict.starts_with("The evidence supports"), "{verdict}");
    assert!(verdict.contains("very strong"), "{verdict}");
    assert!(run.number("timings_ms.nonlinear") > 0.0);
    assert!(n["plant"].is_null());
    // A measured force: RK4 on the cubic hold, its error far below the residuals'.
    let simulation = &best["simulation"];
    assert_eq!(simulation["solver"], "rk4", "{simulation}");
    assert_eq!(simulation["hold"], "cubic", "{simulation}");
    let sigma = (num(best, "sse") / (num(best, "samples") - num(best, "estimated"))).sqrt();
    assert!(
        num(simulation, "error_estimate") < 0.01 * sigma,
        "{simulation}"
    );
    let out = run.out();
    let (w, h) = decode_png(&out.join("nonlinear_residuals.png"));
    assert!(w >= 800 && h >= 500, "{w}×{h}");
    assert!(parse_svg(&out.join("nonlinear_residuals.svg")) > 50);
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("## Beyond linear: nonlinear models"));
    assert!(report.contains("](nonlinear_residuals.png)"));
    assert!(report.contains(verdict), "the report gives the verdict");
    assert!(
        report.contains("RK4 sample by sample on the hold polynomial of the force"),
        "the report names the simulator"
    );
    assert!(report.contains("- `viscous+linear`: RK4 on the cubic hold, "));
    assert!(
        report.contains("the best model's are not white"),
        "the BIC caveat for correlated residuals"
    );
    let csv = std::fs::read_to_string(out.join("nonlinear.csv")).unwrap();
    let mut lines = csv.lines();
    let header = lines.next().unwrap();
    assert!(header.starts_with("t,input,measured,model_"), "{header}");
    assert!(header.contains("residual_viscous+linear"), "{header}");
    assert_eq!(lines.count(), 127_400 - 105_712);
    let summary = &run.summary.summary;
    let line = summary
        .lines()
        .find(|l| l.trim_start().starts_with("nonlinear "))
        .unwrap_or_else(|| panic!("no nonlinear line in {summary}"));
    assert!(line.contains("ranks first of 3 by BIC"), "{line}");
}

#[test]
fn synthetic_nonlinear_plant_is_recovered_and_its_structure_selected() {
    let run = synthetic();
    let n = nonlinear(run);
    assert_eq!(n["mode"], "comparison");
    assert_eq!(rows(run).len(), 6, "all six structures");
    check_ranking(run);
    assert_eq!(n["plant"]["model"], "quadratic_viscous+cubic");
    assert_eq!(n["best"], "quadratic_viscous+cubic");
    let best = row(run, "quadratic_viscous+cubic");
    // Every true value within 4 estimated standard errors.
    for (name, truth) in n["plant"]["parameters"].as_object().unwrap() {
        let truth = truth.as_f64().unwrap();
        let iv = &best["parameters"][name];
        let z = (num(iv, "value") - truth) / num(iv, "standard_error");
        assert!(z.abs() < 4.0, "{name}: {iv} is {z:.1} SE from {truth}");
    }
    // The right model predicts down to the noise: the RMS of 7501 samples of white noise
    // of σ = 2.5 mm lies within ±3 % of σ (its relative SD is 1/√(2N) = 0.8 %); a small
    // model error may add a little.
    let sigma = 0.0025;
    let rms = num(best, "validation.residual_rms");
    assert!(rms > 0.97 * sigma && rms < 1.1 * sigma, "RMS {rms}");
    assert!(best["validation"]["whiteness_passed"].as_bool().unwrap());
    // The linear model misses by far more than the noise.
    assert!(num(row(run, "viscous+linear"), "validation.residual_rms") > 2.0 * sigma);
    // The linear model's data section says how the records were made.
    let report = std::fs::read_to_string(run.out().join("report.md")).unwrap();
    assert!(report.contains("by ode45 (RelTol 1e-8) from the true plant with nonlinear terms"));
    assert!(report.contains("| quadratic_viscous+cubic | cubic_stiffness [N/m³] |"));
}

#[test]
fn nonlinear_results_do_not_depend_on_the_thread_count() {
    let one = run_in_temp(&config("paper-nonlinear.toml"), None, Some(1)).expect("runs");
    assert_eq!(
        without_timings(&one.summary.results),
        without_timings(&synthetic().summary.results),
        "1 thread differs from 2"
    );
    for file in ["nonlinear.csv", "validation.csv"] {
        let a = std::fs::read(one.out().join(file)).unwrap();
        let b = std::fs::read(synthetic().out().join(file)).unwrap();
        assert!(a == b, "{file} differs between 1 and 2 threads");
    }
}

/// A scratch folder for configs written by a test.
fn scratch_config(name: &str, text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

/// The first line of the `[nonlinear]` table in configs/paper-nonlinear.toml.
const COMPARE_ALL: &str = "[nonlinear]\ncompare = \"all\"\n";

/// configs/paper-nonlinear.toml with its `compare = "all"` line replaced by `lines`.
fn synthetic_section(lines: &str) -> String {
    synthetic_with(COMPARE_ALL, &format!("[nonlinear]\n{lines}"))
}

/// configs/paper-nonlinear.toml with `from` replaced by `to` (which must occur).
fn synthetic_with(from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(config("paper-nonlinear.toml")).unwrap();
    assert!(text.contains(from), "paper-nonlinear.toml has no `{from}`");
    text.replacen(from, to, 1)
}

#[test]
fn one_model_can_be_asked_for() {
    let text = synthetic_section("model = { damping = \"viscous\", stiffness = \"cubic\" }\n")
        .replace("samples = 200 ", "samples = 20 ");
    let (_dir, path) = scratch_config("one.toml", &text);
    let dir = tempfile::tempdir().unwrap();
    let options = RunOptions {
        out: Some(dir.path().join("out")),
        ..RunOptions::default()
    };
    let summary = run_experiment(&path, &options).expect("one model runs");
    let n = &summary.results["nonlinear"];
    assert_eq!(n["mode"], "model");
    let rows = n["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 1, "only the model asked for");
    assert_eq!(rows[0]["model"], "viscous+cubic");
    assert_eq!(rows[0]["delta_bic"], 0.0);
    let verdict = n["verdict"].as_str().unwrap();
    assert!(
        verdict.starts_with("One model estimated: viscous+cubic"),
        "{verdict}"
    );
    // Without its quadratic damping the cubic model is biased but still beats the
    // linear model of the estimation stage on the validation data.
    let rms = num(&rows[0], "validation.residual_rms");
    assert!(rms < num(n, "linear_stage_validation_rms"));
    assert!(summary.summary.contains("viscous+cubic: validation RMS"));
    assert!(summary.out_dir.join("nonlinear_residuals.png").exists());
}

#[test]
fn configs_without_the_section_are_unaffected() {
    let run = run_in_temp(&config("paper-fast.toml"), None, None).expect("runs");
    let r = &run.summary.results;
    assert!(r.get("nonlinear").is_none());
    assert!(r["config"].get("nonlinear").is_none());
    for key in ["coulomb_force", "quadratic_damping", "cubic_stiffness"] {
        assert!(r["config"]["plant"].get(key).is_none(), "{key}");
    }
    assert!(r["timings_ms"].get("nonlinear").is_none());
    for file in [
        "nonlinear.csv",
        "nonlinear_residuals.png",
        "nonlinear_residuals.svg",
    ] {
        assert!(!run.out().join(file).exists(), "{file}");
    }
    let report = std::fs::read_to_string(run.out().join("report.md")).unwrap();
    // (The workspace's own path may contain the word: look for what the stage writes.)
    for fragment in ["Beyond linear", "nonlinear_residuals", "nonlinear.csv"] {
        assert!(!report.contains(fragment), "{fragment}");
    }
    assert!(!run.summary.summary.contains("nonlinear models"));
    assert!(!run.summary.summary.contains("\n  nonlinear "));
}

/// Runs `text` as a config and checks the refusal: exit status 2, one line with every
/// fragment, nothing written beside the config.
fn refuses(text: &str, expected: &[&str]) {
    let (dir, path) = scratch_config("c.toml", text);
    let out = dir.path().join("out");
    let options = RunOptions {
        out: Some(out.clone()),
        ..RunOptions::default()
    };
    let err = run_experiment(&path, &options).expect_err("bad input must be refused");
    assert_eq!(err.exit_code(), 2, "{err}");
    let message = err.to_string();
    assert!(!message.contains('\n'), "one line: {message}");
    for fragment in expected {
        assert!(message.contains(fragment), "`{message}` lacks `{fragment}`");
    }
    assert!(!out.exists(), "an output folder was written for: {message}");
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(left.len(), 1, "files appeared for: {message}");
}

/// The 1-based line of the first line of `text` that starts with `start`.
fn line_of(text: &str, start: &str) -> usize {
    text.lines()
        .position(|l| l.starts_with(start))
        .unwrap_or_else(|| panic!("no line starts with {start}"))
        + 1
}

#[test]
fn neither_or_both_of_model_and_compare() {
    let text = synthetic_section("");
    let at = format!("c.toml:{}: ", line_of(&text, "[nonlinear]"));
    refuses(
        &text,
        &[
            &at,
            "nonlinear: neither `model` nor `compare` given: expected exactly one",
        ],
    );
    let text = synthetic_section(
        "model = { damping = \"viscous\", stiffness = \"cubic\" }\ncompare = \"all\"\n",
    );
    let at = format!("c.toml:{}: ", line_of(&text, "compare"));
    refuses(
        &text,
        &[
            &at,
            "nonlinear.compare: both `model` and `compare` given: expected exactly one",
        ],
    );
}

#[test]
fn bad_candidate_lists() {
    let text = synthetic_section("compare = []\n");
    refuses(
        &text,
        &[
            "nonlinear.compare = []: expected \"all\" or at least one candidate",
            "the linear baseline is always added",
        ],
    );
    let cubic = "{ damping = \"viscous\", stiffness = \"cubic\" }";
    let text = synthetic_section(&format!("compare = [{cubic}, {cubic}]\n"));
    let at = format!("c.toml:{}: ", line_of(&text, "compare"));
    refuses(
        &text,
        &[
            &at,
            "nonlinear.compare[1] = viscous+cubic: the same candidate as compare[0]: expected each candidate once",
        ],
    );
    let text = synthetic_section("compare = \"every\"\n");
    let at = format!("c.toml:{}:11", line_of(&text, "compare"));
    refuses(
        &text,
        &[
            &at,
            "invalid value: string \"every\", expected \"all\" or a list of { damping, stiffness }",
        ],
    );
    let text = synthetic_section("compare = [{ damping = \"dry\", stiffness = \"cubic\" }]\n");
    refuses(
        &text,
        &[
            &format!("c.toml:{}:", line_of(&text, "compare")),
            "unknown variant `dry`, expected one of `viscous`, `coulomb_viscous`, `quadratic_viscous`",
        ],
    );
    let text = synthetic_section("model = { damping = \"viscous\", stifness = \"cubic\" }\n");
    refuses(
        &text,
        &[
            &format!("c.toml:{}:", line_of(&text, "model")),
            "unknown field `stifness`, expected `damping` or `stiffness`",
        ],
    );
    let text = synthetic_section("model = { damping = \"viscous\" }\n");
    refuses(&text, &["c.toml:", "missing field `stiffness`"]);
}

#[test]
fn bad_options() {
    refuses(
        &synthetic_section("compare = \"all\"\ncolour = 1\n"),
        &["c.toml:", "unknown field `colour`"],
    );
    refuses(
        &synthetic_with(
            "method = \"levenberg_marquardt\"   # or",
            "method = \"gauss_newton\"   # or",
        ),
        &[
            "c.toml:",
            "unknown variant `gauss_newton`, expected `levenberg_marquardt` or `nelder_mead`",
        ],
    );
    let text = synthetic_with("rel_tol = 1e-8 ", "rel_tol = 0.0 ");
    refuses(
        &text,
        &[
            &format!("c.toml:{}: ", line_of(&text, "rel_tol = 0.0")),
            "nonlinear.simulation.rel_tol = 0: expected a finite number > 0",
        ],
    );
    let text = synthetic_with("{ relative = 1e-3 }", "{ relative = -1.0 }");
    refuses(
        &text,
        &[
            &format!("c.toml:{}: ", line_of(&text, "smoothing_velocity")),
            "nonlinear.simulation.smoothing_velocity.relative = -1: expected a finite number > 0",
        ],
    );
    refuses(
        &synthetic_with("# max_evaluations = 100 ", "max_evaluations = 0 "),
        &["nonlinear.max_evaluations = 0: expected an integer >= 1"],
    );
    refuses(
        &synthetic_with(
            "# [nonlinear.multistart]       # off unless given\n# starts = 8 ",
            "[nonlinear.multistart]\nstarts = 1 ",
        ),
        &["nonlinear.multistart.starts = 1: expected an integer >= 2"],
    );
    refuses(
        &synthetic_with(
            "# [nonlinear.multistart]       # off unless given\n# starts = 8                   # local runs, the nominal start included\n# decades = 0.5 ",
            "[nonlinear.multistart]\ndecades = -0.5 ",
        ),
        &["nonlinear.multistart.decades = -0.5: expected a finite number > 0"],
    );
    let text = synthetic_with("estimate_offset = false ", "estimate_offset = true ");
    refuses(
        &text,
        &[
            &format!("c.toml:{}: ", line_of(&text, "[nonlinear]")),
            "nonlinear: not available with a sensor offset (estimation.estimate_offset = true",
        ],
    );
}

#[test]
fn bad_nonlinear_plants() {
    let text = synthetic_with("# coulomb_force = 0.5 ", "coulomb_force = 0.5 ");
    refuses(
        &text,
        &[
            &format!("c.toml:{}: ", line_of(&text, "quadratic_damping")),
            "plant.quadratic_damping = 3: given with coulomb_force = 0.5: expected at most one nonlinear damping term",
        ],
    );
    refuses(
        &synthetic_with("quadratic_damping = 3.0 ", "quadratic_damping = -3.0 "),
        &["plant.quadratic_damping = -3: expected a finite number >= 0"],
    );
    refuses(
        &synthetic_with("cubic_stiffness = 3000.0 ", "cubic_stiffness = nan "),
        &["plant.cubic_stiffness = NaN: expected a finite number"],
    );
}

#[test]
fn the_shipped_configs_document_every_nonlinear_key() {
    let readme = std::fs::read_to_string(config("README.md")).unwrap();
    let shipped = std::fs::read_to_string(config("paper-nonlinear.toml")).unwrap();
    for key in [
        "model",
        "compare",
        "method",
        "estimate_initial_state",
        "dissipative_damping",
        "max_evaluations",
        "solver",
        "hold",
        "rel_tol",
        "abs_tol",
        "smoothing_velocity",
        "starts",
        "decades",
        "nonlinear_width",
        "seed",
        "coulomb_force",
        "quadratic_damping",
        "cubic_stiffness",
    ] {
        assert!(readme.contains(&format!("{key}`")), "README lacks `{key}`");
        assert!(shipped.contains(key), "paper-nonlinear.toml lacks {key}");
    }
    assert!(Path::new(&config("silverbox-models.toml")).exists());
}

/// Issue 42: the generating model's identification residuals are white, so its
/// intervals are s²·(JᵀJ)⁻¹'s; the linear candidate misses the nonlinear forces, its
/// residuals are coloured, and its intervals are the block sandwich's — wider than the
/// white-noise ones listed beside them — and the report says which ran for each.
#[test]
fn coloured_residuals_get_the_sandwich_and_white_ones_do_not() {
    let run = synthetic();
    let generating = row(run, "quadratic_viscous+cubic");
    assert_eq!(generating["covariance"]["sandwich"], false, "{generating}");
    assert!(generating.get("white_noise_parameters").is_none());
    let linear = row(run, "viscous+linear");
    assert_eq!(linear["covariance"]["sandwich"], true, "{linear}");
    let sandwich = num(linear, "parameters.stiffness.standard_error");
    let white = num(linear, "white_noise_parameters.stiffness.standard_error");
    assert!(sandwich > white, "sandwich {sandwich} vs white {white}");
    let report = std::fs::read_to_string(run.out().join("report.md")).unwrap();
    assert!(report.contains("viscous+linear: intervals from the block sandwich over 20 blocks"));
}
