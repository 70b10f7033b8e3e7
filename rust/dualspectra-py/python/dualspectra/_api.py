"""The implementation of the :mod:`dualspectra` package (its ``__init__`` re-exports the API
and nothing else). Conversion only: every computation is the native module's."""


from __future__ import annotations

import os
import warnings
from typing import (
    TYPE_CHECKING,
    Any,
    Callable,
    Dict,
    Iterable,
    List,
    Literal,
    Optional,
    Sequence,
    Set,
    Tuple,
    Union,
    final,
    overload,
)

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _dualspectra
from ._dualspectra import Cancelled, Localization, Match, MeshError, NumericalError

if TYPE_CHECKING:
    from scipy.sparse import csc_matrix  # type: ignore[import-untyped, unused-ignore]

#: ``callback(fraction, stage)``: ``fraction`` in [0, 1] of the whole run, ``stage`` a short
#: name. Return ``False`` to cancel (``None`` or ``True`` to go on).
ProgressCallback = Callable[[float, str], Optional[bool]]

#: The value of one localizer option: an ``int`` or ``float`` in its range, or a ``str``
#: (a choice's name, or a number as text).
OptionValue = Union[int, float, str]

#: A path to a file: a str or an ``os.PathLike``.
PathLike = Union[str, "os.PathLike[str]"]

_INDEX_MAX = np.iinfo(np.int64).max


class DualspectraWarning(UserWarning):
    """Something was repaired or skipped: the message says what (see the module doc)."""


def options_schema() -> List[Dict[str, Any]]:
    """The localizer's options as the core defines them, in the order front ends list them.

    One dict per option: ``name`` (the keyword argument), ``label`` (a short title),
    ``type`` (``"int"``, ``"float"`` or ``"choice"``), ``min`` and ``max`` (numbers) or
    ``choices`` (names), ``default`` and ``doc``. A new list on each call.
    """
    return _dualspectra.options_schema()


def _options_doc() -> str:
    """The options as docstring lines, generated from :func:`options_schema`."""
    lines = []
    for spec in options_schema():
        if spec["type"] == "choice":
            kind = " | ".join(repr(c) for c in spec["choices"])
        else:
            kind = f"{spec['type']} in [{spec['min']}, {spec['max']}]"
        lines.append(f"            {spec['name']} ({kind}, default {spec['default']!r}): {spec['doc']}")
    return "\n".join(lines)


def _mesh_arrays(vertices: ArrayLike, faces: ArrayLike, what: str = "mesh") -> Tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Contiguous float64 ``(n, 3)`` and int64 ``(m, 3)`` copies (or views) of the inputs.

    Shapes and kinds are checked here for clear messages; index ranges, finiteness and
    the mesh invariants are checked by the core.
    """
    v = np.asarray(vertices)
    if v.ndim != 2 or v.shape[1] != 3:
        raise MeshError(f"{what}: vertices must have shape (n, 3), got {v.shape}")
    if v.dtype.kind not in "fiu":
        raise TypeError(f"{what}: vertices must be a real numeric array, got dtype {v.dtype}")
    f = np.asarray(faces)
    if f.ndim != 2 or f.shape[1] != 3:
        raise MeshError(f"{what}: faces must have shape (m, 3), got {f.shape}")
    if f.dtype.kind not in "iu" and f.size > 0:
        raise TypeError(f"{what}: faces must be an integer array, got dtype {f.dtype}")
    if f.dtype.kind == "u" and f.size > 0 and int(f.max()) > _INDEX_MAX:
        raise MeshError(f"{what}: face index {int(f.max())} is out of range")
    return np.ascontiguousarray(v, dtype=np.float64), np.ascontiguousarray(f, dtype=np.int64)


def _check_progress(progress: Optional[ProgressCallback]) -> None:
    if progress is not None and not callable(progress):
        raise TypeError("progress must be callable as progress(fraction, stage)")


def _warn(messages: Iterable[str]) -> None:
    """Emit each message as a :class:`DualspectraWarning` at the public function's caller."""
    for message in messages:
        warnings.warn(message, DualspectraWarning, stacklevel=3)


@final
class Localizer:
    """A full shape prepared once for locating partial shapes on it.

    Preparing (the constructor) computes what depends on the full shape alone: its scale,
    the decimated optimisation mesh, the scale-invariant metric, descriptors, the plane-cut
    directions and one symbolic factorization. :meth:`locate` then runs the matching for one partial.
    Both release the GIL; :meth:`locate` may be called from several threads at once on one
    ``Localizer``. ``localize(V, F, P, G, **options)`` is
    ``Localizer(V, F, **options).locate(P, G)`` in one call. A prepared shape is saved and
    loaded (:meth:`save`, :meth:`load`), turned into bytes and back (:meth:`to_bytes`,
    :meth:`from_bytes`) and pickled (as those bytes, e.g. for a Dask worker).

    Args:
        vertices, faces: the full shape M, ``(n, 3)`` and ``(m, 3)``. Degenerate faces and
            vertices in no face are left out and non-manifold edges and vertices split (with
            a warning); results are still indexed by these ``n`` vertices.
        progress: optional ``callback(fraction, stage)`` for the preparation; returning
            ``False`` cancels (:class:`Cancelled`), an exception it raises (or Ctrl-C) is
            re-raised.
        **options: the core's options by name (``ValueError`` for an unknown name or a value
            out of range; see :func:`options_schema`):

{options}

    Raises:
        MeshError: the full mesh cannot be used (index out of range, non-finite coordinate,
        no faces, every face degenerate). Cancelled: the callback returned ``False``.
    """

    __slots__ = ("_native",)

    def __init__(
        self,
        vertices: ArrayLike,
        faces: ArrayLike,
        *,
        progress: Optional[ProgressCallback] = None,
        **options: OptionValue,
    ) -> None:
        v, f = _mesh_arrays(vertices, faces, "full mesh")
        _check_progress(progress)
        self._native = _dualspectra.Localizer(v, f, options, progress)
        _warn(self._native.warnings)

    def locate(
        self,
        partial_vertices: ArrayLike,
        partial_faces: ArrayLike,
        *,
        progress: Optional[ProgressCallback] = None,
    ) -> Localization:
        """Find the region of the full shape that the partial mesh ``(P, G)`` is.

        Args:
            partial_vertices, partial_faces: the partial shape N, ``(p, 3)`` and ``(q, 3)``
                (degenerate faces and loose vertices are left out and non-manifold edges
                and vertices split, with a warning).
            progress: optional ``callback(fraction, stage)``; returning ``False`` cancels.

        Returns:
            A :class:`Localization`; its per-vertex arrays have :attr:`n_vertices` entries,
            its ``timings["preparation"]`` is 0 (see :attr:`preparation_seconds`).

        Raises:
            MeshError: the partial mesh cannot be used (index out of range, non-finite
            coordinate, no faces, every face degenerate, no boundary, no interior vertex,
            more area than the full shape).
            Cancelled: the callback returned ``False``.
        """
        pv, pf = _mesh_arrays(partial_vertices, partial_faces, "partial mesh")
        _check_progress(progress)
        result = self._native.locate(pv, pf, progress)
        already = set(self._native.warnings)
        _warn(w for w in result.warnings if w not in already)
        return result

    @property
    def n_vertices(self) -> int:
        """Vertices of the full mesh as given (the length of every per-vertex result)."""
        return self._native.n_vertices

    @property
    def optimisation_vertices(self) -> int:
        """Vertices of the optimisation mesh (the full shape decimated to about ``resolution``)."""
        return self._native.optimisation_vertices

    @property
    def warnings(self) -> Tuple[str, ...]:
        """Notes on the full mesh's intake and the preparation (repeated in every result)."""
        return self._native.warnings

    @property
    def options(self) -> Dict[str, OptionValue]:
        """Every option it was prepared with, by name (a new dict on each access)."""
        return self._native.options

    @property
    def preparation_seconds(self) -> float:
        """Wall-clock seconds the preparation took (for a loaded shape: the loading)."""
        return self._native.preparation_seconds

    def save(self, path: PathLike) -> None:
        """Write the prepared shape to ``path`` (by convention ``*.dsprep``; the core's
        versioned format), to :meth:`load` it later instead of preparing the shape again.

        The file keeps the options and the numbering of the vertices as given (results of
        the loaded shape are indexed by them). Raises ``OSError`` if it cannot be written.
        """
        self._native.save(os.fspath(path))

    @classmethod
    def load(cls, path: PathLike, *, threads: Optional[int] = None) -> "Localizer":
        """A prepared shape written by :meth:`save`: it locates as the saved one did (same
        regions, scores and similarity scores), results indexed by the vertices it was
        prepared with (for a file of ``dualspectra prepare``, the mesh file's vertex records).

        Args:
            path: the ``.dsprep`` file.
            threads: worker threads from now on (0: all cores); default: the saved option.

        Raises:
            MeshError: the file is not a prepared shape (foreign), was written by another
            format version (stale: prepare the shape again), or is truncated or corrupted;
            the message names the file and the problem. OSError: it cannot be read.
        """
        native = _dualspectra.Localizer.load(os.fspath(path), None if threads is None else _count(threads, "threads"))
        localizer = cls._wrap(native)
        _warn(native.warnings)
        return localizer

    def to_bytes(self) -> bytes:
        """The prepared shape as bytes: what :meth:`save` writes."""
        return self._native.to_bytes()

    @classmethod
    def from_bytes(cls, data: Union[bytes, bytearray, memoryview], *, threads: Optional[int] = None) -> "Localizer":
        """A prepared shape from :meth:`to_bytes`' bytes (errors and ``threads`` as :meth:`load`)."""
        native = _dualspectra.Localizer.from_bytes(
            data if isinstance(data, bytes) else bytes(data), None if threads is None else _count(threads, "threads")
        )
        localizer = cls._wrap(native)
        _warn(native.warnings)
        return localizer

    @classmethod
    def _wrap(cls, native: _dualspectra.Localizer) -> "Localizer":
        localizer = cls.__new__(cls)
        localizer._native = native
        return localizer

    def __reduce__(self) -> Tuple[Callable[[bytes, Optional[str]], "Localizer"], Tuple[bytes, Optional[str]]]:
        # Pickled as its bytes (and the intake's note, which the file does not keep), e.g. to
        # ship a prepared shape to a Dask worker; unpickling warns about nothing.
        return (_unpickle_localizer, (self._native.to_bytes(), self._native.intake_note))

    def __repr__(self) -> str:
        return repr(self._native)


def _unpickle_localizer(data: bytes, intake_note: Optional[str]) -> Localizer:
    return Localizer._wrap(_dualspectra.Localizer.from_bytes(data, None, intake_note))


def localize(
    full_vertices: ArrayLike,
    full_faces: ArrayLike,
    partial_vertices: ArrayLike,
    partial_faces: ArrayLike,
    *,
    progress: Optional[ProgressCallback] = None,
    **options: OptionValue,
) -> Localization:
    """Find the region of the full mesh that the partial mesh corresponds to.

    The one-call form of :class:`Localizer` (use that to locate several partials on one full
    shape: the preparation is then done once).

    Args:
        full_vertices, full_faces: the full shape M, ``(n, 3)`` and ``(m, 3)``.
        partial_vertices, partial_faces: the partial shape N. For both meshes, degenerate
            faces and vertices in no face are left out and non-manifold edges and vertices
            split (with a warning).
        progress: optional ``callback(fraction, stage)``; returning ``False`` cancels.
        **options: the core's options by name (``ValueError`` for an unknown name or a value
            out of range; see :func:`options_schema`):

{options}

    Returns:
        A :class:`Localization` (``region`` boolean mask over the ``n`` full-mesh vertices,
        soft ``score``, ``potential``, spectra, ``cost``, ``confidence`` (in [0, 1], the
        estimated probability that the partial is part of ``full`` and ``region`` overlaps
        the true region with IoU >= 0.5),
        ``candidates``, ``timings``, ``warnings``).

    Raises:
        MeshError: a mesh cannot be used (as for :class:`Localizer`). ValueError: the
        partial cannot be matched (as for :meth:`Localizer.locate`). Cancelled: the
        callback returned ``False``. An exception raised by the callback, or
        ``KeyboardInterrupt`` (Ctrl-C), is re-raised.
    """
    fv, ff = _mesh_arrays(full_vertices, full_faces, "full mesh")
    pv, pf = _mesh_arrays(partial_vertices, partial_faces, "partial mesh")
    _check_progress(progress)
    result = _dualspectra.localize(fv, ff, pv, pf, options, progress)
    _warn(result.warnings)
    return result


#: A full shape to search: a prepared :class:`Localizer`, a mesh ``(vertices, faces)``
#: (prepared with the options given) or the path of a prepared shape (``.dsprep``, loaded).
FullShape = Union[Localizer, Tuple[ArrayLike, ArrayLike], PathLike]


def _mesh_pair(mesh: Any, what: str) -> Tuple[NDArray[np.float64], NDArray[np.int64]]:
    """``(vertices, faces)`` as :func:`_mesh_arrays` gives them, from a pair."""
    try:
        vertices, faces = mesh
    except (TypeError, ValueError):
        raise TypeError(f"{what} must be a (vertices, faces) pair, got {type(mesh).__name__}") from None
    return _mesh_arrays(vertices, faces, what)


def _is_path(full: Any) -> bool:
    return isinstance(full, (str, os.PathLike))


def _check_fulls(
    fulls: Sequence[FullShape], options: Dict[str, OptionValue], used: Tuple[str, ...] = ("threads",)
) -> List[FullShape]:
    """The shapes as a list, each checked for its kind (arrays converted); a warning when
    options other than ``used`` (which apply to prepared shapes too) are given for prepared
    shapes (which keep theirs)."""
    out: List[FullShape] = []
    for i, full in enumerate(fulls):
        if isinstance(full, Localizer) or _is_path(full):
            out.append(full)
        elif isinstance(full, (tuple, list)):
            out.append(_mesh_pair(full, f"full shape {i}"))
        else:
            raise TypeError(
                f"full shape {i}: expected a Localizer, a (vertices, faces) pair or the path of a prepared shape, "
                f"got {type(full).__name__}"
            )
    if any(not isinstance(f, tuple) for f in out) and set(options) - set(used):
        _warn(["prepared shapes keep the options they were prepared with; the options given apply to the meshes only"])
    return out


def _prepared(full: FullShape, options: Dict[str, OptionValue], progress: Optional[ProgressCallback] = None) -> Localizer:
    """A checked full shape (:func:`_check_fulls`) as a prepared one."""
    if isinstance(full, Localizer):
        return full
    if isinstance(full, (str, os.PathLike)):
        threads = options.get("threads")
        return Localizer.load(full, threads=None if threads is None else _count(threads, "threads"))
    vertices, faces = full
    return Localizer(vertices, faces, progress=progress, **options)


def _check_screen(screen: Any, n_fulls: int) -> None:
    """``screen`` is a :class:`Screen` of ``n_fulls`` shapes."""
    if not isinstance(screen, Screen):
        raise TypeError(f"screen must be a dualspectra.Screen, got {type(screen).__name__}")
    if len(screen) != n_fulls:
        raise ValueError(
            f"the screen holds {len(screen)} shapes, {n_fulls} full shapes were given (build it from the same shapes, in order)"
        )


def _span(progress: Optional[ProgressCallback], lo: float, hi: float) -> Optional[ProgressCallback]:
    """``progress`` for a part of the run: fractions of the part mapped into ``[lo, hi]``."""
    if progress is None:
        return None
    report = progress
    return lambda fraction, stage: report(lo + (hi - lo) * fraction, stage)


@final
class Screen:
    """A library of full shapes described once for screening: a few SHOT descriptors per
    shape (about 64 KB), so that :meth:`rank` orders the whole library for a partial in a
    fraction of a second and only the most promising shapes need localizing
    (``search(..., screen=)``, ``search_batch(..., shortlist=)``). The core's ``Screen``;
    docs/algorithm.md, "Screening a library".

    A screen is saved and loaded (:meth:`save`, :meth:`load`: the ``.dsscreen`` files that
    ``dualspectra index FULL... -o LIB.dsscreen`` writes, labelled with the shapes' paths),
    turned into bytes and back (:meth:`to_bytes`, :meth:`from_bytes`) and pickled (as those
    bytes). Describing and ranking release the GIL.

    Args:
        fulls: the full shapes, as for :func:`search`: meshes ``(vertices, faces)``,
            prepared :class:`Localizer` objects (their full mesh is described) or paths of
            prepared shapes (``.dsprep``: loaded, described and dropped one at a time).
            Shape ``i`` of the screen is ``fulls[i]``.
        labels: one name per shape (e.g. its file), kept in the file; default: empty.
        progress: optional ``callback(fraction, stage)``, called after each shape;
            returning ``False`` cancels (:class:`Cancelled`), an exception it raises (or
            Ctrl-C) is re-raised.

    Raises:
        ValueError: no shape, a shape with no area, or not one label per shape.
        MeshError: a mesh cannot be used, or a prepared-shape file cannot be loaded.
        Cancelled: the callback returned ``False``.
    """

    __slots__ = ("_native",)

    def __init__(
        self,
        fulls: Sequence[FullShape],
        *,
        labels: Optional[Sequence[str]] = None,
        progress: Optional[ProgressCallback] = None,
    ) -> None:
        shapes: List[Any] = [
            full._native if isinstance(full, Localizer) else os.fspath(full) if isinstance(full, (str, os.PathLike)) else full
            for full in _check_fulls(fulls, {})
        ]
        if labels is not None:
            if isinstance(labels, str) or not all(isinstance(label, str) for label in labels):
                raise TypeError("labels must be a sequence of str, one per full shape")
            labels = list(labels)
        _check_progress(progress)
        self._native = _dualspectra.Screen(shapes, labels, progress)
        _warn(self._native.warnings)

    def rank(
        self,
        vertices: ArrayLike,
        faces: ArrayLike,
        scale: Union[str, float] = "same",
        *,
        progress: Optional[ProgressCallback] = None,
    ) -> List[Tuple[int, float]]:
        """Every shape's screen score for the partial ``(vertices, faces)``, best first.

        The score of a shape is its position in the library by the mean distance from the
        partial's descriptors to the nearest of the shape's, weighed against the library's
        median shape and against how alike the partial's own descriptors are (the mean of the
        two positions; lower is more similar; not comparable with
        :attr:`Localization.similarity_score`).

        Args:
            vertices, faces: the partial shape, ``(p, 3)`` and ``(q, 3)`` (repaired as for
                :meth:`Localizer.locate`, with a warning).
            scale: the partial's units, as the ``scale`` option: ``"same"`` (the shapes'
                units: a shape smaller than the partial scores ``inf``), ``"auto"`` (unknown
                units) or a positive factor the partial's coordinates are multiplied by.
            progress: optional ``callback(fraction, stage)``; returning ``False`` cancels.

        Returns:
            ``[(index, score), ...]`` for every shape, lowest score first, ties by the lower
            distance, then by index, ``inf`` (the partial cannot be part of that shape in
            these units) last.

        Raises:
            MeshError: the partial mesh cannot be used. ValueError: ``scale`` is not
            ``"same"``, ``"auto"`` or a positive number. Cancelled: the callback returned
            ``False``.
        """
        pv, pf = _mesh_arrays(vertices, faces, "partial mesh")
        if isinstance(scale, bool) or not isinstance(scale, (str, int, float, np.integer, np.floating)):
            raise TypeError(f'scale must be "same", "auto" or a positive number, got {type(scale).__name__}')
        _check_progress(progress)
        ranked, notes = self._native.rank(pv, pf, scale if isinstance(scale, str) else float(scale), progress)
        _warn(notes)
        return ranked

    @property
    def labels(self) -> Tuple[str, ...]:
        """Each shape's label (empty strings unless given; a file of ``dualspectra index``:
        the shapes' paths relative to the file's folder)."""
        return self._native.labels

    @property
    def nbytes(self) -> Tuple[int, int]:
        """Bytes held per shape and for the basis all shapes share (the memory a library
        takes is about ``len(screen) * per_shape + basis``)."""
        return self._native.nbytes

    def save(self, path: PathLike) -> None:
        """Write the screen to ``path`` (by convention ``*.dsscreen``; the core's versioned
        format, as ``dualspectra index`` writes). Raises ``OSError`` if it cannot be written."""
        self._native.save(os.fspath(path))

    @classmethod
    def load(cls, path: PathLike) -> "Screen":
        """A screen written by :meth:`save` or ``dualspectra index``: it ranks as the saved
        one did.

        Raises:
            MeshError: the file is not a screen (foreign), was written by another format
            version (stale: make the screen again), or is truncated or corrupted; the message
            names the file and the problem. OSError: it cannot be read.
        """
        return cls._wrap(_dualspectra.Screen.load(os.fspath(path)))

    def to_bytes(self) -> bytes:
        """The screen as bytes: what :meth:`save` writes."""
        return self._native.to_bytes()

    @classmethod
    def from_bytes(cls, data: Union[bytes, bytearray, memoryview]) -> "Screen":
        """A screen from :meth:`to_bytes`' bytes (errors as :meth:`load`)."""
        return cls._wrap(_dualspectra.Screen.from_bytes(data if isinstance(data, bytes) else bytes(data)))

    @classmethod
    def _wrap(cls, native: _dualspectra.Screen) -> "Screen":
        screen = cls.__new__(cls)
        screen._native = native
        return screen

    def __reduce__(self) -> Tuple[Callable[[bytes], "Screen"], Tuple[bytes]]:
        # Pickled as its bytes (the intake's notes were given when it was made).
        return (_unpickle_screen, (self._native.to_bytes(),))

    def __len__(self) -> int:
        return len(self._native)

    def __repr__(self) -> str:
        return repr(self._native)


def _unpickle_screen(data: bytes) -> Screen:
    return Screen._wrap(_dualspectra.Screen.from_bytes(data))


def search(
    partial: Tuple[ArrayLike, ArrayLike],
    fulls: Sequence[FullShape],
    *,
    top: Optional[int] = None,
    shortlist: Optional[int] = None,
    screen: Optional[Screen] = None,
    progress: Optional[ProgressCallback] = None,
    **options: OptionValue,
) -> List[Match]:
    """Which of the full shapes is the partial shape a part of, and where: the partial is
    located on each and the shapes are ranked by :attr:`Localization.similarity_score`
    (lower is more similar; comparable across shapes of different size and meshing). With
    ``shortlist`` below the number of shapes, a screen (a few SHOT descriptors per shape)
    ranks them first and the partial is located on the ``shortlist`` best only (of the
    meshes among ``fulls``, only those are prepared): quickly (fewer starts, iterations and eigenvalues, on the regular optimisation mesh even for a partial with holes,
    :attr:`Match.quick`), then again in full on the best of those (and the second best
    when its quick score is within 4 % of the best's), which rank first.

    Args:
        partial: the partial shape N, ``(vertices, faces)``.
        fulls: the full shapes: prepared :class:`Localizer` objects (used with the options
            they were prepared with), meshes ``(vertices, faces)`` (prepared here with
            ``options``) or paths of prepared shapes (``.dsprep``, :meth:`Localizer.load`).
        top: return the ``top`` best matches only (default: all).
        shortlist: locate the partial on the ``shortlist`` shapes the screen ranks best
            (default: every shape, no screen); the others follow in screen order with
            ``localization = None``, ``error = None`` and their ``screen_score``. The screen
            uses the first shape's ``scale`` option and describes meshes as given; a mesh is
            prepared only if it is shortlisted, just before the partial is located on it.
        screen: a :class:`Screen` of these shapes (``Screen(fulls)``, or loaded; shape
            ``i`` is ``fulls[i]``), so that repeated searches do not describe the library
            again; every match then has its ``screen_score``.
        progress: optional ``callback(fraction, stage)`` over the whole search (preparing
            the meshes, then locating on each shape; with a ``shortlist``: describing the
            shapes unless ``screen`` is given, screening, then preparing each shortlisted
            mesh and locating on each shortlisted shape); returning ``False`` cancels.
        **options: the core's options by name, for the meshes of ``fulls`` (as for
            :class:`Localizer`; a warning when they are given with prepared shapes, apart
            from ``threads``).

    Returns:
        The matches, best first (ties by index): :class:`Match` with ``index`` (into
        ``fulls``), ``score`` (the similarity score), ``localization`` (a
        :class:`Localization` indexed by that shape's vertices) and ``error``. A shape the
        partial cannot be located on (e.g. it is smaller than the partial) ranks last, with
        ``score = inf``, ``localization = None`` and the reason in ``error``.

    Raises:
        MeshError: a mesh cannot be used, or a prepared-shape file cannot be loaded.
        ValueError: the partial cannot be located on any of the shapes (the first shape's
        reason), or ``screen`` does not hold one shape per full shape. Cancelled: the
        callback returned ``False``.
    """
    pv, pf = _mesh_pair(partial, "partial mesh")
    _check_progress(progress)
    checked = _check_fulls(fulls, options)
    if top is not None:
        top = _count(top, "top")
    if shortlist is not None:
        shortlist = _count(shortlist, "shortlist")
    if screen is not None:
        _check_screen(screen, len(checked))
    # With a shortlist the screen picks the shapes to localize first, and the native search
    # prepares the meshes among them only (each just before locating on it). Otherwise every
    # mesh is prepared here first: one progress unit per mesh, one per shape to locate on.
    screened = shortlist is not None and (shortlist < len(checked) or screen is not None)
    meshes = 0 if screened else sum(isinstance(f, tuple) for f in checked)
    units = max(1, meshes + len(checked))
    shapes: List[Union[Localizer, Tuple[Any, Any]]] = []
    done = 0
    for full in checked:
        if screened and isinstance(full, tuple):
            shapes.append(full)
            continue
        part = None
        if isinstance(full, tuple):
            part = _span(progress, done / units, (done + 1) / units)
            done += 1
        shapes.append(_prepared(full, options, part))
    natives = [s._native if isinstance(s, Localizer) else s for s in shapes]
    found, notes = _dualspectra.search(
        pv, pf, natives, top, _span(progress, done / units, 1.0), shortlist, None if screen is None else screen._native, options
    )
    # The notes of the meshes prepared (or only taken in) by the native search; then the
    # partial's notes once, not once per shape (each shape's own notes were given when it was
    # prepared or loaded).
    for shape_notes in notes:
        _warn(shape_notes)
    own = [s.warnings if isinstance(s, Localizer) else tuple(n) for s, n in zip(shapes, notes)]
    seen: Set[str] = set()
    for m in found:
        if m.localization is not None:
            fresh = [w for w in m.localization.warnings if w not in own[m.index] and w not in seen]
            seen.update(fresh)
            _warn(fresh)
    return found


# The options' documentation is the core's table, not a copy.
Localizer.__doc__ = (Localizer.__doc__ or "").replace("{options}", _options_doc())
localize.__doc__ = (localize.__doc__ or "").replace("{options}", _options_doc())


def spectrum(
    vertices: ArrayLike,
    faces: ArrayLike,
    k: int = 20,
    metric: Literal["regular", "si"] = "regular",
    alpha: float = 0.33,
) -> NDArray[np.float64]:
    """The ``k`` smallest eigenvalues of ``W phi = lambda M phi`` (ascending).

    ``W`` is the cotangent stiffness, ``M`` the lumped mass (``metric="regular"``) or the
    scale-invariant mass ``diag(s) A`` with ``s = (eps + K_smooth^2)^(alpha/2)``
    (``metric="si"``). On a mesh with boundary, homogeneous Dirichlet conditions hold on
    the boundary vertices (they are removed); on a closed mesh the first eigenvalue is 0.
    """
    v, f = _mesh_arrays(vertices, faces)
    return _dualspectra.spectrum(v, f, _count(k, "k"), metric, float(alpha))


def gaussian_curvature(vertices: ArrayLike, faces: ArrayLike, smoothed: bool = False) -> NDArray[np.float64]:
    """Pointwise Gaussian curvature per vertex: angle defect / lumped area.

    The angle defect is ``2 pi - sum(theta)`` at interior vertices and ``pi - sum(theta)`` at
    boundary vertices; the lumped area is a third of the incident faces' areas. With
    ``smoothed=True`` each value is replaced by the mean over its one-ring neighbours (the
    curvature the scale-invariant metric uses).
    """
    v, f = _mesh_arrays(vertices, faces)
    return _dualspectra.gaussian_curvature(v, f, bool(smoothed))


def cotangent_stiffness_csc(
    vertices: ArrayLike, faces: ArrayLike
) -> Tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64], Tuple[int, int]]:
    """The cotangent stiffness ``W`` as CSC arrays ``(data, indices, indptr, (n, n))``.

    ``W_ij = -(cot a_ij + cot b_ij) / 2`` off the diagonal, rows summing to zero: positive
    semi-definite, ``W = -L`` with ``L`` libigl's ``cotmatrix``. Needs no scipy.
    """
    v, f = _mesh_arrays(vertices, faces)
    data, indices, indptr, n = _dualspectra.cotangent_stiffness(v, f)
    return data, indices, indptr, (n, n)


def cotangent_stiffness(vertices: ArrayLike, faces: ArrayLike) -> csc_matrix:
    """The cotangent stiffness ``W`` (see :func:`cotangent_stiffness_csc`) as a ``scipy.sparse.csc_matrix``.

    Raises ``ImportError`` if scipy is not installed (use :func:`cotangent_stiffness_csc`).
    """
    try:
        from scipy.sparse import csc_matrix
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("cotangent_stiffness needs scipy; cotangent_stiffness_csc returns the raw CSC arrays") from e
    data, indices, indptr, shape = cotangent_stiffness_csc(vertices, faces)
    return csc_matrix((data, indices, indptr), shape=shape)


def lumped_mass(vertices: ArrayLike, faces: ArrayLike) -> NDArray[np.float64]:
    """Diagonal of the lumped (barycentric) mass matrix: a third of the incident faces' areas."""
    v, f = _mesh_arrays(vertices, faces)
    return _dualspectra.lumped_mass(v, f)


@overload
def read_mesh(
    path: Union[str, "os.PathLike[str]"], *, return_kept: Literal[False] = False
) -> Tuple[NDArray[np.float64], NDArray[np.int64]]: ...
@overload
def read_mesh(
    path: Union[str, "os.PathLike[str]"], *, return_kept: Literal[True]
) -> Tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64]]: ...
def read_mesh(
    path: Union[str, "os.PathLike[str]"], *, return_kept: bool = False
) -> Union[
    Tuple[NDArray[np.float64], NDArray[np.int64]],
    Tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64]],
]:
    """Read a triangle mesh file (OFF, OBJ, PLY) into ``(V (n, 3) float64, F (m, 3) int64)``.

    Polygons are fan-triangulated. A triangle listed twice in opposite orientations (a
    two-sided "flap", as in SHREC'16 ``cat.off``) is removed, and so is its tip vertex if no
    other face uses it. Non-manifold edges (in more than two faces) and vertices (whose faces
    form several fans), as raw scans have, are split: each extra fan gets a copy of the
    vertex, appended after the file's vertices, and a :class:`DualspectraWarning` says how
    many. So rows of ``V`` may differ from the file's vertex records: with
    ``return_kept=True`` a third array ``kept (n,) int64`` gives the file's record of each row
    (``np.arange(n)`` when nothing was dropped or split; a split vertex's copies repeat its
    record). Any other vertex in no face is an error.

    Raises ``OSError`` if the file cannot be read and :class:`MeshError` if its content is
    not a valid triangle mesh.
    """
    v, f, kept, notes = _dualspectra.read_mesh(os.fspath(path))
    _warn(notes)
    return (v, f, kept) if return_kept else (v, f)


def _count(value: Any, name: str) -> int:
    """A non-negative Python int from an integer-like (numpy integers included)."""
    try:
        i = int(value.__index__())
    except (AttributeError, TypeError):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}") from None
    if i < 0:
        raise ValueError(f"{name} must be non-negative, got {i}")
    return i




# The public names are documented and pickled as the package's.
for _public in (
    DualspectraWarning,
    Localizer,
    cotangent_stiffness,
    cotangent_stiffness_csc,
    gaussian_curvature,
    localize,
    lumped_mass,
    options_schema,
    read_mesh,
    Screen,
    search,
    spectrum,
):
    _public.__module__ = "dualspectra"
