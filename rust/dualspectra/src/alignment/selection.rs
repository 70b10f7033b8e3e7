//! Choosing among the optimised starts by descriptors projected on eigenfunctions
//! (ALGORITHM.md "Choosing among the starts"):
//! $c_N = (\Psi^{\circ 2})^\top A_N D_N$ with $\Psi$ the first $k_d$ Dirichlet eigenfunctions of
//! the partial, and for a candidate region $R$ on the full shape
//! $c_M = (\Phi^{\circ 2})^\top A_M D_M$ with $\Phi$ the first $k_d$ eigenfunctions of
//! $W + A\,\mathrm{diag}(\tau (1 - R))$. The score $\sum |c_M - c_N|$ is summed over the
//! regular and (in the dual method) the scale-invariant metric; the lowest score wins.

use crate::error::Result;
use crate::shape::{Metric, Shape};
use crate::spectra::{EigenParams, HamiltonianSolver};
use faer::Mat;

/// Eigenfunctions used by the projection (the reference uses 5).
pub const PROJECTION_EIGENFUNCTIONS: usize = 5;

/// $(\Phi^{\circ 2})^\top \mathrm{diag}(m) D$: a `k x d` matrix. Rows of `vectors`, `mass` and `desc` match.
pub fn descriptor_projection(vectors: &Mat<f64>, mass: &[f64], desc: &Mat<f64>) -> Mat<f64> {
    let (n, k, d) = (vectors.nrows(), vectors.ncols(), desc.ncols());
    let mut out = Mat::<f64>::zeros(k, d);
    for j in 0..k {
        for i in 0..n {
            let w = vectors[(i, j)].powi(2) * mass[i];
            if w == 0.0 {
                continue;
            }
            for c in 0..d {
                out[(j, c)] += w * desc[(i, c)];
            }
        }
    }
    out
}

/// The partial's projections, one per metric.
pub fn partial_signatures(partial: &Shape, desc: &Mat<f64>, metrics: &[Metric]) -> Result<Vec<Mat<f64>>> {
    let dir = partial.dirichlet();
    let desc_free = restrict_rows(desc, &dir.free);
    metrics
        .iter()
        .map(|&m| {
            let k = PROJECTION_EIGENFUNCTIONS.min(dir.n_free().saturating_sub(1)).max(1);
            let s = partial.dirichlet_spectrum(m, k)?;
            Ok(descriptor_projection(&s.vectors, &dir.restrict(partial.metric_mass(m)), &desc_free))
        })
        .collect()
}

/// Score every candidate region on `full` (lower is better): $\sum_t \sum |c_M^t - c_N^t|$.
pub fn selection_scores(
    full: &Shape,
    desc: &Mat<f64>,
    metrics: &[Metric],
    targets: &[Mat<f64>],
    heights: &[f64],
    regions: &[Vec<bool>],
) -> Result<Vec<f64>> {
    let dir = full.dirichlet();
    let desc_free = restrict_rows(desc, &dir.free);
    let mut scores = vec![0.0; regions.len()];
    for ((&m, target), &tau) in metrics.iter().zip(targets).zip(heights) {
        let mass = dir.restrict(full.metric_mass(m));
        let params = EigenParams { k: target.nrows(), ..EigenParams::default() };
        let mut solver = HamiltonianSolver::new(full.dirichlet_stiffness(), &mass, params)?;
        for (r, score) in regions.iter().zip(scores.iter_mut()) {
            let v: Vec<f64> = dir.free.iter().map(|&i| if r[i as usize] { 0.0 } else { tau }).collect();
            let s = solver.solve(&v)?;
            let c = descriptor_projection(&s.vectors, &mass, &desc_free);
            let mut diff = 0.0;
            for j in 0..c.nrows() {
                for col in 0..c.ncols() {
                    diff += (c[(j, col)] - target[(j, col)]).abs();
                }
            }
            *score += diff;
        }
    }
    Ok(scores)
}

fn restrict_rows(m: &Mat<f64>, rows: &[u32]) -> Mat<f64> {
    Mat::from_fn(rows.len(), m.ncols(), |i, j| m[(rows[i] as usize, j)])
}
