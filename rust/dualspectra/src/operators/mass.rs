//! Lumped (barycentric) mass $A = \mathrm{diag}(a_i)$, $a_i = \tfrac13 \sum_{f \ni i} |f|$,
//! and the scale-invariant mass $\tilde A = \mathrm{diag}(s) A$. Matches libigl
//! `massmatrix(..., MASSMATRIX_TYPE_BARYCENTRIC)`. docs/algorithm.md, "Discrete operators".

use crate::mesh::TriMesh;

/// Diagonal of the lumped mass matrix: the barycentric vertex areas.
pub fn lumped_mass(mesh: &TriMesh) -> Vec<f64> {
    crate::geometry::angles::vertex_areas(mesh)
}

/// Diagonal of $\tilde A = \mathrm{diag}(s) A$ for a per-vertex factor `s`.
pub fn scale_invariant_mass(mass: &[f64], factor: &[f64]) -> Vec<f64> {
    mass.iter().zip(factor).map(|(a, s)| a * s).collect()
}
