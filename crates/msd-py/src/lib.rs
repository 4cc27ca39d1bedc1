//! `msd._msd`: the Python bindings of msd-toolkit.
//!
//! Conversion only: NumPy arrays and Python dicts in, the Rust crates' own types built
//! through their public constructors and serde, their results out as Python dicts (via
//! serde) with the long numeric series as NumPy arrays. Every computation runs with the
//! GIL released (`Python::detach`). The pure-Python package `msd` (python/msd) wraps
//! these functions in typed result objects.

mod chain;
mod convert;
mod errors;
mod experiment;
mod files;
mod fit;
mod frf;
mod oma;
mod uff;

use pyo3::prelude::*;

/// The compiled core of the `msd` package; use `msd` itself.
#[pymodule]
fn _msd(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add(
        "IdentificationError",
        py.get_type::<errors::IdentificationError>(),
    )?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(fit::estimate, m)?)?;
    m.add_function(wrap_pyfunction!(fit::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(fit::simulate_motion, m)?)?;
    m.add_function(wrap_pyfunction!(fit::validate, m)?)?;
    m.add_function(wrap_pyfunction!(fit::paper_data, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit_records, m)?)?;
    m.add_function(wrap_pyfunction!(fit::free_decay, m)?)?;
    m.add_function(wrap_pyfunction!(fit::dynamometer, m)?)?;
    m.add_function(wrap_pyfunction!(fit::inverse_dynamics, m)?)?;
    m.add_function(wrap_pyfunction!(chain::simulate_chain, m)?)?;
    m.add_function(wrap_pyfunction!(chain::fit_chain, m)?)?;
    m.add_function(wrap_pyfunction!(chain::predict_chain, m)?)?;
    m.add_function(wrap_pyfunction!(frf::frf, m)?)?;
    m.add_function(wrap_pyfunction!(frf::modal_fit, m)?)?;
    m.add_function(wrap_pyfunction!(frf::one_mode_fit, m)?)?;
    m.add_function(wrap_pyfunction!(oma::oma, m)?)?;
    m.add_function(wrap_pyfunction!(oma::oma_setups, m)?)?;
    m.add_function(wrap_pyfunction!(files::read_file, m)?)?;
    m.add_function(wrap_pyfunction!(files::inspect, m)?)?;
    m.add_function(wrap_pyfunction!(files::init, m)?)?;
    m.add_function(wrap_pyfunction!(uff::uff_read, m)?)?;
    m.add_function(wrap_pyfunction!(uff::uff_write, m)?)?;
    m.add_function(wrap_pyfunction!(experiment::run, m)?)?;
    m.add_function(wrap_pyfunction!(experiment::plan, m)?)?;
    m.add_function(wrap_pyfunction!(experiment::design, m)?)?;
    Ok(())
}
