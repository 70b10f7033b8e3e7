//! # dualspectra-ffi
//!
//! Foreign interfaces of the `dualspectra` core, conversion only (no formula lives here):
//!
//! - [`c_abi`]: a C ABI (`extern "C"`, opaque handles, explicit lengths, status codes,
//!   progress/cancel callback). Its header `cpp/include/dualspectra/dualspectra.h` is generated
//!   by cbindgen from this crate and checked in; `tests/header.rs` regenerates it and fails if
//!   the committed file differs (`DS_BLESS_HEADER=1 cargo test -p dualspectra-ffi --test header`
//!   rewrites it).
//! - [`cxx_bridge`]: the `cxx` bridge behind the C++ API `cpp/include/dualspectra/dualspectra.hpp`.
//!
//! Built as `staticlib` (what CMake imports), `cdylib` and `rlib` (for the Rust tests).

pub mod c_abi;
pub mod cxx_bridge;

use dualspectra::shape::{Metric, Shape};
use dualspectra::{Error, Localization, Mode, Options, Progress, Selection, StartShape, TriMesh};

/// A mesh handle's payload: the core's [`Shape`] (the mesh with its operators cached on first
/// use, so repeated curvature/spectrum queries on one handle do not recompute them).
pub(crate) struct ShapeCache {
    shape: Shape,
}

impl ShapeCache {
    pub(crate) fn new(mesh: TriMesh) -> Self {
        ShapeCache { shape: Shape::new(mesh) }
    }
    pub(crate) fn mesh(&self) -> &TriMesh {
        self.shape.mesh()
    }
    /// Cotangent stiffness $W$ (cached).
    pub(crate) fn stiffness(&self) -> &dualspectra::operators::SparseMatrix {
        self.shape.stiffness()
    }
    /// Run `f` on the handle's shape, or, for the scale-invariant metric with an exponent
    /// other than the handle's, on a fresh [`Shape`] with exponent `alpha`.
    fn with_metric<T>(&self, metric: Metric, alpha: f64, f: impl FnOnce(&Shape) -> Result<T, Error>) -> Result<T, Error> {
        if !alpha.is_finite() {
            return Err(Error::InvalidArgument(format!("alpha must be finite, got {alpha}")));
        }
        if metric == Metric::Regular || alpha == self.shape.alpha() {
            f(&self.shape)
        } else {
            let eps = dualspectra::geometry::metric::DEFAULT_EPS;
            f(&Shape::with_metric_params(self.mesh().clone(), alpha, eps))
        }
    }
}

/// Map a core error to a C status code.
pub(crate) fn status_of(e: &Error) -> c_abi::ds_status {
    #[allow(unreachable_patterns)]
    match e {
        Error::Io { .. } | Error::Parse { .. } => c_abi::DS_IO,
        Error::InvalidMeshFile { .. } | Error::InvalidMesh(_) => c_abi::DS_INVALID_MESH,
        Error::InvalidArgument(_) => c_abi::DS_INVALID_ARGUMENT,
        Error::Numerical(_) => c_abi::DS_NUMERICAL,
        Error::Cancelled => c_abi::DS_CANCELLED,
        _ => c_abi::DS_NUMERICAL,
    }
}

pub(crate) fn metric_from_code(code: u32) -> Result<Metric, Error> {
    match code {
        c_abi::DS_METRIC_REGULAR => Ok(Metric::Regular),
        c_abi::DS_METRIC_SCALE_INVARIANT => Ok(Metric::ScaleInvariant),
        _ => Err(Error::InvalidArgument(format!("unknown metric {code} (expected 0 = regular, 1 = scale-invariant)"))),
    }
}

pub(crate) fn mode_from_code(code: u32) -> Result<Mode, Error> {
    match code {
        c_abi::DS_MODE_DUAL => Ok(Mode::Dual),
        c_abi::DS_MODE_LBO => Ok(Mode::Lbo),
        c_abi::DS_MODE_SI => Ok(Mode::Si),
        _ => Err(Error::InvalidArgument(format!("unknown mode {code} (expected 0 = dual, 1 = lbo, 2 = si)"))),
    }
}

pub(crate) fn mode_code(mode: Mode) -> u32 {
    match mode {
        Mode::Dual => c_abi::DS_MODE_DUAL,
        Mode::Lbo => c_abi::DS_MODE_LBO,
        Mode::Si => c_abi::DS_MODE_SI,
    }
}

pub(crate) fn selection_from_code(code: u32) -> Result<Selection, Error> {
    match code {
        c_abi::DS_SELECTION_DESCRIPTORS => Ok(Selection::Descriptors),
        c_abi::DS_SELECTION_COST => Ok(Selection::Cost),
        c_abi::DS_SELECTION_REGION => Ok(Selection::Region),
        c_abi::DS_SELECTION_GATED => Ok(Selection::Gated),
        _ => Err(Error::InvalidArgument(format!(
            "unknown selection {code} (expected 0 = descriptors, 1 = cost, 2 = region, 3 = gated)"
        ))),
    }
}

pub(crate) fn selection_code(selection: Selection) -> u32 {
    match selection {
        Selection::Descriptors => c_abi::DS_SELECTION_DESCRIPTORS,
        Selection::Cost => c_abi::DS_SELECTION_COST,
        Selection::Region => c_abi::DS_SELECTION_REGION,
        Selection::Gated => c_abi::DS_SELECTION_GATED,
    }
}

pub(crate) fn start_shape_from_code(code: u32) -> Result<StartShape, Error> {
    match code {
        c_abi::DS_STARTS_BALLS_AND_WIDE_BUMPS => Ok(StartShape::BallsAndWideBumps),
        c_abi::DS_STARTS_BALLS_AND_WIDE_GAUSSIANS => Ok(StartShape::BallsAndWideGaussians),
        c_abi::DS_STARTS_GAUSSIAN => Ok(StartShape::Gaussian),
        c_abi::DS_STARTS_AREA_BALL => Ok(StartShape::AreaBall),
        _ => Err(Error::InvalidArgument(format!(
            "unknown start shape {code} (expected 0 = balls and wide bumps, 1 = balls and wide \
             Gaussians, 2 = Gaussian, 3 = area ball)"
        ))),
    }
}

pub(crate) fn start_shape_code(shape: StartShape) -> u32 {
    match shape {
        StartShape::BallsAndWideBumps => c_abi::DS_STARTS_BALLS_AND_WIDE_BUMPS,
        StartShape::BallsAndWideGaussians => c_abi::DS_STARTS_BALLS_AND_WIDE_GAUSSIANS,
        StartShape::Gaussian => c_abi::DS_STARTS_GAUSSIAN,
        StartShape::AreaBall => c_abi::DS_STARTS_AREA_BALL,
    }
}

/// Options from the C struct (the same fields as the C++ one). Ranges are checked by the core's
/// `localize` (each violation is an `InvalidArgument`).
pub(crate) fn options_from_c(o: &c_abi::ds_options) -> Result<Options, Error> {
    #[allow(clippy::needless_update)]
    Ok(Options {
        mode: mode_from_code(o.mode)?,
        k: o.k,
        alpha: o.alpha,
        seed: o.seed,
        resolution: o.resolution,
        centers: o.centers,
        max_iterations: o.max_iterations,
        threads: o.threads,
        selection: selection_from_code(o.selection)?,
        start_shape: start_shape_from_code(o.start_shape)?,
        spectral_cuts: o.spectral_cuts,
        plane_cuts: o.plane_cuts,
        ..Options::default()
    })
}

pub(crate) fn options_to_c(o: &Options) -> c_abi::ds_options {
    c_abi::ds_options {
        mode: mode_code(o.mode),
        k: o.k,
        alpha: o.alpha,
        seed: o.seed,
        resolution: o.resolution,
        centers: o.centers,
        max_iterations: o.max_iterations,
        threads: o.threads,
        selection: selection_code(o.selection),
        start_shape: start_shape_code(o.start_shape),
        spectral_cuts: o.spectral_cuts,
        plane_cuts: o.plane_cuts,
    }
}

/// `major * 10000 + minor * 100 + patch` of this crate.
pub(crate) fn version_number() -> u32 {
    let mut parts = env!("CARGO_PKG_VERSION").split(['.', '-']).map(|p| p.parse::<u32>().unwrap_or(0));
    let (a, b, c) = (parts.next().unwrap_or(0), parts.next().unwrap_or(0), parts.next().unwrap_or(0));
    a * 10000 + b * 100 + c
}

/// Pointwise (angle-defect) Gaussian curvature, raw or one-ring smoothed (cached by the core).
pub(crate) fn gaussian_curvature(shape: &ShapeCache, smoothed: bool) -> Vec<f64> {
    if smoothed {
        shape.shape.smoothed_curvature().to_vec()
    } else {
        shape.shape.gaussian_curvature().to_vec()
    }
}

/// The `k` smallest Dirichlet eigenvalues in `metric` ([`Shape::dirichlet_spectrum`]); a
/// scale-invariant spectrum with an `alpha` other than the handle's default uses a fresh
/// [`Shape`] with that exponent.
pub(crate) fn spectrum(shape: &ShapeCache, k: usize, metric: Metric, alpha: f64) -> Result<Vec<f64>, Error> {
    shape.with_metric(metric, alpha, |s| Ok(s.dirichlet_spectrum(metric, k)?.values))
}

/// Mass diagonal of `metric` ([`Shape::metric_mass`]), all vertices.
pub(crate) fn mass(shape: &ShapeCache, metric: Metric, alpha: f64) -> Result<Vec<f64>, Error> {
    shape.with_metric(metric, alpha, |s| Ok(s.metric_mass(metric).to_vec()))
}

pub(crate) fn localize(full: &ShapeCache, partial: &ShapeCache, options: &Options, progress: &Progress) -> Result<Localization, Error> {
    dualspectra::localize(full.mesh(), partial.mesh(), options, progress)
}

/// The Hamiltonian eigenvalues at the optimum (`target = false`) or the partial shape's
/// spectrum (`target = true`) in one metric.
pub(crate) fn eigenvalues(loc: &Localization, metric: Metric, target: bool) -> &[f64] {
    match (metric, target) {
        (Metric::Regular, false) => &loc.eigenvalues_regular,
        (Metric::ScaleInvariant, false) => &loc.eigenvalues_si,
        (Metric::Regular, true) => &loc.target_regular,
        (Metric::ScaleInvariant, true) => &loc.target_si,
    }
}
