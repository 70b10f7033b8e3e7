//! The localizer (`Localizer`, `localize`) and its results (`Localization`, `Candidate`).
//!
//! Both meshes enter through the core's `MeshIntake`; every per-vertex result leaves through
//! the full mesh's `MeshIntake::to_host` (regions: `to_host_any`, selected if any copy of a
//! split non-manifold vertex is), so it is indexed by the caller's vertices (vertices the
//! intake dropped read `False` / `0.0`), and the intake's notes lead the warnings.

use crate::convert::intake;
use crate::errors::to_py;
use crate::options;
use crate::progress::python_progress;
use dualspectra::mesh::intake::MeshIntake;
use dualspectra::{Error, Progress};
use numpy::{PyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

/// One optimised start of a localization.
#[pyclass(frozen, module = "dualspectra", name = "Candidate")]
pub struct Candidate {
    /// Where it started: `ball@c`, `coball@c`, `bump@c/sigma1`, `planeJ` or `given#i`.
    #[pyo3(get)]
    label: String,
    /// Final alignment cost.
    #[pyo3(get)]
    cost: f64,
    /// Descriptor projection score (lower is better; `None` if not computed).
    #[pyo3(get)]
    descriptor_score: Option<f64>,
    /// Cost of the region's own step potential (lower is better; `None` if not computed).
    #[pyo3(get)]
    region_cost: Option<f64>,
    /// Boundary-length misfit `|ln(L_R / L_N)|` (`None` when a boundary length is 0).
    #[pyo3(get)]
    boundary_misfit: Option<f64>,
    /// Partial-to-region descriptor fit (lower is better; `None` for an empty region).
    #[pyo3(get)]
    partial_fit: Option<f64>,
    /// Trust-region iterations and cost evaluations of its run.
    #[pyo3(get)]
    iterations: usize,
    #[pyo3(get)]
    evaluations: usize,
    /// Its region, one `bool` per vertex of the caller's full mesh.
    #[pyo3(get)]
    region: Py<PyArray1<bool>>,
    n_selected: usize,
}

#[pymethods]
impl Candidate {
    fn __repr__(&self) -> String {
        format!("Candidate(label={:?}, cost={:.6e}, region={} vertices)", self.label, self.cost, self.n_selected)
    }
}

/// Result of a localization. Per-vertex arrays are indexed by the caller's full-mesh vertices.
#[pyclass(frozen, module = "dualspectra", name = "Localization")]
pub struct Localization {
    #[pyo3(get)]
    region: Py<PyArray1<bool>>,
    #[pyo3(get)]
    score: Py<PyArray1<f64>>,
    #[pyo3(get)]
    potential: Py<PyArray1<f64>>,
    #[pyo3(get)]
    eigenvalues_regular: Py<PyArray1<f64>>,
    #[pyo3(get)]
    eigenvalues_si: Py<PyArray1<f64>>,
    #[pyo3(get)]
    target_regular: Py<PyArray1<f64>>,
    #[pyo3(get)]
    target_si: Py<PyArray1<f64>>,
    #[pyo3(get)]
    cost: f64,
    /// Estimated probability, in [0, 1], that the region overlaps the true one with IoU >= 0.5.
    #[pyo3(get)]
    confidence: f64,
    #[pyo3(get)]
    selected_start: usize,
    #[pyo3(get)]
    n_starts: usize,
    candidates: Vec<Py<Candidate>>,
    warnings: Vec<String>,
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
            ("preparation", t.preparation),
            ("preprocessing", t.preprocessing),
            ("starts", t.starts),
            ("optimisation", t.optimisation),
            ("region", t.region),
            ("selection", t.selection),
            ("total", t.total),
        ] {
            d.set_item(k, v)?;
        }
        Ok(d)
    }

    /// Every optimised start; the chosen one is `candidates[selected_start]`.
    #[getter]
    fn candidates<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.candidates.iter().map(|c| c.clone_ref(py)))
    }

    /// What was repaired or skipped (the meshes' intake, a disconnected partial, ...).
    #[getter]
    fn warnings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, &self.warnings)
    }

    fn __repr__(&self) -> String {
        format!(
            "Localization(region={}/{} vertices, cost={:.6e}, confidence={:.3}, selected_start={}, n_starts={}, total={:.3}s)",
            self.n_selected, self.n_vertices, self.cost, self.confidence, self.selected_start, self.n_starts, self.timings.total
        )
    }
}

impl Localization {
    /// The core's result on `full.mesh`, its per-vertex arrays brought back to the host's
    /// vertices; `notes` (the intakes' warnings) go before the core's warnings.
    fn new(py: Python<'_>, r: dualspectra::Localization, full: &MeshIntake, notes: Vec<String>) -> PyResult<Self> {
        let arr = |v: Vec<f64>| PyArray1::from_vec(py, v).unbind();
        // A split (non-manifold) vertex is selected if any copy is; values are its first copy's.
        let mask = |v: &[bool]| PyArray1::from_vec(py, full.to_host_any(v)).unbind();
        let region = full.to_host_any(&r.region);
        let candidates = r
            .candidates
            .into_iter()
            .map(|c| {
                Py::new(
                    py,
                    Candidate {
                        label: c.label,
                        cost: c.cost,
                        descriptor_score: c.scores.descriptor_score,
                        region_cost: c.scores.region_cost,
                        boundary_misfit: c.scores.boundary_misfit,
                        partial_fit: c.scores.partial_fit,
                        iterations: c.iterations,
                        evaluations: c.evaluations,
                        n_selected: c.region.iter().filter(|&&b| b).count(),
                        region: mask(&c.region),
                    },
                )
            })
            .collect::<PyResult<Vec<_>>>()?;
        let mut warnings = notes;
        warnings.extend(r.warnings);
        Ok(Localization {
            n_selected: region.iter().filter(|&&b| b).count(),
            n_vertices: region.len(),
            region: PyArray1::from_vec(py, region).unbind(),
            score: arr(full.to_host(&r.score, 0.0)),
            potential: arr(full.to_host(&r.potential, 0.0)),
            eigenvalues_regular: arr(r.eigenvalues_regular),
            eigenvalues_si: arr(r.eigenvalues_si),
            target_regular: arr(r.target_regular),
            target_si: arr(r.target_si),
            cost: r.cost,
            confidence: r.confidence,
            selected_start: r.selected_start,
            n_starts: r.n_starts,
            candidates,
            warnings,
            timings: r.timings,
        })
    }
}

/// Check the optional progress callback.
fn check_callable(py: Python<'_>, progress: &Option<Py<PyAny>>) -> PyResult<()> {
    match progress {
        Some(cb) if !cb.bind(py).is_callable() => {
            Err(pyo3::exceptions::PyTypeError::new_err("progress must be callable (fraction, stage) -> bool | None"))
        }
        _ => Ok(()),
    }
}

/// Run `work` with the GIL released under a progress handle calling `progress`; a
/// cancellation re-raises the callback's exception (or `KeyboardInterrupt`) if there was one.
fn with_progress<T: Send>(
    py: Python<'_>,
    progress: Option<Py<PyAny>>,
    work: impl FnOnce(&Progress) -> dualspectra::Result<T> + Send,
) -> PyResult<T> {
    let (handle, raised) = python_progress(progress);
    match py.detach(|| work(&handle)) {
        Ok(v) => Ok(v),
        Err(Error::Cancelled) => Err(raised.take().unwrap_or_else(|| to_py(Error::Cancelled))),
        Err(e) => Err(to_py(e)),
    }
}

/// The full mesh's intake note and the core's preparation notes.
fn localizer_warnings(full: &MeshIntake, core: &dualspectra::Localizer) -> Vec<String> {
    full.warning("full mesh").into_iter().chain(core.warnings().iter().cloned()).collect()
}

/// A full shape prepared once for locating partials on it (native side of
/// `dualspectra.Localizer`).
#[pyclass(frozen, module = "dualspectra._dualspectra", name = "Localizer")]
pub struct Localizer {
    inner: dualspectra::Localizer,
    full: MeshIntake,
}

#[pymethods]
impl Localizer {
    #[new]
    #[pyo3(signature = (vertices, faces, options=None, progress=None))]
    fn new(
        py: Python<'_>,
        vertices: PyReadonlyArray2<'_, f64>,
        faces: PyReadonlyArray2<'_, i64>,
        options: Option<&Bound<'_, PyDict>>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Self> {
        check_callable(py, &progress)?;
        let options = options::from_kwargs(options)?;
        let full = intake("full mesh", &vertices, &faces)?;
        let inner = with_progress(py, progress, |p| dualspectra::Localizer::with_progress(&full.mesh, &options, p))?;
        Ok(Localizer { inner, full })
    }

    /// Locate a partial mesh; callable from several threads at once.
    #[pyo3(signature = (vertices, faces, progress=None))]
    fn locate(
        &self,
        py: Python<'_>,
        vertices: PyReadonlyArray2<'_, f64>,
        faces: PyReadonlyArray2<'_, i64>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Localization> {
        check_callable(py, &progress)?;
        let partial = intake("partial mesh", &vertices, &faces)?;
        let r = with_progress(py, progress, |p| self.inner.locate(&partial.mesh, p))?;
        let notes = self.full.warning("full mesh").into_iter().chain(partial.warning("partial mesh")).collect();
        Localization::new(py, r, &self.full, notes)
    }

    /// Vertices of the caller's full mesh (the length of every per-vertex result).
    #[getter]
    fn n_vertices(&self) -> usize {
        self.full.n_host_vertices
    }

    /// Vertices of the optimisation mesh (the full shape decimated to about `resolution`).
    #[getter]
    fn optimisation_vertices(&self) -> usize {
        self.inner.optimisation_vertices()
    }

    /// Notes on the full mesh's intake and the preparation, as a tuple of str.
    #[getter]
    fn warnings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, localizer_warnings(&self.full, &self.inner))
    }

    /// The options it was prepared with, as a dict (a new one on each access).
    #[getter]
    fn options<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        options::to_dict(py, self.inner.options())
    }

    /// Seconds the preparation took.
    #[getter]
    fn preparation_seconds(&self) -> f64 {
        self.inner.preparation_seconds()
    }

    fn __repr__(&self) -> String {
        format!(
            "Localizer(n_vertices={}, optimisation_vertices={}, preparation={:.3}s)",
            self.full.n_host_vertices,
            self.inner.optimisation_vertices(),
            self.inner.preparation_seconds()
        )
    }
}

/// Native `localize` (the one-call form): arrays already float64 (n, 3) / int64 (m, 3).
#[pyfunction]
#[pyo3(signature = (full_vertices, full_faces, partial_vertices, partial_faces, options=None, progress=None))]
pub fn localize(
    py: Python<'_>,
    full_vertices: PyReadonlyArray2<'_, f64>,
    full_faces: PyReadonlyArray2<'_, i64>,
    partial_vertices: PyReadonlyArray2<'_, f64>,
    partial_faces: PyReadonlyArray2<'_, i64>,
    options: Option<&Bound<'_, PyDict>>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Localization> {
    check_callable(py, &progress)?;
    let options = options::from_kwargs(options)?;
    let full = intake("full mesh", &full_vertices, &full_faces)?;
    let partial = intake("partial mesh", &partial_vertices, &partial_faces)?;
    let r = with_progress(py, progress, |p| dualspectra::localize(&full.mesh, &partial.mesh, &options, p))?;
    let notes = full.warning("full mesh").into_iter().chain(partial.warning("partial mesh")).collect();
    Localization::new(py, r, &full, notes)
}
