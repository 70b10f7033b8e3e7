//! The localizer's stages, in order (ALGORITHM.md): normalise scale, decimate the full shape,
//! target spectra of the partial, starts, trust-region optimisation of every start (in
//! parallel), choice among the starts, region on the full shape.

use crate::alignment::cost::{potential_from_w, AlignmentCost, SpectrumTerm};
use crate::alignment::starts::{farthest_point_samples, gaussian_starts, Start};
use crate::alignment::trust_region::{minimize, TrustRegionParams};
use crate::error::{Error, Result};
use crate::localize::internal::{check_options, largest_component};
use crate::localize::{Candidate, Localization, Mode, Options, Selection, StartOutcome, Timings};
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

pub(crate) fn run(full: &TriMesh, partial: &TriMesh, options: &Options, progress: &Progress) -> Result<Localization> {
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
    let part_shape = Shape::with_metric_params(partial_n, options.alpha, crate::geometry::metric::DEFAULT_EPS);
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
                warnings.push(format!("decimation failed ({e}); optimising on the full-resolution shape"));
                None
            }
        }
    } else {
        None
    };
    let (opt_mesh, _opt_to_full) = if let Some(d) = decimated {
        d
    } else {
        let n = full_n.n_vertices() as u32;
        (full_n.clone(), (0..n).collect())
    };
    let opt_shape = Shape::with_metric_params(opt_mesh, options.alpha, crate::geometry::metric::DEFAULT_EPS);

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
        terms.push(SpectrumTerm { metric, target: values, height });
    }
    let t_pre = t_start.elapsed().as_secs_f64();
    progress.report(0.05, "starts")?;

    // --- Starts.
    let t0 = Instant::now();
    let pts = opt_shape.mesh().vertices();
    let centres = farthest_point_samples(pts, options.centers, options.seed);
    let sigma = partial_area.sqrt();
    let starts: Vec<Start> = gaussian_starts(pts, &centres, &[sigma, 2.0 * sigma]);
    let t_starts = t0.elapsed().as_secs_f64();
    if starts.is_empty() {
        return Err(Error::InvalidArgument("no starts (centers = 0)".into()));
    }

    // --- Optimise every start in parallel; progress is reported from this thread only.
    let t0 = Instant::now();
    let iterations_done = AtomicUsize::new(0);
    let total_iterations = starts.len() * options.max_iterations;
    let worker_progress = Progress::none().with_cancel_flag(progress.cancel_flag());
    let tr = TrustRegionParams { max_iterations: options.max_iterations, ..TrustRegionParams::default() };
    let outcomes: Vec<Result<StartOutcome>> = std::thread::scope(|scope| {
        let handle = scope.spawn(|| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(options.threads)
                .build()
                .map_err(|e| Error::Numerical(format!("thread pool: {e}")))?;
            let out = pool.install(|| {
                use rayon::prelude::*;
                starts
                    .par_iter()
                    .map(|s| optimise_start(&opt_shape, &terms, s, &tr, &worker_progress, &iterations_done))
                    .collect::<Vec<_>>()
            });
            Ok::<_, Error>(out)
        });
        while !handle.is_finished() {
            std::thread::sleep(std::time::Duration::from_millis(50));
            let done = iterations_done.load(Ordering::Relaxed) as f64 / total_iterations.max(1) as f64;
            if progress.report(0.05 + 0.85 * done, "optimising").is_err() {
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
    let nearest = crate::mesh::nearest::nearest_vertices(opt_shape.mesh().vertices(), full_n.vertices())?;
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
    let selection = if options.selection == Selection::Descriptors {
        let radius = crate::alignment::shot::DEFAULT_RADIUS_FRACTION; // full shape has unit area
        let d_full = crate::alignment::shot::shot_descriptors(opt_shape.mesh(), radius, crate::alignment::shot::DEFAULT_MIN_NEIGHBORS)?;
        let d_part = crate::alignment::shot::shot_descriptors(part_shape.mesh(), radius, crate::alignment::shot::DEFAULT_MIN_NEIGHBORS)?;
        let metrics: Vec<Metric> = terms.iter().map(|t| t.metric).collect();
        let heights: Vec<f64> = terms.iter().map(|t| 2.0 * t.height).collect();
        let targets = crate::alignment::selection::partial_signatures(&part_shape, &d_part, &metrics)?;
        crate::alignment::selection::selection_scores(&opt_shape, &d_full, &metrics, &targets, &heights, &opt_regions)?
    } else {
        vec![f64::NAN; ok.len()]
    };
    let key = |i: usize| if options.selection == Selection::Descriptors { selection[i] } else { ok[i].cost };
    let selected = (0..ok.len()).min_by(|&a, &b| key(a).total_cmp(&key(b)).then(a.cmp(&b))).unwrap_or(0);
    let t_sel = t0.elapsed().as_secs_f64();
    progress.report(0.98, "finishing")?;

    let best = &ok[selected];
    let emax = best.energy.iter().cloned().fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    let score: Vec<f64> = nearest.iter().map(|&j| (best.energy[j as usize] / emax).clamp(0.0, 1.0)).collect();
    let v_opt = potential_from_w(&best.w, terms[0].height);
    let potential: Vec<f64> = nearest.iter().map(|&j| v_opt[j as usize] / scale.powi(2)).collect();
    let region = full_regions[selected].clone();
    let candidates = ok
        .iter()
        .zip(full_regions)
        .zip(&selection)
        .map(|((o, r), &sc)| Candidate {
            label: o.label.clone(),
            cost: o.cost,
            selection_score: sc,
            iterations: o.iterations,
            evaluations: o.evaluations,
            region: r,
        })
        .collect();
    progress.report(1.0, "done")?;

    let mut eig = best.eigenvalues.iter();
    let eigenvalues_regular = if k_reg > 0 { eig.next().cloned().unwrap_or_default() } else { Vec::new() };
    let eigenvalues_si = if k_si > 0 { eig.next().cloned().unwrap_or_default() } else { Vec::new() };
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

fn optimise_start(
    shape: &Shape,
    terms: &[SpectrumTerm],
    start: &Start,
    params: &TrustRegionParams,
    progress: &Progress,
    iterations_done: &AtomicUsize,
) -> Result<StartOutcome> {
    progress.check()?;
    let mut cost = AlignmentCost::new(shape, terms.to_vec())?;
    let mut last_iter = 0;
    let (w, info) = minimize(
        |w| cost.evaluate(w).map(|e| (e.cost, e.gradient)),
        start.w0.clone(),
        params,
        |iter, _| {
            iterations_done.fetch_add(1, Ordering::Relaxed);
            last_iter = iter + 1;
            progress.check()?;
            Ok(true)
        },
    )?;
    // Credit skipped iterations so the progress bar reaches the end.
    iterations_done.fetch_add(params.max_iterations.saturating_sub(last_iter), Ordering::Relaxed);
    let ev = cost.evaluate(&w)?;
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
        label: start.label.clone(),
        w,
        cost: ev.cost,
        iterations: info.iterations,
        evaluations: cost.evaluations,
        eigenvalues: ev.spectra.iter().map(|s| s.values.clone()).collect(),
        energy,
    })
}
