//! Chains of masses in the time domain: msd-ident's `simulate_chain` and `fit_chain`.

use crate::convert::{options, result_dict, vec_f64};
use crate::errors;
use msd_ident::{ChainOptions, ChainParameters, ChainRecord, ChainSensor, ChainSetup};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::Value;

/// A `ChainSetup` from its JSON (serde's shape), each sensor read on its own so that a
/// bad one is named ("sensors[1]: unknown field `where`").
fn chain_setup(json: &str) -> PyResult<ChainSetup> {
    let mut value: Value = serde_json::from_str(json).map_err(errors::value)?;
    let sensors = match &mut value {
        Value::Object(map) => map.remove("sensors"),
        _ => return Err(PyValueError::new_err("setup: expected a mapping")),
    };
    let mut setup: ChainSetup = options("setup", &value.to_string())?;
    match sensors {
        None | Some(Value::Null) => {}
        Some(Value::Array(items)) => {
            setup.sensors = items
                .iter()
                .enumerate()
                .map(|(i, item)| {
                    options::<ChainSensor>(&format!("sensors[{i}]"), &item.to_string())
                })
                .collect::<PyResult<_>>()?;
        }
        Some(other) => {
            return Err(PyValueError::new_err(format!(
                "sensors = {other}: expected a list of sensors (dicts with at, quantity, delay, estimate_delay, low_pass)"
            )));
        }
    }
    Ok(setup)
}

/// The record of `input` and `outputs` every `dt` s, checked against `setup` as
/// msd-ident checks it (dt, lengths, finite samples, delays shorter than half the record).
fn chain_record(
    setup: &ChainSetup,
    input: Vec<f64>,
    outputs: Vec<Vec<f64>>,
    dt: f64,
) -> PyResult<ChainRecord> {
    setup.validate().map_err(errors::ident)?;
    let record = ChainRecord { dt, input, outputs };
    record.validate(setup).map_err(errors::ident)?;
    Ok(record)
}

/// simulate_chain(setup_json, parameters_json, input, dt)
/// --
///
/// msd-ident's `simulate_chain`: every sensor's noise-free reading, one row per sensor.
/// The setup and the input are checked as a record of `fit_chain` would be (delays
/// shorter than half the record).
#[pyfunction]
pub fn simulate_chain<'py>(
    py: Python<'py>,
    setup_json: &str,
    parameters_json: &str,
    input: PyReadonlyArray1<'py, f64>,
    dt: f64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let setup = chain_setup(setup_json)?;
    let parameters: ChainParameters = options("parameters", parameters_json)?;
    let input = vec_f64(&input);
    let samples = input.len();
    let zeros = vec![vec![0.0; samples]; setup.sensors.len()];
    let record = chain_record(&setup, input, zeros, dt)?;
    let series = py
        .detach(|| msd_ident::simulate_chain(&setup, &parameters, &record.input, dt))
        .map_err(errors::ident)?;
    let mut flat = Vec::with_capacity(setup.sensors.len() * samples);
    for row in &series {
        flat.extend_from_slice(row);
    }
    // No samples: one empty row per sensor.
    flat.resize(setup.sensors.len() * samples, 0.0);
    PyArray1::from_vec(py, flat).reshape([setup.sensors.len(), samples])
}

/// fit_chain(setup_json, input, outputs, dt, guess_json, options_json)
/// --
///
/// msd-ident's `fit_chain` on one record: the result as a dict (serde's fields, with
/// `noise` as an array and `summary`, the Rust display).
#[pyfunction]
pub fn fit_chain<'py>(
    py: Python<'py>,
    setup_json: &str,
    input: PyReadonlyArray1<'py, f64>,
    outputs: Vec<PyReadonlyArray1<'py, f64>>,
    dt: f64,
    guess_json: &str,
    options_json: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let setup = chain_setup(setup_json)?;
    let guess: ChainParameters = options("guess", guess_json)?;
    let opts: ChainOptions = options("fit_chain options", options_json)?;
    let outputs: Vec<Vec<f64>> = outputs.iter().map(vec_f64).collect();
    let record = chain_record(&setup, vec_f64(&input), outputs, dt)?;
    let fit = py
        .detach(|| msd_ident::fit_chain(&setup, &record, &guess, &opts))
        .map_err(errors::ident)?;
    let dict = result_dict(py, &fit, &["noise"])?;
    dict.set_item("summary", fit.to_string())?;
    Ok(dict)
}
