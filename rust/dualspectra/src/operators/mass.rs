//! Lumped (barycentric) mass $A = \mathrm{diag}(a_i)$, $a_i = \tfrac13 \sum_{f \ni i} |f|$,
//! and the scale-invariant mass $\tilde A = \mathrm{diag}(s) A$. Matches libigl
//! `massmatrix(..., MASSMATRIX_TYPE_BARYCENTRIC)`. docs/algorithm.md, "Discrete operators".

use crate::geometry::angles::face_areas;
use crate::mesh::TriMesh;

/// Diagonal of the lumped mass matrix.
pub fn lumped_mass(mesh: &TriMesh) -> Vec<f64> {
    let mut a = vec![0.0; mesh.n_vertices()];
    for (f, area) in mesh.faces().iter().zip(face_areas(mesh)) {
        for &i in f {
            a[i as usize] += area / 3.0;
        }
    }
    a
}

/// Diagonal of $\tilde A = \mathrm{diag}(s) A$ for a per-vertex factor `s`.
pub fn scale_invariant_mass(mass: &[f64], factor: &[f64]) -> Vec<f64> {
    mass.iter().zip(factor).map(|(a, s)| a * s).collect()
}
