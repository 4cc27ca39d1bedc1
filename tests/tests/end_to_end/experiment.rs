//! `cargo xtask experiment`, end to end, in-process: the paper config reproduces the
//! paper, runs are reproducible for any thread count, the real Silverbox record runs,
//! and every kind of bad input is refused with exit status 2 and nothing written.

use msd_tests::{
    Run, TINY_CONFIG, config, decode_png, listing, lookup, parse_svg, run_in_temp, without_timings,
};
use std::sync::OnceLock;

/// The paper config with its own seed and threads, run once for all tests here.
fn paper() -> &'static Run {
    static RUN: OnceLock<Run> = OnceLock::new();
    RUN.get_or_init(|| {
        run_in_temp(&config("paper.toml"), None, None).expect("the paper config runs")
    })
}

#[test]
fn paper_config_reproduces_the_papers_findings() {
    let run = paper();
    // m, c, k within 4 Cramér–Rao (Gauss–Newton) standard deviations of the truth.
    for (name, truth) in [("mass", 2.5), ("damping", 1.8), ("stiffness", 120.0)] {
        let value = run.number(&format!("estimate.{name}.value"));
        let se = run.number(&format!("estimate.{name}.standard_error"));
        assert!(se > 0.0, "{name}: standard error {se}");
        assert!(
            (value - truth).abs() < 4.0 * se,
            "{name} = {value} is more than 4 standard errors ({se}) from {truth}"
        );
        assert_eq!(run.number(&format!("truth.{name}")), truth);
    }
    // R² on both records as the paper's 0.9907 and 0.9949.
    let r2_id = run.number("identification.r2");
    let r2_val = run.number("validation.r2");
    assert!(
        (r2_id - 0.9907).abs() < 0.003,
        "identification R² = {r2_id}"
    );
    assert!((r2_val - 0.9949).abs() < 0.003, "validation R² = {r2_val}");
    // White residuals, independent of the input.
    assert!(run.flag("residuals.whiteness_passed"));
    assert!(run.flag("residuals.cross_correlation_passed"));
    let p = run.number("residuals.ljung_box.p_value");
    assert!(p > 0.01, "Ljung–Box p = {p}");
    // The 90 % Monte Carlo band holds most of the measurements.
    let coverage = run.number("monte_carlo.coverage");
    assert!(coverage > 0.8, "coverage {coverage}");
    assert_eq!(run.number("monte_carlo.samples"), 1000.0);
    assert_eq!(run.number("monte_carlo.threads"), 2.0);
    // The paper's method throughout.
    let r = &run.summary.results;
    assert_eq!(r["estimate"]["method"], "nelder_mead");
    assert_eq!(r["estimate"]["backend"], "ode45");
    assert_eq!(r["validation"]["backend"], "ode45");
    assert_eq!(r["monte_carlo"]["backend"], "ode45");
    assert_eq!(r["experiment"]["seed"], 1);
    // The frequency check finds the plant's resonance.
    assert!(!run.flag("frequency_check.skipped"));
    let fn_hz = run.number("frequency_check.natural_frequency_hz");
    assert!((fn_hz / 1.1027 - 1.0).abs() < 0.01, "fn = {fn_hz}");
    let zeta = run.number("frequency_check.damping_ratio");
    assert!((zeta / 0.051962 - 1.0).abs() < 0.3, "ζ = {zeta}");
}

#[test]
fn paper_results_json_has_every_required_key() {
    let run = paper();
    let numbers = [
        "estimate.mass.value",
        "estimate.damping.value",
        "estimate.stiffness.value",
        "estimate.natural_frequency_hz.value",
        "estimate.damping_ratio.value",
        "estimate.iterations",
        "estimate.evaluations",
        "truth.mass",
        "truth.damping",
        "truth.stiffness",
        "identification.r2",
        "identification.fit_percent",
        "identification.residual_rms",
        "validation.r2",
        "validation.fit_percent",
        "validation.residual_rms",
        "residuals.ljung_box.q",
        "residuals.ljung_box.p_value",
        "frequency_check.natural_frequency_hz",
        "frequency_check.damping_ratio",
        "monte_carlo.samples",
        "monte_carlo.threads",
        "monte_carlo.coverage",
        "timings_ms.total",
        "timings_ms.data",
        "timings_ms.estimation",
        "timings_ms.validation",
        "timings_ms.residuals",
        "timings_ms.frequency_check",
        "timings_ms.monte_carlo",
        "timings_ms.figures",
        "timings_ms.report",
    ];
    for key in numbers {
        assert!(run.number(key).is_finite(), "{key}");
    }
    for name in [
        "mass",
        "damping",
        "stiffness",
        "natural_frequency_hz",
        "damping_ratio",
    ] {
        let ci = &run.summary.results["estimate"][name]["ci95"];
        let ci = ci
            .as_array()
            .unwrap_or_else(|| panic!("estimate.{name}.ci95"));
        assert_eq!(ci.len(), 2);
        let (lo, hi) = (ci[0].as_f64().unwrap(), ci[1].as_f64().unwrap());
        let value = run.number(&format!("estimate.{name}.value"));
        assert!(lo < value && value < hi, "{name}: {lo} < {value} < {hi}");
    }
    for key in [
        "estimate.method",
        "estimate.backend",
        "experiment.crate_version",
    ] {
        assert!(
            msd_tests::lookup(&run.summary.results, key).is_some_and(|v| v.is_string()),
            "{key}"
        );
    }
    for key in [
        "residuals.whiteness_passed",
        "residuals.cross_correlation_passed",
    ] {
        let _ = run.flag(key);
    }
    // The config as read is in the file.
    assert_eq!(run.summary.results["config"]["plant"]["stiffness"], 120.0);
    // The file on disk is the document returned, byte for byte.
    msd_tests::assert_results_file_is(run.out(), &run.summary.results);
}

#[test]
fn paper_writes_every_output_file() {
    let run = paper();
    let out = run.out();
    for file in [
        "results.json",
        "report.md",
        "report.html",
        "identification.csv",
        "validation.csv",
        "residual_correlation.csv",
        "frf.csv",
    ] {
        let len = std::fs::metadata(out.join(file))
            .map(|m| m.len())
            .unwrap_or(0);
        assert!(len > 100, "{file} is missing or empty");
    }
    for figure in [
        "fig2_identification",
        "fig3_validation",
        "fig4_monte_carlo",
        "residual_correlation",
        "frf_bode",
    ] {
        let (w, h) = decode_png(&out.join(format!("{figure}.png")));
        assert!(w >= 800 && h >= 500, "{figure}.png is {w}×{h}");
        assert!(
            parse_svg(&out.join(format!("{figure}.svg"))) > 50,
            "{figure}.svg"
        );
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    for embedded in [
        "fig2_identification.png",
        "fig3_validation.png",
        "fig4_monte_carlo.png",
    ] {
        assert!(
            report.contains(&format!("]({embedded})")),
            "report.md embeds {embedded}"
        );
    }
    // report.html: the same sections, every figure inline as the SVG written beside it,
    // nothing fetched from elsewhere, a print style sheet with the run's name and page
    // numbers. (`cargo xtask check-report` opens it in a browser.)
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    let problems = msd_experiment::page::self_contained_problems(&html);
    assert!(problems.is_empty(), "report.html: {problems:?}");
    for heading in report.lines().filter_map(|l| l.strip_prefix("## ")) {
        assert!(html.contains(&format!("<h2>{heading}</h2>")), "{heading}");
    }
    let figures = report.lines().filter(|l| l.starts_with("![")).count();
    assert_eq!(html.matches("<figure>").count(), figures);
    let svg = std::fs::read_to_string(out.join("frf_bode.svg")).unwrap();
    let body = &svg[svg.find("<svg").unwrap() + 4..];
    assert!(
        html.contains(body.trim_end()),
        "frf_bode.svg is inline, whole"
    );
    assert!(html.contains("@top-center { content: \"paper · msd toolkit\""));
    assert!(html.contains("counter(page)") && html.contains("break-inside: avoid"));
    // The time series: header and one row per sample.
    let validation = std::fs::read_to_string(out.join("validation.csv")).unwrap();
    let mut lines = validation.lines();
    assert_eq!(
        lines.next(),
        Some(
            "t,input,measured,model,residual,true_response,band_lower,band_median,band_upper,band_nominal"
        )
    );
    assert_eq!(lines.count(), 7501);
    // Only the finished folder remains beside it: no staging folder left behind.
    let parent: Vec<_> = std::fs::read_dir(run.dir.path()).unwrap().collect();
    assert_eq!(parent.len(), 1);
}

#[test]
fn same_config_and_seed_give_identical_results_for_any_thread_count() {
    let reference = without_timings(&paper().summary.results);
    let again = run_in_temp(&config("paper.toml"), Some(1), Some(2)).expect("runs");
    assert_eq!(
        without_timings(&again.summary.results),
        reference,
        "a second run differs"
    );
    let one = run_in_temp(&config("paper.toml"), Some(1), Some(1)).expect("runs");
    assert_eq!(one.number("monte_carlo.threads"), 1.0);
    assert_eq!(
        without_timings(&one.summary.results),
        reference,
        "1 thread differs from 2"
    );
    // The CSV files do not depend on the thread count either.
    for file in ["validation.csv", "identification.csv"] {
        let a = std::fs::read(paper().out().join(file)).unwrap();
        let b = std::fs::read(one.out().join(file)).unwrap();
        assert!(a == b, "{file} differs between 1 and 2 threads");
    }
}

#[test]
fn paper_fast_config_agrees_with_the_paper_method() {
    let fast = run_in_temp(&config("paper-fast.toml"), None, None).expect("paper-fast runs");
    let paper = paper();
    let r = &fast.summary.results;
    assert_eq!(r["estimate"]["method"], "levenberg_marquardt");
    assert_eq!(r["estimate"]["backend"], "exact");
    assert_eq!(r["monte_carlo"]["backend"], "exact");
    // Same data: the two methods land on the same optimum, well within its uncertainty.
    for name in ["mass", "damping", "stiffness"] {
        let a = fast.number(&format!("estimate.{name}.value"));
        let b = paper.number(&format!("estimate.{name}.value"));
        let se = paper.number(&format!("estimate.{name}.standard_error"));
        assert!(
            (a - b).abs() < 0.1 * se,
            "{name}: fast {a} vs paper {b} (se {se})"
        );
    }
    assert!((fast.number("validation.r2") - 0.9949).abs() < 0.003);
    assert!(fast.number("monte_carlo.coverage") > 0.8);
}

/// The real Silverbox record as a lab setup: force V1, displacement V2, fitted on the
/// benchmark's training range and validated on its multisine test range
/// (`[data.estimation]`, `[data.validation]`). The linear model predicts the test range
/// (R² > 0.95, as the paper kind's validation), and the circuit's known cubic spring
/// (Wigren & Schoukens 2013) shows where a linear model's residuals must show it: not
/// white, or correlated with the drive on the fresh data.
#[test]
fn silverbox_as_a_setup_is_validated_on_the_test_range() {
    let test = "silverbox_as_a_setup_is_validated_on_the_test_range";
    let Some(data) = msd_tests::real_data("silverbox", test) else {
        return;
    };
    let dir = tempfile::tempdir().expect("a folder");
    let path = dir.path().join("silverbox-setup.toml");
    let file = data.join("SNLS80mV.csv");
    let text = format!(
        "name = \"silverbox-setup\"\n[setup]\nexcitation = \"force\"\nresponses = [{{ quantity = \"displacement\", column = \"V2\" }}]\n[data]\npath = {:?}\ninput = \"V1\"\nsample_rate = 610.3515625\n[data.estimation]\nrange = [40650, 105712]\n[data.validation]\nrange = [105712, 127400]\n",
        file.display().to_string()
    );
    std::fs::write(&path, text).expect("written");
    let run = run_in_temp(&path, None, None).expect("runs");
    let r = &run.summary.results;
    let v = &r["validation"];
    assert!(
        v["source"]
            .as_str()
            .unwrap()
            .contains("given for validation"),
        "{v}"
    );
    let p = &v["predictions"][0];
    assert_eq!(p["channels"][0]["fit"]["samples"], 127400 - 105712);
    assert!(
        p["channels"][0]["fit"]["r2"].as_f64().unwrap() > 0.95,
        "{p}"
    );
    let tests = &p["residual_analysis"][0];
    assert!(
        tests["whiteness_passed"] == false || tests["cross_correlation_passed"] == false,
        "{tests}"
    );
    assert!(run.summary.summary.contains("validation     on fresh data"));
    // The linear model's verdict on a cubic spring: use with care, and why.
    assert_eq!(r["verdict"]["trustworthy"], false, "{}", r["verdict"]);
    assert!(
        run.summary.summary.contains("verdict        use with care"),
        "{}",
        run.summary.summary
    );
}

#[test]
fn silverbox_config_runs_on_the_real_data_and_reports_the_validation_rms() {
    let test = "silverbox_config_runs_on_the_real_data_and_reports_the_validation_rms";
    if msd_tests::real_data("silverbox", test).is_none() {
        return;
    }
    let run = run_in_temp(&config("silverbox.toml"), None, None).expect("silverbox runs");
    let r = &run.summary.results;
    assert_eq!(r["experiment"]["kind"], "measured");
    assert!(r.get("truth").is_none(), "no truth for measured data");
    assert_eq!(r["data"]["source"]["rows"], 131072);
    assert_eq!(
        r["data"]["source"]["estimation_range"],
        serde_json::json!([40650, 105712])
    );
    assert_eq!(
        r["data"]["source"]["validation_range"],
        serde_json::json!([105712, 127400])
    );
    assert_eq!(r["validation"]["scored_from_sample"], 50);
    assert_eq!(r["estimate"]["initial_guess"]["source"], "automatic (ARX)");
    // The validation RMS error (V) of a linear model on the multisine test: a few mV.
    let rms = run.number("validation.residual_rms");
    assert!(rms > 1e-3 && rms < 2e-2, "validation RMS error {rms} V");
    assert!(run.number("validation.r2") > 0.95);
    // The physical resonance of the circuit, from both the estimate and the spectrum.
    let fn_model = run.number("estimate.natural_frequency_hz.value");
    let fn_data = run.number("frequency_check.natural_frequency_hz");
    assert!(fn_model > 50.0 && fn_model < 90.0, "fn = {fn_model} Hz");
    assert!(
        (fn_model / fn_data - 1.0).abs() < 0.02,
        "model {fn_model} vs data {fn_data} Hz"
    );
    let summary = &run.summary.summary;
    assert!(summary.contains("validation"), "{summary}");
    assert!(
        summary.contains(" V"),
        "the RMS error is printed in volts: {summary}"
    );
    for figure in [
        "fig2_identification",
        "fig3_validation",
        "fig4_monte_carlo",
        "frf_bode",
    ] {
        decode_png(&run.out().join(format!("{figure}.png")));
    }
}

/// A synthetic "lab measurement" in the template's layout: t, force, displacement.
pub(crate) fn lab_csv(dir: &std::path::Path) {
    use msd_ident::{Backend, Excitation, InitialState, Parameters, simulate};
    let input = msd_signal::Signal::Sum {
        terms: vec![
            msd_signal::paper_validation_input(),
            msd_signal::Signal::Step {
                amplitude: 2.0,
                time: 0.3,
            },
        ],
    };
    let exc = Excitation::from_signal(input, 0.0, 0.002, 7501).unwrap();
    let x = simulate(
        &Parameters::PAPER,
        &exc,
        InitialState::REST,
        &Backend::EXACT,
    )
    .unwrap();
    let noise = msd_signal::gaussian_noise(7, "lab", 0.001, x.len()).unwrap();
    let mut text = String::from("# bench rig, synthetic\nt,force,displacement\n");
    for i in 0..x.len() {
        let line = format!(
            "{:.3},{:.6},{:.7}\n",
            exc.times()[i],
            exc.samples()[i],
            x[i] + noise[i] + 0.003
        );
        text.push_str(&line);
    }
    std::fs::write(dir.join("my-measurement.csv"), text).unwrap();
}

#[test]
fn lab_template_works_on_a_users_own_file() {
    let dir = tempfile::tempdir().unwrap();
    lab_csv(dir.path());
    let config_path = dir.path().join("my-experiment.toml");
    std::fs::copy(config("lab-template.toml"), &config_path).unwrap();
    let run = run_in_temp(&config_path, None, None).expect("the template runs on a lab file");
    for (name, truth) in [("mass", 2.5), ("damping", 1.8), ("stiffness", 120.0)] {
        let value = run.number(&format!("estimate.{name}.value"));
        assert!(
            (value / truth - 1.0).abs() < 0.05,
            "{name} = {value}, truth {truth}"
        );
    }
    let offset = run.number("estimate.offset");
    assert!((offset - 0.003).abs() < 5e-4, "offset {offset}");
    assert!(run.number("validation.r2") > 0.98);
    assert_eq!(run.summary.results["validation"]["scored_from_sample"], 50);
}

#[test]
fn other_seeds_reproduce_the_paper_too() {
    // Any seed gives the paper's findings within the stated tolerances (the whiteness
    // test, at 99 % confidence, rejects white residuals for about 1 seed in 100 by
    // design, so it is checked only on the default seed).
    for seed in [2, 3, 4] {
        let run = run_in_temp(&config("paper.toml"), Some(seed), None).expect("runs");
        for (name, truth) in [("mass", 2.5), ("damping", 1.8), ("stiffness", 120.0)] {
            let value = run.number(&format!("estimate.{name}.value"));
            let se = run.number(&format!("estimate.{name}.standard_error"));
            assert!(
                (value - truth).abs() < 4.0 * se,
                "seed {seed}: {name} = {value} ± {se}"
            );
        }
        let (r2_id, r2_val) = (run.number("identification.r2"), run.number("validation.r2"));
        assert!((r2_id - 0.9907).abs() < 0.003, "seed {seed}: R² id {r2_id}");
        assert!(
            (r2_val - 0.9949).abs() < 0.003,
            "seed {seed}: R² val {r2_val}"
        );
        assert!(run.number("monte_carlo.coverage") > 0.8, "seed {seed}");
    }
}

#[test]
fn measured_data_by_index_with_sample_rate_scaling_decimation_and_time_ranges() {
    use msd_ident::{Backend, Excitation, InitialState, Parameters, simulate};
    // 1 kHz, no header, semicolons, columns: a counter, displacement in mm, force in N.
    let input = msd_signal::Signal::Chirp {
        amplitude: 4.0,
        f0: 0.2,
        f1: 4.0,
        duration: 12.0,
        phase: 0.0,
        sweep: msd_signal::Sweep::Linear,
        t_start: 0.0,
    };
    let exc = Excitation::from_signal(input, 0.0, 0.001, 12_001).unwrap();
    let x = simulate(
        &Parameters::PAPER,
        &exc,
        InitialState::REST,
        &Backend::EXACT,
    )
    .unwrap();
    let noise = msd_signal::gaussian_noise(11, "bench", 0.0005, x.len()).unwrap();
    let mut text = String::from("# logger v2\n");
    for i in 0..x.len() {
        text.push_str(&format!(
            "{i};{:.5};{:.6}\n",
            1e3 * (x[i] + noise[i]),
            exc.samples()[i]
        ));
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bench.txt"), &text).unwrap();
    let config_text = r#"
name = "bench"
[data]
path = "bench.txt"
input = 2
output = 1
sample_rate = 1000.0
delimiter = ";"
header = false
output_scale = 0.001
preprocessing = [{ kind = "decimate", factor = 2 }]
[data.estimation]
time = [0.0, 8.0]
[data.validation]
time = [8.0, 12.0]
initial_samples = 20
[estimation]
estimate_initial_state = false
[monte_carlo]
samples = 100
"#;
    std::fs::write(dir.path().join("bench.toml"), config_text).unwrap();
    let run = run_in_temp(&dir.path().join("bench.toml"), None, None).expect("runs");
    let r = &run.summary.results;
    assert_eq!(r["data"]["identification"]["samples"], 4000);
    assert_eq!(r["data"]["validation"]["samples"], 2000); // [8, 12) s: 12 s excluded
    assert_eq!(r["data"]["identification"]["dt"], 0.002);
    for (name, truth) in [("mass", 2.5), ("damping", 1.8), ("stiffness", 120.0)] {
        let value = run.number(&format!("estimate.{name}.value"));
        assert!((value / truth - 1.0).abs() < 0.03, "{name} = {value}");
    }
    assert!(run.number("validation.r2") > 0.99);

    // The same file as a European spreadsheet writes it (decimal commas): with
    // `decimal = ","` the same numbers, bit for bit; without it, refused with the hint.
    let commas = text.replace('.', ",");
    std::fs::write(dir.path().join("bench.txt"), commas).unwrap();
    let with_decimal =
        config_text.replace("delimiter = \";\"", "delimiter = \";\"\ndecimal = \",\"");
    std::fs::write(dir.path().join("comma.toml"), &with_decimal).unwrap();
    let again = run_in_temp(&dir.path().join("comma.toml"), None, None).expect("runs");
    for name in ["mass", "damping", "stiffness"] {
        let key = format!("estimate.{name}.value");
        assert_eq!(again.number(&key), run.number(&key), "{name}");
    }
    let Err(err) = run_in_temp(&dir.path().join("bench.toml"), None, None) else {
        panic!("decimal commas read without decimal = \",\"");
    };
    assert_eq!(err.exit_code(), 2);
    assert!(
        err.to_string().contains("line 2") && err.to_string().contains("decimal = \",\""),
        "{err}"
    );
    // Decimal commas beside the default delimiter: the file's `;` is found and said.
    let found = with_decimal.replace("delimiter = \";\"\n", "");
    std::fs::write(dir.path().join("found.toml"), found).unwrap();
    let third = run_in_temp(&dir.path().join("found.toml"), None, None).expect("runs");
    for name in ["mass", "damping", "stiffness"] {
        let key = format!("estimate.{name}.value");
        assert_eq!(third.number(&key), run.number(&key), "{name}");
    }
    let report = std::fs::read_to_string(third.out().join("report.md")).unwrap();
    assert!(
        report.contains("delimiter ';' (found in the file"),
        "{report}"
    );
    // A decimal point that is also the delimiter stays refused.
    let clash = config_text.replace("delimiter = \";\"", "delimiter = \".\"");
    std::fs::write(dir.path().join("clash.toml"), clash).unwrap();
    let Err(err) = run_in_temp(&dir.path().join("clash.toml"), None, None) else {
        panic!("decimal and delimiter both \".\"");
    };
    assert!(err.to_string().contains("data.decimal"), "{err}");
}

/// A damper past critical damping (ζ ≈ 1.7: c = 60 N·s/m on the paper's m and k) has no
/// resonance for the frequency check to fit. The run still succeeds, identifies the
/// damping within 4 standard errors, and says in the summary, the report and
/// results.json that the check was skipped and why; it writes no FRF file or figure.
#[test]
fn an_overdamped_damper_runs_with_the_frequency_check_skipped() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let text = TINY_CONFIG.replace("damping = 1.8", "damping = 60.0");
    assert_ne!(text, TINY_CONFIG, "the fixture's damping line");
    let path = dir.path().join("overdamped.toml");
    std::fs::write(&path, text).expect("the config");
    let run = run_in_temp(&path, None, None).expect("an over-damped damper runs");

    let (c, se) = (
        run.number("estimate.damping.value"),
        run.number("estimate.damping.standard_error"),
    );
    assert!((c - 60.0).abs() < 4.0 * se, "c = {c} ± {se}");
    assert!(run.number("estimate.damping_ratio.value") > 1.0);

    assert!(run.flag("frequency_check.skipped"));
    let reason = lookup(&run.summary.results, "frequency_check.reason")
        .and_then(serde_json::Value::as_str)
        .expect("a reason");
    assert!(reason.contains("no resonance"), "{reason}");
    assert!(run.summary.results.get("monte_carlo").is_some());
    assert!(
        run.summary
            .summary
            .contains(&format!("frequency      skipped: {reason}")),
        "{}",
        run.summary.summary
    );
    let report = std::fs::read_to_string(run.out().join("report.md")).expect("report.md");
    assert!(report.contains(&format!("Skipped: {reason}.")));
    let files = listing(run.out());
    assert!(files.iter().all(|f| !f.starts_with("frf")), "{files:?}");
    assert!(files.contains(&"fig4_monte_carlo.png".to_string()));
}

/// A measured record whose validation part is too short to resolve the mode (1.5 s of
/// the paper's record, fn ≈ 1.1 Hz) runs from memory (`run_config`, the record given as
/// columns, no data file on disk) with the frequency check skipped and the reason said,
/// not refused: the estimate stands.
#[test]
fn a_validation_record_too_short_for_the_frequency_check_is_skipped_with_its_reason() {
    let paper = msd_ident::PaperExperiment::generate(1).expect("the paper's records");
    let record = &paper.identification;
    let text = r#"
name = "short-validation"
[data]
path = "in-memory.csv"
input = "force"
output = "displacement"
time = "t"
[data.estimation]
time = [0.0, 10.0]
[data.validation]
time = [10.0, 11.5]
[monte_carlo]
samples = 50
"#;
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut config = msd_experiment::config::Config::from_toml_str(text, "config.toml").unwrap();
    config.sources = config.sources.clone().with_columns(
        "in-memory.csv",
        vec![
            ("t".into(), record.excitation.times().to_vec()),
            ("force".into(), record.excitation.samples().to_vec()),
            ("displacement".into(), record.output.clone()),
        ],
    );
    let options = msd_experiment::RunOptions {
        out: Some(dir.path().join("out")),
        ..msd_experiment::RunOptions::default()
    };
    let run = msd_experiment::run_config(config, &options).expect("runs");
    let r = &run.results;
    assert_eq!(r["frequency_check"]["skipped"], true);
    let reason = r["frequency_check"]["reason"].as_str().expect("a reason");
    assert!(
        reason.contains("validation record (1.5") && reason.contains("too short"),
        "{reason}"
    );
    let m = &r["estimate"]["mass"];
    let (value, se) = (
        m["value"].as_f64().unwrap(),
        m["standard_error"].as_f64().unwrap(),
    );
    assert!((value - 2.5).abs() < 4.0 * se, "m = {value} ± {se}");
}

/// Issue 45: a newcomer points the displacement template at an accelerometer column.
/// The fit cannot work (it fits x(t) to an acceleration); the run says so by the key,
/// names the template that reads an accelerometer, and exits 2 (the config is to change).
#[test]
fn an_acceleration_in_the_displacement_template_names_the_accelerometer_template() {
    let dir = tempfile::tempdir().unwrap();
    lab_csv(dir.path());
    // The same rig measured with an accelerometer: the displacement's second difference.
    let text = std::fs::read_to_string(dir.path().join("my-measurement.csv")).unwrap();
    let rows: Vec<Vec<f64>> = (text.lines().skip(2))
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let dt = rows[1][0] - rows[0][0];
    let mut csv = String::from("t,force,accel\n");
    for (i, row) in rows.iter().enumerate() {
        let j = i.clamp(1, rows.len() - 2);
        let a = (rows[j + 1][2] - 2.0 * rows[j][2] + rows[j - 1][2]) / (dt * dt);
        csv.push_str(&format!("{},{},{a}\n", row[0], row[1]));
    }
    std::fs::write(dir.path().join("my-measurement.csv"), csv).unwrap();
    let template = std::fs::read_to_string(config("lab-template.toml")).unwrap();
    assert!(template.contains("output = \"displacement\""));
    let config_path = dir.path().join("my-experiment.toml");
    std::fs::write(
        &config_path,
        template.replacen("output = \"displacement\"", "output = \"accel\"", 1),
    )
    .unwrap();
    let Err(err) = run_in_temp(&config_path, None, None) else {
        panic!("a displacement fit of an acceleration was reported");
    };
    let message = err.to_string();
    assert_eq!(err.exit_code(), 2, "{message}");
    for text in [
        "data.output",
        "looks like an acceleration",
        "configs/templates/accelerometer.toml",
    ] {
        assert!(message.contains(text), "{text}: {message}");
    }
}

/// Issue 42: what the noise model found is shown, each channel's residual spectrum
/// against the model's, in results.json and as a figure (PNG and SVG) in the report.
#[test]
fn a_setup_shows_each_channels_residual_spectrum_against_the_noise_model() {
    let run = run_in_temp(&config("accelerometer.toml"), None, None).expect("runs");
    let whiteness = run.summary.results["whiteness"].as_array().unwrap().clone();
    assert!(!whiteness.is_empty());
    for check in &whiteness {
        let s = &check["spectrum"];
        let bands = s["frequency_hz"].as_array().unwrap().len();
        assert!(bands > 20, "{bands} bands");
        for key in ["lines", "residual", "drive", "lower", "upper"] {
            assert_eq!(s[key].as_array().unwrap().len(), bands, "{key}");
        }
        assert!(s["sensor"].as_f64().unwrap() > 0.0);
    }
    // One panel per channel of the first record.
    let (w, h) = decode_png(&run.out().join("setup_noise_spectrum.png"));
    let first = &whiteness[0]["record"];
    let channels = whiteness.iter().filter(|c| &c["record"] == first).count();
    assert!(w >= 800 && h as usize >= 400 * channels, "{w}×{h}");
    assert!(run.out().join("setup_noise_spectrum.svg").exists());
    let report = std::fs::read_to_string(run.out().join("report.md")).unwrap();
    assert!(report.contains("](setup_noise_spectrum.png)"));
}

/// Round three: an `initial_guess` 100× (or 1/100×) the plant in the accelerometer
/// setup was refused ("does not depend on damping": the search ran c to zero) where
/// the paper's kind converges from it. The guess's gain is matched to the records: the
/// fit reaches the minimum the automatic guess reaches.
#[test]
fn a_setup_converges_from_a_guess_a_hundred_times_off() {
    let auto = run_in_temp(&config("accelerometer.toml"), None, None).expect("auto guess");
    let text = std::fs::read_to_string(config("accelerometer.toml")).unwrap();
    assert!(text.contains("initial_guess = \"auto\""));
    for scale in [100.0, 0.01] {
        let guess = format!(
            "initial_guess = {{ mass = {}, damping = {}, stiffness = {} }}",
            2.5 * scale,
            1.8 * scale,
            120.0 * scale
        );
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("far.toml");
        std::fs::write(&path, text.replace("initial_guess = \"auto\"", &guess)).unwrap();
        let far = run_in_temp(&path, None, None).expect("converges from a far guess");
        for name in ["mass", "damping", "stiffness"] {
            let key = format!("estimate.{name}.value");
            let se = auto.number(&format!("estimate.{name}.standard_error"));
            // One minimum: the two estimates agree far inside one standard error.
            assert!(
                (far.number(&key) - auto.number(&key)).abs() < 1e-3 * se,
                "{scale}×: {name} {} against {}",
                far.number(&key),
                auto.number(&key)
            );
        }
    }
}
