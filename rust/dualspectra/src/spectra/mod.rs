//! Generalized symmetric eigenproblems $W\phi = \lambda M \phi$ with $M$ diagonal, and the
//! Hamiltonians $(W + \mathrm{diag}(m \odot v))\phi = \lambda\,\mathrm{diag}(m)\,\phi$
//! (docs/algorithm.md, "Spectra").
//!
//! - [`generalized_eigen`]: one-shot, the $k$ smallest eigenpairs of a pencil.
//! - [`SymbolicHamiltonian`]: the symbolic Cholesky analysis of one $W$, shared.
//! - [`HamiltonianSolver`]: built once per $(W, m)$ (on a shared analysis), then
//!   [`HamiltonianSolver::solve`] per potential $v$ (numeric factorisation + warm start from
//!   the previous eigenvectors).
//! - [`eigenvalue_gradient`]: $\partial\lambda_i/\partial v_j = m_j\phi_{ji}^2$.
//!
//! This module sees matrices, not meshes: the caller assembles $W$ and $m$ (and applies the
//! Dirichlet restriction) with [`crate::operators`].

mod block;
mod dense;
mod eigensolver;
mod factor;
mod gradient;
mod spectrum;

pub use eigensolver::{generalized_eigen, HamiltonianSolver, SymbolicHamiltonian};
pub use gradient::{eigenvalue_gradient, eigenvalue_gradient_dot};
pub use spectrum::{EigenInfo, EigenParams, Spectrum};
pub(crate) use dense::symmetric_eigen;
