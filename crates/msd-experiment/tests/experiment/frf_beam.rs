//! `configs/roving-hammer-beam.toml`: the UFF file it reads is the one the
//! `roving_beam_uff` example writes, and the set's fit finds the beam's modes: every
//! mode, fn within 0.1 %, ζ within 5 %, MAC with the true shape >= 0.99, modal masses
//! of the shapes as the simulation made them.

use msd_experiment::config::{Config, Spec};
use msd_experiment::frf::{self, FrfFit};

#[path = "../../examples/roving_beam_uff.rs"]
mod example;

const CONFIG: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../configs/roving-hammer-beam.toml"
);

#[test]
fn the_shipped_beam_file_is_what_the_example_writes() {
    let shipped = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/data/roving-hammer-beam.uff"
    );
    let bytes = std::fs::read(shipped).expect("the shipped file");
    let written = msd_uff::to_bytes(&example::roving_beam(), &Default::default()).expect("bytes");
    assert!(
        bytes == written,
        "configs/data/roving-hammer-beam.uff differs: run the example again"
    );
    let model = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/data/roving-hammer-beam-model.uff"
    );
    let bytes = std::fs::read(model).expect("the shipped model");
    let written = msd_uff::to_bytes(&example::beam_model(), &Default::default()).expect("bytes");
    assert!(
        bytes == written,
        "configs/data/roving-hammer-beam-model.uff differs: run the example again"
    );
}

/// Issue 30: the shapes against another set of shapes from a file (the model's UFF 55),
/// matched by DOF; and the points' coordinates from the FRF file for the drawing.
#[test]
fn the_shapes_are_compared_with_the_models_file_and_drawn_on_the_geometry() {
    let config = Config::load(CONFIG.as_ref()).expect("valid");
    let outcome = frf::run(
        Spec::new(config).expect("a frequency response"),
        &Default::default(),
    )
    .expect("fits");
    let r = outcome
        .reference_shapes
        .as_ref()
        .expect("reference_shapes given");
    let c = &r.comparison;
    assert_eq!(
        c.shared.len(),
        example::POINTS,
        "the Z DOFs of the ten points"
    );
    assert!(c.only_first.is_empty());
    // The model's X and Y entries (zero) are not measured.
    assert_eq!(c.only_second.len(), 2 * example::POINTS);
    assert_eq!(c.mac.len(), example::MODES.len());
    for (i, best) in c.best_matches().into_iter().enumerate() {
        let (j, mac) = best.expect("five model modes");
        assert_eq!(j, i, "mode {} matches model mode {}", i + 1, j + 1);
        assert!(mac >= 0.99, "mode {}: MAC {mac}", i + 1);
        // Sines of different order are orthogonal over the points: the off-diagonal MAC
        // is the noise's, far below the diagonal.
        for (k, &x) in c.mac[i].iter().enumerate() {
            assert!(k == i || x < 0.05, "MAC[{i}][{k}] = {x}");
        }
    }
    assert_eq!(outcome.geometry.len(), example::POINTS);
    assert!(outcome.indicator.is_some());
    let dir = tempfile::tempdir().expect("a folder");
    let options = msd_experiment::RunOptions {
        out: Some(dir.path().join("beam")),
        ..Default::default()
    };
    let summary = msd_experiment::run_experiment(CONFIG.as_ref(), &options).expect("written");
    for figure in [
        "frf_mac_reference",
        "frf_shapes_geometry",
        "frf_mode_indicator",
    ] {
        assert!(
            summary.out_dir.join(format!("{figure}.png")).is_file(),
            "{figure}.png"
        );
    }
    // Issue 45: the set's figure names every FRF in its key (it named 8 of 10), the MAC
    // map is not a wall (a 5 × 5 MAC in cells of about 90 px).
    let set_fit = std::fs::read_to_string(summary.out_dir.join("frf_set_fit.svg")).expect("svg");
    for point in 1..=example::POINTS {
        let label = format!("3:+3 / {point}:+3");
        assert!(set_fit.contains(&label), "{label} is not in the key");
    }
    let mac = std::fs::read_to_string(summary.out_dir.join("frf_mac.svg")).expect("svg");
    assert!(mac.starts_with("<svg width=\"640\""), "{}", &mac[..60]);
    let report = std::fs::read_to_string(summary.out_dir.join("report.md")).expect("report");
    assert!(report.contains("### Against the shapes of `data/roving-hammer-beam-model.uff`"));
    assert_eq!(
        summary.results["reference_shapes"]["mac"]
            .as_array()
            .map(Vec::len),
        Some(example::MODES.len())
    );
}

#[test]
fn the_roving_hammer_set_gives_the_beams_modes_and_shapes() {
    let config = Config::load(CONFIG.as_ref()).expect("valid");
    let reference = config
        .frequency_response
        .as_ref()
        .and_then(|s| s.reference_modes.clone())
        .expect("the true modes");
    let outcome = frf::run(
        Spec::new(config).expect("a frequency response"),
        &Default::default(),
    )
    .expect("fits");
    let FrfFit::Set(fit) = &outcome.fit else {
        panic!("a set")
    };
    assert_eq!(fit.modes.len(), example::MODES.len(), "{fit}");
    let macs = frf::reference_mac(fit, &reference);
    for (r, (mode, &(fn_hz, zeta))) in fit.modes.iter().zip(&example::MODES).enumerate() {
        let f = mode.natural_frequency_hz.value;
        assert!((f / fn_hz - 1.0).abs() < 1e-3, "mode {}: {f} Hz", r + 1);
        let z = mode.damping_ratio.value;
        assert!((z / zeta - 1.0).abs() < 0.05, "mode {}: ζ = {z}", r + 1);
        assert!(macs[r] >= 0.99, "mode {}: MAC {}", r + 1, macs[r]);
        // The unit shape's modal mass: 0.5 kg / (largest |sin|)².
        let largest = (1..=example::POINTS)
            .map(|i| example::shape(r, i).abs())
            .fold(0.0, f64::max);
        let expected = 0.5 / (largest * largest);
        let mass = mode.modal_mass.expect("point 3 is a driving point");
        assert!(
            (mass / expected - 1.0).abs() < 0.05,
            "mode {}: {mass} kg vs {expected}",
            r + 1
        );
    }
}

/// Issue 30, bad input: a shapes file without shapes, a geometry file without nodes, and
/// either key without a set are exit 2, naming the file or the key.
#[test]
fn shape_and_geometry_files_that_do_not_serve_are_refused_by_name() {
    let dir = tempfile::tempdir().expect("a folder");
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/../../configs/data");
    for file in ["roving-hammer-beam.uff", "roving-hammer-beam-model.uff"] {
        std::fs::copy(format!("{data}/{file}"), dir.path().join(file)).expect("copied");
    }
    let run = |keys: &str, source: &str| {
        let path = dir.path().join("t.toml");
        std::fs::write(
            &path,
            format!("name = \"t\"\n[frequency_response]\n{keys}\n{source}\n"),
        )
        .expect("written");
        let config = Config::load(&path)?;
        frf::run(
            Spec::new(config).expect("a frequency response"),
            &Default::default(),
        )
    };
    let set = "[frequency_response.uff]\npath = \"roving-hammer-beam.uff\"\nset = true";
    let expect = |result: Result<frf::FrfOutcome, msd_experiment::ExperimentError>,
                  parts: &[&str]| {
        let err = result.expect_err("refused");
        assert_eq!(err.exit_code(), 2, "{err}");
        for part in parts {
            assert!(err.to_string().contains(part), "`{part}` not in: {err}");
        }
    };
    expect(
        run("reference_shapes = \"roving-hammer-beam.uff\"", set),
        &["roving-hammer-beam.uff", "no data at nodes (dataset 55)"],
    );
    expect(
        run("geometry = \"roving-hammer-beam-model.uff\"", set),
        &["roving-hammer-beam-model.uff", "no nodes"],
    );
    let one = "[frequency_response.uff]\npath = \"roving-hammer-beam.uff\"";
    expect(
        run("reference_shapes = \"roving-hammer-beam-model.uff\"", one),
        &["frequency_response.reference_shapes", "expected a set"],
    );
}
