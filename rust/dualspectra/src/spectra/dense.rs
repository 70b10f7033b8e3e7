//! Dense fallback for small pencils (where a block of the default size would not fit).
//!
//! $H\phi = \lambda M\phi$ with $M = \mathrm{diag}(m)$ becomes the standard problem
//! $M^{-1/2} H M^{-1/2} y = \lambda y$, $\phi = M^{-1/2} y$, solved by a dense symmetric
//! eigendecomposition.

use super::factor::ShiftedFactor;
use crate::error::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd::{self_adjoint_evd, self_adjoint_evd_scratch, ComputeEigenvectors, EvdError};
use faer::diag::Diag;
use faer::{Mat, MatRef, Par};

/// Eigenvalues (ascending) and eigenvectors of the symmetric matrix whose lower triangle is
/// `a`, computed sequentially. faer's `Mat::self_adjoint_eigen` takes its parallelism from
/// the rayon pool it is called in, and a parallel reduction rounds differently: the same
/// localization gave different regions on 1 and 2 threads. Every dense decomposition of the
/// pipeline goes through these functions, so results do not depend on the thread count.
pub(crate) fn symmetric_eigen(a: MatRef<'_, f64>) -> std::result::Result<(Vec<f64>, Mat<f64>), EvdError> {
    let n = a.nrows();
    let (mut s, mut u) = (Diag::<f64>::zeros(n), Mat::<f64>::zeros(n, n));
    let mut mem = MemBuffer::new(self_adjoint_evd_scratch::<f64>(n, ComputeEigenvectors::Yes, Par::Seq, Default::default()));
    self_adjoint_evd(a, s.as_mut(), Some(u.as_mut()), Par::Seq, MemStack::new(&mut mem), Default::default())?;
    Ok((s.column_vector().iter().copied().collect(), u))
}

/// The lower Cholesky factor `L` (`a = L L^T`) of the symmetric positive definite matrix
/// whose lower triangle is `a`, computed sequentially (see [`symmetric_eigen`]); `None` if
/// `a` is not numerically positive definite.
pub(crate) fn cholesky_lower(a: MatRef<'_, f64>) -> Option<Mat<f64>> {
    use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch};
    let n = a.nrows();
    let mut l = Mat::from_fn(n, n, |i, j| if i >= j { a[(i, j)] } else { 0.0 });
    let mut mem = MemBuffer::new(cholesky_in_place_scratch::<f64>(n, Par::Seq, Default::default()));
    cholesky_in_place(l.as_mut(), Default::default(), Par::Seq, MemStack::new(&mut mem), Default::default()).ok()?;
    for j in 0..n {
        for i in 0..j {
            l[(i, j)] = 0.0;
        }
    }
    Some(l)
}

/// The `k` smallest eigenpairs of `(W + diag(extra)) phi = lambda diag(m) phi`, with
/// `inv_sqrt_m = m^{-1/2}`. Returns `(values ascending, phi n x k)`.
pub(crate) fn dense_smallest(
    factor: &ShiftedFactor,
    extra: &[f64],
    inv_sqrt_m: &[f64],
    k: usize,
) -> Result<(Vec<f64>, Mat<f64>)> {
    let n = factor.n();
    let eye = Mat::<f64>::identity(n, n);
    let mut h = Mat::<f64>::zeros(n, n);
    factor.w_mul(h.as_mut(), eye.as_ref());
    for i in 0..n {
        h[(i, i)] += extra[i];
    }
    let mut b = Mat::from_fn(n, n, |i, j| {
        let v = 0.5 * (h[(i, j)] + h[(j, i)]);
        v * inv_sqrt_m[i] * inv_sqrt_m[j]
    });
    // The decomposition's deflation tests are partly absolute: a pencil of a mesh in
    // nanometres or in kilometres (entries ~1e±16) loses convergence. Solve the matrix scaled
    // to unit size by a power of two (exact), and scale the eigenvalues back.
    let unit = power_of_two_near((0..n).map(|i| b[(i, i)].abs()).fold(0.0, f64::max));
    for j in 0..n {
        for i in 0..n {
            b[(i, j)] /= unit;
        }
    }
    let (s, u) = symmetric_eigen(b.as_ref()).map_err(|e| Error::Numerical(format!("dense eigendecomposition failed: {e:?}")))?;
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &c| s[a].total_cmp(&s[c]));
    let values: Vec<f64> = order[..k].iter().map(|&i| s[i] * unit).collect();
    let phi = Mat::from_fn(n, k, |r, c| u[(r, order[c])] * inv_sqrt_m[r]);
    Ok((values, phi))
}

/// The power of two nearest to `x` in ratio (1 for zero or non-finite `x`).
fn power_of_two_near(x: f64) -> f64 {
    if !(x > 0.0) || !x.is_finite() {
        return 1.0;
    }
    2f64.powi(x.log2().round() as i32)
}
