"""Batches of searches: many partial shapes against a library of full shapes, in this process
or on a Dask cluster (``dask.distributed``).

The work is split per full shape: one task prepares a full shape once (or loads it, or
receives it prepared) and locates on it every partial paired with it; the answers are then
merged into one ranking per partial by the core's ranking rule (the one
:func:`dualspectra.search` uses: :attr:`~dualspectra.Localization.similarity_score`, lower is
more similar, ties by the full shape's index).
Every number comes from the core; this module only distributes the calls and sorts.

With a ``shortlist`` (or a prebuilt :class:`~dualspectra.Screen`), each partial is first
ranked here by the library's screen and only its ``shortlist`` best (partial, full shape)
pairs become work for the tasks; the others are listed after the localized shapes, screened
out (as :func:`dualspectra.search` lists them). As in :func:`dualspectra.search`, a shortlist
shorter than the library and longer than two is localized in two stages: every shortlisted
pair quickly (fewer starts, iterations and eigenvalues, on the regular optimisation mesh even for a partial with holes; :attr:`BatchMatch.quick`), then the best of
each partial's quick ranking (and the second best when close behind it) again in full, in a
second round of tasks. The core decides
which pairs and in what order (``in_two_stages``, ``shapes_to_refine``,
``two_stage_order``), so a batch ranks as :func:`dualspectra.search` does.

``client=None`` runs the tasks one after the other here, without importing Dask; a
``dask.distributed.Client`` runs them on its workers (each needs the ``dualspectra`` wheel
installed; full shapes given as paths must be readable there). Both give the same results:
the core is deterministic (same inputs and options, same region and score) whatever
machine or process computes it.

What travels: each partial once (``Client.scatter``); each full shape to its task, as
arrays, as a path, or as a prepared :class:`~dualspectra.Localizer` (pickled as its
``.dsprep`` bytes, :meth:`~dualspectra.Localizer.to_bytes`); back, plain :class:`BatchMatch`
records (numbers, the region as a boolean array, strings).

Dask's workers run with ``MALLOC_TRIM_THRESHOLD_=65536``, with which glibc maps and unmaps
every large buffer afresh: a localization took twice as long. Each task lifts it while it
runs (:func:`_unhurried_malloc`).
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import math
import os
import threading
import uuid
import warnings
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Dict, Iterable, Iterator, List, Optional, Sequence, Set, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _dualspectra
from ._api import (
    DualspectraWarning,
    FullShape,
    Localizer,
    OptionValue,
    ProgressCallback,
    Screen,
    _check_fulls,
    _check_progress,
    _check_screen,
    _count,
    _mesh_pair,
    _prepared,
    _span,
)
from ._dualspectra import Cancelled, MeshError, NumericalError

if TYPE_CHECKING:
    from distributed import Client

__all__ = ["BatchMatch", "search_batch"]

#: A partial as it travels to a task: its float64 vertices and int64 faces.
_Mesh = Tuple[NDArray[np.float64], NDArray[np.int64]]


@dataclass(frozen=True, eq=False)
class BatchMatch:
    """One full shape's answer for one partial, as plain data (picklable, no native object).

    ``region`` is indexed by the full shape's vertices as given (as
    :attr:`~dualspectra.Localization.region`); ``score`` is the similarity score, lower is
    more similar. When the partial could not be located on the shape, ``score`` is ``inf``,
    ``region``, ``confidence`` and ``cost`` are ``None`` and ``error`` says why. A shape the
    screen left out of the partial's shortlist has ``score = inf``, ``region``,
    ``confidence``, ``cost`` and ``error`` ``None``, and its ``screen_score``.
    """

    #: Index of the partial in ``partials``.
    partial: int
    #: Index of the full shape in ``fulls``.
    index: int
    #: :attr:`~dualspectra.Localization.similarity_score` (``inf``: not located).
    score: float
    #: The matched region, one ``bool`` per vertex of the full shape.
    region: Optional[NDArray[np.bool_]]
    #: :attr:`~dualspectra.Localization.confidence`.
    confidence: Optional[float]
    #: :attr:`~dualspectra.Localization.cost`.
    cost: Optional[float]
    #: :attr:`~dualspectra.Localization.warnings`.
    warnings: Tuple[str, ...]
    #: Why the partial could not be located on the shape (``None`` when it was).
    error: Optional[str]
    #: The screen's score of the shape for the partial (:meth:`~dualspectra.Screen.rank`,
    #: lower is more similar; ``None`` when no screen was used).
    screen_score: Optional[float] = None
    #: How much to trust that the partial is a part of this shape rather than of another one
    #: of its ranking (:attr:`dualspectra.Match.confidence`: the core's ``search_confidences``
    #: among the located ones); ``None`` when not located.
    search_confidence: Optional[float] = None
    #: Whether ``region`` is a two-stage search's quick localization (fewer starts, iterations
    #: and eigenvalues, ranking the shortlist) rather than a full one (:attr:`dualspectra.Match.quick`).
    quick: bool = False


# glibc's mallopt parameters (malloc.h).
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3


@contextlib.contextmanager
def _unhurried_malloc() -> Iterator[None]:
    """Run the block with glibc's default-sized trim and mmap thresholds when the process
    was started with ``MALLOC_TRIM_THRESHOLD_`` (Dask's nanny sets 65536 on every worker, to
    return memory to the system). With that setting every buffer of more than 128 KiB is
    mapped and unmapped afresh and the heap is trimmed on every large free: a localization
    on one thread took 32 s (14 s of it in the kernel) instead of 18 s. Afterwards the
    process's settings are restored and free memory is returned (``malloc_trim``), as the
    setting intends. Elsewhere (no such variable, no glibc) it does nothing."""
    trim = os.environ.get("MALLOC_TRIM_THRESHOLD_")
    libc_name = ctypes.util.find_library("c")
    if trim is None or libc_name is None:
        yield
        return
    try:
        libc = ctypes.CDLL(libc_name)
        mallopt, malloc_trim = libc.mallopt, libc.malloc_trim  # glibc only
    except (OSError, AttributeError):
        yield
        return
    restore_trim = int(trim) if trim.isdigit() else 128 << 10
    mallopt(_M_TRIM_THRESHOLD, 256 << 20)
    mallopt(_M_MMAP_THRESHOLD, 32 << 20)
    try:
        yield
    finally:
        mallopt(_M_MMAP_THRESHOLD, 128 << 10)  # the fixed threshold the variable implies
        mallopt(_M_TRIM_THRESHOLD, restore_trim)
        malloc_trim(0)


#: Partials a process keeps prepared for the batch it runs (:func:`_prepared_partial`). Each
#: holds what its localizations on every full shape share: with ``scale="auto"`` the scale
#: estimate's descriptors of the partial, up to about 10 MB. A batch's partials beyond these
#: are prepared afresh for each full shape, as each task goes through its partials in order
#: (the first ones keep theirs: evicting the oldest would help no task).
_PREPARED_PARTIALS = 32

_prepared_lock = threading.Lock()
_prepared_batch: Optional[str] = None
_prepared_partials: Dict[int, "_dualspectra.PreparedPartial"] = {}


def _prepared_partial(batch: str, i: int, mesh: _Mesh) -> "_dualspectra.PreparedPartial":
    """Partial ``i`` of the batch ``batch`` (a token per :func:`search_batch` call), taken in
    once per process for every full shape its tasks locate it on there: with
    ``scale="auto"``, the scale estimate's scan of the partial is made by the first
    localization and reused by the others, as :func:`dualspectra.search` reuses it. A process
    keeps the partials of one batch, at most :data:`_PREPARED_PARTIALS`; another batch's
    replace them. Raises ``MeshError`` for a mesh the core cannot take in."""
    global _prepared_batch
    with _prepared_lock:
        if _prepared_batch != batch:
            _prepared_partials.clear()
            _prepared_batch = batch
        kept = _prepared_partials.get(i)
    if kept is not None:
        return kept
    prepared = _dualspectra.PreparedPartial(*mesh)
    with _prepared_lock:
        if _prepared_batch == batch and len(_prepared_partials) < _PREPARED_PARTIALS:
            prepared = _prepared_partials.setdefault(i, prepared)
    return prepared


def _forget_batch(batch: str) -> None:
    """Drop the partials this process keeps for ``batch`` (at its end)."""
    global _prepared_batch
    with _prepared_lock:
        if _prepared_batch == batch:
            _prepared_partials.clear()
            _prepared_batch = None


def _locate_on_full(
    index: int,
    full: FullShape,
    partials: Sequence[Tuple[int, _Mesh, bool]],
    options: Dict[str, OptionValue],
    batch: str,
    progress: Optional[ProgressCallback] = None,
) -> List[BatchMatch]:
    """One task: prepare (or load) the full shape ``index`` once and locate every partial
    ``(i, mesh, quick)`` of ``batch`` on it, as a search does (the core's
    ``locate_prepared``; quickly where ``quick``), each partial taken in once per process
    (:func:`_prepared_partial`).

    A partial the core cannot locate on this shape (``ValueError``, ``NumericalError``)
    becomes a match with its ``error``; an invalid mesh (``MeshError``) or cancelling
    raises. The library's warnings are kept in the matches, not emitted.
    """
    out: List[BatchMatch] = []
    with warnings.catch_warnings(), _unhurried_malloc():
        warnings.simplefilter("ignore", DualspectraWarning)
        localizer = _prepared(full, options)
        for k, (i, mesh, quick) in enumerate(partials):
            part = _span(progress, k / len(partials), (k + 1) / len(partials))
            prepared = _prepared_partial(batch, i, mesh)
            try:
                found = localizer._native.locate_prepared(prepared, quick, part)
            except MeshError:
                raise
            except (ValueError, NumericalError) as exc:
                out.append(BatchMatch(i, index, math.inf, None, None, None, (), f"{type(exc).__name__}: {exc}"))
                continue
            out.append(
                BatchMatch(
                    i,
                    index,
                    found.similarity_score,
                    found.region,
                    found.confidence,
                    found.cost,
                    found.warnings,
                    None,
                    quick=quick,
                )
            )
    return out


def _tasks(n_partials: int, n_fulls: int, pairs: Optional[Iterable[Tuple[int, int]]]) -> Dict[int, List[int]]:
    """``{full index: [partial indices]}``, in increasing order, from the pairs (all if ``None``)."""
    if pairs is None:
        return {j: list(range(n_partials)) for j in range(n_fulls)} if n_partials else {}
    tasks: Dict[int, Set[int]] = {}
    for pair in pairs:
        try:
            i, j = (_count(x, "a pair's index") for x in pair)
        except ValueError:
            raise ValueError(f"pairs: {pair!r} is not a (partial index, full index) pair") from None
        if i >= n_partials or j >= n_fulls:
            raise ValueError(f"pairs: {(i, j)} is out of range ({n_partials} partials, {n_fulls} full shapes)")
        tasks.setdefault(j, set()).add(i)
    return {j: sorted(tasks[j]) for j in sorted(tasks)}


def search_batch(
    partials: Sequence[Tuple[ArrayLike, ArrayLike]],
    fulls: Sequence[FullShape],
    *,
    top: Optional[int] = None,
    pairs: Optional[Iterable[Tuple[int, int]]] = None,
    shortlist: Optional[int] = None,
    screen: Optional[Screen] = None,
    client: Optional[Client] = None,
    progress: Optional[ProgressCallback] = None,
    **options: OptionValue,
) -> List[List[BatchMatch]]:
    """Rank the full shapes for each partial shape (:func:`dualspectra.search` for many
    partials), split per full shape: each full shape is prepared once.

    Args:
        partials: the partial shapes, ``(vertices, faces)`` each.
        fulls: the full shapes, as for :func:`dualspectra.search`: prepared
            :class:`~dualspectra.Localizer` objects (pickled to the workers), meshes
            ``(vertices, faces)`` (prepared by the task, with ``options``) or paths of
            prepared shapes (``.dsprep``, loaded by the task: give paths the workers can read).
        top: keep the ``top`` best matches per partial (default: all).
        pairs: compute only these ``(partial index, full index)`` pairs (default: every
            partial against every full shape); a partial is then ranked among its pairs.
        shortlist: locate each partial on the ``shortlist`` full shapes (among its pairs)
            that the library's screen ranks best only (default: on every one, no screen).
            A shortlist shorter than the full shapes and longer than two is localized in
            two stages, as by :func:`dualspectra.search`: quickly, then the best (and the second
            best when its quick score is within 4 % of the best's) again in full (the others
            keep their quick localization, :attr:`BatchMatch.quick`).
            The screen ranks the partials here, before the tasks start; the shapes it leaves
            out follow the localized ones in the partial's ranking, in screen order, with
            ``score = inf`` and their ``screen_score``. It uses the ``scale`` option given,
            else the first full shape's when that is a :class:`~dualspectra.Localizer`,
            else ``"same"``.
        screen: the library's :class:`~dualspectra.Screen` (shape ``i`` is ``fulls[i]``;
            e.g. :meth:`~dualspectra.Screen.load` of a ``dualspectra index`` file). Default
            with a ``shortlist``: ``Screen(fulls)``, built here once, which loads paths of
            prepared shapes (give ``screen`` when they are only readable on the workers).
            With a screen and no ``shortlist``, every pair is localized and every match has
            its ``screen_score``.
        client: a ``dask.distributed.Client`` to run the tasks on (one per full shape);
            ``None``: run them here, one after the other (Dask is not imported).
        progress: optional ``callback(fraction, stage)``, called here; returning ``False``
            cancels (on a cluster: the tasks not yet finished are cancelled). With a client
            it is called as tasks finish. The screen, if any, takes its first 10 %.
        **options: the core's options by name, for the meshes of ``fulls`` (``threads`` also
            for the paths, ``scale`` also for the screen), as for :func:`dualspectra.search`.

    Returns:
        ``rankings[i]``: partial ``i``'s :class:`BatchMatch` list, best first (ties by full
        shape index), at most ``top`` long. A partial that cannot be located on a shape
        has a match with ``score = inf`` and its ``error`` there (unlike
        :func:`dualspectra.search`, the batch does not raise when that is every shape).

    Raises:
        MeshError: a mesh cannot be used, or a prepared-shape file cannot be loaded.
        Cancelled: the callback returned ``False``. ValueError: an option or a pair is
        invalid, ``shortlist`` is 0, or ``screen`` does not hold one shape per full shape.
        With a client, an exception raised in a task is raised here.
    """
    _check_progress(progress)
    meshes: List[_Mesh] = [_mesh_pair(p, f"partial {i}") for i, p in enumerate(partials)]
    if shortlist is not None:
        shortlist = _count(shortlist, "shortlist")
        if shortlist == 0:
            raise ValueError("search_batch: the shortlist must hold at least one shape")
    screening = screen is not None or (shortlist is not None and shortlist < len(fulls))
    checked = _check_fulls(fulls, options, ("threads", "scale") if screening else ("threads",))
    if screen is not None:
        _check_screen(screen, len(checked))
    if top is not None:
        top = _count(top, "top")
    tasks = _tasks(len(meshes), len(checked), pairs)
    screened_out: List[List[BatchMatch]] = [[] for _ in meshes]
    scores: Dict[Tuple[int, int], float] = {}
    two_stage: Set[int] = set()
    if screening:
        if screen is None:
            screen = _library_screen(checked, _span(progress, 0.0, 0.05))
        scale = options.get("scale", checked[0].options["scale"] if isinstance(checked[0], Localizer) else "same")
        ranked = _rank_by_screen(screen, meshes, tasks, scale, _span(progress, 0.05, 0.1))
        kept: List[Tuple[int, int]] = []
        for i, order in enumerate(ranked):
            chosen = order if shortlist is None else order[:shortlist]
            if _dualspectra.in_two_stages(len(chosen), len(order)):
                two_stage.add(i)
            for j, score in chosen:
                kept.append((i, j))
                scores[(i, j)] = score
            screened_out[i] = [BatchMatch(i, j, math.inf, None, None, None, (), None, score) for j, score in order[len(chosen) :]]
        tasks = _tasks(len(meshes), len(checked), kept)
        progress = _span(progress, 0.1, 1.0)
    # The first round: every pair, quick for the partials searched in two stages; the second:
    # the pairs the core picks from those quick rankings, in full.
    quick_share = sum(_QUICK_COST if i in two_stage else 1.0 for w in tasks.values() for i in w)
    refined_share = 2.0 * len(two_stage)
    split = quick_share / max(quick_share + refined_share, 1e-9)
    batch = uuid.uuid4().hex
    try:
        first = _run(client, tasks, checked, meshes, two_stage, options, batch, _span(progress, 0.0, split))
        by_partial: List[List[BatchMatch]] = [[] for _ in meshes]
        for m in first:
            by_partial[m.partial].append(m)
        refine = {i: _dualspectra.shapes_to_refine([(m.score, m.index) for m in by_partial[i]]) for i in sorted(two_stage)}
        refined_pairs = [(i, j) for i, js in refine.items() for j in js]
        second = _run(
            client, _tasks(len(meshes), len(checked), refined_pairs), checked, meshes, set(), options, batch,
            _span(progress, split, 1.0),
        )
    finally:
        _forget(client, batch)
    refined: List[List[BatchMatch]] = [[] for _ in meshes]
    for m in second:
        refined[m.partial].append(m)
    rankings: List[List[BatchMatch]] = []
    for i, found in enumerate(by_partial):
        if i in two_stage:
            full = refined[i]
            stages = _dualspectra.two_stage_order([(m.score, m.index) for m in full], [(m.score, m.index) for m in found])
            ranking = [found[at] if quick else full[at] for quick, at in stages]
        else:
            ranking = [found[at] for at in _dualspectra.rank([(m.score, m.index) for m in found])]
        ranking = [m if (m.partial, m.index) not in scores else replace(m, screen_score=scores[(m.partial, m.index)]) for m in ranking]
        rankings.append(_with_search_confidences(ranking))
    return [(r + out)[:top] for r, out in zip(rankings, screened_out)]


#: Time of a quick localization over a full one, for splitting progress between the rounds.
_QUICK_COST = 0.3


def _run(
    client: Optional[Client],
    tasks: Dict[int, List[int]],
    fulls: List[FullShape],
    meshes: List[_Mesh],
    quick: Set[int],
    options: Dict[str, OptionValue],
    batch: str,
    progress: Optional[ProgressCallback],
) -> List[BatchMatch]:
    """Every match of ``tasks`` (partials in ``quick`` located quickly), here or on ``client``."""
    if client is None:
        results = _run_here(tasks, fulls, meshes, quick, options, batch, progress)
    else:
        results = _run_on(client, tasks, fulls, meshes, quick, options, batch, progress)
    return [m for matches in results for m in matches]


def _forget(client: Optional[Client], batch: str) -> None:
    """Drop the partials kept for ``batch`` here, and on the workers of ``client``."""
    _forget_batch(batch)
    if client is not None:
        with contextlib.suppress(Exception):  # a lost worker keeps nothing; the answer stands
            client.run(_forget_batch, batch)  # type: ignore[no-untyped-call, unused-ignore]


def _with_search_confidences(ranking: List[BatchMatch]) -> List[BatchMatch]:
    """``ranking`` with each located match's ``search_confidence`` among the located ones."""
    located = [m for m in ranking if m.region is not None and m.confidence is not None]
    confidences = _dualspectra.search_confidences([(m.score, float(m.confidence or 0.0)) for m in located])
    found = {id(m): c for m, c in zip(located, confidences)}
    return [replace(m, search_confidence=found[id(m)]) if id(m) in found else m for m in ranking]


def _library_screen(fulls: List[FullShape], progress: Optional[ProgressCallback]) -> Screen:
    """The screen of the checked full shapes, built here (the intake's notes are left to the
    tasks' matches, as without a screen)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DualspectraWarning)
        return Screen(fulls, progress=progress)


def _rank_by_screen(
    screen: Screen,
    meshes: List[_Mesh],
    tasks: Dict[int, List[int]],
    scale: Union[str, float],
    progress: Optional[ProgressCallback],
) -> List[List[Tuple[int, float]]]:
    """Per partial, the full shapes it is paired with in ``tasks`` as ``(full index, screen
    score)``, best first. A partial paired with no shape is not ranked."""
    paired: List[Set[int]] = [set() for _ in meshes]
    for j, wanted in tasks.items():
        for i in wanted:
            paired[i].add(j)
    out: List[List[Tuple[int, float]]] = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DualspectraWarning)  # the tasks' matches keep them
        for i, (vertices, faces) in enumerate(meshes):
            part = _span(progress, i / len(meshes), (i + 1) / len(meshes))
            ranked = screen.rank(vertices, faces, scale, progress=part) if paired[i] else []
            out.append([(j, score) for j, score in ranked if j in paired[i]])
    return out


def _run_here(
    tasks: Dict[int, List[int]],
    fulls: List[FullShape],
    meshes: List[_Mesh],
    quick: Set[int],
    options: Dict[str, OptionValue],
    batch: str,
    progress: Optional[ProgressCallback],
) -> List[List[BatchMatch]]:
    """The tasks in this process, one after the other."""
    results = []
    for t, (j, wanted) in enumerate(tasks.items()):
        part = _span(progress, t / len(tasks), (t + 1) / len(tasks))
        results.append(_locate_on_full(j, fulls[j], [(i, meshes[i], i in quick) for i in wanted], options, batch, part))
    return results


def _run_on(
    client: Client,
    tasks: Dict[int, List[int]],
    fulls: List[FullShape],
    meshes: List[_Mesh],
    quick: Set[int],
    options: Dict[str, OptionValue],
    batch: str,
    progress: Optional[ProgressCallback],
) -> List[List[BatchMatch]]:
    """The tasks on a Dask cluster, one per full shape; the partials are scattered once."""
    from distributed import as_completed

    if not tasks:
        return []
    needed = sorted({i for wanted in tasks.values() for i in wanted})
    scattered = dict(zip(needed, client.scatter([meshes[i] for i in needed])))  # type: ignore[no-untyped-call, unused-ignore]
    futures = [
        client.submit(
            _locate_on_full,
            j,
            fulls[j],
            [(i, scattered[i], i in quick) for i in wanted],
            options,
            batch,
            pure=False,
        )
        for j, wanted in tasks.items()
    ]
    try:
        for done, future in enumerate(as_completed(futures), start=1):  # type: ignore[no-untyped-call, unused-ignore]
            if future.status == "error":
                future.result()  # raises the task's exception here
            if progress is not None and progress(done / len(futures), "searched a full shape") is False:
                raise Cancelled("cancelled by the progress callback")
        return [future.result() for future in futures]
    finally:
        client.cancel(futures)  # type: ignore[no-untyped-call, unused-ignore]
        client.cancel(list(scattered.values()))  # type: ignore[no-untyped-call, unused-ignore]
