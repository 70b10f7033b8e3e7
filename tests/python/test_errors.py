"""Bad input raises named exceptions (never a panic, never a crash)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import icosphere

import dualspectra as ds

V, F = icosphere(1)


def test_exception_hierarchy() -> None:
    assert issubclass(ds.MeshError, ValueError)
    assert issubclass(ds.NumericalError, RuntimeError)
    assert issubclass(ds.Cancelled, Exception)
    assert ds.__version__.count(".") == 2


@pytest.mark.parametrize(
    "faces, match",
    [
        (F - 1, "negative vertex index -1"),
        (F + len(V), "refers to vertex"),
        (np.r_[F, [[0, 0, 1]]], "repeats a vertex"),
        (F[:, :2], r"shape \(m, 3\)"),
        (np.zeros((0, 3), np.int64), "no faces"),
        (np.r_[F, F[:1]], "same three vertices as face 0 \\(a triangle given twice\\)"),
    ],
)
def test_bad_faces(faces: np.ndarray, match: str) -> None:
    with pytest.raises(ds.MeshError, match=match):
        ds.lumped_mass(V, faces)


def test_bad_vertices() -> None:
    v = V.copy()
    v[3, 1] = np.nan
    with pytest.raises(ds.MeshError, match="non-finite"):
        ds.cotangent_stiffness(v, F)
    with pytest.raises(ds.MeshError, match=r"shape \(n, 3\)"):
        ds.gaussian_curvature(V[:, :2], F)
    with pytest.raises(TypeError, match="integer"):
        ds.lumped_mass(V, F.astype(float))
    with pytest.raises(TypeError, match="numeric"):
        ds.lumped_mass(V.astype(complex), F)


def test_array_likes_are_accepted() -> None:
    """Lists, float32, uint32 and non-contiguous views all convert."""
    ref = ds.lumped_mass(V, F)
    np.testing.assert_allclose(ds.lumped_mass(V.tolist(), F.tolist()), ref)
    np.testing.assert_allclose(ds.lumped_mass(V.astype(np.float32), F.astype(np.uint32)), ref, rtol=1e-6)
    np.testing.assert_allclose(ds.lumped_mass(np.asfortranarray(V), F[:, ::-1][:, ::-1]), ref)


def test_read_mesh_errors(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError):
        ds.read_mesh(tmp_path / "missing.off")
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")
    with pytest.raises(ds.MeshError, match="bad.off"):
        ds.read_mesh(bad)
    ok = tmp_path / "tri.off"
    ok.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    v, f = ds.read_mesh(str(ok))
    assert v.shape == (3, 3) and v.dtype == np.float64 and f.tolist() == [[0, 1, 2]] and f.dtype == np.int64
    v, f, kept = ds.read_mesh(ok, return_kept=True)
    assert kept.tolist() == [0, 1, 2] and kept.dtype == np.int64


def test_read_mesh_maps_rows_to_file_records(tmp_path: Path) -> None:
    """A two-sided flap (a triangle and its reverse) is removed with its tip, record 2: the
    rows of V skip it and ``kept`` says which record each row is."""
    flap = tmp_path / "flap.off"
    flap.write_text(
        "OFF\n5 4 0\n0 0 0\n1 0 0\n0.5 -1 0\n1 1 0\n0 1 0\n"
        "3 0 1 3\n3 0 3 4\n3 0 2 1\n3 1 2 0\n"
    )
    v, f, kept = ds.read_mesh(flap, return_kept=True)
    assert kept.tolist() == [0, 1, 3, 4]
    assert v.tolist() == [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    assert kept[f].tolist() == [[0, 1, 3], [0, 3, 4]], "faces in row numbering, records through kept"
    v2, f2 = ds.read_mesh(flap)
    assert np.array_equal(v2, v) and np.array_equal(f2, f)
