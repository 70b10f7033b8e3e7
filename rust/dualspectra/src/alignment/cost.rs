//! The dual-spectra alignment cost and its gradient (ALGORITHM.md "Cost and gradient").
//!
//! With the relaxation $v = c\,(\tanh w + 1)$ (one shared $w$, a step height $c$ per
//! spectrum), for each matched spectrum $t$ (regular and/or scale-invariant):
//! $$f_t(w) = \sum_i \frac{(\lambda^t_i(v_t) - \mu^t_i)^2}{(\mu^t_i)^2},\qquad
//!   (W + M_t\,\mathrm{diag}(v_t))\,\phi = \lambda^t M_t \phi ,$$
//! $M_t$ the metric's mass. For simple eigenvalues and $M_t$-normalised $\phi$,
//! $\partial\lambda_i / \partial v_j = m_{t,j}\,\phi_{ij}^2$, so
//! $$\nabla_w f = \sum_t 2\, c_t (1 - \tanh^2 w) \odot M_t (\Phi_t^{\circ 2}) \frac{\lambda^t - \mu^t}{(\mu^t)^2}.$$
//! The full shape's own boundary (if any) carries Dirichlet conditions; `w` there has no effect.

use crate::error::{Error, Result};
use crate::operators::Dirichlet;
use crate::shape::{Metric, Shape};
use crate::spectra::{EigenParams, HamiltonianSolver, Spectrum};

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
    pub fn new(shape: &'a Shape, terms: Vec<SpectrumTerm>) -> Result<Self> {
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
            // The optimiser needs eigenvalues to ~1e-8, not machine precision.
            let params = EigenParams { k: t.target.len(), tol: 1e-8, ..EigenParams::default() };
            solvers.push(HamiltonianSolver::new(shape.dirichlet_stiffness(), &mass, params)?);
            masses.push(mass);
        }
        Ok(AlignmentCost { shape, terms, solvers, masses, evaluations: 0 })
    }

    pub fn n(&self) -> usize {
        self.shape.n_vertices()
    }
    pub fn terms(&self) -> &[SpectrumTerm] {
        &self.terms
    }
    pub fn dirichlet(&self) -> &Dirichlet {
        self.shape.dirichlet()
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
        let dtanh: Vec<f64> = w_free.iter().map(|x| 1.0 - x.tanh().powi(2)).collect();
        let mut grad_free = vec![0.0; w_free.len()];
        let mut cost = 0.0;
        let mut spectra = Vec::with_capacity(self.terms.len());
        for ((term, solver), mass) in self.terms.iter().zip(&mut self.solvers).zip(&self.masses) {
            let v = potential_from_w(&w_free, term.height);
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
            }
            spectra.push(spec.clone());
        }
        Ok(Evaluation { cost, gradient: dir.extend(&grad_free, 0.0), spectra })
    }
}
