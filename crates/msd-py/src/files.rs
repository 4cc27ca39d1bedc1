//! msd-files' readers (MATLAB .mat, NumPy .npy/.npz, NI TDMS) and `msd inspect`.

use crate::errors;
use numpy::PyArray1;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// The channels of a data file: a list of dicts (name, unit, sample_rate_hz, values)
/// and the list of what was skipped.
#[pyfunction]
pub fn read_file<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
) -> PyResult<(Bound<'py, PyList>, Vec<String>)> {
    let contents = py.detach(|| msd_files::read(&path)).map_err(|e| match e {
        msd_files::FilesError::Io { .. } => PyOSError::new_err(e.to_string()),
        other => PyValueError::new_err(other.to_string()),
    })?;
    let out = PyList::empty(py);
    for c in contents.channels {
        let d = PyDict::new(py);
        d.set_item("name", &c.name)?;
        d.set_item("unit", &c.unit)?;
        d.set_item("sample_rate_hz", c.sample_rate_hz)?;
        d.set_item("values", PyArray1::from_vec(py, c.values))?;
        out.append(d)?;
    }
    Ok((out, contents.skipped))
}

/// `msd inspect FILE`'s report.
#[pyfunction]
pub fn inspect(path: std::path::PathBuf) -> PyResult<String> {
    msd_experiment::inspect::inspect(&path).map_err(errors::experiment)
}

/// `msd init FILE`: writes a config for the file beside it; returns its path, its text
/// and what was found.
#[pyfunction]
#[pyo3(signature = (path, input=None, outputs=Vec::new(), sample_rate=None, config=None, overwrite=false))]
pub fn init(
    path: std::path::PathBuf,
    input: Option<String>,
    outputs: Vec<String>,
    sample_rate: Option<f64>,
    config: Option<std::path::PathBuf>,
    overwrite: bool,
) -> PyResult<(std::path::PathBuf, String, String)> {
    let options = msd_experiment::init::InitOptions {
        input,
        outputs,
        sample_rate_hz: sample_rate,
        config,
        overwrite,
    };
    let done = msd_experiment::init::init(&path, &options).map_err(errors::experiment)?;
    Ok((done.config_path, done.text, done.summary))
}
