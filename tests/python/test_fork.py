"""Issue 23, item 4: a process that forks after using the library (Python ``multiprocessing``
with the fork start method, the Linux default before Python 3.14) can still localize in the
child: no thread pool of the parent's is needed there."""

from __future__ import annotations

import multiprocessing as mp
import sys

import numpy as np
import pytest

import dualspectra as ds

from conftest import bumpy, cut

QUICK = dict(k=6, plane_cuts=2, max_iterations=8, resolution=0)


def _pair():  # type: ignore[no-untyped-def]
    v, f = bumpy(2)
    pv, pf, _ = cut(v, f, v[:, 2] > 0.2)
    return v, f, pv, pf


def _locate_in_child(queue) -> None:  # type: ignore[no-untyped-def]
    found = ds.localize(*_pair(), **QUICK)
    queue.put(int(np.count_nonzero(found.region)))


@pytest.mark.skipif(sys.platform != "linux", reason="the fork start method is Linux's")
def test_issue23_localize_in_a_forked_child_after_the_parent_used_the_library() -> None:
    # The parent uses every part that has thread pools or caches: a one-call localization, a
    # prepared shape and a spectrum.
    before = ds.localize(*_pair(), **QUICK)
    prepared = ds.Localizer(*_pair()[:2], **QUICK)
    prepared.locate(*_pair()[2:])
    ds.spectrum(*_pair()[:2], 4)
    ctx = mp.get_context("fork")
    queue = ctx.Queue()
    child = ctx.Process(target=_locate_in_child, args=(queue,))
    child.start()
    child.join(180)
    if child.is_alive():
        child.kill()
        pytest.fail("the forked child hung in dualspectra.localize")
    assert child.exitcode == 0
    assert queue.get(timeout=5) == int(np.count_nonzero(before.region))
