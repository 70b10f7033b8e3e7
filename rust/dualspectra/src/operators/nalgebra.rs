//! The operators as [`nalgebra_sparse`] matrices (feature `nalgebra`), for Rust code built on
//! nalgebra: the same values as [`super::cotangent_stiffness`] and [`super::lumped_mass`],
//! converted, never recomputed.

use super::SparseMatrix;
use crate::mesh::TriMesh;
use nalgebra_sparse::{CooMatrix, CscMatrix};

/// A faer sparse matrix as an `nalgebra-sparse` CSC matrix (same entries; explicit zeros kept,
/// duplicates summed).
pub fn to_csc(matrix: &SparseMatrix) -> CscMatrix<f64> {
    let (rows, cols) = (matrix.nrows(), matrix.ncols());
    let mut coo = CooMatrix::new(rows, cols);
    for j in 0..cols {
        for (&i, &v) in matrix.row_idx_of_col_raw(j).iter().zip(matrix.val_of_col(j)) {
            coo.push(i, j, v);
        }
    }
    CscMatrix::from(&coo)
}

/// The cotangent stiffness matrix $W$ of [`super::cotangent_stiffness`] as a CSC matrix.
pub fn cotangent_stiffness(mesh: &TriMesh) -> CscMatrix<f64> {
    to_csc(&super::cotangent_stiffness(mesh))
}

/// The lumped mass matrix $A = \mathrm{diag}(a)$ of [`super::lumped_mass`] as a diagonal CSC matrix.
pub fn lumped_mass(mesh: &TriMesh) -> CscMatrix<f64> {
    let a = super::lumped_mass(mesh);
    let mut coo = CooMatrix::new(a.len(), a.len());
    for (i, &ai) in a.iter().enumerate() {
        coo.push(i, i, ai);
    }
    CscMatrix::from(&coo)
}
