//! A mesh with its derived operators, computed on first use and cached
//! (geometry-central's `require*` pattern): stiffness $W$, lumped mass $A$, Gaussian
//! curvature $K$ (raw and one-ring smoothed), scale-invariant factor $s$, boundary and
//! the Dirichlet restriction, and the Dirichlet spectra of both metrics.

use crate::error::{Error, Result};
use crate::geometry::{self, metric};
use crate::mesh::{topology, TriMesh};
use crate::operators::{self, Dirichlet, SparseMatrix};
use crate::spectra::{generalized_eigen, EigenParams, Spectrum, SymbolicHamiltonian};
use serde::{Deserialize, Serialize};
use std::sync::OnceLock;

/// Which metric a spectrum uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Metric {
    /// The surface's own metric $g$: mass $A$.
    Regular,
    /// The scale-invariant metric $\tilde g = s g$: mass $\tilde A = \mathrm{diag}(s) A$.
    #[serde(rename = "si")]
    ScaleInvariant,
}

impl std::str::FromStr for Metric {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "regular" | "lbo" => Ok(Metric::Regular),
            "si" | "scale-invariant" | "scale_invariant" => Ok(Metric::ScaleInvariant),
            _ => Err(Error::InvalidArgument(format!("unknown metric '{s}' (expected regular or si)"))),
        }
    }
}

/// A [`TriMesh`] with cached operators. Cheap to build; every quantity is computed once on first access.
#[derive(Debug)]
pub struct Shape {
    mesh: TriMesh,
    alpha: f64,
    eps: f64,
    stiffness: OnceLock<SparseMatrix>,
    mass: OnceLock<Vec<f64>>,
    curvature: OnceLock<Vec<f64>>,
    smoothed_curvature: OnceLock<Vec<f64>>,
    si_factor: OnceLock<Vec<f64>>,
    si_mass: OnceLock<Vec<f64>>,
    boundary: OnceLock<Vec<bool>>,
    dirichlet: OnceLock<Dirichlet>,
    restricted_stiffness: OnceLock<SparseMatrix>,
    symbolic: OnceLock<SymbolicHamiltonian>,
}

impl Shape {
    /// With the paper's defaults $\alpha = 0.33$, $\epsilon = 10^{-8}$.
    pub fn new(mesh: TriMesh) -> Self {
        Self::with_metric_params(mesh, metric::DEFAULT_ALPHA, metric::DEFAULT_EPS)
    }

    pub fn with_metric_params(mesh: TriMesh, alpha: f64, eps: f64) -> Self {
        Shape {
            mesh,
            alpha,
            eps,
            stiffness: OnceLock::new(),
            mass: OnceLock::new(),
            curvature: OnceLock::new(),
            smoothed_curvature: OnceLock::new(),
            si_factor: OnceLock::new(),
            si_mass: OnceLock::new(),
            boundary: OnceLock::new(),
            dirichlet: OnceLock::new(),
            restricted_stiffness: OnceLock::new(),
            symbolic: OnceLock::new(),
        }
    }

    /// With a given scale-invariant factor $s$ (one per vertex) instead of the one computed from
    /// this mesh's own curvature, e.g. one estimated on a finer mesh of the same surface
    /// ([`crate::geometry::metric::transfer_factor`]). Errors on a wrong length or a
    /// non-positive or non-finite entry.
    pub fn with_scale_invariant_factor(mesh: TriMesh, alpha: f64, eps: f64, factor: Vec<f64>) -> Result<Self> {
        if factor.len() != mesh.n_vertices() {
            return Err(Error::InvalidArgument(format!(
                "scale-invariant factor has {} entries for {} vertices",
                factor.len(),
                mesh.n_vertices()
            )));
        }
        if let Some(i) = factor.iter().position(|s| !(s.is_finite() && *s > 0.0)) {
            return Err(Error::InvalidArgument(format!("scale-invariant factor {} at vertex {i} is not positive", factor[i])));
        }
        let shape = Self::with_metric_params(mesh, alpha, eps);
        let _ = shape.si_factor.set(factor);
        Ok(shape)
    }

    pub fn mesh(&self) -> &TriMesh {
        &self.mesh
    }
    pub fn n_vertices(&self) -> usize {
        self.mesh.n_vertices()
    }
    pub fn alpha(&self) -> f64 {
        self.alpha
    }
    /// Cotangent stiffness $W$ (`n x n`).
    pub fn stiffness(&self) -> &SparseMatrix {
        self.stiffness.get_or_init(|| operators::cotangent_stiffness(&self.mesh))
    }
    /// Lumped mass diagonal $a$.
    pub fn mass(&self) -> &[f64] {
        self.mass.get_or_init(|| operators::lumped_mass(&self.mesh))
    }
    /// Angle-defect Gaussian curvature $K$ per vertex.
    pub fn gaussian_curvature(&self) -> &[f64] {
        self.curvature.get_or_init(|| geometry::gaussian_curvature(&self.mesh))
    }
    /// One-ring mean of $K$.
    pub fn smoothed_curvature(&self) -> &[f64] {
        self.smoothed_curvature
            .get_or_init(|| geometry::smooth_one_ring(&self.mesh, self.gaussian_curvature()))
    }
    /// $s = (\epsilon + K_{smooth}^2)^{\alpha/2}$.
    pub fn scale_invariant_factor(&self) -> &[f64] {
        self.si_factor.get_or_init(|| metric::scale_invariant_factor(self.smoothed_curvature(), self.alpha, self.eps))
    }
    /// Mass diagonal of the given metric: $a$ or $s \odot a$.
    pub fn metric_mass(&self, metric: Metric) -> &[f64] {
        match metric {
            Metric::Regular => self.mass(),
            Metric::ScaleInvariant => self
                .si_mass
                .get_or_init(|| operators::scale_invariant_mass(self.mass(), self.scale_invariant_factor())),
        }
    }
    /// `true` on boundary vertices.
    pub fn boundary_mask(&self) -> &[bool] {
        self.boundary.get_or_init(|| topology::boundary_vertex_mask(&self.mesh))
    }
    pub fn has_boundary(&self) -> bool {
        self.boundary_mask().iter().any(|&b| b)
    }
    /// Dirichlet restriction on the boundary vertices (identity on closed meshes).
    pub fn dirichlet(&self) -> &Dirichlet {
        self.dirichlet.get_or_init(|| Dirichlet::new(self.boundary_mask()))
    }
    /// $W$ restricted to the free (interior) vertices.
    pub fn dirichlet_stiffness(&self) -> &SparseMatrix {
        self.restricted_stiffness.get_or_init(|| self.dirichlet().restrict_matrix(self.stiffness()))
    }
    /// The symbolic Cholesky analysis of the Dirichlet stiffness, shared by every
    /// [`crate::spectra::HamiltonianSolver`] on this shape (every start, both metrics).
    pub fn dirichlet_symbolic(&self) -> Result<&SymbolicHamiltonian> {
        if let Some(s) = self.symbolic.get() {
            return Ok(s);
        }
        let s = SymbolicHamiltonian::new(self.dirichlet_stiffness())?;
        Ok(self.symbolic.get_or_init(|| s))
    }

    /// The `k` smallest eigenpairs of $W\phi = \mu M\phi$ on the interior vertices
    /// (homogeneous Dirichlet conditions on the boundary, none on a closed mesh), with
    /// $M$ the mass of `metric`. Eigenvectors are indexed by the free vertices
    /// (`self.dirichlet().extend` puts zeros back on the boundary).
    pub fn dirichlet_spectrum(&self, metric: Metric, k: usize) -> Result<Spectrum> {
        self.dirichlet_spectrum_to(metric, k, EigenParams::default().tol)
    }

    /// [`Shape::dirichlet_spectrum`] solved to the tolerance `tol` ([`EigenParams::tol`]).
    pub(crate) fn dirichlet_spectrum_to(&self, metric: Metric, k: usize, tol: f64) -> Result<Spectrum> {
        let n_free = self.dirichlet().n_free();
        if n_free == 0 {
            return Err(Error::InvalidArgument(format!(
                "k = {k} eigenvalues requested, but the mesh has no interior vertex (every vertex is on the boundary)"
            )));
        }
        if k == 0 || k >= n_free {
            return Err(Error::InvalidArgument(format!(
                "k = {k} eigenvalues requested, but the mesh has {n_free} interior vertices (need 0 < k < {n_free})"
            )));
        }
        let mass = self.dirichlet().restrict(self.metric_mass(metric));
        generalized_eigen(self.dirichlet_stiffness(), &mass, &EigenParams { k, tol, ..EigenParams::default() })
    }
}
