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

/// Every shipped config with every top-level section it does not have appended (empty):
/// read if its kind reads it (then valid or refused naming it), else refused by name —
/// never silently ignored. Exhaustive over the configs and sections (issue 31, class 4's
/// property).
#[test]
fn every_section_added_to_every_config_is_read_or_refused_by_name() {
    const SECTIONS: [&str; 15] = [
        "setup",
        "plant",
        "time",
        "noise",
        "identification",
        "validation",
        "data",
        "estimation",
        "residuals",
        "frequency_check",
        "monte_carlo",
        "nonlinear",
        "frequency_response",
        "design",
        "pilot",
    ];
    let mut checked = 0;
    for entry in std::fs::read_dir(ROOT).expect("configs") {
        let path = entry.expect("an entry").path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let text = std::fs::read_to_string(&path).expect("a shipped config");
        let doc: toml::Table = toml::from_str(&text).expect("TOML");
        let before = Config::load(&path).expect("the shipped config is valid");
        for section in SECTIONS.iter().filter(|s| !doc.contains_key(**s)) {
            let dir = tempfile::tempdir_in(ROOT).expect("a folder beside the configs");
            let copy = dir.path().join(&name);
            std::fs::write(&copy, format!("{text}\n[{section}]\n")).expect("written");
            checked += 1;
            let reads = reads(&before);
            match Config::load(&copy) {
                // An empty section of defaults that the kind reads.
                Ok(_) => assert!(
                    reads.contains(section),
                    "{name} + [{section}]: accepted, but its kind reads only {reads:?}"
                ),
                Err(e) => {
                    let text = e.to_string();
                    assert_eq!(e.exit_code(), 2, "{name} + [{section}]: {text}");
                    let named = SECTIONS.iter().any(|s| text.contains(s));
                    assert!(named, "{name} + [{section}]: no section named: {text}");
                }
            }
        }
    }
    assert!(checked > 200, "{checked} combinations");
}

/// The sections a config's kind reads, as configs/README.md lists them.
fn reads(config: &Config) -> &'static [&'static str] {
    if config.frequency_only() {
        &["frequency_response"]
    } else if config.setup.is_some() {
        &[
            "setup",
            "plant",
            "time",
            "noise",
            "identification",
            "data",
            "estimation",
            "residuals",
        ]
    } else {
        &[
            "plant",
            "time",
            "noise",
            "identification",
            "validation",
            "data",
            "estimation",
            "residuals",
            "frequency_check",
            "monte_carlo",
            "nonlinear",
            "design",
            "pilot",
        ]
    }
}
