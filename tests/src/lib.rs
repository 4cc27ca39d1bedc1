//! Cross-crate end-to-end tests of the msd toolkit, and the helpers they share.
//!
//! The tests live in `tests/tests/`; this library gives them the workspace paths, an
//! in-process way to run an experiment into a temporary folder, and checks of the files
//! an experiment writes (PNG decodes, SVG parses).

use msd_experiment::{ExperimentError, RunOptions, RunSummary, run_experiment};
use std::path::{Path, PathBuf};

/// The workspace root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from(".."))
}

/// A shipped config, e.g. `config("paper.toml")`.
pub fn config(name: &str) -> PathBuf {
    root().join("configs").join(name)
}

/// A finished run and the temporary folder that holds its output (kept alive with it).
pub struct Run {
    /// The temporary parent folder.
    pub dir: tempfile::TempDir,
    /// What the run returned.
    pub summary: RunSummary,
}

impl Run {
    /// The output folder.
    pub fn out(&self) -> &Path {
        &self.summary.out_dir
    }

    /// A number of results.json by its dotted path, e.g. `"estimate.mass.value"`.
    pub fn number(&self, path: &str) -> f64 {
        lookup(&self.summary.results, path)
            .and_then(serde_json::Value::as_f64)
            .unwrap_or_else(|| panic!("results.json has no number at {path}"))
    }

    /// A boolean of results.json by its dotted path.
    pub fn flag(&self, path: &str) -> bool {
        lookup(&self.summary.results, path)
            .and_then(serde_json::Value::as_bool)
            .unwrap_or_else(|| panic!("results.json has no boolean at {path}"))
    }
}

/// Asserts that `dir/results.json` is `results` byte for byte (pretty-printed, with a
/// final newline): comparing the documents then compares the files, since the floats are
/// written in shortest round-trip form. (Parsing the file back is not exact: serde_json's
/// default float parser may be off by one ulp.)
pub fn assert_results_file_is(dir: &Path, results: &serde_json::Value) {
    let on_disk = std::fs::read_to_string(dir.join("results.json"))
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    let expected = serde_json::to_string_pretty(results).expect("serialisable") + "\n";
    assert!(
        on_disk == expected,
        "{}/results.json differs from the returned document",
        dir.display()
    );
}

/// The value at a dotted path of a JSON document.
pub fn lookup<'a>(value: &'a serde_json::Value, path: &str) -> Option<&'a serde_json::Value> {
    path.split('.').try_fold(value, |v, key| v.get(key))
}

/// Runs `config` in-process into a fresh temporary folder.
pub fn run_in_temp(
    config: &Path,
    seed: Option<u64>,
    threads: Option<usize>,
) -> Result<Run, ExperimentError> {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let options = RunOptions {
        out: Some(dir.path().join("out")),
        seed,
        threads,
        ..RunOptions::default()
    };
    let summary = run_experiment(config, &options)?;
    Ok(Run { dir, summary })
}

/// `results.json` with the wall times and the recorded thread counts removed: what must
/// be identical between runs of the same config and seed.
pub fn without_timings(results: &serde_json::Value) -> serde_json::Value {
    let mut v = results.clone();
    if let Some(map) = v.as_object_mut() {
        map.remove("timings_ms");
        for section in ["experiment", "monte_carlo"] {
            if let Some(s) = map.get_mut(section).and_then(|s| s.as_object_mut()) {
                s.remove("threads");
            }
        }
        if let Some(c) = map
            .get_mut("config")
            .and_then(|c| c.get_mut("monte_carlo"))
            .and_then(|m| m.as_object_mut())
        {
            c.remove("threads");
        }
    }
    v
}

/// A small synthetic experiment (4 s at 5 ms, 801 samples; 50 Monte Carlo draws on the
/// exact simulator): a whole run in a fraction of a second, even in debug.
pub const TINY_CONFIG: &str = include_str!("../fixtures/tiny.toml");

/// The names in a folder, sorted (hidden ones included).
pub fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| {
            e.expect("a folder entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.sort();
    names
}

/// Decodes a PNG (every row of its pixels) and returns its size.
pub fn decode_png(path: &Path) -> (u32, u32) {
    let decode = || -> Result<(u32, u32), String> {
        let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
        let mut reader = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .map_err(|e| e.to_string())?;
        let mut pixels = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut pixels).map_err(|e| e.to_string())?;
        Ok((info.width, info.height))
    };
    decode().unwrap_or_else(|e| panic!("{} does not decode: {e}", path.display()))
}

/// Parses an SVG as XML and returns the number of elements.
pub fn parse_svg(path: &Path) -> usize {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let doc = roxmltree::Document::parse(&text)
        .unwrap_or_else(|e| panic!("{} does not parse: {e}", path.display()));
    assert_eq!(
        doc.root_element().tag_name().name(),
        "svg",
        "{}",
        path.display()
    );
    doc.descendants()
        .filter(roxmltree::Node::is_element)
        .count()
}

/// The folder `data/<set>/` of a real data set when it is in the workspace.
///
/// When it is not (a fresh clone): `None`, after a note on stderr naming the test that
/// did not run and the command that fetches the set — unless the environment variable
/// `MSD_REQUIRE_REAL_DATA` is set (CI sets it), where a missing set fails the test.
pub fn real_data(set: &str, test: &str) -> Option<PathBuf> {
    let folder = root().join("data").join(set);
    if folder.is_dir() {
        return Some(folder);
    }
    let fetch = format!("cargo xtask fetch-data {set}");
    assert!(
        std::env::var_os("MSD_REQUIRE_REAL_DATA").is_none(),
        "{test}: the real data set `{set}` is required here (MSD_REQUIRE_REAL_DATA) and missing: run `{fetch}`"
    );
    eprintln!(
        "{test}: skipped, the real data set `{set}` is not in data/{set}/; `{fetch}` fetches it"
    );
    None
}
