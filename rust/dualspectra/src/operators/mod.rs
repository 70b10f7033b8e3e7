//! Discrete operators: cotangent stiffness, lumped mass, Dirichlet restriction, Hamiltonian.

pub(crate) mod stiffness;
pub(crate) mod mass;
pub(crate) mod dirichlet;
#[cfg(feature = "nalgebra")]
pub mod nalgebra;

pub use dirichlet::Dirichlet;
pub use mass::{lumped_mass, scale_invariant_mass};
pub use stiffness::cotangent_stiffness;

/// Sparse symmetric matrix type used throughout (column-major, `usize` indices).
pub type SparseMatrix = faer::sparse::SparseColMat<usize, f64>;
