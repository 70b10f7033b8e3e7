//! `localize` and its result class.

use crate::convert::trimesh;
use crate::errors::to_py;
use crate::progress::python_progress;
use dualspectra::localize::Selection;
use dualspectra::{Error, Options, StartShape};
use numpy::{PyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Result of `localize`. Per-vertex arrays are indexed by the full mesh's vertices.
#[pyclass(frozen, module = "dualspectra", name = "Localization")]
pub struct Localization {
    /// `True` for vertices of the full mesh in the matched region, shape `(n_full,)`.
    #[pyo3(get)]
    region: Py<PyArray1<bool>>,
    /// Soft membership in [0, 1] per full-mesh vertex.
    #[pyo3(get)]
    score: Py<PyArray1<f64>>,
    /// Optimised potential `v >= 0` per full-mesh vertex.
    #[pyo3(get)]
    potential: Py<PyArray1<f64>>,
    /// Hamiltonian eigenvalues at the optimum, regular metric (empty in `si` mode).
    #[pyo3(get)]
    eigenvalues_regular: Py<PyArray1<f64>>,
    /// Hamiltonian eigenvalues at the optimum, scale-invariant metric (empty in `lbo` mode).
    #[pyo3(get)]
    eigenvalues_si: Py<PyArray1<f64>>,
    /// Target Dirichlet spectra of the partial shape.
    #[pyo3(get)]
    target_regular: Py<PyArray1<f64>>,
    #[pyo3(get)]
    target_si: Py<PyArray1<f64>>,
    /// Final alignment cost of the selected start.
    #[pyo3(get)]
    cost: f64,
    /// Index of the selected start and number of starts run.
    #[pyo3(get)]
    selected_start: usize,
    #[pyo3(get)]
    n_starts: usize,
    timings: dualspectra::Timings,
    n_selected: usize,
    n_vertices: usize,
}

#[pymethods]
impl Localization {
    /// Wall-clock seconds per stage (a new dict on each access).
    #[getter]
    fn timings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let t = &self.timings;
        let d = PyDict::new(py);
        for (k, v) in [
            ("preprocessing", t.preprocessing),
            ("starts", t.starts),
            ("optimisation", t.optimisation),
            ("selection", t.selection),
            ("region", t.region),
            ("total", t.total),
        ] {
            d.set_item(k, v)?;
        }
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!(
            "Localization(region={}/{} vertices, cost={:.6e}, selected_start={}, n_starts={}, total={:.3}s)",
            self.n_selected,
            self.n_vertices,
            self.cost,
            self.selected_start,
            self.n_starts,
            self.timings.total
        )
    }
}

impl Localization {
    fn new(py: Python<'_>, r: dualspectra::Localization) -> Self {
        let arr = |v: Vec<f64>| PyArray1::from_vec(py, v).unbind();
        let n_selected = r.region.iter().filter(|&&b| b).count();
        let n_vertices = r.region.len();
        Localization {
            n_selected,
            n_vertices,
            region: PyArray1::from_vec(py, r.region).unbind(),
            score: arr(r.score),
            potential: arr(r.potential),
            eigenvalues_regular: arr(r.eigenvalues_regular),
            eigenvalues_si: arr(r.eigenvalues_si),
            target_regular: arr(r.target_regular),
            target_si: arr(r.target_si),
            cost: r.cost,
            selected_start: r.selected_start,
            n_starts: r.n_starts,
            timings: r.timings,
        }
    }
}

/// Native `localize`: arrays already converted to float64 (n, 3) / int64 (m, 3) by the Python layer.
#[pyfunction]
#[pyo3(signature = (full_vertices, full_faces, partial_vertices, partial_faces, mode, k, alpha, seed, resolution=None, centers=None, max_iterations=None, threads=None, selection=None, starts=None, spectral_cuts=None, plane_cuts=None, progress=None))]
#[allow(clippy::too_many_arguments)]
pub fn localize(
    py: Python<'_>,
    full_vertices: PyReadonlyArray2<'_, f64>,
    full_faces: PyReadonlyArray2<'_, i64>,
    partial_vertices: PyReadonlyArray2<'_, f64>,
    partial_faces: PyReadonlyArray2<'_, i64>,
    mode: &str,
    k: usize,
    alpha: f64,
    seed: u64,
    resolution: Option<usize>,
    centers: Option<usize>,
    max_iterations: Option<usize>,
    threads: Option<usize>,
    selection: Option<&str>,
    starts: Option<&str>,
    spectral_cuts: Option<usize>,
    plane_cuts: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Localization> {
    if let Some(cb) = &progress {
        if !cb.bind(py).is_callable() {
            return Err(pyo3::exceptions::PyTypeError::new_err("progress must be callable (fraction, stage) -> bool | None"));
        }
    }
    let full = trimesh("full mesh", &full_vertices, &full_faces)?;
    let partial = trimesh("partial mesh", &partial_vertices, &partial_faces)?;
    let mode = mode.parse().map_err(to_py)?;
    if !alpha.is_finite() {
        return Err(pyo3::exceptions::PyValueError::new_err(format!("alpha must be finite, got {alpha}")));
    }
    let defaults = Options::default();
    let selection = match selection {
        None => defaults.selection,
        Some(name) => name
            .parse::<Selection>()
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(format!("selection: {e}")))?,
    };
    let start_shape = match starts {
        None => defaults.start_shape,
        Some(name) => name
            .parse::<StartShape>()
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(format!("starts: {e}")))?,
    };
    let options = Options {
        mode,
        k,
        alpha,
        seed,
        resolution: resolution.unwrap_or(defaults.resolution),
        centers: centers.unwrap_or(defaults.centers),
        max_iterations: max_iterations.unwrap_or(defaults.max_iterations),
        threads: threads.unwrap_or(defaults.threads),
        selection,
        start_shape,
        spectral_cuts: spectral_cuts.unwrap_or(defaults.spectral_cuts),
        plane_cuts: plane_cuts.unwrap_or(defaults.plane_cuts),
        ..defaults
    };
    let (handle, raised) = python_progress(progress);
    let result = py.detach(|| dualspectra::localize(&full, &partial, &options, &handle));
    match result {
        Ok(r) => Ok(Localization::new(py, r)),
        Err(Error::Cancelled) => Err(raised.take().unwrap_or_else(|| to_py(Error::Cancelled))),
        Err(e) => Err(to_py(e)),
    }
}
