//! Per-mesh operators (cotangent stiffness, lumped mass, Gaussian curvature), Dirichlet
//! spectra and mesh reading: thin calls into the core.

use crate::convert::trimesh;
use crate::errors::to_py;
use dualspectra::geometry::metric::DEFAULT_EPS;
use dualspectra::mesh::io::ReadOptions;
use dualspectra::shape::{Metric, Shape};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;
use std::path::PathBuf;

/// `(data, indices, indptr, n)`: the CSC arrays of the `n x n` cotangent stiffness `W` (= -libigl cotmatrix).
#[pyfunction]
#[allow(clippy::type_complexity)]
pub fn cotangent_stiffness<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<i64>>, Bound<'py, PyArray1<i64>>, usize)> {
    let mesh = trimesh("mesh", &vertices, &faces)?;
    let w = py.detach(|| dualspectra::operators::cotangent_stiffness(&mesh));
    let n = w.ncols();
    let mut data = Vec::with_capacity(w.compute_nnz());
    let mut indices = Vec::with_capacity(w.compute_nnz());
    let mut indptr = Vec::with_capacity(n + 1);
    indptr.push(0i64);
    for j in 0..n {
        data.extend_from_slice(w.val_of_col(j));
        indices.extend(w.row_idx_of_col_raw(j).iter().map(|&i| i as i64));
        indptr.push(data.len() as i64);
    }
    Ok((PyArray1::from_vec(py, data), PyArray1::from_vec(py, indices), PyArray1::from_vec(py, indptr), n))
}

/// Diagonal of the lumped (barycentric) mass matrix.
#[pyfunction]
pub fn lumped_mass<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let mesh = trimesh("mesh", &vertices, &faces)?;
    Ok(PyArray1::from_vec(py, py.detach(|| dualspectra::operators::lumped_mass(&mesh))))
}

/// Pointwise Gaussian curvature (angle defect / lumped area), optionally one-ring smoothed.
#[pyfunction]
#[pyo3(signature = (vertices, faces, smoothed=false))]
pub fn gaussian_curvature<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
    smoothed: bool,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let mesh = trimesh("mesh", &vertices, &faces)?;
    let k = py.detach(|| {
        if smoothed {
            dualspectra::geometry::smoothed_gaussian_curvature(&mesh)
        } else {
            dualspectra::geometry::gaussian_curvature(&mesh)
        }
    });
    Ok(PyArray1::from_vec(py, k))
}

/// The `k` smallest Dirichlet eigenvalues of `W phi = lambda M phi` (`M` the mass of `metric`).
#[pyfunction]
pub fn spectrum<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
    k: usize,
    metric: &str,
    alpha: f64,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let mesh = trimesh("mesh", &vertices, &faces)?;
    let metric: Metric = metric.parse().map_err(to_py)?;
    if !alpha.is_finite() {
        return Err(pyo3::exceptions::PyValueError::new_err(format!("alpha must be finite, got {alpha}")));
    }
    let values = py
        .detach(|| {
            Shape::with_metric_params(mesh, alpha, DEFAULT_EPS)
                .dirichlet_spectrum(metric, k)
                .map(|s| s.values)
        })
        .map_err(to_py)?;
    Ok(PyArray1::from_vec(py, values))
}

/// Read a mesh file (format from the extension) into `(V (n, 3) float64, F (m, 3) int64,
/// kept (n,) int64, warnings)`: `kept[i]` is the file's vertex record of row `i` (reading
/// drops the tip vertices of two-sided flaps and appends copies of split non-manifold
/// vertices, see `dualspectra::mesh::io`; the identity otherwise); `warnings` says what the
/// non-manifold split did (the public wrapper emits them as `DualspectraWarning`).
#[pyfunction]
#[allow(clippy::type_complexity)]
pub fn read_mesh<'py>(
    py: Python<'py>,
    path: PathBuf,
) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<i64>>, Bound<'py, PyArray1<i64>>, Vec<String>)> {
    let (mesh, report) = py
        .detach(|| dualspectra::mesh::io::read_mesh_with_report(&path, &ReadOptions::default()))
        .map_err(to_py)?;
    let warnings = report
        .non_manifold_warning()
        .map(|w| format!("{}: {w}; rows after the file's vertices are copies (see kept)", path.display()))
        .into_iter()
        .collect();
    let (v, f) = mesh.into_parts();
    let (n, m) = (v.len(), f.len());
    let v = Array2::from_shape_vec((n, 3), v.into_iter().flatten().collect()).map_err(shape_err)?;
    let f = Array2::from_shape_vec((m, 3), f.into_iter().flatten().map(i64::from).collect()).map_err(shape_err)?;
    let kept = report.kept_vertices.into_iter().map(i64::from).collect();
    Ok((v.into_pyarray(py), f.into_pyarray(py), PyArray1::from_vec(py, kept), warnings))
}

fn shape_err(e: numpy::ndarray::ShapeError) -> PyErr {
    pyo3::exceptions::PyRuntimeError::new_err(format!("internal array shape error: {e}"))
}
