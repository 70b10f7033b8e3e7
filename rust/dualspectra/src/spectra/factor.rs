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
        let mut xbuf = vec![0.0; self.shared.n];
        let mut obuf = vec![0.0; self.shared.n];
        for c in 0..x.ncols() {
            // Contiguous copies: the loop below indexes slices (bounds checks hoisted) instead
            // of strided faer columns.
            for (xi, v) in xbuf.iter_mut().zip(x.col(c).iter()) {
                *xi = *v;
            }
            obuf.fill(0.0);
            for j in 0..self.shared.n {
                let xj = xbuf[j];
                let (s, e) = (col_ptr[j], col_ptr[j + 1]);
                // Diagonal first.
                let mut acc = self.shared.w_values[s] * xj;
                for (&i, &v) in row_idx[s + 1..e].iter().zip(&self.shared.w_values[s + 1..e]) {
                    obuf[i] += v * xj;
                    acc += v * xbuf[i];
                }
                obuf[j] += acc;
            }
            for (o, v) in out.rb_mut().col_mut(c).iter_mut().zip(&obuf) {
                *o = *v;
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
