//! Every class of bad input is refused before anything is written: exit status 2 and
//! one line naming the file, the line or field, the value and what was expected.

use msd_experiment::{RunOptions, run_experiment};
use msd_tests::config;
use std::path::{Path, PathBuf};

/// A scratch folder holding the bad config (and data), with the output folder planned
/// inside it.
pub(crate) struct Case {
    pub(crate) dir: tempfile::TempDir,
}

impl Case {
    pub(crate) fn new() -> Self {
        Self {
            dir: tempfile::tempdir().unwrap(),
        }
    }

    pub(crate) fn file(&self, name: &str, text: &str) -> PathBuf {
        let path = self.dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    /// Runs `config` and checks the refusal: exit status 2, one line containing every
    /// `expected` fragment, and nothing written.
    pub(crate) fn refuses(&self, config: &Path, expected: &[&str]) {
        let before: Vec<_> = listing(self.dir.path());
        let out = self.dir.path().join("out");
        let options = RunOptions {
            out: Some(out.clone()),
            ..RunOptions::default()
        };
        let err = run_experiment(config, &options).expect_err("bad input must be refused");
        assert_eq!(err.exit_code(), 2, "{err}");
        let message = err.to_string();
        assert!(!message.contains('\n'), "one line: {message}");
        for fragment in expected {
            assert!(message.contains(fragment), "`{message}` lacks `{fragment}`");
        }
        assert!(!out.exists(), "an output folder was written for: {message}");
        assert_eq!(
            listing(self.dir.path()),
            before,
            "files appeared for: {message}"
        );
    }
}

fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// The paper-fast config with `from` replaced by `to` (which must occur).
fn paper_with(from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(config("paper-fast.toml")).unwrap();
    assert!(text.contains(from), "paper-fast.toml has no `{from}`");
    text.replacen(from, to, 1)
}

#[test]
fn unknown_key() {
    let case = Case::new();
    let c = case.file(
        "c.toml",
        &paper_with("seed = 1\n", "seed = 1\ncolour = \"red\"\n"),
    );
    case.refuses(
        &c,
        &["c.toml:", "unknown field `colour`", "expected one of"],
    );
    let c = case.file(
        "d.toml",
        &paper_with("[noise]\n", "[noise]\nsigma_mm = 2.5\n"),
    );
    case.refuses(
        &c,
        &["d.toml:", "unknown field `sigma_mm`", "expected `sigma`"],
    );
}

#[test]
fn wrong_type() {
    let case = Case::new();
    let c = case.file("c.toml", &paper_with("mass = 2.5 ", "mass = \"heavy\" "));
    case.refuses(
        &c,
        &[
            "c.toml:23:8",
            "invalid type: string \"heavy\", expected f64",
        ],
    );
}

#[test]
fn missing_field() {
    let case = Case::new();
    let c = case.file("c.toml", &paper_with("dt = 0.002 ", "# dt removed "));
    case.refuses(&c, &["c.toml:", "missing field `dt`", "[time]"]);
    let text = std::fs::read_to_string(config("paper-fast.toml")).unwrap();
    let without_noise = text.replace("[noise]\nsigma = 0.0025", "");
    let c = case.file("d.toml", &without_noise);
    case.refuses(&c, &["d.toml", "noise: missing section"]);
}

#[test]
fn negative_mass() {
    let case = Case::new();
    let c = case.file("c.toml", &paper_with("mass = 2.5 ", "mass = -2.5 "));
    case.refuses(
        &c,
        &[
            "c.toml:23",
            "plant.mass = -2.5",
            "expected a finite number > 0",
        ],
    );
    let c = case.file(
        "d.toml",
        &paper_with(
            "initial_guess = { mass = 2.0",
            "initial_guess = { mass = -2.0",
        ),
    );
    case.refuses(&c, &["d.toml", "estimation.initial_guess.mass = -2", "> 0"]);
}

#[test]
fn non_positive_dt() {
    let case = Case::new();
    let c = case.file("c.toml", &paper_with("dt = 0.002 ", "dt = 0.0 "));
    case.refuses(
        &c,
        &["c.toml:33", "time.dt = 0", "expected a finite number > 0"],
    );
    let c = case.file("d.toml", &paper_with("dt = 0.002 ", "dt = -0.002 "));
    case.refuses(&c, &["time.dt = -0.002"]);
}

#[test]
fn duration_shorter_than_dt() {
    let case = Case::new();
    let c = case.file(
        "c.toml",
        &paper_with("duration = 15.0 ", "duration = 0.001 "),
    );
    case.refuses(
        &c,
        &[
            "c.toml:32",
            "time.duration = 0.001",
            "expected at least one step dt = 0.002",
        ],
    );
}

#[test]
fn nan_in_config() {
    let case = Case::new();
    let c = case.file(
        "c.toml",
        &paper_with("stiffness = 120.0 ", "stiffness = nan "),
    );
    case.refuses(
        &c,
        &[
            "c.toml:25",
            "plant.stiffness = NaN",
            "expected a finite number",
        ],
    );
    let c = case.file("d.toml", &paper_with("sigma = 0.0025 ", "sigma = inf "));
    case.refuses(&c, &["noise.sigma = inf", "expected a finite number >= 0"]);
}

/// The stage options are checked once, by the library that owns them (msd-ident,
/// msd-mc), and the refusal names the TOML key and its line: the config and the library
/// can no longer disagree on a limit.
#[test]
fn stage_options_are_refused_by_the_library_under_their_key() {
    let case = Case::new();
    let cases = [
        (
            "samples = 1000 ",
            "samples = 0 ",
            "c.toml:144: monte_carlo.samples = 0: the number of samples must be at least 1",
        ),
        (
            "percentiles = [5.0, 95.0]",
            "percentiles = [5.0, 50.0]",
            "c.toml:146: monte_carlo.percentiles = [5, 50]: percentiles must be strictly increasing",
        ),
        (
            "power_threshold = 0.01",
            "power_threshold = 1.5",
            "c.toml:135: frequency_check.power_threshold = 1.5: expected a share of the peak power in (0, 1]",
        ),
        (
            "[estimation]\n",
            "[estimation]\nfixed = { mass = -1.0 }\n",
            "estimation.fixed.mass = -1: expected a finite number > 0",
        ),
    ];
    for (from, to, expected) in cases {
        let c = case.file("c.toml", &paper_with(from, to));
        case.refuses(&c, &[expected]);
    }
    // The library allows a power threshold of 1 (only the peak line): so does the config.
    let ok = paper_with("power_threshold = 0.01", "power_threshold = 1.0");
    msd_experiment::config::Config::from_toml_str(&ok, "ok.toml").expect("1.0 is allowed");
}

/// A `[low, high]` pair with a third value is refused by name and line, not read as its
/// first two values.
#[test]
fn a_pair_with_extra_values_is_refused() {
    let case = Case::new();
    let cases = [
        (
            "percentiles = [5.0, 95.0]",
            "percentiles = [5.0, 95.0, 99.0]",
            "c.toml:146:15: monte_carlo.percentiles = [5.0, 95.0, 99.0]",
        ),
        (
            "[estimation]\n",
            "[estimation]\nbounds = { stiffness = [50.0, 200.0, 300.0] }\n",
            "c.toml:92",
        ),
    ];
    for (from, to, location) in cases {
        let c = case.file("c.toml", &paper_with(from, to));
        case.refuses(&c, &[location, "expected 2 values [low, high], got 3"]);
    }
    let c = case.file(
        "m.toml",
        &measured_config("d.csv", "x", "time = [0.0, 10.0, 99.0]"),
    );
    case.refuses(&c, &["m.toml:8", "expected 2 values [low, high], got 3"]);
}

/// A physical quantity's table written as an array would be read by position (m, c, k
/// in that order): refused by name and line, whatever the order the user meant.
#[test]
fn a_table_written_as_an_array_is_refused() {
    let case = Case::new();
    let text = std::fs::read_to_string(config("paper-fast.toml")).unwrap();
    let start = text
        .find("[plant]")
        .expect("paper-fast.toml has a [plant] section");
    let end = start + text[start..].find("\n[").expect("a section after [plant]") + 1;
    for replacement in [
        "plant = [1.0, 2.0, 3.0]\n",
        "[plant]\nmass = 2.5\ndamping = 1.8\nstiffness = 120.0\ninitial_state = [0.01, 0.0]\n",
    ] {
        let with = format!("{}{replacement}{}", &text[..start], &text[end..]);
        let c = case.file("c.toml", &with);
        let key = if replacement.starts_with("plant =") {
            "plant = [1.0, 2.0, 3.0]"
        } else {
            "plant.initial_state = [0.01, 0.0]"
        };
        case.refuses(&c, &["c.toml:", key, "read by name"]);
    }
    let c = case.file(
        "e.toml",
        &paper_with(
            "[estimation]\n",
            "[estimation]\nfixed = [2.5, 1.8, 120.0]\n",
        ),
    );
    case.refuses(
        &c,
        &["estimation.fixed = [2.5, 1.8, 120.0]", "read by name"],
    );
}

/// Limits that are config values are refused as config errors, naming the key, the value
/// and the largest accepted; the thread limit is one for the key and `--threads`.
#[test]
fn config_values_beyond_a_limit_name_the_limit() {
    let case = Case::new();
    let largest = msd_mc::McOptions::default().max_samples();
    let c = case.file(
        "c.toml",
        &paper_with("samples = 1000 ", "samples = 1000000000 "),
    );
    case.refuses(
        &c,
        &[
            "c.toml:144: monte_carlo.samples = 1000000000",
            &format!("expected at most {largest} draws"),
        ],
    );
    let c = case.file(
        "t.toml",
        &paper_with(
            "threads = 2                 # rayon",
            "threads = 10000             # rayon",
        ),
    );
    case.refuses(
        &c,
        &[
            "monte_carlo.threads = 10000",
            &format!("expected at most {}", msd_mc::MAX_THREADS),
        ],
    );
}

/// A value whose square overflows is refused where it is read, with its line and
/// column, instead of surfacing as "the input does not excite the system".
#[test]
fn a_huge_value_is_refused_at_its_line() {
    let case = Case::new();
    case.file("d.csv", &csv_with(57, "0.57,1.0,1e300"));
    let c = case.file("c.toml", &measured_config("d.csv", "displacement", ""));
    case.refuses(
        &c,
        &[
            "d.csv",
            "line 59, output column `displacement`",
            "1e300 is too large",
            "1e100",
        ],
    );
}

#[test]
fn missing_config_file() {
    let case = Case::new();
    let missing = case.dir.path().join("nope.toml");
    case.refuses(&missing, &["nope.toml", "cannot read the config file"]);
}

/// A small, valid lab file: 100 rows at 100 Hz.
const GOOD_CSV: &str = "t,force,displacement\n";

fn good_rows() -> Vec<String> {
    (0..100)
        .map(|i| format!("{:.2},{},{}", i as f64 * 0.01, 1.0, 0.001 * (i % 7) as f64))
        .collect()
}

fn csv_with(row: usize, replacement: &str) -> String {
    let mut rows = good_rows();
    rows[row] = replacement.to_string();
    format!("{GOOD_CSV}{}\n", rows.join("\n"))
}

fn measured_config(path: &str, output: &str, estimation: &str) -> String {
    format!(
        "name = \"lab\"\n[data]\npath = \"{path}\"\ninput = \"force\"\noutput = \"{output}\"\ntime = \"t\"\n[data.estimation]\n{estimation}\n[monte_carlo]\nenabled = false\n"
    )
}

#[test]
fn missing_data_file() {
    let case = Case::new();
    let c = case.file(
        "c.toml",
        &measured_config("missing.csv", "displacement", ""),
    );
    case.refuses(
        &c,
        &["missing.csv", "cannot open the data file", "No such file"],
    );
}

#[test]
fn missing_csv_column() {
    let case = Case::new();
    case.file("data.csv", &csv_with(0, "0.00,1.0,0.0"));
    let c = case.file("c.toml", &measured_config("data.csv", "disp", ""));
    case.refuses(
        &c,
        &[
            "data.csv",
            "line 1",
            "no output column named `disp`",
            "`t`, `force`, `displacement`",
        ],
    );
    let c = case.file(
        "d.toml",
        &measured_config("data.csv", "displacement", "").replace("input = \"force\"", "input = 7"),
    );
    case.refuses(&c, &["data.csv", "line 2", "no input column #7"]);
}

/// Issue 31, class 5: line numbers are the file's own when comment and blank lines come
/// before the header or the rows.
#[test]
fn line_numbers_count_the_comment_lines_before_the_header() {
    let case = Case::new();
    let body = csv_with(0, "0.00,1.0,0.0");
    case.file(
        "data.csv",
        &format!("# rig 3, run 7\n\n# operator: A. B.\n{body}"),
    );
    let c = case.file("c.toml", &measured_config("data.csv", "disp", ""));
    case.refuses(&c, &["data.csv", "line 4", "no output column named `disp`"]);
    // Text in the middle of the data (header = false): its line is named. (Text above
    // the first numeric line is metadata, skipped and reported.)
    let body = csv_with(30, "0.30,1.0,abc");
    case.file(
        "e.csv",
        &format!("# rig 3\n{}", body.split_once('\n').unwrap().1),
    );
    let c = case.file(
        "d.toml",
        &measured_config("e.csv", "2", "")
            .replace("output = \"2\"", "output = 2")
            .replace("input = \"force\"", "input = 1\nheader = false")
            .replace("time = \"t\"", "time = 0"),
    );
    case.refuses(&c, &["e.csv", "line 32", "`abc` is not a number"]);
}

#[test]
fn non_numeric_cell() {
    let case = Case::new();
    case.file("data.csv", &csv_with(48, "0.48,1.0,abc"));
    let c = case.file("c.toml", &measured_config("data.csv", "displacement", ""));
    case.refuses(
        &c,
        &[
            "data.csv",
            "line 50",
            "output column `displacement`",
            "`abc` is not a number",
        ],
    );
    case.file("empty.csv", &csv_with(10, "0.10,,0.0"));
    let c = case.file("d.toml", &measured_config("empty.csv", "displacement", ""));
    case.refuses(
        &c,
        &["empty.csv", "line 12", "input column `force`", "empty cell"],
    );
}

#[test]
fn nan_in_data() {
    let case = Case::new();
    case.file("data.csv", &csv_with(48, "0.48,NaN,0.0"));
    let c = case.file("c.toml", &measured_config("data.csv", "displacement", ""));
    case.refuses(
        &c,
        &[
            "data.csv",
            "line 50",
            "input column `force`",
            "`NaN`: expected a number (set missing = \"drop\" or \"interpolate\"",
        ],
    );
}

#[test]
fn non_monotonic_time() {
    let case = Case::new();
    case.file("data.csv", &csv_with(48, "0.30,1.0,0.0"));
    let c = case.file("c.toml", &measured_config("data.csv", "displacement", ""));
    case.refuses(
        &c,
        &[
            "data.csv",
            "line 50",
            "time column",
            "0.3 s is not after the previous 0.47 s",
            "increasing",
        ],
    );
}

#[test]
fn ranges_outside_the_data() {
    let case = Case::new();
    case.file("data.csv", &csv_with(0, "0.00,1.0,0.0"));
    let c = case.file(
        "c.toml",
        &measured_config("data.csv", "displacement", "range = [0, 500]"),
    );
    case.refuses(
        &c,
        &[
            "c.toml",
            "data.estimation.range = [0, 500]",
            "outside the data",
            "<= 100",
        ],
    );
    let c = case.file(
        "d.toml",
        &measured_config("data.csv", "displacement", "time = [0.5, 3.0]"),
    );
    case.refuses(
        &c,
        &[
            "d.toml",
            "data.estimation.time = [0.5, 3]",
            "outside the data",
            "<= 1 s",
        ],
    );
    let c = case.file(
        "e.toml",
        &measured_config("data.csv", "displacement", "range = [50, 20]"),
    );
    case.refuses(
        &c,
        &["e.toml", "data.estimation.range = [50, 20]", "start < end"],
    );
}

#[test]
fn a_failed_run_leaves_a_previous_result_untouched() {
    let case = Case::new();
    let out = case.dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("results.json"), "{\"previous\": true}").unwrap();
    let c = case.file("c.toml", &paper_with("mass = 2.5 ", "mass = 0.0 "));
    let options = RunOptions {
        out: Some(out.clone()),
        ..RunOptions::default()
    };
    let err = run_experiment(&c, &options).unwrap_err();
    assert_eq!(err.exit_code(), 2);
    assert_eq!(
        std::fs::read_to_string(out.join("results.json")).unwrap(),
        "{\"previous\": true}"
    );
}

/// Issue 46 §1: a chain's sizes go through the one budget before anything is allocated
/// (a 1e9 s record aborted on a 4 TB allocation; 2000 s held 3 GB, the band's draws).
#[test]
fn a_chain_past_the_budget_is_refused_by_its_time_keys() {
    let case = Case::new();
    let shipped = std::fs::read_to_string(config("two-storey.toml")).unwrap();
    for (from, to, expected) in [
        (
            "duration = 10.0",
            "duration = 1e9",
            "time.duration = 1000000000",
        ),
        (
            "duration = 10.0",
            "duration = 2000.0",
            "the largest accepted is 248 s",
        ),
        ("dt = 0.002", "dt = 1e-9", "at time.dt = 0.000000001 s"),
    ] {
        assert!(shipped.contains(from), "{from}");
        let c = case.file("c.toml", &shipped.replacen(from, to, 1));
        case.refuses(&c, &["c.toml", expected, "Monte Carlo band's 200 draws"]);
    }
}
