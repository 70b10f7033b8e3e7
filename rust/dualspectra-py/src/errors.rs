//! Every core error becomes a named Python exception here, and only here.
//!
//! | core `dualspectra::Error`          | Python exception                          |
//! |------------------------------------|-------------------------------------------|
//! | `InvalidMesh`, `InvalidMeshFile`, `Parse` | `dualspectra.MeshError` (a `ValueError`) |
//! | `PreparedShape` (a foreign, stale, truncated or corrupted `.dsprep`) | `dualspectra.MeshError` |
//! | `InvalidArgument`                  | `ValueError`                              |
//! | `Io`                               | `OSError` (errno subclass, e.g. `FileNotFoundError`) |
//! | `Numerical`                        | `dualspectra.NumericalError` (a `RuntimeError`) |
//! | `Cancelled`                        | `dualspectra.Cancelled`, or the exception the progress callback raised (e.g. `KeyboardInterrupt`) |
//!
//! A mesh the intake refuses (`intake_error`) is a `MeshError` naming the mesh, whatever the
//! core's variant ("all faces are degenerate" is an `InvalidArgument` there).

use dualspectra::{Error, MeshError as CoreMeshError};
use pyo3::exceptions::{PyException, PyOSError, PyRuntimeError, PyValueError};
use pyo3::PyErr;

pyo3::create_exception!(
    dualspectra,
    MeshError,
    PyValueError,
    "The mesh arrays or mesh file are invalid (bad shape, index out of range, degenerate or non-manifold, unreadable file content), or a prepared-shape file cannot be loaded (foreign, stale, truncated or corrupted)."
);
pyo3::create_exception!(
    dualspectra,
    Cancelled,
    PyException,
    "The computation was cancelled: the progress callback returned False."
);
pyo3::create_exception!(
    dualspectra,
    NumericalError,
    PyRuntimeError,
    "A numerical step failed (e.g. a factorization or the eigensolver did not converge)."
);

/// The Python exception for a core error.
pub fn to_py(err: Error) -> PyErr {
    match err {
        Error::InvalidMesh(e) => MeshError::new_err(e.to_string()),
        e @ (Error::InvalidMeshFile { .. } | Error::Parse { .. } | Error::PreparedShape { .. }) => {
            MeshError::new_err(e.to_string())
        }
        Error::InvalidArgument(msg) => PyValueError::new_err(msg),
        Error::Io { path, source } => {
            let filename = path.display().to_string();
            match source.raw_os_error() {
                // The 3-argument OSError constructor picks the errno subclass (FileNotFoundError, ...).
                Some(errno) => PyOSError::new_err((errno, source.to_string(), filename)),
                None => PyOSError::new_err(format!("{filename}: {source}")),
            }
        }
        Error::Numerical(msg) => NumericalError::new_err(msg),
        Error::Cancelled => Cancelled::new_err("cancelled by the progress callback"),
        // `Error` may gain variants; keep them visible rather than panicking.
        #[allow(unreachable_patterns)]
        other => PyRuntimeError::new_err(other.to_string()),
    }
}

/// A mesh validation error, prefixed with which mesh it is about (e.g. `"partial mesh"`).
pub fn mesh_error(what: &str, err: CoreMeshError) -> PyErr {
    MeshError::new_err(format!("{what}: {err}"))
}

/// A mesh array problem that the core cannot represent (wrong shape, negative index).
pub fn mesh_array_error(what: &str, message: String) -> PyErr {
    MeshError::new_err(format!("{what}: {message}"))
}

/// An error of the core's mesh intake for the mesh `what` (e.g. `"full mesh"`): a `MeshError`
/// naming it.
pub fn intake_error(what: &str, err: Error) -> PyErr {
    match err {
        Error::InvalidMesh(e) => mesh_error(what, e),
        Error::InvalidArgument(msg) => MeshError::new_err(format!("{what}: {msg}")),
        other => to_py(other),
    }
}
