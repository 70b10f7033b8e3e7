//! Partial shape similarity: which of several full shapes is a partial a part of, and where
//! (docs/algorithm.md, "Searching several full shapes").
//!
//! The partial is located on every prepared full shape ([`Localizer::locate`]), and each
//! localization's [`Localization::similarity_score`]
//! ([`crate::selection::similarity_score`]) ranks it, lower is more similar. Both shapes of
//! every pair are scaled so that the full shape has unit area, and the score is built from
//! dimensionless quantities, so scores of full shapes of different size and meshing are
//! compared directly; the ranking by score is the answer, best first. Each located shape's
//! [`Match::confidence`] weighs its localization's confidence by how its score compares with
//! the best other shape's ([`search_confidences`]).

mod screen;

pub use screen::{Screen, ScreenEntry, SCREEN_EXTENSION};

use crate::error::{Error, Result};
use crate::localizer::{Effort, Localization, Localizer, SharedPartial};
use crate::mesh::TriMesh;
use crate::progress::Progress;
use serde::{Deserialize, Serialize};
use std::borrow::Borrow;

/// One full shape's answer for a partial.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[non_exhaustive]
pub struct Match {
    /// Index of the full shape searched (in the slice, or as given to `open`).
    pub index: usize,
    /// The localization's [`Localization::similarity_score`]; lower is more similar; `+inf`
    /// when the partial could not be located on this shape.
    pub score: f64,
    /// The localization on this shape (`None` when it failed: see `error`).
    pub localization: Option<Localization>,
    /// Why the partial could not be located on this shape (e.g. it is larger than it).
    pub error: Option<String>,
    /// The screen's score of this shape ([`Screen::rank`]; lower is more similar) when the
    /// search was screened ([`search_screened`]); a shape screened out has no localization
    /// and no error.
    #[serde(default)]
    pub screen_score: Option<f64>,
    /// Whether `localization` is a screened search's quick one (fewer starts, iterations and eigenvalues, on the regular optimisation mesh even for a partial with holes,
    /// ranking the shortlist) rather than a full localization with the localizer's options
    /// ([`search_screened`]).
    #[serde(default)]
    pub quick: bool,
    /// How much to trust that the partial is a part of this shape rather than of another one
    /// searched, in [0, 1] ([`search_confidences`]: how far its score is behind, or ahead of,
    /// the best other shape's, and the localization's own confidence); 0 when the shape was not
    /// located. What to threshold to reject a match.
    #[serde(default)]
    pub confidence: f64,
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
    open: impl FnMut(usize, &Progress) -> std::result::Result<L, E>,
    top: usize,
    progress: &Progress,
) -> std::result::Result<Vec<Match>, E>
where
    L: Borrow<Localizer>,
    E: From<Error>,
{
    let indices: Vec<usize> = (0..n).collect();
    let Pass { mut kept, first_error, located } = locate_each(&SharedPartial::new(partial), &indices, open, None, top, progress)?;
    every_shape_failed(&kept, first_error)?;
    // Each kept shape's confidence among every located one, kept or not.
    set_search_confidences(&mut kept, &located);
    progress.report(1.0, "searched")?;
    Ok(kept)
}

/// Shortlisted shapes localized in full after the quick ranking of the shortlist, at most:
/// those the quick localizations rank best (docs/benchmarks/options.md, "Two-stage search").
pub(crate) const REFINED_SHAPES: usize = 2;

/// A shape after the quick ranking's best is localized in full only when its quick score is
/// within this fraction of the best's: on the dev queries a full localization overtook the
/// quick best from at most 2.6 % behind (docs/benchmarks/options.md, "Two-stage search").
pub(crate) const REFINED_WITHIN: f64 = 0.04;

/// The quick localizations that rank a shortlist: the two descriptor starts (the first 2
/// plane-cut starts of the default 6 only where there is no descriptor start), 2
/// trust-region iterations (of the default 8) and 10 eigenvalues per spectrum (of the
/// default 20), each at most the localizer's own, and a partial with holes on the regular
/// optimisation mesh, not the finer one (docs/benchmarks/options.md, "Two-stage search").
pub(crate) const RANKING_EFFORT: Effort = Effort { max_iterations: 2, plane_cuts: 2, k: 10, finer_mesh: false, plane_cuts_beside_descriptors: false };

/// Time of a quick ranking localization over a full one, for splitting progress.
const RANKING_COST: f64 = 0.3;

/// Locate `partial` on the shapes `indices` (each opened by `open(index, progress)` just
/// before and dropped right after), with `effort` (`None`: the localizer's options; a quick
/// localization's [`Match::quick`] is set): the `top` best [`Match`]es in ranking order and
/// what else the pass found ([`Pass`]).
fn locate_each<L, E>(
    partial: &SharedPartial<'_>,
    indices: &[usize],
    mut open: impl FnMut(usize, &Progress) -> std::result::Result<L, E>,
    effort: Option<Effort>,
    top: usize,
    progress: &Progress,
) -> std::result::Result<Pass, E>
where
    L: Borrow<Localizer>,
    E: From<Error>,
{
    let n = indices.len();
    let mut kept: Vec<Match> = Vec::new();
    let mut located = Vec::new();
    let mut first_error = None;
    for (position, &index) in indices.iter().enumerate() {
        let part = progress.sub(position as f64 / n as f64, (position + 1) as f64 / n as f64);
        part.report(0.0, "searching")?;
        let outcome = {
            let shape = open(index, &part.sub(0.0, 0.1))?;
            let shape = shape.borrow();
            match effort {
                Some(effort) => shape.locate_shared(partial, effort, &part.sub(0.1, 1.0)),
                None => shape.locate_shared(partial, Effort::of(shape.options()), &part.sub(0.1, 1.0)),
            }
        };
        let m = match outcome {
            Ok(localization) => Match {
                index,
                score: localization.similarity_score,
                localization: Some(localization),
                error: None,
                screen_score: None,
                quick: effort.is_some(),
                confidence: 0.0,
            },
            Err(Error::Cancelled) => return Err(Error::Cancelled.into()),
            Err(e) => {
                let m = Match { index, score: f64::INFINITY, localization: None, error: Some(e.to_string()), screen_score: None, quick: false, confidence: 0.0 };
                first_error.get_or_insert(e);
                m
            }
        };
        if let Some(l) = &m.localization {
            located.push((index, m.score, l.confidence));
        }
        kept.push(m);
        kept.sort_by(|a, b| ranking_order((a.score, a.index), (b.score, b.index)));
        kept.truncate(top);
    }
    Ok(Pass { kept, first_error, located })
}

/// What [`locate_each`] found: the kept [`Match`]es in ranking order, the first error of a
/// shape the partial could not be located on, and the index, score and localization
/// confidence of every shape located.
struct Pass {
    kept: Vec<Match>,
    first_error: Option<Error>,
    located: Vec<(usize, f64, f64)>,
}

/// The first error when no shape of `found` was located.
fn every_shape_failed<E: From<Error>>(found: &[Match], first_error: Option<Error>) -> std::result::Result<(), E> {
    match first_error {
        Some(e) if found.iter().all(|m| m.localization.is_none()) => Err(e.into()),
        _ => Ok(()),
    }
}

/// A search after a screen: the `n = screen.len()` shapes are scored by `screen`
/// ([`Screen::rank`], with the partial's `scale`) and only the `shortlist` best are opened
/// (`open(i, progress)`, `i` the shape's index in the screen) and localized, in two stages:
/// each shortlisted shape is localized quickly (fewer starts, iterations and eigenvalues, on
/// the regular optimisation mesh even for a partial with holes: the [`Match::quick`] ones),
/// then the best of those again in full, as by [`Localizer::locate`], and the second best too
/// when it is close behind ([`shapes_to_refine`]). The answer ranks the fully localized shapes by similarity score,
/// then the quick ones, then the others in screen order (screened out: no localization, no
/// error, score `+inf`), each with its [`Match::screen_score`]; the `top` best are returned.
/// With `shortlist >= n` every shape is localized in full (the exhaustive search), as by
/// [`search_with`]. The screen takes the first 5 % of `progress`.
pub fn search_screened<L, E>(
    partial: &TriMesh,
    screen: &Screen,
    scale: crate::localizer::Scale,
    shortlist: usize,
    mut open: impl FnMut(usize, &Progress) -> std::result::Result<L, E>,
    top: usize,
    progress: &Progress,
) -> std::result::Result<Vec<Match>, E>
where
    L: Borrow<Localizer>,
    E: From<Error>,
{
    if shortlist == 0 {
        return Err(Error::InvalidArgument("search: the shortlist must hold at least one shape".into()).into());
    }
    let screened = screen.rank(partial, scale, &progress.sub(0.0, 0.05))?;
    let chosen: Vec<usize> = screened.iter().take(shortlist).map(|r| r.0).collect();
    let shared = SharedPartial::new(partial);
    let mut found = if in_two_stages(chosen.len(), screened.len()) {
        let ranking_share = RANKING_COST * chosen.len() as f64;
        let split = 0.05 + 0.95 * ranking_share / (ranking_share + REFINED_SHAPES as f64);
        let Pass { kept: quick, first_error, .. } = locate_each(&shared, &chosen, &mut open, Some(RANKING_EFFORT), usize::MAX, &progress.sub(0.05, split))?;
        every_shape_failed(&quick, first_error)?;
        let best = shapes_to_refine(&scored(&quick));
        let Pass { kept: full, .. } = locate_each(&shared, &best, &mut open, None, usize::MAX, &progress.sub(split, 1.0))?;
        let order = two_stage_order(&scored(&full), &scored(&quick));
        let (mut full, mut quick): (Vec<Option<Match>>, Vec<Option<Match>>) = (full.into_iter().map(Some).collect(), quick.into_iter().map(Some).collect());
        order.into_iter().filter_map(|(is_quick, at)| if is_quick { quick[at].take() } else { full[at].take() }).collect()
    } else {
        let Pass { kept: found, first_error, .. } = locate_each(&shared, &chosen, &mut open, None, usize::MAX, &progress.sub(0.05, 1.0))?;
        every_shape_failed(&found, first_error)?;
        found
    };
    let located: Vec<(usize, f64, f64)> = found.iter().filter_map(|m| m.localization.as_ref().map(|l| (m.index, m.score, l.confidence))).collect();
    set_search_confidences(&mut found, &located);
    let screen_score = |index: usize| screened.iter().find(|r| r.0 == index).map(|r| r.1);
    for m in &mut found {
        m.screen_score = screen_score(m.index);
    }
    found.extend(screened.iter().skip(shortlist).map(|&(index, s)| Match {
        index,
        score: f64::INFINITY,
        localization: None,
        error: None,
        screen_score: Some(s),
        quick: false,
        confidence: 0.0,
    }));
    found.truncate(top);
    progress.report(1.0, "searched")?;
    Ok(found)
}

/// `(score, index)` of each match, `+inf` for a shape not located (the input of
/// [`shapes_to_refine`] and [`two_stage_order`]).
fn scored(matches: &[Match]) -> Vec<(f64, usize)> {
    matches.iter().map(|m| (if m.localization.is_some() { m.score } else { f64::INFINITY }, m.index)).collect()
}

/// Whether a screened search localizes its `shortlist` shapes (of `library`) in two stages
/// ([`search_screened`]): a shortlist shorter than the library and longer than the
/// [`REFINED_SHAPES`] localized again in full; otherwise each is localized once, in full.
pub fn in_two_stages(shortlist: usize, library: usize) -> bool {
    shortlist > REFINED_SHAPES && shortlist < library
}

/// A partial shape prepared to be located on several full shapes, for front ends that run a
/// search's localizations themselves (a batch of searches split per full shape): what every
/// one of them needs of the partial alone (with `scale = auto`, its descriptors under each
/// area hypothesis of the scale estimate) is computed by the first that needs it and kept, as
/// a search keeps it for its own localizations.
pub struct PreparedPartial(SharedPartial<'static>);

impl PreparedPartial {
    /// `partial`, nothing computed yet.
    pub fn new(partial: TriMesh) -> Self {
        PreparedPartial(SharedPartial::owning(partial))
    }

    /// The partial as given.
    pub fn mesh(&self) -> &TriMesh {
        self.0.mesh()
    }
}

impl std::fmt::Debug for PreparedPartial {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PreparedPartial").field("vertices", &self.mesh().n_vertices()).finish_non_exhaustive()
    }
}

/// `partial` located on `shape` as a search locates it: with `quick`, the two-stage search's
/// quick localization that ranks the shortlist ([`Match::quick`]: fewer starts, iterations and
/// eigenvalues than the localizer's options), otherwise [`Localizer::locate`]'s. The same
/// result as locating the partial's mesh afresh.
pub fn locate_prepared(shape: &Localizer, partial: &PreparedPartial, quick: bool, progress: &Progress) -> Result<Localization> {
    let effort = if quick { RANKING_EFFORT } else { Effort::of(shape.options()) };
    shape.locate_shared(&partial.0, effort, progress)
}

/// The full shapes a two-stage search localizes again in full, from the quick ranking's
/// `(similarity score, full shape index)` pairs (`+inf`: not located): the indices of the
/// [`REFINED_SHAPES`] best, in ranking order, those not located left out, and after the
/// best only those whose score $s$ is within [`REFINED_WITHIN`] of the best's $s_1$
/// ($s \le s_1 + 0.04\,|s_1|$).
pub fn shapes_to_refine(quick: &[(f64, usize)]) -> Vec<usize> {
    let best = rank(quick, REFINED_SHAPES);
    let Some(&first) = best.first() else { return Vec::new() };
    let lowest = quick[first].0;
    best.into_iter().filter(|&i| quick[i].0.is_finite() && quick[i].0 <= lowest + REFINED_WITHIN * lowest.abs()).map(|i| quick[i].1).collect()
}

/// The answer's order of a two-stage search from its full and quick localizations'
/// `(similarity score, full shape index)` pairs (`+inf`: not located): the shapes located in
/// full by score, then the quick ones in their ranking order, less those located in full (a
/// shape whose full localization failed keeps its quick one). Each entry is `(quick,
/// position)`: a position in `quick` or in `full`.
pub fn two_stage_order(full: &[(f64, usize)], quick: &[(f64, usize)]) -> Vec<(bool, usize)> {
    let located: Vec<usize> = rank(full, usize::MAX).into_iter().filter(|&i| full[i].0.is_finite()).collect();
    let refined: Vec<usize> = located.iter().map(|&i| full[i].1).collect();
    let rest = rank(quick, usize::MAX).into_iter().filter(|&i| !refined.contains(&quick[i].1));
    located.into_iter().map(|i| (false, i)).chain(rest.map(|i| (true, i))).collect()
}

/// [`search`] with a shortlist: with `shortlist` below `fulls.len()`, a screen of the shapes'
/// full meshes (with the first shape's `scale` option) ranks them and only the `shortlist`
/// best are localized ([`search_screened`]); otherwise every shape is, as by [`search`].
pub fn search_shortlisted(partial: &TriMesh, fulls: &[&Localizer], top: usize, shortlist: usize, progress: &Progress) -> Result<Vec<Match>> {
    if shortlist >= fulls.len() {
        return search(partial, fulls, top, progress);
    }
    let entries = fulls.iter().map(|f| ScreenEntry::new(&f.full_mesh())).collect::<Result<Vec<_>>>()?;
    let screen = Screen::new(&entries)?;
    search_screened(partial, &screen, fulls[0].options().scale, shortlist, |i, _| Ok::<_, Error>(fulls[i]), top, progress)
}

/// Weights of [`search_confidences`]: bias, the relative gap behind the best other shape, the
/// lead over it (in units of 0.01), and the logit of the localization's confidence. A
/// logistic regression of "the right class" over the 2,798 located models of the 280 dev
/// library queries (docs/benchmarks/confidence/fit_search_confidence.py;
/// docs/benchmarks/options.md, "Confidence across models").
const SEARCH_CONFIDENCE_WEIGHTS: [f64; 4] = [1.403, -1.54, 0.6927, 0.1257];

/// Relative gaps above this count as this in [`search_confidences`].
const SEARCH_CONFIDENCE_MAX_GAP: f64 = 3.0;

/// Leads over the best other shape above this count as this in [`search_confidences`] (a lead
/// of 0.05 is already decisive).
const SEARCH_CONFIDENCE_MAX_LEAD: f64 = 0.05;

/// Localization confidences are clamped to `[c, 1 - c]` before their logit is taken.
const SEARCH_CONFIDENCE_CLAMP: f64 = 1e-6;

/// How much to trust, for each shape of a search, that the partial is a part of it rather
/// than of another one searched, in [0, 1], from `located`: the similarity score and the
/// localization's own [`Localization::confidence`] $p$ of every shape the partial was located
/// on. For a shape of score $s$, with $s_o$ the lowest score of the others and $S$ the median
/// of all the scores less the lowest, $\sigma(b + a\,g + d\,l/0.01 + c\,\mathrm{logit}(p))$ of its
/// relative gap $g = \min(\max(s - s_o, 0)/S, 3)$ behind the best other shape (how many
/// typical spreads of this search it is behind: a model far off does not change the
/// others'), its lead $l = \min(\max(s_o - s, 0), 0.05)$ over it, and $p$ (clamped to $[10^{-6}, 1 - 10^{-6}]$).
/// A localization's confidence alone says whether the region fits; a wrong model often fits a
/// part well too, and what tells it apart is that another model fits about as well or better.
/// A lone shape keeps its localization's confidence (there is nothing to weigh it against); a
/// score that is not finite counts as the furthest behind. What a search fills in as
/// [`Match::confidence`]; for front ends that gather a search's localizations themselves (a
/// batch split per full shape).
pub fn search_confidences(located: &[(f64, f64)]) -> Vec<f64> {
    let [b, a_gap, a_lead, a_conf] = SEARCH_CONFIDENCE_WEIGHTS;
    let mut finite: Vec<f64> = located.iter().map(|&(s, _)| s).filter(|s| s.is_finite()).collect();
    finite.sort_by(f64::total_cmp);
    let spread = match finite.first() {
        Some(lowest) => finite[finite.len() / 2] - lowest,
        None => 0.0,
    };
    // The lowest finite score (at its first position) and the lowest of the others: the best
    // other score of every shape.
    let lowest = finite.first().copied().unwrap_or(f64::INFINITY);
    let second_lowest = finite.get(1).copied().unwrap_or(f64::INFINITY);
    let lowest_at = located.iter().position(|&(s, _)| s == lowest);
    located
        .iter()
        .enumerate()
        .map(|(i, &(score, p))| {
            let p = if p.is_nan() { 0.0 } else { p.clamp(0.0, 1.0) };
            if located.len() < 2 {
                return p;
            }
            let best_other = if Some(i) == lowest_at { second_lowest } else { lowest };
            let (gap, lead) = if !score.is_finite() {
                (SEARCH_CONFIDENCE_MAX_GAP, 0.0)
            } else if !best_other.is_finite() {
                (0.0, SEARCH_CONFIDENCE_MAX_LEAD)
            } else if score > best_other {
                let gap = score - best_other;
                (if spread > 0.0 { (gap / spread).min(SEARCH_CONFIDENCE_MAX_GAP) } else { SEARCH_CONFIDENCE_MAX_GAP }, 0.0)
            } else {
                (0.0, (best_other - score).min(SEARCH_CONFIDENCE_MAX_LEAD))
            };
            let p = p.clamp(SEARCH_CONFIDENCE_CLAMP, 1.0 - SEARCH_CONFIDENCE_CLAMP);
            let z = b + a_gap * gap + a_lead * lead / 0.01 + a_conf * (p / (1.0 - p)).ln();
            1.0 / (1.0 + (-z).exp())
        })
        .collect()
}

/// Each match's [`Match::confidence`] among `located`, the index, score and localization
/// confidence of every shape located in the search ([`search_confidences`]); 0 for a match
/// not among them.
fn set_search_confidences(found: &mut [Match], located: &[(usize, f64, f64)]) {
    let confidences = search_confidences(&located.iter().map(|&(_, s, c)| (s, c)).collect::<Vec<_>>());
    for m in found.iter_mut() {
        m.confidence = located.iter().zip(&confidences).find(|((i, _, _), _)| *i == m.index).map_or(0.0, |(_, &c)| c);
    }
}

/// The order of a ranking of `(similarity score, full shape index)`: lowest score (most
/// similar) first, ties by index; `+inf` (a shape not located) last ([`f64::total_cmp`]).
fn ranking_order(a: (f64, usize), b: (f64, usize)) -> std::cmp::Ordering {
    a.0.total_cmp(&b.0).then(a.1.cmp(&b.1))
}

/// Positions of `(similarity score, full shape index)` pairs in [`search`]'s ranking order
/// (lowest score first, ties by index, `+inf` last), the `top` best (all when `top` is at
/// least their number): for front ends that gather the scores themselves (a batch of
/// searches split per full shape).
pub fn rank(scored: &[(f64, usize)], top: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..scored.len()).collect();
    order.sort_by(|&a, &b| ranking_order(scored[a], scored[b]));
    order.truncate(top);
    order
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_stages_only_for_a_shortlist_between_the_refined_shapes_and_the_library() {
        assert!(!in_two_stages(REFINED_SHAPES, 10));
        assert!(in_two_stages(REFINED_SHAPES + 1, 10));
        assert!(!in_two_stages(10, 10));
    }

    #[test]
    fn the_best_located_quick_shapes_are_refined() {
        // Ranking order by score, ties by index; a shape not located is never refined.
        let quick = [(0.5, 7), (0.2, 3), (f64::INFINITY, 1), (0.2, 9), (0.9, 4)];
        assert_eq!(shapes_to_refine(&quick), vec![3, 9]);
        assert_eq!(shapes_to_refine(&[(f64::INFINITY, 0), (0.4, 2)]), vec![2]);
        assert!(shapes_to_refine(&[(f64::INFINITY, 0)]).is_empty());
        assert!(shapes_to_refine(&[]).is_empty());
    }

    #[test]
    fn a_second_shape_is_refined_only_close_behind_the_first() {
        let within = 0.4 * (1.0 + REFINED_WITHIN) - 1e-12;
        assert_eq!(shapes_to_refine(&[(0.4, 0), (within, 1), (0.5, 2)]), vec![0, 1]);
        let behind = 0.4 * (1.0 + REFINED_WITHIN) + 1e-12;
        assert_eq!(shapes_to_refine(&[(0.4, 0), (behind, 1), (0.5, 2)]), vec![0]);
        // A perfect fit first: only its ties follow it.
        assert_eq!(shapes_to_refine(&[(0.0, 5), (1e-9, 6)]), vec![5]);
        assert_eq!(shapes_to_refine(&[(0.0, 5), (0.0, 6)]), vec![5, 6]);
    }

    #[test]
    fn the_full_localizations_come_first_then_the_quick_ones_not_refined() {
        let quick = [(0.5, 7), (0.2, 3), (f64::INFINITY, 1), (0.3, 9)];
        // 3 was refined to a worse score than 9's; 9's full localization failed.
        let full = [(f64::INFINITY, 9), (0.6, 3)];
        let order = two_stage_order(&full, &quick);
        let indices: Vec<usize> = order.iter().map(|&(q, at)| if q { quick[at].1 } else { full[at].1 }).collect();
        assert_eq!(indices, vec![3, 9, 7, 1]);
        assert_eq!(order[0], (false, 1));
        assert!(order[1..].iter().all(|&(q, _)| q), "9 keeps its quick localization");
    }
}
