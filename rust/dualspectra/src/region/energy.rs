//! Where the Hamiltonian's eigenfunctions live: the energy $e_i = \frac1k\sum_j \phi_{ij}^2$
//! (mass-normalised $\phi$, so $\sum_i a_i e_i = 1$). Property 1 of the paper: eigenfunctions
//! decay where $v > \lambda$, so $e$ is large on the matched region and tiny elsewhere.
//!
//! Two region rules:
//! - [`threshold_region`]: the reference rule $e_i > \beta$ with a scale-free $\beta$ given
//!   as a fraction of $1/|N|$ (the energy of a uniform density on an area $|N|$);
//! - [`area_matched_region`]: the highest-energy vertices whose mass adds up to the partial's area.

use faer::Mat;

/// $e_i = \frac1k \sum_j \phi_{ij}^2$ over the columns of `vectors` (rows = vertices).
pub fn eigenvector_energy(vectors: &Mat<f64>) -> Vec<f64> {
    let k = vectors.ncols().max(1) as f64;
    (0..vectors.nrows()).map(|i| (0..vectors.ncols()).map(|j| vectors[(i, j)].powi(2)).sum::<f64>() / k).collect()
}

/// `e_i > fraction / area` (with `area` the partial's area in the same units as the mass).
#[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
pub fn threshold_region(energy: &[f64], partial_area: f64, fraction: f64) -> Vec<bool> {
    let t = fraction / partial_area;
    energy.iter().map(|&e| e > t).collect()
}

/// The highest-energy vertices until their mass reaches `target_area` (ties broken by index);
/// see [`crate::geometry::area_matched_set`].
pub fn area_matched_region(energy: &[f64], mass: &[f64], target_area: f64) -> Vec<bool> {
    crate::geometry::area_matched_set(energy, mass, target_area)
}
