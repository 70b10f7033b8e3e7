//! Choosing among the optimised starts (docs/algorithm.md, "Choosing among the starts").
//!
//! Each candidate region is scored five ways: its *region cost* (how well the region's own
//! step potential reproduces the partial's spectra), its *descriptor score* (SHOT descriptors
//! projected on eigenfunctions, the paper's rule), its *partial fit* (every local shape of
//! the partial found in the region), its *boundary misfit* (all lower-is-better) and its
//! *vote share* (the partial's descriptor votes inside it, higher-is-better). The last four
//! rank: [`choose`]; the region cost only decides which candidates are eligible. The
//! [`confidence`] is $\sigma(b + a f)$ of the chosen candidate's partial fit $f$ alone.
//!
//! The descriptor score:
//! $c_N = (\Psi^{\circ 2})^\top A_N D_N$ with $\Psi$ the first $k_d$ Dirichlet eigenfunctions of
//! the partial, and for a candidate region $R$ on the full shape
//! $c_M = (\Phi^{\circ 2})^\top A_M D_M$ with $\Phi$ the first $k_d$ eigenfunctions of
//! $W + A\,\mathrm{diag}(\tau (1 - R))$. The score $\sum |c_M - c_N|$ is summed over the
//! regular and (in the dual method) the scale-invariant metric; the lowest score wins.

use crate::error::Result;
use serde::{Deserialize, Serialize};
use crate::shape::{Metric, Shape};
use crate::spectra::{EigenParams, HamiltonianSolver, Spectrum};

/// Weight $\beta$ of the boundary-length misfit in [`choose`]: the ranking is multiplied by
/// $\exp(\beta\,|\ln(L_R/L_N)|)$ (docs/benchmarks/options.md).
pub const BOUNDARY_WEIGHT: f64 = 0.5;
use faer::{Mat, MatRef};

/// Eigenfunctions used by the projection (the reference uses 5).
pub const PROJECTION_EIGENFUNCTIONS: usize = 5;

/// $(\Phi^{\circ 2})^\top \mathrm{diag}(m) D$: a `k x d` matrix. Rows of `vectors`, `mass` and `desc` match.
pub fn descriptor_projection(vectors: MatRef<'_, f64>, mass: &[f64], desc: &Mat<f64>) -> Mat<f64> {
    let (n, k, d) = (vectors.nrows(), vectors.ncols(), desc.ncols());
    // (phi^2 .* m)^T D as one matrix product (the descriptors column-major: a loop over
    // them row by row strides through memory).
    let weights = Mat::<f64>::from_fn(n, k, |i, j| vectors[(i, j)].powi(2) * mass[i]);
    let mut out = Mat::<f64>::zeros(k, d);
    faer::linalg::matmul::matmul(out.as_mut(), faer::Accum::Replace, weights.transpose(), desc.as_ref(), 1.0, faer::Par::Seq);
    out
}

/// The partial's projections, one per metric: its first [`PROJECTION_EIGENFUNCTIONS`]
/// Dirichlet eigenfunctions solved here ([`signatures_from_spectra`] with nothing known).
#[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
pub fn partial_signatures(
    partial: &Shape,
    desc: &Mat<f64>,
    metrics: &[Metric],
) -> Result<Vec<Mat<f64>>> {
    let known: Vec<(Metric, Option<&Spectrum>)> = metrics.iter().map(|&m| (m, None)).collect();
    signatures_from_spectra(partial, desc, &known)
}

/// The partial's projections, one per metric, reusing a Dirichlet spectrum of the partial
/// already solved for that metric when it has at least the
/// [`PROJECTION_EIGENFUNCTIONS`] (or all but one of the free vertices) eigenfunctions needed:
/// its first columns are the same eigenfunctions, so a second cold solve is saved. Otherwise
/// they are solved here.
pub fn signatures_from_spectra(
    partial: &Shape,
    desc: &Mat<f64>,
    metrics: &[(Metric, Option<&Spectrum>)],
) -> Result<Vec<Mat<f64>>> {
    let rows: Vec<u32> = (0..partial.n_vertices() as u32).collect();
    pooled_signatures(partial, desc, &rows, metrics)
}

/// [`signatures_from_spectra`] with the partial described at a sample of its vertices
/// ([`crate::geometry::shot::sampled_shot`]): each vertex weighs in with the descriptor of its
/// nearest sampled vertex, $c_N = (\Psi^{\circ 2})^\top A_N P D_S$ with $P$ the
/// vertex-to-sample assignment.
pub fn sampled_signatures(
    partial: &Shape,
    desc: &crate::geometry::shot::SampledShot,
    metrics: &[(Metric, Option<&Spectrum>)],
) -> Result<Vec<Mat<f64>>> {
    pooled_signatures(partial, &desc.descriptors, &desc.row_of_vertex, metrics)
}

/// The projections with vertex `i` described by row `row_of_vertex[i]` of `desc`.
fn pooled_signatures(
    partial: &Shape,
    desc: &Mat<f64>,
    row_of_vertex: &[u32],
    metrics: &[(Metric, Option<&Spectrum>)],
) -> Result<Vec<Mat<f64>>> {
    let dir = partial.dirichlet();
    if row_of_vertex.len() != partial.n_vertices() || row_of_vertex.iter().any(|&r| r as usize >= desc.nrows()) {
        return Err(crate::error::Error::InvalidArgument(format!(
            "descriptor rows for {} vertices ({} rows), the partial has {} vertices",
            row_of_vertex.len(),
            desc.nrows(),
            partial.n_vertices()
        )));
    }
    let rows_free: Vec<u32> = dir.free.iter().map(|&i| row_of_vertex[i as usize]).collect();
    let k = PROJECTION_EIGENFUNCTIONS.min(dir.n_free().saturating_sub(1)).max(1);
    metrics
        .iter()
        .map(|&(m, known)| {
            let mass = dir.restrict(partial.metric_mass(m));
            let project = |s: &Spectrum| pooled_projection(s.vectors.as_ref().subcols(0, k), &mass, &rows_free, desc);
            match known {
                Some(s) if s.vectors.ncols() >= k && s.vectors.nrows() == mass.len() => Ok(project(s)),
                _ => Ok(project(&partial.dirichlet_spectrum(m, k)?)),
            }
        })
        .collect()
}

/// $(\Phi^{\circ 2})^\top \mathrm{diag}(m) P D$ with $P_{i,r} = 1$ for $r$ = `rows[i]`: the
/// squared eigenfunctions' mass summed per descriptor row, then one product with `desc`.
fn pooled_projection(vectors: MatRef<'_, f64>, mass: &[f64], rows: &[u32], desc: &Mat<f64>) -> Mat<f64> {
    let (k, d) = (vectors.ncols(), desc.ncols());
    let mut weights = Mat::<f64>::zeros(desc.nrows(), k);
    for j in 0..k {
        for (i, &r) in rows.iter().enumerate() {
            weights[(r as usize, j)] += vectors[(i, j)].powi(2) * mass[i];
        }
    }
    let mut out = Mat::<f64>::zeros(k, d);
    faer::linalg::matmul::matmul(out.as_mut(), faer::Accum::Replace, weights.transpose(), desc.as_ref(), 1.0, faer::Par::Seq);
    out
}

/// Scores of the candidate regions (lower is better for both).
#[derive(Debug, Clone)]
pub struct RegionScores {
    /// $\sum_t \sum |c_M^t - c_N^t|$ (descriptor projections).
    pub descriptors: Vec<f64>,
    /// The alignment cost of the region's own step potential $\tau(1 - R)$:
    /// $\sum_t \sum_i (\lambda^t_i - \mu^t_i)^2 / (\mu^t_i)^2$ (how well the extracted
    /// region, not the relaxed potential, matches the partial's spectra).
    pub region_cost: Vec<f64>,
}

/// Score every candidate region on `full`: descriptor projections against `targets` (one
/// `k_d x d` matrix per metric) and spectra against `target_values` (one per metric).
/// `seeds[r][t]`, when given, starts the solve of region `r` and metric `t` (rows: the free
/// vertices of `full`; e.g. the last eigenvectors of the run that region came from); without
/// one (or with `seeds` empty) that solve is cold.
#[allow(clippy::too_many_arguments)]
pub fn selection_scores(
    full: &Shape,
    desc: &Mat<f64>,
    metrics: &[Metric],
    targets: &[Mat<f64>],
    target_values: &[Vec<f64>],
    heights: &[f64],
    regions: &[Vec<bool>],
    seeds: &[Vec<Option<Mat<f64>>>],
) -> Result<RegionScores> {
    use rayon::prelude::*;
    let dir = full.dirichlet();
    let desc_free = restrict_rows(desc, &dir.free);
    // Every (metric, region) solve is independent, cold or seeded by that region's own run: a
    // warm start from *another* candidate's eigenvectors (a region elsewhere on the shape)
    // converged to eigenpairs living in the walls, $\lambda \approx \tau$, missing the
    // region's own (SHREC'16 victoria_4: 9 of 32 solves); a seeded solve is inertia-checked
    // and solved cold if it missed any. Independent solves also run in parallel, on the
    // caller's rayon pool; per-metric terms are summed in metric order afterwards
    // (deterministic).
    let jobs: Vec<(usize, usize)> = (0..metrics.len())
        .flat_map(|t| (0..regions.len()).map(move |r| (t, r)))
        .collect();
    let per_job: Vec<(f64, f64)> = jobs
        .par_iter()
        .map(|&(t, ri)| {
            let (m, target, mu, tau) = (metrics[t], &targets[t], &target_values[t], heights[t]);
            let mass = dir.restrict(full.metric_mass(m));
            let k = target
                .nrows()
                .max(mu.len())
                .min(dir.n_free().saturating_sub(1))
                .max(1);
            let r = &regions[ri];
            let v: Vec<f64> = dir
                .free
                .iter()
                .map(|&i| if r[i as usize] { 0.0 } else { tau })
                .collect();
            let seed = seeds
                .get(ri)
                .and_then(|per_metric| per_metric.get(t))
                .and_then(Option::as_ref)
                .filter(|block| block.nrows() == v.len() && block.ncols() >= k);
            // Scores compare eigenvalues to a few percent and eigenfunctions integrated
            // against descriptors: a relative residual of 1e-4 is ample (eigenvalue error ~
            // residual^2). Cold solves reach it at tolerance 1e-6, warm ones at 1e-8
            // (`residual_bound`).
            let params = EigenParams {
                k,
                tol: if seed.is_some() { 1e-8 } else { 1e-6 },
                ..EigenParams::default()
            };
            let mut solver = HamiltonianSolver::with_symbolic(full.dirichlet_symbolic()?, &mass, params)?;
            let s = match seed {
                Some(block) => {
                    solver.seed(block.clone())?;
                    solver.solve(&v)?
                }
                None => solver.solve_cold(&v)?,
            };
            let first = s.vectors.subcols(0, target.nrows().min(s.vectors.ncols()));
            let c = descriptor_projection(first, &mass, &desc_free);
            let mut diff = 0.0;
            for j in 0..c.nrows() {
                for col in 0..c.ncols() {
                    diff += (c[(j, col)] - target[(j, col)]).abs();
                }
            }
            let rc = s
                .values
                .iter()
                .zip(mu)
                .map(|(l, u)| ((l - u) / u).powi(2))
                .sum::<f64>();
            Ok((diff, rc))
        })
        .collect::<Result<_>>()?;
    let mut scores = vec![0.0; regions.len()];
    let mut region_cost = vec![0.0; regions.len()];
    for (&(_, ri), &(d, rc)) in jobs.iter().zip(&per_job) {
        scores[ri] += d;
        region_cost[ri] += rc;
    }
    Ok(RegionScores {
        descriptors: scores,
        region_cost,
    })
}

/// Most partial vertices [`partial_fits`] samples (every `ceil(n / this)`-th).
pub const PARTIAL_FIT_SAMPLES: usize = 1000;

/// Full-shape vertices per block of [`partial_fits`] (bounds its memory to
/// `PARTIAL_FIT_SAMPLES x PARTIAL_FIT_BLOCK` distances, ~16 MB, for any mesh size).
const PARTIAL_FIT_BLOCK: usize = 2048;

/// Partial-to-region descriptor fit of each region (lower is better): the mean, over a
/// sample of the partial's vertices $j$ (every `ceil(n_N / PARTIAL_FIT_SAMPLES)`-th), of
/// $\min_{i \in R} \lVert D_N(j) - D_M(i) \rVert$, the distance to the nearest descriptor
/// inside the region $R$ (rows of `d_full` are the full shape's vertices, of `d_part` the
/// partial's). Every local shape of the partial must be found in the region. SHOT's local
/// frames are right-handed, so a mirrored patch has a mirrored histogram: unlike the
/// eigenfunction projections (which average the descriptors over the region), this tells a
/// region from its mirror twin. NaN for an empty region.
pub fn partial_fits(d_full: &Mat<f64>, d_part: &Mat<f64>, regions: &[&[bool]]) -> Result<Vec<f64>> {
    if d_full.ncols() != d_part.ncols() {
        return Err(crate::error::Error::InvalidArgument(format!(
            "descriptors of {} and {} dimensions",
            d_full.ncols(),
            d_part.ncols()
        )));
    }
    if let Some(r) = regions.iter().find(|r| r.len() != d_full.nrows()) {
        return Err(crate::error::Error::InvalidArgument(format!(
            "a region of {} vertices for {} descriptors",
            r.len(),
            d_full.nrows()
        )));
    }
    let step = d_part.nrows().div_ceil(PARTIAL_FIT_SAMPLES).max(1);
    let sample: Vec<usize> = (0..d_part.nrows()).step_by(step).collect();
    let d = d_part.ncols();
    let a = Mat::<f64>::from_fn(sample.len(), d, |i, c| d_part[(sample[i], c)]);
    let a2: Vec<f64> = (0..a.nrows()).map(|i| (0..d).map(|c| a[(i, c)].powi(2)).sum()).collect();
    // Running minimum of the squared distance, per region and sampled vertex.
    let mut nearest = vec![vec![f64::INFINITY; sample.len()]; regions.len()];
    let n = d_full.nrows();
    for start in (0..n).step_by(PARTIAL_FIT_BLOCK) {
        let cols = PARTIAL_FIT_BLOCK.min(n - start);
        let block = d_full.as_ref().subrows(start, cols);
        let mut dot = Mat::<f64>::zeros(sample.len(), cols);
        faer::linalg::matmul::matmul(dot.as_mut(), faer::Accum::Replace, a.as_ref(), block.transpose(), 1.0, faer::Par::Seq);
        let b2: Vec<f64> = (0..cols).map(|j| (0..d).map(|c| block[(j, c)].powi(2)).sum()).collect();
        for (region, best) in regions.iter().zip(&mut nearest) {
            let inside: Vec<usize> = (0..cols).filter(|&j| region[start + j]).collect();
            // Column by column (the products are column-major); a minimum is exact in any order.
            for &j in &inside {
                let column = dot.col(j);
                for (i, b) in best.iter_mut().enumerate() {
                    *b = b.min(a2[i] + b2[j] - 2.0 * column[i]);
                }
            }
        }
    }
    Ok(nearest
        .iter()
        .map(|best| {
            if best.is_empty() || best[0].is_infinite() {
                f64::NAN
            } else {
                best.iter().map(|x| x.max(0.0).sqrt()).sum::<f64>() / best.len() as f64
            }
        })
        .collect())
}

/// $|\ln(L_R / L_N)|$: how far a region's boundary length $L_R$ is from the partial's $L_N$
/// (0 when equal; NaN when either is not positive).
pub fn boundary_misfit(region_length: f64, partial_length: f64) -> f64 {
    if region_length > 0.0 && partial_length > 0.0 {
        (region_length / partial_length).ln().abs()
    } else {
        f64::NAN
    }
}

/// Exponent $\gamma$ of the partial fit ([`partial_fits`]) in [`choose`]'s ranking (2 to 4 a
/// plateau on SHREC'16 CUTS; on every dev set 4 is at least as good as 2, 6 and 8 worse:
/// docs/benchmarks/options.md).
pub const PARTIAL_FIT_EXPONENT: f64 = 4.0;

/// Exponent $\delta$ of the vote share ([`vote_shares`]) in [`choose`]'s ranking
/// (docs/benchmarks/options.md, "Vote share").
pub const VOTE_SHARE_EXPONENT: f64 = 6.0;

/// Vote shares below this count as this in the ranking (a region with almost no vote is
/// ranked as one with 0.1 %, not infinitely worse).
const VOTE_SHARE_FLOOR: f64 = 1e-3;

/// Share of the partial's descriptor votes
/// ([`crate::alignment::starts::DescriptorMatches::votes`], one per vertex) that each region
/// holds: $s_R = \sum_{i \in R} c_i / \sum_i c_i$ (higher is better: the partial's
/// distinctive local shapes are found inside the region). NaN for no vote.
pub fn vote_shares(votes: &[f64], regions: &[&[bool]]) -> Result<Vec<f64>> {
    if let Some(r) = regions.iter().find(|r| r.len() != votes.len()) {
        return Err(crate::error::Error::InvalidArgument(format!("a region of {} vertices for {} votes", r.len(), votes.len())));
    }
    let total: f64 = votes.iter().sum();
    Ok(regions
        .iter()
        .map(|r| {
            if total > 0.0 {
                votes.iter().zip(r.iter()).filter(|(_, &inside)| inside).map(|(v, _)| v).sum::<f64>() / total
            } else {
                f64::NAN
            }
        })
        .collect())
}

/// The scores of one candidate region (lower is better for each but the vote share; `None`:
/// not computed).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct CandidateScore {
    /// Descriptor projection score ([`RegionScores::descriptors`]).
    pub descriptor_score: Option<f64>,
    /// Region cost ([`RegionScores::region_cost`]).
    pub region_cost: Option<f64>,
    /// [`boundary_misfit`] (`None` when a boundary length is 0).
    pub boundary_misfit: Option<f64>,
    /// [`partial_fits`] (`None` for an empty region).
    pub partial_fit: Option<f64>,
    /// [`vote_shares`] (higher is better; `None` without descriptor votes).
    #[serde(default)]
    pub vote_share: Option<f64>,
}

impl CandidateScore {
    /// $d\,f^\gamma \exp(\beta\,m) / s^\delta$: the descriptor score $d$, the partial fit $f$
    /// to the power [`PARTIAL_FIT_EXPONENT`], the [`boundary_misfit`] $m$ with weight
    /// [`BOUNDARY_WEIGHT`], the vote share $s$ (at least 0.001) to the power
    /// [`VOTE_SHARE_EXPONENT`] (a missing misfit counts as 0, a missing share as 1). `None` if
    /// $d$ or $f$ is missing.
    pub fn ranking(&self) -> Option<f64> {
        let m = self.boundary_misfit.filter(|m| !m.is_nan()).unwrap_or(0.0);
        let share = self.vote_share.filter(|s| s.is_finite()).map_or(1.0, |s| s.max(VOTE_SHARE_FLOOR));
        let r = self.descriptor_score? * self.partial_fit?.powf(PARTIAL_FIT_EXPONENT) * (BOUNDARY_WEIGHT * m).exp()
            / share.powf(VOTE_SHARE_EXPONENT);
        (!r.is_nan()).then_some(r)
    }
}

/// The chosen candidate (an index into `scores`; `None` for no candidate): among those whose
/// region's own spectra could be computed (a region cost is known; all of them if none is),
/// the lowest [`CandidateScore::ranking`]; ties go to the lower index, a missing ranking
/// ranks last. The spectra led the optimisation to the candidates; the descriptors, the
/// vote share, the partial fit (which tells a region from its mirror twin) and the boundary
/// choose among them. A region-cost gate (3x the lowest) was dropped with the vote share:
/// docs/benchmarks/options.md ("Vote share").
pub fn choose(scores: &[CandidateScore]) -> Option<usize> {
    let costed: Vec<usize> = (0..scores.len()).filter(|&i| scores[i].region_cost.is_some()).collect();
    let eligible = if costed.is_empty() { (0..scores.len()).collect() } else { costed };
    let key = |i: usize| scores[i].ranking().unwrap_or(f64::INFINITY);
    eligible.into_iter().min_by(|&a, &b| key(a).total_cmp(&key(b)).then(a.cmp(&b)))
}

/// How the starts agree with a choice, for studies (neither ranked results better than the
/// partial fit alone: [`confidence`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
pub struct Agreement {
    /// Fraction of the scored candidates (those with a region cost) whose region overlaps
    /// the chosen one's with IoU >= 0.5, the chosen one included.
    pub consensus: f64,
    /// How much worse the best-ranked *other* answer is: $\min \ln \rho_j - \ln \rho_c$ over
    /// scored candidates $j$ whose region overlaps the chosen one's with IoU < 0.5
    /// ($\rho$ = [`CandidateScore::ranking`]), at most [`MAX_MARGIN`] (also when there is none).
    pub margin: f64,
}

/// Cap of [`Agreement::margin`].
#[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
pub const MAX_MARGIN: f64 = 3.0;

/// The [`Agreement`] of the starts with candidate `chosen` (`regions[i]` the region of
/// candidate `i`). Consensus 0 and margin 0 when `chosen` is out of range.
#[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
pub fn agreement(regions: &[&[bool]], scores: &[CandidateScore], chosen: usize) -> Agreement {
    let (Some(&mine), Some(own)) = (regions.get(chosen), scores.get(chosen)) else {
        return Agreement { consensus: 0.0, margin: 0.0 };
    };
    let iou = |r: &[bool]| {
        let (both, either) = r.iter().zip(mine).fold((0usize, 0usize), |(b, e), (&x, &y)| (b + (x && y) as usize, e + (x || y) as usize));
        if either == 0 { 0.0 } else { both as f64 / either as f64 }
    };
    let log_rank = |s: &CandidateScore| s.ranking().filter(|r| *r > 0.0).map_or(f64::INFINITY, f64::ln);
    let scored: Vec<usize> = (0..regions.len().min(scores.len())).filter(|&i| scores[i].region_cost.is_some()).collect();
    let (mut agree, mut best_other) = (0usize, f64::INFINITY);
    for &i in &scored {
        if iou(regions[i]) >= 0.5 {
            agree += 1;
        } else {
            best_other = best_other.min(log_rank(&scores[i]));
        }
    }
    let consensus = if scored.is_empty() { 0.0 } else { agree as f64 / scored.len() as f64 };
    let margin = (best_other - log_rank(own)).min(MAX_MARGIN);
    Agreement { consensus, margin: if margin.is_nan() { 0.0 } else { margin } }
}

/// The similarity score of a localization, lower is more similar: the best *partial fit*
/// among its candidate regions $R$ (one per optimised start),
/// $$s = \min_R p(R), \qquad p(R) = \frac{1}{|J|}\sum_{j \in J}\ \min_{i \in R} \lVert D_N(j) - D_M(i) \rVert,$$
/// the mean distance from the partial's SHOT descriptors $D_N(j)$ (a sample $J$ of at most
/// 1000 of its vertices) to the nearest descriptor $D_M(i)$ of the optimisation vertices in
/// $R$ ([`partial_fits`]; docs/algorithm.md, "Searching several full shapes"). It asks
/// whether some region the spectra led to holds every local shape of the partial. SHOT
/// descriptors have unit norm and both shapes are scaled to unit full-shape area, so
/// $s \in [0, \sqrt 2]$ compares across full shapes of any size and meshing (at the same
/// `resolution`). It ranked best among the scores measured (the chosen region's fit,
/// spectral misfits, the descriptor projection, the confidence, combinations):
/// docs/algorithm.md ("Why this score"). `+inf` when no candidate has a fit (empty regions).
pub fn similarity_score(candidates: &[CandidateScore]) -> f64 {
    candidates
        .iter()
        .filter_map(|c| c.partial_fit)
        .filter(|fit| fit.is_finite())
        .fold(f64::INFINITY, f64::min)
        .max(0.0)
}

/// Weights of [`confidence`]: bias, partial fit, $\log_{10}$ of the region cost. A logistic
/// regression of "the right full shape and symmetry-aware IoU >= 0.5" over the 290 dev pairs
/// (each on its own full shape) and 148 localizations of dev partials on the other full shapes
/// of their set (docs/benchmarks/confidence/fit_confidence_models.py): the partial fit tells a
/// good region from a bad one on the right shape, the region cost tells the right shape from
/// another person's body, whose spectra no region matches as well
/// (docs/benchmarks/options.md, "Confidence from the partial fit and the region cost").
const CONFIDENCE_WEIGHTS: [f64; 3] = [9.5519, -16.5673, -1.1848];

/// Region costs below this count as this in [`confidence`] (an exact match is no better
/// evidence than a near one).
const CONFIDENCE_COST_FLOOR: f64 = 1e-6;

/// Region costs above this (and `+inf` or NaN) count as this in [`confidence`].
const CONFIDENCE_COST_CEILING: f64 = 1e6;

/// A region cost that could not be computed counts as this in [`confidence`] (as in the fit).
const CONFIDENCE_UNKNOWN_COST: f64 = 1e3;

/// How much to trust a chosen region, in [0, 1]: the estimated probability that the partial
/// is part of this full shape and the region overlaps the true one with IoU >= 0.5,
/// $\sigma(b + a f + c \log_{10} C)$ from the chosen candidate's partial fit $f$ (how far the
/// partial's descriptors are from the region's; 1 if unknown, clamped to [0, 10]) and its
/// region cost $C$ (how far the spectra of the region itself, as a step potential, are from the
/// partial's; $10^3$ if unknown, clamped to $[10^{-6}, 10^6]$, NaN counts as $10^6$). Both are
/// read off the region, not the optimisation's last iterate, so the confidence does not depend
/// on how many iterations ran.
pub fn confidence(chosen: &CandidateScore) -> f64 {
    let [b, a_fit, a_cost] = CONFIDENCE_WEIGHTS;
    let fit = chosen.partial_fit.filter(|v| v.is_finite()).unwrap_or(1.0).clamp(0.0, 10.0);
    let cost = match chosen.region_cost {
        None => CONFIDENCE_UNKNOWN_COST,
        Some(c) if c.is_nan() => CONFIDENCE_COST_CEILING,
        Some(c) => c.clamp(CONFIDENCE_COST_FLOOR, CONFIDENCE_COST_CEILING),
    };
    1.0 / (1.0 + (-(b + a_fit * fit + a_cost * cost.log10())).exp())
}

fn restrict_rows(m: &Mat<f64>, rows: &[u32]) -> Mat<f64> {
    Mat::from_fn(rows.len(), m.ncols(), |i, j| m[(rows[i] as usize, j)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn descriptor_projection_is_the_mass_weighted_sum_of_squared_eigenfunctions() {
        let (n, k, d) = (37, 3, 11);
        let phi = Mat::<f64>::from_fn(n, k, |i, j| ((i * 7 + j * 3) as f64).sin());
        let mass: Vec<f64> = (0..n).map(|i| 0.5 + (i % 5) as f64 * 0.1).collect();
        let desc = Mat::<f64>::from_fn(n, d, |i, c| ((i + 2 * c) as f64).cos());
        let out = descriptor_projection(phi.as_ref(), &mass, &desc);
        for j in 0..k {
            for c in 0..d {
                let want: f64 = (0..n).map(|i| phi[(i, j)].powi(2) * mass[i] * desc[(i, c)]).sum();
                assert!((out[(j, c)] - want).abs() < 1e-12 * (1.0 + want.abs()), "({j}, {c}): {} against {want}", out[(j, c)]);
            }
        }
    }

    #[test]
    fn agreement_counts_overlapping_starts_and_the_margin_to_the_best_other_answer() {
        let a = [true, true, true, false, false, false];
        let a2 = [true, true, true, true, false, false];
        let b = [false, false, false, true, true, true];
        let regions: Vec<&[bool]> = vec![&a, &a2, &b, &b];
        let sc = |d: f64, fit: f64| CandidateScore { descriptor_score: Some(d), region_cost: Some(1.0), boundary_misfit: Some(0.0), partial_fit: Some(fit), vote_share: None };
        let mut scores = vec![sc(1.0, 0.5), sc(2.0, 0.5), sc(4.0, 0.5), sc(8.0, 0.5)];
        let g = agreement(&regions, &scores, 0);
        assert_eq!(g.consensus, 0.5);
        assert!((g.margin - 4f64.ln()).abs() < 1e-12, "{}", g.margin);
        // A better-ranked disagreeing answer gives a negative margin; unscored starts do not count.
        scores[3] = sc(0.5, 0.5);
        assert!((agreement(&regions, &scores, 0).margin - 0.5f64.ln()).abs() < 1e-12);
        scores[2].region_cost = None;
        scores[3].region_cost = None;
        let g = agreement(&regions, &scores, 0);
        assert_eq!((g.consensus, g.margin), (1.0, MAX_MARGIN));
        assert_eq!(agreement(&regions, &scores, 9), Agreement { consensus: 0.0, margin: 0.0 });
    }

    #[test]
    fn confidence_is_a_probability_falling_with_a_worse_fit_or_region_cost() {
        let s = |fit: f64, cost: f64| CandidateScore { descriptor_score: Some(1.0), region_cost: Some(cost), boundary_misfit: Some(0.0), partial_fit: Some(fit), vote_share: None };
        let c = confidence(&s(0.45, 0.1));
        assert!(c > 0.0 && c < 1.0, "{c}");
        assert!(confidence(&s(0.40, 0.1)) > c && confidence(&s(0.50, 0.1)) < c);
        assert!(confidence(&s(0.45, 0.01)) > c && confidence(&s(0.45, 10.0)) < c);
        // Below the floor the cost no longer counts.
        assert_eq!(confidence(&s(0.45, 1e-9)), confidence(&s(0.45, 0.0)));
        for x in [f64::NAN, f64::INFINITY, -1e300, 0.0] {
            for cost in [f64::NAN, f64::INFINITY, -1.0, 0.0, 1e300] {
                let v = confidence(&s(x, cost));
                assert!((0.0..=1.0).contains(&v), "{x} {cost}: {v}");
            }
        }
        assert!((0.0..=1.0).contains(&confidence(&CandidateScore::default())));
        // An unknown region cost counts as 1e3.
        let unknown = CandidateScore { region_cost: None, ..s(0.45, 1.0) };
        assert_eq!(confidence(&unknown), confidence(&s(0.45, 1e3)));
    }

    /// A score with every entry known (NaN entries become `None`).
    fn score(desc: f64, region: f64, misfit: f64, fit: f64) -> CandidateScore {
        let some = |x: f64| (!x.is_nan()).then_some(x);
        CandidateScore { descriptor_score: some(desc), region_cost: some(region), boundary_misfit: some(misfit), partial_fit: some(fit), vote_share: None }
    }

    fn pick(desc: &[f64], region: &[f64], misfit: &[f64], fit: &[f64]) -> Option<usize> {
        let at = |v: &[f64], i: usize| v.get(i).copied().unwrap_or(f64::NAN);
        let scores: Vec<CandidateScore> =
            (0..desc.len()).map(|i| score(desc[i], at(region, i), at(misfit, i), fit.get(i).copied().unwrap_or(1.0))).collect();
        choose(&scores)
    }

    #[test]
    fn vote_share_is_the_fraction_of_votes_inside_and_divides_the_ranking() {
        let votes = [2.0, 1.0, 0.0, 1.0];
        let regions: [&[bool]; 3] = [&[true, false, false, false], &[false, true, true, true], &[false; 4]];
        assert_eq!(vote_shares(&votes, &regions).unwrap(), vec![0.5, 0.5, 0.0]);
        assert!(vote_shares(&[0.0; 4], &regions).unwrap().iter().all(|s| s.is_nan()));
        assert!(vote_shares(&votes[..3], &regions).is_err());
        // Twice the share: the ranking divided by 2^delta; a missing share counts as 1, a
        // zero share as the floor.
        let with = |s: Option<f64>| CandidateScore { vote_share: s, ..score(2.0, 1.0, 0.0, 0.5) }.ranking().unwrap();
        assert!((with(Some(0.25)) / with(Some(0.5)) - 2f64.powf(VOTE_SHARE_EXPONENT)).abs() < 1e-9);
        assert_eq!(with(None), with(Some(1.0)));
        assert_eq!(with(Some(0.0)), with(Some(VOTE_SHARE_FLOOR)));
    }

    #[test]
    fn partial_fit_is_the_mean_nearest_descriptor_distance_in_the_region() {
        // Descriptors in 2-D: full rows 0..4, partial rows 0..3; nearest over all: 0.1, 0, 0.5.
        let full = Mat::from_fn(4, 2, |i, c| [[0.0, 0.0], [1.0, 0.0], [0.0, 2.0], [5.0, 5.0]][i][c]);
        let part = Mat::from_fn(3, 2, |i, c| [[0.0, 0.1], [1.0, 0.0], [0.0, 2.5]][i][c]);
        let regions: [&[bool]; 3] = [&[true; 4], &[true, false, false, true], &[false; 4]];
        let f = partial_fits(&full, &part, &regions).unwrap();
        assert!((f[0] - 0.2).abs() < 1e-12, "{f:?}");
        // A smaller region fits no better; an empty one is NaN.
        assert!((f[1] - (0.1 + 1.0 + 2.5) / 3.0).abs() < 1e-12 && f[1] >= f[0], "{f:?}");
        assert!(f[2].is_nan());
        // Against brute force, over several blocks of full-shape vertices and with the
        // partial's vertices sampled down to at most PARTIAL_FIT_SAMPLES.
        let n = 2 * PARTIAL_FIT_BLOCK + 5;
        let big_full = Mat::from_fn(n, 3, |i, c| ((i * (c + 3)) % 17) as f64 + 0.1 * c as f64);
        let big_part = Mat::from_fn(2 * PARTIAL_FIT_SAMPLES + 1, 3, |i, c| ((i * (c + 5)) % 13) as f64 * 1.3);
        let region: Vec<bool> = (0..n).map(|i| i % 3 == 0 || i > n - 4).collect();
        let fit = partial_fits(&big_full, &big_part, &[&region]).unwrap()[0];
        let step = big_part.nrows().div_ceil(PARTIAL_FIT_SAMPLES);
        let rows: Vec<usize> = (0..big_part.nrows()).step_by(step).collect();
        assert!(rows.len() <= PARTIAL_FIT_SAMPLES);
        let brute = rows
            .iter()
            .map(|&r| {
                (0..n)
                    .filter(|&j| region[j])
                    .map(|j| (0..3).map(|c| (big_part[(r, c)] - big_full[(j, c)]).powi(2)).sum::<f64>().sqrt())
                    .fold(f64::INFINITY, f64::min)
            })
            .sum::<f64>()
            / rows.len() as f64;
        assert!((fit - brute).abs() < 1e-9, "{fit} vs {brute}");
        assert!(partial_fits(&full, &Mat::zeros(2, 3), &[]).is_err());
        assert!(partial_fits(&full, &part, &[&[true; 3]]).is_err());
    }

    #[test]
    fn partial_fit_tells_a_region_from_its_mirror_image() {
        // A chiral shape (four bumps of different sizes, not coplanar with the centre, so no
        // mirror maps it to itself) and its mirror image (x -> -x, faces reversed to keep the
        // normals outward). The partial, a cut of the shape, fits its own region better than
        // the same region of the mirror image: SHOT frames are right-handed.
        let bumps = [([0.0, 0.0, 1.0], 0.5), ([0.8, 0.6, 0.0], 0.35), ([0.0, -0.6, 0.8], 0.25), ([-0.6, 0.0, 0.8], 0.15)];
        let shape = crate::mesh::generate::icosphere(4)
            .map_positions(|p| {
                let r: f64 = 1.0
                    + bumps
                        .iter()
                        .map(|(c, h)| h * (-(0..3).map(|i| (p[i] - c[i]).powi(2)).sum::<f64>() / 0.1).exp())
                        .sum::<f64>();
                p.map(|x| x * r)
            })
            .unwrap();
        let mirror = crate::mesh::TriMesh::new(
            shape.vertices().iter().map(|p| [-p[0], p[1], p[2]]).collect(),
            shape.faces().iter().map(|f| [f[0], f[2], f[1]]).collect(),
        )
        .unwrap();
        let region: Vec<bool> = shape.vertices().iter().map(|p| p[2] > 0.2).collect();
        let faces: Vec<[u32; 3]> = shape.faces().iter().filter(|f| f.iter().all(|&i| region[i as usize])).copied().collect();
        let (partial, _) = crate::mesh::TriMesh::new_dropping_isolated(shape.vertices().to_vec(), faces).unwrap();
        let radius = 0.15;
        let describe = |m: &crate::mesh::TriMesh| crate::geometry::shot::shot_descriptors(m, radius, 3).unwrap();
        let d_part = describe(&partial);
        let own = partial_fits(&describe(&shape), &d_part, &[&region]).unwrap()[0];
        let mirrored = partial_fits(&describe(&mirror), &d_part, &[&region]).unwrap()[0];
        eprintln!("partial fit: own region {own:.4}, mirror image {mirrored:.4}");
        assert!(own < 0.7 * mirrored, "own {own}, mirrored {mirrored}");
    }

    #[test]
    fn choose_ranks_the_candidates_with_a_region_cost() {
        let desc = [40.0, 10.0, 30.0, 5.0];
        let region = [90.0, 3.0, 2.0, f64::NAN];
        // The lowest ranking among those with a region cost (not 3: unknown), whatever the cost.
        assert_eq!(pick(&desc, &region, &[], &[]), Some(1));
        assert_eq!(pick(&[1.0, 1e9, 30.0, 0.1], &region, &[], &[]), Some(0));
        // No known region cost: the ranking alone.
        assert_eq!(pick(&desc, &[], &[], &[]), Some(3));
        assert_eq!(choose(&[]), None);
        // Ties go to the lower index.
        assert_eq!(pick(&[2.0, 2.0], &[1.0, 1.0], &[], &[]), Some(0));
        // A higher vote share outweighs a descriptor score 2^6 times worse, not 2^7.
        let shared = |d: [f64; 2], v: [f64; 2]| {
            let s: Vec<CandidateScore> = (0..2).map(|i| CandidateScore { vote_share: Some(v[i]), ..score(d[i], 1.0, 0.0, 1.0) }).collect();
            choose(&s)
        };
        assert_eq!(shared([1.0, 60.0], [0.4, 0.8]), Some(1));
        assert_eq!(shared([1.0, 70.0], [0.4, 0.8]), Some(0));
        // A boundary far longer than the partial's (misfit ln 4) outweighs a 10% better
        // descriptor score; a missing misfit counts as a perfect fit.
        let misfit = [0.0, 4f64.ln(), f64::NAN];
        assert_eq!(pick(&[1.0, 0.9], &[1.0; 2], &misfit, &[]), Some(0));
        assert_eq!(pick(&[f64::INFINITY, 0.9, 0.95], &[1.0; 3], &misfit, &[]), Some(2));
        // Mirror twins: equal descriptor scores and region costs, the partial fit decides
        // (f^4: 0.40 against 0.45, a factor 1.60, outweighs a 50% worse descriptor score, not
        // a 70% one); a missing fit (an empty region) ranks last.
        assert_eq!(pick(&[1.0, 1.5], &[1.0; 2], &[], &[0.45, 0.40]), Some(1));
        assert_eq!(pick(&[1.0, 1.7], &[1.0; 2], &[], &[0.45, 0.40]), Some(0));
        assert_eq!(pick(&[1.0, 1.0], &[1.0; 2], &[], &[f64::NAN, 0.40]), Some(1));
        assert!((boundary_misfit(2.0, 1.0) - 2f64.ln()).abs() < 1e-15);
        assert_eq!(boundary_misfit(1.0, 2.0), boundary_misfit(2.0, 1.0));
        assert!(boundary_misfit(0.0, 1.0).is_nan());
    }
}
