"""The localizer end to end on small generated pairs: ``localize`` and ``Localizer``, options
passed through to the core by name, the mesh intake, progress, cancellation and threads.

The pairs: an asymmetric bumpy ellipsoid (icosphere level 3, 642 vertices) and parts of it
cut out and re-indexed (same geometry, so the answer is known exactly). The paper reports
IoU ~0.9 on SHREC'16 cuts; with ``FAST`` the cut ``x > 0.25`` was measured at 0.91 (bar
0.7: the smooth shape is close to symmetric, caps on opposite sides have nearly the same
spectra). ``QUICK`` (5 starts, ~1.5 s a run) is for the laws that do not depend on the
quality of the answer: the same inputs give the same regions whichever way they are run.
"""

from __future__ import annotations

import threading
import time
import warnings
from typing import Any, Dict, List, Tuple

import numpy as np
import pytest
from conftest import bumpy, cut

import dualspectra as ds

FAST: Dict[str, Any] = dict(k=10, max_iterations=40, resolution=0)
QUICK: Dict[str, Any] = dict(k=8, plane_cuts=2, max_iterations=15, resolution=0)
DEADLINE_S = 240.0  # the run is cancelled (and the test fails) past this, so CI cannot hang

Pair = Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def cut_pair(keep_rule) -> Pair:  # type: ignore[no-untyped-def]
    v, f = bumpy(3)
    pv, pf, orig = cut(v, f, keep_rule(v))
    truth = np.zeros(len(v), bool)
    truth[orig] = True
    return v, f, pv, pf, truth


@pytest.fixture(scope="module")
def pair() -> Pair:
    return cut_pair(lambda v: v[:, 0] > 0.25)


@pytest.fixture(scope="module")
def other_pair() -> Pair:
    return cut_pair(lambda v: v[:, 1] < -0.2)


@pytest.fixture(scope="module")
def one_call(pair: Pair, other_pair: Pair) -> Tuple[ds.Localization, ds.Localization]:
    """``localize`` (one call, preparing each time) on both partials, ``QUICK``."""
    return (ds.localize(*pair[:4], **QUICK), ds.localize(*other_pair[:4], **QUICK))


@pytest.fixture(scope="module")
def localizer(pair: Pair) -> ds.Localizer:
    return ds.Localizer(pair[0], pair[1], **QUICK)


def iou(a: np.ndarray, b: np.ndarray) -> float:
    return float((a & b).sum() / (a | b).sum())


def test_localize_finds_the_cut(pair: Pair) -> None:
    v, f, pv, pf, truth = pair
    stages = []
    start = time.monotonic()

    def cb(x: float, s: str) -> bool:
        stages.append((x, s))
        return time.monotonic() - start < DEADLINE_S

    try:
        r = ds.localize(v, f, pv, pf, progress=cb, **FAST)
    except ds.Cancelled:
        pytest.fail(f"localize did not finish within {DEADLINE_S} s (last progress {stages[-1]})")
    assert r.region.dtype == np.bool_ and r.region.shape == (len(v),)
    assert r.score.shape == r.potential.shape == (len(v),)
    print(f"[agreement] localize bumpy3 cut: IoU={iou(r.region, truth):.3f}, cost={r.cost:.3e}, {r.timings}")
    assert iou(r.region, truth) > 0.7
    assert r.n_starts == len(r.candidates) == 1 + 2, "the most voted of the 6 plane cuts, 2 descriptor starts"
    assert 0 <= r.selected_start < r.n_starts
    chosen = r.candidates[r.selected_start]
    assert np.array_equal(chosen.region, r.region) and chosen.cost == r.cost
    assert isinstance(r.confidence, float) and 0.0 <= r.confidence <= 1.0, r.confidence
    assert r.optimisation_vertices == len(v), "resolution=0: optimised on the full mesh itself"
    assert all(c.region.shape == (len(v),) and c.evaluations >= 1 for c in r.candidates)
    assert set(r.timings) == {"preparation", "preprocessing", "starts", "optimisation", "region", "selection", "total"}
    assert r.timings["preparation"] > 0 and r.timings["total"] >= r.timings["optimisation"]
    xs = [x for x, _ in stages]
    assert xs and all(0.0 <= x <= 1.0 for x in xs) and xs == sorted(xs)
    assert {s for _, s in stages} >= {"preparing", "preprocessing"}
    assert r.warnings == ()
    assert "Localization(" in repr(r) and f"confidence={r.confidence:.3f}" in repr(r) and "Candidate(" in repr(chosen)


def test_one_localizer_gives_the_regions_of_one_call_runs(pair: Pair, other_pair: Pair, one_call, localizer) -> None:  # type: ignore[no-untyped-def]
    """Two partials located on one prepared full shape: the same regions as two ``localize``
    calls (which prepare it each time), and the preparation is not counted in the results."""
    assert localizer.n_vertices == len(pair[0]) and localizer.optimisation_vertices == len(pair[0])
    assert localizer.options == {**{s["name"]: s["default"] for s in ds.options_schema()}, **QUICK}
    assert localizer.preparation_seconds > 0 and localizer.warnings == ()
    for p, fresh in zip((pair, other_pair), one_call):
        r = localizer.locate(p[2], p[3])
        assert np.array_equal(r.region, fresh.region), f"differ on {(r.region != fresh.region).sum()} vertices"
        np.testing.assert_array_equal(r.score, fresh.score)
        assert r.cost == fresh.cost and r.confidence == fresh.confidence and r.selected_start == fresh.selected_start
        assert [c.label for c in r.candidates] == [c.label for c in fresh.candidates]
        assert r.timings["preparation"] == 0.0 < fresh.timings["preparation"]
    assert "Localizer(n_vertices=642" in repr(localizer)


def test_two_threads_locate_on_one_localizer_at_once(pair: Pair, other_pair: Pair, one_call, localizer) -> None:  # type: ignore[no-untyped-def]
    """Both threads are inside ``locate`` together (each waits at its first progress report
    for the other: a lock around ``locate`` would deadlock and break the barrier) and get the
    sequential results."""
    barrier = threading.Barrier(2, timeout=120)
    results: Dict[int, ds.Localization] = {}
    errors = []

    def run(i: int, p: Pair) -> None:
        met: List[int] = []

        def cb(x: float, s: str) -> None:
            if not met:
                met.append(barrier.wait())

        try:
            results[i] = localizer.locate(p[2], p[3], progress=cb)
        except BaseException as e:  # reported below, never lost in the thread
            errors.append(e)

    threads = [threading.Thread(target=run, args=(i, p)) for i, p in enumerate((pair, other_pair))]
    for t in threads:
        t.start()
    for t in threads:
        t.join(600)
    assert not errors, errors
    assert not barrier.broken
    for i, fresh in enumerate(one_call):
        assert np.array_equal(results[i].region, fresh.region)
        assert results[i].cost == fresh.cost


def test_intake_drops_a_loose_vertex_and_a_degenerate_face(pair: Pair, one_call) -> None:  # type: ignore[no-untyped-def]
    """A loose vertex (first, so that every index moves) and a zero-area face on a new vertex
    (the midpoint of an edge): the core sees the clean mesh, so the region is the clean run's,
    read at the caller's indices; the dropped vertices are False / 0, and a warning says so."""
    v, f, pv, pf, _ = pair
    a, b = f[0, 0], f[0, 1]
    host_v = np.r_[[[9.0, 9.0, 9.0]], v, [(v[a] + v[b]) / 2]]
    host_f = np.r_[f + 1, [[a + 1, b + 1, len(v) + 1]]]
    host_pv = np.r_[pv, [[5.0, 5.0, 5.0]]]
    with pytest.warns(ds.DualspectraWarning) as caught:
        r = ds.localize(host_v, host_f, host_pv, pf, **QUICK)
    messages = [str(w.message) for w in caught]
    assert messages == list(r.warnings)
    assert messages[0].startswith("full mesh: left out 1 degenerate face(s) and 2 vertex(es)")
    assert messages[1].startswith("partial mesh: left out 0 degenerate face(s) and 1 vertex(es)")
    assert caught[0].filename == __file__, "the warning points at the caller"
    clean = one_call[0]
    for got, want, fill in ((r.region, clean.region, False), (r.score, clean.score, 0.0), (r.potential, clean.potential, 0.0)):
        assert got.shape == (len(host_v),)
        assert got[0] == fill and got[-1] == fill
        np.testing.assert_array_equal(got[1:-1], want)
    assert all(c.region.shape == (len(host_v),) for c in r.candidates)


def test_localizer_warns_once_for_the_full_mesh(pair: Pair, one_call) -> None:  # type: ignore[no-untyped-def]
    """The full mesh's note is emitted by the constructor and kept in every result; ``locate``
    emits only what concerns its partial (here the core's: a disconnected partial is reduced
    to its largest component, which is the clean partial, so the region is the clean run's)."""
    v, f, pv, pf, _ = pair
    with pytest.warns(ds.DualspectraWarning, match="full mesh: left out 0 degenerate face.* and 1 vertex"):
        loc = ds.Localizer(np.r_[v, [[3.0, 0.0, 0.0]]], f, **QUICK)
    assert loc.n_vertices == len(v) + 1 and len(loc.warnings) == 1
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = loc.locate(pv, pf)
    assert r.warnings == loc.warnings and r.region.shape == (len(v) + 1,) and not r.region[-1]
    speck = np.r_[pv, [[4.0, 4.0, 4.0], [4.1, 4.0, 4.0], [4.0, 4.1, 4.0]]]
    with pytest.warns(ds.DualspectraWarning) as caught:
        r = loc.locate(speck, np.r_[pf, [[len(pv), len(pv) + 1, len(pv) + 2]]])
    assert [str(w.message) for w in caught] == list(r.warnings[1:])
    assert r.warnings[0] == loc.warnings[0] and "the partial shape is disconnected" in r.warnings[1]
    np.testing.assert_array_equal(r.region[:-1], one_call[0].region)


def test_options_schema_is_the_core_table() -> None:
    schema = ds.options_schema()
    names = [s["name"] for s in schema]
    assert names[:2] == ["mode", "k"] and len(set(names)) == len(names)
    for s in schema:
        assert s["label"] and s["doc"] and s["type"] in ("int", "float", "choice")
        if s["type"] == "choice":
            assert s["default"] in s["choices"]
        else:
            assert s["min"] <= s["default"] <= s["max"]
    for removed in ("selection", "starts", "spectral_cuts", "finalists", "hessian", "centers", "seed"):
        assert removed not in names
    assert schema is not ds.options_schema(), "a new list on each call"
    assert all(f"            {n} (" in (ds.localize.__doc__ or "") for n in names), "the docstring lists the table"


def test_unknown_option_raises_naming_it(pair: Pair) -> None:
    v, f, pv, pf, _ = pair
    names = ", ".join(s["name"] for s in ds.options_schema())
    with pytest.raises(ValueError, match=f"unknown option 'kk' \\(options: {names}\\)"):
        ds.localize(v, f, pv, pf, kk=3)
    with pytest.raises(ValueError, match="unknown option 'centres'"):
        ds.Localizer(v, f, centres=3)
    # The options removed in 0.3.0 say so, with the version.
    for old in ("centers", "seed"):
        with pytest.raises(ValueError, match=f"option '{old}' was removed in 0.3.0"):
            ds.localize(v, f, pv, pf, **{old: 0})
        with pytest.raises(ValueError, match=f"option '{old}' was removed"):
            ds.Localizer(v, f, **{old: 1})
    # Options removed before any release are unknown, with the same clear message.
    removed: Dict[str, Any] = {"selection": "gated", "starts": "gaussian", "spectral_cuts": 2}
    for old, value in removed.items():
        with pytest.raises(ValueError, match=f"unknown option '{old}'"):
            ds.localize(v, f, pv, pf, **{old: value})


@pytest.mark.parametrize("spec", ds.options_schema(), ids=lambda s: s["name"])
def test_values_out_of_range_raise_naming_the_option(pair: Pair, spec: Dict[str, Any]) -> None:
    """Just past each end of every range in the table (and a bad choice) is refused, before
    any work, with the core's message naming the option."""
    v, f = pair[0], pair[1]
    name = spec["name"]
    if spec["type"] == "choice" and spec.get("positive_number"):
        bad = ["bogus", 0, -3]
    elif spec["type"] == "choice":
        bad = ["bogus", 3]
    elif spec["type"] == "int":
        bad = [spec["min"] - 1, spec["max"] + 1, spec["default"] + 0.5]
    else:
        bad = [spec["min"] - 0.5, spec["max"] + 0.5, float("nan"), float("inf")]
    for value in bad:
        with pytest.raises(ValueError, match=f"^{name} = "):
            ds.Localizer(v, f, **{name: value})  # type: ignore[arg-type]


def test_option_values_convert_by_type(pair: Pair) -> None:
    v, f = pair[0], pair[1]
    # Integer-likes (``__index__``) and real numbers (``__float__``) convert too.
    loc = ds.Localizer(v, f, k=np.int64(7), alpha=np.float32(0.5), mode="LBO", plane_cuts="12", resolution=0)  # type: ignore[arg-type]
    assert {k: loc.options[k] for k in ("k", "alpha", "mode", "plane_cuts")} == {"k": 7, "alpha": 0.5, "mode": "lbo", "plane_cuts": 12}
    with pytest.raises(TypeError, match="option k: expected int, float or str, got NoneType"):
        ds.Localizer(v, f, k=None)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="option k"):
        ds.Localizer(v, f, k=[3])  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="too coarse"):  # the core's joint validation
        ds.Localizer(v, f, resolution=50)


def test_plane_cuts_set_the_plane_starts(pair: Pair) -> None:
    v, f, pv, pf, _ = pair
    loc = ds.Localizer(v, f, **dict(QUICK, plane_cuts=0))
    r = loc.locate(pv, pf)
    assert r.n_starts == 2 and not any(c.label.startswith("plane") for c in r.candidates)
    # Of the 5 plane cuts, the one holding the most descriptor votes is optimised.
    r = ds.localize(v, f, pv, pf, **dict(QUICK, plane_cuts=5))
    assert r.n_starts == 1 + 2
    assert [c.label for c in r.candidates if c.label.startswith("plane")] in [[f"plane{j}"] for j in range(5)]


def test_progress_false_cancels(pair: Pair, localizer: ds.Localizer) -> None:
    v, f, pv, pf, _ = pair
    with pytest.raises(ds.Cancelled):
        ds.localize(v, f, pv, pf, progress=lambda x, s: False, **QUICK)
    with pytest.raises(ds.Cancelled):
        ds.Localizer(v, f, progress=lambda x, s: False, **QUICK)
    calls = []

    def stop_at_third(x: float, s: str) -> bool:
        calls.append(s)
        return len(calls) < 3

    with pytest.raises(ds.Cancelled):
        localizer.locate(pv, pf, progress=stop_at_third)
    assert len(calls) >= 3


def test_progress_exception_propagates(pair: Pair, localizer: ds.Localizer) -> None:
    v, f, pv, pf, _ = pair

    class Stop(Exception):
        pass

    def cb(x: float, s: str) -> None:
        raise Stop(s)

    with pytest.raises(Stop, match="preparing"):
        ds.Localizer(v, f, progress=cb, **QUICK)
    with pytest.raises(Stop, match="preprocessing"):
        localizer.locate(pv, pf, progress=cb)
    with pytest.raises(Stop):
        ds.localize(v, f, pv, pf, progress=cb, **QUICK)


def test_localize_argument_errors(pair: Pair, localizer: ds.Localizer) -> None:
    v, f, pv, pf, _ = pair
    with pytest.raises(ValueError, match="mode = bogus must be one of dual, lbo, si"):
        ds.localize(v, f, pv, pf, mode="bogus")
    with pytest.raises(TypeError, match="progress"):
        ds.localize(v, f, pv, pf, progress=3)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="progress"):
        localizer.locate(pv, pf, progress=3)  # type: ignore[arg-type]
    with pytest.raises(ds.MeshError, match="partial mesh"):
        ds.localize(v, f, pv, pf + len(pv))
    with pytest.raises(ds.MeshError, match="partial mesh"):
        localizer.locate(pv, pf + len(pv))
    with pytest.raises(ds.MeshError, match="full mesh: all 1 faces are degenerate"):
        ds.Localizer([[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 1, 2]])
    with pytest.raises(ds.MeshError, match="full mesh: mesh has no faces"):
        ds.Localizer(v, np.zeros((0, 3), np.int64))
