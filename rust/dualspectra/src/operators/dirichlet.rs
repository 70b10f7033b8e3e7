//! Homogeneous Dirichlet conditions by elimination: the rows and columns of boundary
//! vertices are removed before the eigensolve; eigenfunctions are zero there.

use super::SparseMatrix;
use faer::sparse::Triplet;

/// The map between all vertices and the free (interior) ones.
#[derive(Debug, Clone)]
pub struct Dirichlet {
    /// `free[k]` = original index of the k-th free vertex.
    pub free: Vec<u32>,
    /// `position[i]` = index among free vertices, or `u32::MAX` for a constrained vertex.
    pub position: Vec<u32>,
}

impl Dirichlet {
    /// Constrain the vertices where `constrained[i]` is true.
    pub fn new(constrained: &[bool]) -> Self {
        let free: Vec<u32> = (0..constrained.len() as u32).filter(|&i| !constrained[i as usize]).collect();
        let mut position = vec![u32::MAX; constrained.len()];
        for (k, &i) in free.iter().enumerate() {
            position[i as usize] = k as u32;
        }
        Dirichlet { free, position }
    }
    /// No constraint (closed meshes).
    pub fn none(n: usize) -> Self {
        Self::new(&vec![false; n])
    }
    pub fn n_free(&self) -> usize {
        self.free.len()
    }
    pub fn n_all(&self) -> usize {
        self.position.len()
    }
    /// `M[free, free]`.
    pub fn restrict_matrix(&self, m: &SparseMatrix) -> SparseMatrix {
        let mut trip = Vec::with_capacity(m.compute_nnz());
        for j in 0..m.ncols() {
            let pj = self.position[j];
            if pj == u32::MAX {
                continue;
            }
            let rows = m.row_idx_of_col_raw(j);
            let vals = m.val_of_col(j);
            for (&i, &v) in rows.iter().zip(vals) {
                let pi = self.position[i];
                if pi != u32::MAX {
                    trip.push(Triplet::new(pi as usize, pj as usize, v));
                }
            }
        }
        SparseMatrix::try_new_from_triplets(self.n_free(), self.n_free(), &trip).expect("valid triplets")
    }
    /// `x[free]`.
    pub fn restrict<T: Copy>(&self, x: &[T]) -> Vec<T> {
        self.free.iter().map(|&i| x[i as usize]).collect()
    }
    /// Scatter free values into a full-length vector, `fill` at constrained vertices.
    pub fn extend<T: Copy>(&self, x: &[T], fill: T) -> Vec<T> {
        let mut out = vec![fill; self.n_all()];
        for (k, &i) in self.free.iter().enumerate() {
            out[i as usize] = x[k];
        }
        out
    }
}
