"""Mesh arrays for dualspectra, free of ``bpy`` (numpy only).

The operator (``operators.py``) reads Blender meshes into plain arrays, this module turns
them into what ``dualspectra.localize`` accepts and maps the answer back, and the operator
writes the result. Keeping this side free of ``bpy`` lets it be tested in any Python
(the glTF-Blender-IO split of ``io/`` and ``blender/``).

Conventions: positions are ``(n, 3)`` float64, triangles ``(m, 3)`` int64 indices into
them, masks are ``(n,)`` bool. "Source" vertices are the vertices of the mesh the arrays
were read from (the evaluated mesh); "kept" vertices are the ones used by at least one
non-degenerate triangle, which is what the library sees.
"""

from dataclasses import dataclass

import numpy as np

#: A triangle is degenerate when ``area <= DEGENERATE_RATIO * longest_edge**2``; the same
#: scale-free test as ``TriMesh::new`` in the core crate, so nothing we pass is rejected
#: for it.
DEGENERATE_RATIO = 1e-14


class MeshDataError(ValueError):
    """The object cannot be turned into a triangle mesh the localizer accepts."""


@dataclass
class TriangleMesh:
    """A triangle mesh ready for ``dualspectra.localize`` plus the way back to its source.

    ``vertices``: ``(k, 3)`` float64 world-space positions of the kept vertices.
    ``faces``: ``(m, 3)`` int64 indices into ``vertices``.
    ``kept``: ``(k,)`` int64, ``kept[i]`` is the source index of vertex ``i``.
    ``n_source``: number of vertices of the source mesh.
    ``dropped_faces``: degenerate triangles left out.
    """

    vertices: np.ndarray
    faces: np.ndarray
    kept: np.ndarray
    n_source: int
    dropped_faces: int = 0

    def to_source(self, values, fill):
        """Per-kept-vertex ``values`` scattered to the source vertices; others get ``fill``."""
        values = np.asarray(values)
        out = np.full((self.n_source,) + values.shape[1:], fill, dtype=values.dtype)
        out[self.kept] = values
        return out


def world_positions(local, matrix_world):
    """Positions ``local (n, 3)`` mapped by the 4x4 affine ``matrix_world``: ``M[:3,:3] p + M[:3,3]``.

    Both meshes go to world space so that two objects with different transforms (in
    particular different scales, which change every eigenvalue) are compared as they
    appear in the scene.
    """
    local = np.asarray(local, dtype=np.float64).reshape(-1, 3)
    m = np.asarray(matrix_world, dtype=np.float64).reshape(4, 4)
    return local @ m[:3, :3].T + m[:3, 3]


def triangle_areas(vertices, faces):
    """Area of each triangle: ``|(b - a) x (c - a)| / 2``."""
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)


def degenerate_triangles(vertices, faces):
    """Mask of triangles that repeat a vertex or have ``area <= 1e-14 * longest_edge**2``."""
    if len(faces) == 0:
        return np.zeros(0, dtype=bool)
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    longest = np.maximum.reduce([
        np.einsum("ij,ij->i", b - a, b - a),
        np.einsum("ij,ij->i", c - b, c - b),
        np.einsum("ij,ij->i", a - c, a - c),
    ])
    repeated = (faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 0] == faces[:, 2])
    area = triangle_areas(vertices, faces)
    # `not (area > ...)` also catches NaN.
    return repeated | ~(area > DEGENERATE_RATIO * longest)


def triangle_mesh(vertices, triangles, name="mesh"):
    """Build a :class:`TriangleMesh` from source positions ``(n, 3)`` and triangles ``(m, 3)``.

    Drops degenerate triangles and the vertices no remaining triangle uses (loose
    vertices and edges), keeping the map back to the source indices. Other defects
    (non-manifold edges) are left for the library, which names them.

    Raises :class:`MeshDataError` when nothing usable is left (no faces at all, all
    triangles degenerate) or when coordinates are not finite.
    """
    vertices = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    n = len(vertices)
    if len(triangles) == 0:
        raise MeshDataError(f"'{name}' has no faces ({n} vertices); the localizer needs a surface")
    if triangles.min() < 0 or triangles.max() >= n:
        raise MeshDataError(f"'{name}' has a triangle index outside 0..{n - 1}")
    if not np.isfinite(vertices).all():
        raise MeshDataError(f"'{name}' has non-finite vertex coordinates")
    bad = degenerate_triangles(vertices, triangles)
    good = triangles[~bad]
    if len(good) == 0:
        raise MeshDataError(f"all {len(triangles)} triangles of '{name}' are degenerate (zero area)")
    used = np.zeros(n, dtype=bool)
    used[good.ravel()] = True
    kept = np.flatnonzero(used).astype(np.int64)
    new_index = np.full(n, -1, dtype=np.int64)
    new_index[kept] = np.arange(len(kept), dtype=np.int64)
    return TriangleMesh(
        vertices=np.ascontiguousarray(vertices[kept]),
        faces=np.ascontiguousarray(new_index[good]),
        kept=kept,
        n_source=n,
        dropped_faces=int(bad.sum()),
    )


def nearest_indices(queries, points, chunk=2048):
    """For each row of ``queries (q, 3)`` the index of the nearest row of ``points (p, 3)``.

    Brute force in chunks (memory ``chunk * p``); used only when a modifier changed the
    vertex count and results must go from the evaluated mesh back to the original one.
    """
    queries = np.asarray(queries, dtype=np.float64).reshape(-1, 3)
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    if len(points) == 0:
        raise MeshDataError("no points to map onto")
    p2 = np.einsum("ij,ij->i", points, points)
    out = np.empty(len(queries), dtype=np.int64)
    for s in range(0, len(queries), chunk):
        q = queries[s:s + chunk]
        # |q - p|^2 = |q|^2 - 2 q.p + |p|^2; |q|^2 is constant per row.
        d = p2[None, :] - 2.0 * (q @ points.T)
        out[s:s + chunk] = np.argmin(d, axis=1)
    return out


def edges_in_region(edge_vertices, vertex_mask):
    """Edges ``(e, 2)`` whose two vertices are both in ``vertex_mask``."""
    edge_vertices = np.asarray(edge_vertices, dtype=np.int64).reshape(-1, 2)
    mask = np.asarray(vertex_mask, dtype=bool)
    return mask[edge_vertices[:, 0]] & mask[edge_vertices[:, 1]]


def polygons_in_region(loop_vertices, loop_start, loop_total, vertex_mask):
    """Polygons (n-gons given by Blender's loop arrays) whose vertices are all in ``vertex_mask``.

    ``loop_vertices``: vertex index per loop; polygon ``p`` uses loops
    ``loop_start[p] .. loop_start[p] + loop_total[p]``.
    """
    loop_vertices = np.asarray(loop_vertices, dtype=np.int64)
    loop_start = np.asarray(loop_start, dtype=np.int64)
    loop_total = np.asarray(loop_total, dtype=np.int64)
    if len(loop_start) == 0:
        return np.zeros(0, dtype=bool)
    mask = np.asarray(vertex_mask, dtype=bool)
    inside = mask[loop_vertices].astype(np.int64)
    # Count the inside loops of each polygon (cumulative sums work for any order of loop_start).
    csum = np.concatenate([[0], np.cumsum(inside)])
    count = csum[loop_start + loop_total] - csum[loop_start]
    return count == loop_total


def score_colors(score):
    """RGBA colours ``(n, 4)`` for scores in ``[0, 1]``: dark blue (0) -> white (0.5) -> red (1).

    A diverging ramp, linear in each half; NaN scores are grey.
    """
    s = np.clip(np.nan_to_num(np.asarray(score, dtype=np.float64), nan=0.5), 0.0, 1.0)
    low = np.array([0.02, 0.05, 0.45])
    mid = np.array([1.0, 1.0, 1.0])
    high = np.array([0.75, 0.02, 0.02])
    t = s[:, None]
    rgb = np.where(t < 0.5, low + (mid - low) * (2 * t), mid + (high - mid) * (2 * t - 1))
    rgb[np.isnan(np.asarray(score, dtype=np.float64))] = 0.5
    return np.concatenate([rgb, np.ones((len(s), 1))], axis=1)
