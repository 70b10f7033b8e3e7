//! `dualspectra._dualspectra`: the native module behind the `dualspectra` Python package.
//!
//! Conversion and calls only: every formula lives in the core crate `dualspectra`, and so do
//! the localizer's option names, defaults and ranges (`options.rs` passes keyword arguments
//! through by name). Arrays arrive as contiguous float64 `(n, 3)` / int64 `(m, 3)` (the Python
//! layer converts array-likes); shapes and index ranges are checked again here, the rest by
//! the core (`TriMesh::new` for the operators, `MeshIntake` for the localizer). Errors are
//! mapped to Python exceptions in `errors.rs` only.

mod convert;
mod errors;
mod localization;
mod operators;
mod options;
mod progress;
mod screen;
mod search;

use pyo3::prelude::*;

#[pymodule]
fn _dualspectra(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("MeshError", py.get_type::<errors::MeshError>())?;
    m.add("Cancelled", py.get_type::<errors::Cancelled>())?;
    m.add("NumericalError", py.get_type::<errors::NumericalError>())?;
    m.add_class::<localization::Localization>()?;
    m.add_class::<localization::Candidate>()?;
    m.add_class::<localization::Localizer>()?;
    m.add_class::<localization::PreparedPartial>()?;
    m.add_class::<search::Match>()?;
    m.add_class::<screen::Screen>()?;
    m.add_function(wrap_pyfunction!(localization::localize, m)?)?;
    m.add_function(wrap_pyfunction!(search::search, m)?)?;
    m.add_function(wrap_pyfunction!(search::rank, m)?)?;
    m.add_function(wrap_pyfunction!(search::search_confidences, m)?)?;
    m.add_function(wrap_pyfunction!(search::in_two_stages, m)?)?;
    m.add_function(wrap_pyfunction!(search::shapes_to_refine, m)?)?;
    m.add_function(wrap_pyfunction!(search::two_stage_order, m)?)?;
    m.add_function(wrap_pyfunction!(options::options_schema, m)?)?;
    m.add_function(wrap_pyfunction!(operators::cotangent_stiffness, m)?)?;
    m.add_function(wrap_pyfunction!(operators::lumped_mass, m)?)?;
    m.add_function(wrap_pyfunction!(operators::gaussian_curvature, m)?)?;
    m.add_function(wrap_pyfunction!(operators::spectrum, m)?)?;
    m.add_function(wrap_pyfunction!(operators::read_mesh, m)?)?;
    Ok(())
}
