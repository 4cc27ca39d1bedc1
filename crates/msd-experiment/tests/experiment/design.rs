//! `design`: the D-optimal design of configs/design-paper.toml against simulated tests,
//! its files, and the constraints the command refuses (exit 2, naming the key).

use msd_experiment::design::{DesignRunOptions, design, write};
use std::path::{Path, PathBuf};
use std::process::Command;

fn config(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../configs")
        .join(name)
}

/// The D-optimal design beats the paper's input on its criterion (the target:
/// det(cov)^(1/6) ratio ≤ 0.40), and over 300 simulated tests (Levenberg–Marquardt on
/// the exact simulation) each standard deviation is its prediction within 12.5 % (the
/// relative standard error of a standard deviation from 300 draws is 1/√598 = 4.1 %:
/// 12.5 % is 3σ).
#[test]
fn the_d_optimal_design_beats_the_paper_input_and_its_prediction_holds() {
    let options = DesignRunOptions {
        verify: 300,
        ..DesignRunOptions::default()
    };
    let report = design(&config("design-paper.toml"), &options).unwrap();
    let c = &report.design.comparison;
    assert!(c.determinant_ratio <= 0.40, "{report}");
    let v = report.verification.as_ref().unwrap();
    for ratio in v.ratios {
        assert!((ratio - 1.0).abs() <= 0.125, "{report}");
    }
    assert!(
        report.to_string().contains("simulated over 300 seeds"),
        "{report}"
    );
}

/// The files: the CSV has the record's samples, the written config loads, and planning
/// it predicts the design's own standard errors.
#[test]
fn the_designed_config_runs_the_designed_test() {
    let path = config("design-paper-a.toml");
    let report = design(&path, &DesignRunOptions::default()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let cfg = msd_experiment::config::Config::load(&path).unwrap();
    write(&report, &cfg, &out).unwrap();
    let csv = std::fs::read_to_string(out.join("designed_input.csv")).unwrap();
    assert_eq!(csv.lines().next(), Some("t,force"));
    assert_eq!(csv.lines().count(), 7502);
    for figure in ["design.png", "design.svg", "design.json"] {
        assert!(out.join(figure).is_file(), "{figure}");
    }
    let plan = msd_experiment::plan::plan(&out.join("designed.toml"), &Default::default()).unwrap();
    let predicted = report.design.comparison.design;
    for (name, se) in ["mass", "damping", "stiffness"].iter().zip(predicted) {
        let planned = plan.quantity(name).unwrap().standard_error;
        assert!(
            (planned / se - 1.0).abs() < 1e-9,
            "{name}: {planned} vs {se}"
        );
    }
}

/// `msd design` refuses a stroke below the required step's static deflection, an empty
/// band and a band above Nyquist with exit status 2 and the key.
#[test]
fn bad_constraints_exit_2_naming_their_key() {
    let text = std::fs::read_to_string(config("design-paper.toml")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "# step = { time = 0.5, min_amplitude = 0.0 }",
            "step = { time = 0.5, min_amplitude = 9.0 }\nmax_rms_force = 9.0",
            "design.constraints.max_stroke",
        ),
        (
            "band_hz = [0.2, 4.2]",
            "band_hz = [3.0, 1.0]",
            "design.constraints.band_hz = 1: expected an upper edge above",
        ),
        (
            "band_hz = [0.2, 4.2]",
            "band_hz = [0.2, 400.0]",
            "below the Nyquist frequency 250 Hz",
        ),
    ];
    for (from, to, expected) in cases {
        let edited = text
            .replace(from, to)
            .replace("max_stroke = 0.1115", "max_stroke = 0.05");
        assert_ne!(edited, text);
        let file = dir.path().join("bad.toml");
        std::fs::write(&file, edited).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_msd"))
            .arg("design")
            .arg(&file)
            .current_dir(dir.path())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(
            stderr.contains(expected) && stderr.contains("bad.toml"),
            "{stderr}"
        );
    }
}
