//! The localizer's stages, in order (ALGORITHM.md): normalise scale, decimate the full shape,
//! target spectra of the partial, starts, trust-region optimisation of every start (in
//! parallel), choice among the starts, region on the full shape.

use crate::alignment::cost::{potential_from_w, AlignmentCost, SpectrumTerm};
use crate::alignment::descriptor_start::descriptor_baseline_mask;
use crate::alignment::starts::{
    area_ball_starts, farthest_point_samples, gaussian_pair, gaussian_starts, mask_start, plane_cut_starts, spectral_cut_starts, Start,
};
use crate::alignment::trust_region::{minimize, HessianOperator, Point, TrustRegionParams};
use crate::error::{Error, Result};
use crate::localize::internal::{check_options, largest_component};
use crate::localize::{Candidate, Localization, Mode, Options, Selection, StartOutcome, StartShape, Timings};
use crate::mesh::TriMesh;
use crate::progress::Progress;
use crate::region::energy::{area_matched_region, eigenvector_energy};
use crate::shape::{Metric, Shape};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// Step height of the relaxed potential: $v \in [0, 2c]$ with $2c = 50\,\mu_k$ (ALGORITHM.md,
/// "tau = 50 * mu_k"), one height per spectrum on one shared $w$.
pub const STEP_HEIGHT_FACTOR: f64 = 50.0;

/// The optimisation mesh: the full shape decimated to about `target` vertices, and for each of
/// its vertices the index of the full-shape vertex it came from.
fn optimisation_mesh(full: &TriMesh, target: usize) -> Result<(TriMesh, Vec<u32>)> {
    let d = crate::mesh::decimate::decimate(full, target as f64 / full.n_vertices() as f64)?;
    Ok((d.mesh, d.original_vertex))
}

/// The optimisation mesh as a [`Shape`]. When it is a decimation of `full`, its
/// scale-invariant factor is estimated at the data's resolution (as the partial's is) and
/// integrated over its cells (`nearest[i]`: the cell of full vertex `i`;
/// [`crate::geometry::metric::transfer_factor`]): on 16 SHREC'16 pairs (shape_3, shape_8)
/// symmetry-aware IoU 0.651 instead of 0.560 with the factor of its own curvature.
fn optimisation_shape(
    opt_mesh: TriMesh,
    full: &TriMesh,
    opt_to_full: &[u32],
    nearest: &[u32],
    alpha: f64,
) -> Result<Shape> {
    let eps = crate::geometry::metric::DEFAULT_EPS;
    if opt_mesh.n_vertices() >= full.n_vertices() {
        return Ok(Shape::with_metric_params(opt_mesh, alpha, eps));
    }
    let curvature = crate::geometry::smoothed_gaussian_curvature(full);
    let fine = crate::geometry::metric::scale_invariant_factor(&curvature, alpha, eps);
    let fine_mass = crate::operators::mass::lumped_mass(full);
    let fallback: Vec<f64> = opt_to_full.iter().map(|&j| fine[j as usize]).collect();
    let factor = crate::geometry::metric::transfer_factor(&fine, &fine_mass, nearest, &fallback);
    Shape::with_scale_invariant_factor(opt_mesh, alpha, eps, factor)
}

pub(crate) fn run(
    full: &TriMesh,
    partial: &TriMesh,
    options: &Options,
    initial_regions: &[Vec<bool>],
    progress: &Progress,
) -> Result<Localization> {
    let t_start = Instant::now();
    check_options(options)?;
    let mut warnings = Vec::new();
    progress.report(0.0, "preparing")?;

    // --- Scale both shapes by one factor so that the full shape has unit area.
    let scale = 1.0 / full.area().sqrt();
    let full_n = full.map_positions(|p| p.map(|c| c * scale))?;
    let (partial_c, dropped) = largest_component(partial)?;
    if dropped {
        warnings.push(format!(
            "the partial shape is disconnected: only its largest component ({} of {} vertices) is localized",
            partial_c.n_vertices(),
            partial.n_vertices()
        ));
    }
    let partial_n = partial_c.map_positions(|p| p.map(|c| c * scale))?;
    let partial_area = partial_n.area();
    if partial_area > 1.1 {
        return Err(Error::InvalidArgument(format!(
            "the partial shape's area is {:.2}x the full shape's: it cannot be a part of it",
            partial_area
        )));
    }
    let part_shape = Shape::with_metric_params(
        partial_n,
        options.alpha,
        crate::geometry::metric::DEFAULT_EPS,
    );
    if !part_shape.has_boundary() {
        return Err(Error::InvalidArgument(
            "the partial shape has no boundary (it is closed): there is no Dirichlet spectrum to match; \
             compare whole shapes with the similarity tools instead"
                .into(),
        ));
    }

    // --- Decimated full shape.
    let decimated = if options.resolution > 0 && options.resolution < full_n.n_vertices() {
        match optimisation_mesh(&full_n, options.resolution) {
            Ok(d) => Some(d),
            Err(e) => {
                warnings.push(format!(
                    "decimation failed ({e}); optimising on the full-resolution shape"
                ));
                None
            }
        }
    } else {
        None
    };
    let (opt_mesh, opt_to_full) = if let Some(d) = decimated {
        d
    } else {
        let n = full_n.n_vertices() as u32;
        (full_n.clone(), (0..n).collect())
    };
    // Nearest optimisation-mesh vertex of every full-shape vertex (the cells of the
    // optimisation mesh; the region goes back to the full shape through them).
    let nearest = crate::mesh::nearest::nearest_vertices(opt_mesh.vertices(), full_n.vertices())?;
    let opt_shape = optimisation_shape(opt_mesh, &full_n, &opt_to_full, &nearest, options.alpha)?;

    // --- Target spectra of the partial (Dirichlet on its boundary).
    let (k_reg, k_si) = match options.mode {
        Mode::Dual => (options.k, options.k),
        Mode::Lbo => (2 * options.k, 0),
        Mode::Si => (0, 2 * options.k),
    };
    let mut terms = Vec::new();
    let mut target_regular = Vec::new();
    let mut target_si = Vec::new();
    for (metric, k) in [(Metric::Regular, k_reg), (Metric::ScaleInvariant, k_si)] {
        if k == 0 {
            continue;
        }
        let values = part_shape.dirichlet_spectrum(metric, k)?.values;
        let height = 0.5 * STEP_HEIGHT_FACTOR * values[values.len() - 1];
        match metric {
            Metric::Regular => target_regular = values.clone(),
            Metric::ScaleInvariant => target_si = values.clone(),
        }
        terms.push(SpectrumTerm {
            metric,
            target: values,
            height,
        });
    }
    let t_pre = t_start.elapsed().as_secs_f64();
    progress.report(0.05, "starts")?;

    // --- Starts.
    let t0 = Instant::now();
    let pts = opt_shape.mesh().vertices();
    let centres = farthest_point_samples(pts, options.centers, options.seed);
    let sigma = partial_area.sqrt();
    let balls = || area_ball_starts(opt_shape.mesh(), opt_shape.mass(), &centres, partial_area);
    let mut starts: Vec<Start> = match options.start_shape {
        StartShape::Gaussian => gaussian_starts(pts, &centres, &[sigma, 2.0 * sigma]),
        StartShape::AreaBall => balls(),
        StartShape::BallsAndWideGaussians | StartShape::BallsAndWideBumps => {
            let keep_wells = options.start_shape == StartShape::BallsAndWideGaussians;
            // Per centre: ball, coball, (wide well,) wide bump; the 2-sigma Gaussians are
            // labelled "sigma1" as in `StartShape::Gaussian`.
            balls()
                .chunks(2)
                .zip(&centres)
                .flat_map(|(b, &c)| {
                    let wide = gaussian_pair(pts, c, 2.0 * sigma, 1);
                    b.to_vec().into_iter().chain(wide.into_iter().filter(|s| keep_wells || s.family == "bump"))
                })
                .collect()
        }
    };
    starts.extend(plane_cut_starts(pts, opt_shape.mass(), partial_area, options.plane_cuts));
    // Opt-in extra starts; if the full shape's spectrum fails, the other starts still run.
    match spectral_cut_starts(&opt_shape, partial_area, options.spectral_cuts) {
        Ok(cuts) => starts.extend(cuts),
        Err(e) => warnings.push(format!("the spectral-cut starts were skipped: {e}")),
    }
    // Protected starts (never pruned) first: given regions (on the full shape, read at the
    // vertex each decimated vertex came from), then the descriptor baseline.
    let mut protected: Vec<Start> = initial_regions
        .iter()
        .enumerate()
        .map(|(i, r)| {
            mask_start(
                &opt_to_full
                    .iter()
                    .map(|&j| r[j as usize])
                    .collect::<Vec<_>>(),
                &format!("given#{i}"),
            )
        })
        .collect();
    // SHOT of both shapes (radius relative to the unit-area full shape), for the descriptor
    // start and the selection.
    let radius = crate::alignment::shot::DEFAULT_RADIUS_FRACTION;
    let min_nb = crate::alignment::shot::DEFAULT_MIN_NEIGHBORS;
    let shot = if options.descriptor_start || options.selection != Selection::Cost {
        Some((
            if opt_shape.n_vertices() < full_n.n_vertices() {
                // The optimisation mesh's vertices described with their support at the data's
                // resolution, as the partial's are (16 SHREC'16 pairs: IoU 0.661 vs 0.651).
                crate::alignment::shot::shot_keypoint_descriptors(
                    &full_n,
                    &opt_to_full,
                    radius,
                    min_nb,
                )?
            } else {
                crate::alignment::shot::shot_descriptors(opt_shape.mesh(), radius, min_nb)?
            },
            crate::alignment::shot::shot_descriptors(part_shape.mesh(), radius, min_nb)?,
        ))
    } else {
        None
    };
    if let (true, Some((d_full, d_part))) = (options.descriptor_start, &shot) {
        let r0 = descriptor_baseline_mask(d_full, d_part, opt_shape.mass(), partial_area)?;
        let neighbors = crate::mesh::topology::vertex_neighbors(opt_shape.mesh());
        let r0 = crate::region::closing::close(&r0, &neighbors, crate::region::CLOSING_RINGS)?;
        protected.push(mask_start(&r0, "descriptors"));
    }
    let n_given = protected.len();
    protected.append(&mut starts);
    let starts = protected;
    let t_starts = t0.elapsed().as_secs_f64();
    if starts.is_empty() {
        return Err(Error::InvalidArgument("no starts (centers = 0)".into()));
    }

    // --- Optimise the starts in parallel, by successive halving; progress is reported from
    // this thread only.
    let t0 = Instant::now();
    let rounds = halving_rounds(options.max_iterations, options.finalists);
    let iterations_done = AtomicUsize::new(0);
    let total_iterations = halving_total(&starts, n_given, &rounds, options.finalists)
        + halving_survivors(&starts, n_given, &rounds, options.finalists)
            * options.extra_iterations;
    let worker_progress = Progress::none().with_cancel_flag(progress.cancel_flag());
    // One pool (`options.threads`, 0 = all cores) for the optimisation and the selection.
    let workers = rayon::ThreadPoolBuilder::new()
        .num_threads(options.threads)
        .build()
        .map_err(|e| Error::Numerical(format!("thread pool: {e}")))?;
    let outcomes: Vec<Result<StartOutcome>> = std::thread::scope(|scope| {
        let handle = scope.spawn(|| {
            workers.install(|| {
                optimise_starts(
                    &opt_shape,
                    &terms,
                    &starts,
                    n_given,
                    &rounds,
                    options,
                    &worker_progress,
                    &iterations_done,
                )
            })
        });
        while !handle.is_finished() {
            std::thread::sleep(std::time::Duration::from_millis(50));
            let done =
                iterations_done.load(Ordering::Relaxed) as f64 / total_iterations.max(1) as f64;
            if progress
                .report(0.05 + 0.85 * done.min(1.0), "optimising")
                .is_err()
            {
                worker_progress.cancel();
            }
        }
        match handle.join() {
            Ok(r) => r,
            Err(_) => Err(Error::Numerical("a worker thread panicked".into())),
        }
    })?;
    progress.check()?;
    let t_opt = t0.elapsed().as_secs_f64();

    // A start may fail numerically; the others still count. All failing is an error.
    let mut ok = Vec::new();
    let mut first_err = None;
    for o in outcomes {
        match o {
            Ok(o) => ok.push(o),
            Err(Error::Cancelled) => return Err(Error::Cancelled),
            Err(e) => first_err = first_err.or(Some(e)),
        }
    }
    if ok.is_empty() {
        return Err(first_err.unwrap_or_else(|| Error::Numerical("no start converged".into())));
    }
    if let Some(e) = first_err {
        warnings.push(format!("some starts failed and were skipped: {e}"));
    }

    // --- Region of every start, on the optimisation mesh and on the full shape.
    let t0 = Instant::now();
    progress.report(0.9, "regions")?;
    let neighbors = crate::mesh::topology::vertex_neighbors(&full_n);
    let opt_regions: Vec<Vec<bool>> = ok
        .iter()
        .map(|o| area_matched_region(&o.energy, opt_shape.mass(), partial_area))
        .collect();
    let full_regions: Vec<Vec<bool>> = opt_regions
        .iter()
        .map(|r| {
            let t: Vec<bool> = nearest.iter().map(|&j| r[j as usize]).collect();
            crate::region::closing::close(&t, &neighbors, crate::region::CLOSING_RINGS)
        })
        .collect::<Result<_>>()?;
    let t_region = t0.elapsed().as_secs_f64();

    // --- Choice among the starts: descriptors projected on eigenfunctions (lowest score).
    let t0 = Instant::now();
    progress.report(0.93, "selecting")?;
    // Scores of the finalists (every start without pruning); NaN for the others.
    let mut selection = vec![f64::NAN; ok.len()];
    let mut region_costs = vec![f64::NAN; ok.len()];
    let mut partial_fits = vec![f64::NAN; ok.len()];
    if let (true, Some((d_full, d_part))) = (options.selection != Selection::Cost, &shot) {
        let metrics: Vec<Metric> = terms.iter().map(|t| t.metric).collect();
        let heights: Vec<f64> = terms.iter().map(|t| 2.0 * t.height).collect();
        let targets =
            crate::alignment::selection::partial_signatures(&part_shape, d_part, &metrics)?;
        let finalists: Vec<usize> = (0..ok.len()).filter(|&i| ok[i].finalist).collect();
        // The regions on the optimisation mesh, before transfer and closing. Scoring the
        // returned (closed) regions instead, read back at the optimisation vertices, was
        // measured no better (43 SHREC'16 pairs: symmetry-aware IoU 0.670 vs 0.676; measured
        // while warm-chained scoring solves still missed eigenvalues, see `selection_scores`).
        let finalist_regions: Vec<Vec<bool>> =
            finalists.iter().map(|&i| opt_regions[i].clone()).collect();
        // Only the gated rule ranks by the partial fit.
        if options.selection == Selection::Gated {
            let regions: Vec<&[bool]> = finalist_regions.iter().map(Vec::as_slice).collect();
            let fits = crate::alignment::selection::partial_fits(d_full, d_part, &regions)?;
            for (&i, f) in finalists.iter().zip(fits) {
                partial_fits[i] = f;
            }
        }
        let target_values: Vec<Vec<f64>> = terms.iter().map(|t| t.target.clone()).collect();
        let scores = workers.install(|| {
            crate::alignment::selection::selection_scores(
                &opt_shape,
                d_full,
                &metrics,
                &targets,
                &target_values,
                &heights,
                &finalist_regions,
            )
        })?;
        for (j, &i) in finalists.iter().enumerate() {
            selection[i] = scores.descriptors[j];
            region_costs[i] = scores.region_cost[j];
        }
    }
    // Only finalists are chosen from (every start is a finalist without pruning); a start that
    // failed in the last round leaves its round's survivors to choose from.
    let pool: Vec<usize> = if ok.iter().any(|o| o.finalist) {
        (0..ok.len()).filter(|&i| ok[i].finalist).collect()
    } else {
        (0..ok.len()).collect()
    };
    let costs: Vec<f64> = ok.iter().map(|o| o.cost).collect();
    let n_eigenvalues: usize = terms.iter().map(|t| t.target.len()).sum();
    let floor = n_eigenvalues as f64 * crate::localize::REGION_COST_FLOOR_RMS.powi(2);
    // Boundary length of each region against the partial's cut (both in the same units).
    let partial_boundary = crate::region::boundary::region_boundary_length(part_shape.mesh(), None);
    let misfit: Vec<f64> = full_regions
        .iter()
        .map(|r| {
            let l = crate::region::boundary::region_boundary_length(&full_n, Some(r));
            crate::alignment::selection::boundary_misfit(l, partial_boundary)
        })
        .collect();
    let scores = crate::alignment::selection::CandidateScores {
        cost: &costs,
        descriptors: &selection,
        region_cost: &region_costs,
        boundary_misfit: &misfit,
        partial_fit: &partial_fits,
    };
    let selected = crate::alignment::selection::choose(options.selection, &pool, &scores, floor);
    let t_sel = t0.elapsed().as_secs_f64();
    progress.report(0.98, "finishing")?;

    let best = &ok[selected];
    let emax = best
        .energy
        .iter()
        .cloned()
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let score: Vec<f64> = nearest
        .iter()
        .map(|&j| (best.energy[j as usize] / emax).clamp(0.0, 1.0))
        .collect();
    let v_opt = potential_from_w(&best.w, terms[0].height);
    let potential: Vec<f64> = nearest
        .iter()
        .map(|&j| v_opt[j as usize] / scale.powi(2))
        .collect();
    let region = full_regions[selected].clone();
    let candidates = ok
        .iter()
        .zip(full_regions)
        .zip(selection.iter().zip(&region_costs).zip(&misfit).zip(&partial_fits))
        .map(|((o, r), (((&sc, &rc), &bm), &pf))| Candidate {
            partial_fit: pf,
            label: o.label.clone(),
            cost: o.cost,
            selection_score: sc,
            region_cost: rc,
            boundary_misfit: bm,
            iterations: o.iterations,
            evaluations: o.evaluations,
            finalist: o.finalist,
            region: r,
        })
        .collect();
    progress.report(1.0, "done")?;

    let mut eig = best.eigenvalues.iter();
    let eigenvalues_regular = if k_reg > 0 {
        eig.next().cloned().unwrap_or_default()
    } else {
        Vec::new()
    };
    let eigenvalues_si = if k_si > 0 {
        eig.next().cloned().unwrap_or_default()
    } else {
        Vec::new()
    };
    Ok(Localization {
        region,
        score,
        potential,
        eigenvalues_regular,
        eigenvalues_si,
        target_regular,
        target_si,
        cost: best.cost,
        selected_start: selected,
        n_starts: ok.len(),
        timings: Timings {
            preprocessing: t_pre,
            starts: t_starts,
            optimisation: t_opt,
            selection: t_sel,
            region: t_region,
            total: t_start.elapsed().as_secs_f64(),
        },
        candidates,
        warnings,
    })
}

/// Iterations of each round of the successive halving: rounds end at 1/8, 1/4, 1/2 and all of
/// `max_iterations` (Jamieson & Talwalkar 2016, "successive halving"). `finalists == 0` or too
/// few iterations: one round.
fn halving_rounds(max_iterations: usize, finalists: usize) -> Vec<usize> {
    if finalists == 0 || max_iterations < 8 {
        return vec![max_iterations];
    }
    let ends = [
        max_iterations / 8,
        max_iterations / 4,
        max_iterations / 2,
        max_iterations,
    ];
    ends.iter()
        .scan(0, |done, &end| {
            let r = end - *done;
            *done = end;
            Some(r)
        })
        .collect()
}

/// Survivors of a round in a family of `alive` starts: the better half, but never fewer than
/// `keep_min` (nor more than are alive).
fn survivors(alive: usize, keep_min: usize) -> usize {
    alive.div_ceil(2).max(keep_min).min(alive)
}

/// A start being optimised: its cost (with warm eigensolvers) and where it is.
struct Run<'a> {
    label: String,
    cost: AlignmentCost<'a>,
    w: Vec<f64>,
    fx: f64,
    iterations: usize,
    delta: Option<f64>,
    alive: bool,
    failed: Option<Error>,
    /// The run's cost fell by more than [`STILL_IMPROVING`] over its last
    /// [`IMPROVEMENT_WINDOW`] iterations (it gets the extra iterations).
    improving: bool,
}

/// Iterations over which a run's recent improvement is measured.
const IMPROVEMENT_WINDOW: usize = 10;
/// A run whose cost fell below this fraction of its value [`IMPROVEMENT_WINDOW`] iterations
/// earlier is still converging.
const STILL_IMPROVING: f64 = 0.9;

/// Run the `rounds` over all `starts` (each round in parallel), then the per-start outcome.
/// After each round, each family of starts keeps its better half (by cost, ties by index),
/// at least `options.finalists` in all; the first `protected` starts are never pruned; then
/// `options.extra_iterations` for the runs still converging. Deterministic.
fn optimise_starts(
    shape: &Shape,
    terms: &[SpectrumTerm],
    starts: &[Start],
    protected: usize,
    rounds: &[usize],
    options: &Options,
    progress: &Progress,
    iterations_done: &AtomicUsize,
) -> Result<Vec<Result<StartOutcome>>> {
    use rayon::prelude::*;
    let mut runs: Vec<Run> = starts
        .iter()
        .map(|s| {
            Ok(Run {
                label: s.label.clone(),
                cost: AlignmentCost::new(shape, terms.to_vec())?
                    .with_hessian_model(options.hessian),
                w: s.w0.clone(),
                fx: f64::INFINITY,
                iterations: 0,
                delta: None,
                alive: true,
                failed: None,
                improving: false,
            })
        })
        .collect::<Result<_>>()?;
    let (finalists, extra_iterations) = (options.finalists, options.extra_iterations);
    let (families, keep_min) = family_plan(starts, protected, finalists);
    for (r, &iterations) in rounds.iter().enumerate() {
        if r > 0 {
            for family in &families {
                let mut alive: Vec<usize> = (protected..runs.len())
                    .filter(|&i| runs[i].alive && starts[i].family == *family)
                    .collect();
                alive.sort_by(|&a, &b| runs[a].fx.total_cmp(&runs[b].fx).then(a.cmp(&b)));
                for &i in alive.iter().skip(survivors(alive.len(), keep_min)) {
                    runs[i].alive = false;
                }
            }
        }
        runs.par_iter_mut().filter(|run| run.alive).for_each(|run| {
            if let Err(e) = advance(run, iterations, progress, iterations_done) {
                run.alive = false;
                run.fx = f64::INFINITY;
                run.failed = Some(e);
            }
        });
        progress.check()?;
    }
    // Runs still converging (costs still falling fast: in practice the bump starts, which
    // begin far from any spectrum) get `extra_iterations` more; the others are credited.
    if extra_iterations > 0 {
        runs.par_iter_mut().filter(|run| run.alive).for_each(|run| {
            if !run.improving {
                iterations_done.fetch_add(extra_iterations, Ordering::Relaxed);
            } else if let Err(e) = advance(run, extra_iterations, progress, iterations_done) {
                run.alive = false;
                run.fx = f64::INFINITY;
                run.failed = Some(e);
            }
        });
        progress.check()?;
    }
    let outcomes = runs
        .into_par_iter()
        .map(|run| finish_run(shape, run))
        .collect();
    Ok(outcomes)
}

/// The distinct families of the prunable `starts[protected..]`, in order of appearance, and
/// how many starts each family keeps at least (the `finalists` shared among the families).
fn family_plan(starts: &[Start], protected: usize, finalists: usize) -> (Vec<&'static str>, usize) {
    let mut families: Vec<&'static str> = Vec::new();
    for s in &starts[protected..] {
        if !families.contains(&s.family) {
            families.push(s.family);
        }
    }
    let keep_min = finalists.div_ceil(families.len().max(1));
    (families, keep_min)
}

/// Starts alive after each round of the halving (protected ones included).
fn halving_alive(
    starts: &[Start],
    protected: usize,
    rounds: &[usize],
    finalists: usize,
) -> Vec<usize> {
    let (fams, keep_min) = family_plan(starts, protected, finalists);
    let mut alive: Vec<usize> = fams
        .iter()
        .map(|f| {
            starts[protected..]
                .iter()
                .filter(|s| s.family == *f)
                .count()
        })
        .collect();
    (0..rounds.len())
        .map(|r| {
            if r > 0 {
                alive.iter_mut().for_each(|a| *a = survivors(*a, keep_min));
            }
            protected + alive.iter().sum::<usize>()
        })
        .collect()
}

/// Total iterations the halving runs (for the progress bar; exact unless a start fails or
/// converges early, which is credited as if it ran).
fn halving_total(starts: &[Start], protected: usize, rounds: &[usize], finalists: usize) -> usize {
    let alive = halving_alive(starts, protected, rounds, finalists);
    alive.iter().zip(rounds).map(|(a, it)| a * it).sum()
}

/// Starts that run to the end of the halving.
fn halving_survivors(
    starts: &[Start],
    protected: usize,
    rounds: &[usize],
    finalists: usize,
) -> usize {
    halving_alive(starts, protected, rounds, finalists)
        .last()
        .copied()
        .unwrap_or(0)
}

/// `iterations` more trust-region iterations of `run`, resuming with its trust radius.
fn advance(
    run: &mut Run,
    iterations: usize,
    progress: &Progress,
    iterations_done: &AtomicUsize,
) -> Result<()> {
    progress.check()?;
    let params = TrustRegionParams {
        max_iterations: iterations,
        initial_delta: run.delta,
        ..TrustRegionParams::default()
    };
    let cost = &mut run.cost;
    let mut last_iter = 0;
    let (w, info) = minimize(
        |w| {
            cost.evaluate(w).map(|e| Point {
                cost: e.cost,
                gradient: e.gradient,
                hessian: e
                    .hessian
                    .map(|h| Box::new(move |eta: &[f64]| h.apply(eta)) as HessianOperator),
            })
        },
        std::mem::take(&mut run.w),
        &params,
        |iter, _| {
            iterations_done.fetch_add(1, Ordering::Relaxed);
            last_iter = iter + 1;
            progress.check()?;
            Ok(true)
        },
    )?;
    // Credit skipped iterations (converged early) so the progress bar reaches the end.
    iterations_done.fetch_add(iterations.saturating_sub(last_iter), Ordering::Relaxed);
    let h = &info.history;
    run.improving = h.len() > IMPROVEMENT_WINDOW
        && info.cost < STILL_IMPROVING * h[h.len() - 1 - IMPROVEMENT_WINDOW];
    run.w = w;
    run.fx = info.cost;
    run.iterations += info.iterations;
    run.delta = Some(info.delta);
    Ok(())
}

/// The outcome of a run: eigenvalues and eigenvector energy at its final `w`.
fn finish_run(shape: &Shape, mut run: Run) -> Result<StartOutcome> {
    if let Some(e) = run.failed {
        return Err(e);
    }
    let ev = run.cost.evaluate(&run.w)?;
    let dir = shape.dirichlet();
    // Energy of all matched eigenfunctions (every term), per vertex of the shape.
    let mut energy = vec![0.0; shape.n_vertices()];
    for s in &ev.spectra {
        let e = dir.extend(&eigenvector_energy(&s.vectors), 0.0);
        for (a, b) in energy.iter_mut().zip(e) {
            *a += b / ev.spectra.len() as f64;
        }
    }
    Ok(StartOutcome {
        label: run.label,
        w: run.w,
        cost: ev.cost,
        iterations: run.iterations,
        evaluations: run.cost.evaluations,
        finalist: run.alive,
        eigenvalues: ev.spectra.iter().map(|s| s.values.clone()).collect(),
        energy,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halving_rounds_and_survivors() {
        assert_eq!(halving_rounds(100, 4), vec![12, 13, 25, 50]);
        assert_eq!(halving_rounds(100, 0), vec![100]);
        assert_eq!(halving_rounds(5, 4), vec![5]);
        assert_eq!(
            (
                survivors(20, 2),
                survivors(3, 2),
                survivors(2, 2),
                survivors(1, 2)
            ),
            (10, 2, 2, 1)
        );
        // 40 Gaussian starts (20 wells, 20 bumps), 4 finalists: 40, 20, 10, 6 (3 + 3) run.
        let pts = vec![[0.0, 0.0, 0.0]; 3];
        let starts = crate::alignment::starts::gaussian_starts(
            &pts,
            &[0, 1, 2, 0, 1, 2, 0, 1, 2, 0],
            &[1.0, 2.0],
        );
        assert_eq!(starts.len(), 40);
        assert_eq!(
            halving_total(&starts, 0, &[1, 1, 1, 1], 4),
            40 + 20 + 10 + 6
        );
        // One protected start always runs; the other 39 (20 bumps, 19 wells) are halved.
        assert_eq!(
            halving_total(&starts, 1, &[1, 1, 1, 1], 4),
            40 + 21 + 11 + 7
        );
    }
}
