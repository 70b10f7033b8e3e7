"""Shared meshes and references for the dualspectra Python tests.

Meshes come in two kinds (geometry-central's grouping): generated ones, built here in numpy
so that they do not depend on the library under test, and real ones read by libigl from
``$DUALSPECTRA_DATA/shrec16/null`` (tests using them skip with a message when absent).

References are libigl's operators (``cotmatrix``, ``massmatrix``, ``gaussian_curvature``)
and scipy's ARPACK (``eigsh`` in shift-invert mode) on them.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Dict, List, Tuple

import numpy as np
import pytest

EPS = np.finfo(np.float64).eps


# --------------------------------------------------------------------------------------
# Generated meshes (numpy only)
# --------------------------------------------------------------------------------------


def icosphere(level: int) -> Tuple[np.ndarray, np.ndarray]:
    """Unit icosphere: the icosahedron subdivided ``level`` times, projected on the sphere."""
    t = (1.0 + 5.0**0.5) / 2.0
    v = [
        [-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0],
        [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
        [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1],
    ]
    f = [
        [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
        [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
        [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
        [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
    ]
    verts: List[np.ndarray] = [np.array(p, float) / np.linalg.norm(p) for p in v]
    faces = f
    for _ in range(level):
        mid: Dict[Tuple[int, int], int] = {}

        def midpoint(a: int, b: int) -> int:
            key = (min(a, b), max(a, b))
            if key not in mid:
                p = verts[a] + verts[b]
                verts.append(p / np.linalg.norm(p))
                mid[key] = len(verts) - 1
            return mid[key]

        new = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            new += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        faces = new
    return np.array(verts), np.array(faces, dtype=np.int64)


def disk(rings: int, sectors: int = 6) -> Tuple[np.ndarray, np.ndarray]:
    """Unit disk in z = 0: a centre vertex and ``rings`` rings of ``sectors * r`` vertices."""
    v = [[0.0, 0.0, 0.0]]
    start = [0]
    for r in range(1, rings + 1):
        start.append(len(v))
        n = sectors * r
        th = 2 * np.pi * np.arange(n) / n
        v += np.c_[r / rings * np.cos(th), r / rings * np.sin(th), np.zeros(n)].tolist()
    f = [[0, 1 + j, 1 + (j + 1) % sectors] for j in range(sectors)]
    for r in range(1, rings):
        a0, na, b0, nb = start[r], sectors * r, start[r + 1], sectors * (r + 1)
        i = j = 0
        while i < na or j < nb:
            if j < nb and (i >= na or (j + 1) / nb <= (i + 1) / na):
                f.append([a0 + i % na, b0 + j % nb, b0 + (j + 1) % nb])
                j += 1
            else:
                f.append([a0 + i % na, b0 + j % nb, a0 + (i + 1) % na])
                i += 1
    return np.array(v), np.array(f, dtype=np.int64)


def bumpy(level: int = 3) -> Tuple[np.ndarray, np.ndarray]:
    """An icosphere with a smooth, asymmetric radial bump field (curved, irregular triangles)."""
    v, f = icosphere(level)
    x, y, z = v.T
    r = 1.0 + 0.25 * np.sin(3 * x + 1) * np.cos(2 * y) + 0.15 * z**3 + 0.1 * x * y
    return v * r[:, None] * np.array([1.6, 1.0, 0.8]), f


def torus(nu: int = 40, nv: int = 16, big: float = 1.0, small: float = 0.35) -> Tuple[np.ndarray, np.ndarray]:
    """Closed genus-1 torus grid (Euler characteristic 0)."""
    u = 2 * np.pi * np.arange(nu) / nu
    w = 2 * np.pi * np.arange(nv) / nv
    uu, ww = np.meshgrid(u, w, indexing="ij")
    v = np.c_[
        ((big + small * np.cos(ww)) * np.cos(uu)).ravel(),
        ((big + small * np.cos(ww)) * np.sin(uu)).ravel(),
        (small * np.sin(ww)).ravel(),
    ]
    idx = lambda i, j: (i % nu) * nv + (j % nv)  # noqa: E731
    f = []
    for i in range(nu):
        for j in range(nv):
            f += [[idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)], [idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)]]
    return v, np.array(f, dtype=np.int64)


def wavy_disk(rings: int = 14) -> Tuple[np.ndarray, np.ndarray]:
    """The disk lifted to a non-flat height field (boundary, non-zero curvature)."""
    v, f = disk(rings)
    v[:, 2] = 0.3 * np.sin(2.5 * v[:, 0]) * np.cos(1.7 * v[:, 1]) + 0.2 * v[:, 0] ** 2
    return v, f


def cut(v: np.ndarray, f: np.ndarray, keep: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The faces whose three vertices are all kept, re-indexed; returns (V', F', original index of each V' row)."""
    fk = f[keep[f].all(axis=1)]
    used = np.unique(fk)
    new = -np.ones(len(v), dtype=np.int64)
    new[used] = np.arange(len(used))
    return v[used], new[fk], used


def assert_damaged_files_refused(
    load: Callable[[Path], object],
    from_bytes: Callable[[bytes], object],
    cases: Dict[str, Tuple[bytes, str]],
    folder: Path,
    extension: str,
) -> None:
    """Every ``name: (bytes, message)`` of ``cases``, written to ``folder/name.extension``, is
    refused by ``load`` with a :class:`dualspectra.MeshError` matching ``message`` and naming the
    file, and by ``from_bytes`` with the same message; a missing file is a FileNotFoundError."""
    import dualspectra as ds

    for name, (data, message) in cases.items():
        path = folder / f"{name}.{extension}"
        path.write_bytes(data)
        with pytest.raises(ds.MeshError, match=message) as err:
            load(path)
        assert str(path) in str(err.value), err.value
        with pytest.raises(ds.MeshError, match=message):
            from_bytes(data)
    with pytest.raises(FileNotFoundError):
        load(folder / f"missing.{extension}")


#: Limbs ``(direction, height, width)`` of :func:`figure`'s shapes: the default figure (head,
#: long arm +x, short arm -x, two legs), a four-legged one with a tail, one with a long horn
#: (the Rust core's ``evaluation::synthetic`` figures).
FIGURE_LIMBS: Dict[str, List[Tuple[Tuple[float, float, float], float, float]]] = {
    "figure": [((0, 0, 1), 0.55, 0.38), ((1, 0, 0.12), 1.25, 0.24), ((-1, 0, 0.12), 0.8, 0.26),
               ((0.42, 0, -1), 1.1, 0.26), ((-0.42, 0, -1), 1.1, 0.26)],
    "quadruped": [((1, 0, 0.3), 0.6, 0.35), ((0.5, 0.5, -1), 0.9, 0.2), ((0.5, -0.5, -1), 0.9, 0.2),
                  ((-0.5, 0.5, -1), 0.9, 0.2), ((-0.5, -0.5, -1), 0.9, 0.2), ((-1, 0, 0.4), 1.4, 0.12)],
    "horned": [((0, 0, 1), 2.0, 0.15), ((0, 0, -1), 0.4, 0.6)],
}


def figure(level: int, kind: str = "figure") -> Tuple[np.ndarray, np.ndarray]:
    """An icosphere pushed out radially by Gaussian limbs (``FIGURE_LIMBS[kind]``), then
    flattened front to back (y * 0.7)."""
    u, f = icosphere(level)
    r = np.ones(len(u))
    for direction, height, width in FIGURE_LIMBS[kind]:
        d = np.asarray(direction, float) / np.linalg.norm(direction)
        r += height * np.exp(-((np.arccos(np.clip(u @ d, -1, 1)) / width) ** 2))
    p = u * r[:, None]
    p[:, 1] *= 0.7
    return p, f


def bend(p: np.ndarray, joint: float = 1.1, length: float = 1.1, angle: float = np.radians(50)) -> np.ndarray:
    """:func:`figure`'s long arm bent up: points beyond ``joint`` along the arm's axis are
    bent by ``angle`` towards +z over ``length`` (a near-isometric pose of the figure)."""
    a = np.array([1.0, 0.0, 0.12]) / np.linalg.norm([1.0, 0.0, 0.12])
    b = np.array([0.0, 0.0, 1.0]) - a[2] * a
    b /= np.linalg.norm(b)
    t, h = p @ a, p @ b
    rest = p - np.outer(t, a) - np.outer(h, b)
    kappa = angle / length
    s = np.minimum(t - joint, length)
    sn, cs = np.sin(kappa * s), np.cos(kappa * s)
    beyond = np.maximum(t - joint - length, 0.0)
    c0, c1 = sn / kappa + beyond * cs, (1 - cs) / kappa + beyond * sn
    bent = rest + np.outer(joint + c0 - h * sn, a) + np.outer(c1 + h * cs, b)
    return np.where((t > joint)[:, None], bent, p)


GENERATED: Dict[str, Callable[[], Tuple[np.ndarray, np.ndarray]]] = {
    # closed
    "icosphere3": lambda: icosphere(3),
    "bumpy3": lambda: bumpy(3),
    "torus": torus,
    # with boundary
    "disk12": lambda: disk(12),
    "wavy_disk14": wavy_disk,
}

# --------------------------------------------------------------------------------------
# Real meshes (SHREC'16 null shapes)
# --------------------------------------------------------------------------------------

REAL = ["cat", "david", "horse", "wolf"]  # the cat has two boundary loops


def data_dir() -> Path:
    return Path(os.environ.get("DUALSPECTRA_DATA", Path(__file__).resolve().parents[3] / "shared" / "datasets"))


def real_mesh_path(name: str) -> Path:
    path = data_dir() / "shrec16" / "null" / f"{name}.off"
    if not path.is_file():
        pytest.skip(f"dataset mesh {path} absent (set DUALSPECTRA_DATA to the datasets directory)")
    return path


@dataclass
class Mesh:
    name: str
    v: np.ndarray
    f: np.ndarray

    @property
    def boundary(self) -> np.ndarray:
        """Indices of all boundary vertices (every loop), from libigl's boundary edges."""
        import igl

        e = igl.boundary_facets(self.f)
        e = e[0] if isinstance(e, tuple) else e
        return np.unique(np.asarray(e).ravel()).astype(np.int64)


def load(name: str) -> Mesh:
    if name in GENERATED:
        v, f = GENERATED[name]()
        return Mesh(name, v, f)
    # Read by dualspectra: it removes the two-sided "flaps" of cat.off (a triangle listed in
    # both orientations), which make edges non-manifold; libigl's references are then
    # computed on exactly the same arrays.
    import dualspectra

    v, f = dualspectra.read_mesh(real_mesh_path(name))
    return Mesh(name, v, f)


ALL_MESHES = list(GENERATED) + REAL


@pytest.fixture(params=ALL_MESHES)
def mesh(request: pytest.FixtureRequest) -> Mesh:
    return load(request.param)


# --------------------------------------------------------------------------------------
# References (libigl + scipy)
# --------------------------------------------------------------------------------------


def igl_dirichlet_eigenvalues(m: Mesh, k: int, mass_diag: np.ndarray | None = None) -> np.ndarray:
    """The ``k`` smallest eigenvalues of ``-L[I,I] x = lambda M[I,I] x``, ``I`` the interior vertices.

    ``L`` is libigl's ``cotmatrix``, ``M`` libigl's barycentric ``massmatrix`` (or the given
    diagonal). Up to ``DENSE_REFERENCE_MAX`` interior vertices: LAPACK's dense generalized
    ``eigh``, exact for repeated eigenvalues. Larger meshes: ARPACK in shift-invert mode around
    a small negative shift ``-1/area`` (below the spectrum, so the zero eigenvalue of a closed
    mesh is found too), ``tol=0``. ARPACK is single-vector Lanczos: on a symmetric mesh it can
    drop a member of a repeated eigenvalue, CPU-dependently (CI, twice: icosphere3's 4-fold
    19.4701 came back 3-fold, the 20th value read 19.5089), so it is kept to the large, irregular
    meshes (cat, david), which have no such multiplicities.
    """
    import igl
    import scipy.linalg as la
    import scipy.sparse as sp
    from scipy.sparse.linalg import eigsh

    w = -igl.cotmatrix(m.v, m.f)
    if mass_diag is None:
        mass_diag = igl.massmatrix(m.v, m.f, igl.MASSMATRIX_TYPE_BARYCENTRIC).diagonal()
    interior = np.setdiff1d(np.arange(len(m.v)), m.boundary)
    wi = sp.csc_matrix(w[interior][:, interior])
    if len(interior) <= DENSE_REFERENCE_MAX:
        dense = wi.toarray()
        return la.eigh(0.5 * (dense + dense.T), np.diag(mass_diag[interior]), eigvals_only=True, subset_by_index=[0, k - 1])
    mi = sp.diags(mass_diag[interior]).tocsc()
    sigma = -1.0 / mass_diag.sum()
    vals = eigsh(wi, k=k, M=mi, sigma=sigma, which="LM", tol=0, return_eigenvectors=False)
    return np.sort(vals)


DENSE_REFERENCE_MAX = 3000
"""Largest interior vertex count whose reference spectrum is computed densely (~1 s)."""


def rel_err_eigenvalues(ours: np.ndarray, ref: np.ndarray) -> float:
    """Max over i of ``|ours_i - ref_i| / |ref_i|``; for a zero eigenvalue (closed mesh),
    relative to the largest one instead."""
    denom = np.where(np.abs(ref) > 1e-9 * np.abs(ref[-1]), np.abs(ref), np.abs(ref[-1]))
    return float(np.max(np.abs(ours - ref) / denom))


def max_rel(a: np.ndarray, b: np.ndarray) -> float:
    """``max|a - b| / max|b|`` (entrywise error relative to the largest reference entry)."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def report(name: str, **numbers: float) -> None:
    """Print measured agreement (shown with ``pytest -s`` / in the stage log with ``-rA``)."""
    print(f"[agreement] {name}: " + ", ".join(f"{k}={v:.3e}" for k, v in numbers.items()))
