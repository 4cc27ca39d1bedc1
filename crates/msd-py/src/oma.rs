//! Output-only modal analysis: msd-modal's `ssi_cov` on a NumPy array of channels.

use crate::convert::{options, result_dict};
use crate::errors;
use msd_modal::{Dof, OmaOptions, OutputChannel, OutputRecord, Quantity, ssi_cov};
use numpy::PyReadonlyArray2;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// oma(data, sample_rate_hz, references, dofs, quantities, names, options_json)
/// --
///
/// msd-modal's `ssi_cov` on `data` (samples × channels): every channel's DOF
/// (node, direction), quantity and name; the reference channels' indices (None: all).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn oma<'py>(
    py: Python<'py>,
    data: PyReadonlyArray2<'py, f64>,
    sample_rate_hz: f64,
    references: Option<Vec<usize>>,
    dofs: Vec<(u32, i32)>,
    quantities: Vec<String>,
    names: Vec<String>,
    options_json: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let opts: OmaOptions = options("oma options", options_json)?;
    let array = data.as_array();
    let channels = array.ncols();
    if [dofs.len(), quantities.len(), names.len()] != [channels; 3] {
        return Err(PyValueError::new_err(format!(
            "{} DOFs, {} quantities and {} names for {channels} channels",
            dofs.len(),
            quantities.len(),
            names.len()
        )));
    }
    let mut record = OutputRecord {
        sample_rate_hz,
        channels: Vec::with_capacity(channels),
        references: references.unwrap_or_default(),
    };
    for (c, ((&(node, direction), quantity), name)) in dofs.iter().zip(&quantities).zip(&names).enumerate() {
        let quantity: Quantity = options(
            &format!("quantities[{c}]"),
            &serde_json::Value::from(quantity.as_str()).to_string(),
        )?;
        let samples = array.column(c).iter().copied().collect();
        record.channels.push(OutputChannel::new(name.clone(), Dof { node, direction }, quantity, samples));
    }
    let fit = py.detach(|| ssi_cov(&record, &opts)).map_err(errors::ident)?;
    let dict = result_dict(py, &fit, &["singular_values"])?;
    dict.set_item("summary", fit.to_string())?;
    Ok(dict)
}
