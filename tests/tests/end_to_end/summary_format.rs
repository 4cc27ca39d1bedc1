//! Every kind's printed summary takes one format (the paper's): `experiment `name`
//! (what ran)`, then lines that are either a label in the 14-wide column and its text,
//! a continuation under that text, or a table row; a table's header names its columns
//! (`quantity … 95 % interval`, `mode fn [Hz] … ζ [-] …`); and every summary ends with
//! the stages' times and where the report is. Every report opens with the same head (the
//! name, a sentence on what was identified from what, the run's table) and ends with the
//! same table of timings.

use msd_tests::{config, run_in_temp};

/// The labels a summary line may carry (what a reader scans the column for).
const LABELS: [&str; 22] = [
    "verdict",
    "estimation",
    "ωn",
    "warning",
    "note",
    "validation",
    "noise model",
    "method",
    "residuals",
    "frequency",
    "Monte Carlo",
    "nonlinear",
    "band",
    "noise",
    "coherence",
    "force noise",
    "window",
    "classroom",
    "truth",
    "time domain",
    "ideal sensors",
    "refused",
];

/// Checks `summary` line by line; `name` is the config's.
fn check(name: &str, summary: &str) {
    let lines: Vec<&str> = summary.lines().collect();
    let head = format!("experiment `{name}` (");
    assert!(
        lines[0].starts_with(&head) && lines[0].ends_with(')'),
        "{summary}"
    );
    let mut table = false;
    for line in &lines[1..] {
        if line.is_empty() {
            table = false;
            continue;
        }
        assert!(
            line.starts_with("  ") && !line.ends_with(' '),
            "{line:?} in\n{summary}"
        );
        let body = &line[2..];
        if body.starts_with("quantity ") || body.starts_with("mode ") || body.starts_with("data ") {
            assert!(
                body.contains("95 % interval") || body.contains("R²"),
                "{line}"
            );
            table = true;
            continue;
        }
        if table {
            continue;
        }
        // A labelled line: the label, padded to 14 characters, then one space; or a
        // continuation: 15 spaces.
        let label: String = body.chars().take(14).collect();
        let rest: String = body.chars().skip(14).collect();
        assert!(
            rest.starts_with(' ') && !rest[1..].starts_with(' '),
            "{line:?}"
        );
        let label = label.trim_end();
        assert!(
            label.is_empty()
                || LABELS.contains(&label)
                || label == "time [ms]"
                || label == "report",
            "{label:?} is not a summary label: {line}"
        );
    }
    let n = lines.len();
    assert!(lines[n - 2].starts_with("  time [ms]      ") && lines[n - 2].contains(" · total "));
    assert!(
        lines[n - 1].starts_with("  report         ") && lines[n - 1].ends_with("(and report.md)")
    );
}

#[test]
fn every_kind_prints_its_summary_and_report_head_in_one_format() {
    for name in [
        "paper-fast",
        "repeats",
        "free-decay",
        "damper-test-machine",
        "two-storey",
        "delayed-sensor",
        "frf-table",
        "hammer-2dof",
        "roving-hammer-beam",
        "shear-building",
    ] {
        let run = run_in_temp(&config(&format!("{name}.toml")), None, None).expect(name);
        check(name, &run.summary.summary);
        let report = std::fs::read_to_string(run.out().join("report.md")).expect("report.md");
        let head = format!("# Experiment `{name}`\n\n");
        assert!(report.starts_with(&head), "{name}: {}", &report[..80]);
        let table = format!("| run | |\n|---|---|\n| config | `{name}.toml` |\n");
        assert!(report.contains(&table), "{name}");
        let timings = report
            .rfind("## Timings\n\n| stage | time [ms] |")
            .expect("timings");
        assert!(
            !report[timings..].contains("\n## ") && report.trim_end().ends_with('|'),
            "{name}: the timings end the report"
        );
        assert!(report.contains("| total before this report | "), "{name}");
    }
}
