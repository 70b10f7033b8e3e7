//! Discrete operators: cotangent stiffness, lumped mass, Dirichlet restriction, Hamiltonian.

pub mod stiffness;
pub mod mass;
pub mod dirichlet;

pub use dirichlet::Dirichlet;
pub use mass::{lumped_mass, scale_invariant_mass};
pub use stiffness::cotangent_stiffness;

/// Sparse symmetric matrix type used throughout (column-major, `usize` indices).
pub type SparseMatrix = faer::sparse::SparseColMat<usize, f64>;
