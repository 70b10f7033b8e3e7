//! Partial shape similarity: `search` ranks full shapes for one partial
//! (`dualspectra::search_with`, screened by `dualspectra::search_screened` with a shortlist
//! or a `Screen`), each answer a `Match`. Full shapes given as meshes are prepared one at a
//! time as the search reaches them, so after a screen only the shortlisted ones are.
//!
//! The meshes enter through the core's `MeshIntake`; every match's localization leaves
//! through its full shape's numbering, as `Localizer.locate`'s does.

use crate::convert::intake;
use crate::localization::{check_callable, with_progress, Localization, Localizer};
use crate::options;
use crate::screen::{describe_library, in_shape, Screen};
use dualspectra::mesh::intake::MeshIntake;
use dualspectra::{Options, Progress, Scale, ScreenEntry};
use numpy::PyReadonlyArray2;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::borrow::Borrow;

/// One full shape's answer for a partial: its index in the shapes searched, the similarity
/// score (lower is more similar; `inf` when the partial could not be located on it), the
/// localization (`None` then) and why it failed.
#[pyclass(frozen, module = "dualspectra", name = "Match")]
pub struct Match {
    #[pyo3(get)]
    index: usize,
    #[pyo3(get)]
    score: f64,
    #[pyo3(get)]
    localization: Option<Py<Localization>>,
    #[pyo3(get)]
    error: Option<String>,
    #[pyo3(get)]
    screen_score: Option<f64>,
    /// Whether `localization` is a screened search's quick one (fewer starts, iterations and eigenvalues, on the regular optimisation mesh even for a partial with holes,
    /// ranking the shortlist) rather than a full localization.
    #[pyo3(get)]
    quick: bool,
    /// How much to trust that the partial is a part of this shape rather than of another one
    /// searched (`dualspectra::search::search_confidences`); 0 when not located.
    #[pyo3(get)]
    confidence: f64,
}

#[pymethods]
impl Match {
    fn __repr__(&self) -> String {
        match (&self.localization, &self.error) {
            (Some(l), _) => format!("Match(index={}, score={:.6e}, localization={})", self.index, self.score, l.get().__repr__()),
            (None, e) => format!("Match(index={}, score={}, error={:?})", self.index, self.score, e.as_deref().unwrap_or("")),
        }
    }
}

/// One full shape to search, as the caller gave it.
enum Full {
    /// Prepared already (used with its own options).
    Prepared(Py<Localizer>),
    /// A mesh, prepared with the options given just before the partial is located on it
    /// (so a mesh the screen leaves out is never prepared).
    Mesh(MeshIntake),
}

/// A shape opened for one localization: borrowed when it was given prepared.
enum Opened<'a> {
    Given(&'a dualspectra::Localizer),
    Prepared(Box<dualspectra::Localizer>),
}

impl Borrow<dualspectra::Localizer> for Opened<'_> {
    fn borrow(&self) -> &dualspectra::Localizer {
        match self {
            Opened::Given(l) => l,
            Opened::Prepared(l) => l,
        }
    }
}

impl Full {
    /// A native `Localizer` or a `(vertices, faces)` pair of float64 / int64 arrays.
    fn from_arg(index: usize, full: &Bound<'_, PyAny>) -> PyResult<Self> {
        if let Ok(localizer) = full.cast::<Localizer>() {
            return Ok(Full::Prepared(localizer.clone().unbind()));
        }
        let what = format!("full shape {index}");
        match full.extract::<(PyReadonlyArray2<'_, f64>, PyReadonlyArray2<'_, i64>)>() {
            Ok((vertices, faces)) => Ok(Full::Mesh(intake(&what, &vertices, &faces)?)),
            Err(_) => Err(PyTypeError::new_err(format!(
                "{what}: expected a Localizer or a (float64 (n, 3), int64 (m, 3)) array pair, got {}",
                full.get_type().name()?
            ))),
        }
    }

    /// The shape's screen entry, from the mesh as given (for a prepared shape: its full mesh).
    fn describe(&self, index: usize) -> dualspectra::Result<ScreenEntry> {
        match self {
            Full::Prepared(l) => ScreenEntry::new(&l.get().inner.full_mesh()),
            Full::Mesh(m) => ScreenEntry::new(&m.mesh),
        }
        .map_err(|e| in_shape(index, e))
    }

    /// The `scale` option it is (or will be) prepared with.
    fn scale(&self, options: &Options) -> Scale {
        match self {
            Full::Prepared(l) => l.get().inner.options().scale,
            Full::Mesh(_) => options.scale,
        }
    }

    /// Ready to locate on: prepared now for a mesh.
    fn open(&self, options: &Options, progress: &Progress) -> dualspectra::Result<Opened<'_>> {
        match self {
            Full::Prepared(l) => Ok(Opened::Given(&l.get().inner)),
            Full::Mesh(m) => Localizer::prepare(m, options, progress).map(|l| Opened::Prepared(Box::new(l))),
        }
    }

    /// A localization on it in the caller's numbering, after the notes its intake and the
    /// partial's gave (as `Localizer.locate`'s).
    fn localization(&self, py: Python<'_>, l: dualspectra::Localization, partial: &MeshIntake) -> PyResult<Localization> {
        match self {
            Full::Prepared(full) => Localization::new(py, l, &full.get().host, full.get().notes_for(partial)),
            Full::Mesh(m) => {
                let notes = m.warning("full mesh").into_iter().chain(partial.warning("partial mesh")).collect();
                Localization::new(py, l, &m.host_numbering(), notes)
            }
        }
    }
}

/// Native `search`: locate the partial `(vertices, faces)` on the shapes of `fulls` (native
/// `Localizer`s, or meshes as `(vertices, faces)` pairs prepared with `options`) and return
/// the `top` best matches (all when `None`), best first (`dualspectra::search_with`). With
/// `shortlist` below the number of shapes, or a `screen` (one model per shape of `fulls`, in
/// order), the shapes are screened first (`dualspectra::search_screened`, with the first
/// shape's `scale` option) and only the `shortlist` best are prepared and localized; every
/// match then carries its screen score. Without `screen`, the screen is described here (the
/// meshes as given, a `Localizer`'s full mesh) in the first 20 % of `progress`. A mesh is
/// prepared just before the partial is located on it and dropped after. Also returns, per
/// shape, the notes of a mesh's intake and, if it was prepared, its preparation (what a
/// `Localizer`'s `warnings` would be; empty for a given `Localizer`).
#[pyfunction]
#[pyo3(signature = (vertices, faces, fulls, top=None, progress=None, shortlist=None, screen=None, options=None))]
#[allow(clippy::too_many_arguments)]
pub fn search(
    py: Python<'_>,
    vertices: PyReadonlyArray2<'_, f64>,
    faces: PyReadonlyArray2<'_, i64>,
    fulls: Vec<Bound<'_, PyAny>>,
    top: Option<usize>,
    progress: Option<Py<PyAny>>,
    shortlist: Option<usize>,
    screen: Option<Py<Screen>>,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<(Vec<Match>, Vec<Vec<String>>)> {
    check_callable(py, &progress)?;
    if let Some(s) = &screen {
        let models = s.get().inner.len();
        if models != fulls.len() {
            return Err(PyValueError::new_err(format!(
                "search: the screen holds {models} shapes, {} full shapes were given (build it from the same shapes, in order)",
                fulls.len()
            )));
        }
    }
    let shapes = fulls.iter().enumerate().map(|(i, f)| Full::from_arg(i, f)).collect::<PyResult<Vec<_>>>()?;
    // The options are for the meshes: unread (as the Python layer's warning says) without one.
    let options =
        if shapes.iter().any(|s| matches!(s, Full::Mesh(_))) { options::from_kwargs(options)? } else { Options::default() };
    let partial = intake("partial mesh", &vertices, &faces)?;
    let n = shapes.len();
    let top = top.unwrap_or(usize::MAX);
    let shortlist = shortlist.unwrap_or(usize::MAX);
    let mut prepared: Vec<Option<Vec<String>>> = (0..n).map(|_| None).collect();
    let found = with_progress(py, progress, |p| {
        let open = |i: usize, part: &Progress| {
            let opened = shapes[i].open(&options, part)?;
            if let Opened::Prepared(l) = &opened {
                prepared[i] = Some(l.warnings().to_vec());
            }
            Ok::<_, dualspectra::Error>(opened)
        };
        if screen.is_none() && shortlist >= n {
            return dualspectra::search_with(&partial.mesh, n, open, top, p);
        }
        let scale = shapes.first().map_or(Scale::default(), |f| f.scale(&options));
        match &screen {
            Some(s) => dualspectra::search_screened(&partial.mesh, &s.get().inner, scale, shortlist, open, top, p),
            None => {
                let described = describe_library(n, |i| shapes[i].describe(i), &p.sub(0.0, 0.2))?;
                dualspectra::search_screened(&partial.mesh, &described, scale, shortlist, open, top, &p.sub(0.2, 1.0))
            }
        }
    })?;
    let matches = found
        .into_iter()
        .map(|m| {
            let full = &shapes[m.index];
            let localization =
                m.localization.map(|l| full.localization(py, l, &partial).and_then(|l| Py::new(py, l))).transpose()?;
            Ok(Match { index: m.index, score: m.score, localization, error: m.error, screen_score: m.screen_score, quick: m.quick, confidence: m.confidence })
        })
        .collect::<PyResult<Vec<_>>>()?;
    let notes = shapes
        .iter()
        .zip(prepared)
        .map(|(shape, prepared)| match shape {
            Full::Prepared(_) => Vec::new(),
            Full::Mesh(m) => m.warning("full mesh").into_iter().chain(prepared.into_iter().flatten()).collect(),
        })
        .collect();
    Ok((matches, notes))
}

/// Native `rank`: positions of `(score, index)` pairs in the core's ranking order (lowest
/// similarity score first, ties by index, `inf` last), the `top` best (all when `None`):
/// `dualspectra::search::rank`, for rankings gathered outside `search` (`search_batch`).
#[pyfunction]
#[pyo3(signature = (scored, top=None))]
pub fn rank(scored: Vec<(f64, usize)>, top: Option<usize>) -> Vec<usize> {
    dualspectra::search::rank(&scored, top.unwrap_or(usize::MAX))
}

/// Native `search_confidences`: `dualspectra::search::search_confidences` of every located
/// shape's `(similarity score, localization confidence)` in a search, for rankings gathered
/// outside `search` (`search_batch`).
#[pyfunction]
pub fn search_confidences(located: Vec<(f64, f64)>) -> Vec<f64> {
    dualspectra::search::search_confidences(&located)
}

/// Native `in_two_stages`: `dualspectra::search::in_two_stages`, whether a screened search of
/// `shortlist` shapes of `library` ranks them quickly first (`search_batch`).
#[pyfunction]
pub fn in_two_stages(shortlist: usize, library: usize) -> bool {
    dualspectra::search::in_two_stages(shortlist, library)
}

/// Native `shapes_to_refine`: `dualspectra::search::shapes_to_refine`, the full shape indices
/// of a quick ranking's `(score, index)` pairs to localize again in full (`search_batch`).
#[pyfunction]
pub fn shapes_to_refine(quick: Vec<(f64, usize)>) -> Vec<usize> {
    dualspectra::search::shapes_to_refine(&quick)
}

/// Native `two_stage_order`: `dualspectra::search::two_stage_order`, the answer's order of a
/// two-stage search as `(quick, position)` pairs (`search_batch`).
#[pyfunction]
pub fn two_stage_order(full: Vec<(f64, usize)>, quick: Vec<(f64, usize)>) -> Vec<(bool, usize)> {
    dualspectra::search::two_stage_order(&full, &quick)
}
