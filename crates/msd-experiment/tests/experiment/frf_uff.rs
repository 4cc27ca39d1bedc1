//! The UFF file `configs/frf-uff.toml` reads is the one the `frf_uff` example writes.

#[path = "../../examples/frf_uff.rs"]
mod example;

#[test]
fn the_shipped_uff_file_is_what_the_example_writes() {
    let shipped = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/data/frf-2dof.uff"
    );
    let bytes = std::fs::read(shipped).expect("the shipped file");
    let written = msd_uff::to_bytes(&example::frf_2dof(), &Default::default()).expect("bytes");
    assert!(
        bytes == written,
        "configs/data/frf-2dof.uff differs: run the example again"
    );
    // And it reads back as the file's contents (to the 13 digits of its ASCII columns).
    let read = msd_uff::parse(&bytes).expect("reads");
    assert_eq!(read.functions.len(), 1);
    assert_eq!(read.functions[0].len(), 200);
}

/// A UFF 58 as pyuff writes an accelerance when its ordinate type is "general" (1): the
/// quantity is in the units, `(1/N)*(m/s2)`. Read as such, the one-mode fit gives the
/// plant's m, c, k (noise-free: to 1e-6); read as a receptance it would not (the issue's
/// silent failure). Without `kind` and without units saying, the file is refused.
#[test]
fn a_general_ordinate_is_read_by_its_units() {
    use msd_experiment::config::Config;
    use msd_experiment::frf::{self, FrfFit};
    use msd_uff::{Abscissa, Function58, FunctionType, Ordinate, UffFile};
    let (m, c, k) = (2.5, 1.8, 120.0);
    let accelerance: Vec<(f64, f64)> = (1..=200)
        .map(|i| {
            let w = std::f64::consts::TAU * 0.02 * i as f64;
            // A = −ω²/(k − mω² + jcω)
            let (re, im) = (k - m * w * w, c * w);
            let d = re * re + im * im;
            (-w * w * re / d, w * w * im / d)
        })
        .collect();
    let write = |units: &str| {
        let mut f = Function58::new(
            FunctionType::FrequencyResponse,
            Abscissa::Even {
                start: 0.02,
                step: 0.02,
            },
            Ordinate::Complex(accelerance.clone()),
        );
        f.abscissa_axis.data_type = 18;
        f.ordinate_axis.data_type = 1;
        f.ordinate_axis.units = units.into();
        let file = UffFile {
            functions: vec![f],
            ..UffFile::default()
        };
        msd_uff::to_bytes(&file, &Default::default()).expect("bytes")
    };
    let dir = tempfile::tempdir().expect("a folder");
    let config_text = r#"
name = "general-accelerance"
[frequency_response.uff]
path = "frf.uff"
[frequency_response.one_mode]
weighting = "relative"
"#;
    let path = dir.path().join("config.toml");
    std::fs::write(&path, config_text).expect("config");
    std::fs::write(dir.path().join("frf.uff"), write("(1/N)*(m/s2)")).expect("uff");
    let config = Config::load(&path).expect("valid");
    let outcome = frf::run(
        msd_experiment::config::Spec::new(config).expect("a frequency response"),
        &Default::default(),
    )
    .expect("fits");
    assert_eq!(outcome.data.kind, msd_signal::FrfKind::Accelerance);
    let FrfFit::OneMode(fit) = &outcome.fit else {
        panic!("one mode")
    };
    let u = &fit.uncertainty;
    for (name, value, truth) in [
        ("m", u.mass.value, m),
        ("c", u.damping.value, c),
        ("k", u.stiffness.value, k),
    ] {
        assert!(
            (value / truth - 1.0).abs() < 1e-6,
            "{name} = {value}, truth {truth}"
        );
    }
    std::fs::write(dir.path().join("frf.uff"), write("NONE")).expect("uff");
    let config = Config::load(&path).expect("valid");
    let err = frf::run(
        msd_experiment::config::Spec::new(config).expect("a frequency response"),
        &Default::default(),
    )
    .expect_err("refused");
    assert!(
        err.to_string().contains("frequency_response.uff.kind"),
        "{err}"
    );
}
