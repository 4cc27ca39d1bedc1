//! The toolkit's errors as Python exceptions, with the toolkit's message text.

use msd_experiment::ExperimentError;
use msd_ident::IdentError;
use msd_modal::ModalError;
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::{PyErr, Python, create_exception};

create_exception!(
    msd,
    IdentificationError,
    PyValueError,
    "The data cannot identify what was asked (parameters not identifiable, too few \
     modes, an estimation that failed). A subclass of ValueError: the remedy is other \
     data or other options."
);

/// Whether `e` says the data cannot identify the model (as opposed to bad input).
fn cannot_identify(e: &IdentError) -> bool {
    matches!(
        e,
        IdentError::NotIdentifiable { .. }
            | IdentError::EstimationFailed { .. }
            | IdentError::Modal(
                ModalError::NotIdentifiable { .. }
                    | ModalError::TooFewModes { .. }
                    | ModalError::EstimationFailed { .. }
            )
    )
}

/// msd-ident's (or msd-modal's) error: `IdentificationError` for a fit that cannot
/// identify, else `ValueError`.
pub fn ident(e: impl Into<IdentError>) -> PyErr {
    let e = e.into();
    if cannot_identify(&e) {
        IdentificationError::new_err(e.to_string())
    } else {
        PyValueError::new_err(e.to_string())
    }
}

/// Any other crate's error on bad input: `ValueError`.
pub fn value(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// `e` with the argument it concerns named first (`datasets[2]: …`), of the same type.
pub fn within(py: Python<'_>, argument: &str, e: PyErr) -> PyErr {
    let message = format!("{argument}: {}", e.value(py));
    let renamed = PyErr::from_type(e.get_type(py), message);
    renamed.set_cause(py, e.cause(py));
    renamed
}

/// msd-experiment's error: a bad config or bad data `ValueError`, a failed download
/// `OSError`, a failure during the run `IdentificationError` when msd-ident says the
/// data cannot identify, `ValueError` for msd-ident's other errors, `OSError` for a file
/// system error, else `RuntimeError`.
pub fn experiment(e: ExperimentError) -> PyErr {
    experiment_kind(&e)(e.to_string())
}

fn experiment_kind(e: &ExperimentError) -> fn(String) -> PyErr {
    match e {
        ExperimentError::Config { .. } | ExperimentError::Data { .. } => PyValueError::new_err,
        ExperimentError::Download { .. } => PyOSError::new_err,
        ExperimentError::Run { source, .. } => match source.downcast_ref::<IdentError>() {
            Some(inner) if cannot_identify(inner) => IdentificationError::new_err,
            Some(_) => PyValueError::new_err,
            None if source.downcast_ref::<std::io::Error>().is_some() => PyOSError::new_err,
            None => PyRuntimeError::new_err,
        },
        ExperimentError::Kept { error, .. } => experiment_kind(error),
    }
}
