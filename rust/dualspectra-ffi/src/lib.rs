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
//! Both share the (crate-private) types of this module: `HostMesh` (a mesh with the map back
//! to the host's vertex numbering, when it came through the core's
//! [`MeshIntake`]), `HostLocalizer` (the core's [`Localizer`] with the full mesh's map; saved
//! and loaded with it), the search over several of them, and the conversion of results to the
//! host's numbering.
//!
//! Built as `staticlib` (what CMake imports), `cdylib` and `rlib` (for the Rust tests).

pub mod c_abi;
pub mod cxx_bridge;

use dualspectra::localizer::HostNumbering;
use dualspectra::mesh::intake::MeshIntake;
use dualspectra::shape::{Metric, Shape};
use dualspectra::{Error, Localization, Localizer, Match, Options, Progress, TriMesh};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A mesh handle's payload: the core's [`Shape`] (the mesh with its operators cached on first
/// use, so repeated curvature/spectrum queries on one handle do not recompute them) and, for a
/// mesh taken in from a host's arrays, the intake's map back to the host's vertices.
///
/// Every per-vertex array in or out of a `HostMesh` is in the host's numbering, of length
/// [`HostMesh::n_vertices`]; vertices the intake left out get a fill value (0, `false`).
pub(crate) struct HostMesh {
    shape: Shape,
    /// `None`: a strict mesh (the host's numbering is the mesh's).
    intake: Option<Arc<MeshIntake>>,
    /// The intake's map back to the host's vertices (`None` with `intake`).
    numbering: Option<Arc<HostNumbering>>,
}

impl HostMesh {
    /// A mesh checked strictly ([`TriMesh::from_flat`]).
    pub(crate) fn strict(xyz: &[f64], tri: &[u32]) -> Result<Self, Error> {
        Ok(HostMesh { shape: Shape::new(TriMesh::from_flat(xyz, tri)?), intake: None, numbering: None })
    }

    /// A host's arrays through the core intake ([`MeshIntake::from_flat`]): degenerate faces and
    /// vertices in no face are left out, non-manifold edges and vertices split, results come
    /// back in the host's numbering.
    pub(crate) fn from_host(xyz: &[f64], tri: &[u32]) -> Result<Self, Error> {
        let intake = MeshIntake::from_flat(xyz, tri)?;
        let numbering = Some(Arc::new(intake.host_numbering()));
        Ok(HostMesh { shape: Shape::new(intake.mesh.clone()), intake: Some(Arc::new(intake)), numbering })
    }

    /// The mesh the core works on.
    pub(crate) fn mesh(&self) -> &TriMesh {
        self.shape.mesh()
    }

    /// Vertices in the host's numbering: the length of every per-vertex array.
    pub(crate) fn n_vertices(&self) -> usize {
        self.intake.as_ref().map_or(self.mesh().n_vertices(), |i| i.n_host_vertices)
    }

    /// Host index of each vertex of [`HostMesh::mesh`]: the used host vertices, increasing, then
    /// the copies of split non-manifold vertices (each its host vertex's index).
    pub(crate) fn used_vertices(&self) -> Vec<u32> {
        match &self.intake {
            Some(i) => i.kept.clone(),
            None => (0..self.mesh().n_vertices() as u32).collect(),
        }
    }

    /// The map of this mesh's results to the host's numbering.
    pub(crate) fn host_map(&self) -> HostMap {
        HostMap { numbering: self.numbering.clone(), intake: self.intake.clone() }
    }

    /// Amounts at the host's indices, summed over a split vertex's copies
    /// ([`MeshIntake::to_host_sum`]).
    fn to_host_sum(&self, values: Vec<f64>) -> Vec<f64> {
        match &self.intake {
            Some(i) => i.to_host_sum(&values),
            None => values,
        }
    }

    /// Cotangent stiffness $W$ (cached), on the mesh's own vertices.
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

/// How per-vertex results of one mesh go back to its host's numbering (cheap to clone: the
/// map is shared): the core's [`HostNumbering`] (`None`: the host's numbering is the mesh's),
/// and the intake whose note it carries (`None` for a strict mesh or a loaded shape, whose
/// file keeps the numbering but not the note). The mapping rules are the core's.
#[derive(Clone, Default)]
pub(crate) struct HostMap {
    numbering: Option<Arc<HostNumbering>>,
    intake: Option<Arc<MeshIntake>>,
}

impl HostMap {
    /// `values` (one per mesh vertex) at the host's indices; `fill` at left-out vertices; a
    /// split host vertex takes its first copy's value ([`HostNumbering::values_to_host`]).
    pub(crate) fn to_host<T: Clone>(&self, values: Vec<T>, fill: T) -> Vec<T> {
        match &self.numbering {
            None => values,
            Some(h) => h.values_to_host(&values, fill),
        }
    }

    /// A localization in the host's numbering ([`Localization::to_host`]).
    fn localization_to_host(&self, loc: Localization) -> Localization {
        match &self.numbering {
            None => loc,
            Some(h) => loc.to_host(h),
        }
    }

    /// Vertices in the host's numbering, for a mesh of `n_mesh` vertices.
    pub(crate) fn n_vertices(&self, n_mesh: usize) -> usize {
        self.numbering.as_ref().map_or(n_mesh, |h| h.n_host_vertices)
    }

    /// What the intake left out, as a sentence about `what` ("full mesh").
    pub(crate) fn warning(&self, what: &str) -> Option<String> {
        self.intake.as_ref().and_then(|i| i.warning(what))
    }
}

/// A prepared full shape ([`Localizer`]) with the map of its results to the host's numbering
/// and the intake's note about the full mesh. `Send + Sync`: partials may be located from
/// several threads at once.
pub(crate) struct HostLocalizer {
    localizer: Localizer,
    full: HostMap,
}

impl HostLocalizer {
    /// Prepare `full`; the core localizer keeps the host's numbering, so that a saved shape
    /// loads with it ([`HostLocalizer::load`]).
    pub(crate) fn new(full: &HostMesh, options: &Options, progress: &Progress) -> Result<Self, Error> {
        let mut localizer = Localizer::with_progress(full.mesh(), options, progress)?;
        localizer.set_host_numbering(full.numbering.as_deref().cloned())?;
        Ok(HostLocalizer { localizer, full: full.host_map() })
    }

    /// A prepared shape saved by [`HostLocalizer::save`] (or `dualspectra prepare`), with the
    /// host numbering it was saved with ([`Localizer::load`]: a foreign, stale or damaged file
    /// is an [`Error::PreparedShape`]).
    pub(crate) fn load(path: &Path) -> Result<Self, Error> {
        let localizer = Localizer::load(path)?;
        let full = HostMap { numbering: localizer.host_numbering().cloned().map(Arc::new), intake: None };
        Ok(HostLocalizer { localizer, full })
    }

    /// Write the prepared shape, with the host's numbering, to `path` ([`Localizer::save`]).
    pub(crate) fn save(&self, path: &Path) -> Result<(), Error> {
        self.localizer.save(path)
    }

    /// Locate `partial`; the result in the host's numbering of the full mesh.
    pub(crate) fn locate(&self, partial: &HostMesh, progress: &Progress) -> Result<Localization, Error> {
        let loc = self.localizer.locate(partial.mesh(), progress)?;
        Ok(to_host(loc, &self.full, &partial.host_map()))
    }

    pub(crate) fn localizer(&self) -> &Localizer {
        &self.localizer
    }

    /// Vertices of the full mesh in the host's numbering.
    pub(crate) fn n_vertices(&self) -> usize {
        self.full.n_vertices(self.localizer.n_vertices())
    }

    /// The intake's note on the full mesh, then the preparation's notes.
    pub(crate) fn warnings(&self) -> Vec<String> {
        self.full.warning("full mesh").into_iter().chain(self.localizer.warnings().iter().cloned()).collect()
    }
}

/// Rank the prepared full shapes for `partial` ([`dualspectra::search()`]): the `top` best
/// matches, best first, each localization in the host's numbering of its full mesh; `top`
/// 0 is refused (it would compute everything to keep nothing). With `shortlist` below the
/// number of shapes, they are screened first ([`dualspectra::search_screened`], with the
/// first shape's `scale` option) and only the `shortlist` best are localized.
pub(crate) fn search(partial: &HostMesh, fulls: &[&HostLocalizer], top: usize, shortlist: usize, progress: &Progress) -> Result<Vec<Match>, Error> {
    if top == 0 {
        return Err(Error::InvalidArgument("top is 0: keep at least one match (the number of shapes or more keeps all)".into()));
    }
    if shortlist == 0 {
        return Err(Error::InvalidArgument("shortlist is 0: localize at least one shape (the number of shapes or more localizes all)".into()));
    }
    let cores: Vec<&Localizer> = fulls.iter().map(|f| &f.localizer).collect();
    let mut found = dualspectra::search_shortlisted(partial.mesh(), &cores, top, shortlist, progress)?;
    let partial_map = partial.host_map();
    for m in &mut found {
        m.localization = m.localization.take().map(|loc| to_host(loc, &fulls[m.index].full, &partial_map));
    }
    Ok(found)
}

/// Find the region of `full` that `partial` is, in one call ([`dualspectra::localize`]); the
/// result in the host's numbering of the full mesh.
pub(crate) fn localize(full: &HostMesh, partial: &HostMesh, options: &Options, progress: &Progress) -> Result<Localization, Error> {
    let loc = dualspectra::localize(full.mesh(), partial.mesh(), options, progress)?;
    Ok(to_host(loc, &full.host_map(), &partial.host_map()))
}

/// A result in the host's numbering of the full mesh ([`Localization::to_host`]), with the
/// intakes' notes first among its warnings.
fn to_host(loc: Localization, full: &HostMap, partial: &HostMap) -> Localization {
    let mut loc = full.localization_to_host(loc);
    let notes = full.warning("full mesh").into_iter().chain(partial.warning("partial mesh"));
    loc.warnings = notes.chain(std::mem::take(&mut loc.warnings)).collect();
    loc
}

/// Map a core error to a C status code.
pub(crate) fn status_of(e: &Error) -> c_abi::ds_status {
    #[allow(unreachable_patterns)]
    match e {
        Error::Io { .. } | Error::Parse { .. } => c_abi::DS_IO,
        Error::InvalidMeshFile { .. } | Error::InvalidMesh(_) => c_abi::DS_INVALID_MESH,
        Error::InvalidArgument(_) => c_abi::DS_INVALID_ARGUMENT,
        Error::PreparedShape { .. } => c_abi::DS_INVALID_PREPARED_SHAPE,
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

/// Set the options of a JSON object (`{"k": 10, "mode": "lbo"}`) on top of `options`: all or
/// none (an unknown name or a value out of range leaves `options` unchanged and names it).
pub(crate) fn set_json(options: &mut Options, json: &str) -> Result<(), Error> {
    let value: serde_json::Value =
        serde_json::from_str(json).map_err(|e| Error::InvalidArgument(format!("options are not valid JSON: {e}")))?;
    let object = value
        .as_object()
        .ok_or_else(|| Error::InvalidArgument("options must be a JSON object of name: value".into()))?;
    let mut updated = options.clone();
    for (name, v) in object {
        updated.set(name, v.clone())?;
    }
    updated.validate()?;
    *options = updated;
    Ok(())
}

/// Set one option from text ([`Options::set_str`]) or a JSON value ([`Options::set`]), checked
/// together with the others ([`Options::validate`]); `options` unchanged on error.
pub(crate) fn set_option(options: &mut Options, name: &str, value: serde_json::Value) -> Result<(), Error> {
    let mut updated = options.clone();
    match value {
        serde_json::Value::String(text) => updated.set_str(name, &text)?,
        v => updated.set(name, v)?,
    }
    updated.validate()?;
    *options = updated;
    Ok(())
}

/// A path from the bytes of its name (`what` names it in errors): any bytes on Unix, as the
/// file system takes them; UTF-8 elsewhere. Empty is refused.
pub(crate) fn path_of(bytes: &[u8], what: &str) -> Result<PathBuf, Error> {
    if bytes.is_empty() {
        return Err(Error::InvalidArgument(format!("{what} is empty")));
    }
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt;
        Ok(PathBuf::from(std::ffi::OsStr::from_bytes(bytes)))
    }
    #[cfg(not(unix))]
    {
        std::str::from_utf8(bytes).map(PathBuf::from).map_err(|_| Error::InvalidArgument(format!("{what} is not valid UTF-8")))
    }
}

/// `major * 10000 + minor * 100 + patch` of this crate.
pub(crate) fn version_number() -> u32 {
    let mut parts = env!("CARGO_PKG_VERSION").split(['.', '-']).map(|p| p.parse::<u32>().unwrap_or(0));
    let (a, b, c) = (parts.next().unwrap_or(0), parts.next().unwrap_or(0), parts.next().unwrap_or(0));
    a * 10000 + b * 100 + c
}

/// Pointwise (angle-defect) Gaussian curvature, raw or one-ring smoothed (cached by the core),
/// in the host's numbering (0 at left-out vertices; a split vertex's first copy's).
pub(crate) fn gaussian_curvature(mesh: &HostMesh, smoothed: bool) -> Vec<f64> {
    let k = if smoothed { mesh.shape.smoothed_curvature() } else { mesh.shape.gaussian_curvature() };
    mesh.host_map().to_host(k.to_vec(), 0.0)
}

/// The `k` smallest Dirichlet eigenvalues in `metric` ([`Shape::dirichlet_spectrum`]); a
/// scale-invariant spectrum with an `alpha` other than the handle's default uses a fresh
/// [`Shape`] with that exponent.
pub(crate) fn spectrum(mesh: &HostMesh, k: usize, metric: Metric, alpha: f64) -> Result<Vec<f64>, Error> {
    mesh.with_metric(metric, alpha, |s| Ok(s.dirichlet_spectrum(metric, k)?.values))
}

/// Mass diagonal of `metric` ([`Shape::metric_mass`]) in the host's numbering (0 at left-out
/// vertices; a split vertex's copies summed, so the total is the mesh's).
pub(crate) fn mass(mesh: &HostMesh, metric: Metric, alpha: f64) -> Result<Vec<f64>, Error> {
    let m = mesh.with_metric(metric, alpha, |s| Ok(s.metric_mass(metric).to_vec()))?;
    Ok(mesh.to_host_sum(m))
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
