//! The library screen (`dualspectra::Screen`): full shapes described once by a few SHOT
//! descriptors each, so that a partial is ranked against the whole library in a fraction of
//! a second and localized on the most promising shapes only (`search(..., screen=)`,
//! `search_batch(..., shortlist=)`). Saved and loaded as the core's `.dsscreen` files, the
//! format `dualspectra index` writes.
//!
//! Meshes enter through the core's `MeshIntake` (as the localizer's do); a prepared shape
//! contributes its full mesh (`dualspectra::Localizer::full_mesh`), a `.dsprep` path is
//! loaded, described and dropped, one at a time, as the command line's `index` does.

use crate::convert::intake;
use crate::errors::to_py;
use crate::localization::{check_callable, with_progress, Localizer};
use dualspectra::{Error, Progress, Scale, ScreenEntry, TriMesh};
use numpy::PyReadonlyArray2;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyString, PyTuple};
use std::path::PathBuf;

/// `(shape index, screen score)` for every shape, best first.
type Ranking = Vec<(usize, f64)>;

/// One full shape to describe, as the caller gave it.
enum Shape {
    Mesh(TriMesh),
    Prepared(Py<Localizer>),
    File(PathBuf),
}

impl Shape {
    /// The shape's screen entry; errors name the shape (`index`, or the file).
    fn describe(&self, index: usize) -> dualspectra::Result<ScreenEntry> {
        let named = |e: Error| in_shape(index, e);
        match self {
            Shape::Mesh(mesh) => ScreenEntry::new(mesh).map_err(named),
            Shape::Prepared(localizer) => ScreenEntry::new(&localizer.get().inner.full_mesh()).map_err(named),
            Shape::File(path) => {
                let mesh = dualspectra::Localizer::load(path)?.full_mesh();
                ScreenEntry::new(&mesh).map_err(|e| named(e.in_file(path)))
            }
        }
    }
}

/// `e` naming full shape `index` when it is about the input (`InvalidArgument`).
pub(crate) fn in_shape(index: usize, e: Error) -> Error {
    match e {
        Error::InvalidArgument(msg) => Error::InvalidArgument(format!("full shape {index}: {msg}")),
        other => other,
    }
}

/// The screen of `n` shapes, shape `i`'s entry `entry(i)`, reporting per shape (`Screen(fulls)`,
/// and `search` with a shortlist and no screen).
pub(crate) fn describe_library(
    n: usize,
    mut entry: impl FnMut(usize) -> dualspectra::Result<ScreenEntry>,
    progress: &Progress,
) -> dualspectra::Result<dualspectra::Screen> {
    let mut entries = Vec::with_capacity(n);
    for i in 0..n {
        progress.report(i as f64 / n as f64, "describing the library")?;
        entries.push(entry(i)?);
    }
    let screen = dualspectra::Screen::new(&entries)?;
    progress.report(1.0, "described the library")?;
    Ok(screen)
}

/// `scale` as the core takes it: `"same"`, `"auto"` (any case) or a positive number.
fn scale_arg(value: &Bound<'_, PyAny>) -> PyResult<Scale> {
    if value.is_instance_of::<PyString>() {
        return value.extract::<String>()?.parse().map_err(to_py);
    }
    if !value.is_instance_of::<PyBool>() {
        if let Ok(f) = value.extract::<f64>() {
            return Scale::factor(f).map_err(to_py);
        }
    }
    Err(PyTypeError::new_err(format!("scale must be \"same\", \"auto\" or a positive number, got {}", value.get_type().name()?)))
}

/// A library of full shapes ready to be screened (native side of `dualspectra.Screen`).
#[pyclass(frozen, module = "dualspectra._dualspectra", name = "Screen")]
pub struct Screen {
    pub(crate) inner: dualspectra::Screen,
    /// What the intake of the meshes changed, one note per mesh that needed one.
    notes: Vec<String>,
}

#[pymethods]
impl Screen {
    /// Describe `fulls` (each a native `Localizer`, a `(vertices, faces)` pair of float64 /
    /// int64 arrays or the path of a prepared shape); `labels`, one per shape, name them.
    #[new]
    #[pyo3(signature = (fulls, labels=None, progress=None))]
    fn new(
        py: Python<'_>,
        fulls: Vec<Bound<'_, PyAny>>,
        labels: Option<Vec<String>>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Self> {
        check_callable(py, &progress)?;
        if let Some(l) = &labels {
            if l.len() != fulls.len() {
                return Err(PyValueError::new_err(format!("screen: {} labels for {} full shapes", l.len(), fulls.len())));
            }
        }
        let mut notes = Vec::new();
        let mut shapes = Vec::with_capacity(fulls.len());
        for (i, full) in fulls.iter().enumerate() {
            let what = format!("full shape {i}");
            if let Ok(localizer) = full.cast::<Localizer>() {
                shapes.push(Shape::Prepared(localizer.clone().unbind()));
            } else if full.is_instance_of::<PyString>() {
                shapes.push(Shape::File(full.extract()?));
            } else if let Ok((vertices, faces)) = full.extract::<(PyReadonlyArray2<'_, f64>, PyReadonlyArray2<'_, i64>)>() {
                let mesh = intake(&what, &vertices, &faces)?;
                notes.extend(mesh.warning(&what));
                shapes.push(Shape::Mesh(mesh.mesh));
            } else {
                return Err(PyTypeError::new_err(format!(
                    "{what}: expected a Localizer, a (float64 (n, 3), int64 (m, 3)) array pair or a path, got {}",
                    full.get_type().name()?
                )));
            }
        }
        let inner = with_progress(py, progress, |p| {
            let mut screen = describe_library(shapes.len(), |i| shapes[i].describe(i), p)?;
            if let Some(labels) = labels {
                screen.set_labels(labels)?;
            }
            Ok(screen)
        })?;
        Ok(Screen { inner, notes })
    }

    /// Every shape's screen score for the partial `(vertices, faces)` under `scale` (`"same"`
    /// when `None`): `[(index, score)]`, best (lowest) first, ties by the lower distance then
    /// by index, `inf` (the partial cannot be part of it in these units) last; and the
    /// partial's intake note.
    #[pyo3(signature = (vertices, faces, scale=None, progress=None))]
    fn rank(
        &self,
        py: Python<'_>,
        vertices: PyReadonlyArray2<'_, f64>,
        faces: PyReadonlyArray2<'_, i64>,
        scale: Option<&Bound<'_, PyAny>>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<(Ranking, Vec<String>)> {
        check_callable(py, &progress)?;
        let scale = scale.map(scale_arg).transpose()?.unwrap_or_default();
        let partial = intake("partial mesh", &vertices, &faces)?;
        let ranked = with_progress(py, progress, |p| self.inner.rank(&partial.mesh, scale, p))?;
        Ok((ranked, partial.warning("partial mesh").into_iter().collect()))
    }

    /// Write the screen to `path` (the core's `.dsscreen` format).
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        py.detach(|| self.inner.save(&path)).map_err(to_py)
    }

    /// A screen read from `path` (a `MeshError` for a foreign, stale, truncated or corrupted file).
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let inner = py.detach(|| dualspectra::Screen::load(&path)).map_err(to_py)?;
        Ok(Screen { inner, notes: Vec::new() })
    }

    /// The screen as bytes (the file's content).
    fn to_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        let bytes = py.detach(|| self.inner.to_bytes());
        PyBytes::new(py, &bytes)
    }

    /// A screen from `to_bytes`' bytes.
    #[staticmethod]
    fn from_bytes(py: Python<'_>, data: &[u8]) -> PyResult<Self> {
        let inner = py.detach(|| dualspectra::Screen::from_bytes(data, None)).map_err(to_py)?;
        Ok(Screen { inner, notes: Vec::new() })
    }

    /// Each shape's label, as a tuple of str (empty strings unless given).
    #[getter]
    fn labels<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.inner.labels())
    }

    /// What the intake of the meshes changed, as a tuple of str (empty for a loaded screen).
    #[getter]
    fn warnings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, &self.notes)
    }

    /// Bytes held per shape (its projected descriptors) and for the shared basis.
    #[getter]
    fn nbytes(&self) -> (usize, usize) {
        self.inner.bytes()
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    fn __repr__(&self) -> String {
        let (per_model, basis) = self.inner.bytes();
        format!("Screen(shapes={}, bytes={})", self.inner.len(), self.inner.len() * per_model + basis)
    }
}
