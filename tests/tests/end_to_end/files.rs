//! One lab record in the forms data-acquisition software writes it — a plain CSV, a
//! European spreadsheet export (Latin-1 metadata line, `;`, decimal commas, a units line,
//! CRLF), a NumPy array — read by the same `[data]` section with one or two keys each:
//! the same numbers, bit for bit, and the report says what the reader passed over.

use super::experiment::lab_csv;
use msd_tests::{config, run_in_temp};
use std::path::Path;

/// The lab template's estimates (mass, damping, stiffness, offset) on `data`, a file
/// in `dir`, with `keys` added to its `[data]` section and its columns renamed (time,
/// input, output; no time line for a time column named "").
fn estimates(dir: &Path, data: &str, keys: &str, columns: [&str; 3]) -> (Vec<f64>, String) {
    let template = std::fs::read_to_string(config("lab-template.toml")).unwrap();
    // Each key replaces the template's line that sets it, or follows `path`.
    let mut lines: Vec<String> = template.lines().map(str::to_string).collect();
    for key in keys.lines() {
        let name = key.split('=').next().unwrap_or_default().trim();
        match lines
            .iter()
            .position(|l| l.split('=').next().is_some_and(|n| n.trim() == name))
        {
            Some(i) => lines[i] = key.to_string(),
            None => {
                let at = lines.iter().position(|l| l.starts_with("path =")).unwrap();
                lines.insert(at + 1, key.to_string());
            }
        }
    }
    // A column by 0-based number (no header) is written bare.
    let key = |c: &str| match c.parse::<usize>() {
        Ok(n) => n.to_string(),
        Err(_) => format!("{c:?}"),
    };
    let text = lines
        .join("\n")
        .replacen(
            "path = \"my-measurement.csv\"",
            &format!("path = {data:?}"),
            1,
        )
        .replacen(
            "input = \"force\"",
            &format!("input = {}", key(columns[1])),
            1,
        )
        .replacen(
            "output = \"displacement\"",
            &format!("output = {}", key(columns[2])),
            1,
        )
        .replacen(
            "time = \"t\"",
            // No time column: the keys give `sample_rate`.
            &match columns[0] {
                "" => String::new(),
                t => format!("time = {}", key(t)),
            },
            1,
        );
    let path = dir.join(format!("{data}.toml"));
    std::fs::write(&path, text).unwrap();
    let run = run_in_temp(&path, None, None).unwrap_or_else(|e| panic!("{data}: {e}"));
    let values = ["mass", "damping", "stiffness"]
        .map(|p| run.number(&format!("estimate.{p}.value")))
        .into_iter()
        .chain([run.number("estimate.offset")])
        .collect();
    let report = std::fs::read_to_string(run.out().join("report.md")).unwrap();
    (values, report)
}

/// The CSV's rows as numbers (the very values its text reads as).
fn rows(dir: &Path) -> Vec<[f64; 3]> {
    let text = std::fs::read_to_string(dir.join("my-measurement.csv")).unwrap();
    text.lines()
        .skip(2)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|c| c.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

/// The lab record as the template's plain CSV in a scratch folder, and its estimates.
fn plain_run() -> (tempfile::TempDir, Vec<f64>) {
    let dir = tempfile::tempdir().unwrap();
    lab_csv(dir.path());
    let columns = ["t", "force", "displacement"];
    let (plain, _) = estimates(dir.path(), "my-measurement.csv", "", columns);
    (dir, plain)
}

#[test]
fn a_european_export_and_a_numpy_array_read_as_the_plain_csv() {
    let (dir, plain) = plain_run();

    // Latin-1, a metadata line, `;` and decimal commas, a units line, CRLF.
    let mut text: Vec<u8> = b"Pr\xfcfstand 3; Messung 7\r\nZeit;Kraft;Weg\r\ns;N;m\r\n".to_vec();
    let original = std::fs::read_to_string(dir.path().join("my-measurement.csv")).unwrap();
    for line in original.lines().skip(2) {
        text.extend(line.replace(',', ";").replace('.', ",").as_bytes());
        text.extend(b"\r\n");
    }
    std::fs::write(dir.path().join("export.csv"), &text).unwrap();
    // One key: the delimiter is found in the file.
    let (european, report) = estimates(
        dir.path(),
        "export.csv",
        "decimal = \",\"",
        ["Zeit", "Kraft", "Weg"],
    );
    assert_eq!(european, plain);
    for said in [
        "delimiter ';' (found in the file",
        "read as Windows-1252",
        "line 3: units s, N, m",
        "line 1 read as metadata",
    ] {
        assert!(report.contains(said), "the report does not say `{said}`");
    }

    // samples × 3, float64, C order, as numpy.save writes it.
    let header = "{'descr': '<f8', 'fortran_order': False, 'shape': (7501, 3), }";
    let padded = format!("{header:<117}\n");
    let mut npy = b"\x93NUMPY\x01\x00".to_vec();
    npy.extend((padded.len() as u16).to_le_bytes());
    npy.extend(padded.as_bytes());
    for row in rows(dir.path()) {
        for v in row {
            npy.extend(v.to_le_bytes());
        }
    }
    std::fs::write(dir.path().join("rec.npy"), npy).unwrap();
    let (numpy, _) = estimates(dir.path(), "rec.npy", "", ["rec[0]", "rec[1]", "rec[2]"]);
    assert_eq!(numpy, plain);
}

#[test]
fn missing_values_are_interpolated_when_asked_and_counted() {
    let (dir, plain) = plain_run();
    let original = std::fs::read_to_string(dir.path().join("my-measurement.csv")).unwrap();
    let mut lines: Vec<String> = original.lines().map(str::to_string).collect();
    for (row, with) in [
        (1000, "{t},{f},"),
        (3000, "{t},NaN,{x}"),
        (5000, "{t},,{x}"),
    ] {
        let cells: Vec<&str> = lines[row].split(',').collect();
        let (t, f, x) = (cells[0], cells[1], cells[2]);
        lines[row] = with.replace("{t}", t).replace("{f}", f).replace("{x}", x);
    }
    std::fs::write(dir.path().join("gaps.csv"), lines.join("\n")).unwrap();
    let (filled, report) = estimates(
        dir.path(),
        "gaps.csv",
        "missing = \"interpolate\"",
        ["t", "force", "displacement"],
    );
    assert!(
        report.contains("3 missing values interpolated (line 1001, 3001, 5001)"),
        "the report does not count the gaps"
    );
    // Three of 7501 samples replaced by their neighbours' mean: the estimates move by
    // far less than their standard errors (here within 0.1 %).
    for (a, b) in filled.iter().zip(&plain).take(3) {
        assert!((a / b - 1.0).abs() < 1e-3, "{a} against {b}");
    }
}

/// A SignalCalc-style ASCII export of a measured FRF: nine header lines (seven of
/// metadata, the column names, a units line with `m/s²` in Latin-1), tab-separated, read
/// by `[frequency_response.table]` with one key (the delimiter); `msd inspect` prints the
/// lines that read it.
#[test]
fn a_signalcalc_export_reads_with_one_key() {
    let dir = tempfile::tempdir().unwrap();
    let mut text: Vec<u8> = b"SignalCalc ACE ASCII Export\r\nTitle:\tbeam\r\nDate:\t11/29/2026\r\nChannels:\t2\r\nAverages:\t10\r\nWindow:\tHanning\r\n\r\nX Axis\tReal\tImag\r\nHz\tm/s\xb2/N\tm/s\xb2/N\r\n".to_vec();
    let (m, k, zeta) = (1.0, (2.0 * std::f64::consts::PI * 100.0).powi(2), 0.01);
    let c = 2.0 * zeta * (k * m).sqrt();
    for i in 1..=1600 {
        let f = i as f64 * 0.3125;
        let w = 2.0 * std::f64::consts::PI * f;
        let (re, im) = (k - m * w * w, c * w);
        let d = re * re + im * im;
        text.extend(format!("{f:.4}\t{:.9e}\t{:.9e}\r\n", re / d, -im / d).as_bytes());
    }
    std::fs::write(dir.path().join("beam.txt"), &text).unwrap();
    let config = dir.path().join("beam.toml");
    std::fs::write(
        &config,
        "name = \"beam\"\n[frequency_response.table]\npath = \"beam.txt\"\ndelimiter = \"\\t\"\nfrequency = \"X Axis\"\nreal = \"Real\"\nimaginary = \"Imag\"\n",
    )
    .unwrap();
    let run = run_in_temp(&config, None, None).expect("the export reads with one key");
    let f = run.number("estimate.natural_frequency_hz.value");
    assert!((f / 100.0 - 1.0).abs() < 1e-4, "fn = {f}");
    let report = std::fs::read_to_string(run.out().join("report.md")).unwrap();
    assert!(report.contains("lines 1–7 read as metadata"), "{report}");
    let listing = msd_experiment::inspect::inspect(&dir.path().join("beam.txt")).unwrap();
    for line in [
        "[frequency_response.table]",
        "delimiter = \"\\t\"",
        "frequency = \"X Axis\"",
    ] {
        assert!(listing.contains(line), "{listing}");
    }
}

/// The lab record as NumPy's `savetxt` and MATLAB's `save -ascii` write it — columns
/// separated by runs of spaces (here of one to three, and a tab), a leading space, no
/// quotes — reads with `delimiter = " "` to the plain CSV's numbers bit for bit, and
/// `msd inspect` finds that delimiter by itself.
#[test]
fn a_whitespace_separated_table_reads_as_the_plain_csv() {
    let (dir, plain) = plain_run();
    let mut text = String::from("time   force \t displacement\n");
    for (i, [t, f, x]) in rows(dir.path()).into_iter().enumerate() {
        let gap = " ".repeat(1 + i % 3);
        text.push_str(&format!(" {t:e}{gap}{f:e}\t{x:e}\n"));
    }
    std::fs::write(dir.path().join("savetxt.txt"), &text).unwrap();
    let columns = ["time", "force", "displacement"];
    let (spaced, _) = estimates(dir.path(), "savetxt.txt", "delimiter = \" \"", columns);
    assert_eq!(spaced, plain);
    let listing = msd_experiment::inspect::inspect(&dir.path().join("savetxt.txt")).unwrap();
    for line in ["delimiter = \" \"", "time = \"time\"", "input = \"force\""] {
        assert!(listing.contains(line), "{listing}");
    }
}

/// The lab record with no header line (as `numpy.savetxt` writes it without `header=`):
/// read with the default `header = true` it is refused (its first row would have named
/// the columns and been lost); `msd inspect` says so and its lines, by column number,
/// read the plain CSV's numbers bit for bit.
#[test]
fn a_table_without_a_header_is_read_by_column_number() {
    let (dir, plain) = plain_run();
    let text = std::fs::read_to_string(dir.path().join("my-measurement.csv")).unwrap();
    let body: String = text.lines().skip(2).map(|l| format!("{l}\n")).collect();
    std::fs::write(dir.path().join("bare.csv"), body).unwrap();
    let listing = msd_experiment::inspect::inspect(&dir.path().join("bare.csv")).unwrap();
    for said in [
        "no header: the first line is data; the columns are read by number",
        "[data]\npath = \"bare.csv\"\nheader = false\ntime = 0\ninput = 1\noutput = 2",
    ] {
        assert!(listing.contains(said), "{listing}");
    }
    let (bare, _) = estimates(dir.path(), "bare.csv", "header = false", ["0", "1", "2"]);
    assert_eq!(bare, plain);
    // `msd init` names the columns by number too, and its config reads them.
    let options = msd_experiment::init::InitOptions {
        input: Some("1".into()),
        outputs: vec!["2".into()],
        ..Default::default()
    };
    let init = msd_experiment::init::init(&dir.path().join("bare.csv"), &options).unwrap();
    for said in [
        "column = 2,",
        "header = false\ntime = 0    # s\ninput = 1\n",
    ] {
        assert!(init.text.contains(said), "{}", init.text);
    }
    // Its fit (the setup kind) holds the plant's stiffness in its 95 % interval.
    let run = run_in_temp(&dir.path().join("bare.toml"), None, None).expect("init's config runs");
    let ci = msd_tests::lookup(&run.summary.results, "estimate.stiffness.ci95")
        .and_then(|v| Some((v.get(0)?.as_f64()?, v.get(1)?.as_f64()?)))
        .expect("an interval");
    let k = msd_ident::Parameters::PAPER.stiffness;
    assert!(ci.0 <= k && k <= ci.1, "k {k} outside {ci:?}");
    let template = std::fs::read_to_string(config("lab-template.toml")).unwrap();
    let config = dir.path().join("refused.toml");
    std::fs::write(
        &config,
        template.replacen("my-measurement.csv", "bare.csv", 1),
    )
    .unwrap();
    let refused = run_in_temp(&config, None, None)
        .err()
        .expect("refused")
        .to_string();
    assert!(
        refused.contains("the first line is data, not column names")
            && refused.contains("header = false"),
        "{refused}"
    );
}

/// The lab record as a Rigol oscilloscope writes its CSV: names over units, the
/// capture's `Start` and `Increment` beside them, a sample counter `X` and a trailing
/// delimiter on every line. `msd inspect` takes the names as the header, the counter for
/// no time (a step of 1 read as seconds would put every frequency 500× low) and the rate
/// from `Increment`; its lines read the plain CSV's numbers bit for bit.
#[test]
fn an_oscilloscope_export_reads_by_its_channel_names() {
    let (dir, plain) = plain_run();
    let mut text =
        String::from("X,CH1,CH2,Start,Increment,\nSequence,Volt,Volt,0.000000e+00,2.000000e-03\n");
    let csv = std::fs::read_to_string(dir.path().join("my-measurement.csv")).unwrap();
    for (i, line) in csv.lines().skip(2).enumerate() {
        let (_, values) = line.split_once(',').unwrap();
        text.push_str(&format!("{i},{values},\n"));
    }
    std::fs::write(dir.path().join("scope.csv"), text).unwrap();
    let listing = msd_experiment::inspect::inspect(&dir.path().join("scope.csv")).unwrap();
    for said in [
        "line 2: units Sequence, Volt, Volt; settings beside the columns: Start 0, Increment 0.002",
        "sample_rate = 500    # Hz; \"X\" counts samples, it is not a time\ninput = \"CH1\"\noutput = \"CH2\"",
    ] {
        assert!(listing.contains(said), "{listing}");
    }
    assert!(!listing.contains("missing"), "{listing}");
    let (scope, _) = estimates(
        dir.path(),
        "scope.csv",
        "sample_rate = 500",
        ["", "CH1", "CH2"],
    );
    assert_eq!(scope, plain);
}

/// The lab record as a data logger stamps its rows, with the date and the clock
/// (`2024-05-01 12:00:07.314`): `msd inspect` takes the stamps for the time and the
/// reader counts them from the first row. At 1.7e9 s since 1970 a stamp carries
/// rounding of 2⁻²² s ≈ 2.4e-7 s, which puts the 15 s record's step within 4e-8 of
/// the plain CSV's: the estimates (m, c, k scale at most as the step's square) agree
/// within 1e-6.
#[test]
fn clock_time_stamps_read_as_seconds_from_the_first() {
    let (dir, plain) = plain_run();
    let csv = std::fs::read_to_string(dir.path().join("my-measurement.csv")).unwrap();
    let mut text = String::from("Timestamp,Force,Displacement\n");
    for line in csv.lines().skip(2) {
        let (t, values) = line.split_once(',').unwrap();
        let ms = (t.parse::<f64>().unwrap() * 1000.0).round() as u64;
        let (s, ms) = (ms / 1000, ms % 1000);
        text.push_str(&format!("2024-05-01 12:00:{s:02}.{ms:03},{values}\n"));
    }
    std::fs::write(dir.path().join("logger.csv"), text).unwrap();
    let listing = msd_experiment::inspect::inspect(&dir.path().join("logger.csv")).unwrap();
    assert!(listing.contains("time = \"Timestamp\""), "{listing}");
    let columns = ["Timestamp", "Force", "Displacement"];
    let (logged, report) = estimates(dir.path(), "logger.csv", "", columns);
    for (a, b) in logged.iter().zip(&plain) {
        assert!((a / b - 1.0).abs() < 1e-6, "{logged:?} against {plain:?}");
    }
    assert!(
        report.contains("the time column holds clock times: read as seconds from its first, 2024-05-01 12:00:00.000 (0 s)"),
        "{report}"
    );
}

/// One column of complex numbers in Python's notation with no header and no frequencies
/// (as pyuff's example FRFs, or `numpy.savetxt` of a complex array): `msd inspect` says
/// so and prints the `[frequency_response.table]` lines that read it, which run once
/// the lines' spacing is filled in; the mode comes back where it was put.
#[test]
fn a_column_of_complex_numbers_is_found_and_its_config_lines_run() {
    let dir = tempfile::tempdir().unwrap();
    let (m, k, zeta) = (1.0, (2.0 * std::f64::consts::PI * 80.0).powi(2), 0.02);
    let c = 2.0 * zeta * (k * m).sqrt();
    let mut text = String::new();
    for i in 0..=400 {
        let w = 2.0 * std::f64::consts::PI * 0.5 * i as f64;
        let (re, im) = (k - m * w * w, c * w);
        let d = re * re + im * im;
        // Accelerance −ω²·H, written as Python writes a complex number.
        let (a, b) = (-w * w * re / d, w * w * im / d);
        text.push_str(&format!("({a:e}{b:+e}j)\n"));
    }
    std::fs::write(dir.path().join("frf.txt"), &text).unwrap();
    let listing = msd_experiment::inspect::inspect(&dir.path().join("frf.txt")).unwrap();
    for said in [
        "no header: the first line is data (complex numbers)",
        "complex, |z|",
        "[frequency_response.table]",
        "header = false",
        "complex = 0",
        "frequency_step_hz = …",
    ] {
        assert!(listing.contains(said), "{listing}");
    }
    // `msd init` writes configs of time records: it gives the same lines instead.
    let refused = msd_experiment::init::init(
        &dir.path().join("frf.txt"),
        &msd_experiment::init::InitOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(refused.contains("a column of complex numbers: a frequency response"));
    assert!(
        refused.contains("complex = 0\nkind = \"accelerance\""),
        "{refused}"
    );
    let lines = &listing[listing.find("[frequency_response.table]").unwrap()..];
    let config = format!(
        "name = \"frf\"\n{}",
        lines.replace("frequency_step_hz = …", "frequency_step_hz = 0.5")
    );
    std::fs::write(dir.path().join("frf.toml"), config).unwrap();
    let run = run_in_temp(&dir.path().join("frf.toml"), None, None)
        .expect("the lines msd inspect printed run");
    let f = run.number("estimate.natural_frequency_hz.value");
    assert!((f / 80.0 - 1.0).abs() < 1e-6, "fn = {f}");
}

/// A Universal File Format file: `msd inspect` lists its functions and prints the
/// `[frequency_response.uff]` lines that read it, which run as they are; `msd init`
/// (which writes configs of time records) gives the same listing instead of a config.
#[test]
fn a_universal_file_is_listed_with_the_lines_that_read_it() {
    let dir = tempfile::tempdir().unwrap();
    let uff = dir.path().join("frf-2dof.uff");
    std::fs::copy(config("data/frf-2dof.uff"), &uff).unwrap();
    let listing = msd_experiment::inspect::inspect(&uff).unwrap();
    for said in [
        "a Universal File Format file",
        "0: frequency response function, response 2:+X, reference 1:+X, 200 complex points",
        "[frequency_response.uff]\npath = \"frf-2dof.uff\"",
    ] {
        assert!(listing.contains(said), "{listing}");
    }
    let lines = &listing[listing.find("[frequency_response.uff]").unwrap()..];
    std::fs::write(dir.path().join("u.toml"), format!("name = \"u\"\n{lines}")).unwrap();
    let run = run_in_temp(&dir.path().join("u.toml"), None, None).expect("the lines run");
    assert!(run.number("estimate.natural_frequency_hz.value") > 0.0);
    let refused = msd_experiment::init::init(&uff, &Default::default())
        .unwrap_err()
        .to_string();
    assert!(refused.contains("holds none") && refused.contains("[frequency_response.uff]"));
}

/// The lab record as a test system exports a run, time responses in a Universal File
/// Format file (the force and the displacement both at the driving point, 1:+Z): read
/// by the same `[data]` section through their DOFs, the plain CSV's numbers bit for
/// bit; `msd inspect` lists them as columns with the `[data]` lines, and `msd init`
/// takes the one in newtons as the force.
#[test]
fn time_responses_in_a_universal_file_read_as_the_plain_csv() {
    use msd_uff::{Abscissa, Function58, FunctionType, Ordinate};
    let (dir, plain) = plain_run();
    let mut file = msd_uff::UffFile::default();
    let rows = rows(dir.path());
    for (column, data_type, units) in [(1, 13, "N"), (2, 8, "NONE")] {
        let values = rows.iter().map(|r| r[column]).collect();
        let step = Abscissa::Even {
            start: 0.0,
            step: 0.002,
        };
        let mut f = Function58::new(FunctionType::TimeResponse, step, Ordinate::Real(values));
        (f.response_node, f.response_direction) = (1, 3);
        f.ordinate_axis.data_type = data_type;
        f.ordinate_axis.units = units.into();
        file.functions.push(f);
    }
    let bytes = msd_uff::to_bytes(&file, &Default::default()).unwrap();
    let path = dir.path().join("run.uff");
    std::fs::write(&path, bytes).unwrap();
    let columns = ["", "1:+Z #1", "1:+Z #2"];
    let (uff, _) = estimates(dir.path(), "run.uff", "sample_rate = 500.0", columns);
    assert_eq!(uff, plain);
    let listing = msd_experiment::inspect::inspect(&path).unwrap();
    for said in [
        "Its 2 time responses read as columns",
        "1:+Z #2  m",
        "[data]\npath = \"run.uff\"\nsample_rate = 500\ninput = \"1:+Z #1\"\noutput = \"1:+Z #2\"",
    ] {
        assert!(listing.contains(said), "{listing}");
    }
    let init = msd_experiment::init::init(&path, &Default::default()).unwrap();
    assert!(
        init.text.contains("excitation = \"force\""),
        "{}",
        init.text
    );
}

/// An analyser's export of magnitude in decibels and phase: `msd inspect` gives the
/// lines with `magnitude_in_db = true`; without the key it is refused (its name says dB;
/// a negative value says so too); with it the mode comes back where it was put.
#[test]
fn a_magnitude_in_decibels_is_refused_until_the_key_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let (m, k, zeta) = (1.0, (2.0 * std::f64::consts::PI * 100.0).powi(2), 0.01);
    let c = 2.0 * zeta * (k * m).sqrt();
    let mut text = String::from("Frequency (Hz),Magnitude (dB),Phase (deg)\n");
    for i in 1..=1600 {
        let f = i as f64 * 0.3125;
        let w = 2.0 * std::f64::consts::PI * f;
        let h = 1.0 / msd_signal::Complex64::new(k - m * w * w, c * w);
        let db = 20.0 * h.norm().log10();
        text.push_str(&format!("{f:.4},{db:.9},{:.9}\n", h.arg().to_degrees()));
    }
    std::fs::write(dir.path().join("db.csv"), &text).unwrap();
    let listing = msd_experiment::inspect::inspect(&dir.path().join("db.csv")).unwrap();
    for line in [
        "magnitude = \"Magnitude (dB)\"\nphase = \"Phase (deg)\"\nmagnitude_in_db = true",
        "frequency = \"Frequency (Hz)\"",
    ] {
        assert!(listing.contains(line), "{listing}");
    }
    let table = "name = \"db\"\n[frequency_response.table]\npath = \"db.csv\"\nfrequency = \"Frequency (Hz)\"\nmagnitude = \"Magnitude (dB)\"\nphase = \"Phase (deg)\"\n";
    let config = dir.path().join("db.toml");
    std::fs::write(&config, table).unwrap();
    let refused = run_in_temp(&config, None, None)
        .err()
        .expect("refused")
        .to_string();
    assert!(
        refused.contains("magnitude = `Magnitude (dB)`")
            && refused.contains("magnitude_in_db = true"),
        "{refused}"
    );
    std::fs::write(&config, format!("{table}magnitude_in_db = true\n")).unwrap();
    let run = run_in_temp(&config, None, None).expect("read in decibels");
    let f = run.number("estimate.natural_frequency_hz.value");
    assert!((f / 100.0 - 1.0).abs() < 1e-4, "fn = {f}");
    // Named otherwise, its negative values give it away.
    let renamed = table.replace("Magnitude (dB)", "Mag");
    std::fs::write(
        dir.path().join("db.csv"),
        text.replace("Magnitude (dB)", "Mag"),
    )
    .unwrap();
    std::fs::write(&config, renamed).unwrap();
    let refused = run_in_temp(&config, None, None)
        .err()
        .expect("refused")
        .to_string();
    assert!(
        refused.contains("holds -") && refused.contains("on line 2"),
        "{refused}"
    );
}

/// A frequency column in rad/s (or kHz) is refused when read as Hz — every mode would be
/// 2π× off, silently — and read with `frequency_unit`, which `msd inspect` writes.
#[test]
fn a_frequency_column_in_radians_per_second_is_read_as_such() {
    let dir = tempfile::tempdir().unwrap();
    let (m, k, zeta) = (1.0, (2.0 * std::f64::consts::PI * 40.0).powi(2), 0.02);
    let c = 2.0 * zeta * (k * m).sqrt();
    let mut text = String::from("w (rad/s),Re,Im\n");
    for i in 1..=800 {
        let w = i as f64 * 0.5;
        let h = 1.0 / msd_signal::Complex64::new(k - m * w * w, c * w);
        text.push_str(&format!("{w:.3},{:e},{:e}\n", h.re, h.im));
    }
    std::fs::write(dir.path().join("w.csv"), &text).unwrap();
    let listing = msd_experiment::inspect::inspect(&dir.path().join("w.csv")).unwrap();
    assert!(
        listing.contains("frequency = \"w (rad/s)\"\nfrequency_unit = \"rad/s\""),
        "{listing}"
    );
    let lines = &listing[listing.find("[frequency_response.table]").unwrap()..];
    let config = dir.path().join("w.toml");
    let table = format!(
        "name = \"w\"\n{}",
        lines.replace("accelerance", "receptance")
    );
    std::fs::write(&config, &table).unwrap();
    let run = run_in_temp(&config, None, None).expect("the lines msd inspect printed run");
    let f = run.number("estimate.natural_frequency_hz.value");
    assert!((f / 40.0 - 1.0).abs() < 1e-6, "fn = {f}");
    std::fs::write(&config, table.replace("frequency_unit = \"rad/s\"\n", "")).unwrap();
    let refused = run_in_temp(&config, None, None)
        .err()
        .expect("refused")
        .to_string();
    assert!(
        refused.contains("its name says rad/s") && refused.contains("frequency_unit = \"rad/s\""),
        "{refused}"
    );
    let khz = text.replace("w (rad/s)", "f [kHz]");
    std::fs::write(dir.path().join("w.csv"), khz).unwrap();
    let listing = msd_experiment::inspect::inspect(&dir.path().join("w.csv")).unwrap();
    assert!(listing.contains("frequency_unit = \"kHz\""), "{listing}");
}

/// A data file that is not what its extension says, or is cut short, is refused before
/// anything is written: exit status 2, the file and the key named.
#[test]
fn a_damaged_binary_file_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let fixture = msd_tests::root().join("crates/msd-files/fixtures/record-v7.mat");
    let bytes = std::fs::read(fixture).unwrap();
    std::fs::write(dir.path().join("cut.mat"), &bytes[..bytes.len() / 2]).unwrap();
    std::fs::write(dir.path().join("text.npy"), "t,F\n0,1\n").unwrap();
    for (file, expected) in [
        ("cut.mat", "not a MATLAB .mat file"),
        ("text.npy", "not a NumPy .npy file"),
    ] {
        let config = dir.path().join("c.toml");
        std::fs::write(
            &config,
            format!("name = \"bad\"\n[data]\npath = \"{file}\"\ninput = \"force\"\noutput = \"x\"\nsample_rate = 100\n"),
        )
        .unwrap();
        let Err(err) = run_in_temp(&config, None, None) else {
            panic!("{file}: a damaged file must be refused");
        };
        assert_eq!(err.exit_code(), 2, "{err}");
        let message = err.to_string();
        for fragment in [file, "data.path", expected] {
            assert!(message.contains(fragment), "`{message}` lacks `{fragment}`");
        }
    }
}

/// Every text reader's format keys are checked alike: a decimal mark that is neither
/// "." nor "," is refused, naming the section's key.
#[test]
fn a_table_s_decimal_mark_is_checked_as_data_s() {
    let dir = tempfile::tempdir().unwrap();
    for (section, extra) in [
        (
            "frequency_response.table",
            "frequency = 0\nreal = 1\nimaginary = 2\n",
        ),
        (
            "frequency_response.records",
            "sample_rate = 100\nforce = [0]\nresponse = [1]\n",
        ),
    ] {
        let config = dir.path().join("c.toml");
        std::fs::write(
            &config,
            format!("name = \"t\"\n[{section}]\npath = \"x.csv\"\ndecimal = \"x\"\n{extra}"),
        )
        .unwrap();
        let Err(err) = run_in_temp(&config, None, None) else {
            panic!("{section}: decimal = \"x\" must be refused");
        };
        assert_eq!(err.exit_code(), 2, "{err}");
        assert!(
            err.to_string().contains(&format!("{section}.decimal")),
            "{err}"
        );
    }
}

/// An analyser's FRF export with its coherence (issue 44 §1): 1601 lines 0–500 Hz of
/// accelerance written with the other phase convention (the conjugate), coherence 0.4
/// around the peak and 0.95 away from it. `[frequency_response.table]` with `coherence`
/// and `averages` and no band: the band chosen around the peak, the conjugate fitted and
/// said so, the low coherence reported, fn exact (the data are noise-free); a coherence
/// outside [0, 1] refused naming its line.
#[test]
fn an_analyser_export_with_coherence_is_fitted_at_defaults() {
    use std::f64::consts::TAU;
    let dir = tempfile::tempdir().unwrap();
    let (fn_hz, zeta) = (192.4, 0.008);
    let wn = TAU * fn_hz;
    let mut text = String::from("f,re,im,coh\n");
    for i in 0..=1600 {
        let f = 0.3125 * i as f64;
        let w = TAU * f;
        // A = −ω²/(ωn² − ω² + 2jζωnω), conjugated.
        let (re, im) = (wn * wn - w * w, 2.0 * zeta * wn * w);
        let d = re * re + im * im;
        let (a, b) = (-w * w * re / d, -w * w * im / d);
        let coherence = 0.95 - 0.55 * (-((f - fn_hz) / 10.0).powi(2)).exp();
        text.push_str(&format!("{f},{a:e},{b:e},{coherence}\n"));
    }
    std::fs::write(dir.path().join("frf.csv"), &text).unwrap();
    let config = dir.path().join("frf.toml");
    let write = |extra: &str| {
        std::fs::write(
            &config,
            format!("name = \"export\"\n[frequency_response.table]\npath = \"frf.csv\"\nfrequency = \"f\"\nreal = \"re\"\nimaginary = \"im\"\ncoherence = \"coh\"\naverages = 10\nkind = \"accelerance\"\n{extra}"),
        )
        .unwrap()
    };
    write("");
    let run = run_in_temp(&config, None, None).expect("fitted at defaults");
    let f = run.number("estimate.natural_frequency_hz.value");
    assert!((f / fn_hz - 1.0).abs() < 1e-6, "fn = {f}");
    assert!(run.flag("estimate.conjugated"));
    let peak = run.number("estimate.dominant_peak.peak_hz");
    assert!((peak - fn_hz).abs() <= 0.3125, "peak at {peak}");
    assert!(run.number("estimate.low_coherence.median") < 0.5);
    let report = std::fs::read_to_string(run.out().join("report.md")).unwrap();
    for text in [
        "phase rises through the resonance",
        "the coherence is only",
        "around the dominant resonance",
    ] {
        assert!(report.contains(text), "{text}: {report}");
    }
    std::fs::write(
        dir.path().join("frf.csv"),
        text.replacen(",0.95\n", ",1.5\n", 1),
    )
    .unwrap();
    let Err(e) = run_in_temp(&config, None, None) else {
        panic!("γ² = 1.5 was accepted");
    };
    let message = e.to_string();
    assert!(
        message.contains("line 2") && message.contains("1.5"),
        "{message}"
    );
}
