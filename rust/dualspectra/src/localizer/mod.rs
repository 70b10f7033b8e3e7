//! The localizer: find the region of a full mesh that a partial mesh is
//! (docs/algorithm.md, the whole pipeline).
//!
//! [`Localizer::new`] prepares what depends on the full shape alone, once: its scale, the
//! decimated optimisation mesh and its cells on the full shape, the transferred
//! scale-invariant factor, the SHOT descriptors, the plane-cut heights,
//! and one symbolic Cholesky analysis shared by every eigensolver; a second, finer
//! optimisation mesh for partials with holes is prepared the same way on the first such
//! partial (`stages::FINE_RESOLUTION_FACTOR`), and each optimisation mesh's coarser warm-up
//! mesh on the first start (`stages::WARM_UP_FRACTION`). [`Localizer::locate`] then runs the stages for one
//! partial (`stages.rs`); a `Localizer` is `Send + Sync`, so
//! several partials may be located concurrently. [`localize`] is the one-call form
//! (geometry-central's `HeatMethodDistanceSolver` beside `heatMethodDistance`). A prepared
//! shape is saved and loaded with [`Localizer::save`] / [`Localizer::load`] (`persist.rs`:
//! the versioned file format), so a library of full shapes is prepared once.

mod options;
pub(crate) mod persist;
mod result;
pub(crate) mod stages;

pub use crate::mesh::intake::HostNumbering;
pub use persist::EXTENSION;
pub use options::{option_spec, options_schema_json, Mode, OptionKind, OptionSpec, Options, Scale, MIN_RESOLUTION, OPTIONS, REMOVED_OPTIONS};
pub use result::{Candidate, CandidateScore, Localization, Timings};
pub(crate) use stages::{Effort, SharedPartial};

use crate::error::{Error, Result};
use crate::mesh::TriMesh;
use crate::progress::Progress;
use crate::shape::Shape;
use faer::Mat;
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// A full shape prepared for locating partials on it.
pub struct Localizer {
    options: Options,
    /// Vertices of the full mesh as given (the length of every per-vertex result).
    n_vertices: usize,
    /// $1/\sqrt{A_M}$: both shapes are scaled by it, so that the full shape has unit area and
    /// results do not depend on units.
    scale: f64,
    /// The full shape, scaled.
    full: TriMesh,
    /// Vertex neighbours of the full shape (the closing of regions).
    full_neighbors: Vec<Vec<u32>>,
    /// The optimisation mesh (the full shape decimated to about `resolution` vertices) and
    /// what the starts and the choice read from it.
    level: Arc<OptimisationMesh>,
    /// The finer optimisation mesh for partials with holes (`stages::FINE_RESOLUTION_FACTOR` x
    /// `resolution` vertices) and its preparation's notes, built on first use (and not saved:
    /// a loaded localizer builds the same one from the stored full shape).
    fine_level: Mutex<Option<(Arc<OptimisationMesh>, Vec<String>)>>,
    workers: rayon::ThreadPool,
    /// Notes shown with every result: the preparation's, and a loaded file's.
    warnings: Vec<String>,
    /// The preparation's notes (what [`Localizer::save`] keeps).
    prepared_warnings: Vec<String>,
    /// The caller's numbering of the full mesh's vertices ([`Localizer::set_host_numbering`]).
    host: Option<HostNumbering>,
    preparation_seconds: f64,
}

/// An optimisation mesh: a decimation of the full shape, its cells on the full shape, and
/// the data the starts and the choice read from it.
pub(crate) struct OptimisationMesh {
    /// The decimated full shape, with the scale-invariant factor transferred from the full
    /// resolution.
    coarse: Shape,
    /// Full-shape vertex each optimisation vertex came from.
    coarse_to_full: Vec<u32>,
    /// The optimisation-mesh cell of each full-shape vertex (its nearest optimisation vertex).
    cell_of_full: Vec<u32>,
    /// SHOT descriptors of the optimisation vertices, with their support at the data's
    /// resolution.
    coarse_descriptors: Mat<f64>,
    /// Heights of the optimisation vertices along each plane-cut direction.
    plane_heights: Vec<Vec<f64>>,
    /// A coarser mesh for the first iterations of every start, built on first use.
    warmup: std::sync::OnceLock<Option<WarmUpMesh>>,
}

/// A decimation of an optimisation mesh on which starts take their first iterations.
pub(crate) struct WarmUpMesh {
    shape: Shape,
    /// The optimisation-mesh vertex each warm-up vertex came from.
    to_level: Vec<u32>,
    /// The warm-up cell (nearest warm-up vertex) of each optimisation vertex.
    cell_of_level: Vec<u32>,
}

impl std::fmt::Debug for Localizer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Localizer")
            .field("n_vertices", &self.n_vertices)
            .field("optimisation_vertices", &self.level.coarse.n_vertices())
            .field("options", &self.options)
            .finish()
    }
}

impl Localizer {
    /// Prepare `full` for the given options (checked first).
    pub fn new(full: &TriMesh, options: &Options) -> Result<Self> {
        Self::with_progress(full, options, &Progress::none())
    }

    /// [`Localizer::new`], reporting progress and cancellable.
    pub fn with_progress(full: &TriMesh, options: &Options, progress: &Progress) -> Result<Self> {
        let t0 = Instant::now();
        options.validate()?;
        let workers = rayon::ThreadPoolBuilder::new()
            .num_threads(options.threads)
            .build()
            .map_err(|e| Error::Numerical(format!("thread pool: {e}")))?;
        let mut localizer = workers.install(|| stages::prepare(full, options, progress))?;
        localizer.workers = workers;
        localizer.preparation_seconds = t0.elapsed().as_secs_f64();
        Ok(localizer)
    }

    /// Locate `partial` on the prepared full shape. Documented behaviours on unusual input: a
    /// partial without boundary is rejected as [`Error::InvalidMesh`] with
    /// [`crate::MeshError::ClosedPartial`] (a closed surface has no Dirichlet spectrum to
    /// match), one without interior vertex with [`crate::MeshError::NoInteriorVertex`]; a
    /// partial larger than 1.1x the full shape's area is rejected; a disconnected partial is
    /// reduced to its largest connected component (a warning says so).
    pub fn locate(&self, partial: &TriMesh, progress: &Progress) -> Result<Localization> {
        self.locate_with_initial_regions(partial, &[], progress)
    }

    /// [`Localizer::locate`] with extra starts: each mask (one `bool` per vertex of the full
    /// mesh) is a guess of the region, started from as $w_0 = 2 - 4R_0$; such starts are
    /// labelled `given#i` in [`Localization::candidates`].
    pub(crate) fn locate_with_initial_regions(
        &self,
        partial: &TriMesh,
        initial_regions: &[Vec<bool>],
        progress: &Progress,
    ) -> Result<Localization> {
        for (i, r) in initial_regions.iter().enumerate() {
            if r.len() != self.n_vertices {
                return Err(Error::InvalidArgument(format!(
                    "initial region {i} has {} entries, the full mesh {} vertices",
                    r.len(),
                    self.n_vertices
                )));
            }
        }
        stages::locate(self, &SharedPartial::new(partial), initial_regions, Effort::of(&self.options), progress)
    }

    /// [`Localizer::locate`] with at most `effort`'s iterations and plane-cut starts, of a
    /// partial other localizations share (a search's):
    /// what they all need of it alone is prepared once ([`SharedPartial`]).
    pub(crate) fn locate_shared(&self, partial: &SharedPartial<'_>, effort: Effort, progress: &Progress) -> Result<Localization> {
        stages::locate(self, partial, &[], effort, progress)
    }

    /// The regions the optimisation starts from for `partial` (each start's partial-area
    /// set of lowest initial potential, carried to the full mesh as [`Localization::region`]
    /// is), labelled as in [`Localization::candidates`]: a diagnostic of the starts, without
    /// optimising.
    #[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
    pub(crate) fn start_regions(&self, partial: &TriMesh) -> Result<Vec<(String, Vec<bool>)>> {
        stages::start_regions(self, partial)
    }

    /// The factor `partial` is multiplied by to be in the full shape's units under the
    /// `scale` option (estimated with `auto`), without locating it: a diagnostic of the
    /// scale estimate.
    #[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab
    pub(crate) fn partial_factor(&self, partial: &TriMesh) -> Result<f64> {
        self.workers.install(|| stages::partial_in_full_units(self, &SharedPartial::new(partial))).map(|(_, factor, _)| factor)
    }

    /// The options it was prepared with.
    pub fn options(&self) -> &Options {
        &self.options
    }

    /// Vertices of the full mesh.
    pub fn n_vertices(&self) -> usize {
        self.n_vertices
    }

    /// Vertices of the optimisation mesh.
    pub fn optimisation_vertices(&self) -> usize {
        self.level.coarse.n_vertices()
    }

    /// For each optimisation vertex, the full-mesh vertex it is (the decimation keeps a
    /// subset of the full mesh's vertices; increasing).
    #[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
    pub(crate) fn optimisation_vertex_origins(&self) -> &[u32] {
        &self.level.coarse_to_full
    }

    /// Notes on the preparation (e.g. a decimation that failed), repeated in every result.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Seconds [`Localizer::new`] took (for a loaded shape: [`Localizer::load`]).
    pub fn preparation_seconds(&self) -> f64 {
        self.preparation_seconds
    }

    /// Take partials in `scale`'s units from now on (the `scale` option is about the partial,
    /// not part of what was prepared), e.g. a library prepared once and searched with partials
    /// in other units.
    pub fn set_scale(&mut self, scale: Scale) -> Result<()> {
        let mut options = self.options.clone();
        options.scale = scale;
        options.validate()?;
        self.options = options;
        Ok(())
    }

    /// Run on `threads` worker threads from now on (0: all cores), e.g. a shape prepared on
    /// another machine (the thread count is not part of what was prepared).
    pub fn set_threads(&mut self, threads: usize) -> Result<()> {
        let mut options = self.options.clone();
        options.threads = threads;
        options.validate()?;
        self.workers = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| Error::Numerical(format!("thread pool: {e}")))?;
        self.options = options;
        Ok(())
    }
}

/// Find the region of `full` that `partial` corresponds to: [`Localizer::new`] then
/// [`Localizer::locate`].
///
/// ```
/// use dualspectra::evaluation::synthetic::{synthetic_pair, SyntheticParams};
/// use dualspectra::{localize, Options, Progress};
/// # fn main() -> dualspectra::Result<()> {
/// // A figure with limbs, and a part cut off a posed copy of it.
/// let pair = synthetic_pair(&SyntheticParams { level: 3, ..SyntheticParams::default() })?;
/// let options = Options { k: 8, max_iterations: 10, ..Options::default() };
/// let found = localize(&pair.full, &pair.partial, &options, &Progress::none())?;
/// assert_eq!(found.region.len(), pair.full.n_vertices());
/// assert!(found.region.iter().any(|&inside| inside));
/// # Ok(()) }
/// ```
pub fn localize(full: &TriMesh, partial: &TriMesh, options: &Options, progress: &Progress) -> Result<Localization> {
    localize_with_initial_regions(full, partial, options, &[], progress)
}

/// [`localize`] with extra starts (see [`Localizer::locate_with_initial_regions`]).
pub(crate) fn localize_with_initial_regions(
    full: &TriMesh,
    partial: &TriMesh,
    options: &Options,
    initial_regions: &[Vec<bool>],
    progress: &Progress,
) -> Result<Localization> {
    let localizer = Localizer::with_progress(full, options, &progress.sub(0.0, 0.05))?;
    let mut result = localizer.locate_with_initial_regions(partial, initial_regions, &progress.sub(0.05, 1.0))?;
    result.timings.preparation = localizer.preparation_seconds;
    result.timings.total += localizer.preparation_seconds;
    Ok(result)
}

// Compile-time check: a prepared shape may be shared between threads.
const _: fn() = || {
    fn send_sync<T: Send + Sync>() {}
    send_sync::<Localizer>();
};
