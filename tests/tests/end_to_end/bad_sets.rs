//! Issue 46 §5: malformed sets, shapes and tables are refused naming the file, line and
//! key (they were read as zeros, as real numbers, or ran to NaN); shapes of any scale
//! give the MAC of their directions.

use super::bad_input::Case;
use msd_tests::{config, run_in_temp};

/// One accelerance of a single mode (m 1 kg, fn ≈ 50 Hz, ζ ≈ 2 %) at 1 Hz lines from
/// 1 to 200 Hz, each line `(re+imj)` as Python writes complex numbers.
fn accelerance_lines() -> Vec<String> {
    (1..=200)
        .map(|f| {
            let w = std::f64::consts::TAU * f64::from(f);
            let (k, c) = (98_696.0, 12.57);
            let den = msd_signal::Complex64::new(k - w * w, c * w);
            let h = msd_signal::Complex64::new(-w * w, 0.0) / den;
            format!("({:e}{:+e}j)", h.re, h.im)
        })
        .collect()
}

/// A set of one FRF read from `frf.txt`, its reference DOF `reference`.
fn set_config(reference: &str) -> String {
    format!(
        "name = \"set\"\n[[frequency_response.set]]\npath = \"frf.txt\"\nheader = false\nfrequency_step_hz = 1.0\ncomplex = 0\nkind = \"accelerance\"\nresponse = {{ node = 1, direction = 1 }}\nreference = {reference}\n"
    )
}

#[test]
fn a_set_file_written_with_decimal_commas_is_refused_at_its_first_line() {
    let case = Case::new();
    let lines: Vec<String> = accelerance_lines()
        .iter()
        .map(|l| l.replace('.', ","))
        .collect();
    case.file("frf.txt", &(lines.join("\n") + "\n"));
    let c = case.file("c.toml", &set_config("{ node = 1, direction = 1 }"));
    case.refuses(
        &c,
        &[
            "frf.txt",
            "line 1",
            "parenthesis is not closed",
            "decimal = \",\"",
        ],
    );
}

#[test]
fn a_set_file_cut_short_is_refused_at_its_last_line() {
    let case = Case::new();
    let mut lines = accelerance_lines();
    let last = lines.pop().unwrap();
    lines.push(last[..12].to_string());
    case.file("frf.txt", &(lines.join("\n") + "\n"));
    let c = case.file("c.toml", &set_config("{ node = 1, direction = 1 }"));
    case.refuses(&c, &["frf.txt", "line 200", "parenthesis is not closed"]);
}

#[test]
fn a_direction_uff_does_not_number_is_refused() {
    let case = Case::new();
    case.file("frf.txt", &(accelerance_lines().join("\n") + "\n"));
    for direction in [0, 7, -9] {
        let c = case.file(
            "c.toml",
            &set_config(&format!("{{ node = 1, direction = {direction} }}")),
        );
        case.refuses(
            &c,
            &[
                &format!("frequency_response.set[0].reference.direction = {direction}"),
                "±1, ±2, ±3",
            ],
        );
    }
}

/// The roving-hammer beam's first reference mode with `from` replaced by `to`.
fn beam_with(from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(config("roving-hammer-beam.toml")).unwrap();
    assert!(text.contains(from), "{from}");
    text.replacen(from, to, 1)
        .replace("\"data/", &format!("\"{}/", config("data").display()))
}

#[test]
fn reference_modes_that_are_not_modes_are_refused_naming_the_key() {
    let case = Case::new();
    for (from, to, fragments) in [
        (
            "natural_frequency_hz = 12.0",
            "natural_frequency_hz = nan",
            [
                "reference_modes[0].natural_frequency_hz = NaN",
                "finite frequency > 0",
            ],
        ),
        (
            "damping_ratio = 1e-2",
            "damping_ratio = -0.01",
            [
                "reference_modes[0].damping_ratio = -0.01",
                "from 0 to below 1",
            ],
        ),
        (
            "shape = [0.281733,",
            "shape = [nan,",
            ["reference_modes[0].shape[0] = NaN", "finite number"],
        ),
    ] {
        let c = case.file("c.toml", &beam_with(from, to));
        case.refuses(&c, &fragments);
    }
}

#[test]
fn a_reference_shape_of_any_scale_gives_the_mac_of_its_direction() {
    // The first reference mode's shape times 1e300 (it gave a NaN MAC): the MAC is a
    // ratio of products of the same shape, so it is the unscaled run's to rounding.
    let shape = "shape = [0.281733, 0.540641, 0.755750, 0.909632, 0.989821, 0.989821, 0.909632, 0.755750, 0.540641, 0.281733]";
    let scaled = "shape = [0.281733e300, 0.540641e300, 0.755750e300, 0.909632e300, 0.989821e300, 0.989821e300, 0.909632e300, 0.755750e300, 0.540641e300, 0.281733e300]";
    let dir = tempfile::tempdir().unwrap();
    let mac = |text: String| {
        let path = dir.path().join("beam.toml");
        std::fs::write(&path, text).unwrap();
        let run = run_in_temp(&path, None, None).expect("runs");
        run.summary.results["reference_mac"].clone()
    };
    let plain = mac(beam_with(shape, shape));
    let big = mac(beam_with(shape, scaled));
    let numbers = |v: &serde_json::Value| -> Vec<f64> {
        (v.as_array().expect("reference_mac").iter())
            .map(|x| x.as_f64().expect("a number"))
            .collect()
    };
    let (plain, big) = (numbers(&plain), numbers(&big));
    assert!(!plain.is_empty() && plain.len() == big.len());
    for (a, b) in plain.into_iter().zip(big) {
        assert!((a - b).abs() < 1e-12, "{a} against {b}");
    }
}

#[test]
fn two_columns_of_one_name_are_refused_naming_both() {
    let case = Case::new();
    let rows: Vec<String> = (0..100)
        .map(|i| {
            format!(
                "{:.2},1.0,0.0,{}",
                f64::from(i) * 0.01,
                0.001 * f64::from(i % 7)
            )
        })
        .collect();
    case.file(
        "data.csv",
        &format!("t,force,displacement,displacement\n{}\n", rows.join("\n")),
    );
    let c = case.file(
        "c.toml",
        "name = \"lab\"\n[data]\npath = \"data.csv\"\ninput = \"force\"\noutput = \"displacement\"\ntime = \"t\"\n[monte_carlo]\nenabled = false\n",
    );
    case.refuses(
        &c,
        &[
            "data.csv",
            "line 1",
            "two columns are named `displacement`",
            "#2 and #3",
        ],
    );
}

/// Issue 46 §6: messages that pointed the wrong way now name the key and the file.
#[test]
fn messages_name_the_key_and_the_file() {
    let case = Case::new();
    let rows: Vec<String> = (0..100)
        .map(|i| {
            format!(
                "{:.2},{},{}",
                f64::from(i) * 0.01,
                (f64::from(i) * 0.3).sin(),
                0.0
            )
        })
        .collect();
    case.file(
        "data.csv",
        &format!("t,force,displacement\n{}\n", rows.join("\n")),
    );
    let measured = |extra: &str| {
        format!(
            "name = \"lab\"\n[data]\npath = \"data.csv\"\ninput = \"force\"\noutput = \"displacement\"\ntime = \"t\"\n{extra}\n[monte_carlo]\nenabled = false\n"
        )
    };
    // skip_lines past the end said "the file is empty".
    let c = case.file("c.toml", &measured("skip_lines = 1000000000"));
    case.refuses(
        &c,
        &[
            "data.csv",
            "skip_lines = 1000000000",
            "the file has 101 lines",
        ],
    );
    // An empty reference_shapes named the config's folder.
    let c = case.file(
        "b.toml",
        &beam_with(
            "reference_shapes = \"data/roving-hammer-beam-model.uff\"",
            "reference_shapes = \"\"",
        ),
    );
    case.refuses(
        &c,
        &["frequency_response.reference_shapes = \"\"", "UFF file"],
    );
    // A table too short for the fit named the key but not the file.
    let table = std::fs::read_to_string(config("data/stepped-sine-table.csv")).unwrap();
    let short: Vec<&str> = table.lines().take(5).collect();
    case.file("short.csv", &(short.join("\n") + "\n"));
    let text = std::fs::read_to_string(config("frf-table.toml"))
        .unwrap()
        .replace("data/stepped-sine-table.csv", "short.csv");
    let c = case.file("t.toml", &text);
    case.refuses(
        &c,
        &[
            "frequency_response.one_mode.band_hz",
            "short.csv",
            "2 lines",
        ],
    ); // Records of eight rows: five lines, no resonance among them (was exit 1, no file).
    let rows: Vec<String> = (0..8)
        .map(|i| {
            let t = 0.7 * f64::from(i);
            format!("{},{}", t.sin(), 0.01 * (t - 0.3).sin())
        })
        .collect();
    case.file("rec8.csv", &format!("force,accel\n{}\n", rows.join("\n")));
    let c = case.file(
        "r.toml",
        "name = \"r\"\n[frequency_response.records]\npath = \"rec8.csv\"\nsample_rate = 100.0\nforce = [\"force\"]\nresponse = [\"accel\"]\n[frequency_response.estimator]\nkind = \"acceleration\"\n",
    );
    case.refuses(
        &c,
        &[
            "frequency_response.one_mode.band_hz",
            "rec8.csv",
            "5 lines",
            "no resonance",
        ],
    );
}

/// A UFF file that holds a time response beside its FRFs: the FRFs are read and the
/// report names the dataset that was not (it was skipped without a word).
#[test]
fn a_mixed_uff_file_says_which_datasets_were_not_read() {
    use msd_uff::{Abscissa, Function58, FunctionType, Ordinate};
    let case = Case::new();
    let mut file = msd_uff::read(config("data/frf-2dof.uff")).unwrap();
    let time = Function58::new(
        FunctionType::TimeResponse,
        Abscissa::Even {
            start: 0.0,
            step: 1e-3,
        },
        Ordinate::Real(vec![0.5; 64]),
    );
    file.functions.insert(0, time);
    let uff = case.dir.path().join("mixed.uff");
    msd_uff::write(&uff, &file, &Default::default()).unwrap();
    let text = std::fs::read_to_string(config("frf-uff.toml"))
        .unwrap()
        .replace("data/frf-2dof.uff", &uff.display().to_string());
    let c = case.file("mixed.toml", &text);
    let run = run_in_temp(&c, None, None).expect("the FRF of a mixed file is fitted");
    let report = std::fs::read_to_string(run.out().join("report.md")).unwrap();
    assert!(
        report.contains("dataset 58 #2 of") && report.contains("not read: dataset 58 #1 (time"),
        "the report names the FRF read and the time response not read"
    );
}

/// A setup record whose units line holds a number: read as units (a units line may), and
/// said in the report, with or without validation records (it was said only with them).
#[test]
fn what_the_reader_found_is_said_in_a_setup_report() {
    let case = Case::new();
    let rows: Vec<String> = (1..3000)
        .map(|i| {
            let t = f64::from(i) * 0.002;
            format!("{t},{}", 0.01 * (-0.36 * t).exp() * (6.9 * t).cos())
        })
        .collect();
    case.file(
        "decay.csv",
        &format!("# rig 3\nt,displacement\ns,m\n{}\n", rows.join("\n")),
    );
    let c = case.file(
        "fd.toml",
        "name = \"fd\"\n[setup]\nexcitation = \"none\"\nresponses = [{ quantity = \"displacement\", column = \"displacement\" }]\n[data]\npath = \"decay.csv\"\ntime = \"t\"\n",
    );
    let run = run_in_temp(&c, None, None).expect("a clean decay is fitted");
    let report = std::fs::read_to_string(run.out().join("report.md")).unwrap();
    assert!(report.contains("decay.csv: line 3: units s, m"), "{report}");
}

/// A measured free decay that sinks below its noise is refused naming its file (the
/// message named the record and the config).
#[test]
fn a_free_decay_below_its_noise_is_refused_naming_its_file() {
    let case = Case::new();
    let rows: Vec<String> = (1..3000_u32)
        .map(|i| {
            let t = f64::from(i) * 0.002;
            // A uniform draw of a multiplicative hash: white, not a tone.
            let u = f64::from(i.wrapping_mul(2_654_435_761_u32)) / f64::from(u32::MAX);
            let noise = 2e-4 * (u - 0.5);
            format!("{t},{}", 1e-5 * (-0.36 * t).exp() * (6.9 * t).cos() + noise)
        })
        .collect();
    case.file(
        "quiet.csv",
        &format!("t,displacement\n{}\n", rows.join("\n")),
    );
    let c = case.file(
        "fd.toml",
        "name = \"fd\"\n[setup]\nexcitation = \"none\"\nresponses = [{ quantity = \"displacement\", column = \"displacement\" }]\n[data]\npath = \"quiet.csv\"\ntime = \"t\"\n",
    );
    case.refuses(&c, &["quiet.csv", "not a free decay"]);
}
