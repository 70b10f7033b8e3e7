//! The dual-spectra alignment cost and its gradient (docs/algorithm.md, "Cost and gradient").
//!
//! With the relaxation $v = c\,(\tanh w + 1)$ (one shared $w$, a step height $c$ per
//! spectrum), for each matched spectrum $t$ (regular and/or scale-invariant):
//! $$f_t(w) = \sum_i \frac{(\lambda^t_i(v_t) - \mu^t_i)^2}{(\mu^t_i)^2},\qquad
//!   (W + M_t\,\mathrm{diag}(v_t))\,\phi = \lambda^t M_t \phi ,$$
//! $M_t$ the metric's mass. For simple eigenvalues and $M_t$-normalised $\phi$,
//! $\partial\lambda_i / \partial v_j = m_{t,j}\,\phi_{ij}^2$, so
//! $$\nabla_w f = \sum_t 2\, c_t (1 - \tanh^2 w) \odot M_t (\Phi_t^{\circ 2}) \frac{\lambda^t - \mu^t}{(\mu^t)^2}.$$
//! The full shape's own boundary (if any) carries Dirichlet conditions; `w` there has no effect.
//!
//! Model Hessian: with the residuals
//! $r_i = (\lambda_i - \mu_i)/\mu_i$ and $J = \partial r / \partial w$,
//! $J_{ij} = m_j \phi_{ij}^2\, c (1 - \tanh^2 w_j) / \mu_i$,
//! $$\nabla^2 f \approx 2 J^\top J + 2\,\mathrm{diag}\Big(\sum_i \frac{r_i}{\mu_i} m_j \phi_{ij}^2\, v''(w_j)\Big),
//!   \quad v'' = -2c \tanh w\,(1 - \tanh^2 w),$$
//! the exact Hessian but for the eigenvalues' own second derivatives
//! $r_i \nabla^2_v \lambda_i$ (which need every eigenpair; small where the fit is good):
//! the Gauss-Newton model of nonlinear least squares (Nocedal & Wright 2006, 10.3) plus the
//! exactly known curvature of the relaxation. Free: no eigensolve beyond the gradient's, so
//! one evaluation per trust-region iteration (finite differences of the gradient, Manopt's
//! default, cost ~4 and were measured worse: docs/benchmarks/options.md).

use crate::error::{Error, Result};
use crate::operators::Dirichlet;
use crate::shape::{Metric, Shape};
use crate::spectra::{EigenParams, HamiltonianSolver, Spectrum};

/// Tolerance of the eigensolves inside the optimisation ([`EigenParams::tol`]): warm solves
/// stop at a relative residual of $10^{-3}$, which puts the eigenvalues within $\sim 10^{-6}$
/// (the error of a Rayleigh quotient is of the order of the residual squared) and the
/// gradient's $\phi^2$ within $\sim 10^{-3}$, more than the trust region needs: a quarter
/// fewer block iterations than $10^{-8}$ at the same regions (docs/benchmarks/options.md,
/// "Where the time goes").
pub const EIGEN_TOLERANCE: f64 = 1e-7;

/// The Gauss-Newton model Hessian (module doc) at one `w`, over all vertices of the shape
/// (zero rows and columns at the shape's own boundary).
#[derive(Debug, Clone)]
pub struct GaussNewtonHessian {
    n: usize,
    free: Vec<u32>,
    /// Rows of $J$ over the free vertices, one per matched eigenvalue (all terms).
    jacobian: Vec<Vec<f64>>,
    /// The relaxation's curvature, a diagonal over the free vertices.
    diagonal: Vec<f64>,
}

impl GaussNewtonHessian {
    /// $(2 J^\top J + D)\,\eta$.
    pub fn apply(&self, eta: &[f64]) -> Vec<f64> {
        let e: Vec<f64> = self.free.iter().map(|&j| eta[j as usize]).collect();
        let mut out_free: Vec<f64> = self.diagonal.iter().zip(&e).map(|(d, x)| d * x).collect();
        for row in &self.jacobian {
            let s = 2.0 * row.iter().zip(&e).map(|(a, b)| a * b).sum::<f64>();
            out_free.iter_mut().zip(row).for_each(|(o, a)| *o += s * a);
        }
        let mut out = vec![0.0; self.n];
        for (&j, o) in self.free.iter().zip(out_free) {
            out[j as usize] = o;
        }
        out
    }
}

/// One spectrum to match: metric, target eigenvalues $\mu$ and step height $c$.
#[derive(Debug, Clone)]
pub struct SpectrumTerm {
    pub metric: Metric,
    pub target: Vec<f64>,
    /// $c$ in $v = c(\tanh w + 1)$; the potential's maximum is $2c$.
    pub height: f64,
}

/// The value, gradient (over all vertices of the shape) and spectra at one `w`.
#[derive(Debug, Clone)]
pub struct Evaluation {
    pub cost: f64,
    pub gradient: Vec<f64>,
    /// One spectrum per term (eigenvectors over the free vertices).
    pub spectra: Vec<Spectrum>,
    /// The Gauss-Newton model Hessian at `w`.
    pub hessian: GaussNewtonHessian,
}

/// $v = c(\tanh w + 1)$ elementwise.
pub fn potential_from_w(w: &[f64], height: f64) -> Vec<f64> {
    w.iter().map(|x| height * (x.tanh() + 1.0)).collect()
}

/// Stateful cost: keeps one Hamiltonian solver (symbolic factorisation, warm-start
/// eigenvectors) per term, so successive nearby `w` are cheap.
pub struct AlignmentCost<'a> {
    shape: &'a Shape,
    terms: Vec<SpectrumTerm>,
    solvers: Vec<HamiltonianSolver>,
    masses: Vec<Vec<f64>>,
    /// Number of evaluations so far.
    pub evaluations: usize,
}

impl<'a> AlignmentCost<'a> {
    /// One term per spectrum, solved to [`EIGEN_TOLERANCE`].
    pub fn new(shape: &'a Shape, terms: Vec<SpectrumTerm>) -> Result<Self> {
        Self::with_tolerance(shape, terms, EIGEN_TOLERANCE)
    }

    /// [`AlignmentCost::new`] with the eigensolves' tolerance `tol` ([`EigenParams::tol`]).
    pub fn with_tolerance(shape: &'a Shape, terms: Vec<SpectrumTerm>, tol: f64) -> Result<Self> {
        if terms.is_empty() {
            return Err(Error::InvalidArgument("no spectrum to align".into()));
        }
        let dir = shape.dirichlet();
        let mut solvers = Vec::with_capacity(terms.len());
        let mut masses = Vec::with_capacity(terms.len());
        for t in &terms {
            if t.target.is_empty() || t.target.iter().any(|&m| !(m > 0.0 && m.is_finite())) {
                return Err(Error::InvalidArgument("target eigenvalues must be positive and finite".into()));
            }
            let mass = dir.restrict(shape.metric_mass(t.metric));
            let params = EigenParams { k: t.target.len(), tol, ..EigenParams::default() };
            solvers.push(HamiltonianSolver::with_symbolic(shape.dirichlet_symbolic()?, &mass, params)?);
            masses.push(mass);
        }
        Ok(AlignmentCost { shape, terms, solvers, masses, evaluations: 0 })
    }

    pub fn n(&self) -> usize {
        self.shape.n_vertices()
    }
    #[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
    pub fn terms(&self) -> &[SpectrumTerm] {
        &self.terms
    }
    #[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
    pub fn dirichlet(&self) -> &Dirichlet {
        self.shape.dirichlet()
    }

    /// Each term's last eigensolver block over all vertices of the shape (zero at its own
    /// boundary), carried by `carry` (a vertex function of this shape to one of another),
    /// to seed the same terms on another shape ([`AlignmentCost::seed`]).
    pub fn carried_blocks(&self, carry: impl Fn(&[f64]) -> Vec<f64>) -> Vec<Option<Vec<Vec<f64>>>> {
        let dir = self.shape.dirichlet();
        self.solvers
            .iter()
            .map(|solver| {
                solver.block().map(|x| (0..x.ncols()).map(|j| carry(&dir.extend(&x.col(j).iter().copied().collect::<Vec<_>>(), 0.0))).collect())
            })
            .collect()
    }

    /// Each term's last eigensolver block (the free vertices' rows: the `k` wanted
    /// eigenvectors and the guard ones), `None` before the first solve.
    pub fn blocks(&self) -> Vec<Option<faer::Mat<f64>>> {
        self.solvers.iter().map(|solver| solver.block().cloned()).collect()
    }

    /// Start each term's next eigensolve from `blocks` (columns over all vertices of this
    /// shape; [`AlignmentCost::carried_blocks`] of the same terms elsewhere).
    pub fn seed(&mut self, blocks: Vec<Option<Vec<Vec<f64>>>>) -> Result<()> {
        let dir = self.shape.dirichlet();
        for (solver, block) in self.solvers.iter_mut().zip(blocks) {
            let Some(columns) = block else { continue };
            let restricted: Vec<Vec<f64>> = columns.iter().map(|c| dir.restrict(c)).collect();
            let n = restricted.first().map_or(0, Vec::len);
            solver.seed(faer::Mat::from_fn(n, restricted.len(), |i, j| restricted[j][i]))?;
        }
        Ok(())
    }

    /// Cost and gradient at `w` (length = number of vertices of the shape).
    pub fn evaluate(&mut self, w: &[f64]) -> Result<Evaluation> {
        let n = self.n();
        if w.len() != n {
            return Err(Error::InvalidArgument(format!("w has length {}, expected {n}", w.len())));
        }
        if w.iter().any(|x| !x.is_finite()) {
            return Err(Error::Numerical("non-finite potential".into()));
        }
        self.evaluations += 1;
        let dir = self.shape.dirichlet();
        let w_free = dir.restrict(w);
        let tanh: Vec<f64> = w_free.iter().map(|x| x.tanh()).collect();
        let dtanh: Vec<f64> = tanh.iter().map(|t| 1.0 - t * t).collect();
        let mut jacobian = Vec::with_capacity(self.terms.iter().map(|t| t.target.len()).sum());
        let mut diagonal = vec![0.0; w_free.len()];
        let mut grad_free = vec![0.0; w_free.len()];
        let mut cost = 0.0;
        let mut spectra = Vec::with_capacity(self.terms.len());
        for t in 0..self.terms.len() {
            let (term, mass) = (&self.terms[t], &self.masses[t]);
            // potential_from_w, with the tanh computed once for every term.
            let v: Vec<f64> = tanh.iter().map(|t| term.height * (t + 1.0)).collect();
            // A first solve starts from the previous term's eigenvectors at the same `w` (the
            // same potential shape, another metric) instead of a random block.
            if t > 0 && self.solvers[t].block().is_none() {
                if let Some(b) = self.solvers[t - 1].block().filter(|b| b.ncols() >= self.terms[t].target.len()).cloned() {
                    self.solvers[t].seed(b)?;
                }
            }
            let solver = &mut self.solvers[t];
            let spec = solver.solve(&v)?;
            let k = term.target.len();
            let phi = &spec.vectors;
            for i in 0..k {
                let (lam, mu) = (spec.values[i], term.target[i]);
                let r = (lam - mu) / mu;
                cost += r * r;
                let coef = 2.0 * (lam - mu) / (mu * mu);
                let col = phi.col(i);
                for j in 0..grad_free.len() {
                    let p = col[j];
                    grad_free[j] += coef * mass[j] * p * p * term.height * dtanh[j];
                }
                // J_ij = m_j phi_ij^2 c s_j / mu_i; D_j += 2 (r_i / mu_i) m_j phi_ij^2 v''_j.
                let row = (0..w_free.len())
                    .map(|j| mass[j] * col[j] * col[j] * term.height * dtanh[j] / mu)
                    .collect();
                jacobian.push(row);
                for j in 0..w_free.len() {
                    let v2 = -2.0 * term.height * tanh[j] * dtanh[j];
                    diagonal[j] += 2.0 * r / mu * mass[j] * col[j] * col[j] * v2;
                }
            }
            spectra.push(spec.clone());
        }
        let hessian = GaussNewtonHessian { n, free: dir.free.clone(), jacobian, diagonal };
        Ok(Evaluation { cost, gradient: dir.extend(&grad_free, 0.0), spectra, hessian })
    }
}
