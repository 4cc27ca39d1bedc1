//! Issue 31, class 4: a section the config's kind does not read is refused by name (exit
//! 2), with the kind and the sections it reads, instead of being ignored.

use msd_experiment::config::Config;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../configs/");

/// A shipped config with `extra` appended, loaded from a copy beside the original (so
/// that its relative paths still resolve).
fn load_with(config: &str, extra: &str) -> msd_experiment::ExperimentError {
    let text = std::fs::read_to_string(format!("{ROOT}{config}")).expect("a shipped config");
    let dir = tempfile::tempdir_in(ROOT).expect("a folder beside the configs");
    let path = dir.path().join(config);
    std::fs::write(&path, format!("{text}\n{extra}\n")).expect("written");
    Config::load(&path).expect_err("refused")
}

#[test]
fn a_section_the_kind_does_not_read_is_refused_by_name() {
    for (config, extra, section, kind) in [
        (
            "free-decay.toml",
            "[nonlinear]\ncompare = \"all\"",
            "nonlinear",
            "[setup] config",
        ),
        (
            "free-decay.toml",
            "[design]\nlines = 10",
            "design",
            "[setup] config",
        ),
        (
            "paper-fast.toml",
            "[frequency_response.sweep]\nband_hz = [0.2, 3.0]\nlines = 40",
            "frequency_response",
            "force-and-displacement config",
        ),
        (
            "stepped-sine.toml",
            "[monte_carlo]\nsamples = 10",
            "monte_carlo",
            "frequency-response config",
        ),
    ] {
        let err = load_with(config, extra);
        let text = err.to_string();
        assert_eq!(err.exit_code(), 2, "{text}");
        assert!(
            text.contains(section) && text.contains(kind) && text.contains("it reads"),
            "{config} + [{section}]: {text}"
        );
    }
}
