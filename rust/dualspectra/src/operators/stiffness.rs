//! Cotangent stiffness matrix $W$ (positive semi-definite):
//! $W_{ij} = -\tfrac12(\cot\alpha_{ij} + \cot\beta_{ij})$ for an edge $ij$ with opposite angles
//! $\alpha_{ij}, \beta_{ij}$ (one on a boundary edge), $W_{ii} = -\sum_{j\ne i} W_{ij}$.
//! Sign convention: $W = -L$ with $L$ libigl's `cotmatrix`. docs/algorithm.md, "Discrete operators".

use super::SparseMatrix;
use crate::geometry::angles::{cross, dot, norm, sub};
use crate::mesh::TriMesh;
use faer::sparse::Triplet;

/// Cotangent of the angle at each corner: `cot[f][c]` at vertex `F[f][c]`, opposite edge
/// `(F[f][c+1], F[f][c+2])`.
pub fn corner_cotangents(mesh: &TriMesh) -> Vec<[f64; 3]> {
    let v = mesh.vertices();
    mesh.faces()
        .iter()
        .map(|f| {
            let mut ct = [0.0; 3];
            for c in 0..3 {
                let p = v[f[c] as usize];
                let u = sub(v[f[(c + 1) % 3] as usize], p);
                let w = sub(v[f[(c + 2) % 3] as usize], p);
                ct[c] = dot(u, w) / norm(cross(u, w));
            }
            ct
        })
        .collect()
}

/// The `n x n` cotangent stiffness matrix $W$ (symmetric, rows sum to zero).
pub fn cotangent_stiffness(mesh: &TriMesh) -> SparseMatrix {
    let n = mesh.n_vertices();
    let cots = corner_cotangents(mesh);
    let mut trip = Vec::with_capacity(mesh.n_faces() * 12);
    for (f, ct) in mesh.faces().iter().zip(&cots) {
        for c in 0..3 {
            let i = f[(c + 1) % 3] as usize;
            let j = f[(c + 2) % 3] as usize;
            let w = 0.5 * ct[c];
            trip.push(Triplet::new(i, j, -w));
            trip.push(Triplet::new(j, i, -w));
            trip.push(Triplet::new(i, i, w));
            trip.push(Triplet::new(j, j, w));
        }
    }
    SparseMatrix::try_new_from_triplets(n, n, &trip).expect("valid triplets")
}
