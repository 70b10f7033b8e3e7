"""Operators against libigl: cotangent stiffness, lumped mass, Gaussian curvature.

Tolerances. Every entry is a short sum of closed-form per-triangle terms (a cotangent,
an area, an angle), computed by both libraries in double precision with different but
stable formulas and summation orders. The rounding error is then a few ulps of the
largest term, so ``1e-8`` relative (about 4.5e7 ulps) is a generous bound that still
catches any wrong formula, sign, factor or boundary rule (those give O(1) errors). The
measured errors are printed (``-s``) and are ~1e-15.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import EPS, Mesh, max_rel, report

import dualspectra as ds

igl = pytest.importorskip("igl")
sp = pytest.importorskip("scipy.sparse")

MATRIX_RTOL = 1e-8


def test_cotangent_stiffness_is_minus_libigl_cotmatrix(mesh: Mesh) -> None:
    """``W = -L``, L = ``igl.cotmatrix``: max entry error / max entry <= 1e-8 (see module doc)."""
    w = ds.cotangent_stiffness(mesh.v, mesh.f)
    assert isinstance(w, sp.csc_matrix)
    assert w.shape == (len(mesh.v), len(mesh.v))
    ref = -igl.cotmatrix(mesh.v, mesh.f)
    err = abs(w - ref).max() / abs(ref).max()
    report(f"cotangent {mesh.name}", max_rel=err)
    assert err <= MATRIX_RTOL
    # Same sparsity up to explicit zeros: the structure is the edge graph plus the diagonal.
    assert abs(w - w.T).max() <= 8 * EPS * abs(w).max()
    np.testing.assert_allclose(np.asarray(w.sum(axis=1)).ravel(), 0.0, atol=64 * EPS * abs(w).max())


def test_cotangent_stiffness_csc_arrays_are_consistent(mesh: Mesh) -> None:
    """The raw CSC arrays build the same matrix as the scipy one (no scipy needed for them)."""
    data, indices, indptr, shape = ds.cotangent_stiffness_csc(mesh.v, mesh.f)
    n = len(mesh.v)
    assert shape == (n, n) and len(indptr) == n + 1 and indptr[-1] == len(data) == len(indices)
    assert data.dtype == np.float64 and indices.dtype == np.int64
    assert indices.min() >= 0 and indices.max() < n


def test_lumped_mass_is_libigl_barycentric_massmatrix(mesh: Mesh) -> None:
    """Diagonal of ``igl.massmatrix(..., MASSMATRIX_TYPE_BARYCENTRIC)``, relative 1e-8 (module doc);
    the masses add up to the surface area (law)."""
    a = ds.lumped_mass(mesh.v, mesh.f)
    ref = igl.massmatrix(mesh.v, mesh.f, igl.MASSMATRIX_TYPE_BARYCENTRIC).diagonal()
    err = max_rel(a, ref)
    report(f"mass {mesh.name}", max_rel=err)
    assert err <= MATRIX_RTOL
    area = igl.doublearea(mesh.v, mesh.f).sum() / 2
    assert abs(a.sum() - area) <= 1e-12 * area


def test_gaussian_curvature_is_libigl_angle_defect_over_area(mesh: Mesh) -> None:
    """``K_i a_i`` is libigl's ``gaussian_curvature`` (the angle defect ``2 pi - sum theta``, not
    divided by area) at interior vertices, and that minus ``pi`` at boundary vertices (we use
    ``pi - sum theta`` there, libigl ``2 pi`` everywhere).

    Tolerance: the defect is a sum of <= ~10 angles of at most pi each, so its rounding error
    is a few ulps of 2 pi; we allow ``1e-8 * 2 pi`` absolute (radians), as for the matrices.
    """
    k = ds.gaussian_curvature(mesh.v, mesh.f)
    a = ds.lumped_mass(mesh.v, mesh.f)
    defect = k * a
    ref = np.asarray(igl.gaussian_curvature(mesh.v, mesh.f), dtype=np.float64)
    boundary = np.zeros(len(mesh.v), bool)
    boundary[mesh.boundary] = True
    ref_ours = np.where(boundary, ref - np.pi, ref)
    err_interior = float(np.max(np.abs(defect - ref_ours)[~boundary]))
    err_boundary = float(np.max(np.abs(defect - ref_ours)[boundary])) if boundary.any() else 0.0
    report(f"curvature {mesh.name}", abs_interior_rad=err_interior, abs_boundary_rad=err_boundary)
    assert err_interior <= MATRIX_RTOL * 2 * np.pi
    assert err_boundary <= MATRIX_RTOL * 2 * np.pi


def test_gauss_bonnet_on_closed_meshes(mesh: Mesh) -> None:
    """Law: on a closed mesh ``sum_i K_i a_i = 2 pi chi`` exactly up to rounding (chi = V - E + F)."""
    if len(mesh.boundary):
        pytest.skip(f"{mesh.name} has a boundary")
    total = float(np.sum(ds.gaussian_curvature(mesh.v, mesh.f) * ds.lumped_mass(mesh.v, mesh.f)))
    edges = {tuple(sorted(e)) for f in mesh.f.tolist() for e in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))}
    chi = len(mesh.v) - len(edges) + len(mesh.f)
    assert abs(total - 2 * np.pi * chi) <= 1e-9 * len(mesh.v)


def test_smoothed_curvature_is_one_ring_mean(mesh: Mesh) -> None:
    """``smoothed=True`` replaces each K_i by the mean of K over its one-ring neighbours (the
    vertex excluded), neighbours taken from libigl's ``adjacency_matrix``. Relative 1e-12 of
    max |K|: a mean of ~6 values adds a few ulps."""
    k = ds.gaussian_curvature(mesh.v, mesh.f)
    ks = ds.gaussian_curvature(mesh.v, mesh.f, smoothed=True)
    adj = sp.csr_matrix(igl.adjacency_matrix(mesh.f))
    adj.data[:] = 1.0
    ref = (adj @ k) / np.asarray(adj.sum(axis=1)).ravel()
    assert max_rel(ks, ref) <= 1e-12


@pytest.mark.parametrize("scale", [1e-8, 1e8])
def test_scaling_laws(scale: float) -> None:
    """Laws under ``V -> c V``: W is invariant, mass scales by c^2, K by 1/c^2 (to rounding)."""
    from conftest import bumpy

    v, f = bumpy(2)
    w1, w2 = ds.cotangent_stiffness(v, f), ds.cotangent_stiffness(scale * v, f)
    assert abs(w1 - w2).max() <= 64 * EPS * abs(w1).max()
    np.testing.assert_allclose(ds.lumped_mass(scale * v, f), scale**2 * ds.lumped_mass(v, f), rtol=64 * EPS)
    k1, k2 = ds.gaussian_curvature(v, f), ds.gaussian_curvature(scale * v, f)
    np.testing.assert_allclose(k2 * scale**2, k1, rtol=1e-9, atol=1e-9 * np.abs(k1).max())
