//! Frequency responses: msd-signal's `frf_estimate` from time records, msd-ident's
//! `fit_modes` (one FRF) and `fit_mode_set` (a set, with shapes).

use crate::convert::{PyDof, array, dof, options, result_dict, vec_f64};
use crate::errors;
use msd_ident::OneModeOptions;
use msd_modal::ModalOptions;
use msd_modal::SetMember;
use msd_signal::{
    Complex64, Estimator, FrequencyResponseEstimate, FrfKind, FrfOptions, LineCorrelation,
};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// frf(t, forces, responses, options_json)
/// --
///
/// msd-signal's `frf_estimate` over the records (forces[i], responses[i]) sampled on `t`.
#[pyfunction]
pub fn frf<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'py, f64>,
    forces: Vec<PyReadonlyArray1<'py, f64>>,
    responses: Vec<PyReadonlyArray1<'py, f64>>,
    options_json: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let opts: FrfOptions = options("frf options", options_json)?;
    let t = vec_f64(&t);
    if forces.len() != responses.len() {
        return Err(PyValueError::new_err(format!(
            "{} force records but {} response records",
            forces.len(),
            responses.len()
        )));
    }
    let forces: Vec<Vec<f64>> = forces.iter().map(vec_f64).collect();
    let responses: Vec<Vec<f64>> = responses.iter().map(vec_f64).collect();
    let first = forces.first().cloned().unwrap_or_default();
    let zeros = vec![0.0; t.len()];
    let grid = msd_ident::DataSet::from_columns("frf", &t, first, zeros).map_err(errors::ident)?;
    let fs = 1.0 / grid.excitation.dt();
    let estimate = py.detach(|| {
        let records: Vec<msd_signal::Record<'_>> = forces
            .iter()
            .zip(&responses)
            .map(|(f, r)| msd_signal::Record {
                input: f,
                output: r,
            })
            .collect();
        msd_signal::frf_estimate(&records, fs, &opts)
    });
    let estimate = estimate.map_err(errors::value)?;
    estimate_dict(py, estimate)
}

fn estimate_dict(py: Python<'_>, e: FrequencyResponseEstimate) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("frequency", array(py, e.frequency))?;
    d.set_item("h", PyArray1::from_vec(py, e.h))?;
    d.set_item("coherence", array(py, e.coherence))?;
    d.set_item("averages", e.averages)?;
    d.set_item(
        "kind",
        serde_json::to_value(e.kind)
            .map_err(errors::value)?
            .as_str()
            .unwrap_or(""),
    )?;
    d.set_item("variance", e.variance.map(|v| array(py, v)))?;
    d.set_item("exponential_decay", e.exponential_decay)?;
    d.set_item("noise_bandwidth", e.noise_bandwidth)?;
    let c = e.line_correlation;
    d.set_item(
        "line_correlation",
        (
            PyArray1::from_vec(py, c.response),
            PyArray1::from_vec(py, c.force),
        ),
    )?;
    d.set_item("estimator", e.estimator.map(estimator_name))?;
    d.set_item(
        "input_noise_variance",
        e.input_noise_variance.map(|v| array(py, v)),
    )?;
    Ok(d)
}

/// "H1", "H2" or "Hv", as the options write it.
fn estimator_name(e: Estimator) -> &'static str {
    match e {
        Estimator::H1 => "H1",
        Estimator::H2 => "H2",
        Estimator::Hv => "Hv",
    }
}

/// How an FRF was made, where known: K segments averaged and the estimator, which a
/// fit needs to take the coherence's noise apart (and H1's bias off), how the windows
/// correlate the lines' errors, and each line's variance from the force's noise where
/// it was measured (an impact test's force channel after the force window).
struct Made {
    averages: usize,
    estimator: Option<Estimator>,
    noise_bandwidth: f64,
    line_correlation: LineCorrelation,
    input_noise_variance: Option<Vec<f64>>,
}

/// The lines' correlation as Python gives it: (response, force) kernels, or None.
type PyCorrelation<'py> = Option<(
    PyReadonlyArray1<'py, Complex64>,
    PyReadonlyArray1<'py, Complex64>,
)>;

/// A kernel ρ(0), ρ(1), … checked: empty, or ρ(0) = 1 and every |ρ(d)| ≤ 1.
fn kernel(name: &str, values: &PyReadonlyArray1<'_, Complex64>) -> PyResult<Vec<Complex64>> {
    let values: Vec<Complex64> = values.as_array().iter().copied().collect();
    if let Some(first) = values.first()
        && (first - 1.0).norm() > 1e-9
    {
        return Err(PyValueError::new_err(format!(
            "line_correlation {name}[0] = {first}: expected 1 (a line's error is its own)"
        )));
    }
    if let Some((d, v)) =
        (values.iter().enumerate()).find(|(_, v)| v.norm().is_nan() || v.norm() > 1.0 + 1e-9)
    {
        return Err(PyValueError::new_err(format!(
            "line_correlation {name}[{d}] = {v}: expected a correlation, |ρ| ≤ 1"
        )));
    }
    Ok(values)
}

impl Made {
    /// From the Python arguments: `averages` ≥ 1 (1: one segment, or not known), an
    /// estimator name or None (a measured table), and the window's noise bandwidth in
    /// lines (≥ 1: 1 rectangular, 1.5 Hann).
    fn new(
        averages: usize,
        estimator: Option<&str>,
        noise_bandwidth: f64,
        line_correlation: PyCorrelation<'_>,
        input_noise_variance: Option<PyReadonlyArray1<'_, f64>>,
    ) -> PyResult<Self> {
        if !(noise_bandwidth.is_finite() && noise_bandwidth >= 1.0) {
            return Err(PyValueError::new_err(format!(
                "noise_bandwidth = {noise_bandwidth}: expected the window's noise bandwidth in lines, ≥ 1"
            )));
        }
        if averages == 0 {
            return Err(PyValueError::new_err(
                "averages = 0: expected the number of segments averaged, ≥ 1",
            ));
        }
        let estimator = match estimator {
            None => None,
            Some(name) => Some(options::<Estimator>(
                "estimator",
                &serde_json::Value::from(name).to_string(),
            )?),
        };
        let line_correlation = match line_correlation {
            None => LineCorrelation::default(),
            Some((response, force)) => LineCorrelation {
                response: kernel("response", &response)?,
                force: kernel("force", &force)?,
            },
        };
        let input_noise_variance = input_noise_variance.map(|v| vec_f64(&v));
        if let Some((i, v)) = (input_noise_variance.iter().flatten().enumerate())
            .find(|(_, v)| !(v.is_finite() && **v >= 0.0))
        {
            return Err(PyValueError::new_err(format!(
                "input_noise_variance line {i} is {v}: expected a variance ≥ 0"
            )));
        }
        Ok(Self {
            averages,
            estimator,
            noise_bandwidth,
            line_correlation,
            input_noise_variance,
        })
    }
}

/// A measured FRF on `frequency` with its coherence, kind and window.
fn measured(
    frequency: &[f64],
    h: Vec<Complex64>,
    coherence: Option<Vec<f64>>,
    kind: FrfKind,
    exponential_decay: Option<f64>,
    made: &Made,
) -> PyResult<FrequencyResponseEstimate> {
    let mut e = FrequencyResponseEstimate::new(frequency.to_vec(), h).map_err(errors::value)?;
    e.averages = made.averages;
    e.estimator = made.estimator;
    e.noise_bandwidth = made.noise_bandwidth;
    e.line_correlation = made.line_correlation.clone();
    if let Some(v) = &made.input_noise_variance {
        if v.len() != frequency.len() {
            return Err(PyValueError::new_err(format!(
                "length mismatch: input_noise_variance has {} lines, expected {}",
                v.len(),
                frequency.len()
            )));
        }
        e.input_noise_variance = Some(v.clone());
    }
    if let Some(c) = coherence {
        if c.len() != frequency.len() {
            return Err(PyValueError::new_err(format!(
                "length mismatch: coherence has {} lines, expected {}",
                c.len(),
                frequency.len()
            )));
        }
        if let Some((i, v)) = c
            .iter()
            .enumerate()
            .find(|(_, v)| !(**v >= 0.0 && **v <= 1.0))
        {
            return Err(PyValueError::new_err(format!(
                "coherence line {i} is {v}: expected a number in [0, 1]"
            )));
        }
        e.coherence = c;
    }
    if let Some(tau) = exponential_decay
        && !(tau.is_finite() && tau > 0.0)
    {
        return Err(PyValueError::new_err(format!(
            "exponential_decay = {tau}: expected a decay time > 0 in seconds"
        )));
    }
    e.kind = kind;
    e.exponential_decay = exponential_decay;
    Ok(e)
}

/// modal_fit(frequency, frfs, coherences, kind, exponential_decay, averages, estimator, noise_bandwidth, line_correlation, input_noise_variance, dofs, options_json)
/// --
///
/// msd-ident's `fit_modes` on one FRF (dofs None) or `fit_mode_set` on a set, each
/// member with (response DOF, reference DOF).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn modal_fit<'py>(
    py: Python<'py>,
    frequency: PyReadonlyArray1<'py, f64>,
    frfs: Vec<PyReadonlyArray1<'py, Complex64>>,
    coherences: Option<Vec<PyReadonlyArray1<'py, f64>>>,
    kind: &str,
    exponential_decay: Option<f64>,
    averages: usize,
    estimator: Option<&str>,
    noise_bandwidth: f64,
    line_correlation: PyCorrelation<'py>,
    input_noise_variance: Option<PyReadonlyArray1<'py, f64>>,
    dofs: Option<Vec<(PyDof<'py>, PyDof<'py>)>>,
    options_json: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let opts: ModalOptions = options("modal_fit options", options_json)?;
    let made = Made::new(
        averages,
        estimator,
        noise_bandwidth,
        line_correlation,
        input_noise_variance,
    )?;
    let kind: FrfKind = options("kind", &serde_json::Value::from(kind).to_string())?;
    let frequency = vec_f64(&frequency);
    if frfs.is_empty() {
        return Err(PyValueError::new_err("no frequency responses given"));
    }
    if let Some(c) = &coherences
        && c.len() != frfs.len()
    {
        return Err(PyValueError::new_err(format!(
            "{} coherences for {} frequency responses",
            c.len(),
            frfs.len()
        )));
    }
    let mut estimates = Vec::with_capacity(frfs.len());
    for (i, h) in frfs.iter().enumerate() {
        let h: Vec<Complex64> = match h.as_slice() {
            Ok(s) => s.to_vec(),
            Err(_) => h.as_array().iter().copied().collect(),
        };
        let c = coherences.as_ref().map(|c| vec_f64(&c[i]));
        estimates.push(measured(&frequency, h, c, kind, exponential_decay, &made)?);
    }
    match dofs {
        None => {
            if estimates.len() != 1 {
                return Err(PyValueError::new_err(
                    "a set of frequency responses needs their DOFs (dofs=[((response node, direction), (reference node, direction)), ...])",
                ));
            }
            let e = estimates.pop().expect("one estimate");
            let fit = py
                .detach(|| msd_modal::fit_modes(&e, &opts))
                .map_err(errors::ident)?;
            let dict = result_dict(py, &fit, &[])?;
            dict.set_item("summary", fit.to_string())?;
            dict.set_item("set", false)?;
            Ok(dict)
        }
        Some(dofs) => {
            if dofs.len() != estimates.len() {
                return Err(PyValueError::new_err(format!(
                    "{} DOF pairs for {} frequency responses",
                    dofs.len(),
                    estimates.len()
                )));
            }
            let members: Vec<SetMember> = estimates
                .into_iter()
                .zip(&dofs)
                .enumerate()
                .map(|(i, (frf, (response, reference)))| {
                    Ok(SetMember {
                        frf,
                        response: dof(&format!("dofs[{i}] response"), response)?,
                        reference: dof(&format!("dofs[{i}] reference"), reference)?,
                    })
                })
                .collect::<PyResult<_>>()?;
            let fit = py
                .detach(|| msd_modal::fit_mode_set(&members, &opts))
                .map_err(errors::ident)?;
            let dict = result_dict(py, &fit, &[])?;
            dict.set_item("summary", fit.to_string())?;
            dict.set_item("set", true)?;
            Ok(dict)
        }
    }
}

/// one_mode_fit(frequency, h, coherence, kind, exponential_decay, averages, estimator, noise_bandwidth, line_correlation, input_noise_variance, options_json)
/// --
///
/// msd-ident's `fit_one_mode`: m, c, k (with fn and ζ) of one FRF with 95 % intervals.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn one_mode_fit<'py>(
    py: Python<'py>,
    frequency: PyReadonlyArray1<'py, f64>,
    h: PyReadonlyArray1<'py, Complex64>,
    coherence: Option<PyReadonlyArray1<'py, f64>>,
    kind: &str,
    exponential_decay: Option<f64>,
    averages: usize,
    estimator: Option<&str>,
    noise_bandwidth: f64,
    line_correlation: PyCorrelation<'py>,
    input_noise_variance: Option<PyReadonlyArray1<'py, f64>>,
    options_json: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let opts: OneModeOptions = options("one_mode_fit options", options_json)?;
    let made = Made::new(
        averages,
        estimator,
        noise_bandwidth,
        line_correlation,
        input_noise_variance,
    )?;
    let kind: FrfKind = options("kind", &serde_json::Value::from(kind).to_string())?;
    let h: Vec<Complex64> = h.as_array().iter().copied().collect();
    let e = measured(
        &vec_f64(&frequency),
        h,
        coherence.as_ref().map(vec_f64),
        kind,
        exponential_decay,
        &made,
    )?;
    let fit = py
        .detach(|| msd_ident::fit_one_mode(&e, &opts))
        .map_err(errors::ident)?;
    let dict = result_dict(py, &fit, &[])?;
    dict.set_item("summary", fit.to_string())?;
    Ok(dict)
}
