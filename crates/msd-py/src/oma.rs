//! Output-only modal analysis: msd-modal's `ssi_cov` or `efdd` on a NumPy array of
//! channels.

use crate::convert::{PyDof, channel_dof, integer, options, result_dict};
use crate::errors;
use msd_signal::Channel;
use msd_modal::{
    FddOptions, OmaFit, OmaMethod, OmaOptions, OutputRecord, Quantity, Setup, efdd,
    merge_setups, ssi_cov, ssi_dat,
};
use numpy::PyReadonlyArray2;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// One setup as Python gives it: the array (samples × channels), the rate, the
/// references, and per channel its DOF, oblique direction, quantity and name.
type PySetup<'py> = (
    PyReadonlyArray2<'py, f64>,
    f64,
    Option<Vec<Bound<'py, PyAny>>>,
    Vec<PyDof<'py>>,
    Vec<Option<[f64; 3]>>,
    Vec<String>,
    Vec<String>,
);

/// The method named (`"ssi-cov"`, `"ssi-dat"` or `"efdd"`) with its options parsed: a closure
/// analysing one record.
fn analysis(
    method: &str,
    options_json: &str,
) -> PyResult<impl Fn(&OutputRecord) -> Result<OmaFit, msd_modal::ModalError> + Send + Sync> {
    let method: OmaMethod = options("method", &serde_json::to_string(method).unwrap_or_default())?;
    let (ssi, fdd): (Option<OmaOptions>, Option<FddOptions>) = match method {
        OmaMethod::SsiCov | OmaMethod::SsiDat => {
            (Some(options("oma options", options_json)?), None)
        }
        OmaMethod::Efdd => (None, Some(options("efdd options", options_json)?)),
    };
    Ok(move |record: &OutputRecord| match (&ssi, &fdd) {
        (Some(o), _) if method == OmaMethod::SsiDat => ssi_dat(record, o),
        (Some(o), _) => ssi_cov(record, o),
        (_, Some(o)) => efdd(record, o),
        (None, None) => unreachable!("one method's options are parsed"),
    })
}

/// oma(data, sample_rate_hz, references, dofs, directions, quantities, names, method, options_json)
/// --
///
/// msd-modal's `ssi_cov` (method "ssi-cov"), `ssi_dat` ("ssi-dat") or `efdd` ("efdd") on `data` (samples ×
/// channels): every channel's DOF (node, direction), oblique direction (a unit vector or
/// None), quantity and name; the reference channels' indices (None: all).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn oma<'py>(
    py: Python<'py>,
    data: PyReadonlyArray2<'py, f64>,
    sample_rate_hz: f64,
    references: Option<Vec<Bound<'py, PyAny>>>,
    dofs: Vec<PyDof<'py>>,
    directions: Vec<Option<[f64; 3]>>,
    quantities: Vec<String>,
    names: Vec<String>,
    method: &str,
    options_json: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let analyse = analysis(method, options_json)?;
    let record = record_of(
        "",
        (
            data,
            sample_rate_hz,
            references,
            dofs,
            directions,
            quantities,
            names,
        ),
    )?;
    let fit = py.detach(|| analyse(&record)).map_err(errors::ident)?;
    let dict = result_dict(py, &fit, &["singular_values"])?;
    dict.set_item("summary", fit.to_string())?;
    Ok(dict)
}

/// oma_setups(setups, tolerance, method, options_json)
/// --
///
/// `ssi_cov` or `efdd` on each setup, then msd-modal's `merge_setups` (PoSER): a dict with `setups`
/// (each setup's fit) and `merged`.
#[pyfunction]
pub fn oma_setups<'py>(
    py: Python<'py>,
    setups: Vec<PySetup<'py>>,
    tolerance: f64,
    method: &str,
    options_json: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let analyse = analysis(method, options_json)?;
    let records: Vec<OutputRecord> = setups
        .into_iter()
        .enumerate()
        .map(|(i, setup)| record_of(&format!("setups[{i}]."), setup))
        .collect::<PyResult<_>>()?;
    let (fits, merged) = py
        .detach(|| -> Result<_, msd_modal::ModalError> {
            let fits: Vec<OmaFit> = records.iter().map(&analyse).collect::<Result<_, _>>()?;
            let views: Vec<Setup<'_>> = records
                .iter()
                .zip(&fits)
                .map(|(record, fit)| Setup { record, fit })
                .collect();
            let merged = merge_setups(&views, tolerance)?;
            Ok((fits, merged))
        })
        .map_err(errors::ident)?;
    let dict = PyDict::new(py);
    let list = pyo3::types::PyList::empty(py);
    for fit in &fits {
        list.append(result_dict(py, fit, &["singular_values"])?)?;
    }
    dict.set_item("setups", list)?;
    dict.set_item("merged", result_dict(py, &merged, &[])?)?;
    Ok(dict)
}

/// A setup's record, its lengths, references and DOFs checked (each named after
/// `prefix`: "" for `oma`'s arguments, `setups[i].` for a setup's).
fn record_of(prefix: &str, setup: PySetup<'_>) -> PyResult<OutputRecord> {
    let (data, sample_rate_hz, references, dofs, directions, quantities, names) = setup;
    let array = data.as_array();
    let channels = array.ncols();
    if [dofs.len(), directions.len(), quantities.len(), names.len()] != [channels; 4] {
        return Err(PyValueError::new_err(format!(
            "{} DOFs, {} directions, {} quantities and {} names for {channels} channels",
            dofs.len(),
            directions.len(),
            quantities.len(),
            names.len()
        )));
    }
    let references = references
        .unwrap_or_default()
        .iter()
        .enumerate()
        .map(|(i, r)| integer(&format!("{prefix}references[{i}]"), r))
        .collect::<PyResult<_>>()?;
    let mut record =
        OutputRecord::new(sample_rate_hz, Vec::with_capacity(channels)).with_references(references);
    for (c, (((pair, oblique), quantity), name)) in dofs
        .iter()
        .zip(&directions)
        .zip(&quantities)
        .zip(&names)
        .enumerate()
    {
        let dof = channel_dof(&format!("{prefix}dofs[{c}]"), pair)?;
        let quantity: Quantity = options(
            &format!("{prefix}quantities[{c}]"),
            &serde_json::Value::from(quantity.as_str()).to_string(),
        )?;
        let samples = array.column(c).iter().copied().collect();
        record.recording.channels.push(Channel {
            direction: *oblique,
            ..Channel::new(name.clone(), quantity, samples).at(dof)
        });
    }
    Ok(record)
}
