//! The $k$ smallest eigenpairs of $H\phi = \lambda M\phi$, $H = W + \mathrm{diag}(m \odot v)$,
//! $M = \mathrm{diag}(m)$ (docs/algorithm.md, "Spectra").
//!
//! **Shift-invert.** With a shift $\sigma < 0$, $K = H - \sigma M$ is symmetric positive
//! definite ($W \succeq 0$, $v \ge 0$, $m > 0$), and with $D = M^{1/2}$
//! $$S = D K^{-1} D, \qquad S y = \theta y \iff H\phi = \lambda M\phi,\quad
//! \lambda = \sigma + 1/\theta,\quad \phi = D^{-1} y .$$
//! The smallest $\lambda$ are the largest $\theta$, well separated, so a subspace method on
//! $S$ converges in a few dozen applications of $K^{-1}$ (one sparse Cholesky solve each). The
//! orthonormal $y$ give $M$-orthonormal $\phi$: $\Phi^\top M \Phi = Y^\top Y = I$.
//!
//! **Cold solve**: block LOBPCG preconditioned by $K^{-1}$ (see `block`) from the Ritz
//! vectors of a block Krylov space of $S$ grown from a fixed pseudo-random block, checked by
//! Sylvester's inertia. **Warm solve**
//! ([`HamiltonianSolver`]): the previous eigenvectors start the same iteration.
//!
//! **Shift.** $\sigma = -1/\sum_j m_j$ by default: the eigenvalue unit of a surface of that
//! area (a unit sphere has $\lambda_1 \sum m = 8\pi$, a unit-area disk with Dirichlet
//! boundary $\approx 18$). A tiny $|\sigma|$ makes the zero eigenvalue of a closed mesh
//! swamp the others ($\theta_0 = 1/|\sigma|$) and costs accuracy; a huge one compresses the
//! wanted $\theta$ together and costs iterations.

use super::block;
use super::dense::dense_smallest;
use super::factor::{ShiftedFactor, ShiftedPattern};
use std::sync::Arc;
use super::spectrum::{EigenInfo, EigenParams, Spectrum};
use crate::error::{Error, Result};
use crate::operators::SparseMatrix;
use faer::{Mat, MatRef};

/// Columns of the random block a cold solve's Krylov space grows from, and the applications
/// of the shift-inverted operator to it (a space of `6 x 20 = 120` directions): LOBPCG then
/// starts from that space's Ritz vectors instead of a random block. On the warm-up meshes of
/// 4 SHREC'16 pairs (1,000 vertices, 20 eigenpairs and 5 guards, one thread) a cold solve
/// took 10.4 ms instead of 21 ms, on their partials (2,000-6,000 vertices) 26-49 ms instead
/// of 47-92 ms. Blocks of 10 to 26 columns with as many directions, or fewer steps, left
/// LOBPCG more iterations and took longer; 24 steps took as long, 28 and 32 longer
/// (docs/benchmarks/options.md, "Where the time goes").
const KRYLOV_BLOCK: usize = 6;
const KRYLOV_STEPS: usize = 20;

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
    /// The potential of the last solve checked complete (cold, or warm and inertia-checked)
    /// and its guard gap $\lambda_{\text{last guard}} - \lambda_k$.
    checked: Option<(Vec<f64>, f64)>,
    /// Warm solves whose inertia check was skipped as provably unnecessary.
    unchecked_solves: usize,
    /// The LOBPCG blocks, reused by every solve.
    workspace: block::Workspace,
}

/// The symbolic Cholesky analysis of $W + \mathrm{diag}(d)$ for one stiffness $W$: checked
/// once (square, finite, symmetric), analysed once (fill-reducing ordering, elimination tree,
/// supernodes), then shared by every [`HamiltonianSolver`] of that $W$ (every start, both
/// metrics, the selection's solves), which factorise numerically only. Cheap to clone
/// (reference counted); `Send + Sync`. faer's `SymbolicLlt` / `Llt::try_new_with_symbolic`
/// pattern.
#[derive(Debug, Clone)]
pub struct SymbolicHamiltonian(Arc<ShiftedPattern>);

impl SymbolicHamiltonian {
    /// Check and analyse `w`.
    pub fn new(w: &SparseMatrix) -> Result<Self> {
        Ok(SymbolicHamiltonian(Arc::new(ShiftedPattern::new(w)?)))
    }

    /// Rows (and columns) of the analysed `W`.
    pub fn n(&self) -> usize {
        self.0.n()
    }
}

impl HamiltonianSolver {
    /// Check `(w, mass, params)` and analyse the sparsity of `w`. See [`generalized_eigen`]
    /// for the conditions.
    pub fn new(w: &SparseMatrix, mass: &[f64], params: EigenParams) -> Result<Self> {
        Self::with_symbolic(&SymbolicHamiltonian::new(w)?, mass, params)
    }

    /// As [`HamiltonianSolver::new`], on an analysed `W` (no symbolic work).
    pub fn with_symbolic(symbolic: &SymbolicHamiltonian, mass: &[f64], params: EigenParams) -> Result<Self> {
        let n = symbolic.n();
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
        let factor = ShiftedFactor::with_pattern(symbolic.0.clone());
        Ok(HamiltonianSolver {
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
            checked: None,
            unchecked_solves: 0,
            workspace: block::Workspace::new(),
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

    /// Warm solves so far that skipped the inertia check: the potential was within a tenth of
    /// the guard gap of a checked one (see `warm`).
    pub fn unchecked_solves(&self) -> usize {
        self.unchecked_solves
    }

    /// The last solve's block: the `k` wanted eigenvectors and the guard ones, `M`-orthonormal.
    pub(crate) fn block(&self) -> Option<&Mat<f64>> {
        self.block.as_ref().map(|(_, x)| x)
    }

    /// Start the next solve from `block` (`n` rows, at least `k` columns; e.g. a coarser
    /// mesh's eigenvectors carried over): warm and inertia-checked, cold if that fails.
    /// The columns need not be orthonormal (the solve starts with a Rayleigh-Ritz step).
    pub(crate) fn seed(&mut self, block: Mat<f64>) -> Result<()> {
        if block.nrows() != self.n() || block.ncols() < self.params.k || block.ncols() >= self.n() {
            return Err(Error::InvalidArgument(format!(
                "a seed block of {} x {} for n = {} and k = {}",
                block.nrows(),
                block.ncols(),
                self.n(),
                self.params.k
            )));
        }
        self.reset();
        self.block = Some((Vec::new(), block));
        Ok(())
    }

    /// Forget the previous spectrum: the next solve is cold.
    pub fn reset(&mut self) {
        self.spectrum = None;
        self.block = None;
        self.checked = None;
    }

    /// Eigenpairs for the potential `potential` (length `n`, finite, `>= 0`), warm-started
    /// from the previous solve when there is one and `params.warm_start`.
    pub fn solve(&mut self, potential: &[f64]) -> Result<&Spectrum> {
        self.set_potential(potential)?;
        if self.params.warm_start && self.block.is_some() {
            // The old factor preconditions well while v moves little; refresh it when the
            // last warm solve needed many iterations, or when no solve made it (a seeded
            // block: nothing checked yet).
            if !self.factor_current && (self.last_warm_iterations > 3 || self.checked.is_none()) {
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
        self.checked = Some((self.potential.clone(), guard_gap(&values, k)));
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

    /// Eigenvalues of the current pencil missing from the ascending `lam` (the `k` wanted plus
    /// guards) below the `k`-th one: Sylvester's inertia (the negative pivots of
    /// $W + \mathrm{diag}(m \odot (v - \mu))$ count the eigenvalues below $\mu$) at the cut
    /// $\mu$ just below the cluster of $\lambda_k$ ([`inertia_cut`]), against the found values
    /// below $\mu$. A repeated $\lambda_k$ whose cluster extends past the guards is not a miss
    /// (its members have one value). `accuracy`: the relative residual the values were solved
    /// to (it bounds their error). 0 on a zero pivot.
    fn missing_below_kth(&self, lam: &[f64], accuracy: f64) -> usize {
        let mu = inertia_cut(lam, self.params.k, accuracy, self.sigma);
        let found = lam.iter().filter(|&&l| l < mu).count();
        let d: Vec<f64> = self
            .mass
            .iter()
            .zip(&self.potential)
            .map(|(m, v)| m * (v - mu))
            .collect();
        self.factor
            .count_negative(&d)
            .map_or(0, |below| below.saturating_sub(found))
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

    /// Cold solve of `k + guards` pairs (ascending): block LOBPCG preconditioned by the exact
    /// shift-inverted factor (= block shift-invert subspace iteration) from `p > k + guards`
    /// vectors: the lowest Ritz vectors of a block Krylov space of the shift-inverted operator
    /// grown from a fixed pseudo-random block ([`KRYLOV_BLOCK`], [`KRYLOV_STEPS`]; the random
    /// block itself on meshes too small for that space), then Sylvester's inertia check that no
    /// eigenvalue below the `k`-th was missed (the negative pivots of $H - \mu M$ count the
    /// eigenvalues below $\mu$). A miss is retried from another random block (of `p` columns,
    /// no Krylov space) with room for the missing ones, a block iteration that does not converge (a stall) from another
    /// random block; after three attempts it is an error, never a silent wrong spectrum.
    ///
    /// A block method finds every member of a repeated eigenvalue (symmetric meshes). The
    /// single-vector Krylov-Schur used before (faer's `partial_self_adjoint_eigen`) holds one
    /// direction per eigenspace and needed deflation rounds for the rest; on a symmetric mesh
    /// its space can outgrow the number of distinct eigenvalues, and at that (near)
    /// breakdown faer 0.24's Lanczos re-orthogonalisation never returns (icosphere, k = 43:
    /// it compares the removed component to a vanishing norm; open upstream as faer-rs issue
    /// #262, "partial_self_adjoint_eigen hangs indefinitely on some inputs"). It also stalled
    /// on step potentials ~50x
    /// the wanted eigenvalues (tens of seconds per solve against ~0.4 s for this path on a
    /// 2,500-vertex shape).
    fn cold(&mut self) -> Result<(Vec<f64>, Mat<f64>, usize)> {
        let n = self.n();
        let k = self.params.k;
        let nev = k + self.guards();
        if n <= DENSE_MAX.max(3 * k + 2) {
            let extra = self.extra_diag();
            let (values, vectors) = dense_smallest(&self.factor, &extra, &self.inv_sqrt_m, nev)?;
            return Ok((values, vectors, 0));
        }
        let mut p = (nev + nev / 2 + 2).min(n - 1);
        let (mut missing, mut unconverged) = (0, 0);
        for attempt in 0..3u64 {
            let random = |cols: usize| {
                Mat::from_fn(n, cols, |i, j| start_value(i as u64, 7 + 1000 * attempt + j as u64) * self.inv_sqrt_m[i])
            };
            // The Krylov space must leave room for the wanted directions to converge in.
            // A repeated eigenvalue of more members than the Krylov block has would be missed
            // again: the retries start from a random block of `p` columns.
            let krylov = (attempt == 0 && KRYLOV_BLOCK * (KRYLOV_STEPS + 1) + p < n)
                .then(|| super::block::krylov_start(&self.factor, &self.mass, random(KRYLOV_BLOCK).as_ref(), KRYLOV_STEPS, p))
                .flatten();
            let x0 = krylov.unwrap_or_else(|| random(p));
            let Some((values, vectors, iters)) = super::block::refine(
                &self.factor,
                &self.mass,
                &self.potential,
                self.sigma,
                x0.as_ref(),
                nev,
                cold_target(self.params.tol),
                self.params.max_cold_iter,
                &mut self.workspace,
            )?
            else {
                // Not converged (a stall of the block iteration): another random block.
                unconverged += 1;
                continue;
            };
            let mut lam = values.clone();
            lam.sort_by(f64::total_cmp);
            missing = self.missing_below_kth(&lam, cold_target(self.params.tol));
            if missing == 0 {
                return Ok((
                    values[..nev].to_vec(),
                    vectors.as_ref().subcols(0, nev).to_owned(),
                    iters,
                ));
            }
            p = (p + 2 * missing).min(n - 1);
        }
        if unconverged > 0 && missing == 0 {
            return Err(Error::Numerical(format!(
                "the eigensolver did not converge in {} block iterations from {unconverged} \
                 random starts ({nev} eigenpairs, {n} vertices)",
                self.params.max_cold_iter
            )));
        }
        Err(Error::Numerical(format!(
            "the eigensolver missed {missing} of the {k} smallest eigenvalues after three \
             attempts (Sylvester inertia check, {n} vertices)"
        )))
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
            residual_bound(self.params.tol),
            self.params.max_iter,
            &mut self.workspace,
        )?;
        let Some((values, vectors, iters)) = out else {
            return Ok(None);
        };
        // Sylvester check: from eigenvectors of a different potential, the block can converge
        // to eigenpairs that are not the smallest (e.g. when a well opens where the old
        // vectors have no support, the new low eigenvalues are missed and the Ritz values sit
        // on the walls). Any eigenvalue missed below the k-th (inertia) -> solve cold.
        // Skipped when v is within a tenth of the guard gap of a checked potential (every
        // block since then started there): the pencil's eigenvalues move by at most
        // max|dv| (Weyl, the change is M diag(dv)) and the wanted subspace turns by at most
        // max|dv| / gap (Davis-Kahan), so the start block holds it and none can be missed.
        // This spares the check (one more factorisation) on the trust region's
        // finite-difference Hessian-vector evaluations.
        let near_checked = self.checked.as_ref().is_some_and(|(v0, gap)| {
            let dv = self
                .potential
                .iter()
                .zip(v0)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            dv <= 0.1 * gap
        });
        let mut lam = values.clone();
        lam.sort_by(f64::total_cmp);
        if near_checked {
            self.unchecked_solves += 1;
        } else if self.missing_below_kth(&lam, residual_bound(self.params.tol)) > 0 {
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
        if !near_checked {
            self.checked = Some((self.potential.clone(), guard_gap(&lam, k)));
        }
        self.block = Some((values, vectors));
        Ok(Some(spec))
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

/// $\lambda_{\text{last}} - \lambda_k$ of the values of a block (`k` wanted plus guards).
fn guard_gap(values: &[f64], k: usize) -> f64 {
    let last = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut lam = values.to_vec();
    lam.sort_by(f64::total_cmp);
    (last - lam[k - 1]).max(0.0)
}

/// The relative residual a cold solve is converged to for a tolerance `tol` (one-off solves:
/// near the accuracy of the former Krylov-Schur, at a few more block iterations).
fn cold_target(tol: f64) -> f64 {
    (100.0 * tol).max(1e-13)
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

/// The inertia cut for the `k`-th of the ascending `lam`: a hair below the lowest member of
/// its cluster (the values chained to $\lambda_k$ by gaps under a hair). The hair is the
/// eigenvalue error bound of the solve, $\max(\text{accuracy}, 10^{-8})\,(|\lambda_k| +
/// |\sigma|)$ (a relative residual $r$ puts a true eigenvalue within $r(|\lambda| + |\sigma|)$
/// of $\lambda$), so every eigenvalue below the cut has its computed value below it too, and
/// one between the cut and $\lambda_k$ equals $\lambda_k$ to the solve's accuracy.
fn inertia_cut(lam: &[f64], k: usize, accuracy: f64, sigma: f64) -> f64 {
    let hair = accuracy.max(1e-8) * (lam[k - 1].abs() + sigma.abs());
    let mut j = k - 1;
    while j > 0 && lam[j] - lam[j - 1] < hair {
        j -= 1;
    }
    lam[j] - hair
}

#[cfg(test)]
mod seed_tests {
    use super::*;
    use crate::mesh::generate::icosphere;
    use crate::operators::{cotangent_stiffness, lumped_mass};

    /// A solve seeded with a coarser mesh's eigenvectors, carried over by nearest vertices
    /// (as the warm-up mesh hands over to the optimisation mesh), converges warm to the
    /// eigenvalues of a cold solve.
    #[test]
    fn a_solve_seeded_from_a_coarser_mesh_matches_cold() {
        let (coarse, fine) = (icosphere(3), icosphere(4));
        let well = |m: &crate::mesh::TriMesh| -> Vec<f64> { m.vertices().iter().map(|p| if p[2] > 0.3 { 0.0 } else { 1e3 }).collect() };
        let solver = |m: &crate::mesh::TriMesh| HamiltonianSolver::new(&cotangent_stiffness(m), &lumped_mass(m), EigenParams { k: 12, ..EigenParams::default() }).unwrap();
        let mut on_coarse = solver(&coarse);
        on_coarse.solve(&well(&coarse)).unwrap();
        let block = on_coarse.block().unwrap();
        let cell = crate::mesh::nearest::nearest_vertices(coarse.vertices(), fine.vertices()).unwrap();
        let carried = Mat::from_fn(fine.n_vertices(), block.ncols(), |i, j| block[(cell[i] as usize, j)]);

        let cold = solver(&fine).solve_cold(&well(&fine)).unwrap().clone();
        let mut seeded = solver(&fine);
        seeded.seed(carried).unwrap();
        let warm = seeded.solve(&well(&fine)).unwrap().clone();
        assert!(warm.info.warm && warm.info.converged, "{:?}", warm.info);
        for (a, b) in warm.values.iter().zip(&cold.values) {
            assert!((a - b).abs() <= 1e-8 * b.abs(), "seeded {a} vs cold {b}");
        }

        // A block of the wrong shape is refused.
        assert!(solver(&fine).seed(Mat::zeros(10, 14)).is_err());
    }
}
