//! The `xtask` binary itself: help texts, exit statuses (0, 1, 2), output only on
//! success, the summary on stdout and nothing on stderr when it is not a terminal.

use std::path::Path;
use std::process::{Command, Output};

fn xtask(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the xtask binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A small synthetic experiment (4 s at 5 ms, 50 Monte Carlo draws): fast in debug.
const TINY: &str = r#"
name = "tiny"
[plant]
mass = 2.5
damping = 1.8
stiffness = 120.0
[time]
duration = 4.0
dt = 0.005
[noise]
sigma = 0.001
[identification.input]
kind = "chirp"
amplitude = 5.0
f0 = 0.2
f1 = 4.0
duration = 4.0
[validation.input]
kind = "step"
amplitude = 3.0
time = 0.5
[estimation]
initial_guess = { mass = 2.0, damping = 1.0, stiffness = 100.0 }
[monte_carlo]
samples = 50
backend = { kind = "exact" }
"#;

#[test]
fn help_explains_the_tasks() {
    let dir = tempfile::tempdir().unwrap();
    let top = xtask(&["--help"], dir.path());
    assert!(top.status.success());
    let help = text(&top.stdout);
    assert!(help.contains("experiment"), "{help}");
    assert!(help.contains("configs/paper.toml"), "{help}");
    let sub = xtask(&["experiment", "--help"], dir.path());
    assert!(sub.status.success());
    let help = text(&sub.stdout);
    for fragment in [
        "--out",
        "--seed",
        "--threads",
        "--quiet",
        "Exit status",
        "results.json",
        "report.md",
    ] {
        assert!(
            help.contains(fragment),
            "experiment --help lacks {fragment}: {help}"
        );
    }
}

#[test]
fn a_run_exits_0_prints_the_summary_and_writes_the_folder() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("tiny.toml"), TINY).unwrap();
    let run = xtask(
        &["experiment", "tiny.toml", "--out", "out", "--seed", "3"],
        dir.path(),
    );
    assert!(run.status.success(), "{}", text(&run.stderr));
    let stdout = text(&run.stdout);
    assert!(
        stdout.contains("experiment `tiny` (the paper's workflow: synthetic data, seed 3)"),
        "{stdout}"
    );
    assert!(stdout.contains("Monte Carlo"), "{stdout}");
    // Not a terminal: no progress, nothing on stderr.
    assert!(run.stderr.is_empty(), "{}", text(&run.stderr));
    let results = std::fs::read_to_string(dir.path().join("out/results.json")).unwrap();
    assert!(results.contains("\"seed\": 3"), "{results}");
    assert!(dir.path().join("out/report.md").exists());
    assert!(dir.path().join("out/fig4_monte_carlo.svg").exists());
    // Only the finished folder is left beside the config: no staging folder.
    let mut left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["out", "tiny.toml"]);
}

#[test]
fn a_bad_config_exits_2_with_one_line_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bad.toml"),
        TINY.replace("mass = 2.5", "mass = -2.5"),
    )
    .unwrap();
    let run = xtask(&["experiment", "bad.toml", "--out", "out"], dir.path());
    assert_eq!(run.status.code(), Some(2));
    let stderr = text(&run.stderr);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with("error: bad.toml:4: plant.mass = -2.5: expected a finite number > 0"),
        "{stderr}"
    );
    assert!(run.stdout.is_empty());
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(left.len(), 1, "only the config remains");
}

#[test]
fn a_failure_during_the_run_exits_1_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    // No excitation: the parameters cannot be identified and the estimation fails.
    let silent = TINY.replace(
        "kind = \"chirp\"\namplitude = 5.0\nf0 = 0.2\nf1 = 4.0\nduration = 4.0",
        "kind = \"constant\"\nvalue = 0.0",
    );
    std::fs::write(dir.path().join("silent.toml"), silent).unwrap();
    let run = xtask(&["experiment", "silent.toml", "--out", "out"], dir.path());
    assert_eq!(run.status.code(), Some(1), "{}", text(&run.stderr));
    let stderr = text(&run.stderr);
    assert!(stderr.starts_with("error: estimation failed:"), "{stderr}");
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(left.len(), 1, "only the config remains");
}

#[test]
fn bad_arguments_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let run = xtask(&["experiment", "x.toml", "--threads", "0"], dir.path());
    assert_eq!(run.status.code(), Some(2));
    let run = xtask(&["experiment"], dir.path());
    assert_eq!(run.status.code(), Some(2));
}
