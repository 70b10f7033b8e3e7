//! Partial shape similarity: which of several full shapes is a partial a part of, and where
//! (docs/algorithm.md, "Searching several full shapes").
//!
//! The partial is located on every prepared full shape ([`Localizer::locate`]), and each
//! localization is scored by [`similarity_score_of`], lower is more similar. Both shapes of
//! every pair are scaled so that the full shape has unit area, and the score is built from
//! dimensionless quantities, so scores of full shapes of different size and meshing are
//! compared directly; the ranking by score is the answer, best first.

use crate::error::{Error, Result};
use crate::localizer::{Localization, Localizer};
use crate::mesh::TriMesh;
use crate::progress::Progress;
use serde::{Deserialize, Serialize};
use std::borrow::Borrow;

/// One full shape's answer for a partial.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Match {
    /// Index of the full shape searched (in the slice, or as given to `open`).
    pub index: usize,
    /// [`similarity_score_of`] the localization; lower is more similar; `+inf` when the
    /// partial could not be located on this shape.
    pub score: f64,
    /// The localization on this shape (`None` when it failed: see `error`).
    pub localization: Option<Localization>,
    /// Why the partial could not be located on this shape (e.g. it is larger than it).
    pub error: Option<String>,
}

/// The similarity score of a localization, lower is more similar: the best *partial fit*
/// among its candidate regions $R$ (one per optimised start),
/// $$s = \min_R p(R), \qquad p(R) = \frac{1}{|J|}\sum_{j \in J}\ \min_{i \in R} \lVert D_N(j) - D_M(i) \rVert,$$
/// the mean distance from the partial's SHOT descriptors $D_N(j)$ (a sample $J$ of at most
/// 1000 of its vertices) to the nearest descriptor $D_M(i)$ of the optimisation vertices in
/// $R$ ([`crate::selection::partial_fits`]; docs/algorithm.md, "Searching several full
/// shapes"). It asks whether some region the spectra led to holds every local shape of the
/// partial. SHOT descriptors have unit norm and both shapes are scaled to unit full-shape
/// area, so $s \in [0, \sqrt 2]$ compares across full shapes of any size and meshing (at the
/// same `resolution`). It ranked best among the scores measured (the chosen region's fit,
/// spectral misfits, the descriptor projection, the confidence, combinations):
/// docs/benchmarks/search-2026-12-02.md. `+inf` when no candidate has a fit (empty regions).
pub fn similarity_score_of(localization: &Localization) -> f64 {
    localization
        .candidates
        .iter()
        .filter_map(|c| c.scores.partial_fit)
        .filter(|fit| fit.is_finite())
        .fold(f64::INFINITY, f64::min)
        .max(0.0)
}

/// Locate `partial` on every shape of `fulls` and rank them: the `top` best [`Match`]es
/// (all of them when `top >= fulls.len()`), best (lowest score) first, ties broken by index.
/// A shape the partial cannot be located on ranks last with its `error`; if that is every
/// shape, the first shape's error is returned. Progress is split evenly over the shapes;
/// cancelling returns [`Error::Cancelled`]. Only the `top` best localizations are kept in
/// memory while searching. [`search_with`] with the shapes already open.
pub fn search(partial: &TriMesh, fulls: &[&Localizer], top: usize, progress: &Progress) -> Result<Vec<Match>> {
    search_with(partial, fulls.len(), |i, _| Ok::<_, Error>(fulls[i]), top, progress)
}

/// [`search`] over `n` shapes opened one at a time: shape `i` is `open(i, progress)`, called
/// in order just before locating on it and dropped right after, so memory holds one prepared
/// shape plus the `top` kept localizations. An error of `open` stops the search and is
/// returned as is. Each shape's progress span gives its first 10 % to `open`.
pub fn search_with<L, E>(
    partial: &TriMesh,
    n: usize,
    mut open: impl FnMut(usize, &Progress) -> std::result::Result<L, E>,
    top: usize,
    progress: &Progress,
) -> std::result::Result<Vec<Match>, E>
where
    L: Borrow<Localizer>,
    E: From<Error>,
{
    let mut kept: Vec<Match> = Vec::new();
    let mut first_error = None;
    let mut failures = 0;
    for index in 0..n {
        let part = progress.sub(index as f64 / n as f64, (index + 1) as f64 / n as f64);
        part.report(0.0, "searching")?;
        let located = {
            let shape = open(index, &part.sub(0.0, 0.1))?;
            shape.borrow().locate(partial, &part.sub(0.1, 1.0))
        };
        let m = match located {
            Ok(localization) => Match { index, score: similarity_score_of(&localization), localization: Some(localization), error: None },
            Err(Error::Cancelled) => return Err(Error::Cancelled.into()),
            Err(e) => {
                failures += 1;
                let m = Match { index, score: f64::INFINITY, localization: None, error: Some(e.to_string()) };
                first_error.get_or_insert(e);
                m
            }
        };
        kept.push(m);
        kept.sort_by(|a, b| a.score.total_cmp(&b.score).then(a.index.cmp(&b.index)));
        kept.truncate(top);
    }
    if failures == n {
        if let Some(e) = first_error {
            return Err(e.into());
        }
    }
    progress.report(1.0, "searched")?;
    Ok(kept)
}
