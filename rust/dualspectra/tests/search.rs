//! Laws of the search over several full shapes (`search.rs`) on a small generated library:
//! the model the partial was cut from ranks first, ties go to the lower index, a shape the
//! partial cannot be on ranks last, the search can be cancelled, `search_with` (shapes
//! opened one at a time) answers as `search`, and a screened search localizes its shortlist
//! quickly and its best few in full.

use dualspectra::evaluation::synthetic::{figure, horned_limbs, quadruped_limbs, synthetic_pair, SyntheticPair, SyntheticParams};
use dualspectra::lab::selection::similarity_score;
use dualspectra::search::{locate_prepared, rank, search_confidences, PreparedPartial};
use dualspectra::{search, search_screened, search_with, Error, Localizer, Match, Options, Progress, Scale, Screen, ScreenEntry, TriMesh};
use std::borrow::Borrow;
use std::cell::Cell;
use std::sync::OnceLock;

fn light() -> Options {
    Options { k: 6, max_iterations: 10, threads: 2, ..Options::default() }
}

fn pair() -> &'static SyntheticPair {
    static PAIR: OnceLock<SyntheticPair> = OnceLock::new();
    PAIR.get_or_init(|| synthetic_pair(&SyntheticParams { level: 3, ..SyntheticParams::default() }).unwrap())
}

/// Other models: a four-legged figure with a tail, and a figure with one long horn.
fn others() -> Vec<TriMesh> {
    vec![figure(3, &quadruped_limbs()).unwrap(), figure(3, &horned_limbs()).unwrap()]
}

fn library() -> &'static Vec<Localizer> {
    static LIBRARY: OnceLock<Vec<Localizer>> = OnceLock::new();
    LIBRARY.get_or_init(|| {
        let [a, b] = <[TriMesh; 2]>::try_from(others()).unwrap();
        [a, pair().full.clone(), b].iter().map(|m| Localizer::new(m, &light()).unwrap()).collect()
    })
}

#[test]
fn the_model_the_partial_was_cut_from_ranks_first() {
    let shapes: Vec<&Localizer> = library().iter().collect();
    let found = search(&pair().partial, &shapes, 10, &Progress::none()).unwrap();
    let order: Vec<(usize, f64)> = found.iter().map(|m| (m.index, m.score)).collect();
    assert_eq!(found.len(), 3);
    assert_eq!(found[0].index, 1, "ranking {order:?}");
    assert!(found.windows(2).all(|w| w[0].score <= w[1].score), "{order:?}");
    for m in &found {
        let loc = m.localization.as_ref().expect("every shape located");
        assert_eq!(m.score, loc.similarity_score);
        // The score is the best candidate's partial fit: unit-norm descriptors, in [0, sqrt 2].
        let fits: Vec<f64> = loc.candidates.iter().filter_map(|c| c.scores.partial_fit).collect();
        assert!(fits.iter().all(|&f| m.score <= f) && fits.contains(&m.score), "{} against {fits:?}", m.score);
        assert!(m.score.is_finite() && (0.0..=2f64.sqrt()).contains(&m.score));
        assert_eq!(loc.region.len(), shapes[m.index].n_vertices());
    }
    // Unknown (no fit, no candidate): ranks last.
    let mut unknown = found[0].localization.clone().unwrap();
    unknown.candidates.iter_mut().for_each(|c| c.scores.partial_fit = None);
    let scores = |l: &dualspectra::Localization| l.candidates.iter().map(|c| c.scores).collect::<Vec<_>>();
    assert_eq!(similarity_score(&scores(&unknown)), f64::INFINITY);
    unknown.candidates.clear();
    assert_eq!(similarity_score(&scores(&unknown)), f64::INFINITY);
    // The ranking rule on its own (what front ends that gather scores call) gives this order.
    let scored: Vec<(f64, usize)> = found.iter().rev().map(|m| (m.score, m.index)).collect();
    let ranked: Vec<usize> = rank(&scored, 10).into_iter().map(|i| scored[i].1).collect();
    assert_eq!(ranked, found.iter().map(|m| m.index).collect::<Vec<_>>());
    // Progress runs over the shapes, from 0 to 1.
    let seen = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
    let log = seen.clone();
    let progress = Progress::new(move |f, _| {
        log.lock().unwrap().push(f);
        true
    });
    search(&pair().partial, &shapes[..1], 1, &progress).unwrap();
    let seen = seen.lock().unwrap();
    assert!(seen.windows(2).all(|w| w[0] <= w[1] + 1e-12) && seen.last() == Some(&1.0), "{seen:?}");
}

#[test]
fn ties_go_to_the_lower_index_and_top_keeps_the_best() {
    let one = &library()[1];
    let found = search(&pair().partial, &[one, one], 2, &Progress::none()).unwrap();
    assert_eq!(found.iter().map(|m| m.index).collect::<Vec<_>>(), [0, 1]);
    assert_eq!(found[0].score.to_bits(), found[1].score.to_bits(), "the same shape twice, the same score");
    let best = search(&pair().partial, &[one, one], 1, &Progress::none()).unwrap();
    assert_eq!(best.len(), 1);
    assert_eq!(best[0].index, 0);
    assert!(search(&pair().partial, &[], 3, &Progress::none()).unwrap().is_empty());
}

#[test]
fn a_shape_the_partial_cannot_be_on_ranks_last_and_cancelling_stops() {
    // The figure at a tenth of its size: the partial has far more area than it.
    let small = pair().full.map_positions(|p| p.map(|c| 0.1 * c)).unwrap();
    let small = Localizer::new(&small, &light()).unwrap();
    let right = &library()[1];
    let found = search(&pair().partial, &[&small, right], 5, &Progress::none()).unwrap();
    assert_eq!(found.iter().map(|m| m.index).collect::<Vec<_>>(), [1, 0]);
    assert_eq!(found[1].score, f64::INFINITY);
    assert!(found[1].localization.is_none());
    assert!(found[1].error.as_deref().unwrap_or("").contains("cannot be a part of it"), "{:?}", found[1].error);
    // When no shape can take the partial, the first shape's error is returned.
    let err = search(&pair().partial, &[&small], 5, &Progress::none()).unwrap_err();
    assert!(err.to_string().contains("cannot be a part of it"), "{err}");
    let stop = Progress::new(|_, _| false);
    assert!(matches!(search(&pair().partial, &[right], 1, &stop), Err(Error::Cancelled)));
}

/// A shape handed out by `open`, counting how many are alive.
struct Opened<'a> {
    shape: &'a Localizer,
    alive: &'a Cell<usize>,
}

impl Borrow<Localizer> for Opened<'_> {
    fn borrow(&self) -> &Localizer {
        self.shape
    }
}

impl Drop for Opened<'_> {
    fn drop(&mut self) {
        self.alive.set(self.alive.get() - 1);
    }
}

#[test]
fn search_with_opens_one_shape_at_a_time_and_answers_as_search() {
    let shapes: Vec<&Localizer> = library().iter().collect();
    let alive = Cell::new(0);
    let mut opened = Vec::new();
    let open = |i: usize, _: &Progress| {
        assert_eq!(alive.get(), 0, "the previous shape is dropped before the next is opened");
        opened.push(i);
        alive.set(alive.get() + 1);
        Ok::<_, Error>(Opened { shape: shapes[i], alive: &alive })
    };
    let found = search_with(&pair().partial, 3, open, 2, &Progress::none()).unwrap();
    assert_eq!(opened, [0, 1, 2], "each shape opened once, in order");
    assert_eq!(alive.get(), 0);
    let expected = search(&pair().partial, &shapes, 2, &Progress::none()).unwrap();
    let key = |m: &Match| (m.index, m.score.to_bits(), m.localization.as_ref().map(|l| l.region.clone()), m.error.clone());
    assert_eq!(found.iter().map(key).collect::<Vec<_>>(), expected.iter().map(key).collect::<Vec<_>>());
    // An error of `open` stops the search and is returned as is.
    let mut calls = Vec::new();
    let open = |i: usize, _: &Progress| {
        calls.push(i);
        if i == 1 {
            return Err(Error::InvalidArgument("no shape 1".into()));
        }
        Ok(shapes[i])
    };
    let err = search_with(&pair().partial, 3, open, 2, &Progress::none()).unwrap_err();
    assert!(matches!(&err, Error::InvalidArgument(m) if m == "no shape 1"), "{err}");
    assert_eq!(calls, [0, 1]);
}

#[test]
fn rank_orders_by_score_then_index_and_keeps_the_top() {
    let inf = f64::INFINITY;
    let scored = [(0.3, 4), (inf, 0), (0.1, 2), (0.3, 1), (0.2, 3)];
    assert_eq!(rank(&scored, 10), [2, 4, 3, 0, 1], "lowest score first, ties by index, inf last");
    assert_eq!(rank(&scored, 2), [2, 4]);
    assert!(rank(&scored, 0).is_empty() && rank(&[], 3).is_empty());
}

#[test]
fn a_localization_keeps_an_infinite_similarity_through_json() {
    // serde_json writes +inf as null; it reads back as +inf.
    let shapes: Vec<&Localizer> = library().iter().take(1).collect();
    let mut loc = search(&pair().partial, &shapes, 1, &Progress::none()).unwrap().remove(0).localization.unwrap();
    let back: dualspectra::Localization = serde_json::from_str(&serde_json::to_string(&loc).unwrap()).unwrap();
    assert!((back.similarity_score - loc.similarity_score).abs() <= 4.0 * f64::EPSILON * loc.similarity_score, "a number stays one");
    loc.similarity_score = f64::INFINITY;
    let text = serde_json::to_string(&loc).unwrap();
    assert!(text.contains("\"similarity_score\":null"), "{text}");
    let back: dualspectra::Localization = serde_json::from_str(&text).unwrap();
    assert_eq!(back.similarity_score, f64::INFINITY);
}

/// A screened search with a shortlist below the library's size localizes its shortlist
/// quickly and the best of those again in full, with the second (the partial's own figure
/// twice: tied, so close behind); the full ones are exactly
/// `Localizer::locate`'s answers, the quick one is exactly a localization from the descriptor
/// starts (no plane cut), at most 2 iterations and at most 10 eigenvalues, and the shape the
/// screen leaves out
/// follows, not located.
#[test]
fn a_screened_search_localizes_its_shortlist_quickly_and_the_best_again_in_full() {
    let lib = library();
    // Four shapes, the partial's own figure twice: the screen keeps 3, 2 are refined.
    let shapes: Vec<&Localizer> = vec![&lib[0], &lib[1], &lib[2], &lib[1]];
    let [a, b] = <[TriMesh; 2]>::try_from(others()).unwrap();
    let meshes = [&a, &pair().full, &b, &pair().full];
    let entries = meshes.iter().map(|m| ScreenEntry::new(m)).collect::<Result<Vec<_>, _>>().unwrap();
    let screen = Screen::new(&entries).unwrap();
    let mut opened = Vec::new();
    let open = |i: usize, _: &Progress| {
        opened.push(i);
        Ok::<_, Error>(shapes[i])
    };
    let found = search_screened(&pair().partial, &screen, Scale::Same, 3, open, usize::MAX, &Progress::none()).unwrap();
    assert_eq!(found.len(), 4);
    let kinds: Vec<(bool, bool)> = found.iter().map(|m| (m.localization.is_some(), m.quick)).collect();
    assert_eq!(kinds, [(true, false), (true, false), (true, true), (false, false)], "two in full, one quick, one screened out");
    assert_eq!(opened.len(), 3 + 2, "the shortlist opened once each, the two best again");
    assert!(found[0].score <= found[1].score);
    for m in &found[..2] {
        let direct = shapes[m.index].locate(&pair().partial, &Progress::none()).unwrap();
        let loc = m.localization.as_ref().unwrap();
        assert_eq!((loc.region.clone(), m.score.to_bits()), (direct.region, direct.similarity_score.to_bits()));
    }
    let quick = &found[2];
    let quick_options = Options { plane_cuts: 0, max_iterations: light().max_iterations.min(2), k: light().k.min(10), ..light() };
    let prepared = Localizer::new(meshes[quick.index], &quick_options).unwrap();
    let direct = prepared.locate(&pair().partial, &Progress::none()).unwrap();
    let loc = quick.localization.as_ref().unwrap();
    assert_eq!((loc.region.clone(), quick.score.to_bits()), (direct.region, direct.similarity_score.to_bits()));
    let full = shapes[quick.index].locate(&pair().partial, &Progress::none()).unwrap();
    assert!(loc.candidates.len() < full.candidates.len(), "fewer starts: {} against {}", loc.candidates.len(), full.candidates.len());
    assert!(loc.candidates.iter().all(|c| c.label.starts_with("descriptor")), "descriptor starts only");
    let out = &found[3];
    assert!(out.error.is_none() && out.score == f64::INFINITY && out.screen_score >= found[0].screen_score);
    // The search's confidence: each located match's among the located ones.
    let located: Vec<(f64, f64)> = found[..3].iter().map(|m| (m.score, m.localization.as_ref().unwrap().confidence)).collect();
    let expected = search_confidences(&located);
    assert_eq!(found[..3].iter().map(|m| m.confidence.to_bits()).collect::<Vec<_>>(), expected.iter().map(|c| c.to_bits()).collect::<Vec<_>>());
    assert_eq!(out.confidence, 0.0);
    // A shortlist of the whole library localizes every shape in full.
    let every = search_screened(&pair().partial, &screen, Scale::Same, 4, |i, _| Ok::<_, Error>(shapes[i]), usize::MAX, &Progress::none()).unwrap();
    assert!(every.iter().all(|m| m.localization.is_some() && !m.quick));
}

#[test]
fn a_prepared_partial_locates_as_its_mesh_does_on_every_shape() {
    // In other units, with `scale = auto`: the scale scan the first localization makes is
    // reused by the others, and every result is the one the partial's mesh gives afresh.
    let auto = Options { scale: Scale::Auto, ..light() };
    let [a, _] = <[TriMesh; 2]>::try_from(others()).unwrap();
    let shapes = [Localizer::new(&pair().full, &auto).unwrap(), Localizer::new(&a, &auto).unwrap()];
    let partial = pair().partial.map_positions(|p| p.map(|c| 1000.0 * c)).unwrap();
    let prepared = PreparedPartial::new(partial.clone());
    assert_eq!(prepared.mesh(), &partial);
    for quick in [true, false] {
        for shape in &shapes {
            let shared = locate_prepared(shape, &prepared, quick, &Progress::none()).unwrap();
            let fresh = locate_prepared(shape, &PreparedPartial::new(partial.clone()), quick, &Progress::none()).unwrap();
            assert_eq!(shared.region, fresh.region);
            assert_eq!((shared.similarity_score.to_bits(), shared.scale.to_bits()), (fresh.similarity_score.to_bits(), fresh.scale.to_bits()));
            if !quick {
                let direct = shape.locate(&partial, &Progress::none()).unwrap();
                assert_eq!((direct.region, direct.cost.to_bits()), (shared.region.clone(), shared.cost.to_bits()));
            }
        }
    }
    let quick = locate_prepared(&shapes[0], &prepared, true, &Progress::none()).unwrap();
    let full = locate_prepared(&shapes[0], &prepared, false, &Progress::none()).unwrap();
    assert!(quick.candidates.len() < full.candidates.len(), "quick: fewer starts");
    assert!((full.scale / 1e-3 - 1.0).abs() < 0.25, "sized back: {}", full.scale);
}

/// [`search_confidences`] of a shape of score `score` and localization confidence `p` among
/// others of scores `others` (localization confidence 0.5).
fn confidence_among(score: f64, p: f64, others: &[f64]) -> f64 {
    let located: Vec<(f64, f64)> = std::iter::once((score, p)).chain(others.iter().map(|&s| (s, 0.5))).collect();
    search_confidences(&located)[0]
}

#[test]
fn the_search_confidence_falls_behind_the_best_other_score_and_rises_with_the_fit() {
    let others = [0.40, 0.50, 0.52, 0.55];
    let c = confidence_among(0.45, 0.8, &others);
    assert!((0.0..=1.0).contains(&c));
    // Further behind the best other shape: less trusted; ahead of it: more, up to a lead of 0.05.
    assert!(confidence_among(0.48, 0.8, &others) < c);
    assert!(confidence_among(0.40, 0.8, &others) > c);
    assert!(confidence_among(0.38, 0.8, &others) > confidence_among(0.40, 0.8, &others));
    assert_eq!(confidence_among(0.30, 0.8, &others), confidence_among(0.35, 0.8, &others));
    // The gap is relative to the search's spread of scores (the median less the lowest), and
    // counts at most 3 spreads; a model far off does not change the others' confidences.
    assert_eq!(confidence_among(0.9, 0.8, &others).to_bits(), confidence_among(0.8, 0.8, &others).to_bits());
    let with_far = |far: f64| search_confidences(&[(0.40, 0.8), (0.42, 0.7), (0.45, 0.9), (0.47, 0.6), (far, 0.1)]);
    assert_eq!(with_far(5.0)[..4], with_far(9.0)[..4]);
    assert!(with_far(5.0)[1] > with_far(5.0)[3], "closer behind the best: more trusted");
    // A better-fitting localization: more trusted.
    assert!(confidence_among(0.45, 0.95, &others) > c && confidence_among(0.45, 0.2, &others) < c);
    // A lone shape: its localization's confidence; nothing located: nothing.
    assert_eq!(search_confidences(&[(0.41, 0.8)]), [0.8]);
    assert!(search_confidences(&[]).is_empty());
    // Unknown or degenerate inputs: a probability all the same, never NaN; an unknown score is
    // the furthest behind.
    for (score, p, others) in [(f64::INFINITY, 0.9, vec![0.4]), (f64::NAN, 0.9, vec![0.4]), (0.4, 0.9, vec![f64::NAN]), (0.4, f64::NAN, vec![0.4]), (0.4, 0.0, vec![0.4]), (0.4, 1.0, vec![0.4, 0.4]), (0.4, 7.0, vec![f64::INFINITY])] {
        let v = confidence_among(score, p, &others);
        assert!((0.0..=1.0).contains(&v), "{score} {p} {others:?}: {v}");
    }
    assert!(confidence_among(f64::INFINITY, 0.8, &others) <= confidence_among(0.50, 0.8, &others));
}

#[test]
fn a_search_fills_in_each_located_shape_confidence_among_all_located() {
    let shapes: Vec<&Localizer> = library().iter().collect();
    let found = search(&pair().partial, &shapes, 10, &Progress::none()).unwrap();
    let located: Vec<(f64, f64)> = found.iter().map(|m| (m.score, m.localization.as_ref().unwrap().confidence)).collect();
    let expected = search_confidences(&located);
    for (m, c) in found.iter().zip(&expected) {
        assert_eq!(m.confidence.to_bits(), c.to_bits());
    }
    // `top` keeps the best, its confidence weighed against every shape located all the same.
    let best = search(&pair().partial, &shapes, 1, &Progress::none()).unwrap();
    assert_eq!(best.len(), 1);
    assert_eq!(best[0].confidence.to_bits(), found[0].confidence.to_bits());
    // One shape: nothing to weigh against, the localization's confidence.
    let alone = search(&pair().partial, &shapes[1..2], 1, &Progress::none()).unwrap();
    assert_eq!(alone[0].confidence, alone[0].localization.as_ref().unwrap().confidence);
}
