//! The $k$ smallest eigenpairs of $H\phi = \lambda M\phi$, $H = W + \mathrm{diag}(m \odot v)$,
//! $M = \mathrm{diag}(m)$ (ALGORITHM.md, "Spectra").
//!
//! **Shift-invert.** With a shift $\sigma < 0$, $K = H - \sigma M$ is symmetric positive
//! definite ($W \succeq 0$, $v \ge 0$, $m > 0$), and with $D = M^{1/2}$
//! $$S = D K^{-1} D, \qquad S y = \theta y \iff H\phi = \lambda M\phi,\quad
//! \lambda = \sigma + 1/\theta,\quad \phi = D^{-1} y .$$
//! The smallest $\lambda$ are the largest $\theta$, well separated, so a Krylov method on $S$
//! converges in a few dozen applications of $K^{-1}$ (one sparse Cholesky solve each). The
//! orthonormal $y$ give $M$-orthonormal $\phi$: $\Phi^\top M \Phi = Y^\top Y = I$.
//!
//! **Cold solve**: thick-restart Lanczos (Krylov-Schur, faer's `partial_self_adjoint_eigen`)
//! from a fixed pseudo-random start vector. **Warm solve** ([`HamiltonianSolver`]): the
//! previous eigenvectors start a block Rayleigh-Ritz iteration (see `block`).
//!
//! **Shift.** $\sigma = -1/\sum_j m_j$ by default: the eigenvalue unit of a surface of that
//! area (a unit sphere has $\lambda_1 \sum m = 8\pi$, a unit-area disk with Dirichlet
//! boundary $\approx 18$). A tiny $|\sigma|$ makes the zero eigenvalue of a closed mesh
//! swamp the others ($\theta_0 = 1/|\sigma|$) and costs accuracy; a huge one compresses the
//! wanted $\theta$ together and costs iterations.

use super::block;
use super::dense::dense_smallest;
use super::factor::ShiftedFactor;
use super::spectrum::{EigenInfo, EigenParams, Spectrum};
use crate::error::{Error, Result};
use crate::operators::SparseMatrix;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::matrix_free::eigen::{
    partial_self_adjoint_eigen, partial_self_adjoint_eigen_scratch, PartialEigenParams,
};
use faer::matrix_free::LinOp;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Col, Mat, MatMut, MatRef, Par};

/// Below this size (or `3 k`), the dense fallback is used.
const DENSE_MAX: usize = 200;

/// The $k$ smallest eigenpairs of $W\phi = \lambda\,\mathrm{diag}(m)\,\phi$.
///
/// `w`: `n x n` symmetric positive semi-definite (already Dirichlet-restricted by the caller),
/// `mass`: the `n` positive diagonal entries of $M$. Errors: `k == 0` or `k >= n`, wrong
/// lengths, non-finite entries, non-positive mass, asymmetric `w`, failed factorisation.
/// One-shot form of [`HamiltonianSolver`] with $v = 0$ (always a cold solve).
pub fn generalized_eigen(w: &SparseMatrix, mass: &[f64], params: &EigenParams) -> Result<Spectrum> {
    let mut solver = HamiltonianSolver::new(w, mass, params.clone())?;
    let zero = vec![0.0; solver.n()];
    solver.solve_cold(&zero)?;
    Ok(solver
        .take_spectrum()
        .expect("solve_cold stored a spectrum"))
}

/// Solver of $(W + \mathrm{diag}(m \odot v))\phi = \lambda\,\mathrm{diag}(m)\,\phi$ for a
/// sequence of potentials $v \ge 0$ on one pencil $(W, m)$.
///
/// Built once per $(W, m)$: checks the input and runs the symbolic Cholesky analysis of the
/// pattern of $W$ plus the diagonal. Each [`solve`](Self::solve) factorises
/// $K = W + \mathrm{diag}(m \odot (v - \sigma))$ numerically and, when a previous spectrum is
/// there and `params.warm_start`, starts from its eigenvectors (falling back to a cold solve
/// if the warm iteration does not converge). Deterministic: the same sequence of calls gives
/// bitwise the same results.
#[derive(Debug)]
pub struct HamiltonianSolver {
    params: EigenParams,
    mass: Vec<f64>,
    sqrt_m: Vec<f64>,
    inv_sqrt_m: Vec<f64>,
    sigma: f64,
    factor: ShiftedFactor,
    potential: Vec<f64>,
    spectrum: Option<Spectrum>,
    /// Eigenvalues and `M`-orthonormal vectors of the last solve, `k` wanted plus guards.
    block: Option<(Vec<f64>, Mat<f64>)>,
    /// The numeric factor is of the current potential (else of an older one).
    factor_current: bool,
    /// Iterations of the last warm solve (a stale preconditioner is refreshed when high).
    last_warm_iterations: usize,
    /// Warm solves that missed eigenvalues (caught by the inertia check, solved cold).
    missed_solves: usize,
}

impl HamiltonianSolver {
    /// Check `(w, mass, params)` and analyse the sparsity of `w`. See [`generalized_eigen`]
    /// for the conditions.
    pub fn new(w: &SparseMatrix, mass: &[f64], params: EigenParams) -> Result<Self> {
        let n = w.nrows();
        if mass.len() != n {
            return Err(Error::InvalidArgument(format!(
                "mass has {} entries, W is {n} x {n}",
                mass.len()
            )));
        }
        if params.k == 0 || params.k >= n {
            return Err(Error::InvalidArgument(format!(
                "k = {} must be in 1..{n} (n = {n})",
                params.k
            )));
        }
        if !(params.tol.is_finite() && params.tol > 0.0) {
            return Err(Error::InvalidArgument(format!(
                "tol = {} must be positive",
                params.tol
            )));
        }
        if let Some((i, &mi)) = mass
            .iter()
            .enumerate()
            .find(|(_, &m)| !(m.is_finite() && m > 0.0))
        {
            return Err(Error::InvalidArgument(format!(
                "mass[{i}] = {mi} is not a positive finite number"
            )));
        }
        let total: f64 = mass.iter().sum();
        let sigma = match params.shift {
            Some(s) if s.is_finite() && s < 0.0 => s,
            Some(s) => {
                return Err(Error::InvalidArgument(format!(
                    "shift = {s} must be negative and finite"
                )))
            }
            None => -1.0 / total,
        };
        if !sigma.is_finite() || sigma >= 0.0 {
            return Err(Error::InvalidArgument(
                "the total mass is not finite and positive".into(),
            ));
        }
        let factor = ShiftedFactor::new(w)?;
        Ok(HamiltonianSolver {
            sqrt_m: mass.iter().map(|m| m.sqrt()).collect(),
            inv_sqrt_m: mass.iter().map(|m| 1.0 / m.sqrt()).collect(),
            mass: mass.to_vec(),
            sigma,
            factor,
            potential: vec![0.0; n],
            spectrum: None,
            block: None,
            factor_current: false,
            last_warm_iterations: 0,
            missed_solves: 0,
            params,
        })
    }

    /// Number of unknowns `n`.
    pub fn n(&self) -> usize {
        self.factor.n()
    }

    /// The shift $\sigma$ in use.
    pub fn shift(&self) -> f64 {
        self.sigma
    }

    /// The parameters.
    pub fn params(&self) -> &EigenParams {
        &self.params
    }

    /// The mass diagonal $m$.
    pub fn mass(&self) -> &[f64] {
        &self.mass
    }

    /// The last computed spectrum, if any.
    pub fn spectrum(&self) -> Option<&Spectrum> {
        self.spectrum.as_ref()
    }

    /// Move the last spectrum out (the next solve is then cold).
    pub fn take_spectrum(&mut self) -> Option<Spectrum> {
        self.block = None;
        self.spectrum.take()
    }

    /// Warm solves so far whose block had converged to eigenpairs that are not the smallest
    /// (found by the inertia check and redone cold).
    pub fn missed_solves(&self) -> usize {
        self.missed_solves
    }

    /// Forget the previous spectrum: the next solve is cold.
    pub fn reset(&mut self) {
        self.spectrum = None;
        self.block = None;
    }

    /// Eigenpairs for the potential `potential` (length `n`, finite, `>= 0`), warm-started
    /// from the previous solve when there is one and `params.warm_start`.
    pub fn solve(&mut self, potential: &[f64]) -> Result<&Spectrum> {
        self.set_potential(potential)?;
        if self.params.warm_start && self.block.is_some() {
            // The old factor preconditions well while v moves little; refresh it when the
            // last warm solve needed many iterations.
            if !self.factor_current && self.last_warm_iterations > 3 {
                self.factorize()?;
            }
            if let Some(s) = self.warm()? {
                self.spectrum = Some(s);
                return Ok(self.spectrum.as_ref().expect("just stored"));
            }
        }
        self.cold_and_store()
    }

    /// Eigenpairs for `potential`, ignoring any previous solve.
    pub fn solve_cold(&mut self, potential: &[f64]) -> Result<&Spectrum> {
        self.set_potential(potential)?;
        self.cold_and_store()
    }

    fn cold_and_store(&mut self) -> Result<&Spectrum> {
        if !self.factor_current {
            self.factorize()?;
        }
        self.spectrum = None;
        self.block = None;
        let (values, vectors, restarts) = self.cold()?;
        let k = self.params.k;
        let spec = self.finish(
            values[..k].to_vec(),
            vectors.as_ref().subcols(0, k).to_owned(),
            restarts,
            false,
        );
        self.block = Some((values, vectors));
        self.last_warm_iterations = 0;
        self.spectrum = Some(spec);
        Ok(self.spectrum.as_ref().expect("just stored"))
    }

    /// Validate and store the potential (the factor becomes stale).
    fn set_potential(&mut self, potential: &[f64]) -> Result<()> {
        let n = self.n();
        if potential.len() != n {
            return Err(Error::InvalidArgument(format!(
                "potential has {} entries, expected {n}",
                potential.len()
            )));
        }
        if let Some((i, &vi)) = potential
            .iter()
            .enumerate()
            .find(|(_, &v)| !(v.is_finite() && v >= 0.0))
        {
            return Err(Error::InvalidArgument(format!(
                "potential[{i}] = {vi} is not finite and >= 0"
            )));
        }
        if self.potential != potential {
            self.potential.copy_from_slice(potential);
            self.factor_current = false;
        }
        Ok(())
    }

    /// Factorise $K = W + \mathrm{diag}(m \odot (v - \sigma))$ for the current potential.
    fn factorize(&mut self) -> Result<()> {
        self.factor_current = false;
        let d: Vec<f64> = self
            .mass
            .iter()
            .zip(&self.potential)
            .map(|(m, v)| m * (v - self.sigma))
            .collect();
        self.factor.factorize(&d)?;
        self.factor_current = true;
        Ok(())
    }

    /// Sylvester inertia: the number of eigenvalues of the current pencil below `mu` (negative
    /// pivots of $W + \mathrm{diag}(m \odot (v - \mu))$); `None` on a zero pivot.
    fn eigenvalues_below(&self, mu: f64) -> Option<usize> {
        let d: Vec<f64> = self.mass.iter().zip(&self.potential).map(|(m, v)| m * (v - mu)).collect();
        self.factor.count_negative(&d)
    }

    /// Number of guard vectors carried beyond the `k` wanted.
    fn guards(&self) -> usize {
        (self.params.k / 4)
            .max(2)
            .min(self.n().saturating_sub(self.params.k + 1))
    }

    /// $m \odot v$, the diagonal added to $W$.
    fn extra_diag(&self) -> Vec<f64> {
        self.mass
            .iter()
            .zip(&self.potential)
            .map(|(m, v)| m * v)
            .collect()
    }

    /// Cold solve of `k + guards` pairs (ascending), with the Sylvester-inertia check that no
    /// eigenvalue below the `k`-th was missed: a single-vector Krylov space holds one direction
    /// per eigenspace, so members of an exactly repeated eigenvalue (symmetric meshes) can be
    /// missing. The count of negative pivots of $H - \mu M$ is the number of eigenvalues below
    /// $\mu$; missing ones are found by Krylov-Schur on the deflated operator
    /// $(I - YY^\top) S (I - YY^\top)$.
    fn cold(&self) -> Result<(Vec<f64>, Mat<f64>, usize)> {
        let n = self.n();
        let k = self.params.k;
        let nev = k + self.guards();
        if n <= DENSE_MAX.max(3 * k + 2) {
            let extra = self.extra_diag();
            let (values, vectors) = dense_smallest(&self.factor, &extra, &self.inv_sqrt_m, nev)?;
            return Ok((values, vectors, 0));
        }
        // A Hamiltonian with a non-zero potential: block iteration (LOBPCG preconditioned by
        // the exact shift-inverted factor = block shift-invert subspace iteration) from a fixed
        // pseudo-random block. Single-vector Krylov-Schur was measured to stall on step
        // potentials whose height is ~50x the wanted eigenvalues (tens of seconds per solve,
        // against ~0.4 s for this path on a 2,500-vertex shape).
        if self.potential.iter().any(|&v| v != 0.0) {
            let p = (nev + nev / 2 + 2).min(n - 1);
            let x0 = Mat::from_fn(n, p, |i, j| {
                start_value(i as u64, 7 + j as u64) * self.inv_sqrt_m[i]
            });
            if let Some((values, vectors, iters)) = super::block::refine(
                &self.factor,
                &self.mass,
                &self.potential,
                self.sigma,
                x0.as_ref(),
                nev,
                self.params.tol,
                300,
            )? {
                return Ok((
                    values[..nev].to_vec(),
                    vectors.as_ref().subcols(0, nev).to_owned(),
                    iters,
                ));
            }
        }
        let v0 = Col::from_fn(n, |i| start_value(i as u64, 0) * self.sqrt_m[i]);
        let (mut thetas, mut y) = self.krylov_schur(v0.as_ref(), nev, None)?;
        let mut rounds = 0;
        for round in 1..=4u64 {
            let mut lam: Vec<f64> = thetas.iter().map(|t| self.sigma + 1.0 / t).collect();
            lam.sort_by(f64::total_cmp);
            let mu = inertia_cut(&lam, k, self.sigma);
            let found = lam.iter().filter(|&&l| l < mu).count();
            let Some(below) = self.eigenvalues_below(mu) else {
                break;
            };
            if below <= found {
                break;
            }
            rounds = round as usize;
            let missing = below - found;
            let v1 = Col::from_fn(n, |i| start_value(i as u64, round) * self.sqrt_m[i]);
            let extra_nev = (missing + self.guards()).min(n.saturating_sub(y.ncols() + 70));
            if extra_nev == 0 {
                break;
            }
            let (t2, y2) = self.krylov_schur(v1.as_ref(), extra_nev, Some(y.as_ref()))?;
            thetas.extend_from_slice(&t2);
            let mut merged = Mat::<f64>::zeros(n, y.ncols() + y2.ncols());
            merged.as_mut().subcols_mut(0, y.ncols()).copy_from(&y);
            merged
                .as_mut()
                .subcols_mut(y.ncols(), y2.ncols())
                .copy_from(&y2);
            y = merged;
        }
        let mut order: Vec<usize> = (0..thetas.len()).collect();
        order.sort_by(|&a, &b| thetas[b].total_cmp(&thetas[a]));
        order.truncate(nev);
        let values: Vec<f64> = order
            .iter()
            .map(|&j| self.sigma + 1.0 / thetas[j])
            .collect();
        let vectors = Mat::from_fn(n, nev, |i, j| y[(i, order[j])] * self.inv_sqrt_m[i]);
        Ok((values, vectors, rounds))
    }

    fn warm(&mut self) -> Result<Option<Spectrum>> {
        let (_, x0) = self.block.as_ref().expect("warm needs a previous block");
        let k = self.params.k;
        let out = block::refine(
            &self.factor,
            &self.mass,
            &self.potential,
            self.sigma,
            x0.as_ref(),
            k,
            self.params.tol,
            self.params.max_iter,
        )?;
        let Some((values, vectors, iters)) = out else {
            return Ok(None);
        };
        // Sylvester check: from eigenvectors of a different potential, the block can converge
        // to eigenpairs that are not the smallest (e.g. when a well opens where the old
        // vectors have no support, the new low eigenvalues are missed and the Ritz values sit
        // on the walls). The number of negative pivots of $H - \mu M$, $\mu$ a hair above
        // $\lambda_k$, must not exceed the eigenvalues found below $\mu$; else solve cold.
        let mut lam = values.clone();
        lam.sort_by(f64::total_cmp);
        let mu = lam[k - 1] + 1e-6 * (lam[k - 1].abs() + self.sigma.abs());
        let found = lam.iter().filter(|&&l| l < mu).count();
        if self.eigenvalues_below(mu).is_some_and(|below| below > found)
        {
            self.missed_solves += 1;
            return Ok(None);
        }
        self.last_warm_iterations = iters;
        let spec = self.finish(
            values[..k].to_vec(),
            vectors.as_ref().subcols(0, k).to_owned(),
            iters,
            true,
        );
        if !spec.info.converged {
            return Ok(None);
        }
        self.block = Some((values, vectors));
        Ok(Some(spec))
    }

    /// Krylov-Schur on $S = D K^{-1} D$ (deflated by the orthonormal columns of `deflate`):
    /// the `k` largest $\theta$ (descending) and their orthonormal $y$.
    fn krylov_schur(
        &self,
        v0: faer::ColRef<'_, f64>,
        k: usize,
        deflate: Option<MatRef<'_, f64>>,
    ) -> Result<(Vec<f64>, Mat<f64>)> {
        let n = self.n();
        let op = ShiftInvert {
            factor: &self.factor,
            sqrt_m: &self.sqrt_m,
            deflate,
        };
        let mut kp = PartialEigenParams::default();
        kp.max_restarts = self.params.max_restarts;
        kp.min_dim = (k + k / 2).max(32);
        kp.max_dim = (2 * kp.min_dim).max(64);
        // The Krylov space must be smaller than n (faer panics otherwise).
        if kp.max_dim >= n {
            kp.max_dim = n - 1;
            kp.min_dim = kp.min_dim.min(kp.max_dim - 1);
        }
        let req = partial_self_adjoint_eigen_scratch::<f64>(&op, k, Par::Seq, kp);
        let mut mem =
            MemBuffer::try_new(req).map_err(|_| Error::Numerical("out of memory".into()))?;
        let mut y = Mat::<f64>::zeros(n, k);
        let mut thetas = vec![0.0; k];
        // Absolute tolerance on the residual of theta: theta_max <= 1/|sigma|.
        let tol = self.params.tol / self.sigma.abs();
        let info = partial_self_adjoint_eigen(
            y.as_mut(),
            &mut thetas,
            &op,
            v0,
            tol,
            Par::Seq,
            MemStack::new(&mut mem),
            kp,
        );
        if info.n_converged_eigen < k {
            return Err(Error::Numerical(format!(
                "Krylov-Schur found {} of {k} eigenpairs in {} restarts",
                info.n_converged_eigen, self.params.max_restarts
            )));
        }
        Ok((thetas, y))
    }

    /// Sort, fix signs, measure residuals.
    fn finish(
        &self,
        values: Vec<f64>,
        vectors: Mat<f64>,
        iterations: usize,
        warm: bool,
    ) -> Spectrum {
        let (n, k) = (vectors.nrows(), vectors.ncols());
        let mut order: Vec<usize> = (0..k).collect();
        order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
        let values: Vec<f64> = order.iter().map(|&i| values[i]).collect();
        let mut vectors = Mat::from_fn(n, k, |i, j| vectors[(i, order[j])]);
        for j in 0..k {
            let mut best = 0usize;
            let mut best_abs = -1.0;
            for i in 0..n {
                let a = vectors[(i, j)].abs();
                if a > best_abs {
                    best_abs = a;
                    best = i;
                }
            }
            if vectors[(best, j)] < 0.0 {
                for i in 0..n {
                    vectors[(i, j)] = -vectors[(i, j)];
                }
            }
        }
        let max_residual = self
            .residuals(&values, vectors.as_ref())
            .into_iter()
            .fold(0.0, f64::max);
        let converged = max_residual <= residual_bound(self.params.tol);
        Spectrum {
            values,
            vectors,
            info: EigenInfo {
                converged,
                iterations,
                max_residual,
                warm,
                shift: self.sigma,
            },
        }
    }

    /// $\lVert H\phi_i - \lambda_i M\phi_i \rVert_{M^{-1}} / (|\lambda_i| + |\sigma|)$.
    pub(crate) fn residuals(&self, values: &[f64], vectors: MatRef<'_, f64>) -> Vec<f64> {
        let (n, k) = (vectors.nrows(), vectors.ncols());
        let mut r = Mat::<f64>::zeros(n, k);
        self.factor.w_mul(r.as_mut(), vectors);
        (0..k)
            .map(|j| {
                let mut s = 0.0;
                for i in 0..n {
                    let m = self.mass[i];
                    let ri = r[(i, j)] + m * (self.potential[i] - values[j]) * vectors[(i, j)];
                    s += ri * ri / m;
                }
                s.sqrt() / (values[j].abs() + self.sigma.abs())
            })
            .collect()
    }
}

/// The residual reported as converged for a tolerance `tol` (the solvers control the
/// residual of the transformed problem; the pencil residual may be a little larger).
pub(crate) fn residual_bound(tol: f64) -> f64 {
    (tol * 1e4).max(tol.sqrt() * 1e-1)
}

/// Deterministic pseudo-random number in `[-1, 1)` (SplitMix64 of `(i, stream)`).
pub(crate) fn start_value(i: u64, stream: u64) -> f64 {
    let mut z = i
        .wrapping_add(stream.wrapping_mul(0xD1B5_4A32_D192_ED03))
        .wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}

/// $S = D K^{-1} D$ as a faer linear operator.
#[derive(Debug)]
struct ShiftInvert<'a> {
    factor: &'a ShiftedFactor,
    sqrt_m: &'a [f64],
    deflate: Option<MatRef<'a, f64>>,
}

/// `x <- (I - Y Y^T) x`.
fn project_out(y: MatRef<'_, f64>, mut x: MatMut<'_, f64>) {
    let mut c = Mat::<f64>::zeros(y.ncols(), x.ncols());
    faer::linalg::matmul::matmul(
        c.as_mut(),
        faer::Accum::Replace,
        y.transpose(),
        x.rb(),
        1.0,
        Par::Seq,
    );
    faer::linalg::matmul::matmul(x.rb_mut(), faer::Accum::Add, y, c.as_ref(), -1.0, Par::Seq);
}

/// A shift $\mu$ just above the cluster of the `k`-th smallest of the ascending `lam`: half way
/// to the next larger value (or a relative hair above when there is none).
fn inertia_cut(lam: &[f64], k: usize, sigma: f64) -> f64 {
    let lk = lam[k - 1];
    let hair = 1e-8 * (lk.abs() + sigma.abs());
    match lam[k..].iter().find(|&&l| l > lk + hair) {
        Some(&next) => 0.5 * (lam.iter().copied().filter(|&l| l < next).fold(lk, f64::max) + next),
        None => lk + hair,
    }
}

impl LinOp<f64> for ShiftInvert<'_> {
    fn apply_scratch(&self, rhs_ncols: usize, _par: Par) -> StackReq {
        self.factor.solve_scratch(rhs_ncols)
    }
    fn nrows(&self) -> usize {
        self.factor.n()
    }
    fn ncols(&self) -> usize {
        self.factor.n()
    }
    fn apply(
        &self,
        mut out: MatMut<'_, f64>,
        rhs: MatRef<'_, f64>,
        _par: Par,
        stack: &mut MemStack,
    ) {
        let n = self.factor.n();
        out.copy_from(rhs);
        if let Some(y) = self.deflate {
            project_out(y, out.rb_mut());
        }
        for c in 0..rhs.ncols() {
            for i in 0..n {
                out[(i, c)] *= self.sqrt_m[i];
            }
        }
        self.factor.solve_in_place(out.rb_mut(), stack);
        for c in 0..rhs.ncols() {
            for i in 0..n {
                out[(i, c)] *= self.sqrt_m[i];
            }
        }
        if let Some(y) = self.deflate {
            project_out(y, out.rb_mut());
        }
    }
    fn conj_apply(
        &self,
        out: MatMut<'_, f64>,
        rhs: MatRef<'_, f64>,
        par: Par,
        stack: &mut MemStack,
    ) {
        self.apply(out, rhs, par, stack)
    }
}
