//! The descriptor baseline start (ALGORITHM.md "Optimisation": the 41st start): a guess of
//! the region from SHOT descriptors alone, $w_0 = 2 - 4 R_0$.
//!
//! The reference clusters the SHOT descriptors of both shapes together (k-means,
//! $\min(4000, |N|)$ clusters) and marks the vertices of $M$ that share a cluster with some
//! vertex of $N$. We use the nearest-neighbour form of the same idea, which needs no iterative
//! clustering and no random initialisation: for every vertex $i$ of $M$ the descriptor distance
//! to the closest descriptor of $N$, $d_i = \min_j \lVert D_M(i) - D_N(j) \rVert$, and $R_0$ =
//! the vertices of lowest $d_i$ whose mass adds up to the partial's area (a cluster shared with
//! $N$ is a neighbourhood of some $D_N(j)$; ranking by $d_i$ and matching the area replaces the
//! choice of the number of clusters). $R_0$ is then closed on the mesh graph, as regions are.

use crate::error::{Error, Result};
use crate::region::energy::area_matched_region;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};

/// Descriptors of the partial compared per block (bounds the distance matrix's memory).
const BLOCK: usize = 512;

/// $d_i = \min_j \lVert a_i - b_j \rVert^2$ for the rows of `a` against the rows of `b`, by
/// $\lVert a\rVert^2 + \lVert b\rVert^2 - 2 a\cdot b$ in blocks (one matrix product per block).
/// Zero rows of `b` (SHOT with too small a support) are skipped.
pub fn nearest_descriptor_distances(a: &Mat<f64>, b: &Mat<f64>) -> Result<Vec<f64>> {
    if a.ncols() != b.ncols() {
        return Err(Error::InvalidArgument(format!(
            "descriptors of {} and {} dimensions",
            a.ncols(),
            b.ncols()
        )));
    }
    let norm2 = |m: &Mat<f64>, i: usize| (0..m.ncols()).map(|c| m[(i, c)].powi(2)).sum::<f64>();
    let keep: Vec<usize> = (0..b.nrows()).filter(|&j| norm2(b, j) > 0.0).collect();
    if keep.is_empty() {
        return Err(Error::Numerical("the partial shape has no usable descriptor".into()));
    }
    let a2: Vec<f64> = (0..a.nrows()).map(|i| norm2(a, i)).collect();
    let mut best = vec![f64::INFINITY; a.nrows()];
    for chunk in keep.chunks(BLOCK) {
        let bt = Mat::from_fn(a.ncols(), chunk.len(), |c, j| b[(chunk[j], c)]);
        let b2: Vec<f64> = chunk.iter().map(|&j| norm2(b, j)).collect();
        let mut dot = Mat::<f64>::zeros(a.nrows(), chunk.len());
        matmul(dot.as_mut(), Accum::Replace, a.as_ref(), bt.as_ref(), 1.0, Par::Seq);
        for (i, best_i) in best.iter_mut().enumerate() {
            for (j, &b2j) in b2.iter().enumerate() {
                let d = (a2[i] + b2j - 2.0 * dot[(i, j)]).max(0.0);
                if d < *best_i {
                    *best_i = d;
                }
            }
        }
    }
    Ok(best)
}

/// $R_0$ on the full shape's vertices: the lowest nearest-descriptor distances whose mass adds
/// up to `partial_area`. Vertices without a usable descriptor (zero rows) come last.
pub fn descriptor_baseline_mask(
    full_desc: &Mat<f64>,
    partial_desc: &Mat<f64>,
    full_mass: &[f64],
    partial_area: f64,
) -> Result<Vec<bool>> {
    if full_desc.nrows() != full_mass.len() {
        return Err(Error::InvalidArgument(format!(
            "{} descriptors for {} vertices",
            full_desc.nrows(),
            full_mass.len()
        )));
    }
    let d = nearest_descriptor_distances(full_desc, partial_desc)?;
    let usable = |i: usize| (0..full_desc.ncols()).any(|c| full_desc[(i, c)] != 0.0);
    // area_matched_region takes the highest values first: rank by -d.
    let score: Vec<f64> = d.iter().enumerate().map(|(i, &x)| if usable(i) { -x } else { f64::NEG_INFINITY }).collect();
    Ok(area_matched_region(&score, full_mass, partial_area))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_distances_match_brute_force() {
        let a = Mat::from_fn(37, 5, |i, j| ((i * 7 + j * 3) % 11) as f64 / 11.0 - 0.4);
        let b = Mat::from_fn(600, 5, |i, j| ((i * 5 + j * 13) % 17) as f64 / 17.0 - 0.5);
        let d = nearest_descriptor_distances(&a, &b).unwrap();
        for i in 0..a.nrows() {
            let brute = (0..b.nrows())
                .map(|j| (0..5).map(|c| (a[(i, c)] - b[(j, c)]).powi(2)).sum::<f64>())
                .fold(f64::INFINITY, f64::min);
            assert!((d[i] - brute).abs() < 1e-12, "{} vs {brute}", d[i]);
        }
        assert!(nearest_descriptor_distances(&a, &Mat::zeros(3, 5)).is_err());
        assert!(nearest_descriptor_distances(&a, &Mat::zeros(3, 4)).is_err());
    }

    /// The descriptors of a shape against those of one of its parts: the part's own vertices
    /// are at distance 0, so the mask is exactly the part (area matched).
    #[test]
    fn mask_of_an_exact_part_is_the_part() {
        let m = crate::mesh::generate::icosphere(3);
        let shot = crate::alignment::shot::shot_descriptors(&m, 0.5, 3).unwrap();
        let mass = crate::operators::lumped_mass(&m);
        let part: Vec<usize> = (0..m.n_vertices()).filter(|&i| m.vertices()[i][2] > 0.3).collect();
        let pd = Mat::from_fn(part.len(), shot.ncols(), |i, c| shot[(part[i], c)]);
        let area: f64 = part.iter().map(|&i| mass[i]).sum();
        let mask = descriptor_baseline_mask(&shot, &pd, &mass, area - 1e-12).unwrap();
        let chosen: Vec<usize> = (0..m.n_vertices()).filter(|&i| mask[i]).collect();
        // Every vertex at distance 0 is a candidate; on a sphere many are (all SHOTs agree up to
        // discretisation), so only check the area and that chosen vertices are at distance ~0.
        let d = nearest_descriptor_distances(&shot, &pd).unwrap();
        let chosen_area: f64 = chosen.iter().map(|&i| mass[i]).sum();
        assert!((chosen_area - area).abs() <= mass.iter().cloned().fold(0.0, f64::max) + 1e-12);
        let worst_chosen = chosen.iter().map(|&i| d[i]).fold(0.0, f64::max);
        let best_unchosen = (0..m.n_vertices()).filter(|&i| !mask[i]).map(|i| d[i]).fold(f64::INFINITY, f64::min);
        assert!(worst_chosen <= best_unchosen + 1e-12);
    }
}
