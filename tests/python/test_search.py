"""Issue 21: partial shape similarity from Python: ``search`` over several full shapes, prepared
shapes saved, loaded and pickled, and the batch (``search_batch``) here and on a Dask
``LocalCluster``.

The library: three figures of the Rust core's ``evaluation::synthetic`` kind (icosphere level
3, 642 vertices): a four-legged one, the default one and a horned one; the partials are cut
from a posed copy of the default figure (its long arm bent by 50 degrees), so the right
model is known. ``LIGHT`` keeps a localization near a second.
"""

from __future__ import annotations

import pickle
import warnings
from pathlib import Path
from typing import Any, Dict, List, Tuple

import numpy as np
import pytest
from conftest import assert_damaged_files_refused, bend, cut, figure

import dualspectra as ds
from dualspectra import _dualspectra
from dualspectra.batch import BatchMatch, search_batch

LIGHT: Dict[str, Any] = dict(k=6, plane_cuts=2, max_iterations=8, resolution=0)

Mesh = Tuple[np.ndarray, np.ndarray]


@pytest.fixture(scope="module")
def library() -> List[Mesh]:
    """The full shapes; the partials come from index 1."""
    return [figure(3, "quadruped"), figure(3, "figure"), figure(3, "horned")]


def cut_posed(full: Mesh, normal: Tuple[float, float, float], offset: float) -> Mesh:
    v, f = full
    posed = bend(v)
    pv, pf, _ = cut(posed, f, posed @ (np.asarray(normal) / np.linalg.norm(normal)) > offset)
    return pv, pf


@pytest.fixture(scope="module")
def partials(library: List[Mesh]) -> List[Mesh]:
    """The long arm and shoulder (bent), and the upper body with the head."""
    return [cut_posed(library[1], (1.0, 0.0, 0.2), 0.3), cut_posed(library[1], (0.0, 0.2, 1.0), 0.2)]


@pytest.fixture(scope="module")
def prepared(library: List[Mesh]) -> ds.Localizer:
    return ds.Localizer(*library[1], **LIGHT)


@pytest.fixture(scope="module")
def ranked(library: List[Mesh], partials: List[Mesh], prepared: ds.Localizer) -> List[List[ds.Match]]:
    """``search`` for each partial, the right model given prepared, the others as meshes."""
    fulls = [library[0], prepared, library[2]]
    with warnings.catch_warnings():
        # The options are for the meshes: said once, since the prepared shape keeps its own.
        warnings.filterwarnings("ignore", "prepared shapes keep the options", ds.DualspectraWarning)
        return [ds.search(p, fulls, **LIGHT) for p in partials]


def key(index: int, score: float, region: Any) -> Tuple[int, float, bytes]:
    return index, score, np.asarray(region).tobytes()


def test_search_ranks_the_model_the_partial_was_cut_from_first(ranked: List[List[ds.Match]], library: List[Mesh]) -> None:
    for matches in ranked:
        order = [(m.index, round(m.score, 4)) for m in matches]
        print(f"[agreement] search: ranking (index, score) {order}")
        assert [m.index for m in matches][0] == 1, order
        assert sorted(m.index for m in matches) == [0, 1, 2]
        assert all(a.score <= b.score for a, b in zip(matches, matches[1:])), order
        for m in matches:
            assert m.error is None and m.localization is not None
            assert m.score == m.localization.similarity_score and np.isfinite(m.score)
            assert m.localization.region.shape == (len(library[m.index][0]),)
            assert "score=" in repr(m)


def test_search_top_and_progress(library: List[Mesh], partials: List[Mesh], ranked: List[List[ds.Match]]) -> None:
    seen: List[Tuple[float, str]] = []
    top = ds.search(partials[0], library, top=2, progress=lambda f, s: seen.append((f, s)), **LIGHT)
    assert [key(m.index, m.score, m.localization.region) for m in top if m.localization is not None] == [
        key(m.index, m.score, m.localization.region) for m in ranked[0][:2] if m.localization is not None
    ]
    fractions = [f for f, _ in seen]
    assert fractions == sorted(fractions) and fractions[-1] == 1.0 and fractions[0] < 0.5, fractions[:3]
    with pytest.raises(ds.Cancelled):
        ds.search(partials[0], library, progress=lambda f, s: f < 0.6, **LIGHT)


def test_search_bad_input(library: List[Mesh], partials: List[Mesh], prepared: ds.Localizer) -> None:
    with pytest.raises(TypeError, match="partial mesh must be a .vertices, faces. pair"):
        ds.search(partials[0][0], [prepared])  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="full shape 1: expected a Localizer"):
        ds.search(partials[0], [prepared, 3])  # type: ignore[list-item]
    with pytest.raises(ValueError, match="top must be non-negative"):
        ds.search(partials[0], [prepared], top=-1)
    with pytest.raises(ds.MeshError, match="full shape 0: vertices must have shape"):
        ds.search(partials[0], [(library[0][0][:, :2], library[0][1])])
    assert ds.search(partials[0], []) == []
    # A shape smaller than the partial ranks last with the reason; if every shape is, it raises.
    small = (library[1][0] * 0.2, library[1][1])
    matches = ds.search(partials[1], [small, library[1]], **LIGHT)
    assert [m.index for m in matches] == [1, 0]
    assert matches[1].score == np.inf and matches[1].localization is None
    assert "cannot be a part of it" in (matches[1].error or ""), matches[1].error
    with pytest.raises(ValueError, match="cannot be a part of it"):
        ds.search(partials[1], [small], **LIGHT)


def test_save_load_and_pickle_give_identical_results(tmp_path: Path, library: List[Mesh], partials: List[Mesh]) -> None:
    # A loose vertex (dropped by the intake, with a warning): results of the loaded shape must
    # still be indexed by the vertices as given.
    v, f = library[1]
    v = np.r_[v, [[9.0, 9.0, 9.0]]]
    with pytest.warns(ds.DualspectraWarning, match="1 vertex"):
        fresh = ds.Localizer(v, f, **LIGHT)
    path = tmp_path / "figure.dsprep"
    fresh.save(path)
    loaded = ds.Localizer.load(path)
    unpickled = pickle.loads(pickle.dumps(fresh))
    assert path.read_bytes() == fresh.to_bytes() == loaded.to_bytes() == unpickled.to_bytes()
    assert loaded.options == fresh.options and loaded.n_vertices == fresh.n_vertices == len(v)
    assert unpickled.warnings == fresh.warnings  # the intake's note travels with the pickle
    results = [loc.locate(*partials[0]) for loc in (fresh, loaded, unpickled)]
    assert len({key(0, r.similarity_score, r.region) for r in results}) == 1
    assert all(np.array_equal(results[0].score, r.score) for r in results)
    assert results[0].region.shape == (len(v),) and not results[0].region[-1]
    assert ds.Localizer.load(path, threads=1).options["threads"] == 1
    assert ds.Localizer.from_bytes(bytearray(fresh.to_bytes())).n_vertices == len(v)
    # Searching prepared files gives what searching the shapes gives.
    found = ds.search(partials[0], [path, fresh])
    assert found[0].score == found[1].score and {m.index for m in found} == {0, 1}


def test_stale_foreign_and_damaged_files_are_mesh_errors(tmp_path: Path, prepared: ds.Localizer) -> None:
    good = prepared.to_bytes()
    cases = {
        "foreign": (b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "not a dualspectra prepared shape"),
        "stale": (good[:8] + (99).to_bytes(4, "little") + good[12:], "stale prepared shape: format version 99"),
        "truncated": (good[: len(good) // 2], "truncated"),
        "corrupted": (good[:-9] + bytes([good[-9] ^ 0xFF]) + good[-8:], "corrupted"),
        "empty": (b"", "empty file"),
    }
    assert_damaged_files_refused(ds.Localizer.load, ds.Localizer.from_bytes, cases, tmp_path, "dsprep")
    with pytest.raises(ds.MeshError, match="stale"):
        ds.search(cases_partial(), [tmp_path / "stale.dsprep"])


def cases_partial() -> Mesh:
    v, f = figure(2)
    return cut(v, f, v[:, 2] > 0.3)[:2]


def batch_key(m: BatchMatch) -> Tuple[Any, ...]:
    return (m.partial, m.index, m.score, None if m.region is None else m.region.tobytes(), m.confidence, m.cost, m.error)


@pytest.fixture(scope="module")
def serial(library: List[Mesh], partials: List[Mesh], prepared: ds.Localizer) -> List[List[BatchMatch]]:
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", "prepared shapes keep the options", ds.DualspectraWarning)
        return search_batch(partials, [library[0], prepared, library[2]], **LIGHT)


def test_batch_here_equals_search(serial: List[List[BatchMatch]], ranked: List[List[ds.Match]]) -> None:
    assert len(serial) == len(ranked) == 2
    for i, (batch, matches) in enumerate(zip(serial, ranked)):
        assert all(m.partial == i and m.error is None for m in batch)
        assert [(m.index, m.score) for m in batch] == [(m.index, m.score) for m in matches]
        for b, m in zip(batch, matches):
            assert m.localization is not None and b.region is not None
            assert np.array_equal(b.region, m.localization.region) and b.confidence == m.localization.confidence
            assert b.search_confidence == m.confidence, "the batch's search confidence is the search's"
    assert pickle.loads(pickle.dumps(serial))[0][0].score == serial[0][0].score


def test_batch_pairs_and_top(library: List[Mesh], partials: List[Mesh], serial: List[List[BatchMatch]]) -> None:
    got = search_batch(partials, library, pairs=[(1, 1), (0, 1), (1, 0)], top=1, **LIGHT)
    assert [[batch_key(m) for m in r] for r in got] == [[batch_key(serial[0][0])], [batch_key(serial[1][0])]]
    assert search_batch(partials, library, pairs=[], **LIGHT) == [[], []]
    with pytest.raises(ValueError, match="out of range"):
        search_batch(partials, library, pairs=[(2, 0)])
    seen: List[float] = []
    with pytest.raises(ds.Cancelled):
        search_batch(partials, library, progress=lambda f, s: seen.append(f) or f < 0.2, **LIGHT)
    assert seen and seen[-1] >= 0.2


def test_a_batch_in_other_units_takes_each_partial_in_once(
    monkeypatch: pytest.MonkeyPatch, library: List[Mesh], partials: List[Mesh]
) -> None:
    """With ``scale="auto"`` each partial is taken in once for every full shape (its scale
    scan made once, as ``ds.search`` makes it), and the rankings are ``ds.search``'s; a
    partial beyond the ones a process keeps is taken in again per shape, same answers."""
    import dualspectra.batch as batch

    made: List[int] = []
    real = _dualspectra.PreparedPartial

    def counted(vertices: np.ndarray, faces: np.ndarray) -> Any:
        made.append(len(vertices))
        return real(vertices, faces)

    monkeypatch.setattr(_dualspectra, "PreparedPartial", counted)
    in_mm = [(1000.0 * v, f) for v, f in partials]
    auto = dict(LIGHT, scale="auto")
    got = search_batch(in_mm, library, **auto)
    assert len(made) == len(in_mm), "one intake per partial, not one per (partial, full shape)"
    assert not batch._prepared_partials, "the batch's partials are dropped at its end"
    for i, ranking in enumerate(got):
        expected = ds.search(in_mm[i], library, **auto)
        assert [(m.index, m.score) for m in ranking] == [(m.index, m.score) for m in expected]
        assert all(m.error is None and m.region is not None for m in ranking)
    made.clear()
    monkeypatch.setattr(batch, "_PREPARED_PARTIALS", 1)
    again = search_batch(in_mm, library, **auto)
    assert len(made) == 1 + len(library), "the first partial kept, the second taken in per shape"
    assert [[batch_key(m) for m in r] for r in again] == [[batch_key(m) for m in r] for r in got]


def test_batch_on_a_local_dask_cluster_equals_the_serial_run(
    tmp_path: Path, library: List[Mesh], partials: List[Mesh], prepared: ds.Localizer, serial: List[List[BatchMatch]]
) -> None:
    distributed = pytest.importorskip("distributed")
    # Each kind of full shape travels: arrays, a prepared shape (pickled) and a file's path.
    path = tmp_path / "horned.dsprep"
    ds.Localizer(*library[2], **LIGHT).save(path)
    fulls = [library[0], prepared, path]
    seen: List[float] = []
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, host="127.0.0.1"
    ) as cluster, distributed.Client(cluster) as client:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", "prepared shapes keep the options", ds.DualspectraWarning)
            got = search_batch(partials, fulls, client=client, progress=lambda f, s: seen.append(f), **LIGHT)
        workers = {w["id"] for w in client.scheduler_info()["workers"].values()}
    assert [[batch_key(m) for m in r] for r in got] == [[batch_key(m) for m in r] for r in serial]
    assert seen == [1 / 3, 2 / 3, 1.0] and len(workers) == 2


def test_a_screened_search_localizes_only_the_shortlist(library: List[Mesh], partials: List[Mesh]) -> None:
    """With ``shortlist=1`` the screen ranks the three shapes, the partial is located on the
    best one only (its own figure), and the others follow screened out with a screen score."""
    found = ds.search(partials[0], library, shortlist=1, **LIGHT)
    assert [m.index for m in found][0] == 1
    assert found[0].localization is not None and found[0].screen_score is not None
    rest = found[1:]
    assert len(rest) == 2
    assert all(m.localization is None and m.error is None and m.score == float("inf") for m in rest)
    assert all(m.screen_score is not None and m.screen_score >= found[0].screen_score for m in rest)
    # The full search gives the shortlisted shape the same localization.
    full = ds.search(partials[0], library, **LIGHT)
    assert full[0].index == 1 and full[0].screen_score is None
    np.testing.assert_array_equal(full[0].localization.region, found[0].localization.region)
    assert not found[0].quick and not full[0].quick
    with pytest.raises(ValueError, match="shortlist"):
        ds.search(partials[0], library, shortlist=0, **LIGHT)


def test_a_shortlist_is_localized_quickly_and_its_best_two_again_in_full(
    library: List[Mesh], partials: List[Mesh]
) -> None:
    """Four shapes (the partial's own figure twice), shortlist 3: one quick localization, the
    two best in full, ranked first, the full ones as ``Localizer.locate`` finds them."""
    four = [library[0], library[1], library[2], library[1]]
    found = ds.search(partials[0], four, shortlist=3, **LIGHT)
    kinds = [(m.localization is not None, m.quick) for m in found]
    assert kinds == [(True, False), (True, False), (True, True), (False, False)]
    direct = ds.Localizer(*four[found[0].index], **LIGHT).locate(*partials[0])
    np.testing.assert_array_equal(found[0].localization.region, direct.region)
    assert found[0].score == direct.similarity_score
    # The search's confidence: the core's among the located shapes; 0 screened out.
    expected = _dualspectra.search_confidences([(m.score, m.localization.confidence) for m in found[:3]])
    assert [m.confidence for m in found[:3]] == expected and all(0.0 <= c <= 1.0 for c in expected)
    assert found[3].confidence == 0.0
