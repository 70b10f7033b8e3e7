"""Mesh arrays for dualspectra, free of ``bpy`` (numpy only).

The operator (``operators.py``) reads Blender meshes into plain arrays (world-space
positions, loop triangles), hands them to ``dualspectra`` as they are, and writes the
answer back with the helpers here. Keeping this side free of ``bpy`` lets it be tested in
any Python (the glTF-Blender-IO split of ``io/`` and ``blender/``).

Nothing is compacted or repaired here: the library's mesh intake leaves out degenerate
triangles and vertices in no triangle (loose vertices and edges), says so in its warnings,
and returns every per-vertex result at the indices of the arrays it was given.

Conventions: positions are ``(n, 3)`` float64, triangles ``(m, 3)`` int64 indices into
them, masks are ``(n,)`` bool.
"""

import numpy as np


def world_positions(local, matrix_world):
    """Positions ``local (n, 3)`` mapped by the 4x4 affine ``matrix_world``: ``M[:3,:3] p + M[:3,3]``.

    Both meshes go to world space so that two objects with different transforms (in
    particular different scales, which change every eigenvalue) are compared as they
    appear in the scene.
    """
    local = np.asarray(local, dtype=np.float64).reshape(-1, 3)
    m = np.asarray(matrix_world, dtype=np.float64).reshape(4, 4)
    return local @ m[:3, :3].T + m[:3, 3]


def nearest_indices(queries, points, chunk=2048):
    """For each row of ``queries (q, 3)`` the index of the nearest row of ``points (p, 3)``.

    Brute force in chunks (memory ``chunk * p``); used only when a modifier changed the
    vertex count and results must go from the evaluated mesh back to the original one.
    """
    queries = np.asarray(queries, dtype=np.float64).reshape(-1, 3)
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    if len(points) == 0:
        raise ValueError("no points to map onto")
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
