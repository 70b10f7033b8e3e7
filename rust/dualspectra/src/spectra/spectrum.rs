//! Parameters in, spectrum and diagnostics out.

use faer::Mat;

/// Tuning of the eigensolvers. `Default` asks for the 20 smallest eigenpairs.
#[derive(Debug, Clone, PartialEq)]
pub struct EigenParams {
    /// Number $k$ of smallest eigenpairs wanted (`1 <= k < n`).
    pub k: usize,
    /// Convergence tolerance, relative: an eigenpair is accepted when the block
    /// residual of the shift-inverted operator is below `tol` times its largest eigenvalue.
    /// The achieved residual of the pencil is reported in [`EigenInfo::max_residual`].
    pub tol: f64,
    /// Maximum number of block iterations of a cold solve (an error beyond it).
    pub max_cold_iter: usize,
    /// Maximum number of block iterations of a warm re-solve before falling back to a cold solve.
    pub max_iter: usize,
    /// Shift $\sigma < 0$ of the shift-invert transform. `None`: $\sigma = -1 / \sum_j m_j$
    /// (the eigenvalue unit of a surface of that area, so the zero eigenvalue of a closed
    /// mesh and the first nonzero ones are resolved alike whatever the scale of the mesh).
    pub shift: Option<f64>,
    /// Re-use the previous eigenvectors of a [`super::HamiltonianSolver`] as the start block.
    pub warm_start: bool,
    /// Keeps the struct extensible (construct with `..Default::default()`).
    #[doc(hidden)]
    pub non_exhaustive: crate::NonExhaustive,
}

impl Default for EigenParams {
    fn default() -> Self {
        EigenParams {
            k: 20,
            tol: 1e-10,
            max_cold_iter: 300,
            max_iter: 30,
            shift: None,
            warm_start: true,
            non_exhaustive: crate::NonExhaustive::default(),
        }
    }
}

/// Diagnostics of one solve.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct EigenInfo {
    /// All `k` pairs met the tolerance.
    pub converged: bool,
    /// LOBPCG iterations (0 for the dense path of small pencils).
    pub iterations: usize,
    /// $\max_i \lVert H\phi_i - \lambda_i M\phi_i \rVert_{M^{-1}} / (|\lambda_i| + |\sigma|)$ with
    /// $H$ the operator of the pencil and $\sigma$ the shift: a relative backward error
    /// (for $\phi^\top M \phi = 1$ it bounds $|\lambda_i - \lambda_i^{\text{exact}}|/(|\lambda_i|+|\sigma|)$).
    pub max_residual: f64,
    /// The solve started from the previous eigenvectors.
    pub warm: bool,
    /// The shift $\sigma$ used.
    pub shift: f64,
}

/// The $k$ smallest eigenpairs of a pencil $H\phi = \lambda M\phi$, $M$ diagonal.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct Spectrum {
    /// Eigenvalues $\lambda_1 \le \dots \le \lambda_k$ (ascending).
    pub values: Vec<f64>,
    /// Eigenvectors, `n x k`, column `i` belongs to `values[i]`; $M$-orthonormal:
    /// $\Phi^\top M \Phi = I$. The sign of each column is fixed so that its entry of largest
    /// magnitude is positive (the lowest index wins ties).
    pub vectors: Mat<f64>,
    /// Diagnostics.
    pub info: EigenInfo,
}
