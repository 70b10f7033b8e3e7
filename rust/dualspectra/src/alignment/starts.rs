//! Initial relaxed potentials $w_0$ (docs/algorithm.md, "Starts"): the sides of planes
//! normal to the principal axes; the regions whose SHOT descriptors the partial's resemble;
//! and given regions; each a step $w_0 = 2 - 4 R_0$ (low potential, the candidate region, on
//! the mask $R_0$).

/// A starting point of the optimisation.
#[derive(Debug, Clone)]
pub struct Start {
    pub w0: Vec<f64>,
    pub label: String,
    /// Kind of start ("well": a plane cut; "mask": a given or descriptor region).
    pub family: &'static str,
}

/// Most plane-cut directions (see [`plane_cut_directions`]).
pub const MAX_PLANE_CUTS: usize = 26;

/// Up to 26 unit directions in the frame $(e_1, e_2, e_3)$ of the shape's principal axes
/// (area-weighted covariance of the vertex positions, $e_1$ the largest variance): first
/// $\pm e_1, \pm e_2, \pm e_3$, then the 8 diagonals $(\pm e_1 \pm e_2 \pm e_3)/\sqrt 3$, then the
/// 12 face diagonals $(\pm e_i \pm e_j)/\sqrt 2$. Every prefix of length 6, 14 or 26 holds each
/// direction with its opposite, so it does not depend on the axes' signs.
pub fn plane_cut_directions(points: &[[f64; 3]], mass: &[f64], count: usize) -> Vec<[f64; 3]> {
    let total: f64 = mass.iter().sum();
    let mut c = [0.0; 3];
    for (p, &m) in points.iter().zip(mass) {
        for k in 0..3 {
            c[k] += m * p[k] / total;
        }
    }
    let mut cov = [[0.0; 3]; 3];
    for (p, &m) in points.iter().zip(mass) {
        for i in 0..3 {
            for j in 0..3 {
                cov[i][j] += m * (p[i] - c[i]) * (p[j] - c[j]);
            }
        }
    }
    let (_, axes) = crate::geometry::shot::sym_eigen3(cov);
    let mut frame: Vec<[f64; 3]> = Vec::with_capacity(MAX_PLANE_CUTS);
    for e in &axes {
        frame.push(*e);
        frame.push(e.map(|x| -x));
    }
    let combine = |w: [f64; 3]| -> [f64; 3] {
        let mut d = [0.0; 3];
        for (a, e) in w.iter().zip(&axes) {
            for k in 0..3 {
                d[k] += a * e[k];
            }
        }
        let l = crate::geometry::angles::norm(d);
        d.map(|x| x / l)
    };
    for s in 0..8 {
        let sign = |b: usize| if s >> b & 1 == 0 { 1.0 } else { -1.0 };
        frame.push(combine([sign(0), sign(1), sign(2)]));
    }
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        for s in 0..4 {
            let mut w = [0.0; 3];
            w[i] = if s & 1 == 0 { 1.0 } else { -1.0 };
            w[j] = if s & 2 == 0 { 1.0 } else { -1.0 };
            frame.push(combine(w));
        }
    }
    frame.truncate(count.min(MAX_PLANE_CUTS));
    frame
}

/// Plane-cut starts: for each of the first `count` directions $d$ of [`plane_cut_directions`],
/// a well on the vertices of largest $\langle x, d \rangle$ up to the partial's `area` (the
/// side of a plane normal to $d$), $w_0 = 2 - 4 R_d$ (labels `plane{j}`). A partial cut off
/// by one roughly planar cut through the body (a half, the front of a torso), which no ball
/// around an extremity approximates, is one side of such a plane.
#[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
pub fn plane_cut_starts(points: &[[f64; 3]], mass: &[f64], area: f64, count: usize) -> Vec<Start> {
    plane_cut_starts_from_heights(&plane_heights(points, mass, count), mass, area)
}

/// $\langle x_i, d \rangle$ for each of the first `count` directions $d$ of
/// [`plane_cut_directions`]: what [`plane_cut_starts`] needs of the shape, computed once.
pub fn plane_heights(points: &[[f64; 3]], mass: &[f64], count: usize) -> Vec<Vec<f64>> {
    plane_cut_directions(points, mass, count)
        .iter()
        .map(|d| points.iter().map(|&p| crate::geometry::angles::dot(p, *d)).collect())
        .collect()
}

/// [`plane_cut_starts`] from the [`plane_heights`].
pub fn plane_cut_starts_from_heights(heights: &[Vec<f64>], mass: &[f64], area: f64) -> Vec<Start> {
    heights
        .iter()
        .enumerate()
        .map(|(j, height)| plane_cut_start(j, &crate::geometry::area_matched_set(height, mass, area)))
        .collect()
}

/// The start of plane-cut direction `j` from its area-matched `region` (label `plane{j}`).
fn plane_cut_start(j: usize, region: &[bool]) -> Start {
    let mut start = mask_start(region, &format!("plane{j}"));
    start.family = "well";
    start
}

/// Plane-cut starts optimised beside the descriptor starts: the ones whose regions hold the
/// most descriptor votes ([`most_voted_plane_cut_starts`]). On every dev pair the choice among
/// all 6 was the most voted one or a descriptor start (docs/benchmarks/options.md,
/// `plane_cuts`).
pub const PLANE_CUTS_OPTIMISED: usize = 1;

/// The `keep` starts of [`plane_cut_starts_from_heights`] whose regions $R_d$ hold the most
/// descriptor votes, $\sum_{i \in R_d} c_i$ (`votes`: $c_i$ per vertex, as the heights; those
/// of [`DescriptorMatches::votes`]), in direction order (ties to the earlier direction); every
/// one when no vote is positive or `keep` covers them all. The choice among the candidates
/// weighs their vote share, and an optimised plane cut keeps about the region it started from.
pub fn most_voted_plane_cut_starts(heights: &[Vec<f64>], mass: &[f64], area: f64, votes: &[f64], keep: usize) -> Vec<Start> {
    let regions: Vec<Vec<bool>> = heights.iter().map(|h| crate::geometry::area_matched_set(h, mass, area)).collect();
    let shares: Vec<f64> = regions
        .iter()
        .map(|r| r.iter().zip(votes).filter(|(&inside, _)| inside).map(|(_, &v)| v).sum())
        .collect();
    let mut kept: Vec<usize> = (0..regions.len()).collect();
    if keep < regions.len() && shares.iter().any(|&s| s > 0.0) {
        kept.sort_by(|&a, &b| shares[b].total_cmp(&shares[a]).then(a.cmp(&b)));
        kept.truncate(keep);
        kept.sort_unstable();
    }
    kept.into_iter().map(|j| plane_cut_start(j, &regions[j])).collect()
}

/// Partial vertices [`descriptor_matches`] compares (every `ceil(n / this)`-th).
pub const DESCRIPTOR_START_SAMPLES: usize = 2000;

/// Full-shape vertices per block of [`descriptor_matches`]' distances, the blocks computed in
/// parallel (each holds `DESCRIPTOR_START_SAMPLES x DESCRIPTOR_START_BLOCK` distances, ~4 MB,
/// for any resolution).
const DESCRIPTOR_START_BLOCK: usize = 256;

/// Rounds of one-ring averaging of the descriptor scores in [`descriptor_starts`] (not varied).
pub const DESCRIPTOR_START_SMOOTHING: usize = 3;

/// Radius (on the full shape of unit area; about 2.3 SHOT support radii) of the
/// neighbourhood in which a descriptor vote's match is checked against its neighbours'
/// ([`vote_consistency`]). docs/benchmarks/options.md ("Consistent votes").
pub const VOTE_CONSISTENCY_RADIUS: f64 = 0.15;

/// How far, as a fraction of [`VOTE_CONSISTENCY_RADIUS`], the distance between two matches may
/// be from the distance between the partial points they match, for the pair to agree.
pub const VOTE_CONSISTENCY_TOLERANCE: f64 = 0.25;

/// Power of the consistency in a vote's weight ([`descriptor_matches`]).
pub const VOTE_CONSISTENCY_EXPONENT: i32 = 2;

/// Passes of [`vote_consistency`]: after the first, each neighbour counts with its Lowe
/// weight times its own consistency of the pass before, so wrong matches around a right one
/// no longer dilute it, nor bear out one another. docs/benchmarks/options.md ("Consistent
/// votes").
pub const VOTE_CONSISTENCY_ROUNDS: usize = 2;

/// Descriptors at points: one SHOT row per position, in the full shape's units (of unit area).
#[derive(Debug, Clone, Copy)]
pub struct Described<'a> {
    /// One descriptor per row.
    pub descriptors: &'a faer::Mat<f64>,
    /// Where each row was described.
    pub positions: &'a [[f64; 3]],
}

/// Starts from descriptor correspondences, for partials no ball or plane resembles (a whole
/// body with holes): with $D_M(i)$ the full shape's SHOT descriptors and $D_N(j)$ a sample
/// of the partial's, $d_1(j) \le d_2(j)$ the distances from $D_N(j)$ to its nearest and
/// second-nearest $D_M$,
/// - `fit`: the vertices whose distance to the nearest partial descriptor,
///   $\min_j \lVert D_M(i) - D_N(j)\rVert$, is lowest (vertices inside a hole have no
///   counterpart);
/// - `vote`: the vertices the partial's vertices match best: each sampled partial vertex $j$
///   votes for its nearest full-shape vertex with weight $1 - d_1(j)/d_2(j)$, Lowe's ratio
///   test (Lowe 2004, "Distinctive image features from scale-invariant keypoints"): a
///   vertex whose descriptor many full-shape vertices share nearly as well (a flat or
///   symmetric stretch) votes little; times the square of the match's local consistency
///   ([`vote_consistency`]): a match its neighbours' matches do not bear out votes little;
///
/// each averaged over one-rings [`DESCRIPTOR_START_SMOOTHING`] times, then the partial's area
/// of the best vertices taken as a step start ([`mask_start`]). docs/algorithm.md ("Starts");
/// why: docs/benchmarks/options.md ("Descriptor starts").
pub fn descriptor_starts(matches: &DescriptorMatches, neighbors: &[Vec<u32>], mass: &[f64], area: f64) -> Vec<Start> {
    let n = matches.fit.len();
    if n == 0 || neighbors.len() != n || mass.len() != n {
        return Vec::new();
    }
    let smooth = |mut x: Vec<f64>| {
        for _ in 0..DESCRIPTOR_START_SMOOTHING {
            x = (0..n)
                .map(|i| {
                    let (mut s, mut w) = (x[i] * mass[i], mass[i]);
                    for &j in &neighbors[i] {
                        s += x[j as usize] * mass[j as usize];
                        w += mass[j as usize];
                    }
                    if w > 0.0 { s / w } else { x[i] }
                })
                .collect();
        }
        x
    };
    [("fit", &matches.fit), ("vote", &matches.votes)]
        .into_iter()
        .map(|(label, score)| mask_start(&crate::geometry::area_matched_set(&smooth(score.clone()), mass, area), &format!("descriptor-{label}")))
        .collect()
}

/// The partial's descriptor correspondences on the full shape, per full-shape vertex $i$
/// ([`descriptor_matches`]).
#[derive(Debug, Clone, PartialEq)]
pub struct DescriptorMatches {
    /// $-\min_j \lVert D_M(i) - D_N(j)\rVert$ over the sampled partial vertices $j$.
    pub fit: Vec<f64>,
    /// $\sum_j (1 - d_1(j)/d_2(j))\,c_j^2$ over the sampled partial vertices $j$ whose
    /// nearest full-shape descriptor is $D_M(i)$ (Lowe's ratio, a tie counting 0, times the
    /// match's local consistency $c_j$, [`vote_consistency`]).
    pub votes: Vec<f64>,
}

/// The [`DescriptorMatches`] of the partial's descriptors (every
/// `ceil(n / DESCRIPTOR_START_SAMPLES)`-th row of `partial`) on the full shape's; `None` for
/// no descriptor, mismatched dimensions, or a position missing. Each sampled partial point
/// $j$ is matched to the full-shape vertex of its nearest descriptor, and votes for it with
/// Lowe's ratio weight times the square of the match's local consistency
/// ([`vote_consistency`]: whether the matches of the partial points around $j$, weighted by
/// their own consistency, lie as far from $j$'s match as those points lie from $j$; Lowe's
/// weight alone when no match is borne out, as for a partial too coarse for the radius). The
/// nearest and
/// second-nearest rows are found from single-precision distances (by blocks of full-shape
/// rows: memory bounded for any resolution), and the distances they give are those rows'
/// distances in double precision: only rows within single precision's rounding of each other
/// can be ordered differently than in double precision, at half the cost of the products.
pub fn descriptor_matches(full: Described<'_>, partial: Described<'_>) -> Option<DescriptorMatches> {
    use crate::alignment::scale::SingleRows;
    let (full_descriptors, partial_descriptors, full_positions) = (full.descriptors, partial.descriptors, full.positions);
    let (n, d) = (full_descriptors.nrows(), full_descriptors.ncols());
    if n == 0 || partial_descriptors.nrows() == 0 || partial_descriptors.ncols() != d {
        return None;
    }
    if full_positions.len() != n || partial.positions.len() != partial_descriptors.nrows() {
        return None;
    }
    let step = partial_descriptors.nrows().div_ceil(DESCRIPTOR_START_SAMPLES).max(1);
    let sample: Vec<usize> = (0..partial_descriptors.nrows()).step_by(step).collect();
    let a = SingleRows::of_rows(partial_descriptors, &sample);
    let full = SingleRows::new(full_descriptors);
    // Per full vertex the nearest sampled partial vertex; per sampled partial vertex the
    // nearest and second-nearest full vertices (ties to the lower index), by squared
    // single-precision distances. Blocks of full rows in parallel, merged in row order: the
    // same nearest vertices and ties as one pass over the rows.
    use rayon::prelude::*;
    let starts: Vec<usize> = (0..n).step_by(DESCRIPTOR_START_BLOCK).collect();
    let blocks: Vec<(Vec<usize>, Vec<Nearest2>)> = starts
        .par_iter()
        .map(|&start| {
            let rows = DESCRIPTOR_START_BLOCK.min(n - start);
            let block = full.rows.as_ref().subrows(start, rows);
            let mut dot = faer::Mat::<f32>::zeros(rows, sample.len());
            faer::linalg::matmul::matmul(dot.as_mut(), faer::Accum::Replace, block, a.rows.transpose(), 1.0f32, faer::Par::Seq);
            let mut own = vec![0usize; rows];
            let mut nearest = vec![Nearest2::NONE; sample.len()];
            for r in 0..rows {
                let f2 = full.norms2[start + r];
                let mut best = (f32::INFINITY, 0usize);
                for (j, near) in nearest.iter_mut().enumerate() {
                    let distance2 = (f2 + a.norms2[j] - 2.0 * dot[(r, j)]).max(0.0);
                    if distance2 < best.0 {
                        best = (distance2, j);
                    }
                    near.push(distance2, start + r);
                }
                own[r] = best.1;
            }
            (own, nearest)
        })
        .collect();
    let mut own = Vec::with_capacity(n);
    let mut nearest = vec![Nearest2::NONE; sample.len()];
    for (block_own, block_nearest) in blocks {
        own.extend(block_own);
        for (best, later) in nearest.iter_mut().zip(block_nearest) {
            // Later rows have higher indices: as if pushed one by one.
            best.push(later.d1, later.v1);
            best.push(later.d2, later.v2);
        }
    }
    // The distances of the rows found, in double precision.
    let distance = |row: usize, j: usize| {
        let partial_row = sample[j];
        (0..d).map(|c| (full_descriptors[(row, c)] - partial_descriptors[(partial_row, c)]).powi(2)).sum::<f64>().sqrt()
    };
    let fit: Vec<f64> = own.iter().enumerate().map(|(r, &j)| -distance(r, j)).collect();
    let mut votes = vec![0.0; n];
    let mut matched = Vec::with_capacity(nearest.len());
    for (j, m) in nearest.iter().enumerate() {
        let d1 = distance(m.v1, j);
        // A single full row has no second nearest (d2 = inf): a vote of 1, as before.
        let d2 = if m.d2.is_finite() { distance(m.v2, j) } else { f64::INFINITY };
        let (vertex, d1, d2) = if d2 < d1 { (m.v2, d2, d1) } else { (m.v1, d1, d2) };
        // A tie (d1 = d2) is no evidence; d2 = 0 only if both are 0.
        matched.push((vertex, if d2 > 0.0 { 1.0 - d1 / d2 } else { 0.0 }));
    }
    let at: Vec<[f64; 3]> = sample.iter().map(|&r| partial.positions[r]).collect();
    let mut consistency = vote_consistency(&at, full_positions, &matched, VOTE_CONSISTENCY_ROUNDS);
    if consistency.iter().all(|&c| c == 0.0) {
        // No match has a neighbour that bears it out (a partial too coarse or too small for
        // the radius): Lowe's weights alone, rather than no vote at all.
        consistency.fill(1.0);
    }
    for (&(vertex, w), c) in matched.iter().zip(consistency) {
        votes[vertex] += w * c.powi(VOTE_CONSISTENCY_EXPONENT);
    }
    Some(DescriptorMatches { fit, votes })
}

/// Each match's local consistency $c_j$ ([`descriptor_matches`]) after `rounds` passes:
/// `at[j]` is the partial point of match `j` and `matched[j]` its full-shape vertex (an index
/// into `full`) and Lowe weight $w_j$. With $e_{jk}$ the distance between partial points $j$
/// and $k$ and $f_{jk}$ between their matches,
/// $$c^{(t+1)}_j = \frac{\sum_{k \in B_j} w_k\,c^{(t)}_k\,[\,|f_{jk} - e_{jk}| \le \epsilon r\,]}{\sum_{k \in B_j} w_k\,c^{(t)}_k},\qquad c^{(0)} = 1,$$
/// $B_j$ the other points within $r$ = [`VOTE_CONSISTENCY_RADIUS`] of $j$ and $\epsilon$ =
/// [`VOTE_CONSISTENCY_TOLERANCE`] (0 for a point without weighted neighbours). Euclidean
/// distances within a part barely change as a body bends, so right matches keep them, and a
/// wrong match, placed elsewhere by a look-alike, does not; from the second pass on, the
/// neighbours that count are those borne out themselves. A pass in which no match is borne
/// out ends the passes (its predecessor is returned).
fn vote_consistency(at: &[[f64; 3]], full: &[[f64; 3]], matched: &[(usize, f64)], rounds: usize) -> Vec<f64> {
    use crate::mesh::distance;
    use rayon::prelude::*;
    let tolerance = VOTE_CONSISTENCY_TOLERANCE * VOTE_CONSISTENCY_RADIUS;
    let mut consistency = vec![1.0; at.len()];
    for round in 0..rounds.max(1) {
        let next: Vec<f64> = (0..at.len())
            .into_par_iter()
            .map(|j| {
                let (mut agree, mut all) = (0.0, 0.0);
                for k in (0..at.len()).filter(|&k| k != j) {
                    let e = distance(at[j], at[k]);
                    if e > VOTE_CONSISTENCY_RADIUS {
                        continue;
                    }
                    let w = matched[k].1 * consistency[k];
                    all += w;
                    if (distance(full[matched[j].0], full[matched[k].0]) - e).abs() <= tolerance {
                        agree += w;
                    }
                }
                if all > 0.0 { agree / all } else { 0.0 }
            })
            .collect();
        if round > 0 && next.iter().all(|&c| c == 0.0) {
            break;
        }
        consistency = next;
    }
    consistency
}

/// The nearest and second-nearest squared distances seen so far and their vertices.
#[derive(Debug, Clone, Copy)]
struct Nearest2 {
    d1: f32,
    d2: f32,
    v1: usize,
    v2: usize,
}

impl Nearest2 {
    const NONE: Nearest2 = Nearest2 { d1: f32::INFINITY, d2: f32::INFINITY, v1: 0, v2: 0 };

    /// Take `distance` to `vertex` into account (vertices in increasing order: ties keep the
    /// lower index as the nearest, and make `d2 = d1`).
    fn push(&mut self, distance: f32, vertex: usize) {
        if distance < self.d1 {
            (self.d2, self.v2) = (self.d1, self.v1);
            (self.d1, self.v1) = (distance, vertex);
        } else if distance < self.d2 {
            (self.d2, self.v2) = (distance, vertex);
        }
    }
}

/// A start from a guess of the region: $w_0 = 2 - 4 R_0$ (low potential on the mask).
pub fn mask_start(mask: &[bool], label: &str) -> Start {
    Start { w0: mask.iter().map(|&m| if m { -2.0 } else { 2.0 }).collect(), label: label.to_string(), family: "mask" }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::angles::{cross, dot};

    /// SplitMix64: a tiny deterministic generator for the tests' random descriptors.
    fn splitmix64(state: &mut u64) -> u64 {
        *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = *state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn described<'a>(descriptors: &'a faer::Mat<f64>, positions: &'a [[f64; 3]]) -> Described<'a> {
        Described { descriptors, positions }
    }

    /// A vote counts by its match's consistency: a patch of a grid matched in place, with
    /// every 10th of its points matched to a look-alike far away instead. The right matches
    /// keep their neighbours' distances (consistency near 1), the wrong ones do not (near
    /// 0), so the far place gets almost no votes; moving and turning the partial changes
    /// nothing.
    #[test]
    fn a_match_that_does_not_keep_its_neighbours_distances_votes_little() {
        let mesh = crate::mesh::generate::grid(1.0, 1.0, 39, 39);
        let points = mesh.vertices();
        let d = 16;
        let mut state = 5;
        let mut full = faer::Mat::<f64>::from_fn(points.len(), d, |_, _| (splitmix64(&mut state) >> 11) as f64 / (1u64 << 53) as f64);
        let patch: Vec<usize> = (0..points.len()).filter(|&i| points[i][0] < 0.4 && points[i][1] < 0.4).collect();
        // Far look-alikes: the wrong matches' targets, near (0.9, 0.9), carry their descriptors.
        let far: Vec<usize> = (0..points.len()).filter(|&i| points[i][0] > 0.8 && points[i][1] > 0.8).collect();
        let wrong: Vec<(usize, usize)> = patch.iter().step_by(10).zip(far.iter().step_by(3)).map(|(&p, &f)| (p, f)).collect();
        for &(p, f) in &wrong {
            for c in 0..d {
                full[(f, c)] = full[(p, c)];
            }
            // The patch's own vertex differs a little, so the far copy is the nearest.
            full[(p, 0)] += 0.3;
        }
        let partial = faer::Mat::<f64>::from_fn(patch.len(), d, |i, c| {
            let v = patch[i];
            match wrong.iter().find(|&&(p, _)| p == v) {
                Some(&(_, f)) => full[(f, c)],
                None => full[(v, c)],
            }
        });
        let at: Vec<[f64; 3]> = patch.iter().map(|&i| points[i]).collect();
        let matches = descriptor_matches(described(&full, points), described(&partial, &at)).unwrap();
        let inside: f64 = patch.iter().map(|&i| matches.votes[i]).sum();
        let outside: f64 = far.iter().map(|&i| matches.votes[i]).sum();
        assert!(inside > 0.5 * (patch.len() - wrong.len()) as f64, "the right matches vote: {inside}");
        assert!(outside < 0.02 * inside, "the look-alikes get little: {outside} against {inside}");
        // Rigid motions of the partial keep every distance: the same votes.
        let (c, s) = (0.6f64, 0.8f64);
        let moved: Vec<[f64; 3]> = at.iter().map(|p| [c * p[0] - s * p[2] + 3.0, p[1] - 1.0, s * p[0] + c * p[2]]).collect();
        let again = descriptor_matches(described(&full, points), described(&partial, &moved)).unwrap();
        for (a, b) in again.votes.iter().zip(&matches.votes) {
            assert!((a - b).abs() < 1e-9);
        }
        // Points farther apart than the radius have no neighbour to bear them out: Lowe's
        // weights alone (as if every pair agreed), not no vote at all.
        let apart: Vec<[f64; 3]> = (0..patch.len()).map(|i| [i as f64, 0.0, 0.0]).collect();
        let lone = descriptor_matches(described(&full, points), described(&partial, &apart)).unwrap();
        let together = descriptor_matches(described(&full, &vec![[0.0; 3]; points.len()]), described(&partial, &vec![[0.0; 3]; patch.len()])).unwrap();
        assert!(lone.votes.iter().sum::<f64>() > 0.0);
        assert_eq!(lone.votes, together.votes);
    }

    /// The second pass of the consistency counts only neighbours that are borne out
    /// themselves: with 40 % of the matches sent to random places, the right ones' consistency
    /// rises from about the share of right neighbours to near 1, and the wrong ones' stays low.
    #[test]
    fn consistency_counts_the_neighbours_that_are_borne_out() {
        let mesh = crate::mesh::generate::grid(0.5, 0.5, 29, 29);
        let at = mesh.vertices().to_vec();
        // The full shape: the patch itself (right matches keep every distance) and a far
        // square the wrong matches land in at random.
        let mut full = at.clone();
        let mut state = 17;
        let mut uniform = || (splitmix64(&mut state) >> 11) as f64 / (1u64 << 53) as f64;
        let far_start = full.len();
        full.extend((0..400).map(|_| [5.0 + uniform(), 5.0 + uniform(), 0.0]));
        let wrong: Vec<bool> = (0..at.len()).map(|_| uniform() < 0.4).collect();
        let matched: Vec<(usize, f64)> = (0..at.len())
            .map(|j| (if wrong[j] { far_start + (uniform() * 400.0) as usize % 400 } else { j }, 0.5 + 0.5 * uniform()))
            .collect();
        let mean = |c: &[f64], of_wrong: bool| {
            let picked: Vec<f64> = c.iter().zip(&wrong).filter(|(_, &w)| w == of_wrong).map(|(&c, _)| c).collect();
            picked.iter().sum::<f64>() / picked.len() as f64
        };
        let once = vote_consistency(&at, &full, &matched, 1);
        let twice = vote_consistency(&at, &full, &matched, 2);
        assert!(mean(&once, false) < 0.7, "one pass: right matches diluted by the wrong ({})", mean(&once, false));
        assert!(mean(&twice, false) > 0.95, "two passes: right matches borne out ({})", mean(&twice, false));
        assert!(mean(&twice, true) < 0.1, "two passes: wrong matches not ({})", mean(&twice, true));
        assert!(mean(&twice, true) <= mean(&once, true));
        // Rounds past a pass that bears nothing out return that pass's predecessor.
        let apart: Vec<[f64; 3]> = (0..at.len()).map(|i| [i as f64, 0.0, 0.0]).collect();
        assert!(vote_consistency(&apart, &full, &matched, 2).iter().all(|&c| c == 0.0));
    }

    /// The matches found in single precision are the double-precision nearest rows' (to
    /// within single precision's rounding of the distances), with their double-precision
    /// distances: fit and votes against a brute-force double-precision reference on unit
    /// rows (as SHOT's), with a block boundary crossed and a duplicated row (a tie: no vote).
    #[test]
    fn single_precision_search_gives_the_double_precision_matches() {
        let (n, m, d) = (DESCRIPTOR_START_BLOCK + 37, 150, 24);
        let mut state = 11;
        let mut unit = |rows: usize| {
            let mut x = faer::Mat::<f64>::from_fn(rows, d, |_, _| (splitmix64(&mut state) >> 11) as f64 / (1u64 << 53) as f64 - 0.5);
            for i in 0..rows {
                let norm = (0..d).map(|c| x[(i, c)].powi(2)).sum::<f64>().sqrt();
                for c in 0..d {
                    x[(i, c)] /= norm;
                }
            }
            x
        };
        let mut full = unit(n);
        let mut partial = unit(m);
        // Full row 290 duplicates row 5, and partial row 0 is row 5: a tie at distance 0,
        // kept by the lower index, with no vote from partial row 0.
        for c in 0..d {
            full[(290, c)] = full[(5, c)];
            partial[(0, c)] = full[(5, c)];
        }
        // Every point at the origin: every pair of matches agrees, so each vote is Lowe's weight.
        let (at_full, at_partial) = (vec![[0.0; 3]; n], vec![[0.0; 3]; m]);
        let matches = descriptor_matches(described(&full, &at_full), described(&partial, &at_partial)).unwrap();
        let dist = |i: usize, j: usize| (0..d).map(|c| (full[(i, c)] - partial[(j, c)]).powi(2)).sum::<f64>().sqrt();
        for i in 0..n {
            let best = (0..m).map(|j| dist(i, j)).fold(f64::INFINITY, f64::min);
            assert!((matches.fit[i] + best).abs() < 1e-6, "row {i}: fit {} against {best}", matches.fit[i]);
        }
        let mut votes = vec![0.0; n];
        for j in 0..m {
            let mut order: Vec<usize> = (0..n).collect();
            order.sort_by(|&a, &b| dist(a, j).total_cmp(&dist(b, j)).then(a.cmp(&b)));
            let (d1, d2) = (dist(order[0], j), dist(order[1], j));
            votes[order[0]] += if d2 > 0.0 { 1.0 - d1 / d2 } else { 0.0 };
        }
        for i in 0..n {
            assert!((matches.votes[i] - votes[i]).abs() < 1e-5, "row {i}: votes {} against {}", matches.votes[i], votes[i]);
        }
        assert_eq!((matches.fit[5], matches.fit[290], matches.votes[290]), (0.0, 0.0, 0.0));
    }

    #[test]
    fn descriptor_starts_find_the_region_whose_descriptors_the_partial_has() {
        // A 30 x 30 grid with random descriptors; the "partial" carries the descriptors of a
        // disc and of a ring-shaped region (a patch with a hole): both starts recover each
        // region, blurred only at its rim by the smoothing, with the partial's area.
        let mesh = crate::mesh::generate::grid(1.0, 1.0, 29, 29);
        let shape = crate::shape::Shape::new(mesh);
        let (points, mass) = (shape.mesh().vertices(), shape.mass());
        let neighbors = crate::mesh::topology::vertex_neighbors(shape.mesh());
        let mut state = 3;
        let d = 16;
        let full = faer::Mat::<f64>::from_fn(points.len(), d, |_, _| (splitmix64(&mut state) >> 11) as f64 / (1u64 << 53) as f64);
        let r = |p: [f64; 3]| ((p[0] - 0.5).powi(2) + (p[1] - 0.5).powi(2)).sqrt();
        let regions: [Vec<bool>; 2] = [
            points.iter().map(|&p| r(p) < 0.3).collect(),
            points.iter().map(|&p| r(p) < 0.4 && r(p) > 0.15).collect(),
        ];
        for truth in &regions {
            let rows: Vec<usize> = (0..points.len()).filter(|&i| truth[i]).collect();
            let partial = faer::Mat::<f64>::from_fn(rows.len(), d, |i, c| full[(rows[i], c)]);
            let area: f64 = rows.iter().map(|&i| mass[i]).sum();
            let at: Vec<[f64; 3]> = rows.iter().map(|&i| points[i]).collect();
            let matches = descriptor_matches(described(&full, points), described(&partial, &at)).unwrap();
            let starts = descriptor_starts(&matches, &neighbors, mass, area);
            assert_eq!(starts.iter().map(|s| s.label.as_str()).collect::<Vec<_>>(), ["descriptor-fit", "descriptor-vote"]);
            for s in &starts {
                let inside: Vec<bool> = s.w0.iter().map(|&w| w < 0.0).collect();
                let both = (0..points.len()).filter(|&i| inside[i] && truth[i]).count() as f64;
                let either = (0..points.len()).filter(|&i| inside[i] || truth[i]).count() as f64;
                assert!(both / either > 0.85, "{}: IoU {}", s.label, both / either);
                assert!((well_area(&s.w0, mass) - area).abs() < 0.02 * area + 0.01, "{}: area", s.label);
            }
            // Deterministic.
            let again = descriptor_starts(&descriptor_matches(described(&full, points), described(&partial, &at)).unwrap(), &neighbors, mass, area);
            assert!(starts.iter().zip(&again).all(|(a, b)| a.w0 == b.w0));
        }
        // Mismatched dimensions or empty input give no start, not a panic.
        let other = faer::Mat::<f64>::zeros(5, d + 1);
        let nowhere = vec![[0.0; 3]; 5];
        assert!(descriptor_matches(described(&full, points), described(&other, &nowhere)).is_none());
        assert!(descriptor_matches(described(&full, points), described(&faer::Mat::<f64>::zeros(0, d), &[])).is_none());
        assert!(descriptor_matches(described(&full, &points[1..]), described(&full, points)).is_none(), "a position missing");
        let matches = descriptor_matches(described(&full, points), described(&full, points)).unwrap();
        assert!(descriptor_starts(&matches, &neighbors[1..], mass, 0.1).is_empty());
    }

    #[test]
    fn nearest_two_keeps_the_lower_index_and_a_tie_as_the_second_distance() {
        let mut m = Nearest2::NONE;
        for (i, d) in [3.0, 1.0, 2.0, 1.0, 5.0].into_iter().enumerate() {
            m.push(d, i);
        }
        // Nearest at vertex 1; the tie at vertex 3 is the second distance: ratio 1, no vote.
        assert_eq!((m.d1, m.d2, m.v1, m.v2), (1.0, 1.0, 1, 3));
        let mut m = Nearest2::NONE;
        for (i, d) in [4.0, 2.0, 3.0].into_iter().enumerate() {
            m.push(d, i);
        }
        assert_eq!((m.d1, m.d2, m.v1, m.v2), (2.0, 3.0, 1, 2));
    }

    /// Area of the vertices where `w0 < 0` (the start's well, `v < c`).
    fn well_area(w0: &[f64], mass: &[f64]) -> f64 {
        w0.iter().zip(mass).filter(|(w, _)| **w < 0.0).map(|(_, m)| m).sum()
    }

    fn rotate(p: [f64; 3], axis: [f64; 3], angle: f64) -> [f64; 3] {
        let (c, s) = (angle.cos(), angle.sin());
        let (kxp, kp) = (cross(axis, p), dot(axis, p));
        [0, 1, 2].map(|i| p[i] * c + kxp[i] * s + axis[i] * kp * (1.0 - c))
    }

    #[test]
    fn plane_cut_directions_follow_the_principal_axes_both_ways() {
        // An ellipsoid 3:2:1, rotated: the first two directions are +-its long axis, the next
        // +-the middle one; every prefix of 6, 14, 26 is closed under negation; the set turns
        // with the shape.
        let axis = {
            let a = [1.0, 2.0, 2.0];
            a.map(|x| x / 3.0)
        };
        let mesh = crate::mesh::generate::icosphere(3).map_positions(|p| rotate([3.0 * p[0], 2.0 * p[1], p[2]], axis, 0.7)).unwrap();
        let shape = crate::shape::Shape::new(mesh);
        let dirs = plane_cut_directions(shape.mesh().vertices(), shape.mass(), 100);
        assert_eq!(dirs.len(), MAX_PLANE_CUTS);
        let (long, mid) = (rotate([1.0, 0.0, 0.0], axis, 0.7), rotate([0.0, 1.0, 0.0], axis, 0.7));
        assert!(dot(dirs[0], long).abs() > 1.0 - 1e-9 && dot(dirs[1], long).abs() > 1.0 - 1e-9);
        assert!(dot(dirs[2], mid).abs() > 1.0 - 1e-9);
        for d in &dirs {
            assert!((dot(*d, *d) - 1.0).abs() < 1e-12);
        }
        for n in [6, 14, 26] {
            for d in &dirs[..n] {
                assert!(dirs[..n].iter().any(|e| dot(*d, *e) < -1.0 + 1e-12), "prefix {n} misses -{d:?}");
            }
        }
        for i in 0..dirs.len() {
            for j in 0..i {
                assert!(dot(dirs[i], dirs[j]) < 1.0 - 1e-6, "directions {i} and {j} repeat");
            }
        }
        assert_eq!(plane_cut_directions(shape.mesh().vertices(), shape.mass(), 6).len(), 6);
    }

    #[test]
    fn plane_cut_starts_turn_with_the_shape() {
        // The same sheared ellipsoid, rotated: each plane-cut well of one is a well of the
        // other (in some order, as the principal axes' signs may differ), for every prefix of
        // 6, 14, 26, up to the vertices tied in height at the cut (the icosphere is
        // symmetric, and rounding after the rotation reorders ties).
        let base = crate::mesh::generate::icosphere(3).map_positions(|p| [3.0 * p[0], 2.0 * p[1], p[2] + 0.3 * p[0] * p[1]]).unwrap();
        let turned = base.map_positions(|p| rotate(p, [0.0, 0.6, 0.8], 1.1)).unwrap();
        let wells = |m: &crate::mesh::TriMesh, n: usize| -> Vec<Vec<bool>> {
            let shape = crate::shape::Shape::new(m.clone());
            let total: f64 = shape.mass().iter().sum();
            plane_cut_starts(shape.mesh().vertices(), shape.mass(), 0.3 * total, n)
                .iter()
                .map(|s| s.w0.iter().map(|&x| x < 0.0).collect())
                .collect()
        };
        let iou = |a: &[bool], b: &[bool]| {
            let i = a.iter().zip(b).filter(|(x, y)| **x && **y).count() as f64;
            i / a.iter().zip(b).filter(|(x, y)| **x || **y).count() as f64
        };
        for n in [6, 14, 26] {
            let (a, b) = (wells(&base, n), wells(&turned, n));
            assert_eq!(a.len(), n);
            for (x, y) in [(&a, &b), (&b, &a)] {
                for w in x.iter() {
                    let best = y.iter().map(|v| iou(w, v)).fold(0.0, f64::max);
                    assert!(best > 0.95, "prefix {n}: a well's best match in the rotated shape has IoU {best}");
                }
            }
        }
    }

    #[test]
    fn plane_cut_starts_open_a_well_on_one_side_of_a_plane() {
        let shape = crate::shape::Shape::new(crate::mesh::generate::icosphere(3).map_positions(|p| [2.0 * p[0], p[1], p[2]]).unwrap());
        let (pts, mass) = (shape.mesh().vertices(), shape.mass());
        let total: f64 = mass.iter().sum();
        let max_mass = mass.iter().cloned().fold(0.0, f64::max);
        let dirs = plane_cut_directions(pts, mass, 14);
        let starts = plane_cut_starts(pts, mass, 0.25 * total, 14);
        assert_eq!(starts.len(), 14);
        for (j, (s, d)) in starts.iter().zip(&dirs).enumerate() {
            assert_eq!(s.label, format!("plane{j}"));
            let a = well_area(&s.w0, mass);
            assert!(a >= 0.25 * total && a <= 0.25 * total + max_mass, "{}: {a}", s.label);
            // Every vertex of the well lies above every vertex outside it along d.
            let h = |p: &[f64; 3]| dot(*p, *d);
            let low = pts.iter().zip(&s.w0).filter(|(_, w)| **w < 0.0).map(|(p, _)| h(p)).fold(f64::INFINITY, f64::min);
            let high = pts.iter().zip(&s.w0).filter(|(_, w)| **w > 0.0).map(|(p, _)| h(p)).fold(f64::NEG_INFINITY, f64::max);
            assert!(low >= high, "{}: well not on one side ({low} < {high})", s.label);
        }
        // The first two are the two ends of the long (x) axis.
        let xs = |s: &Start| pts.iter().zip(&s.w0).filter(|(_, w)| **w < 0.0).map(|(p, _)| p[0]).collect::<Vec<_>>();
        let (a, b) = (xs(&starts[0]), xs(&starts[1]));
        assert!(a.iter().all(|&x| x * a[0] > 0.0) && b.iter().all(|&x| x * b[0] > 0.0) && a[0] * b[0] < 0.0);
        assert!(plane_cut_starts(pts, mass, 0.25 * total, 0).is_empty());
    }

    /// The plane cut kept is the one whose region holds the votes; without votes, or keeping
    /// as many as there are, every one is kept as it would be without votes.
    #[test]
    fn the_plane_cut_kept_is_the_one_holding_the_votes() {
        let shape = crate::shape::Shape::new(crate::mesh::generate::icosphere(3).map_positions(|p| [2.0 * p[0], p[1], p[2]]).unwrap());
        let (pts, mass) = (shape.mesh().vertices(), shape.mass());
        let area = 0.25 * mass.iter().sum::<f64>();
        let heights = plane_heights(pts, mass, 6);
        let all = plane_cut_starts_from_heights(&heights, mass, area);
        // Votes at the -y end (y and z are axes of equal variance: whichever plane cuts the
        // frame gives, the kept one is the one reaching furthest towards -y).
        let votes: Vec<f64> = pts.iter().map(|p| if p[1] < -0.8 { 1.0 } else { 0.0 }).collect();
        let kept = most_voted_plane_cut_starts(&heights, mass, area, &votes, 1);
        assert_eq!(kept.len(), 1);
        let inside = |s: &Start| pts.iter().zip(&s.w0).filter(|(_, w)| **w < 0.0).map(|(p, _)| p[1]).sum::<f64>();
        assert!(inside(&kept[0]) < 0.0 && all.iter().all(|s| inside(s) >= inside(&kept[0])), "kept {}", kept[0].label);
        let same = |a: &[Start], b: &[Start]| a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.label == y.label && x.w0 == y.w0);
        let two = most_voted_plane_cut_starts(&heights, mass, area, &votes, 2);
        assert!(two.len() == 2 && two.iter().any(|s| s.label == kept[0].label));
        assert!(same(&most_voted_plane_cut_starts(&heights, mass, area, &vec![0.0; pts.len()], 1), &all));
        assert!(same(&most_voted_plane_cut_starts(&heights, mass, area, &votes, 6), &all));
    }
}
