"""Dirichlet spectra against scipy (LAPACK / ARPACK) on libigl's matrices.

Reference: the generalized eigenvalues of ``(-L[I,I], M[I,I])`` with L = ``igl.cotmatrix``, M =
``igl.massmatrix`` (barycentric), I the interior vertices (all boundary loops removed:
homogeneous Dirichlet conditions; the cat has two loops, which ``igl.boundary_loop`` alone
would miss), by dense LAPACK up to 3,000 vertices and ARPACK above
(``conftest.igl_dirichlet_eigenvalues`` says why). The matrices agree to ~1e-14 (test_operators), so the eigenvalues differ only
by the two solvers' convergence: LAPACK/ARPACK at machine precision, the core's block LOBPCG at
its residual tolerance. ``1e-6`` relative is the accuracy the localizer needs from a
spectrum (its cost compares eigenvalues relatively) with margin for that tolerance.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import Mesh, igl_dirichlet_eigenvalues, rel_err_eigenvalues, report

import dualspectra as ds

igl = pytest.importorskip("igl")
pytest.importorskip("scipy.sparse.linalg")

K = 20
EIG_RTOL = 1e-6


def test_regular_dirichlet_spectrum_matches_scipy(mesh: Mesh) -> None:
    """First 20 eigenvalues, relative 1e-6 (module doc)."""
    ours = ds.spectrum(mesh.v, mesh.f, k=K, metric="regular")
    ref = igl_dirichlet_eigenvalues(mesh, K)
    assert ours.shape == (K,) and np.all(np.diff(ours) >= -1e-12 * abs(ours[-1]))
    err = rel_err_eigenvalues(ours, ref)
    report(f"spectrum regular {mesh.name}", max_rel=err)
    assert err <= EIG_RTOL, worst_pair(ours, ref)


@pytest.mark.parametrize("name", ["bumpy3", "wavy_disk14", "cat"])
def test_scale_invariant_spectrum_matches_scipy(name: str) -> None:
    """``metric="si"``: mass ``s * a`` with ``s = (1e-8 + Ks^2)^(alpha/2)``, Ks the one-ring mean
    of K = (libigl angle defect, minus pi on the boundary) / a. Relative 1e-6 (module doc)."""
    from conftest import load

    m = load(name)
    import scipy.sparse as sp

    alpha = 0.33
    a = igl.massmatrix(m.v, m.f, igl.MASSMATRIX_TYPE_BARYCENTRIC).diagonal()
    defect = np.asarray(igl.gaussian_curvature(m.v, m.f), dtype=np.float64)
    defect[m.boundary] -= np.pi
    k = defect / a
    adj = sp.csr_matrix(igl.adjacency_matrix(m.f)).astype(np.float64)
    adj.data[:] = 1.0
    ks = (adj @ k) / np.asarray(adj.sum(axis=1)).ravel()
    s = (1e-8 + ks**2) ** (alpha / 2)
    ref = igl_dirichlet_eigenvalues(m, K, mass_diag=s * a)
    ours = ds.spectrum(m.v, m.f, k=K, metric="si", alpha=alpha)
    err = rel_err_eigenvalues(ours, ref)
    report(f"spectrum si {name}", max_rel=err)
    assert err <= EIG_RTOL, worst_pair(ours, ref)


def worst_pair(ours: np.ndarray, ref: np.ndarray) -> str:
    """Which eigenvalue differs most, with both values (tells which solver dropped one)."""
    i = int(np.argmax(np.abs(ours - ref)))
    return f"eigenvalue {i}: ours {ours[i]:.10g}, reference {ref[i]:.10g}"


def test_spectrum_scales_as_inverse_area() -> None:
    """Law: ``V -> c V`` divides the regular eigenvalues by c^2."""
    from conftest import wavy_disk

    v, f = wavy_disk()
    e1 = ds.spectrum(v, f, k=10)
    e2 = ds.spectrum(3.0 * v, f, k=10)
    np.testing.assert_allclose(e2 * 9.0, e1, rtol=1e-8)


def test_spectrum_rejects_bad_arguments() -> None:
    from conftest import icosphere

    v, f = icosphere(1)
    with pytest.raises(ValueError, match="metric"):
        ds.spectrum(v, f, k=5, metric="nope")
    with pytest.raises(ValueError):
        ds.spectrum(v, f, k=10_000)
    with pytest.raises(ValueError):
        ds.spectrum(v, f, k=-1)
