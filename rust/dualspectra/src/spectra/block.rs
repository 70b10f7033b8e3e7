//! Warm re-solve: LOBPCG preconditioned by the shifted Cholesky factor.
//!
//! Start block $X$ ($n \times k$, the previous eigenvectors). Each iteration forms the
//! residuals $R = HX - MX\Lambda$, the preconditioned directions $W = K^{-1}R$ for the
//! columns not yet converged ($K = H - \sigma M$, factorised by the caller), and the
//! Rayleigh-Ritz projection of the pencil onto $\mathrm{span}[X, W, P]$ ($P$ the previous
//! update directions): with $S$ that basis, $G = S^\top M S$, $A = S^\top H S$, the $k$
//! smallest eigenpairs of $A c = \lambda G c$ give $X \leftarrow S C$ (Knyazev 2001,
//! "Toward the optimal preconditioned eigensolver: LOBPCG"). $G$ is inverted through its
//! Cholesky factor, or, when the basis is near-dependent, its eigendecomposition, dropping
//! those directions (Stathopoulos & Wu 2002, SVQB), so the basis needs no explicit
//! orthogonalisation.
//!
//! With $K^{-1}$ the exact shift-inverted operator, $\mathrm{span}[X, W]
//! = \mathrm{span}[X, K^{-1}MX]$: a block Krylov step. When the potential changed a little,
//! $X$ is nearly invariant and a few iterations suffice.

use super::dense::{cholesky_lower, symmetric_eigen};
use super::factor::ShiftedFactor;
use crate::error::Result;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::matmul::matmul;
use faer::reborrow::ReborrowMut;
use faer::{Accum, Mat, MatMut, MatRef, Par};

/// The `n`-row blocks of [`refine`], kept between iterations and between solves so that
/// each is allocated once (per solver) and written in place: $X$, $HX$, the residuals
/// $R$, $W$, $HW$, $P$, $HP$, the basis $S$, $HS$ and $MS$. Each buffer grows when a
/// block needs more columns than it has; a block is its first columns.
#[derive(Debug)]
pub(crate) struct Workspace {
    x: Mat<f64>,
    hx: Mat<f64>,
    r: Mat<f64>,
    w: Mat<f64>,
    hw: Mat<f64>,
    p: Mat<f64>,
    hp: Mat<f64>,
    s: Mat<f64>,
    hs: Mat<f64>,
    ms: Mat<f64>,
}

impl Workspace {
    /// Empty buffers (they grow on first use).
    pub(crate) fn new() -> Self {
        Workspace {
            x: Mat::new(),
            hx: Mat::new(),
            r: Mat::new(),
            w: Mat::new(),
            hw: Mat::new(),
            p: Mat::new(),
            hp: Mat::new(),
            s: Mat::new(),
            hs: Mat::new(),
            ms: Mat::new(),
        }
    }
}

/// The first `ncols` columns of `buf` as an `n x ncols` block to overwrite; `buf` is
/// reallocated when it has another row count or too few columns.
fn block_mut(buf: &mut Mat<f64>, n: usize, ncols: usize) -> MatMut<'_, f64> {
    if buf.nrows() != n || buf.ncols() < ncols {
        let cap = if buf.nrows() == n {
            ncols.max(buf.ncols())
        } else {
            ncols
        };
        *buf = Mat::zeros(n, cap);
    }
    buf.as_mut().subcols_mut(0, ncols)
}

/// The first `ncols` columns of `buf`.
fn block(buf: &Mat<f64>, ncols: usize) -> MatRef<'_, f64> {
    buf.as_ref().subcols(0, ncols)
}

/// Column `j` of a block as a slice (the blocks here are column-major, their columns
/// contiguous): loops over it index a slice instead of a strided view.
fn column(a: MatRef<'_, f64>, j: usize) -> &[f64] {
    a.col(j).try_as_col_major().expect("column-major block").as_slice()
}

/// Column `j` of a block as a mutable slice ([`column`]).
fn column_mut(a: MatMut<'_, f64>, j: usize) -> &mut [f64] {
    a.col_mut(j).try_as_col_major_mut().expect("column-major block").as_slice_mut()
}

/// $\sum_i r_i^2 w_i$ in four interleaved partial sums: a single running sum waits on each
/// addition in turn (the residual norms of [`refine`] were a tenth of a localization's time).
fn weighted_squares(r: &[f64], w: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (rc, wc) = (r.chunks_exact(4), w.chunks_exact(4));
    let tail: f64 = rc.remainder().iter().zip(wc.remainder()).map(|(a, b)| a * a * b).sum();
    for (a, b) in rc.zip(wc) {
        for l in 0..4 {
            acc[l] += a[l] * a[l] * b[l];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// `out = H x = W x + (m v) .* x`.
fn h_mul(factor: &ShiftedFactor, mv: &[f64], x: MatRef<'_, f64>, mut out: MatMut<'_, f64>) {
    factor.w_mul(out.rb_mut(), x);
    for c in 0..x.ncols() {
        let (xc, oc) = (column(x, c), column_mut(out.rb_mut(), c));
        for i in 0..xc.len() {
            oc[i] += mv[i] * xc[i];
        }
    }
}

fn mat_tr_mul(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let mut out = Mat::<f64>::zeros(a.ncols(), b.ncols());
    matmul(out.as_mut(), Accum::Replace, a.transpose(), b, 1.0, Par::Seq);
    out
}

fn mat_mul(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let mut out = Mat::<f64>::zeros(a.nrows(), b.ncols());
    matmul(out.as_mut(), Accum::Replace, a, b, 1.0, Par::Seq);
    out
}

/// `out = a b`.
fn mat_mul_into(out: MatMut<'_, f64>, a: MatRef<'_, f64>, b: MatRef<'_, f64>) {
    matmul(out, Accum::Replace, a, b, 1.0, Par::Seq);
}

/// Rayleigh-Ritz: the `k` smallest eigenpairs of $(S^\top H S, S^\top M S)$; returns the
/// values and the coefficient matrix `C` (`s x k`), or `None` if the basis degenerated.
/// `ms_buf` holds $MS$.
///
/// With `ritz = Some(lambda)` the first `lambda.len()` columns of $S$ are the Ritz vectors of
/// the previous projection ($M$-orthonormal, $X^\top H X = \mathrm{diag}(\lambda)$), so that
/// block of both Gram matrices is taken as known and only the columns of the other
/// directions are multiplied: $n\,m\,(m - k)$ products each instead of $n\,m^2$ (as
/// Knyazev's and SciPy's LOBPCG do away from convergence).
fn rayleigh_ritz(
    s: MatRef<'_, f64>,
    hs: MatRef<'_, f64>,
    mass: &[f64],
    k: usize,
    ritz: Option<&[f64]>,
    ms_buf: &mut Mat<f64>,
) -> Option<(Vec<f64>, Mat<f64>)> {
    let (n, m) = (s.nrows(), s.ncols());
    let known = ritz.map_or(0, <[f64]>::len).min(m);
    let mut ms = block_mut(ms_buf, n, m - known);
    for j in known..m {
        let (sj, msj) = (column(s, j), column_mut(ms.rb_mut(), j - known));
        for i in 0..n {
            msj[i] = mass[i] * sj[i];
        }
    }
    // Columns `known..m` of G and A (every row); the first `known` columns are the
    // transposes of those rows, or the known block.
    let g_rest = mat_tr_mul(s, ms.as_ref());
    let a_rest = mat_tr_mul(s, hs.subcols(known, m - known));
    let entry = |rest: &Mat<f64>, diag: &dyn Fn(usize) -> f64, i: usize, j: usize| -> f64 {
        match (i < known, j < known) {
            (true, true) => {
                if i == j {
                    diag(i)
                } else {
                    0.0
                }
            }
            (_, false) => rest[(i, j - known)],
            (false, true) => rest[(j, i - known)],
        }
    };
    let lambda = ritz.unwrap_or(&[]);
    let g = Mat::from_fn(m, m, |i, j| entry(&g_rest, &|_| 1.0, i, j));
    let a = Mat::from_fn(m, m, |i, j| entry(&a_rest, &|i| lambda[i], i, j));
    // Scale to unit diagonal.
    let d: Vec<f64> = (0..m)
        .map(|j| if g[(j, j)] > 0.0 { 1.0 / g[(j, j)].sqrt() } else { 0.0 })
        .collect();
    let gs = Mat::from_fn(m, m, |i, j| 0.5 * (g[(i, j)] + g[(j, i)]) * d[i] * d[j]);
    // T with S T M-orthonormal.
    let t = orthonormalizer(gs.as_ref(), &d, k)?;
    let at = mat_mul(a.as_ref(), t.as_ref());
    let b0 = mat_tr_mul(t.as_ref(), at.as_ref());
    let r = t.ncols();
    let b = Mat::from_fn(r, r, |i, j| 0.5 * (b0[(i, j)] + b0[(j, i)]));
    let (bv, bu) = symmetric_eigen(b.as_ref()).ok()?;
    let values: Vec<f64> = (0..k).map(|i| bv[i]).collect();
    let c = mat_mul(t.as_ref(), bu.subcols(0, k));
    Some((values, c))
}

/// Smallest squared Cholesky pivot (of the unit-diagonal Gram matrix) accepted: below it the
/// basis is near-dependent and [`orthonormalizer`] drops directions by SVQB instead. A squared
/// pivot is the squared sine of the angle between a column and the span of the previous
/// ones. At 1e-10 a cold solve on a SHREC'16 cat (941 vertices, relative residual target
/// 1e-4) stalled at residuals ~1e-3 and then diverged (negative Ritz values of a positive
/// pencil): near convergence the directions $P$ lie almost in $\mathrm{span}\,X$ and the
/// Cholesky-QR orthonormalisation, accurate to ~$\epsilon\,\mathrm{cond}(G)$, lost the
/// basis. 1e-8 .. 1e-2 all solved it, at the same wall time on two pairs.
const MIN_PIVOT: f64 = 1e-6;

/// `T` (`m x r`, `r <= m`) with $T^\top D^{-1} G_s D^{-1} T = I$ for the unit-diagonal Gram
/// matrix `gs` $= D G D$, i.e. $S T$ is $M$-orthonormal: $T = D L^{-\top}$ from the Cholesky
/// factor $G_s = L L^\top$ when every squared pivot is at least [`MIN_PIVOT`] (the usual case, ~10x
/// cheaper than an eigendecomposition), else SVQB (Stathopoulos & Wu 2002: $T = D U_r
/// \Sigma_r^{-1/2}$, keeping the eigenvalues above $10^{-13}$ of the largest). `None` if fewer
/// than `k` directions remain.
fn orthonormalizer(gs: MatRef<'_, f64>, d: &[f64], k: usize) -> Option<Mat<f64>> {
    let m = gs.nrows();
    if let Some(l) = cholesky_lower(gs) {
        if (0..m).all(|j| l[(j, j)] * l[(j, j)] >= MIN_PIVOT) {
            let mut linv = Mat::<f64>::identity(m, m);
            faer::linalg::triangular_solve::solve_lower_triangular_in_place(l.as_ref(), linv.as_mut(), Par::Seq);
            return Some(Mat::from_fn(m, m, |i, c| d[i] * linv[(c, i)]));
        }
    }
    let (gv, gu) = symmetric_eigen(gs).ok()?;
    let gmax = (0..m).map(|i| gv[i]).fold(0.0, f64::max);
    let keep: Vec<usize> = (0..m).filter(|&i| gv[i] > 1e-13 * gmax).collect();
    if keep.len() < k {
        return None;
    }
    Some(Mat::from_fn(m, keep.len(), |i, c| d[i] * gu[(i, keep[c])] / gv[keep[c]].sqrt()))
}

/// Smallest residual target at which [`refine`] takes the Ritz block of its Gram matrices as
/// known (`rayleigh_ritz`): the $M$-orthonormality of the Ritz vectors holds to about
/// $\epsilon\,\mathrm{cond}(G) \le 10^{-16} / $ [`MIN_PIVOT`] $= 10^{-10}$, which perturbs the
/// Ritz values relatively by as much; solves to tighter residuals form every block
/// explicitly.
const KNOWN_RITZ_BLOCK_MIN_TARGET: f64 = 1e-6;

/// Refined eigenvalues, their eigenvectors and the iterations it took.
pub(crate) type Refined = (Vec<f64>, Mat<f64>, usize);

/// LOBPCG from `x0` (`n x b`) until the first `wanted` Ritz pairs have converged, i.e. their
/// relative residuals $\lVert H\phi - \lambda M\phi \rVert_{M^{-1}} / (|\lambda| + |\sigma|)$
/// are at most `target` (the others are guard vectors: they enrich the Rayleigh-Ritz space and speed up the last wanted pairs).
/// `factor` may hold an older potential: it is only a preconditioner. `Ok(None)` when it does
/// not converge in `max_iter` iterations (the caller then solves cold). The blocks live in
/// `ws`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn refine(
    factor: &ShiftedFactor,
    mass: &[f64],
    potential: &[f64],
    sigma: f64,
    x0: MatRef<'_, f64>,
    wanted: usize,
    target: f64,
    max_iter: usize,
    ws: &mut Workspace,
) -> Result<Option<Refined>> {
    let (n, k) = (x0.nrows(), x0.ncols());
    let nr = wanted.min(k);
    let mv: Vec<f64> = mass.iter().zip(potential).map(|(m, v)| m * v).collect();
    let inv_mass: Vec<f64> = mass.iter().map(|m| 1.0 / m).collect();
    let mut solve_mem = MemBuffer::new(factor.solve_scratch(nr));

    // S = X0 at the start: H X0 goes in the HS buffer.
    h_mul(factor, &mv, x0, block_mut(&mut ws.hs, n, k));
    let Some((mut lambda, c)) = rayleigh_ritz(x0, block(&ws.hs, k), mass, k, None, &mut ws.ms) else {
        return Ok(None);
    };
    mat_mul_into(block_mut(&mut ws.x, n, k), x0, c.as_ref());
    mat_mul_into(block_mut(&mut ws.hx, n, k), block(&ws.hs, k), c.as_ref());
    // Columns of P (and HP) from the previous iteration.
    let mut np: Option<usize> = None;

    for it in 0..max_iter {
        // Residuals and the active set.
        let mut r = block_mut(&mut ws.r, n, nr);
        let (x, hx) = (block(&ws.x, k), block(&ws.hx, k));
        let mut active = Vec::new();
        for j in 0..nr {
            let (xj, hxj) = (column(x, j), column(hx, j));
            let rj = column_mut(r.rb_mut(), j);
            for i in 0..n {
                rj[i] = hxj[i] - mass[i] * lambda[j] * xj[i];
            }
            let s2 = weighted_squares(rj, &inv_mass);
            if s2.sqrt() / (lambda[j].abs() + sigma.abs()) > target {
                active.push(j);
            }
        }
        if active.is_empty() {
            return Ok(Some((lambda, x.to_owned(), it)));
        }
        let na = active.len();
        let mut w = block_mut(&mut ws.w, n, na);
        for (c, &j) in active.iter().enumerate() {
            w.rb_mut().col_mut(c).copy_from(r.as_ref().col(j));
        }
        factor.solve_in_place(w.rb_mut(), MemStack::new(&mut solve_mem));
        let w = block(&ws.w, na);
        h_mul(factor, &mv, w, block_mut(&mut ws.hw, n, na));
        let hw = block(&ws.hw, na);
        // S = [X, W, P] and HS = [HX, HW, HP].
        let m = k + na + np.unwrap_or(0);
        let mut s = block_mut(&mut ws.s, n, m);
        let mut hs = block_mut(&mut ws.hs, n, m);
        s.rb_mut().subcols_mut(0, k).copy_from(x);
        s.rb_mut().subcols_mut(k, na).copy_from(w);
        hs.rb_mut().subcols_mut(0, k).copy_from(hx);
        hs.rb_mut().subcols_mut(k, na).copy_from(hw);
        if let Some(np) = np {
            s.rb_mut()
                .subcols_mut(k + na, np)
                .copy_from(block(&ws.p, np));
            hs.rb_mut()
                .subcols_mut(k + na, np)
                .copy_from(block(&ws.hp, np));
        }
        let (s, hs) = (block(&ws.s, m), block(&ws.hs, m));
        let ritz = (target >= KNOWN_RITZ_BLOCK_MIN_TARGET).then_some(lambda.as_slice());
        let Some((new_lambda, c)) = rayleigh_ritz(s, hs, mass, k, ritz, &mut ws.ms) else {
            return Ok(None);
        };
        // P = the non-X part of the update, for the active columns.
        let c_rest = Mat::from_fn(m - k, na, |i, a| c[(k + i, active[a])]);
        mat_mul_into(
            block_mut(&mut ws.p, n, na),
            s.subcols(k, m - k),
            c_rest.as_ref(),
        );
        mat_mul_into(
            block_mut(&mut ws.hp, n, na),
            hs.subcols(k, m - k),
            c_rest.as_ref(),
        );
        mat_mul_into(block_mut(&mut ws.x, n, k), s, c.as_ref());
        mat_mul_into(block_mut(&mut ws.hx, n, k), hs, c.as_ref());
        lambda = new_lambda;
        np = Some(na);
    }
    Ok(None)
}

/// A start block for a cold solve: the `want` lowest Ritz vectors of the pencil in a block
/// Krylov space of the shift-inverted operator $S = D K^{-1} D$ ($D = M^{1/2}$),
/// $\mathrm{span}\{Y_0, S Y_0, \dots, S^{\,s-1} Y_0\}$ with $Y_0 = D X_0$ (`x0`, `n x b`) and
/// $s$ = `steps`: block Lanczos with full reorthogonalisation. Each $S Y_j$ is orthogonalised
/// against the basis twice (classical Gram-Schmidt) and within itself (directions below
/// $10^{-10}$ of its largest dropped); the coefficients are the projection
/// $T = Q^\top S Q$, whose largest eigenvalues $\theta$ are the pencil's lowest
/// ($\lambda = \sigma + 1/\theta$, the Ritz vectors $D^{-1} Q u$). One eigendecomposition at
/// the end instead of a Rayleigh-Ritz projection per block iteration (LOBPCG from a random
/// block projects $k + 2b$ columns at every step). `None` when fewer than `want` directions
/// remain (the caller starts from `x0`).
pub(crate) fn krylov_start(factor: &ShiftedFactor, mass: &[f64], x0: MatRef<'_, f64>, steps: usize, want: usize) -> Option<Mat<f64>> {
    let (n, b) = (x0.nrows(), x0.ncols());
    let sqrt_m: Vec<f64> = mass.iter().map(|m| m.sqrt()).collect();
    let cap = b * (steps + 1);
    let mut basis = Mat::<f64>::zeros(n, cap);
    let mut t = Mat::<f64>::zeros(cap, cap);
    let mut solve_mem = MemBuffer::new(factor.solve_scratch(b));
    // Orthonormalise a block within itself: Z U diag(s)^{-1/2} of its Gram matrix's
    // eigenpairs, keeping the well-determined directions.
    let orthonormal = |z: MatRef<'_, f64>| -> Option<Mat<f64>> {
        let g = mat_tr_mul(z, z);
        let (gv, gu) = symmetric_eigen(g.as_ref()).ok()?;
        let gmax = gv.iter().copied().fold(0.0, f64::max);
        let keep: Vec<usize> = (0..gv.len()).filter(|&i| gmax > 0.0 && gv[i] > 1e-10 * gmax).collect();
        let scale = Mat::from_fn(z.ncols(), keep.len(), |i, c| gu[(i, keep[c])] / gv[keep[c]].sqrt());
        Some(mat_mul(z, scale.as_ref()))
    };
    let y0 = orthonormal(Mat::from_fn(n, b, |i, j| sqrt_m[i] * x0[(i, j)]).as_ref())?;
    basis.as_mut().subcols_mut(0, y0.ncols()).copy_from(y0.as_ref());
    // Columns [start, filled) are the newest block; [0, applied) have had S applied.
    let (mut start, mut filled, mut applied) = (0, y0.ncols(), 0);
    for _ in 0..steps {
        if filled == start || filled + b > cap {
            break;
        }
        // Z = S Y = D K^{-1} D Y for the newest block Y.
        let mut z = Mat::from_fn(n, filled - start, |i, j| sqrt_m[i] * basis[(i, start + j)]);
        factor.solve_in_place(z.as_mut(), MemStack::new(&mut solve_mem));
        for j in 0..z.ncols() {
            column_mut(z.as_mut(), j).iter_mut().zip(&sqrt_m).for_each(|(x, d)| *x *= d);
        }
        for _ in 0..2 {
            let q = basis.as_ref().subcols(0, filled);
            let coef = mat_tr_mul(q, z.as_ref());
            matmul(z.as_mut(), Accum::Add, q, coef.as_ref(), -1.0, Par::Seq);
            for i in 0..filled {
                for j in 0..coef.ncols() {
                    t[(i, start + j)] += coef[(i, j)];
                }
            }
        }
        // The coefficients of both passes are T's column block of Y, Q^T S Y, for the rows of
        // the basis so far: T's upper triangle.
        let next = orthonormal(z.as_ref())?;
        basis.as_mut().subcols_mut(filled, next.ncols()).copy_from(next.as_ref());
        applied = filled;
        start = filled;
        filled += next.ncols();
    }
    if applied < want {
        return None;
    }
    // T on the applied columns, from the upper triangle the recurrences filled (the block
    // not applied only bounds the residuals; it is left out).
    let projected = Mat::from_fn(applied, applied, |i, j| if i <= j { t[(i, j)] } else { t[(j, i)] });
    let (_, u) = symmetric_eigen(projected.as_ref()).ok()?;
    // The largest theta come last: the lowest eigenvalues' vectors, lowest first.
    let top = Mat::from_fn(applied, want, |i, c| u[(i, applied - 1 - c)]);
    let y = mat_mul(basis.as_ref().subcols(0, applied), top.as_ref());
    Some(Mat::from_fn(n, want, |i, j| y[(i, j)] / sqrt_m[i]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `T^T (D^-1 Gs D^-1) T`, which must be the identity.
    fn gram_in_t(gs: MatRef<'_, f64>, d: &[f64], t: MatRef<'_, f64>) -> Mat<f64> {
        let m = gs.nrows();
        let g = Mat::from_fn(m, m, |i, j| gs[(i, j)] / (d[i] * d[j]));
        mat_tr_mul(t, mat_mul(g.as_ref(), t).as_ref())
    }

    fn max_off_identity(a: MatRef<'_, f64>) -> f64 {
        let mut worst = 0.0f64;
        for i in 0..a.nrows() {
            for j in 0..a.ncols() {
                worst = worst.max((a[(i, j)] - f64::from(u8::from(i == j))).abs());
            }
        }
        worst
    }

    /// `orthonormalizer(gs, d, k)`'s column count and $\max|T^\top G T - I|$.
    fn orthonormalized(gs: MatRef<'_, f64>, d: &[f64], k: usize) -> (usize, f64) {
        let t = orthonormalizer(gs, d, k).expect("enough directions");
        (t.ncols(), max_off_identity(gram_in_t(gs, d, t.as_ref()).as_ref()))
    }

    /// The unit-diagonal Gram matrix of `cols` pseudo-random vectors in R^20, the last of
    /// which is the first plus `eps` times a pseudo-random direction.
    fn gram(cols: usize, eps: f64) -> Mat<f64> {
        let v = Mat::from_fn(20, cols, |i, j| {
            let r = super::super::eigensolver::start_value(i as u64, j as u64);
            if j == cols - 1 {
                super::super::eigensolver::start_value(i as u64, 0) + eps * r
            } else {
                r
            }
        });
        let g = mat_tr_mul(v.as_ref(), v.as_ref());
        Mat::from_fn(cols, cols, |i, j| g[(i, j)] / (g[(i, i)] * g[(j, j)]).sqrt())
    }

    /// The path-graph Laplacian on `n` vertices (a `W` for [`refine`]).
    fn path_laplacian(n: usize) -> crate::operators::SparseMatrix {
        use faer::sparse::Triplet;
        let mut trip = Vec::new();
        for i in 0..n - 1 {
            trip.push(Triplet::new(i, i + 1, -1.0));
            trip.push(Triplet::new(i + 1, i, -1.0));
            trip.push(Triplet::new(i, i, 1.0));
            trip.push(Triplet::new(i + 1, i + 1, 1.0));
        }
        crate::operators::SparseMatrix::try_new_from_triplets(n, n, &trip).expect("valid triplets")
    }

    /// `refine` on the path of `n` vertices with a `b`-column start, in `ws`.
    fn refine_path(n: usize, b: usize, ws: &mut Workspace) -> Refined {
        let mut factor = ShiftedFactor::new(&path_laplacian(n)).expect("symmetric");
        let mass: Vec<f64> = (0..n).map(|i| 1.0 + 0.01 * i as f64).collect();
        let potential: Vec<f64> = (0..n).map(|i| if i < n / 3 { 0.0 } else { 5.0 }).collect();
        let sigma = -1.0 / mass.iter().sum::<f64>();
        let d: Vec<f64> = mass
            .iter()
            .zip(&potential)
            .map(|(m, v)| m * (v - sigma))
            .collect();
        factor.factorize(&d).expect("positive definite");
        let x0 = Mat::from_fn(n, b, |i, j| {
            super::super::eigensolver::start_value(i as u64, j as u64)
        });
        let out = refine(
            &factor,
            &mass,
            &potential,
            sigma,
            x0.as_ref(),
            b - 2,
            1e-10,
            100,
            ws,
        );
        out.expect("solve").expect("converged")
    }

    /// The Ritz vectors of a block Krylov space of the shift-inverted operator start LOBPCG
    /// next to the answer: the same eigenvalues as from a random block, in at most two block
    /// iterations instead of many.
    #[test]
    fn a_krylov_start_converges_to_the_eigenpairs_of_a_random_start_in_fewer_iterations() {
        let n = 400;
        let mut factor = ShiftedFactor::new(&path_laplacian(n)).expect("symmetric");
        let mass: Vec<f64> = (0..n).map(|i| 1.0 + 0.01 * i as f64).collect();
        let potential: Vec<f64> = (0..n).map(|i| if i < n / 3 { 0.0 } else { 5.0 }).collect();
        let sigma = -1.0 / mass.iter().sum::<f64>();
        let d: Vec<f64> = mass.iter().zip(&potential).map(|(m, v)| m * (v - sigma)).collect();
        factor.factorize(&d).expect("positive definite");
        let random = |cols: usize| Mat::from_fn(n, cols, |i, j| super::super::eigensolver::start_value(i as u64, j as u64));
        let (b, wanted) = (12, 10);
        let start = krylov_start(&factor, &mass, random(4).as_ref(), 15, b).expect("a 64-direction space");
        assert_eq!((start.nrows(), start.ncols()), (n, b));
        let solve = |x0: MatRef<'_, f64>| refine(&factor, &mass, &potential, sigma, x0, wanted, 1e-9, 200, &mut Workspace::new()).expect("solve").expect("converged");
        let (from_krylov, from_random) = (solve(start.as_ref()), solve(random(b).as_ref()));
        for (a, r) in from_krylov.0.iter().zip(&from_random.0).take(wanted) {
            assert!((a - r).abs() <= 1e-10 * r.abs(), "{a} vs {r}");
        }
        assert!(from_krylov.2 <= 2 && from_random.2 > 2 * from_krylov.2 + 2, "iterations: Krylov start {}, random {}", from_krylov.2, from_random.2);
        // Too small a space for the wanted directions: no start.
        assert!(krylov_start(&factor, &mass, random(2).as_ref(), 2, b).is_none());
    }

    #[test]
    fn weighted_squares_is_the_weighted_sum_of_squares_at_any_length() {
        for n in 0..11 {
            let r: Vec<f64> = (0..n).map(|i| (i as f64 * 1.7).sin()).collect();
            let w: Vec<f64> = (0..n).map(|i| 0.5 + i as f64).collect();
            let want: f64 = r.iter().zip(&w).map(|(a, b)| a * a * b).sum();
            assert!((weighted_squares(&r, &w) - want).abs() <= 1e-14 * want.max(1.0), "n = {n}");
        }
    }

    #[test]
    fn a_reused_workspace_gives_bitwise_the_results_of_a_fresh_one() {
        let fresh = refine_path(60, 8, &mut Workspace::new());
        // Buffers left by other solves: more rows, then as many rows and more columns.
        let mut ws = Workspace::new();
        refine_path(80, 12, &mut ws);
        refine_path(60, 10, &mut ws);
        let reused = refine_path(60, 8, &mut ws);
        let bits = |r: &Refined| {
            let vectors = (0..r.1.ncols()).flat_map(|j| (0..r.1.nrows()).map(move |i| (i, j)));
            let mut b: Vec<u64> = r.0.iter().map(|v| v.to_bits()).collect();
            b.extend(vectors.map(|ij| r.1[ij].to_bits()));
            (b, r.1.ncols(), r.2)
        };
        assert_eq!(bits(&fresh), bits(&reused));
    }

    #[test]
    fn cholesky_path_orthonormalizes_a_well_conditioned_basis() {
        let gs = gram(8, 1.0);
        let d: Vec<f64> = (0..8).map(|i| 1.0 + i as f64).collect();
        let (cols, e) = orthonormalized(gs.as_ref(), &d, 4);
        assert_eq!(cols, 8, "no direction may be dropped");
        assert!(e < 1e-12, "T^T G T - I = {e:e}");
    }

    #[test]
    fn near_dependent_basis_falls_back_to_svqb_and_drops_the_direction() {
        // The last vector equals the first to 1e-9: the squared pivot (~1e-18) is below
        // MIN_PIVOT, so SVQB runs and keeps 7 directions.
        let gs = gram(8, 1e-9);
        let d = vec![1.0; 8];
        let (cols, e) = orthonormalized(gs.as_ref(), &d, 4);
        assert_eq!(cols, 7);
        assert!(e < 1e-6, "T^T G T - I = {e:e}");
        assert!(orthonormalizer(gs.as_ref(), &d, 8).is_none(), "8 directions cannot be had");
    }

    #[test]
    fn moderately_dependent_basis_is_orthonormalized_accurately() {
        // Squared pivot ~1e-8 (below MIN_PIVOT): SVQB keeps all 8 directions, and S T is
        // orthonormal to ~eps cond(G) ~ 2e-8 (measured 2.9e-8).
        let gs = gram(8, 1e-4);
        let d = vec![1.0; 8];
        let (cols, e) = orthonormalized(gs.as_ref(), &d, 4);
        assert_eq!(cols, 8);
        assert!(e < 1e-6, "T^T G T - I = {e:e}");
    }
}
