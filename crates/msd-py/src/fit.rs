//! Time-domain fits and simulation: msd-ident's `estimate`, `simulate`, `validate_model`, `fit_records`,
//! `free_decay`, `dynamometer`, and the paper's synthetic data.

use crate::convert::{array, integer, merged, options, result_dict, vec_f64};
use crate::errors;
use msd_ident::dynamometer::{Condition, machine_recording};
use msd_ident::{
    Backend, Channel, DataSet, EstimationOptions, Excitation, InitialState, PaperExperiment,
    Parameters, Record, RecordsOptions, ValidationOptions, dynamometer::DynamometerOptions,
    free_decay::FreeDecayOptions,
};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::Value;

/// The uniform grid of `time` (checked as msd-ident checks a data set's time column:
/// finite, increasing, uniform within 1e-6 relative) with `input` on it.
fn excitation(name: &str, time: &[f64], input: Vec<f64>) -> PyResult<Excitation> {
    let zeros = vec![0.0; time.len()];
    DataSet::from_columns(name, time, input, zeros)
        .map(|d| d.excitation)
        .map_err(errors::ident)
}

/// A backend given by name (`"ode45"`: the paper's tolerances, `"exact"`: the cubic
/// hold) as its serde value; any other value unchanged.
fn backend_value(v: Value) -> PyResult<Value> {
    let named = match v.as_str() {
        Some("ode45") => Backend::PAPER,
        Some("exact") => Backend::EXACT,
        Some(other) => {
            return Err(PyValueError::new_err(format!(
                "backend = {other:?}: expected \"ode45\", \"exact\" or a dict with \"kind\""
            )));
        }
        None => return Ok(v),
    };
    serde_json::to_value(named).map_err(errors::value)
}

/// `EstimationOptions` from a preset (`"default"`, `"fast"`, `"paper"`) and the JSON of
/// the keys that replace its values.
fn estimation_options(preset: &str, json: &str) -> PyResult<EstimationOptions> {
    let base = match preset {
        "default" => EstimationOptions::default(),
        "fast" => EstimationOptions::fast(),
        "paper" => EstimationOptions::paper(),
        other => {
            return Err(PyValueError::new_err(format!(
                "preset = {other:?}: expected \"default\", \"fast\" or \"paper\""
            )));
        }
    };
    let mut value = merged(serde_json::to_value(base).map_err(errors::value)?, json)?;
    if let Some(b) = value.get_mut("backend") {
        *b = backend_value(b.take())?;
    }
    options("estimation options", &value.to_string())
}

/// estimate(t, force, displacement, preset, options_json)
/// --
///
/// msd-ident's `estimate` on one record: the result as a dict (serde's fields, with
/// `model_output` and `residuals` as arrays and `summary`, the Rust display).
#[pyfunction]
pub fn estimate<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'py, f64>,
    force: PyReadonlyArray1<'py, f64>,
    displacement: PyReadonlyArray1<'py, f64>,
    preset: &str,
    options_json: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = estimation_options(preset, options_json)?;
    let (t, force, x) = (vec_f64(&t), vec_f64(&force), vec_f64(&displacement));
    let fit = py.detach(|| {
        let data = DataSet::from_columns("python", &t, force, x)?;
        msd_ident::estimate(&data, &opts)
    });
    let fit = fit.map_err(errors::ident)?;
    let dict = result_dict(py, &fit, &["model_output", "residuals"])?;
    dict.set_item("summary", fit.to_string())?;
    dict.set_item("converged", fit.stop.converged())?;
    Ok(dict)
}

/// simulate(mass, damping, stiffness, t, force, x0, v0, backend_json)
/// --
///
/// msd-ident's `simulate` of the plant on the sampled force: the displacement.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn simulate<'py>(
    py: Python<'py>,
    mass: f64,
    damping: f64,
    stiffness: f64,
    t: PyReadonlyArray1<'py, f64>,
    force: PyReadonlyArray1<'py, f64>,
    x0: f64,
    v0: f64,
    backend_json: &str,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (parameters, initial, input) =
        simulation([mass, damping, stiffness], &t, &force, [x0, v0])?;
    let backend: Value = serde_json::from_str(backend_json).map_err(errors::value)?;
    let backend: Backend = options("backend", &backend_value(backend)?.to_string())?;
    let out = py
        .detach(|| msd_ident::simulate(&parameters, &input, initial, &backend))
        .map_err(errors::ident)?;
    Ok(array(py, out))
}

/// A simulation's plant, initial state and sampled force, each checked.
fn simulation(
    [mass, damping, stiffness]: [f64; 3],
    t: &PyReadonlyArray1<'_, f64>,
    force: &PyReadonlyArray1<'_, f64>,
    [x0, v0]: [f64; 2],
) -> PyResult<(Parameters, InitialState, Excitation)> {
    let parameters = Parameters::new(mass, damping, stiffness).map_err(errors::ident)?;
    if !(x0.is_finite() && v0.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "initial_state = ({x0}, {v0}): expected finite numbers"
        )));
    }
    let initial = InitialState {
        displacement: x0,
        velocity: v0,
    };
    let input = excitation("simulate", &vec_f64(t), vec_f64(force))?;
    Ok((parameters, initial, input))
}

/// simulate_motion(mass, damping, stiffness, t, force, x0, v0)
/// --
///
/// The plant's displacement, velocity and acceleration on the sampled force (msd-ident's
/// exact simulator with a cubic hold: `records::simulate_response`), as a dict.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn simulate_motion<'py>(
    py: Python<'py>,
    mass: f64,
    damping: f64,
    stiffness: f64,
    t: PyReadonlyArray1<'py, f64>,
    force: PyReadonlyArray1<'py, f64>,
    x0: f64,
    v0: f64,
) -> PyResult<Bound<'py, PyDict>> {
    use msd_ident::{Drive, Frame, ResponseQuantity};
    let (parameters, initial, input) =
        simulation([mass, damping, stiffness], &t, &force, [x0, v0])?;
    let out = PyDict::new(py);
    for (name, quantity) in [
        ("displacement", ResponseQuantity::Displacement),
        ("velocity", ResponseQuantity::Velocity),
        ("acceleration", ResponseQuantity::Acceleration),
    ] {
        let series = py
            .detach(|| {
                msd_ident::records::simulate_response(
                    &parameters,
                    Drive::Force,
                    &input,
                    initial,
                    quantity,
                    Frame::Absolute,
                )
            })
            .map_err(errors::ident)?;
        out.set_item(name, array(py, series))?;
    }
    Ok(out)
}

/// validate(mass, damping, stiffness, t, force, displacement, options_json)
/// --
///
/// msd-ident's `validate_model`: the plant's prediction of fresh data, its fit and the
/// residual analysis (`model_output` and `residuals` as arrays, `summary` the display).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn validate<'py>(
    py: Python<'py>,
    mass: f64,
    damping: f64,
    stiffness: f64,
    t: PyReadonlyArray1<'py, f64>,
    force: PyReadonlyArray1<'py, f64>,
    displacement: PyReadonlyArray1<'py, f64>,
    options_json: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let parameters = Parameters::new(mass, damping, stiffness).map_err(errors::ident)?;
    let mut value: Value = serde_json::from_str(options_json).map_err(errors::value)?;
    if let Some(b) = value.get_mut("backend") {
        *b = backend_value(b.take())?;
    }
    let opts: ValidationOptions = options("validation options", &value.to_string())?;
    let (t, force, x) = (vec_f64(&t), vec_f64(&force), vec_f64(&displacement));
    let validation = py
        .detach(|| {
            let data = DataSet::from_columns("validation", &t, force, x)?;
            msd_ident::validate_model(&parameters, &data, &opts)
        })
        .map_err(errors::ident)?;
    let dict = result_dict(py, &validation, &["model_output", "residuals"])?;
    dict.set_item("summary", validation.to_string())?;
    Ok(dict)
}

/// paper_data(seed)
/// --
///
/// msd-ident's `PaperExperiment::generate(seed)`: the paper's identification and
/// validation records (t, force, displacement, true response).
#[pyfunction]
pub fn paper_data<'py>(py: Python<'py>, seed: Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
    let seed: u64 = integer("seed", &seed)?;
    let paper = py
        .detach(|| PaperExperiment::generate(seed))
        .map_err(errors::ident)?;
    let out = PyDict::new(py);
    for (name, data, truth) in [
        (
            "identification",
            &paper.identification,
            &paper.identification_truth,
        ),
        ("validation", &paper.validation, &paper.validation_truth),
    ] {
        let d = PyDict::new(py);
        d.set_item("t", array(py, data.excitation.times().to_vec()))?;
        d.set_item("force", array(py, data.excitation.samples().to_vec()))?;
        d.set_item("displacement", array(py, data.output.clone()))?;
        d.set_item("true_displacement", array(py, truth.clone()))?;
        out.set_item(name, d)?;
    }
    Ok(out)
}

/// What a channel of `fit_records` measures, as Python names it.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Sensor {
    quantity: msd_ident::Quantity,
    frame: msd_ident::Frame,
}

/// One channel as the Python layer passes it: name, quantity, frame, samples.
type PyChannel<'py> = (String, String, String, PyReadonlyArray1<'py, f64>);
/// One record as the Python layer passes it: name, t, drive samples (None: no drive),
/// channels.
type PyRecord<'py> = (
    String,
    PyReadonlyArray1<'py, f64>,
    Option<PyReadonlyArray1<'py, f64>>,
    Vec<PyChannel<'py>>,
);

/// fit_records(records, options_json)
/// --
///
/// msd-ident's `fit_records`: records as (name, t, drive or None, [(name, quantity,
/// frame, samples)]).
#[pyfunction]
pub fn fit_records<'py>(
    py: Python<'py>,
    records: Vec<PyRecord<'py>>,
    options_json: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let opts: RecordsOptions = options("fit_records options", options_json)?;
    let mut built = Vec::with_capacity(records.len());
    for (name, t, drive, channels) in &records {
        let t = vec_f64(t);
        let drive = match drive {
            Some(d) => vec_f64(d),
            None => vec![0.0; t.len()],
        };
        let excitation = excitation(name, &t, drive)?;
        let mut chans = Vec::with_capacity(channels.len());
        for (cname, quantity, frame, samples) in channels {
            let described = serde_json::json!({ "quantity": quantity, "frame": frame });
            let sensor: Sensor = options(&format!("channel `{cname}`"), &described.to_string())?;
            let channel = Channel::new(cname.clone(), sensor.quantity, vec_f64(samples));
            chans.push(channel.in_frame(sensor.frame));
        }
        built.push(Record {
            name: name.clone(),
            excitation,
            channels: chans,
        });
    }
    let fit = py
        .detach(|| msd_ident::fit_records(&built, &opts))
        .map_err(errors::ident)?;
    let dict = result_dict(py, &fit, &[])?;
    dict.set_item("summary", fit.to_string())?;
    add_predictions(py, &dict, &fit, &built)?;
    Ok(dict)
}

/// Puts each channel's model (`model`: the fitted plant's prediction at every sample,
/// offset included) and residual (`residual`: measured − model) as arrays into
/// `dict["records"][i]["channels"][j]`, beside the channel's metrics.
fn add_predictions(
    py: Python<'_>,
    dict: &Bound<'_, PyDict>,
    fit: &msd_ident::records::RecordsFit,
    records: &[Record],
) -> PyResult<()> {
    let Some(listed) = dict.get_item("records")? else {
        return Ok(());
    };
    for ((entry, fitted), measured) in listed.try_iter()?.zip(&fit.records).zip(records) {
        let channels = entry?.get_item("channels")?;
        for ((channel, c), samples) in channels
            .try_iter()?
            .zip(&fitted.channels)
            .zip(&measured.channels)
        {
            let residual: Vec<f64> = samples
                .samples
                .iter()
                .zip(&c.model)
                .map(|(y, m)| y - m)
                .collect();
            let channel = channel?;
            channel.set_item("model", PyArray1::from_slice(py, &c.model))?;
            channel.set_item("residual", PyArray1::from_vec(py, residual))?;
        }
    }
    Ok(())
}

/// free_decay(t, response, options_json)
/// --
///
/// msd-ident's `free_decay` on a ring-down sampled on `t`.
#[pyfunction]
pub fn free_decay<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'py, f64>,
    response: PyReadonlyArray1<'py, f64>,
    options_json: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let opts: FreeDecayOptions = options("free_decay options", options_json)?;
    let t = vec_f64(&t);
    let grid = excitation("free decay", &t, vec![0.0; t.len()])?;
    let response = vec_f64(&response);
    if response.len() != t.len() {
        return Err(PyValueError::new_err(format!(
            "length mismatch: response has {} samples, expected {}",
            response.len(),
            t.len()
        )));
    }
    let fit = py
        .detach(|| msd_ident::free_decay::free_decay(grid.dt(), &response, &opts))
        .map_err(errors::ident)?;
    let dict = result_dict(py, &fit, &[])?;
    dict.set_item("summary", fit.to_string())?;
    Ok(dict)
}

/// One test-machine condition as the Python layer passes it: name, dt or time stamps
/// (checked uniform), displacement, force, frequency in Hz or None.
type PyCondition<'py> = (
    String,
    Option<f64>,
    Option<PyReadonlyArray1<'py, f64>>,
    PyReadonlyArray1<'py, f64>,
    PyReadonlyArray1<'py, f64>,
    Option<f64>,
);

/// dynamometer(conditions, options_json)
/// --
///
/// msd-ident's `dynamometer`: conditions as (name, dt or None, t or None, displacement,
/// force, frequency_hz or None).
#[pyfunction]
pub fn dynamometer<'py>(
    py: Python<'py>,
    conditions: Vec<PyCondition<'py>>,
    options_json: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let opts: DynamometerOptions = options("dynamometer options", options_json)?;
    let mut built = Vec::with_capacity(conditions.len());
    for (name, dt, t, x, f, hz) in &conditions {
        let dt = match (dt, t) {
            (Some(dt), None) => *dt,
            (None, Some(t)) => {
                let t = vec_f64(t);
                excitation(name, &t, vec![0.0; t.len()])?.dt()
            }
            _ => {
                return Err(PyValueError::new_err(format!(
                    "condition `{name}`: give the sampling interval dt or the time stamps t, one of them"
                )));
            }
        };
        built.push(Condition {
            recording: machine_recording(name, dt, vec_f64(x), vec_f64(f)),
            frequency_hz: *hz,
        });
    }
    let fit = py
        .detach(|| msd_ident::dynamometer::dynamometer(&built, &opts))
        .map_err(errors::ident)?;
    let dict = result_dict(py, &fit, &[])?;
    dict.set_item("summary", fit.to_string())?;
    Ok(dict)
}

/// A stroke record from Python: (name, dt, stroke, force).
type PyStroke<'py> = (
    String,
    f64,
    PyReadonlyArray1<'py, f64>,
    PyReadonlyArray1<'py, f64>,
);

fn stroke_records(records: &[PyStroke<'_>]) -> Vec<msd_signal::Recording> {
    records
        .iter()
        .map(|(name, dt, x, f)| machine_recording(name, *dt, vec_f64(x), vec_f64(f)))
        .collect()
}

/// inverse_dynamics(records, validation, options_json)
/// --
///
/// msd-ident's `inverse_dynamics` on `records` (name, dt, stroke, force), each of
/// `validation` predicted by the best law.
#[pyfunction]
pub fn inverse_dynamics<'py>(
    py: Python<'py>,
    records: Vec<PyStroke<'py>>,
    validation: Vec<PyStroke<'py>>,
    options_json: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let opts: msd_ident::dynamometer::InverseOptions =
        options("inverse_dynamics options", options_json)?;
    let (fitted, fresh) = (stroke_records(&records), stroke_records(&validation));
    let (fit, predictions) = py
        .detach(|| {
            let fit = msd_ident::dynamometer::inverse_dynamics(&fitted, &opts)?;
            let predictions = fresh
                .iter()
                .map(|r| fit.predict(fit.best, r))
                .collect::<msd_ident::Result<Vec<_>>>()?;
            Ok::<_, msd_ident::IdentError>((fit, predictions))
        })
        .map_err(errors::ident)?;
    let dict = result_dict(py, &fit, &[])?;
    let list = pyo3::types::PyList::empty(py);
    for (r, p) in fresh.iter().zip(predictions) {
        let d = PyDict::new(py);
        d.set_item("name", &r.name)?;
        d.set_item("first", p.first)?;
        d.set_item("rms_error", p.rms_error)?;
        d.set_item("rms_force", p.rms_force)?;
        d.set_item("measured", PyArray1::from_vec(py, p.measured))?;
        d.set_item("predicted", PyArray1::from_vec(py, p.predicted))?;
        list.append(d)?;
    }
    dict.set_item("validation", list)?;
    dict.set_item("summary", fit.to_string())?;
    Ok(dict)
}
