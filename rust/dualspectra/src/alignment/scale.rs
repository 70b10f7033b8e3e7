//! The partial's scale when its units are unknown (`scale = auto`; docs/algorithm.md, "Units").
//!
//! SHOT descriptors (Tombari et al. 2010) describe the surface inside a support ball of radius
//! $r$; the full shape's are taken at $r_0$ = [`shot::DEFAULT_RADIUS_FRACTION`] (the full shape
//! has unit area). The partial multiplied by $s$ and described at $r_0$ is the partial described
//! at $r_0 / s$, so the hypothesis "the partial covers a fraction $a$ of the full shape's area"
//! ($s = \sqrt{a / A_N}$) is scored by
//! $$d(a) = \frac{1}{|P|}\sum_{p \in P} \min_{q} \lVert D_N(p;\, r_0/s) - D_M(q;\, r_0) \rVert,$$
//! the mean distance of the partial's keypoints $P$ to their nearest full-shape descriptor:
//! at the right scale the partial's patches look like the full shape's; and by the
//! consistency $c(a)$ of those nearest matches ([`match_consistency`]: right matches keep the
//! partial's distances). $a$ is scanned on a log grid over $[10^{-2}, 1]$ for the lowest
//! $\ln d - \frac12 \ln(c + 0.05)$ and refined by a parabola through the best point and its
//! neighbours (in $\log a$). Measured per dev set in docs/benchmarks/options.md (`scale`).

use crate::error::{Error, Result};
use crate::geometry::shot;
use crate::mesh::{distance, TriMesh};
use faer::Mat;

/// Smallest area fraction considered: a partial of less than 1 % of the full shape carries too
/// little of it to place (and to size).
pub const MIN_AREA_FRACTION: f64 = 1e-2;
/// Grid points per decade of area fraction (a step of about 10 % in the linear factor).
const STEPS_PER_DECADE: usize = 12;
/// The scan's first pass takes every this many hypotheses (a step of about 21 % in $s$).
const COARSE_STRIDE: usize = 2;
/// The scan's second pass refines around this many of the first pass's lowest local minima
/// (the descriptor distance can have a narrow dip beside a flat stretch).
const REFINED_MINIMA: usize = 2;
/// Support points a keypoint's SHOT ball holds at most (about) in the scan: the partial's
/// cloud is thinned ([`shot::support_cloud`]) for the hypotheses whose radius would hold
/// more. Only hypotheses of small area are thinned; on every dev pair the estimate is the
/// same as with every vertex, in 0.5-0.7x the time (docs/benchmarks/options.md, `scale`).
const SUPPORT_PER_KEYPOINT: f64 = 1000.0;
/// Fewest points a thinned cloud keeps.
const MIN_SUPPORT_CLOUD: f64 = 500.0;
/// Partial keypoints described per hypothesis.
const KEYPOINTS: usize = 200;

/// The partial's side of the scale estimate: its keypoints and their descriptors
/// under each area hypothesis, each computed when a scan first needs it and kept. A search
/// sizes one partial on many full shapes; the descriptors under hypothesis $a$ (support
/// radius $r_0\sqrt{A_N/a}$ in the partial's units) are the same for every full shape, so
/// they are computed once per query rather than once per shape.
pub(crate) struct ScaleScan {
    partial: TriMesh,
    area: f64,
    keypoints: Vec<u32>,
    /// The distance between keypoints `i < j`, row by row (`(0, 1), (0, 2), ..., (1, 2), ...`).
    keypoint_distances: Vec<f64>,
    log_a: Vec<f64>,
    descriptors: Vec<std::sync::OnceLock<Mat<f64>>>,
}

impl ScaleScan {
    /// The scan of `partial` (any units): nothing is described yet.
    pub(crate) fn new(partial: TriMesh) -> Result<Self> {
        let area = partial.area();
        if !(area > 0.0 && area.is_finite()) {
            return Err(Error::InvalidArgument("scale = auto: the partial has no area to estimate the scale from".into()));
        }
        let n = partial.n_vertices();
        let step = n.div_ceil(KEYPOINTS).max(1);
        let keypoints: Vec<u32> = (0..n as u32).step_by(step).collect();
        let keypoint_distances = pairwise_distances(partial.vertices(), &keypoints);
        let log_a = area_grid();
        let descriptors = (0..log_a.len()).map(|_| std::sync::OnceLock::new()).collect();
        Ok(ScaleScan { partial, area, keypoints, keypoint_distances, log_a, descriptors })
    }

    /// The partial it scans.
    pub(crate) fn partial(&self) -> &TriMesh {
        &self.partial
    }

    /// The partial's keypoint descriptors under hypothesis `i` of the grid, described once.
    fn descriptors(&self, i: usize) -> Result<&Mat<f64>> {
        if let Some(d) = self.descriptors[i].get() {
            return Ok(d);
        }
        let s = (10f64.powf(self.log_a[i]) / self.area).sqrt();
        let radius = shot::DEFAULT_RADIUS_FRACTION / s;
        // Expected support points per keypoint: n pi r^2 / A_N; the cloud is thinned to keep
        // about SUPPORT_PER_KEYPOINT of them (only the small-area hypotheses, whose radius
        // holds most of the partial).
        let cloud = (SUPPORT_PER_KEYPOINT * self.area / (std::f64::consts::PI * radius * radius)).max(MIN_SUPPORT_CLOUD) as usize;
        let d = shot::shot_keypoint_descriptors_thinned(&self.partial, &self.keypoints, radius, shot::DEFAULT_MIN_NEIGHBORS, cloud)?;
        Ok(self.descriptors[i].get_or_init(|| d))
    }

    /// The estimated area fraction $a^*$ of the scanned partial (area $A_N$, in the units of a
    /// full shape of unit area, possibly wrong) on a full shape, and the factor
    /// $s = \sqrt{a^* / A_N}$ that brings it to the full shape's units. `full_descriptors`: SHOT
    /// at [`shot::DEFAULT_RADIUS_FRACTION`] on the full shape of unit area (rows: keypoints),
    /// taken at `full_positions` (one per row).
    pub(crate) fn estimate(&self, full_descriptors: &Mat<f64>, full_positions: &[[f64; 3]]) -> Result<(f64, f64)> {
        if full_descriptors.nrows() == 0 {
            return Err(Error::InvalidArgument("scale = auto: no full-shape descriptor to estimate the scale from".into()));
        }
        if full_positions.len() != full_descriptors.nrows() {
            return Err(Error::InvalidArgument(format!(
                "scale = auto: {} full-shape descriptors but {} positions",
                full_descriptors.nrows(),
                full_positions.len()
            )));
        }
        let (log_a, area) = (&self.log_a, self.area);
        let count = log_a.len();
        let full32 = SingleRows::new(full_descriptors);
        let hypothesis = |i: usize| -> Result<Hypothesis> {
            let s = (10f64.powf(log_a[i]) / area).sqrt();
            let d = self.descriptors(i)?;
            let (distances, matches) = nearest_rows(full_descriptors, &full32, d);
            let distance = distances.iter().sum::<f64>() / distances.len() as f64;
            let consistency = match_consistency(&self.keypoint_distances, s, full_positions, &matches);
            Ok(Hypothesis { distance, consistency })
        };
        let (best, costs) = coarse_to_fine_minimum(count, |i| Ok(hypothesis(i)?.cost()))?;
        let cost = |i: usize| costs[i].unwrap_or(f64::INFINITY);
        let la = if best > 0 && best + 1 < count {
            let (y0, y1, y2) = (cost(best - 1), cost(best), cost(best + 1));
            let h = log_a[1] - log_a[0];
            let curvature = y0 - 2.0 * y1 + y2;
            let offset = if curvature > 0.0 && curvature.is_finite() { 0.5 * (y0 - y2) / curvature } else { 0.0 };
            log_a[best] + offset.clamp(-0.5, 0.5) * h
        } else {
            log_a[best]
        };
        let fraction = 10f64.powf(la);
        Ok((fraction, (fraction / area).sqrt()))
    }
}

/// One area hypothesis scored: the mean descriptor distance to the full shape and the
/// consistency of the nearest-descriptor matches ([`match_consistency`]).
#[derive(Clone, Copy, Debug)]
struct Hypothesis {
    distance: f64,
    consistency: f64,
}

impl Hypothesis {
    /// $\ln d - $ [`CONSISTENCY_WEIGHT`] $\ln(c + $ [`CONSISTENCY_FLOOR`]$)$: a low
    /// descriptor distance $d$ with consistent matches $c$.
    fn cost(&self) -> f64 {
        self.distance.ln() - CONSISTENCY_WEIGHT * (self.consistency + CONSISTENCY_FLOOR).ln()
    }
}

/// Weight of the matches' consistency against the descriptor distance (in logarithms).
const CONSISTENCY_WEIGHT: f64 = 0.5;
/// Added to the consistency before its logarithm: a hypothesis with no consistent pair is
/// not ruled out by that alone.
const CONSISTENCY_FLOOR: f64 = 0.05;

/// Largest $|\ln(f/e)|$ of a consistent pair (20 %).
const CONSISTENT_LOG_RATIO: f64 = 0.2;

/// The distances between `points[keypoints[i]]` and `points[keypoints[j]]` for `i < j`, row by
/// row: the input of [`match_consistency`].
fn pairwise_distances(points: &[[f64; 3]], keypoints: &[u32]) -> Vec<f64> {
    (0..keypoints.len())
        .flat_map(|i| keypoints[i + 1..].iter().map(move |&j| (keypoints[i], j)))
        .map(|(i, j)| distance(points[i as usize], points[j as usize]))
        .collect()
}

/// The fraction of pairs of partial keypoints (distance `keypoint_distances` times `s`, the
/// pairs $i < j$ row by row, farther apart than the SHOT radius $r_0$) whose distance $e$ is
/// kept by their nearest-descriptor matches on the full shape (distance $f$):
/// $|\ln(f/e)| <$ [`CONSISTENT_LOG_RATIO`], tested as $e^{-0.2} < f/e < e^{0.2}$. Matches at the
/// right scale are near their true places, so they keep the partial's distances; at a wrong
/// scale they scatter. `matches` (one per keypoint) index `full_positions`.
fn match_consistency(keypoint_distances: &[f64], s: f64, full_positions: &[[f64; 3]], matches: &[usize]) -> f64 {
    let (low, high) = ((-CONSISTENT_LOG_RATIO).exp(), CONSISTENT_LOG_RATIO.exp());
    let (mut pairs, mut consistent) = (0usize, 0usize);
    let mut distances = keypoint_distances.iter();
    for i in 0..matches.len() {
        let from = full_positions[matches[i]];
        for (&to, &d) in matches[i + 1..].iter().zip(distances.by_ref()) {
            let e = s * d;
            if e <= shot::DEFAULT_RADIUS_FRACTION {
                continue;
            }
            pairs += 1;
            let ratio = distance(from, full_positions[to]) / e;
            if ratio > low && ratio < high {
                consistent += 1;
            }
        }
    }
    if pairs == 0 { 0.0 } else { consistent as f64 / pairs as f64 }
}

/// The index of the lowest of `count` costs found by scanning every [`COARSE_STRIDE`]-th
/// index, then every index within `COARSE_STRIDE - 1` of each of the [`REFINED_MINIMA`]
/// lowest local minima of that scan; the costs evaluated (`None`: skipped). The minimum found
/// has both its neighbours evaluated, and is the lowest of all when it lies within one of
/// those windows (always for costs that fall, then rise). Each pass scores its indices in
/// parallel.
fn coarse_to_fine_minimum(count: usize, cost_of: impl Fn(usize) -> Result<f64> + Sync) -> Result<(usize, Vec<Option<f64>>)> {
    use rayon::prelude::*;
    let mut costs: Vec<Option<f64>> = vec![None; count];
    // Each pass's new indices are scored side by side (each cost is independent of the others).
    let evaluate = |wanted: Vec<usize>, costs: &mut [Option<f64>]| -> Result<()> {
        let fresh: Vec<usize> = wanted.into_iter().filter(|&i| costs[i].is_none()).collect();
        let values = fresh.par_iter().map(|&i| cost_of(i)).collect::<Result<Vec<f64>>>()?;
        for (i, v) in fresh.into_iter().zip(values) {
            costs[i] = Some(v);
        }
        Ok(())
    };
    let coarse: Vec<usize> = (0..count).step_by(COARSE_STRIDE).collect();
    evaluate(coarse.clone(), &mut costs)?;
    let coarse_costs: Vec<f64> = coarse.iter().map(|&i| costs[i].unwrap_or(f64::INFINITY)).collect();
    // Local minima of the first pass; a flat stretch counts once (at its start).
    let mut minima: Vec<usize> = (0..coarse.len())
        .filter(|&j| (j == 0 || coarse_costs[j] < coarse_costs[j - 1]) && (j + 1 == coarse.len() || coarse_costs[j] <= coarse_costs[j + 1]))
        .collect();
    minima.sort_by(|&a, &b| coarse_costs[a].total_cmp(&coarse_costs[b]).then(a.cmp(&b)));
    let mut refined = Vec::new();
    for &j in minima.iter().take(REFINED_MINIMA) {
        let centre = coarse[j];
        refined.extend(centre.saturating_sub(COARSE_STRIDE - 1)..(centre + COARSE_STRIDE).min(count));
    }
    evaluate(refined, &mut costs)?;
    let cost = |i: usize| costs[i].unwrap_or(f64::INFINITY);
    let best = (0..count).min_by(|&a, &b| cost(a).total_cmp(&cost(b))).unwrap_or(0);
    Ok((best, costs))
}

/// The area-fraction hypotheses, $\log_{10} a$ from $\log_{10}$ [`MIN_AREA_FRACTION`] to 0,
/// [`STEPS_PER_DECADE`] per decade.
pub(crate) fn area_grid() -> Vec<f64> {
    let decades = -MIN_AREA_FRACTION.log10();
    let count = (decades * STEPS_PER_DECADE as f64).round() as usize + 1;
    (0..count).map(|i| -decades + decades * i as f64 / (count - 1) as f64).collect()
}

/// Per row of `query`, the Euclidean distance to the nearest row of `model` (single
/// precision; `model_norms2` are `model`'s squared row norms), by blocks of `query`.
pub(crate) fn nearest_distances(model: &Mat<f32>, model_norms2: &[f32], query: faer::MatRef<'_, f32>) -> Vec<f32> {
    const BLOCK: usize = 1024;
    let mut out = vec![f32::INFINITY; query.nrows()];
    if model.nrows() == 0 || model.ncols() != query.ncols() {
        return out;
    }
    for start in (0..query.nrows()).step_by(BLOCK) {
        let rows = BLOCK.min(query.nrows() - start);
        let q = query.subrows(start, rows);
        let mut dot = Mat::<f32>::zeros(model.nrows(), rows);
        faer::linalg::matmul::matmul(dot.as_mut(), faer::Accum::Replace, model.as_ref(), q.transpose(), 1.0f32, faer::Par::Seq);
        for j in 0..rows {
            let q2: f32 = (0..q.ncols()).map(|c| q[(j, c)] * q[(j, c)]).sum();
            let best = (0..model.nrows()).map(|r| model_norms2[r] - 2.0 * dot[(r, j)]).fold(f32::INFINITY, f32::min);
            out[start + j] = (best + q2).max(0.0).sqrt();
        }
    }
    out
}

/// Descriptor rows in single precision with their squared norms: the side of a
/// nearest-descriptor search whose products are taken in single precision
/// ([`nearest_rows`], [`crate::alignment::starts::descriptor_matches`]).
pub(crate) struct SingleRows {
    pub(crate) rows: Mat<f32>,
    pub(crate) norms2: Vec<f32>,
}

impl SingleRows {
    /// Every row of `m`.
    pub(crate) fn new(m: &Mat<f64>) -> Self {
        Self::of_rows(m, &(0..m.nrows()).collect::<Vec<_>>())
    }

    /// The rows `rows` of `m`, in that order.
    pub(crate) fn of_rows(m: &Mat<f64>, rows: &[usize]) -> Self {
        let rows = Mat::<f32>::from_fn(rows.len(), m.ncols(), |i, c| m[(rows[i], c)] as f32);
        let norms2 = (0..rows.nrows()).map(|i| (0..rows.ncols()).map(|c| rows[(i, c)] * rows[(i, c)]).sum()).collect();
        SingleRows { rows, norms2 }
    }
}

/// Per row of `partial`, the nearest row of `full` (ties to the lower row) and its Euclidean
/// distance: found from single-precision distances to `full32` (`full` converted; by blocks
/// of `full`: memory bounded), measured in double precision.
fn nearest_rows(full: &Mat<f64>, full32: &SingleRows, partial: &Mat<f64>) -> (Vec<f64>, Vec<usize>) {
    const BLOCK: usize = 512;
    let d = full.ncols();
    if partial.nrows() == 0 || partial.ncols() != d || full32.rows.nrows() != full.nrows() {
        return (vec![f64::INFINITY; partial.nrows()], vec![0; partial.nrows()]);
    }
    let query = SingleRows::new(partial);
    let mut nearest = vec![f32::INFINITY; partial.nrows()];
    let mut row = vec![0usize; partial.nrows()];
    for start in (0..full.nrows()).step_by(BLOCK) {
        let rows = BLOCK.min(full.nrows() - start);
        let mut dot = Mat::<f32>::zeros(rows, partial.nrows());
        faer::linalg::matmul::matmul(dot.as_mut(), faer::Accum::Replace, full32.rows.as_ref().subrows(start, rows), query.rows.transpose(), 1.0f32, faer::Par::Seq);
        for r in 0..rows {
            let f2 = full32.norms2[start + r];
            for (j, best) in nearest.iter_mut().enumerate() {
                let distance2 = (f2 + query.norms2[j] - 2.0 * dot[(r, j)]).max(0.0);
                if distance2 < *best {
                    *best = distance2;
                    row[j] = start + r;
                }
            }
        }
    }
    let distances = row.iter().enumerate().map(|(j, &r)| (0..d).map(|c| (full[(r, c)] - partial[(j, c)]).powi(2)).sum::<f64>().sqrt()).collect();
    (distances, row)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluation::synthetic::{cut_by_plane, default_limbs, figure};

    /// A plane cut of a figure with limbs, given in other units, is sized back.
    #[test]
    fn a_part_in_other_units_is_sized_back() {
        let full = figure(4, &default_limbs()).unwrap();
        let unit = 1.0 / full.area().sqrt();
        let full = full.map_positions(|p| p.map(|c| c * unit)).unwrap();
        let keypoints: Vec<u32> = (0..full.n_vertices() as u32).collect();
        let descriptors =
            shot::shot_keypoint_descriptors(&full, &keypoints, shot::DEFAULT_RADIUS_FRACTION, shot::DEFAULT_MIN_NEIGHBORS).unwrap();
        let (cut, _) = cut_by_plane(&full, [0.3, 1.0, 0.2], 0.0).unwrap();
        let truth = cut.area();
        assert!((0.1..0.9).contains(&truth), "cut area {truth}");
        for factor in [1e-3, 1.0, 1e3] {
            let given = cut.map_positions(|p| p.map(|c| c * factor)).unwrap();
            let (fraction, s) = ScaleScan::new(given).unwrap().estimate(&descriptors, full.vertices()).unwrap();
            let error = (fraction / truth).sqrt();
            assert!((0.85..1.18).contains(&error), "factor {factor}: fraction {fraction} vs {truth}");
            assert!((s * factor - 1.0).abs() < 0.18, "factor {factor}: s {s}");
        }
    }

    /// A scan shared by several full shapes gives each the estimate a fresh scan gives (the
    /// partial's descriptors do not depend on the full shape), and keeps what it described.
    #[test]
    fn a_shared_scan_estimates_as_a_fresh_one() {
        let described = |mesh: &TriMesh| {
            let unit = 1.0 / mesh.area().sqrt();
            let mesh = mesh.map_positions(|p| p.map(|c| c * unit)).unwrap();
            let keypoints: Vec<u32> = (0..mesh.n_vertices() as u32).collect();
            let d = shot::shot_keypoint_descriptors(&mesh, &keypoints, shot::DEFAULT_RADIUS_FRACTION, shot::DEFAULT_MIN_NEIGHBORS).unwrap();
            (d, mesh)
        };
        let (d4, f4) = described(&figure(4, &default_limbs()).unwrap());
        let (d3, f3) = described(&figure(3, &default_limbs()).unwrap());
        let (cut, _) = cut_by_plane(&f4, [0.3, 1.0, 0.2], 0.0).unwrap();
        let shared = ScaleScan::new(cut.clone()).unwrap();
        for (d, f) in [(&d4, &f4), (&d3, &f3), (&d4, &f4)] {
            let fresh = ScaleScan::new(cut.clone()).unwrap().estimate(d, f.vertices()).unwrap();
            assert_eq!(shared.estimate(d, f.vertices()).unwrap(), fresh);
        }
        assert!(shared.descriptors.iter().any(|d| d.get().is_some()));
    }

    /// On costs that fall, then rise, the scan finds the lowest of all with at most 17 of 25
    /// evaluations, wherever it lies; a narrow dip between two coarse points is found beside
    /// a lower flat stretch elsewhere; an error is passed on.
    #[test]
    fn coarse_to_fine_scan_finds_a_single_minimum() {
        for m in 0..25usize {
            let evaluated = std::sync::atomic::AtomicUsize::new(0);
            let (best, costs) = coarse_to_fine_minimum(25, |i| {
                evaluated.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                Ok((i as f64 - m as f64 - 0.3).powi(2))
            })
            .unwrap();
            let evaluated = evaluated.into_inner();
            assert_eq!(best, m);
            assert!(evaluated <= 17, "{evaluated} evaluations");
            assert_eq!(costs.iter().filter(|c| c.is_some()).count(), evaluated);
            for n in [best.wrapping_sub(1), best + 1] {
                if n < 25 {
                    assert!(costs[n].is_some(), "neighbour {n} of {best} not scored");
                }
            }
        }
        // A flat stretch at 0.5 from 20 on, a dip to 0.4 at 17 between coarse points at 0.52
        // and 0.55 (the shape of SHREC'16 HOLES victoria 3's costs).
        let plateau = |i: usize| Ok(match i { 17 => 0.4, 18 | 19 => 0.55, 20.. => 0.5, _ => 1.0 - 0.03 * i as f64 });
        assert_eq!(coarse_to_fine_minimum(25, plateau).unwrap().0, 17);
        assert!(coarse_to_fine_minimum(25, |i| if i == 10 { Err(Error::InvalidArgument("x".into())) } else { Ok(0.0) }).is_err());
    }

    /// Matches at their true places keep every distance (consistency 1); the same matches
    /// under a factor off by 2 keep none; matches scattered (reversed) keep few.
    #[test]
    fn consistency_counts_the_distances_kept() {
        let mesh = crate::mesh::generate::grid(1.0, 1.0, 12, 12);
        let keypoints: Vec<u32> = (0..mesh.n_vertices() as u32).collect();
        let identity: Vec<usize> = (0..mesh.n_vertices()).collect();
        let positions = mesh.vertices();
        let distances = pairwise_distances(positions, &keypoints);
        assert_eq!(match_consistency(&distances, 1.0, positions, &identity), 1.0);
        assert_eq!(match_consistency(&distances, 2.0, positions, &identity), 0.0);
        let reversed: Vec<usize> = identity.iter().rev().copied().collect();
        let scattered = match_consistency(&distances, 1.0, positions, &reversed);
        // Reversal is a point reflection of the square: it keeps distances.
        assert_eq!(scattered, 1.0);
        let shuffled: Vec<usize> = identity.iter().map(|&i| (i * 37 + 11) % identity.len()).collect();
        let c = match_consistency(&distances, 1.0, positions, &shuffled);
        assert!(c < 0.3, "shuffled matches: consistency {c}");
        // No pair farther apart than the SHOT radius: nothing to count.
        assert_eq!(match_consistency(&distances, 1e-3, positions, &identity), 0.0);
    }

    /// The ratio test is the definition $|\ln(f/e)| < 0.2$: the same fraction as the
    /// logarithm on every pair, for matches near and far and factors around the truth.
    #[test]
    fn consistency_is_the_log_ratio_rule() {
        let mesh = crate::mesh::generate::grid(1.0, 1.0, 15, 11);
        let positions = mesh.vertices();
        let keypoints: Vec<u32> = (0..mesh.n_vertices() as u32).step_by(2).collect();
        let distances = pairwise_distances(positions, &keypoints);
        let by_logarithm = |s: f64, matches: &[usize]| {
            let (mut pairs, mut kept) = (0, 0);
            for i in 0..keypoints.len() {
                for j in i + 1..keypoints.len() {
                    let e = s * distance(positions[keypoints[i] as usize], positions[keypoints[j] as usize]);
                    if e > shot::DEFAULT_RADIUS_FRACTION {
                        pairs += 1;
                        kept += usize::from((distance(positions[matches[i]], positions[matches[j]]) / e).ln().abs() < CONSISTENT_LOG_RATIO);
                    }
                }
            }
            kept as f64 / pairs as f64
        };
        let n = positions.len();
        let mut partly = 0;
        for shift in [0usize, 1, 7, 40] {
            let matches: Vec<usize> = keypoints.iter().map(|&k| (k as usize * 13 * usize::from(shift > 1) + k as usize + shift) % n).collect();
            for s in [0.7, 0.9, 1.0, 1.15, 1.3] {
                let c = match_consistency(&distances, s, positions, &matches);
                assert_eq!(c, by_logarithm(s, &matches), "shift {shift}, factor {s}");
                partly += usize::from(c > 0.05 && c < 0.95);
            }
        }
        assert!(partly >= 5, "only {partly} cases keep some pairs and lose others");
    }

    /// The cost falls with the descriptor distance and with the consistency.
    #[test]
    fn cost_prefers_near_and_consistent_matches() {
        let h = |distance, consistency| Hypothesis { distance, consistency }.cost();
        assert!(h(0.4, 0.2) < h(0.5, 0.2));
        assert!(h(0.4, 0.3) < h(0.4, 0.2));
        assert!(h(0.4, 0.0).is_finite());
    }

    /// The nearest rows found in single precision, measured in double precision: each
    /// distance within single precision's rounding of the brute-force double-precision
    /// nearest distance, across a block boundary; an exact copy is found at distance 0.
    #[test]
    fn nearest_rows_match_a_double_precision_search() {
        let (n, m, d) = (700, 90, 20);
        let value = |i: usize, c: usize| ((i * 7919 + c * 104_729) % 1000) as f64 / 1000.0 - 0.5 + (i as f64 * 0.37 + c as f64).sin() * 0.1;
        let full = Mat::<f64>::from_fn(n, d, value);
        let mut partial = Mat::<f64>::from_fn(m, d, |i, c| value(i + n + 3, c));
        for c in 0..d {
            partial[(0, c)] = full[(600, c)];
        }
        let (distances, rows) = nearest_rows(&full, &SingleRows::new(&full), &partial);
        for j in 0..m {
            let dist = |i: usize| (0..d).map(|c| (full[(i, c)] - partial[(j, c)]).powi(2)).sum::<f64>().sqrt();
            let best = (0..n).map(dist).fold(f64::INFINITY, f64::min);
            assert!((distances[j] - best).abs() < 1e-5 * (1.0 + best), "row {j}: {} against {best}", distances[j]);
            assert_eq!(distances[j], dist(rows[j]));
        }
        assert_eq!((distances[0], rows[0]), (0.0, 600));
    }

    #[test]
    fn no_full_shape_descriptor_is_an_error() {
        let mesh = crate::mesh::generate::grid(1.0, 1.0, 3, 3);
        let scan = ScaleScan::new(mesh).unwrap();
        assert!(scan.estimate(&Mat::zeros(0, 352), &[]).is_err());
        // Descriptors without one position each.
        assert!(scan.estimate(&Mat::zeros(2, 352), &[[0.0; 3]]).is_err());
    }
}
