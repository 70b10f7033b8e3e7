//! The shifted operator $K = W + \mathrm{diag}(d)$ and its sparse Cholesky factor.
//!
//! The pencil solvers never form $K^{-1}$: they apply it through $K = L L^\top$ (faer's
//! supernodal Cholesky with an AMD fill-reducing ordering). The sparsity pattern of $K$ is the
//! lower triangle of $W$ plus the full diagonal, fixed for the lifetime of the factor, so the
//! symbolic analysis (ordering, elimination tree, supernodes) runs once and every new diagonal
//! $d$ (a new potential, docs/algorithm.md "Hamiltonian") costs one numeric factorisation only.
//!
//! Everything runs sequentially (`Par::Seq`): results are bitwise reproducible and the
//! optimiser above may parallelise over shapes instead.

use crate::error::{Error, Result};
use crate::operators::SparseMatrix;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::reborrow::ReborrowMut;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, supernodal::SupernodalLdltRef, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};
use std::sync::Arc;

/// The pattern of `tril(W) + I`, the values of `W` on it and its symbolic Cholesky analysis
/// (ordering, elimination tree, supernodes): everything that depends on `W` alone. Immutable,
/// shared (through an `Arc`) by every factor of `W + diag(d)`.
#[derive(Debug)]
pub(crate) struct ShiftedPattern {
    n: usize,
    /// Pattern of `tril(W) + I` (sorted rows, diagonal first in every column).
    pattern: SymbolicSparseColMat<usize>,
    /// Values of `tril(W)` on `pattern` (0 on a diagonal absent from `W`).
    w_values: Vec<f64>,
    /// `diag_pos[j]`: position of `(j, j)` in the value arrays.
    diag_pos: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
}

/// The numeric Cholesky factor of $K = W + \mathrm{diag}(d)$ on a shared [`ShiftedPattern`].
#[derive(Debug)]
pub(crate) struct ShiftedFactor {
    shared: Arc<ShiftedPattern>,
    /// Scratch values of `K` on the pattern.
    k_values: Vec<f64>,
    l_values: Vec<f64>,
}

impl ShiftedFactor {
    /// A factor (not yet computed) on an analysed pattern.
    pub(crate) fn with_pattern(shared: Arc<ShiftedPattern>) -> Self {
        ShiftedFactor { k_values: shared.w_values.clone(), l_values: vec![0.0; shared.symbolic.len_val()], shared }
    }

}

impl ShiftedPattern {
    /// Number of rows and columns of `W`.
    pub(crate) fn n(&self) -> usize {
        self.n
    }

    /// Check `W` (square, finite, symmetric) and run the symbolic analysis.
    pub(crate) fn new(w: &SparseMatrix) -> Result<Self> {
        let n = w.nrows();
        if w.ncols() != n {
            return Err(Error::InvalidArgument(format!(
                "W is {} x {}, not square",
                n,
                w.ncols()
            )));
        }
        if n == 0 {
            return Err(Error::InvalidArgument("W is empty".into()));
        }
        // Columns of W as sorted (row, value) lists, for the symmetry check and the lower part.
        let mut cols: Vec<Vec<(usize, f64)>> = Vec::with_capacity(n);
        for j in 0..n {
            let rows = w.row_idx_of_col_raw(j);
            let vals = w.val_of_col(j);
            let mut c: Vec<(usize, f64)> = rows.iter().copied().zip(vals.iter().copied()).collect();
            c.sort_unstable_by_key(|e| e.0);
            // Merge duplicates (faer matrices have none, but be defensive).
            c.dedup_by(|b, a| {
                if a.0 == b.0 {
                    a.1 += b.1;
                    true
                } else {
                    false
                }
            });
            if let Some(&(i, _)) = c.iter().find(|e| !e.1.is_finite()) {
                return Err(Error::InvalidArgument(format!("W[{i}, {j}] is not finite")));
            }
            cols.push(c);
        }
        let mut max_abs = 0.0f64;
        for c in &cols {
            for &(_, v) in c {
                max_abs = max_abs.max(v.abs());
            }
        }
        let sym_tol = 1e3 * f64::EPSILON * max_abs;
        for (j, c) in cols.iter().enumerate() {
            for &(i, v) in c {
                if i > j {
                    let t = match cols[i].binary_search_by_key(&j, |e| e.0) {
                        Ok(p) => cols[i][p].1,
                        Err(_) => 0.0,
                    };
                    if (t - v).abs() > sym_tol {
                        return Err(Error::InvalidArgument(format!(
                            "W is not symmetric: W[{i}, {j}] = {v:e}, W[{j}, {i}] = {t:e}"
                        )));
                    }
                }
            }
        }
        // Lower pattern with the diagonal first.
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        let mut w_values = Vec::new();
        let mut diag_pos = Vec::with_capacity(n);
        col_ptr.push(0usize);
        for (j, c) in cols.iter().enumerate() {
            diag_pos.push(row_idx.len());
            row_idx.push(j);
            let d = c.iter().find(|e| e.0 == j).map_or(0.0, |e| e.1);
            w_values.push(d);
            for &(i, v) in c {
                if i > j {
                    row_idx.push(i);
                    w_values.push(v);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let symbolic =
            factorize_symbolic_cholesky(pattern.as_ref(), Side::Lower, Default::default(), supernodal_params())
                .map_err(|e| Error::Numerical(format!("symbolic Cholesky analysis failed: {e:?}")))?;
        Ok(ShiftedPattern { n, pattern, w_values, diag_pos, symbolic })
    }
}

/// The symbolic analysis asks for the supernodal factor on every mesh. faer's automatic
/// choice (by the ratio of flops to nonzeros) takes the simplicial one on the 2,000-4,000-vertex
/// optimisation meshes, whose triangular solves with a block of right-hand sides (the LOBPCG
/// preconditioner, a fifth of a localization's time) then go entry by entry; the supernodal
/// factor solves them with dense kernels (docs/benchmarks/options.md, "Where the time goes").
fn supernodal_params() -> faer::sparse::linalg::cholesky::CholeskySymbolicParams<'static> {
    faer::sparse::linalg::cholesky::CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: faer::sparse::linalg::SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    }
}

impl ShiftedFactor {
    /// Check `W` (square, finite, symmetric), analyse it and make a factor on it.
    #[allow(dead_code)]
    pub(crate) fn new(w: &SparseMatrix) -> Result<Self> {
        Ok(Self::with_pattern(Arc::new(ShiftedPattern::new(w)?)))
    }

    pub(crate) fn n(&self) -> usize {
        self.shared.n
    }

    /// Number of stored entries of the factor `L` (a measure of the solve cost).
    #[allow(dead_code)]
    pub(crate) fn factor_nnz(&self) -> usize {
        self.l_values.len()
    }

    /// Numeric factorisation of $K = W + \mathrm{diag}(d)$.
    pub(crate) fn factorize(&mut self, d: &[f64]) -> Result<()> {
        debug_assert_eq!(d.len(), self.shared.n);
        self.k_values.copy_from_slice(&self.shared.w_values);
        for (j, &dj) in d.iter().enumerate() {
            self.k_values[self.shared.diag_pos[j]] += dj;
        }
        let k = SparseColMatRef::new(self.shared.pattern.as_ref(), &self.k_values);
        let req = self
            .shared
            .symbolic
            .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default());
        let mut mem = MemBuffer::try_new(req).map_err(|_| Error::Numerical("out of memory".into()))?;
        self.shared.symbolic
            .factorize_numeric_llt::<f64>(
                &mut self.l_values,
                k,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| Error::Numerical(format!("Cholesky factorisation of W + diag(d) failed: {e:?}")))?;
        Ok(())
    }

    /// Workspace for [`Self::solve_in_place`] with `ncols` right-hand sides.
    pub(crate) fn solve_scratch(&self, ncols: usize) -> StackReq {
        self.shared.symbolic.solve_in_place_scratch::<f64>(ncols, Par::Seq)
    }

    /// `rhs <- K^{-1} rhs`. Requires a successful [`Self::factorize`].
    pub(crate) fn solve_in_place(&self, rhs: MatMut<'_, f64>, stack: &mut MemStack) {
        LltRef::new(&self.shared.symbolic, &self.l_values).solve_in_place_with_conj(Conj::No, rhs, Par::Seq, stack);
    }

    /// `out = W x` for a dense block `x` (uses the stored lower triangle, symmetric product).
    pub(crate) fn w_mul(&self, mut out: MatMut<'_, f64>, x: faer::MatRef<'_, f64>) {
        let col_ptr = self.shared.pattern.col_ptr();
        let row_idx = self.shared.pattern.row_idx();
        let values = &self.shared.w_values;
        let (n, b) = (self.shared.n, x.ncols());
        // The block row-major (vertex by vertex, its `b` columns side by side), so that each
        // stored entry of W updates `b` contiguous values; every output entry sums the same
        // terms in the same order as a column-by-column product (the same bits).
        let mut rows = vec![0.0; n * b];
        for c in 0..b {
            for (i, v) in x.col(c).iter().enumerate() {
                rows[i * b + c] = *v;
            }
        }
        let mut products = vec![0.0; n * b];
        let mut acc = vec![0.0; b];
        for j in 0..n {
            let (s, e) = (col_ptr[j], col_ptr[j + 1]);
            let xj = &rows[j * b..(j + 1) * b];
            // Diagonal first.
            for (a, v) in acc.iter_mut().zip(xj) {
                *a = values[s] * v;
            }
            for (&i, &w) in row_idx[s + 1..e].iter().zip(&values[s + 1..e]) {
                let xi = &rows[i * b..(i + 1) * b];
                let oi = &mut products[i * b..(i + 1) * b];
                for (o, x) in oi.iter_mut().zip(xj) {
                    *o += w * x;
                }
                for (a, x) in acc.iter_mut().zip(xi) {
                    *a += w * x;
                }
            }
            for (o, a) in products[j * b..(j + 1) * b].iter_mut().zip(&acc) {
                *o += a;
            }
        }
        for c in 0..b {
            for (i, o) in out.rb_mut().col_mut(c).iter_mut().enumerate() {
                *o = products[i * b + c];
            }
        }
    }

    /// Sylvester inertia: the number of negative eigenvalues of $W + \mathrm{diag}(d)$, read off
    /// the pivots of its $LDL^\top$ factorisation (same symbolic analysis, no pivoting).
    /// `None` if the factorisation broke down (a zero pivot).
    pub(crate) fn count_negative(&self, d: &[f64]) -> Option<usize> {
        let mut a = self.shared.w_values.clone();
        for (j, &dj) in d.iter().enumerate() {
            a[self.shared.diag_pos[j]] += dj;
        }
        let mat = SparseColMatRef::new(self.shared.pattern.as_ref(), &a);
        let mut values = vec![0.0; self.shared.symbolic.len_val()];
        let req = self
            .shared
            .symbolic
            .factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Default::default());
        let mut mem = MemBuffer::try_new(req).ok()?;
        self.shared.symbolic
            .factorize_numeric_ldlt::<f64>(
                &mut values,
                mat,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .ok()?;
        let mut negative = 0usize;
        let mut count = |p: f64| -> Option<()> {
            if !p.is_finite() || p == 0.0 {
                return None;
            }
            if p < 0.0 {
                negative += 1;
            }
            Some(())
        };
        match self.shared.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(sym) => {
                let col_ptr = sym.col_ptr();
                for j in 0..self.shared.n {
                    count(values[col_ptr[j]])?;
                }
            }
            SymbolicCholeskyRaw::Supernodal(sym) => {
                let l = SupernodalLdltRef::new(sym, &values);
                for s in 0..sym.n_supernodes() {
                    let block = l.supernode(s).val();
                    for i in 0..block.ncols() {
                        count(block[(i, i)])?;
                    }
                }
            }
        }
        Some(negative)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;

    /// A symmetric `W` with irregular rows: a ring of `n` vertices, each also joined to the
    /// vertex `n / 3` ahead, with weights that differ edge by edge.
    fn irregular(n: usize) -> crate::operators::SparseMatrix {
        use faer::sparse::Triplet;
        let mut trip = Vec::new();
        for i in 0..n {
            for (j, w) in [((i + 1) % n, 1.0 + (i % 7) as f64 * 0.3), ((i + n / 3) % n, 0.25 + (i % 3) as f64 * 0.1)] {
                trip.extend([Triplet::new(i, j, -w), Triplet::new(j, i, -w), Triplet::new(i, i, w), Triplet::new(j, j, w)]);
            }
        }
        crate::operators::SparseMatrix::try_new_from_triplets(n, n, &trip).expect("valid triplets")
    }

    #[test]
    fn w_mul_is_the_symmetric_product_and_a_block_gives_each_column_s_bits() {
        let n = 41;
        let w = irregular(n);
        let factor = ShiftedFactor::new(&w).expect("symmetric");
        let x = Mat::<f64>::from_fn(n, 5, |i, c| ((3 * i + 11 * c) as f64).sin());
        let mut block = Mat::<f64>::zeros(n, 5);
        factor.w_mul(block.as_mut(), x.as_ref());
        let dense = w.to_dense();
        for c in 0..5 {
            let mut alone = Mat::<f64>::zeros(n, 1);
            factor.w_mul(alone.as_mut(), x.as_ref().subcols(c, 1));
            for i in 0..n {
                assert_eq!(block[(i, c)].to_bits(), alone[(i, 0)].to_bits(), "({i}, {c})");
                let want: f64 = (0..n).map(|j| dense[(i, j)] * x[(j, c)]).sum();
                assert!((block[(i, c)] - want).abs() < 1e-12, "({i}, {c}): {} against {want}", block[(i, c)]);
            }
        }
    }
}
