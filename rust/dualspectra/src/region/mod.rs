//! From an optimised potential to a vertex region: eigenvector energy, thresholding, closing, transfer.

pub mod energy;
pub mod closing;

use crate::error::Result;
use crate::mesh::TriMesh;
use crate::shape::Shape;

/// Rings of the morphological closing applied on the full shape (ALGORITHM.md: grow 4, shrink 4).
pub const CLOSING_RINGS: usize = 4;

/// Transfer a region, a score and a potential from the optimisation mesh to the full mesh by
/// nearest neighbour, then close the region by [`CLOSING_RINGS`] rings on the full mesh.
/// Returns `(region, score in [0, 1], potential)` per full-mesh vertex.
pub fn transfer_to_full(
    opt: &Shape,
    full: &TriMesh,
    region: &[bool],
    energy: &[f64],
    potential: &[f64],
) -> Result<(Vec<bool>, Vec<f64>, Vec<f64>)> {
    let nearest = crate::mesh::nearest::nearest_vertices(opt.mesh().vertices(), full.vertices())?;
    let emax = energy.iter().cloned().fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    let mut r: Vec<bool> = nearest.iter().map(|&j| region[j as usize]).collect();
    let score = nearest.iter().map(|&j| (energy[j as usize] / emax).clamp(0.0, 1.0)).collect();
    let pot = nearest.iter().map(|&j| potential[j as usize]).collect();
    let neighbors = crate::mesh::topology::vertex_neighbors(full);
    r = crate::region::closing::close(&r, &neighbors, CLOSING_RINGS)?;
    Ok((r, score, pot))
}
