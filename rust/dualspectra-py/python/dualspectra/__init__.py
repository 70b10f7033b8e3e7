"""Partial shape localization by multi-metric Hamiltonian spectra matching.

Given a full triangle mesh M and a partial, possibly deformed copy N of a part of it,
:func:`localize` finds the region of M that N is (Bracha, Halimi, Kimmel: "Partial Shape
Similarity by Multi-metric Hamiltonian Spectra Matching"). The operators it is built on
(cotangent stiffness, lumped mass, Gaussian curvature, Dirichlet spectra) are exposed too.

Meshes are passed as two array-likes: vertices ``V`` of shape ``(n, 3)`` (anything
convertible to float64) and faces ``F`` of shape ``(m, 3)`` (integers, 0-based). Every
computation runs in the Rust core ``dualspectra`` with the GIL released; this module only
converts arrays.

Errors: :class:`MeshError` (a ``ValueError``) for invalid meshes or mesh files,
:class:`Cancelled` when a progress callback returns ``False``, :class:`NumericalError`
(a ``RuntimeError``) when a numerical step fails, ``ValueError`` for bad arguments,
``OSError`` for unreadable files, ``TypeError`` for arrays of the wrong kind.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, Callable, Literal, Optional, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _dualspectra
from ._dualspectra import Cancelled, Localization, MeshError, NumericalError, __version__

if TYPE_CHECKING:
    from scipy.sparse import csc_matrix  # type: ignore[import-untyped, unused-ignore]

__all__ = [
    "__version__",
    "Cancelled",
    "Localization",
    "MeshError",
    "NumericalError",
    "ProgressCallback",
    "cotangent_stiffness",
    "cotangent_stiffness_csc",
    "gaussian_curvature",
    "localize",
    "lumped_mass",
    "read_mesh",
    "spectrum",
]

#: ``callback(fraction, stage)``: ``fraction`` in [0, 1] of the whole run, ``stage`` a short
#: name. Return ``False`` to cancel (``None`` or ``True`` to go on).
ProgressCallback = Callable[[float, str], Optional[bool]]

_INDEX_MAX = np.iinfo(np.int64).max


def _mesh_arrays(vertices: ArrayLike, faces: ArrayLike, what: str = "mesh") -> Tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Contiguous float64 ``(n, 3)`` and int64 ``(m, 3)`` copies (or views) of the inputs.

    Shapes and kinds are checked here for clear messages; index ranges, finiteness and
    the mesh invariants are checked by the core (``TriMesh::new``).
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


def localize(
    full_vertices: ArrayLike,
    full_faces: ArrayLike,
    partial_vertices: ArrayLike,
    partial_faces: ArrayLike,
    *,
    mode: Literal["dual", "lbo", "si"] = "dual",
    k: int = 20,
    alpha: float = 0.33,
    seed: int = 0,
    resolution: Optional[int] = None,
    centers: Optional[int] = None,
    max_iterations: Optional[int] = None,
    threads: Optional[int] = None,
    selection: Optional[Literal["gated", "region", "descriptors", "cost"]] = None,
    starts: Optional[
        Literal["balls-and-wide-bumps", "balls-and-wide-gaussians", "gaussian", "area-ball"]
    ] = None,
    spectral_cuts: Optional[int] = None,
    plane_cuts: Optional[int] = None,
    progress: Optional[ProgressCallback] = None,
) -> Localization:
    """Find the region of the full mesh that the partial mesh corresponds to.

    Args:
        full_vertices, full_faces: the full shape M, ``(n, 3)`` and ``(m, 3)``.
        partial_vertices, partial_faces: the partial shape N.
        mode: ``"dual"`` matches k regular + k scale-invariant Dirichlet eigenvalues (the
            paper's method); ``"lbo"`` 2k regular ones; ``"si"`` 2k scale-invariant ones.
        k: eigenvalues per spectrum.
        alpha: exponent of the scale-invariant metric factor.
        seed: seed of every random choice (results are deterministic for a seed).
        resolution: vertices of the decimated full shape the potential is optimised on
            (0: no decimation; default: the core's, 1000).
        centers: farthest-point centres of the starts (3 starts each by default, see
            ``starts``; default 4, the paper used 10).
        max_iterations: trust-region iterations per start (default 25).
        threads: worker threads (0 or default: all cores).
        selection: how the result is chosen among the starts: ``"gated"`` (default:
            the best descriptor score, times the squared fit of the partial's descriptors
            to the region's, which tells a region from its mirror image, among the starts
            whose extracted region's own spectra are within 3x of the closest to the
            partial's), ``"region"`` (those spectra
            closest), ``"descriptors"``
            (SHOT descriptors, the paper's rule) or ``"cost"`` (lowest optimised cost).
        starts: the starting potentials around each centre: ``"balls-and-wide-bumps"``
            (default, 3 per centre: a well on the ball with the partial's area, one on
            everything but the ball with the rest of the area, and the wide Gaussian bump),
            ``"balls-and-wide-gaussians"`` (4: also the wide Gaussian well), ``"gaussian"``
            (4: the paper's Gaussians of two widths, both signs) or ``"area-ball"`` (2: the
            two balls only). Unknown names raise ``ValueError``.
        spectral_cuts: further starts from the full shape's first eigenfunctions, two each
            (the region on either side of a level set, with the partial's area); default 0.
            They suit partials cut across a natural axis, e.g. the left half of a body.
        plane_cuts: further starts, one per direction: the side of a plane with the
            partial's area, normal to the first ``plane_cuts`` of 26 directions (default 6:
            both ways along the full shape's principal axes; 14: and the diagonals; at most
            26). They suit partials cut off across the body, e.g. the front half of a torso.
        progress: optional ``callback(fraction, stage)``; returning ``False`` cancels.

    Returns:
        A :class:`Localization` (``region`` boolean mask over the full mesh's vertices, soft
        ``score``, ``potential``, spectra, ``cost``, ``timings``).

    Raises:
        MeshError: a mesh is invalid. Cancelled: the callback returned ``False``. An
        exception raised by the callback, or ``KeyboardInterrupt`` (Ctrl-C), is re-raised.
    """
    fv, ff = _mesh_arrays(full_vertices, full_faces, "full mesh")
    pv, pf = _mesh_arrays(partial_vertices, partial_faces, "partial mesh")
    if progress is not None and not callable(progress):
        raise TypeError("progress must be callable as progress(fraction, stage)")
    return _dualspectra.localize(
        fv,
        ff,
        pv,
        pf,
        mode,
        _count(k, "k"),
        float(alpha),
        _count(seed, "seed"),
        _optional_count(resolution, "resolution"),
        _optional_count(centers, "centers"),
        _optional_count(max_iterations, "max_iterations"),
        _optional_count(threads, "threads"),
        selection,
        starts,
        _optional_count(spectral_cuts, "spectral_cuts"),
        _optional_count(plane_cuts, "plane_cuts"),
        progress,
    )


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


def read_mesh(path: Union[str, "os.PathLike[str]"]) -> Tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Read a triangle mesh file (OFF, OBJ, PLY, STL) into ``(V (n, 3) float64, F (m, 3) int64)``.

    Raises ``OSError`` if the file cannot be read and :class:`MeshError` if its content is
    not a valid triangle mesh.
    """
    return _dualspectra.read_mesh(os.fspath(path))


def _count(value: Any, name: str) -> int:
    """A non-negative Python int from an integer-like (numpy integers included)."""
    try:
        i = int(value.__index__())
    except (AttributeError, TypeError):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}") from None
    if i < 0:
        raise ValueError(f"{name} must be non-negative, got {i}")
    return i


def _optional_count(value: Any, name: str) -> Optional[int]:
    return None if value is None else _count(value, name)
