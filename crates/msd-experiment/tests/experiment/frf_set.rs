//! A set of FRFs from CSV tables (`[[frequency_response.set]]`): fitted together with
//! their shapes, and refused with the key and the file when the set is inconsistent.

use msd_experiment::config::{Config, Spec};
use msd_experiment::frf::{self, FrfFit};
use msd_modal::ModalParameters;
use std::fmt::Write;
use std::path::Path;

/// Two modes at points 1–3 (shapes [1, 0.8, 0.4] and [1, −0.5, −1]), the hammer at point 1:
/// the receptance H_1i as a CSV of frequency, real and imaginary parts.
fn write_table(dir: &Path, point: usize, lines: usize) {
    let shapes = [[1.0, 0.8, 0.4], [1.0, -0.5, -1.0]];
    let mut text = String::from("f,re,im\n");
    for i in 1..=lines {
        let f = 0.05 * i as f64;
        let h: msd_signal::Complex64 = (0..2)
            .map(|r| {
                ModalParameters {
                    natural_frequency_hz: [10.0, 24.0][r],
                    damping_ratio: [0.01, 0.02][r],
                    modal_constant: shapes[r][0] * shapes[r][point - 1],
                    modal_constant_imaginary: 0.0,
                }
                .receptance(f)
            })
            .sum();
        writeln!(text, "{f},{},{}", h.re, h.im).expect("a string");
    }
    std::fs::write(dir.join(format!("h{point}.csv")), text).expect("written");
}

fn member(point: usize, response: usize) -> String {
    format!(
        "[[frequency_response.set]]\npath = \"h{point}.csv\"\nfrequency = \"f\"\nreal = \"re\"\nimaginary = \"im\"\nresponse = {{ node = {response}, direction = 3 }}\nreference = {{ node = 1, direction = 3 }}\n"
    )
}

fn run(dir: &Path, body: &str) -> Result<frf::FrfOutcome, msd_experiment::ExperimentError> {
    let path = dir.join("set.toml");
    std::fs::write(&path, format!("name = \"set\"\n{body}")).expect("written");
    let config = Config::load(&path)?;
    frf::run(
        Spec::new(config).expect("a frequency response"),
        &Default::default(),
    )
}

#[test]
fn a_set_of_tables_gives_the_modes_and_their_shapes() {
    let dir = tempfile::tempdir().expect("a folder");
    for point in 1..=3 {
        write_table(dir.path(), point, 600);
    }
    let body: String = (1..=3).map(|p| member(p, p)).collect();
    let outcome = run(dir.path(), &body).expect("a fit");
    let FrfFit::Set(fit) = &outcome.fit else {
        panic!("a set fit")
    };
    assert_eq!(fit.modes.len(), 2, "{fit}");
    // Exact data: the second shape's last entry is −1 of the largest (point 1).
    let last = fit.modes[1].shape[2];
    assert!(
        (last.re + 1.0).abs() < 1e-6 && last.im.abs() < 1e-6,
        "{last:?}"
    );
    let json = frf::to_json(&outcome, &[], Default::default());
    assert_eq!(json["modes"][1]["shape"][2]["node"], 3);
    assert_eq!(json["mac"].as_array().map(Vec::len), Some(2));
    assert_eq!(json["fit_error"].as_array().map(Vec::len), Some(3));
    // Tables without coherence: unchecked, and how well the worst member is reproduced.
    let v = &outcome.verdict;
    assert!(v.unchecked && !v.trustworthy, "{v}");
    let text = v.to_string();
    assert!(text.contains("the set's FRFs carry no coherence"), "{text}");
    assert!(
        text.contains("2 modes common to the 3 FRFs reproduce each within"),
        "{text}"
    );
}

#[test]
fn an_inconsistent_set_is_refused_naming_the_member() {
    let dir = tempfile::tempdir().expect("a folder");
    write_table(dir.path(), 1, 600);
    write_table(dir.path(), 2, 500);
    write_table(dir.path(), 3, 600);
    // Other lines.
    let err = run(dir.path(), &(member(1, 1) + &member(2, 2))).expect_err("refused");
    let text = err.to_string();
    assert!(
        text.contains("h2.csv") && text.contains("set[1]") && text.contains("share their lines"),
        "{text}"
    );
    assert_eq!(err.exit_code(), 2, "{text}");
    // The same pair of DOFs twice.
    let err = run(dir.path(), &(member(1, 1) + &member(3, 1))).expect_err("refused");
    assert!(err.to_string().contains("each pair of DOFs once"), "{err}");
    assert_eq!(err.exit_code(), 2);
    // A member without its DOFs.
    let body = member(1, 1).replace("response = { node = 1, direction = 3 }\n", "");
    let err = run(dir.path(), &body).expect_err("refused");
    assert!(
        err.to_string()
            .contains("frequency_response.set[0].response"),
        "{err}"
    );
    assert_eq!(err.exit_code(), 2);
}

#[test]
fn the_shapes_and_the_synthesized_frfs_are_written_as_uff() {
    let dir = tempfile::tempdir().expect("a folder");
    for point in 1..=3 {
        write_table(dir.path(), point, 600);
    }
    let body: String = (1..=3).map(|p| member(p, p)).collect();
    let path = dir.path().join("set.toml");
    std::fs::write(&path, format!("name = \"set\"\n{body}")).expect("written");
    let out = dir.path().join("out");
    let options = msd_experiment::RunOptions {
        out: Some(out.clone()),
        ..Default::default()
    };
    let summary = msd_experiment::run_experiment(&path, &options).expect("a run");
    let modes = msd_uff::read(out.join("modes.uff")).expect("modes.uff");
    assert_eq!(modes.data_at_nodes.len(), 2);
    let shapes = &summary.results["modes"];
    for (r, dataset) in modes.data_at_nodes.iter().enumerate() {
        for entry in shapes[r]["shape"].as_array().expect("a shape") {
            let node = entry["node"].as_i64().expect("a node");
            let (re, im) = dataset.value(node, 3).expect("the node's Z value");
            // Written in 13 columns: the shape to within 1e-6 of its largest entry (1).
            // pyuff 2.5 reads the same file (checked by hand on configs/impact-frf.toml:
            // every shape value within 1.7e-7, eigenvalues, nodes, the 58s' DOFs and lines).
            assert!(
                (re - entry["re"].as_f64().expect("re")).abs() < 1e-6,
                "{re}"
            );
            assert!(
                (im - entry["im"].as_f64().expect("im")).abs() < 1e-6,
                "{im}"
            );
        }
    }
    let synthesized = msd_uff::read(out.join("synthesized.uff")).expect("synthesized.uff");
    assert_eq!(synthesized.functions.len(), 3);
    assert_eq!(synthesized.functions[2].response_node, 3);
    assert_eq!(synthesized.functions[2].len(), 600);
}

/// The table of `write_table` (600 lines) with complex noise σ = 2e-6 flat in receptance
/// from `seed`, and the coherence such noise gives over 20 averages (its
/// (1 − γ²)/(K·γ²)·|Ĥ|² is (K − 1)/K·σ², as a coherence estimated from the K averages
/// gives it on average).
fn write_noisy_table(dir: &Path, point: usize, seed: u64) {
    const SIGMA: f64 = 2e-6;
    const K: f64 = 20.0;
    write_table(dir, point, 600);
    let file = dir.join(format!("h{point}.csv"));
    let text = std::fs::read_to_string(&file).expect("written");
    let noise = |name: &str| {
        msd_signal::gaussian_noise(seed * 10 + point as u64, name, SIGMA / 2f64.sqrt(), 600)
            .expect("noise")
    };
    let (re, im) = (noise("re"), noise("im"));
    let mut out = String::from("f,re,im,coh\n");
    for (i, line) in text.lines().skip(1).enumerate() {
        let v: Vec<f64> = line
            .split(',')
            .map(|x| x.parse().expect("a number"))
            .collect();
        let (hr, hi) = (v[1] + re[i], v[2] + im[i]);
        let power = hr * hr + hi * hi;
        let coherence = power / (power + (K - 1.0) * SIGMA * SIGMA);
        writeln!(out, "{},{hr},{hi},{coherence}", v[0]).expect("a string");
    }
    std::fs::write(&file, out).expect("written");
}

/// A set whose tables carry their coherence (and its count of averages): its residual is
/// checked against the members' own noise, and the verdict rests on it — trustworthy
/// with the model complete, "use with care" with a mode too few.
#[test]
fn a_set_with_coherence_checks_its_residual_against_its_noise() {
    let dir = tempfile::tempdir().expect("a folder");
    for point in 1..=3 {
        write_noisy_table(dir.path(), point, 7);
    }
    let body: String = (1..=3)
        .map(|p| member(p, p) + "coherence = \"coh\"\naverages = 20\n")
        .collect();
    let outcome = run(dir.path(), &body).expect("a fit");
    let FrfFit::Set(fit) = &outcome.fit else {
        panic!("a set fit")
    };
    let check = fit.noise_check.expect("coherence from 20 averages");
    assert!(check.passed, "{check}");
    assert!(outcome.verdict.trustworthy, "{}", outcome.verdict);
    assert!(
        (outcome.verdict.to_string())
            .contains("the modes leave only the noise the FRF's coherence shows"),
        "{}",
        outcome.verdict
    );
    let json = frf::to_json(&outcome, &[], Default::default());
    assert_eq!(json["modal_set"]["noise_check"]["passed"], true);
    assert!(
        outcome
            .to_string()
            .contains("\n  residuals      against the FRF's own noise"),
        "{outcome}"
    );

    // The coherence without its count of averages: relative weights only, said.
    let relative: String = (1..=3)
        .map(|p| member(p, p) + "coherence = \"coh\"\n")
        .collect();
    let outcome = run(dir.path(), &relative).expect("a fit");
    let text = outcome.verdict.to_string();
    assert!(outcome.verdict.unchecked, "{text}");
    assert!(
        text.contains("averages in each [[frequency_response.set]]"),
        "{text}"
    );

    let one_mode = format!("[frequency_response.modes]\nmode_count = 1\n{body}");
    let outcome = run(dir.path(), &one_mode).expect("a fit");
    assert!(
        !outcome.verdict.trustworthy && !outcome.verdict.unchecked,
        "{}",
        outcome.verdict
    );
    assert!(
        (outcome.verdict.to_string())
            .starts_with("use with care: the residual exceeds the FRF's own noise"),
        "{}",
        outcome.verdict
    );
}
