//! The localizer's stages, in order (docs/algorithm.md): prepare the full shape (once per
//! [`Localizer`]), then for each partial: target, starts, runs, candidates, scores, choice,
//! result. [`locate`] reads as that list.

use super::{Candidate, Localization, Localizer, OptimisationMesh, Options, Scale, Timings};
use crate::alignment::cost::{potential_from_w, AlignmentCost, SpectrumTerm};
use crate::alignment::scale::ScaleScan;
use crate::alignment::starts::{self, Start};
use crate::alignment::trust_region::{minimize, HessianOperator, Point, TrustRegionInfo, TrustRegionParams};
use crate::error::{Error, MeshError, Result};
use crate::geometry::shot;
use crate::mesh::TriMesh;
use crate::progress::Progress;
use crate::region::energy::{area_matched_region, eigenvector_energy};
use crate::selection::{self, CandidateScore};
use crate::shape::{Metric, Shape};
use crate::spectra::Spectrum;
use faer::Mat;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// Step height of the relaxed potential: $v \in [0, 2c]$ with $2c = 50\,\mu_k$
/// (docs/algorithm.md, "Relaxation"), one height per spectrum on one shared $w$.
pub const STEP_HEIGHT_FACTOR: f64 = 50.0;

/// Partials with more vertices are decimated to about this many (quadric collapse, the
/// boundary kept vertex for vertex) before their spectra and descriptors: dense scans
/// (PFARM: up to 27k vertices) then cost what a SHREC'16 partial costs. The low
/// Dirichlet eigenvalues the method matches change little under this coarsening
/// (docs/benchmarks/options.md, "Partials above 12,000 vertices"); every SHREC'16 partial is below it.
pub const MAX_PARTIAL_VERTICES: usize = 12_000;

/// Eigensolver tolerance of the partial's spectra (the targets): a cold solve to a relative
/// residual of $10^{-4}$, which puts the eigenvalues within about $10^{-10}$ of the
/// default's $10^{-8}$ (an eigenvalue's error is of the order of the residual squared) at 10
/// block iterations instead of 16 (docs/benchmarks/options.md, "Where the time goes").
pub const PARTIAL_EIGEN_TOLERANCE: f64 = 1e-6;

/// A partial of less than this fraction of the full shape's area is warned about: it is likely
/// in other units (`scale = auto`), and too small to place reliably if it is not.
pub const SMALLEST_AREA_FRACTION: f64 = 1e-3;

/// Partials with holes are optimised on a mesh this many times finer than `resolution`
/// (docs/benchmarks/options.md, "Finer mesh for partials with holes").
pub const FINE_RESOLUTION_FACTOR: usize = 2;

/// Every start takes its first iterations on a decimation of the optimisation mesh to this
/// fraction of its vertices, and the rest on the optimisation mesh (docs/benchmarks/options.md,
/// "Warm-up on a coarser mesh").
pub const WARM_UP_FRACTION: f64 = 0.5;

/// Eigensolver tolerance on the warm-up mesh (warm solves to a relative residual of
/// $10^{-2}$, against $10^{-3}$ at [`crate::alignment::cost::EIGEN_TOLERANCE`]): the warm-up
/// only brings $w$ near an optimum the optimisation mesh then refines
/// (docs/benchmarks/options.md, "Warm-up on a coarser mesh").
pub const WARM_UP_EIGEN_TOLERANCE: f64 = 1e-6;

/// The share of `max_iterations` taken on the warm-up mesh (rounded down; at least one
/// iteration is left for the optimisation mesh).
pub const WARM_UP_SHARE: f64 = 0.8;

/// A partial has holes when the rims of its boundary curves other than the longest add up
/// to at least this fraction of $\sqrt{A_N}$ (docs/benchmarks/options.md, "Finer mesh for
/// partials with holes").
pub const HOLE_RIM_FRACTION: f64 = 1.0;

/// Whether `partial` has holes (other boundary curves than its outer rim, long enough):
/// holes of a few coarse edges' size are what the default optimisation mesh cannot draw.
fn has_holes(partial: &TriMesh) -> bool {
    let rims: f64 = crate::mesh::topology::boundary_curve_lengths(partial).iter().skip(1).sum();
    rims >= HOLE_RIM_FRACTION * partial.area().sqrt()
}

/// A vertex mask on the optimisation (coarse) mesh.
#[derive(Debug, Clone, PartialEq)]
struct CoarseMask(Vec<bool>);

/// A vertex mask on the full mesh.
#[derive(Debug, Clone, PartialEq)]
struct FullMask(Vec<bool>);

impl OptimisationMesh {
    /// A full-shape mask read at the vertex each optimisation vertex came from.
    fn to_coarse(&self, mask: &[bool]) -> CoarseMask {
        CoarseMask(self.coarse_to_full.iter().map(|&j| mask[j as usize]).collect())
    }
}

impl Localizer {
    /// The optimisation mesh for a partial and notes on it: the finer one for a partial with
    /// holes (built on first use), else the prepared one.
    fn level_for(&self, has_holes: bool, progress: &Progress) -> Result<(Arc<OptimisationMesh>, Vec<String>)> {
        // A prepared mesh that is the full shape itself (resolution 0 or above the vertex
        // count, or a failed decimation) has nothing finer.
        if self.level.coarse.n_vertices() >= self.full.n_vertices() || !has_holes {
            return Ok((self.level.clone(), Vec::new()));
        }
        // Held while the finer mesh is built: concurrent partials with holes wait for it, and a
        // cancelled or failed build leaves it unset for the next one.
        let mut fine = self.fine_level.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some(built) = fine.as_ref() {
            return Ok(built.clone());
        }
        progress.report(0.0, "preparing the finer optimisation mesh")?;
        let mut notes = Vec::new();
        let cancel = Progress::none().with_cancel_flag(progress.cancel_flag());
        let fine_resolution = self.options.resolution.saturating_mul(FINE_RESOLUTION_FACTOR);
        let level = self.workers.install(|| prepare_level(&self.full, fine_resolution, &self.options, &mut notes, &cancel))?;
        let built = (Arc::new(level), notes);
        *fine = Some(built.clone());
        Ok(built)
    }

    /// A coarse mask spread over each optimisation vertex's cell on the full shape, then
    /// closed ([`crate::region::CLOSING_RINGS`] rings).
    fn to_full(&self, level: &OptimisationMesh, mask: &CoarseMask) -> Result<FullMask> {
        let spread: Vec<bool> = level.cell_of_full.iter().map(|&j| mask.0[j as usize]).collect();
        Ok(FullMask(crate::region::closing::close(&spread, &self.full_neighbors, crate::region::CLOSING_RINGS)?))
    }
}

/// Everything that depends on the full shape alone ([`Localizer::new`]). Runs on the
/// localizer's pool; the caller sets `workers` and the timing.
pub(super) fn prepare(full: &TriMesh, options: &Options, progress: &Progress) -> Result<Localizer> {
    progress.report(0.0, "preparing")?;
    let mut warnings = Vec::new();
    let scale = 1.0 / full.area().sqrt();
    let full_n = full.map_positions(|p| p.map(|c| c * scale))?;
    let level = prepare_level(&full_n, options.resolution, options, &mut warnings, &progress.sub(0.0, 0.95))?;
    let full_neighbors = crate::mesh::topology::vertex_neighbors(&full_n);
    progress.report(1.0, "prepared")?;
    Ok(Localizer {
        options: options.clone(),
        n_vertices: full.n_vertices(),
        scale,
        full: full_n,
        full_neighbors,
        level: Arc::new(level),
        fine_level: Mutex::new(None),
        workers: rayon::ThreadPoolBuilder::new().num_threads(1).build().map_err(|e| Error::Numerical(e.to_string()))?,
        prepared_warnings: warnings.clone(),
        warnings,
        host: None,
        preparation_seconds: 0.0,
    })
}

/// The optimisation mesh of about `resolution` vertices (0 or more than the full shape's:
/// the full shape itself) and its start data. A failed decimation falls back to the full
/// shape with a warning.
fn prepare_level(
    full_n: &TriMesh,
    resolution: usize,
    options: &Options,
    warnings: &mut Vec<String>,
    progress: &Progress,
) -> Result<OptimisationMesh> {
    let decimated = if resolution > 0 && resolution < full_n.n_vertices() {
        let ratio = resolution as f64 / full_n.n_vertices() as f64;
        match crate::mesh::decimate::decimate(full_n, ratio) {
            Ok(d) => Some((d.mesh, d.original_vertex)),
            Err(e) => {
                warnings.push(format!("decimation failed ({e}); optimising on the full-resolution shape"));
                None
            }
        }
    } else {
        None
    };
    let (coarse_mesh, coarse_to_full) = decimated.unwrap_or_else(|| {
        let n = full_n.n_vertices() as u32;
        (full_n.clone(), (0..n).collect())
    });
    progress.check()?;
    let cell_of_full = crate::mesh::nearest::nearest_vertices(coarse_mesh.vertices(), full_n.vertices())?;
    let coarse = coarse_shape(coarse_mesh, full_n, &coarse_to_full, &cell_of_full, options.alpha)?;
    // Warm the caches every locate reads (operators, both masses, the symbolic analysis).
    coarse.dirichlet_symbolic()?;
    coarse.metric_mass(Metric::ScaleInvariant);
    progress.report(0.4, "descriptors")?;
    let (radius, min_nb) = (shot::DEFAULT_RADIUS_FRACTION, shot::DEFAULT_MIN_NEIGHBORS);
    let coarse_descriptors = if coarse.n_vertices() < full_n.n_vertices() {
        // The optimisation vertices described with their support at the data's resolution,
        // as the partial's are.
        shot::shot_keypoint_descriptors(full_n, &coarse_to_full, radius, min_nb)?
    } else {
        shot::shot_descriptors(coarse.mesh(), radius, min_nb)?
    };
    progress.report(0.9, "starts")?;
    let points = coarse.mesh().vertices();
    let plane_heights = starts::plane_heights(points, coarse.mass(), options.plane_cuts);
    Ok(OptimisationMesh { coarse, coarse_to_full, cell_of_full, coarse_descriptors, plane_heights, warmup: Default::default() })
}

/// The warm-up mesh of `level`: its optimisation mesh decimated to [`WARM_UP_FRACTION`] of its
/// vertices, the scale-invariant factor integrated over the cells (as the optimisation mesh's
/// is from the full shape). `None` (no warm-up) below `2 x MIN_RESOLUTION` vertices or where
/// the decimation fails.
fn warmup_mesh(level: &OptimisationMesh) -> Option<super::WarmUpMesh> {
    let mesh = level.coarse.mesh();
    let fraction = WARM_UP_FRACTION;
    if (mesh.n_vertices() as f64 * fraction) < super::MIN_RESOLUTION as f64 {
        return None;
    }
    let d = crate::mesh::decimate::decimate(mesh, fraction).ok()?;
    let cell_of_level = crate::mesh::nearest::nearest_vertices(d.mesh.vertices(), mesh.vertices()).ok()?;
    let (fine, alpha) = (&level.coarse, level.coarse.alpha());
    let shape = transferred_factor_shape(d.mesh, fine.scale_invariant_factor(), fine.mass(), &d.original_vertex, &cell_of_level, alpha).ok()?;
    shape.dirichlet_symbolic().ok()?;
    shape.metric_mass(Metric::ScaleInvariant);
    Some(super::WarmUpMesh { shape, to_level: d.original_vertex, cell_of_level })
}

impl super::WarmUpMesh {
    /// A function on the warm-up mesh's vertices carried to the optimisation mesh's (each
    /// vertex takes its cell's value).
    fn carry(&self, x: &[f64]) -> Vec<f64> {
        self.cell_of_level.iter().map(|&j| x[j as usize]).collect()
    }
}

/// The optimisation mesh as a [`Shape`]. When it is a decimation of `full`, its
/// scale-invariant factor is estimated at the data's resolution (as the partial's is) and
/// integrated over its cells (`cell_of_full[i]`: the cell of full vertex `i`;
/// [`crate::geometry::metric::transfer_factor`]; docs/benchmarks/options.md).
fn coarse_shape(coarse: TriMesh, full: &TriMesh, coarse_to_full: &[u32], cell_of_full: &[u32], alpha: f64) -> Result<Shape> {
    let eps = crate::geometry::metric::DEFAULT_EPS;
    if coarse.n_vertices() >= full.n_vertices() {
        return Ok(Shape::with_metric_params(coarse, alpha, eps));
    }
    let curvature = crate::geometry::smoothed_gaussian_curvature(full);
    let fine = crate::geometry::metric::scale_invariant_factor(&curvature, alpha, eps);
    let fine_mass = crate::operators::mass::lumped_mass(full);
    transferred_factor_shape(coarse, &fine, &fine_mass, coarse_to_full, cell_of_full, alpha)
}

/// `coarse` as a [`Shape`] whose scale-invariant factor is the finer mesh's `fine_factor`
/// integrated over the cells (`cell[i]`: the coarse vertex of fine vertex `i`; a coarse vertex
/// with an empty cell takes the factor of the fine vertex it came from, `origin`;
/// [`crate::geometry::metric::transfer_factor`]).
fn transferred_factor_shape(coarse: TriMesh, fine_factor: &[f64], fine_mass: &[f64], origin: &[u32], cell: &[u32], alpha: f64) -> Result<Shape> {
    let fallback: Vec<f64> = origin.iter().map(|&j| fine_factor[j as usize]).collect();
    let factor = crate::geometry::metric::transfer_factor(fine_factor, fine_mass, cell, &fallback);
    Shape::with_scale_invariant_factor(coarse, alpha, crate::geometry::metric::DEFAULT_EPS, factor)
}

/// The partial, scaled like the full shape, with its spectra and descriptors: what the
/// optimisation matches.
struct Target {
    shape: Shape,
    area: f64,
    /// The factor applied to the partial's coordinates ([`Options::scale`]).
    factor: f64,
    terms: Vec<SpectrumTerm>,
    /// The partial's Dirichlet spectrum of each term (its eigenfunctions also give the
    /// descriptor projections of the selection).
    spectra: Vec<Spectrum>,
    /// Its SHOT descriptors at up to [`starts::DESCRIPTOR_START_SAMPLES`] of its vertices,
    /// the ones the descriptor matches sample (each vertex represented by its nearest).
    descriptors: shot::SampledShot,
    /// Its descriptors' correspondences on the optimisation mesh (the descriptor starts and
    /// the vote share of the selection); `None` without descriptors.
    matches: Option<starts::DescriptorMatches>,
    /// Whether it has holes ([`has_holes`]): it is optimised on the finer mesh, and it is not
    /// a plane cut, so the plane-cut starts are left out.
    has_holes: bool,
    warnings: Vec<String>,
}

/// One optimised start.
struct Run {
    label: String,
    w: Vec<f64>,
    cost: f64,
    iterations: usize,
    evaluations: usize,
    /// The cost after each iteration.
    history: Vec<f64>,
    /// Eigenvalues per term at the optimum.
    eigenvalues: Vec<Vec<f64>>,
    /// Mean eigenvector energy per optimisation vertex at the optimum.
    energy: Vec<f64>,
    /// Each term's last eigensolver block at the optimum (free vertices): it starts the
    /// selection's solves of this run's region (taken from the run there).
    blocks: Vec<Option<Mat<f64>>>,
}

/// A run with its region on both meshes and its scores.
struct Scored {
    run: Run,
    full: FullMask,
    score: CandidateScore,
}

/// How much of the method a localization runs: trust-region iterations per start, plane-cut
/// starts, eigenvalues per spectrum (each at most the localizer's options), whether a
/// partial with holes is optimised on the finer mesh ([`FINE_RESOLUTION_FACTOR`]) and whether
/// a partial without holes gets its plane-cut starts beside its descriptor starts (otherwise
/// only when it has no descriptor start, as a partial with holes); [`Effort::of`] is all of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Effort {
    pub max_iterations: usize,
    pub plane_cuts: usize,
    pub k: usize,
    pub finer_mesh: bool,
    pub plane_cuts_beside_descriptors: bool,
}

impl Effort {
    /// What `options` ask for.
    pub(crate) fn of(options: &crate::localizer::Options) -> Effort {
        Effort { max_iterations: options.max_iterations, plane_cuts: options.plane_cuts, k: options.k, finer_mesh: true, plane_cuts_beside_descriptors: true }
    }

    /// The smaller of each.
    pub(crate) fn min(self, other: Effort) -> Effort {
        Effort {
            max_iterations: self.max_iterations.min(other.max_iterations),
            plane_cuts: self.plane_cuts.min(other.plane_cuts),
            k: self.k.min(other.k),
            finer_mesh: self.finer_mesh && other.finer_mesh,
            plane_cuts_beside_descriptors: self.plane_cuts_beside_descriptors && other.plane_cuts_beside_descriptors,
        }
    }
}

/// The stages for one partial, with `effort` (at most the localizer's options).
pub(super) fn locate(loc: &Localizer, partial: &SharedPartial<'_>, initial_regions: &[Vec<bool>], effort: Effort, progress: &Progress) -> Result<Localization> {
    let effort = effort.min(Effort::of(&loc.options));
    let clock = Clock::start();
    progress.report(0.0, "preprocessing")?;
    let (target, level, level_notes) = target_on_its_mesh(loc, partial, effort, progress)?;
    let t_pre = clock.lap();
    progress.report(0.05, "starts")?;
    let starts = starts_for(&level, &target, initial_regions, effort);
    if starts.is_empty() {
        return Err(Error::InvalidArgument("no starts (plane_cuts = 0, no initial region, and no descriptor start)".into()));
    }
    let t_starts = clock.lap();
    let (runs, failure) = optimise(loc, &level, &target, &starts, effort.max_iterations, &progress.sub(0.05, 0.9))?;
    let t_opt = clock.lap();
    progress.report(0.9, "regions")?;
    let candidates = regions(loc, &level, &target, runs)?;
    let t_region = clock.lap();
    progress.report(0.93, "selecting")?;
    let scored = loc.workers.install(|| score(loc, &level, &target, candidates))?;
    let scores: Vec<CandidateScore> = scored.iter().map(|c| c.score).collect();
    let choice = selection::choose(&scores).unwrap_or(0);
    let t_sel = clock.lap();
    progress.report(1.0, "done")?;
    let mut warnings = loc.warnings.clone();
    warnings.extend(level_notes);
    warnings.extend(target.warnings.iter().cloned());
    warnings.extend(failure);
    let timings = Timings {
        preparation: 0.0,
        preprocessing: t_pre,
        starts: t_starts,
        optimisation: t_opt,
        region: t_region,
        selection: t_sel,
        total: clock.total(),
    };
    Ok(result(loc, &level, &target, scored, choice, timings, warnings))
}

/// Each start's region for `partial`: the partial's area of lowest $w_0$ (a start's mask),
/// carried to the full shape, with its label:
/// what the optimisation begins from (a diagnostic; [`Localizer::start_regions`]).
#[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
pub(super) fn start_regions(loc: &Localizer, partial: &TriMesh) -> Result<Vec<(String, Vec<bool>)>> {
    let effort = Effort::of(&loc.options);
    let (target, level, _) = target_on_its_mesh(loc, &SharedPartial::new(partial), effort, &Progress::none())?;
    starts_for(&level, &target, &[], effort)
        .into_iter()
        .map(|s| {
            let low: Vec<f64> = s.w0.iter().map(|w| -w).collect();
            let coarse = crate::geometry::area_matched_set(&low, level.coarse.mass(), target.area);
            Ok((s.label, loc.to_full(&level, &CoarseMask(coarse))?.0))
        })
        .collect()
}

/// Stage 1 on the localizer's pool: the target and the optimisation mesh it chooses
/// ([`Localizer::level_for`]; the regular one when `effort` leaves out the finer mesh), with
/// the notes on that mesh: the target's descriptor matches are on that mesh.
fn target_on_its_mesh(loc: &Localizer, partial: &SharedPartial<'_>, effort: Effort, progress: &Progress) -> Result<(Target, Arc<OptimisationMesh>, Vec<String>)> {
    loc.workers.install(|| target(loc, partial, effort, progress))
}

/// A partial as the localizations of one search share it: with `scale = auto`, its largest
/// component at unit area, decimated above [`MAX_PARTIAL_VERTICES`], and its scale scan
/// ([`ScaleScan`]: the partial's descriptors under each area hypothesis), made by the first
/// localization that needs them and reused by the others.
pub(crate) struct SharedPartial<'a> {
    mesh: std::borrow::Cow<'a, TriMesh>,
    auto: std::sync::OnceLock<AutoPartial>,
}

/// The `scale = auto` preparation of a partial ([`SharedPartial`]).
struct AutoPartial {
    /// Scans the largest component times `unit`, decimated.
    scan: ScaleScan,
    /// $1/\sqrt{A}$ of the largest component.
    unit: f64,
    warnings: Vec<String>,
}

impl<'a> SharedPartial<'a> {
    /// `mesh`, nothing prepared yet.
    pub(crate) fn new(mesh: &'a TriMesh) -> Self {
        SharedPartial { mesh: std::borrow::Cow::Borrowed(mesh), auto: std::sync::OnceLock::new() }
    }

    /// `mesh`, kept: nothing prepared yet.
    pub(crate) fn owning(mesh: TriMesh) -> SharedPartial<'static> {
        SharedPartial { mesh: std::borrow::Cow::Owned(mesh), auto: std::sync::OnceLock::new() }
    }

    /// The partial as given.
    pub(crate) fn mesh(&self) -> &TriMesh {
        &self.mesh
    }

    /// The `scale = auto` preparation, made on first use.
    fn auto(&self) -> Result<&AutoPartial> {
        if let Some(a) = self.auto.get() {
            return Ok(a);
        }
        let (component, warnings) = largest_component_noted(&self.mesh)?;
        let area = component.area();
        if !(area > 0.0 && area.is_finite()) {
            return Err(Error::InvalidArgument("scale = auto: the partial has no area to estimate the scale from".into()));
        }
        let unit = 1.0 / area.sqrt();
        let scan = ScaleScan::new(decimated(component.map_positions(|p| p.map(|c| c * unit))?))?;
        Ok(self.auto.get_or_init(|| AutoPartial { scan, unit, warnings }))
    }
}

/// `partial`'s largest connected component, and a warning if that drops any of it.
fn largest_component_noted(partial: &TriMesh) -> Result<(TriMesh, Vec<String>)> {
    let (component, dropped) = largest_component(partial)?;
    let mut warnings = Vec::new();
    if dropped {
        warnings.push(format!(
            "the partial shape is disconnected: only its largest component ({} of {} vertices) is localized",
            component.n_vertices(),
            partial.n_vertices()
        ));
    }
    Ok((component, warnings))
}

/// `partial` decimated to about [`MAX_PARTIAL_VERTICES`] when it has more (as it is if the
/// collapse fails validation: slower, not worse).
fn decimated(partial: TriMesh) -> TriMesh {
    if partial.n_vertices() > MAX_PARTIAL_VERTICES {
        let fraction = MAX_PARTIAL_VERTICES as f64 / partial.n_vertices() as f64;
        if let Ok(coarser) = crate::mesh::decimate::decimate(&partial, fraction) {
            return coarser.mesh;
        }
    }
    partial
}

/// The partial's largest component in the units of the localizer's unit-area full shape
/// (the `scale` option applied or estimated), decimated above [`MAX_PARTIAL_VERTICES`]; the
/// factor the caller's partial was multiplied by (beside the full shape's own normalisation)
/// and the notes on the way.
pub(super) fn partial_in_full_units(loc: &Localizer, partial: &SharedPartial<'_>) -> Result<(TriMesh, f64, Vec<String>)> {
    let given_factor = match loc.options.scale {
        Scale::Factor(f) => f,
        Scale::Same => 1.0,
        Scale::Auto => {
            let auto = partial.auto()?;
            let (_, s) = auto.scan.estimate(&loc.level.coarse_descriptors, loc.level.coarse.mesh().vertices())?;
            let scaled = auto.scan.partial().map_positions(|p| p.map(|c| c * s))?;
            return Ok((scaled, auto.unit * s / loc.scale, auto.warnings.clone()));
        }
    };
    let (component, warnings) = largest_component_noted(&partial.mesh)?;
    let scaled = decimated(component.map_positions(|p| p.map(|c| c * loc.scale * given_factor))?);
    Ok((scaled, given_factor, warnings))
}

/// Stage 1: the partial's largest component, scaled; its Dirichlet spectra (`k` eigenvalues
/// each, split as the mode says), its descriptors and their matches on the optimisation mesh
/// it is optimised on (the finer one for a partial with holes, when `effort` allows).
fn target(loc: &Localizer, partial: &SharedPartial<'_>, effort: Effort, progress: &Progress) -> Result<(Target, Arc<OptimisationMesh>, Vec<String>)> {
    let options = &loc.options;
    let (scaled, factor, mut warnings) = partial_in_full_units(loc, partial)?;
    let area = scaled.area();
    let hint = match options.scale {
        Scale::Same => " (if the partial is in other units, use scale = auto or give the factor)",
        _ => "",
    };
    if area > 1.1 {
        return Err(MeshError::PartialLargerThanFull { ratio: area, hint }.into());
    }
    if area < SMALLEST_AREA_FRACTION {
        warnings.push(format!(
            "the partial shape's area is {area:.2e} of the full shape's: too small a part to place reliably{hint}"
        ));
    }
    let shape = Shape::with_metric_params(scaled, options.alpha, crate::geometry::metric::DEFAULT_EPS);
    if !shape.has_boundary() {
        return Err(MeshError::ClosedPartial.into());
    }
    if shape.dirichlet().n_free() == 0 {
        return Err(MeshError::NoInteriorVertex.into());
    }
    let has_holes = has_holes(shape.mesh());
    let (level, notes) = if effort.finer_mesh { loc.level_for(has_holes, progress)? } else { (loc.level.clone(), Vec::new()) };
    let (k_regular, k_si) = options.mode.counts(effort.k);
    let wanted: Vec<(Metric, usize)> = [(Metric::Regular, k_regular), (Metric::ScaleInvariant, k_si)].into_iter().filter(|&(_, k)| k > 0).collect();
    // The spectra (one single-threaded solve each) and the descriptors with their matches are
    // independent: they run side by side on the localizer's pool, each result the same as
    // alone.
    let (solved, described) = rayon::join(
        || {
            use rayon::prelude::*;
            wanted.par_iter().map(|&(metric, k)| shape.dirichlet_spectrum_to(metric, k, PARTIAL_EIGEN_TOLERANCE)).collect::<Result<Vec<Spectrum>>>()
        },
        || {
            let descriptors = shot::sampled_shot(shape.mesh(), starts::DESCRIPTOR_START_SAMPLES, shot::DEFAULT_RADIUS_FRACTION, shot::DEFAULT_MIN_NEIGHBORS)?;
            let full = starts::Described { descriptors: &level.coarse_descriptors, positions: level.coarse.mesh().vertices() };
            let positions = descriptors.positions(shape.mesh());
            let matches = starts::descriptor_matches(full, starts::Described { descriptors: &descriptors.descriptors, positions: &positions });
            Ok::<_, Error>((descriptors, matches))
        },
    );
    let (spectra, (descriptors, matches)) = (solved?, described?);
    let terms = wanted
        .iter()
        .zip(&spectra)
        .map(|(&(metric, _), spectrum)| {
            let values = spectrum.values.clone();
            let height = 0.5 * STEP_HEIGHT_FACTOR * values[values.len() - 1];
            SpectrumTerm { metric, target: values, height }
        })
        .collect();
    Ok((Target { shape, area, factor, terms, spectra, descriptors, matches, has_holes, warnings }, level, notes))
}

/// Stage 2: the starts. Given regions first, then the first `effort.plane_cuts` plane cuts
/// (not for a partial with holes, nor without `effort.plane_cuts_beside_descriptors`, unless
/// there is no descriptor start), then the two descriptor starts (the regions whose SHOT
/// descriptors the partial's resemble).
fn starts_for(level: &OptimisationMesh, target: &Target, initial_regions: &[Vec<bool>], effort: Effort) -> Vec<Start> {
    let mass = level.coarse.mass();
    let mut out: Vec<Start> = initial_regions
        .iter()
        .enumerate()
        .map(|(i, r)| starts::mask_start(&level.to_coarse(r).0, &format!("given#{i}")))
        .collect();
    let descriptor_starts = match &target.matches {
        Some(matches) => {
            let neighbors = crate::mesh::topology::vertex_neighbors(level.coarse.mesh());
            starts::descriptor_starts(matches, &neighbors, mass, target.area)
        }
        None => Vec::new(),
    };
    // A partial with holes is no plane cut: its plane starts added nothing but time
    // (docs/benchmarks/options.md, "Starts for each kind of partial"); they stay when there
    // is no descriptor start. A search's quick localizations leave them out the same way
    // (`plane_cuts_beside_descriptors` false: docs/benchmarks/options.md, "Two-stage search").
    // Beside descriptor starts, only the plane cut that holds the most descriptor votes is
    // optimised (docs/benchmarks/options.md, `plane_cuts`).
    if (!target.has_holes && effort.plane_cuts_beside_descriptors) || descriptor_starts.is_empty() {
        let heights = &level.plane_heights[..effort.plane_cuts.min(level.plane_heights.len())];
        out.extend(match &target.matches {
            Some(matches) if !descriptor_starts.is_empty() => {
                starts::most_voted_plane_cut_starts(heights, mass, target.area, &matches.votes, starts::PLANE_CUTS_OPTIMISED)
            }
            _ => starts::plane_cut_starts_from_heights(heights, mass, target.area),
        });
    }
    out.extend(descriptor_starts);
    out
}

/// Stage 3: every start optimised for `iterations` iterations (in parallel on the
/// localizer's pool, progress reported from this thread). A start that fails numerically is
/// dropped with a warning; all failing is an error.
fn optimise(loc: &Localizer, level: &OptimisationMesh, target: &Target, starts: &[Start], iterations: usize, progress: &Progress) -> Result<(Vec<Run>, Option<String>)> {
    use rayon::prelude::*;
    let done = AtomicUsize::new(0);
    let total = (starts.len() * iterations).max(1);
    let workers_progress = Progress::none().with_cancel_flag(progress.cancel_flag());
    let outcomes: Vec<Result<Run>> = std::thread::scope(|scope| {
        let handle = scope.spawn(|| {
            loc.workers.install(|| {
                starts
                    .par_iter()
                    .map(|s| optimise_start(level, &target.terms, s, iterations, &workers_progress, &done))
                    .collect()
            })
        });
        while !handle.is_finished() {
            std::thread::sleep(std::time::Duration::from_millis(50));
            let fraction = done.load(Ordering::Relaxed) as f64 / total as f64;
            if progress.report(fraction.min(1.0), "optimising").is_err() {
                workers_progress.cancel();
            }
        }
        handle.join().unwrap_or_else(|_| vec![Err(Error::Numerical("a worker thread panicked".into()))])
    });
    progress.check()?;
    let mut runs = Vec::with_capacity(outcomes.len());
    let mut first_error = None;
    for outcome in outcomes {
        match outcome {
            Ok(run) => runs.push(run),
            Err(Error::Cancelled) => return Err(Error::Cancelled),
            Err(e) => first_error = first_error.or(Some(e)),
        }
    }
    if runs.is_empty() {
        return Err(first_error.unwrap_or_else(|| Error::Numerical("no start converged".into())));
    }
    Ok((runs, first_error.map(|e| format!("some starts failed and were skipped: {e}"))))
}

/// `iterations` trust-region iterations from one start (the first [`WARM_UP_SHARE`] of them
/// on the warm-up mesh, if there is one; `w` carried to the optimisation mesh by cells), then
/// its spectra and eigenvector energy at the optimum.
fn optimise_start(level: &OptimisationMesh, terms: &[SpectrumTerm], start: &Start, iterations: usize, progress: &Progress, done: &AtomicUsize) -> Result<Run> {
    progress.check()?;
    let shape = &level.coarse;
    let warm_iterations = ((iterations as f64 * WARM_UP_SHARE) as usize).min(iterations.saturating_sub(1));
    let warm_up = if warm_iterations > 0 { level.warmup.get_or_init(|| warmup_mesh(level)).as_ref() } else { None };
    let mut w0 = start.w0.clone();
    let (mut history, mut evaluations, mut offset) = (Vec::new(), 0, 0);
    let mut cost = AlignmentCost::new(shape, terms.to_vec())?;
    if let Some(warm) = warm_up {
        let w_warm = warm.to_level.iter().map(|&j| w0[j as usize]).collect();
        let mut warm_cost = AlignmentCost::with_tolerance(&warm.shape, terms.to_vec(), WARM_UP_EIGEN_TOLERANCE)?;
        let (w, info) = trust_region(&mut warm_cost, w_warm, warm_iterations, progress, done)?;
        w0 = warm.carry(&w);
        // The warm-up's eigenvectors, carried over, start the first solves (not cold ones).
        cost.seed(warm_cost.carried_blocks(|x| warm.carry(x)))?;
        (history, evaluations, offset) = (info.history, warm_cost.evaluations, info.iterations);
    }
    let (w, info) = trust_region(&mut cost, w0, iterations - offset, progress, done)?;
    history.extend(info.history);
    let last_iteration = offset + info.iterations;
    // Credit the iterations skipped by an early convergence, so the progress bar ends at 1.
    done.fetch_add(iterations.saturating_sub(last_iteration), Ordering::Relaxed);
    let at_optimum = cost.evaluate(&w)?;
    let dirichlet = shape.dirichlet();
    let mut energy = vec![0.0; shape.n_vertices()];
    let n_terms = at_optimum.spectra.len() as f64;
    for spectrum in &at_optimum.spectra {
        let e = dirichlet.extend(&eigenvector_energy(&spectrum.vectors), 0.0);
        energy.iter_mut().zip(e).for_each(|(a, b)| *a += b / n_terms);
    }
    Ok(Run {
        label: start.label.clone(),
        w,
        cost: at_optimum.cost,
        iterations: last_iteration,
        evaluations: evaluations + cost.evaluations,
        history,
        eigenvalues: at_optimum.spectra.iter().map(|s| s.values.clone()).collect(),
        energy,
        blocks: cost.blocks(),
    })
}

/// `iterations` trust-region iterations of `cost` from `w0` (its Gauss-Newton model Hessian),
/// each counted in `done`.
fn trust_region(
    cost: &mut AlignmentCost<'_>,
    w0: Vec<f64>,
    iterations: usize,
    progress: &Progress,
    done: &AtomicUsize,
) -> Result<(Vec<f64>, TrustRegionInfo)> {
    let params = TrustRegionParams { max_iterations: iterations, ..TrustRegionParams::default() };
    minimize(
        |w| {
            cost.evaluate(w).map(|e| Point {
                cost: e.cost,
                gradient: e.gradient,
                hessian: Some(Box::new(move |eta: &[f64]| e.hessian.apply(eta)) as HessianOperator),
            })
        },
        w0,
        &params,
        |_, _| {
            done.fetch_add(1, Ordering::Relaxed);
            progress.check()?;
            Ok(true)
        },
    )
}

/// Stage 4: each run's region: the superlevel set of its eigenvector energy with the
/// partial's area on the optimisation mesh, carried to the full shape and closed.
fn regions(loc: &Localizer, level: &OptimisationMesh, target: &Target, runs: Vec<Run>) -> Result<Vec<(Run, CoarseMask, FullMask)>> {
    runs.into_iter()
        .map(|run| {
            let coarse = CoarseMask(area_matched_region(&run.energy, level.coarse.mass(), target.area));
            let full = loc.to_full(level, &coarse)?;
            Ok((run, coarse, full))
        })
        .collect()
}

/// Stage 5: every candidate's scores ([`crate::selection`]): descriptor projections and
/// region cost on the optimisation mesh, the partial fit, the boundary misfit on the full
/// shape.
fn score(loc: &Localizer, level: &OptimisationMesh, target: &Target, mut candidates: Vec<(Run, CoarseMask, FullMask)>) -> Result<Vec<Scored>> {
    let metrics: Vec<Metric> = target.terms.iter().map(|t| t.metric).collect();
    let heights: Vec<f64> = target.terms.iter().map(|t| 2.0 * t.height).collect();
    let target_values: Vec<Vec<f64>> = target.terms.iter().map(|t| t.target.clone()).collect();
    let known: Vec<(Metric, Option<&Spectrum>)> = target.terms.iter().zip(&target.spectra).map(|(t, s)| (t.metric, Some(s))).collect();
    let signatures = selection::sampled_signatures(&target.shape, &target.descriptors, &known)?;
    let coarse_regions: Vec<Vec<bool>> = candidates.iter().map(|(_, c, _)| c.0.clone()).collect();
    let borrowed: Vec<&[bool]> = coarse_regions.iter().map(Vec::as_slice).collect();
    let fits = selection::partial_fits(&level.coarse_descriptors, &target.descriptors.descriptors, &borrowed)?;
    let spectral = selection::selection_scores(
        &level.coarse,
        &level.coarse_descriptors,
        &metrics,
        &signatures,
        &target_values,
        &heights,
        &coarse_regions,
        &candidates.iter_mut().map(|(run, _, _)| std::mem::take(&mut run.blocks)).collect::<Vec<_>>(),
    )?;
    let shares = match &target.matches {
        Some(m) => selection::vote_shares(&m.votes, &borrowed)?,
        None => vec![f64::NAN; borrowed.len()],
    };
    let partial_boundary = crate::region::boundary::region_boundary_length(target.shape.mesh(), None);
    let known = |x: f64| (!x.is_nan()).then_some(x);
    Ok(candidates
        .into_iter()
        .enumerate()
        .map(|(i, (run, coarse, full))| {
            let length = crate::region::boundary::region_boundary_length(&loc.full, Some(&full.0));
            let score = CandidateScore {
                descriptor_score: known(spectral.descriptors[i]),
                region_cost: known(spectral.region_cost[i]),
                boundary_misfit: known(selection::boundary_misfit(length, partial_boundary)),
                partial_fit: known(fits[i]),
                vote_share: known(shares[i]),
            };
            let _ = coarse;
            Scored { run, full, score }
        })
        .collect())
}

/// Stage 7: the chosen candidate's region, score and potential on the full mesh, and every
/// candidate for inspection.
fn result(loc: &Localizer, level: &OptimisationMesh, target: &Target, scored: Vec<Scored>, choice: usize, timings: Timings, warnings: Vec<String>) -> Localization {
    let best = &scored[choice].run;
    let energy_max = best.energy.iter().cloned().fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    let score = level.cell_of_full.iter().map(|&j| (best.energy[j as usize] / energy_max).clamp(0.0, 1.0)).collect();
    let v = potential_from_w(&best.w, target.terms[0].height);
    let potential = level.cell_of_full.iter().map(|&j| v[j as usize] / loc.scale.powi(2)).collect();
    let (k_regular, _) = loc.options.mode.counts(loc.options.k);
    let mut values = best.eigenvalues.iter().cloned();
    let mut targets = target.terms.iter().map(|t| t.target.clone());
    let (eigenvalues_regular, target_regular) =
        if k_regular > 0 { (values.next().unwrap_or_default(), targets.next().unwrap_or_default()) } else { Default::default() };
    let eigenvalues_si = values.next().unwrap_or_default();
    let target_si = targets.next().unwrap_or_default();
    let cost = best.cost;
    let n_starts = scored.len();
    let confidence = selection::confidence(&scored[choice].score);
    let similarity_score = selection::similarity_score(&scored.iter().map(|c| c.score).collect::<Vec<_>>());
    let region = scored[choice].full.0.clone();
    let candidates = scored
        .into_iter()
        .map(|c| Candidate {
            label: c.run.label,
            cost: c.run.cost,
            scores: c.score,
            iterations: c.run.iterations,
            evaluations: c.run.evaluations,
            cost_history: c.run.history,
            region: c.full.0,
        })
        .collect();
    Localization {
        region,
        score,
        potential,
        eigenvalues_regular,
        eigenvalues_si,
        target_regular,
        target_si,
        cost,
        confidence,
        similarity_score,
        optimisation_vertices: level.coarse.n_vertices(),
        scale: target.factor,
        selected_start: choice,
        n_starts,
        timings,
        candidates,
        warnings,
    }
}

/// Keep the largest connected component (by area) of a mesh; returns it and whether anything
/// was dropped.
pub(crate) fn largest_component(mesh: &TriMesh) -> Result<(TriMesh, bool)> {
    let (component, count) = crate::mesh::topology::connected_components(mesh);
    if count <= 1 {
        return Ok((mesh.clone(), false));
    }
    let mut area = vec![0.0; count];
    let v = mesh.vertices();
    for f in mesh.faces() {
        area[component[f[0] as usize] as usize] +=
            crate::mesh::triangle_area(v[f[0] as usize], v[f[1] as usize], v[f[2] as usize]);
    }
    let best = (0..count).max_by(|&a, &b| area[a].total_cmp(&area[b]).then(b.cmp(&a))).unwrap_or(0) as u32;
    let faces: Vec<[u32; 3]> = mesh.faces().iter().filter(|f| component[f[0] as usize] == best).copied().collect();
    let (m, _) = TriMesh::new_dropping_isolated(mesh.vertices().to_vec(), faces)?;
    Ok((m, true))
}

/// Seconds per stage.
struct Clock {
    start: Instant,
    lap: std::cell::Cell<Instant>,
}

impl Clock {
    fn start() -> Self {
        let now = Instant::now();
        Clock { start: now, lap: std::cell::Cell::new(now) }
    }
    /// Seconds since the previous lap.
    fn lap(&self) -> f64 {
        let now = Instant::now();
        let seconds = (now - self.lap.get()).as_secs_f64();
        self.lap.set(now);
        seconds
    }
    fn total(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }
}
