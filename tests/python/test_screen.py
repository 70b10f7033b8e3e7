"""Issue 37: a library search that does not localize every model, from Python: ``Screen``
built from meshes, prepared shapes and ``.dsprep`` paths, saved and loaded, passed to
``search(..., screen=)``, ``search(..., shortlist=)`` over meshes (only the shortlisted ones
prepared), and ``search_batch(..., shortlist=)``.

The library is test_search.py's: three figures of the Rust core's ``evaluation::synthetic``
kind (a four-legged one, the default one, a horned one), with a torus beside them; the
partials are cut from a posed copy of the default figure (index 1), so the right model is
known.
"""

from __future__ import annotations

import pickle
import warnings
from pathlib import Path
from typing import Any, Dict, List, Tuple

import numpy as np
import pytest
from conftest import assert_damaged_files_refused, bend, cut, figure, torus

import dualspectra as ds
from dualspectra.batch import BatchMatch, search_batch

LIGHT: Dict[str, Any] = dict(k=6, plane_cuts=2, max_iterations=8, resolution=0)

Mesh = Tuple[np.ndarray, np.ndarray]

OWN = 1
"""Index of the shape the partials are cut from."""


@pytest.fixture(scope="module")
def library() -> List[Mesh]:
    return [figure(3, "quadruped"), figure(3, "figure"), figure(3, "horned"), torus()]


def cut_posed(full: Mesh, normal: Tuple[float, float, float], offset: float) -> Mesh:
    v, f = full
    posed = bend(v)
    pv, pf, _ = cut(posed, f, posed @ (np.asarray(normal) / np.linalg.norm(normal)) > offset)
    return pv, pf


@pytest.fixture(scope="module")
def partials(library: List[Mesh]) -> List[Mesh]:
    """The long arm and shoulder (bent), and the lower body with the legs."""
    return [cut_posed(library[OWN], (1.0, 0.0, 0.2), 0.3), cut_posed(library[OWN], (0.0, 0.1, -1.0), 0.2)]


@pytest.fixture(scope="module")
def screen(library: List[Mesh]) -> ds.Screen:
    return ds.Screen(library, labels=["quadruped", "figure", "horned", "torus"])


def check_ranking(ranking: List[Tuple[int, float]], n: int) -> None:
    """Every shape once, scores ascending (``inf`` last; ties are broken by the distance
    the scores are positions by)."""
    assert sorted(i for i, _ in ranking) == list(range(n)), ranking
    assert all(a[1] <= b[1] for a, b in zip(ranking, ranking[1:])), ranking


def test_a_partial_ranks_its_own_shape_first(screen: ds.Screen, library: List[Mesh], partials: List[Mesh]) -> None:
    assert len(screen) == len(library) and screen.labels == ("quadruped", "figure", "horned", "torus")
    per_shape, basis = screen.nbytes
    assert per_shape > 0 and basis > 0
    assert repr(screen) == f"Screen(shapes={len(library)}, bytes={len(library) * per_shape + basis})"
    for p in partials:
        ranking = screen.rank(*p)
        print(f"[agreement] screen: ranking (index, score) {[(i, round(s, 4)) for i, s in ranking]}")
        check_ranking(ranking, len(library))
        assert ranking[0][0] == OWN and np.isfinite(ranking[0][1]), ranking


def test_scale_laws(screen: ds.Screen, partials: List[Mesh]) -> None:
    v, f = partials[0]
    same = screen.rank(v, f, "same")
    # Coordinates halved and a factor of 2: the partial the screen sees is the same one.
    doubled = screen.rank(v * 0.5, f, 2.0)
    assert [i for i, _ in doubled] == [i for i, _ in same]
    np.testing.assert_allclose([s for _, s in doubled], [s for _, s in same], rtol=1e-4)
    # "auto" tries every area hypothesis: the partial's units do not matter, and its own
    # shape scores best (a mean of positions in the library, so ties are possible).
    auto = screen.rank(v * 1e-3, f, "AUTO")
    check_ranking(auto, len(screen))
    assert auto == screen.rank(v, f, "auto")
    assert dict(auto)[OWN] == auto[0][1], auto
    # In the same units, a partial larger than every shape cannot be part of any.
    assert all(s == np.inf for _, s in screen.rank(v * 1e3, f)), "a partial larger than every shape"
    assert screen.rank(v, f, np.float32(1.0)) == same


def test_shapes_from_localizers_and_files_describe_as_their_meshes(tmp_path: Path, library: List[Mesh]) -> None:
    prepared = ds.Localizer(*library[OWN], **LIGHT)
    path = tmp_path / "figure.dsprep"
    prepared.save(path)
    from_localizer = ds.Screen([library[0], prepared])
    assert ds.Screen([library[0], path]).to_bytes() == from_localizer.to_bytes()
    # The prepared shape's mesh is the given one up to rounding: the same ranking.
    partial = cut(*library[OWN], library[OWN][0][:, 0] > 0.3)[:2]
    assert [i for i, _ in from_localizer.rank(*partial)] == [i for i, _ in ds.Screen(library[:2]).rank(*partial)]


def test_save_load_and_pickle_rank_the_same(tmp_path: Path, screen: ds.Screen, partials: List[Mesh]) -> None:
    path = tmp_path / "library.dsscreen"
    screen.save(path)
    loaded = ds.Screen.load(path)
    unpickled = pickle.loads(pickle.dumps(screen))
    assert path.read_bytes() == screen.to_bytes() == loaded.to_bytes() == unpickled.to_bytes()
    assert loaded.labels == unpickled.labels == screen.labels and len(loaded) == len(screen)
    assert ds.Screen.from_bytes(bytearray(screen.to_bytes())).labels == screen.labels
    for p in partials:
        assert loaded.rank(*p) == screen.rank(*p) == unpickled.rank(*p)
        assert loaded.rank(*p, "auto") == screen.rank(*p, "auto")


def test_bad_input_is_a_clear_error(tmp_path: Path, screen: ds.Screen, library: List[Mesh], partials: List[Mesh]) -> None:
    with pytest.raises(ValueError, match="no full shape"):
        ds.Screen([])
    with pytest.raises(TypeError, match="full shape 1: expected a Localizer"):
        ds.Screen([library[0], 3])  # type: ignore[list-item]
    with pytest.raises(ds.MeshError, match="full shape 0: vertices must have shape"):
        ds.Screen([(library[0][0][:, :2], library[0][1])])
    with pytest.raises(ds.MeshError, match="full shape 1: face 0 refers to vertex 10000"):
        ds.Screen([library[0], (library[0][0], library[0][1] + 10_000)])
    with pytest.raises(ValueError, match="1 labels for 2 full shapes"):
        ds.Screen(library[:2], labels=["one"])
    with pytest.raises(TypeError, match="labels must be a sequence of str"):
        ds.Screen(library[:2], labels="ab")
    v, f = partials[0]
    for bad in ("metres", 0.0, -2.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="same, auto or a positive number"):
            screen.rank(v, f, bad)
    for wrong in (True, None, [1.0]):
        with pytest.raises(TypeError, match="scale must be"):
            screen.rank(v, f, wrong)  # type: ignore[arg-type]
    with pytest.raises(ds.MeshError, match="partial mesh: faces must have shape"):
        screen.rank(v, f[:, :2])
    # Files: damaged, foreign, missing.
    good = screen.to_bytes()
    cases = {
        "truncated": (good[: len(good) // 2], "truncated"),
        "corrupted": (good[:-9] + bytes([good[-9] ^ 0xFF]) + good[-8:], "corrupted"),
        "foreign": (b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "not a dualspectra screen"),
        "empty": (b"", "not a dualspectra screen"),
    }
    assert_damaged_files_refused(ds.Screen.load, ds.Screen.from_bytes, cases, tmp_path, "dsscreen")
    # A screen of other shapes than those searched.
    with pytest.raises(ValueError, match="the screen holds 4 shapes, 2 full shapes were given"):
        ds.search(partials[0], library[:2], screen=screen, **LIGHT)
    with pytest.raises(ValueError, match="the screen holds 4 shapes, 3 full shapes were given"):
        search_batch(partials, library[:3], shortlist=1, screen=screen, **LIGHT)
    with pytest.raises(TypeError, match="screen must be a dualspectra.Screen"):
        ds.search(partials[0], library, screen=screen.to_bytes(), **LIGHT)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="shortlist must hold at least one shape"):
        search_batch(partials, library, shortlist=0, **LIGHT)


def test_progress_reports_and_cancels(library: List[Mesh], screen: ds.Screen, partials: List[Mesh]) -> None:
    seen: List[Tuple[float, str]] = []
    ds.Screen(library, progress=lambda f, s: seen.append((f, s)))
    fractions = [f for f, _ in seen]
    assert fractions == sorted(fractions) and fractions[0] == 0.0 and fractions[-1] == 1.0, seen
    assert len(fractions) > len(library), "one report per shape at least"
    with pytest.raises(ds.Cancelled):
        ds.Screen(library, progress=lambda f, s: f < 0.5)
    with pytest.raises(ds.Cancelled):
        screen.rank(*partials[0], progress=lambda f, s: False)

    def raising(fraction: float, stage: str) -> bool:
        raise KeyError("stop")

    with pytest.raises(KeyError, match="stop"):
        screen.rank(*partials[0], progress=raising)
    with pytest.raises(TypeError, match="progress must be callable"):
        screen.rank(*partials[0], progress=3)  # type: ignore[arg-type]
    # search_batch: cancelled while screening, before any task ran.
    reported: List[float] = []
    with pytest.raises(ds.Cancelled):
        search_batch(partials, library, shortlist=1, progress=lambda f, s: reported.append(f) or f < 0.07, **LIGHT)
    assert reported and 0.07 <= reported[-1] <= 0.1, reported


@pytest.fixture(scope="module")
def prepared(library: List[Mesh]) -> List[ds.Localizer]:
    return [ds.Localizer(*full, **LIGHT) for full in library]


def test_search_with_a_screen_equals_the_shortlisted_search(prepared: List[ds.Localizer], partials: List[Mesh]) -> None:
    """A screen of the prepared shapes is the one ``shortlist`` builds: the same answer,
    without describing the library again."""
    screen = ds.Screen(prepared)
    found = ds.search(partials[0], prepared, shortlist=1, screen=screen)
    again = ds.search(partials[0], prepared, shortlist=1)
    assert [(m.index, m.score, m.screen_score, m.error) for m in found] == [
        (m.index, m.score, m.screen_score, m.error) for m in again
    ]
    assert found[0].index == OWN and found[0].localization is not None
    assert all(m.localization is None and m.score == np.inf for m in found[1:])
    assert [m.screen_score for m in found] == [s for _, s in screen.rank(*partials[0])]
    # With a screen and no shortlist, every shape is localized and keeps its screen score.
    every = ds.search(partials[0], prepared[:2], screen=ds.Screen(prepared[:2]))
    assert all(m.localization is not None and m.screen_score is not None for m in every)


def batch_key(m: BatchMatch) -> Tuple[Any, ...]:
    return (m.partial, m.index, m.score, None if m.region is None else m.region.tobytes(), m.confidence, m.cost, m.error)


def test_batch_with_a_shortlist_localizes_only_the_shortlisted_pairs(
    library: List[Mesh], partials: List[Mesh], screen: ds.Screen
) -> None:
    shortlist = 2
    got = search_batch(partials, library, shortlist=shortlist, **LIGHT)
    assert len(got) == len(partials)
    kept: List[Tuple[int, int]] = []
    for i, (ranking, p) in enumerate(zip(got, partials)):
        screened = screen.rank(*p)
        assert sorted(m.index for m in ranking) == list(range(len(library)))
        assert all(m.partial == i and m.screen_score is not None for m in ranking)
        # Localized: the screen's best `shortlist` (each has a region or a reason), ranked by score.
        localized, out = ranking[:shortlist], ranking[shortlist:]
        assert {m.index for m in localized} == {j for j, _ in screened[:shortlist]}
        assert all((m.region is None) != (m.error is None) for m in localized)
        assert [m.score for m in localized] == sorted(m.score for m in localized)
        # Screened out: not localized, in screen order, with the screen's scores.
        assert [(m.index, m.screen_score) for m in out] == screened[shortlist:]
        assert all(m.score == np.inf and m.region is None and m.error is None and m.cost is None for m in out)
        assert {m.index: m.screen_score for m in ranking} == dict(screened)
        kept += [(i, m.index) for m in localized]
    # The localized pairs are what the batch of those pairs alone gives.
    alone = search_batch(partials, library, pairs=kept, **LIGHT)
    assert [[batch_key(m) for m in r[:shortlist]] for r in got] == [[batch_key(m) for m in r] for r in alone]
    # top cuts the whole ranking, screened-out shapes included.
    top = search_batch(partials, library, shortlist=shortlist, top=3, screen=screen, **LIGHT)
    assert [[batch_key(m) for m in r] for r in top] == [[batch_key(m) for m in r[:3]] for r in got]


def test_batch_in_two_stages_ranks_as_the_search_does(
    prepared: List[ds.Localizer], library: List[Mesh], partials: List[Mesh]
) -> None:
    """Shortlist 3 of 4 shapes: the batch localizes each shortlisted pair quickly, then the
    best (and the second best when close behind) again in full (a second round of tasks), as
    ``search`` does: the same order, scores, regions, quick flags, screen scores and
    confidences."""
    got = search_batch(partials, prepared, shortlist=3)
    for p, ranking in zip(partials, got):
        found = ds.search(p, prepared, shortlist=3)
        flags = [m.quick for m in found]
        in_full = flags[:3].count(False)
        assert 1 <= in_full <= 2 and flags == [False] * in_full + [True] * (3 - in_full) + [False], (
            "the best (and maybe the second) in full, then quick, one screened out"
        )
        assert [(m.index, m.score, m.quick, m.screen_score) for m in ranking] == [
            (m.index, m.score, m.quick, m.screen_score) for m in found
        ]
        for b, m in zip(ranking, found):
            loc = m.localization
            assert (b.region is None) == (loc is None)
            if loc is not None:
                assert b.region is not None and b.region.tobytes() == loc.region.tobytes()
                assert (b.confidence, b.cost, b.search_confidence) == (loc.confidence, loc.cost, m.confidence)
    # The quick localization is the core's: at most its effort (2 iterations, 10 eigenvalues,
    # the descriptor starts without the plane cuts), so with these options (8 iterations,
    # 2 plane cuts, k = 6) the full one of a shape prepared with 2 iterations and no plane cut.
    quick = next(b for b in got[0] if b.quick)
    light_two = ds.Localizer(*library[quick.index], **{**LIGHT, "max_iterations": 2, "plane_cuts": 0})
    full = search_batch(partials[:1], [light_two], pairs=[(0, 0)])[0][0]
    assert not full.quick and full.region is not None and quick.region is not None
    assert (quick.score, quick.cost, quick.region.tobytes()) == (full.score, full.cost, full.region.tobytes())


def test_batch_shortlist_within_pairs_and_from_files(
    tmp_path: Path, library: List[Mesh], partials: List[Mesh], prepared: List[ds.Localizer]
) -> None:
    paths = []
    for k, localizer in enumerate(prepared):
        paths.append(tmp_path / f"{k}.dsprep")
        localizer.save(paths[-1])
    screen_file = tmp_path / "library.dsscreen"
    ds.Screen(paths).save(screen_file)
    # Partial 0 among shapes 0 and 1 only; partial 1 paired with nothing.
    got = search_batch(partials, paths, pairs=[(0, 0), (0, OWN)], shortlist=1, screen=ds.Screen.load(screen_file))
    assert got[1] == []
    assert [m.index for m in got[0]] == [OWN, 0]
    assert got[0][0].region is not None and got[0][1].region is None and got[0][1].score == np.inf
    # Without a screen the paths' shapes are loaded here and described: the same answer.
    built = search_batch(partials, paths, pairs=[(0, 0), (0, OWN)], shortlist=1)
    assert [[batch_key(m) + (m.screen_score,) for m in r] for r in built] == [
        [batch_key(m) + (m.screen_score,) for m in r] for r in got
    ]
    # The scale option applies to the screen of prepared shapes (no warning about it).
    small = (partials[0][0] * 1e-3, partials[0][1])
    with warnings.catch_warnings():
        warnings.simplefilter("error", ds.DualspectraWarning)
        auto = search_batch([small], prepared, shortlist=1, scale="auto")
    screened = ds.Screen(prepared).rank(*small, "auto")
    assert screened != ds.Screen(prepared).rank(*small, "same")
    assert [(m.index, m.screen_score) for m in auto[0]] == screened


def match_key(m: ds.Match) -> Tuple[Any, ...]:
    """Everything a match says, its localization's arrays as bytes."""
    loc = m.localization
    arrays = () if loc is None else (loc.region.tobytes(), loc.score.tobytes(), loc.confidence, loc.cost, loc.warnings)
    return (m.index, m.score, m.error) + arrays


def test_a_shortlist_over_meshes_equals_the_search_over_their_prepared_shapes(
    tmp_path: Path, library: List[Mesh], partials: List[Mesh], prepared: List[ds.Localizer]
) -> None:
    """Meshes with a shortlist are screened from the meshes and only the shortlisted ones are
    prepared: the ranking, scores and regions are those of the search over the same shapes
    prepared first."""
    for p in partials:
        meshes_screen = ds.Screen(library).rank(*p)
        for shortlist, top in ((1, None), (2, None), (3, 2)):
            lazy = ds.search(p, library, shortlist=shortlist, top=top, **LIGHT)
            ready = ds.search(p, prepared, shortlist=shortlist, top=top)
            assert [match_key(m) for m in lazy] == [match_key(m) for m in ready]
            assert len(lazy) == (top or len(library))
            assert sum(m.localization is not None for m in lazy) == min(shortlist, len(lazy))
            # The screen describes the meshes as given (the prepared shapes' meshes are those
            # up to rounding): the scores of Screen(meshes), close to Screen(prepared)'s.
            assert {m.index: m.screen_score for m in lazy}.items() <= dict(meshes_screen).items()
            np.testing.assert_allclose([m.screen_score for m in lazy], [m.screen_score for m in ready], rtol=1e-2)
        # With a screen given, every field is the same, screen scores too.
        screen = ds.Screen(prepared)
        lazy = ds.search(p, library, shortlist=2, screen=screen, **LIGHT)
        ready = ds.search(p, prepared, shortlist=2, screen=screen)
        assert [match_key(m) + (m.screen_score,) for m in lazy] == [match_key(m) + (m.screen_score,) for m in ready]
    # The kinds mixed: a mesh, a prepared shape, a prepared shape's file, a mesh.
    path = tmp_path / "horned.dsprep"
    prepared[2].save(path)
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", "prepared shapes keep the options", ds.DualspectraWarning)
        mixed = ds.search(partials[0], [library[0], prepared[1], path, library[3]], shortlist=2, **LIGHT)
    ready = ds.search(partials[0], prepared, shortlist=2)
    assert [match_key(m) for m in mixed] == [match_key(m) for m in ready]


def test_a_shortlist_prepares_only_the_shortlisted_meshes(library: List[Mesh], partials: List[Mesh]) -> None:
    """Counted by the core's progress stage "prepared" (one per preparation)."""
    def preparations(stages: List[Tuple[float, str]]) -> int:
        return sum(s == "prepared" for _, s in stages)

    everything: List[Tuple[float, str]] = []
    ds.search(partials[0], library, progress=lambda f, s: everything.append((f, s)), **LIGHT)
    assert preparations(everything) == len(library)
    for shortlist, screen in ((1, None), (2, None), (2, ds.Screen(library)), (len(library), ds.Screen(library))):
        seen: List[Tuple[float, str]] = []
        report = lambda f, s: seen.append((f, s))  # noqa: E731
        found = ds.search(partials[0], library, shortlist=shortlist, screen=screen, progress=report, **LIGHT)
        assert preparations(seen) == shortlist == sum(m.localization is not None for m in found), seen
        # The screen first (describing the library unless it is given), then the preparations.
        fractions = [f for f, _ in seen]
        assert fractions == sorted(fractions) and fractions[-1] == 1.0, fractions
        stages = [s for _, s in seen]
        assert ("describing the library" in stages) == (screen is None)
        assert stages.index("screened") < stages.index("preparing")
    # A prepared shape shortlisted: no mesh is prepared.
    shapes: List[Any] = list(library)
    shapes[OWN] = ds.Localizer(*library[OWN], **LIGHT)
    seen = []
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", "prepared shapes keep the options", ds.DualspectraWarning)
        found = ds.search(partials[0], shapes, shortlist=1, progress=lambda f, s: seen.append((f, s)), **LIGHT)
    assert found[0].index == OWN and preparations(seen) == 0
    # Cancelling while a shortlisted mesh is prepared, or by raising there.
    with pytest.raises(ds.Cancelled):
        ds.search(partials[0], library, shortlist=2, progress=lambda f, s: s != "descriptors", **LIGHT)

    def raising(fraction: float, stage: str) -> None:
        if stage == "preparing":
            raise KeyError("stop")

    with pytest.raises(KeyError, match="stop"):
        ds.search(partials[0], library, shortlist=1, progress=raising, **LIGHT)


def test_a_shortlist_over_meshes_warns_as_preparing_them_does(library: List[Mesh], partials: List[Mesh]) -> None:
    """A mesh's intake note is given whether it is shortlisted or not, once; the
    localizations carry the notes the prepared shapes' do."""
    v, f = library[OWN]
    far = [[9.0, 9.0, 9.0]]
    loose = [library[0], (np.r_[v, far], f), library[2], (np.r_[library[3][0], far], library[3][1])]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        lazy = ds.search(partials[0], loose, shortlist=1, **LIGHT)
    notes = [str(w.message) for w in caught if issubclass(w.category, ds.DualspectraWarning)]
    assert len(notes) == 2 and all("1 vertex" in n for n in notes), notes
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ds.DualspectraWarning)
        ready = ds.search(partials[0], [ds.Localizer(*full, **LIGHT) for full in loose], shortlist=1)
    assert lazy[0].index == OWN and lazy[0].localization is not None
    assert [match_key(m) for m in lazy] == [match_key(m) for m in ready]
    assert lazy[0].localization.region.shape == (len(v) + 1,) and not lazy[0].localization.region[-1]
    # A mesh's bad index is an error before anything is prepared, naming the shape.
    with pytest.raises(ds.MeshError, match="full shape 1: face 0 refers to vertex"):
        ds.search(partials[0], [library[0], (v, f + len(v))], shortlist=1, **LIGHT)
