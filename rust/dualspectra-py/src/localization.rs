//! The localizer (`Localizer`, `localize`), its results (`Localization`, `Candidate`) and
//! prepared shapes as files and bytes (`Localizer.save` / `load` / `to_bytes` / `from_bytes`,
//! the core's `.dsprep` format).
//!
//! Both meshes enter through the core's `MeshIntake`; the full mesh's numbering (the
//! intake's `kept` map, a `HostNumbering`) stays with the prepared shape, in memory and in
//! its file, and every per-vertex result leaves through it (the core's
//! `Localization::to_host`: regions hold a split non-manifold vertex if any copy is; values
//! are the first copy's), so it is indexed by the
//! caller's vertices (vertices the intake dropped read `False` / `0.0`), and the intake's
//! notes lead the warnings.

use crate::convert::intake;
use crate::errors::to_py;
use crate::options;
use crate::progress::python_progress;
use dualspectra::localizer::HostNumbering;
use dualspectra::mesh::intake::MeshIntake;
use dualspectra::{Error, Options, Progress};
use numpy::{PyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyTuple};
use std::path::PathBuf;

/// One optimised start of a localization.
#[pyclass(frozen, module = "dualspectra", name = "Candidate")]
pub struct Candidate {
    /// Where it started: `planeJ`, `descriptor-fit`, `descriptor-vote` or `given#i`.
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
    /// Share of the partial's descriptor votes inside the region (higher is better; `None`
    /// without descriptors).
    #[pyo3(get)]
    vote_share: Option<f64>,
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
    /// Estimated probability, in [0, 1], that the partial is part of this full shape and the
    /// region overlaps the true one with IoU >= 0.5.
    #[pyo3(get)]
    confidence: f64,
    /// The core's similarity score of the partial to the full shape (lower is more similar;
    /// `dualspectra::Localization::similarity_score`).
    #[pyo3(get)]
    similarity_score: f64,
    /// The factor the partial's coordinates were multiplied by (1 with ``scale="same"``, the
    /// estimate with ``scale="auto"``; `dualspectra::Localization::scale`).
    #[pyo3(get)]
    scale: f64,
    /// Vertices of the optimisation mesh used (about twice the `resolution` option for a
    /// partial with holes).
    #[pyo3(get)]
    optimisation_vertices: usize,
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

    pub(crate) fn __repr__(&self) -> String {
        format!(
            "Localization(region={}/{} vertices, cost={:.6e}, confidence={:.3}, similarity_score={:.6e}, selected_start={}, n_starts={}, total={:.3}s)",
            self.n_selected,
            self.n_vertices,
            self.cost,
            self.confidence,
            self.similarity_score,
            self.selected_start,
            self.n_starts,
            self.timings.total
        )
    }
}

impl Localization {
    /// The core's result on the full shape's mesh, its per-vertex arrays brought back to the
    /// caller's vertices (`host`); `notes` (the intakes' warnings) go before the core's
    /// warnings.
    pub(crate) fn new(py: Python<'_>, r: dualspectra::Localization, host: &HostNumbering, notes: Vec<String>) -> PyResult<Self> {
        let r = r.to_host(host);
        let arr = |v: Vec<f64>| PyArray1::from_vec(py, v).unbind();
        let region = r.region;
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
                        vote_share: c.scores.vote_share,
                        iterations: c.iterations,
                        evaluations: c.evaluations,
                        n_selected: c.region.iter().filter(|&&b| b).count(),
                        region: PyArray1::from_vec(py, c.region).unbind(),
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
            score: arr(r.score),
            potential: arr(r.potential),
            eigenvalues_regular: arr(r.eigenvalues_regular),
            eigenvalues_si: arr(r.eigenvalues_si),
            target_regular: arr(r.target_regular),
            target_si: arr(r.target_si),
            cost: r.cost,
            confidence: r.confidence,
            similarity_score: r.similarity_score,
            scale: r.scale,
            optimisation_vertices: r.optimisation_vertices,
            selected_start: r.selected_start,
            n_starts: r.n_starts,
            candidates,
            warnings,
            timings: r.timings,
        })
    }
}

/// Check the optional progress callback.
pub(crate) fn check_callable(py: Python<'_>, progress: &Option<Py<PyAny>>) -> PyResult<()> {
    match progress {
        Some(cb) if !cb.bind(py).is_callable() => {
            Err(pyo3::exceptions::PyTypeError::new_err("progress must be callable (fraction, stage) -> bool | None"))
        }
        _ => Ok(()),
    }
}

/// Run `work` with the GIL released under a progress handle calling `progress`; a
/// cancellation re-raises the callback's exception (or `KeyboardInterrupt`) if there was one.
pub(crate) fn with_progress<T: Send>(
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

/// A full shape prepared once for locating partials on it (native side of
/// `dualspectra.Localizer`).
#[pyclass(frozen, module = "dualspectra._dualspectra", name = "Localizer")]
pub struct Localizer {
    pub(crate) inner: dualspectra::Localizer,
    /// The caller's numbering of the full mesh (also kept in `inner`, and so in its file,
    /// when it is not the identity).
    pub(crate) host: HostNumbering,
    /// What the intake of the full mesh changed (`None` for a loaded shape: not in the file).
    note: Option<String>,
}

/// A partial shape taken in once to be located on several full shapes
/// (`dualspectra::search::PreparedPartial`): what every localization needs of the partial
/// alone is computed by the first that needs it and kept. Private to the batch module.
#[pyclass(frozen, module = "dualspectra._dualspectra", name = "PreparedPartial")]
pub struct PreparedPartial {
    inner: dualspectra::search::PreparedPartial,
    /// What the intake of the partial mesh changed.
    note: Option<String>,
}

#[pymethods]
impl PreparedPartial {
    #[new]
    fn new(vertices: PyReadonlyArray2<'_, f64>, faces: PyReadonlyArray2<'_, i64>) -> PyResult<Self> {
        let partial = intake("partial mesh", &vertices, &faces)?;
        let note = partial.warning("partial mesh");
        Ok(PreparedPartial { inner: dualspectra::search::PreparedPartial::new(partial.mesh), note })
    }

    fn __repr__(&self) -> String {
        format!("PreparedPartial(vertices={})", self.inner.mesh().n_vertices())
    }
}

impl Localizer {
    /// The full mesh's intake note, if any, and the core's notes.
    fn all_warnings(&self) -> Vec<String> {
        self.note.iter().chain(self.inner.warnings()).cloned().collect()
    }

    /// The notes every result on this shape starts with, then `partial`'s intake note.
    pub(crate) fn notes_for(&self, partial: &MeshIntake) -> Vec<String> {
        self.notes_with(partial.warning("partial mesh"))
    }

    /// The notes every result on this shape starts with, then the partial's intake note.
    fn notes_with(&self, partial_note: Option<String>) -> Vec<String> {
        self.note.iter().cloned().chain(partial_note).collect()
    }

    /// The partial `(vertices, faces)` taken in and located by `how` (with `progress`, the GIL
    /// released), as a Python result with this shape's notes.
    fn locate_by(
        &self,
        py: Python<'_>,
        vertices: &PyReadonlyArray2<'_, f64>,
        faces: &PyReadonlyArray2<'_, i64>,
        progress: Option<Py<PyAny>>,
        how: impl FnOnce(&dualspectra::Localizer, &dualspectra::TriMesh, &Progress) -> dualspectra::Result<dualspectra::Localization> + Send,
    ) -> PyResult<Localization> {
        check_callable(py, &progress)?;
        let partial = intake("partial mesh", vertices, faces)?;
        let r = with_progress(py, progress, |p| how(&self.inner, &partial.mesh, p))?;
        Localization::new(py, r, &self.host, self.notes_for(&partial))
    }

    /// The core's preparation of the full mesh `full` (an intake of the caller's arrays), its
    /// numbering stored with it (saved files name the caller's vertices) unless it is the
    /// identity: `Localizer(vertices, faces)`'s, and `search`'s for the meshes it prepares.
    pub(crate) fn prepare(
        full: &MeshIntake,
        options: &Options,
        progress: &Progress,
    ) -> dualspectra::Result<dualspectra::Localizer> {
        let mut inner = dualspectra::Localizer::with_progress(&full.mesh, options, progress)?;
        let host = full.host_numbering();
        inner.set_host_numbering((!host.is_identity()).then_some(host))?;
        Ok(inner)
    }

    /// A loaded core localizer, run on `threads` threads if given, results in its stored
    /// numbering (the identity when none was stored).
    fn loaded(mut inner: dualspectra::Localizer, threads: Option<usize>, note: Option<String>) -> PyResult<Self> {
        if let Some(t) = threads {
            inner.set_threads(t).map_err(to_py)?;
        }
        let host = inner.host_numbering().cloned().unwrap_or_else(|| HostNumbering::identity(inner.n_vertices()));
        Ok(Localizer { inner, host, note })
    }
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
        let inner = with_progress(py, progress, |p| Localizer::prepare(&full, &options, p))?;
        Ok(Localizer { inner, host: full.host_numbering(), note: full.warning("full mesh") })
    }

    /// Write the prepared shape to `path` (the core's `.dsprep` format).
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        py.detach(|| self.inner.save(&path)).map_err(to_py)
    }

    /// A prepared shape read from `path`, run on `threads` threads if given.
    #[staticmethod]
    #[pyo3(signature = (path, threads=None))]
    fn load(py: Python<'_>, path: PathBuf, threads: Option<usize>) -> PyResult<Self> {
        let inner = py.detach(|| dualspectra::Localizer::load(&path)).map_err(to_py)?;
        Localizer::loaded(inner, threads, None)
    }

    /// The prepared shape as bytes (the file's content).
    fn to_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        let bytes = py.detach(|| self.inner.to_bytes());
        PyBytes::new(py, &bytes)
    }

    /// A prepared shape from `to_bytes`' bytes, run on `threads` threads if given;
    /// `intake_note` restores the full mesh's intake note (pickling keeps it beside the bytes).
    #[staticmethod]
    #[pyo3(signature = (data, threads=None, intake_note=None))]
    fn from_bytes(py: Python<'_>, data: &[u8], threads: Option<usize>, intake_note: Option<String>) -> PyResult<Self> {
        let inner = py.detach(|| dualspectra::Localizer::from_bytes(data)).map_err(to_py)?;
        Localizer::loaded(inner, threads, intake_note)
    }

    /// What the intake of the full mesh changed (`None`: nothing, or a loaded shape).
    #[getter]
    fn intake_note(&self) -> Option<String> {
        self.note.clone()
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
        self.locate_by(py, &vertices, &faces, progress, dualspectra::Localizer::locate)
    }

    /// `locate` of a prepared partial (`dualspectra::search::locate_prepared`), as a search
    /// locates it: with `quick`, the two-stage search's quick localization (fewer starts,
    /// iterations and eigenvalues, on the regular optimisation mesh even for a partial with
    /// holes). For batches that run a search's localizations themselves: what the partial
    /// alone needs (the `scale = auto` scan) is computed once for every shape it is located on.
    #[pyo3(signature = (partial, quick=false, progress=None))]
    fn locate_prepared(&self, py: Python<'_>, partial: &PreparedPartial, quick: bool, progress: Option<Py<PyAny>>) -> PyResult<Localization> {
        check_callable(py, &progress)?;
        let r = with_progress(py, progress, |p| dualspectra::search::locate_prepared(&self.inner, &partial.inner, quick, p))?;
        Localization::new(py, r, &self.host, self.notes_with(partial.note.clone()))
    }

    /// Vertices of the caller's full mesh (the length of every per-vertex result).
    #[getter]
    fn n_vertices(&self) -> usize {
        self.host.n_host_vertices
    }

    /// Vertices of the optimisation mesh (the full shape decimated to about `resolution`).
    #[getter]
    fn optimisation_vertices(&self) -> usize {
        self.inner.optimisation_vertices()
    }

    /// Notes on the full mesh's intake and the preparation, as a tuple of str.
    #[getter]
    fn warnings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.all_warnings())
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
            self.host.n_host_vertices,
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
    Localization::new(py, r, &full.host_numbering(), notes)
}
