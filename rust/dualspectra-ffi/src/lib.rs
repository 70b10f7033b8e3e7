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

use dualspectra::{Error, Localization, Mode, Options, Progress, TriMesh};

/// Spectrum metric, shared by both interfaces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Metric {
    Regular,
    ScaleInvariant,
}

/// A mesh handle's payload: the validated mesh (per-mesh operators are cached by the core).
pub(crate) struct ShapeCache {
    mesh: TriMesh,
}

impl ShapeCache {
    pub(crate) fn new(mesh: TriMesh) -> Self {
        ShapeCache { mesh }
    }
    pub(crate) fn mesh(&self) -> &TriMesh {
        &self.mesh
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

/// Check the options every interface accepts: k >= 1, finite alpha.
pub(crate) fn checked_options(mode: Mode, k: usize, alpha: f64, seed: u64) -> Result<Options, Error> {
    if k == 0 {
        return Err(Error::InvalidArgument("k must be at least 1".into()));
    }
    if !alpha.is_finite() {
        return Err(Error::InvalidArgument(format!("alpha must be finite, got {alpha}")));
    }
    #[allow(clippy::needless_update)]
    Ok(Options { mode, k, alpha, seed, ..Options::default() })
}

pub(crate) fn options_from_c(o: &c_abi::ds_options) -> Result<Options, Error> {
    checked_options(mode_from_code(o.mode)?, o.k, o.alpha, o.seed)
}

pub(crate) fn options_to_c(o: &Options) -> c_abi::ds_options {
    c_abi::ds_options { mode: mode_code(o.mode), k: o.k, alpha: o.alpha, seed: o.seed }
}

/// `major * 10000 + minor * 100 + patch` of this crate.
pub(crate) fn version_number() -> u32 {
    let mut parts = env!("CARGO_PKG_VERSION").split(['.', '-']).map(|p| p.parse::<u32>().unwrap_or(0));
    let (a, b, c) = (parts.next().unwrap_or(0), parts.next().unwrap_or(0), parts.next().unwrap_or(0));
    a * 10000 + b * 100 + c
}

pub(crate) fn gaussian_curvature(shape: &ShapeCache, smoothed: bool) -> Vec<f64> {
    if smoothed {
        dualspectra::geometry::smoothed_gaussian_curvature(shape.mesh())
    } else {
        dualspectra::geometry::gaussian_curvature(shape.mesh())
    }
}

pub(crate) fn spectrum(shape: &ShapeCache, k: usize, metric: Metric, alpha: f64) -> Result<Vec<f64>, Error> {
    if k == 0 {
        return Err(Error::InvalidArgument("k must be at least 1".into()));
    }
    if !alpha.is_finite() {
        return Err(Error::InvalidArgument(format!("alpha must be finite, got {alpha}")));
    }
    let _ = (shape, metric);
    Err(Error::Numerical("spectrum: the core's eigensolver is not available yet".into()))
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
