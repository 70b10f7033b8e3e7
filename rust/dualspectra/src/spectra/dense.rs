//! Dense fallback for small pencils (where a block of the default size would not fit).
//!
//! $H\phi = \lambda M\phi$ with $M = \mathrm{diag}(m)$ becomes the standard problem
//! $M^{-1/2} H M^{-1/2} y = \lambda y$, $\phi = M^{-1/2} y$, solved by a dense symmetric
//! eigendecomposition.

use super::factor::ShiftedFactor;
use crate::error::{Error, Result};
use faer::{Mat, Side};

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
    let b = Mat::from_fn(n, n, |i, j| {
        let v = 0.5 * (h[(i, j)] + h[(j, i)]);
        v * inv_sqrt_m[i] * inv_sqrt_m[j]
    });
    let evd = b
        .self_adjoint_eigen(Side::Lower)
        .map_err(|e| Error::Numerical(format!("dense eigendecomposition failed: {e:?}")))?;
    let s = evd.S();
    let u = evd.U();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &c| s[a].total_cmp(&s[c]));
    let values: Vec<f64> = order[..k].iter().map(|&i| s[i]).collect();
    let phi = Mat::from_fn(n, k, |r, c| u[(r, order[c])] * inv_sqrt_m[r]);
    Ok((values, phi))
}
