//! Chains of masses in the time domain: msd-ident's `simulate_chain`, `fit_chain` and
//! `predict_chain`.

use crate::convert::{options, result_dict, vec_f64};
use crate::errors;
use msd_ident::{
    IdentError,
    chain::{ChainOptions, ChainParameters, ChainSensor, ChainSetup},
};
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
                "sensors = {other}: expected a list of sensors (dicts with at, quantity, delay, estimate_delay, low_pass, estimate_cutoff)"
            )));
        }
    }
    Ok(setup)
}

/// simulate_chain(setup_json, parameters_json, input, dt)
/// --
///
/// msd-ident's `simulate_chain`: every sensor's noise-free reading, one row per sensor
/// (each empty for an empty input). It checks the setup, the parameters, dt, the
/// input (finite) and the delays (shorter than the record).
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
    let series = py
        .detach(|| msd_ident::chain::simulate_chain(&setup, &parameters, &input, dt))
        .map_err(errors::ident)?;
    let mut flat = Vec::with_capacity(series.len() * samples);
    for row in &series {
        flat.extend_from_slice(row);
    }
    PyArray1::from_vec(py, flat).reshape([series.len(), samples])
}

/// fit_chain(setup_json, input, outputs, dt, guess_json, options_json)
/// --
///
/// msd-ident's `fit_chain` on one record: the result as a dict (serde's fields, the
/// uncertainty's flattened among them, with `noise` as an array and `summary`, the Rust
/// display).
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
    if opts.passes == 0 {
        return Err(PyValueError::new_err(
            "passes = 0: expected at least 1 (each pass fits the record once)",
        ));
    }
    let record = setup.recording(
        "record",
        dt,
        vec_f64(&input),
        outputs.iter().map(vec_f64).collect(),
    );
    // fit_chain checks the setup, the guess, the options and the record itself.
    let fit = py
        .detach(|| msd_ident::chain::fit_chain(&setup, &record, &guess, &opts))
        .map_err(errors::ident)?;
    let dict = result_dict(py, &fit, &["noise"])?;
    dict.set_item("summary", fit.to_string())?;
    Ok(dict)
}

/// predict_chain(setup_json, truth_json, input, dt, noise, options_json)
/// --
///
/// msd-ident's `predict_chain`: the uncertainty a fit of one record will have (the
/// Cramér–Rao bound at the truth with each sensor's noise σ), as a dict (serde's fields
/// and `summary`, the Rust display).
#[pyfunction]
pub fn predict_chain<'py>(
    py: Python<'py>,
    setup_json: &str,
    truth_json: &str,
    input: PyReadonlyArray1<'py, f64>,
    dt: f64,
    noise: PyReadonlyArray1<'py, f64>,
    options_json: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let setup = chain_setup(setup_json)?;
    let truth: ChainParameters = options("truth", truth_json)?;
    let opts: ChainOptions = options("predict_chain options", options_json)?;
    let (input, noise) = (vec_f64(&input), vec_f64(&noise));
    let predicted = py
        .detach(|| {
            check_planned(&setup, &truth, &input, dt, &noise, &opts.known_masses)?;
            msd_ident::chain::predict_chain(&setup, &truth, &input, dt, &noise, &opts)
        })
        .map_err(errors::ident)?;
    let dict = result_dict(py, &predicted, &[])?;
    dict.set_item("summary", predicted.to_string())?;
    Ok(dict)
}

/// The largest RMS reading, the largest signal-to-noise ratio and the smallest σ (whose
/// reciprocal weights the channel) of a planned test.
const MAX_READING: f64 = 1e150;
const MAX_SIGNAL_TO_NOISE: f64 = 1e100;
const MIN_NOISE: f64 = 1e-300;

/// What msd-ident's `predict_chain` does not refuse itself but its `fit_chain` would, or
/// cannot compute: a known mass the chain does not have (predict_chain ignores it), a
/// drive that is zero throughout, a sensor that reads nothing, or readings so large, or
/// σ so small beside them, that the weighted sensitivities overflow (predict_chain then
/// decomposes a non-finite matrix, which does not end). Everything else, and the noise
/// levels' count and sign, predict_chain checks with its own messages.
///
/// Not caught here: sensitivities that overflow while the readings do not (parameters
/// tens of orders of magnitude apart, e.g. m = 1e128, c = 1e111, k = 1e-125), where
/// predict_chain still does not return (a test marks it as msd-ident's to fix).
fn check_planned(
    setup: &ChainSetup,
    truth: &ChainParameters,
    input: &[f64],
    dt: f64,
    noise: &[f64],
    known_masses: &[usize],
) -> msd_ident::Result<()> {
    let refuse = |reason: String| {
        Err(IdentError::Setup {
            setup: "chain of masses",
            reason,
        })
    };
    // predict_chain's first step: the setup, the truth, dt, the input and the delays.
    let readings = msd_ident::chain::simulate_chain(setup, truth, input, dt)?;
    if let Some(&m) = known_masses
        .iter()
        .find(|&&m| !(1..=setup.masses).contains(&m))
    {
        return refuse(format!(
            "known_masses contains {m}: expected masses from 1 to {}",
            setup.masses
        ));
    }
    if noise.len() != readings.len() || noise.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return Ok(());
    }
    if !input.is_empty() && input.iter().all(|&u| u == 0.0) {
        return refuse("the drive is zero throughout: nothing excites the chain".into());
    }
    for (i, (y, &sigma)) in readings.iter().zip(noise).enumerate() {
        if sigma < MIN_NOISE {
            return refuse(format!(
                "sensors[{i}] noise σ = {sigma:e}: expected at least {MIN_NOISE:e} (its reciprocal weights the channel)"
            ));
        }
        if y.is_empty() {
            continue;
        }
        if let Some(k) = y.iter().position(|v| !v.is_finite()) {
            return refuse(format!(
                "sensors[{i}]: its noise-free reading overflows (sample {k} is {}): expected a test whose readings are neither zero throughout nor beyond {MAX_READING:e}",
                y[k]
            ));
        }
        let top = y.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        // The RMS scaled by the largest value: no overflow on the way.
        let level = if top > 0.0 {
            top * (y.iter().map(|v| (v / top).powi(2)).sum::<f64>() / y.len() as f64).sqrt()
        } else {
            0.0
        };
        if !(level > 0.0 && level <= MAX_READING) {
            return refuse(format!(
                "sensors[{i}]: its noise-free reading has RMS {level:e}: expected a test whose readings are neither zero throughout nor beyond {MAX_READING:e}"
            ));
        }
        if level / sigma > MAX_SIGNAL_TO_NOISE {
            return refuse(format!(
                "sensors[{i}] noise σ = {sigma:e} beside an RMS reading of {level:e}: expected a signal-to-noise ratio below {MAX_SIGNAL_TO_NOISE:e}"
            ));
        }
    }
    Ok(())
}
