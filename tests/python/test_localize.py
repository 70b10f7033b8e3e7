"""``localize`` end to end on a small generated pair, progress and cancellation.

The pair: an asymmetric bumpy ellipsoid (icosphere level 3, 642 vertices) and the part of
it with ``x > 0.25`` cut out and re-indexed (same geometry, so the answer is known
exactly). The paper reports IoU ~0.9 on SHREC'16 cuts. This smooth shape is close to
symmetric (caps on opposite sides have nearly the same spectra), so the bars are lower:
measured with these settings, the default starts (balls-and-wide-bumps, 9) reach 0.76,
balls-and-wide-gaussians (12) and gaussian 0.82, area-ball (6) 0.76; the bars are 0.7 for
the default and 0.8 where 0.82 was measured, 0.6 for the six area-ball starts.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import bumpy, cut

import dualspectra as ds

FAST = dict(k=10, centers=3, max_iterations=40, resolution=0)
DEADLINE_S = 240.0  # the run is cancelled (and the test fails) past this, so CI cannot hang


@pytest.fixture(scope="module")
def pair():
    v, f = bumpy(3)
    keep = v[:, 0] > 0.25
    pv, pf, orig = cut(v, f, keep)
    truth = np.zeros(len(v), bool)
    truth[orig] = True
    return v, f, pv, pf, truth


def test_localize_finds_the_cut(pair) -> None:
    v, f, pv, pf, truth = pair
    import time

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
    iou = (r.region & truth).sum() / (r.region | truth).sum()
    print(f"[agreement] localize bumpy3 cut: IoU={iou:.3f}, cost={r.cost:.3e}, {r.timings}")
    assert iou > 0.7
    assert 0 <= r.selected_start < r.n_starts
    assert r.n_starts == 3 * FAST["centers"] + 6, "balls-and-wide-bumps: 3 per centre, and 6 plane cuts"
    assert set(r.timings) >= {"preprocessing", "total"}
    assert stages and all(0.0 <= x <= 1.0 for x, _ in stages)
    assert "Localization(" in repr(r)


# The other start shapes reach the core (their number of starts) and find the cut; the balls
# alone are only 6 starts here (IoU 0.76 measured), hence the lower bar.
@pytest.mark.parametrize(
    "starts, per_centre, min_iou",
    [("balls-and-wide-gaussians", 4, 0.8), ("gaussian", 4, 0.8), ("area-ball", 2, 0.6)],
)
def test_localize_other_starts_find_the_cut(pair, starts: str, per_centre: int, min_iou: float) -> None:
    v, f, pv, pf, truth = pair
    r = ds.localize(v, f, pv, pf, starts=starts, **FAST)  # type: ignore[arg-type]
    assert r.n_starts == per_centre * FAST["centers"] + 6
    iou = (r.region & truth).sum() / (r.region | truth).sum()
    print(f"[agreement] localize bumpy3 cut, starts={starts}: IoU={iou:.3f}")
    assert iou > min_iou


def test_localize_spectral_cuts_add_two_starts_each(pair) -> None:
    v, f, pv, pf, truth = pair
    r = ds.localize(v, f, pv, pf, spectral_cuts=2, **FAST)
    assert r.n_starts == 3 * FAST["centers"] + 6 + 4
    iou = (r.region & truth).sum() / (r.region | truth).sum()
    print(f"[agreement] localize bumpy3 cut, spectral_cuts=2: IoU={iou:.3f}")
    assert iou > 0.7
    with pytest.raises(ValueError, match="spectral_cuts"):
        ds.localize(v, f, pv, pf, spectral_cuts=-1)


def test_localize_plane_cuts_set_the_plane_starts(pair) -> None:
    v, f, pv, pf, truth = pair
    r = ds.localize(v, f, pv, pf, plane_cuts=0, **FAST)
    assert r.n_starts == 3 * FAST["centers"]
    r = ds.localize(v, f, pv, pf, plane_cuts=14, **FAST)
    assert r.n_starts == 3 * FAST["centers"] + 14
    iou = (r.region & truth).sum() / (r.region | truth).sum()
    print(f"[agreement] localize bumpy3 cut, plane_cuts=14: IoU={iou:.3f}")
    assert iou > 0.7
    with pytest.raises(ValueError, match="plane_cuts = 27 must be at most 26"):
        ds.localize(v, f, pv, pf, plane_cuts=27)
    with pytest.raises(ValueError, match="plane_cuts"):
        ds.localize(v, f, pv, pf, plane_cuts=-1)


def test_progress_false_cancels(pair) -> None:
    v, f, pv, pf, _ = pair
    with pytest.raises(ds.Cancelled):
        ds.localize(v, f, pv, pf, progress=lambda x, s: False, **FAST)


def test_progress_exception_propagates(pair) -> None:
    v, f, pv, pf, _ = pair

    class Stop(Exception):
        pass

    def cb(x: float, s: str) -> None:
        raise Stop(s)

    with pytest.raises(Stop):
        ds.localize(v, f, pv, pf, progress=cb, **FAST)


def test_localize_argument_errors(pair) -> None:
    v, f, pv, pf, _ = pair
    with pytest.raises(ValueError, match="mode"):
        ds.localize(v, f, pv, pf, mode="bogus")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="selection"):
        ds.localize(v, f, pv, pf, selection="bogus")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="starts"):
        ds.localize(v, f, pv, pf, starts="bogus")  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        ds.localize(v, f, pv, pf, progress=3)  # type: ignore[arg-type]
    with pytest.raises(ds.MeshError, match="partial mesh"):
        ds.localize(v, f, pv, pf + len(pv))
