//! msd-experiment's commands: `run` (a config to its result folder), `plan`, `design`.

use crate::convert::{integer, integer_in, result_dict, value_to_py, vec_f64};
use crate::errors;
use msd_experiment::config::Config;
use msd_experiment::design::DesignRunOptions;
use msd_experiment::plan::PlanOptions;
use msd_experiment::{DEFAULT_RESULTS_ROOT, ExperimentError, RunOptions};
use numpy::PyReadonlyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// A table's columns as Python gives them: (name, values) pairs.
type NamedColumns<'py> = Vec<(String, PyReadonlyArray1<'py, f64>)>;

/// run(config, config_json, out, seed, threads, files, tables)
/// --
///
/// msd-experiment's `run_config`: the config from its file (`config`) or from its JSON
/// text (`config_json`, a dict), the data files given in memory as bytes (`files`) or
/// named columns (`tables`), by the path the config writes; the results.json content,
/// the summary and the output folder.
#[pyfunction]
#[pyo3(signature = (config, config_json, out=None, seed=None, threads=None, files=None, tables=None))]
#[allow(clippy::too_many_arguments)]
pub fn run<'py>(
    py: Python<'py>,
    config: Option<PathBuf>,
    config_json: Option<String>,
    out: Option<PathBuf>,
    seed: Option<Bound<'py, PyAny>>,
    threads: Option<Bound<'py, PyAny>>,
    files: Option<BTreeMap<String, Vec<u8>>>,
    tables: Option<BTreeMap<String, NamedColumns<'py>>>,
) -> PyResult<Bound<'py, PyDict>> {
    let options = RunOptions {
        out,
        seed: seed.map(|s| integer("seed", &s)).transpose()?,
        threads: threads
            .map(|t| integer_in("threads", &t, 1, msd_mc::MAX_THREADS as i128))
            .transpose()?,
        ..RunOptions::default()
    };
    let mut config = match (config, config_json) {
        (Some(path), _) => Config::load(&path),
        (None, Some(json)) => serde_json::from_str(&json)
            .map_err(|e| {
                ExperimentError::config("config", format!("{e}: expected a table of keys"))
            })
            .and_then(|v| Config::from_value(v, "config.toml")),
        (None, None) => Err(ExperimentError::config(
            "config",
            "missing: expected a file or a dict",
        )),
    }
    .map_err(errors::experiment)?;
    let mut sources = config.sources.clone();
    for (path, bytes) in files.unwrap_or_default() {
        sources = sources.with_bytes(path, bytes);
    }
    for (path, columns) in tables.unwrap_or_default() {
        let columns = columns
            .iter()
            .map(|(n, a)| (n.clone(), vec_f64(a)))
            .collect();
        sources = sources.with_columns(path, columns);
    }
    config.sources = sources;
    let summary = py
        .detach(|| msd_experiment::run_config(config, &options))
        .map_err(errors::experiment)?;
    let d = PyDict::new(py);
    d.set_item("results", value_to_py(py, &summary.results)?)?;
    d.set_item("summary", summary.summary)?;
    d.set_item("out_dir", summary.out_dir)?;
    Ok(d)
}

/// plan(config, target, verify)
/// --
///
/// msd-experiment's `plan`: the predicted precision of a synthetic config's test.
#[pyfunction]
#[pyo3(signature = (config, target=0.01, verify=None), text_signature = "(config, target=0.01, verify=0)")]
pub fn plan<'py>(
    py: Python<'py>,
    config: PathBuf,
    target: f64,
    verify: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let options = PlanOptions {
        target,
        verify: verify
            .map(|v| integer("verify", &v))
            .transpose()?
            .unwrap_or(0),
        ..PlanOptions::default()
    };
    let plan = py
        .detach(|| msd_experiment::plan::plan(&config, &options))
        .map_err(errors::experiment)?;
    let dict = result_dict(py, &plan, &[])?;
    dict.set_item("summary", plan.to_string())?;
    Ok(dict)
}

/// design(config, out, verify, write)
/// --
///
/// msd-experiment's `design` (and, when `write`, its files in `out`, else
/// `msd-results/<name>-design`).
#[pyfunction]
#[pyo3(signature = (config, out=None, verify=None, write=true), text_signature = "(config, out=None, verify=0, write=True)")]
pub fn design<'py>(
    py: Python<'py>,
    config: PathBuf,
    out: Option<PathBuf>,
    verify: Option<Bound<'py, PyAny>>,
    write: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let options = DesignRunOptions {
        verify: verify
            .map(|v| integer("verify", &v))
            .transpose()?
            .unwrap_or(0),
        out: out.clone(),
        ..DesignRunOptions::default()
    };
    let (report, target) = py
        .detach(|| {
            let report = msd_experiment::design::design(&config, &options)?;
            let target = if write {
                let target = out.unwrap_or_else(|| {
                    PathBuf::from(DEFAULT_RESULTS_ROOT)
                        .join(format!("{}-design", report.config.name))
                });
                msd_experiment::design::write(&report, &report.config, &target)?;
                Some(target)
            } else {
                None
            };
            Ok((report, target))
        })
        .map_err(errors::experiment)?;
    let dict = result_dict(py, &report, &[])?;
    dict.set_item("summary", report.to_string())?;
    dict.set_item("out_dir", target)?;
    Ok(dict)
}
