//! Partial shape similarity: `search` ranks prepared full shapes for one partial
//! (`dualspectra::search`, screened by `dualspectra::search_screened` with a shortlist or a
//! `Screen`), each answer a `Match`.
//!
//! The partial enters through the core's `MeshIntake`; every match's localization leaves
//! through its full shape's numbering, as `Localizer.locate`'s does.

use crate::convert::intake;
use crate::localization::{check_callable, with_progress, Localization, Localizer};
use crate::screen::Screen;
use numpy::PyReadonlyArray2;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

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

/// Native `search`: locate the partial `(vertices, faces)` on every prepared shape of `fulls`
/// and return the `top` best matches (all when `None`), best first (`dualspectra::search`).
/// With `shortlist` below the number of shapes, the shapes are screened first
/// (`dualspectra::search_screened`, with the first shape's `scale` option) and only the
/// `shortlist` best are localized. A given `screen` (one model per shape of `fulls`, in
/// order) is used instead of describing the shapes again, and every match then carries its
/// screen score.
#[pyfunction]
#[pyo3(signature = (vertices, faces, fulls, top=None, progress=None, shortlist=None, screen=None))]
#[allow(clippy::too_many_arguments)]
pub fn search(
    py: Python<'_>,
    vertices: PyReadonlyArray2<'_, f64>,
    faces: PyReadonlyArray2<'_, i64>,
    fulls: Vec<Py<Localizer>>,
    top: Option<usize>,
    progress: Option<Py<PyAny>>,
    shortlist: Option<usize>,
    screen: Option<Py<Screen>>,
) -> PyResult<Vec<Match>> {
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
    let partial = intake("partial mesh", &vertices, &faces)?;
    let shapes: Vec<&dualspectra::Localizer> = fulls.iter().map(|f| &f.get().inner).collect();
    let top = top.unwrap_or(usize::MAX);
    let shortlist = shortlist.unwrap_or(usize::MAX);
    let found = with_progress(py, progress, |p| match &screen {
        Some(s) => {
            let scale = shapes.first().map_or(dualspectra::Scale::default(), |f| f.options().scale);
            let open = |i: usize, _: &dualspectra::Progress| Ok::<_, dualspectra::Error>(shapes[i]);
            dualspectra::search_screened(&partial.mesh, &s.get().inner, scale, shortlist, open, top, p)
        }
        None => dualspectra::search_shortlisted(&partial.mesh, &shapes, top, shortlist, p),
    })?;
    found
        .into_iter()
        .map(|m| {
            let full = fulls[m.index].get();
            let localization = m
                .localization
                .map(|l| Localization::new(py, l, &full.host, full.notes_for(&partial)).and_then(|l| Py::new(py, l)))
                .transpose()?;
            Ok(Match { index: m.index, score: m.score, localization, error: m.error, screen_score: m.screen_score })
        })
        .collect()
}

/// Native `rank`: positions of `(score, index)` pairs in the core's ranking order (lowest
/// similarity score first, ties by index, `inf` last), the `top` best (all when `None`):
/// `dualspectra::search::rank`, for rankings gathered outside `search` (`search_batch`).
#[pyfunction]
#[pyo3(signature = (scored, top=None))]
pub fn rank(scored: Vec<(f64, usize)>, top: Option<usize>) -> Vec<usize> {
    dualspectra::search::rank(&scored, top.unwrap_or(usize::MAX))
}
