//! Derivative of the eigenvalues with respect to the potential.
//!
//! For $(W + \mathrm{diag}(m \odot v))\phi_i = \lambda_i\, \mathrm{diag}(m)\, \phi_i$ with
//! $\phi_i^\top \mathrm{diag}(m) \phi_i = 1$ and a simple eigenvalue, Hellmann-Feynman gives
//! $$\frac{\partial \lambda_i}{\partial v_j} = \phi_i^\top \frac{\partial H}{\partial v_j}\phi_i = m_j\, \phi_{ji}^2 .$$
//! (docs/algorithm.md, "Gradient of the spectral cost"; for a repeated eigenvalue this is the
//! derivative of the eigenvalue branch carried by the returned basis vector.)

use crate::error::{Error, Result};
use faer::Mat;

/// The `k x n` Jacobian $J_{ij} = \partial\lambda_i / \partial v_j = m_j \phi_{ji}^2$ for the
/// `n x k` $M$-orthonormal eigenvectors `vectors` of the Hamiltonian and its mass `mass`.
pub fn eigenvalue_gradient(vectors: &Mat<f64>, mass: &[f64]) -> Result<Mat<f64>> {
    let (n, k) = (vectors.nrows(), vectors.ncols());
    if mass.len() != n {
        return Err(Error::InvalidArgument(format!(
            "mass has {} entries, eigenvectors have {n} rows",
            mass.len()
        )));
    }
    Ok(Mat::from_fn(k, n, |i, j| {
        let p = vectors[(j, i)];
        mass[j] * p * p
    }))
}

/// $g_j = \sum_i c_i\, \partial\lambda_i/\partial v_j = m_j \sum_i c_i \phi_{ji}^2$: the gradient
/// of a cost $C(\lambda)$ with $c_i = \partial C / \partial \lambda_i$, without forming the
/// Jacobian. `coeffs.len() == vectors.ncols()`, output length `n`.
pub fn eigenvalue_gradient_dot(vectors: &Mat<f64>, mass: &[f64], coeffs: &[f64]) -> Result<Vec<f64>> {
    let (n, k) = (vectors.nrows(), vectors.ncols());
    if mass.len() != n || coeffs.len() != k {
        return Err(Error::InvalidArgument(format!(
            "mass has {} entries and coeffs {}, expected {n} and {k}",
            mass.len(),
            coeffs.len()
        )));
    }
    let mut g = vec![0.0; n];
    for (i, &c) in coeffs.iter().enumerate() {
        let col = vectors.col(i);
        for j in 0..n {
            let p = col[j];
            g[j] += c * p * p;
        }
    }
    for (gj, &mj) in g.iter_mut().zip(mass) {
        *gj *= mj;
    }
    Ok(g)
}
