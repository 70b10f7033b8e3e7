//! SHOT: Signatures of Histograms of OrienTations, a 352-dimensional local descriptor per
//! vertex (Salti, Tombari, Di Stefano 2014, "SHOT: Unique signatures of histograms for
//! surface and texture description", CVIU 125).
//!
//! The localizer scores its candidate regions with them (docs/algorithm.md, "Choosing among
//! the starts").
//!
//! # Definition
//! For a vertex `p` with support `S = { q : 0 < |q - p| <= R }` (a kd-tree radius search):
//!
//! 1. **Local reference frame** (paper section 4). The weighted covariance about `p`,
//!    $M = \frac{1}{\sum_i w_i} \sum_i w_i (q_i - p)(q_i - p)^\top$, $w_i = R - |q_i - p|$
//!    (the sum of weights includes `p` itself, weight `R`, as in PCL). Its eigenvectors by
//!    decreasing eigenvalue are `x`, `y`, `z`. Signs: `x` (and `z`) point towards the
//!    majority of the `q_i - p`, i.e. `x` is flipped if
//!    $|\{i : (q_i - p)\cdot x \ge 0\}| < |\{i : (q_i - p)\cdot x < 0\}|$; on a tie, the
//!    five support points nearest the median distance vote by the sign of their
//!    projection (paper eq. 5-6 and PCL's `SHOTLocalReferenceFrameEstimation`). Then
//!    `y = z × x`.
//! 2. **Spatial grid**: 8 azimuth sectors (angle of `(q·x, q·y)`), 2 elevation halves
//!    (sign of `q·z`), 2 radial shells (inner `|q - p| <= R/2`): 32 sectors.
//! 3. **Histogram** per sector of $\cos\theta_q = n_q \cdot z$ ($n_q$ the unit vertex normal at
//!    `q`, area-weighted face normals) in 11 bins centred at `cos = -1, -0.8, ..., 1`
//!    (PCL's layout for 10 shape bins: `32 x 11 = 352`).
//! 4. **Quadrilinear interpolation** (paper section 5): each `q` votes into the 2 nearest
//!    cosine bins, 2 nearest radial shells (centres `R/4`, `3R/4`), 2 nearest elevations
//!    (centres 45° and 135° from `z`) and 2 nearest azimuths (sector centres, cyclic), with
//!    the product of the four linear weights `1 - d` (16 bins per point). PCL adds the four
//!    1-D weights instead of multiplying them and wraps the cosine interpolation around;
//!    the product used here is the interpolation the paper describes and is continuous.
//! 5. **Normalisation** to unit Euclidean norm.
//!
//! A vertex with fewer than `min_neighbors` support points (or an all-zero histogram)
//! gets a zero row, and no frame.
//!
//! Every support point votes 1, as in the reference: votes weighted by the point's area
//! (density-independent histograms) traded SHREC'16 CUTS for PFARM on the dev sets
//! (docs/benchmarks/options.md, "Tried, never an option").
//!
//! # Radius
//! The reference implementation used radius 9 (10 bins, 3 minimum neighbours) on
//! SHREC'16 shapes, whose `sqrt(area)` is 126..263 (median ~140) for the null shapes.
//! [`default_shot_radius`] therefore takes [`DEFAULT_RADIUS_FRACTION`]` = 9 / 140 ≈ 0.064`
//! of `sqrt(area)` **of the full shape**; use the same absolute radius for the partial
//! shape (it is at the full shape's scale), so that both are described alike.
//!
//! # Invariance and determinism
//! Invariant to rigid motions (the frame moves with the shape) except at vertices whose
//! frame is degenerate (two nearly equal covariance eigenvalues, or a tie in the sign
//! vote; see [`LocalFrame::eigenvalues`]); invariant to a uniform scale `s` when the
//! radius becomes `s R`. Parallel over vertices (rayon), each row computed independently,
//! so the result does not depend on the thread count.

use crate::error::{Error, Result};
use crate::mesh::nearest::KdTree;
use crate::mesh::TriMesh;
use faer::Mat;
use rayon::prelude::*;

/// Length of a SHOT descriptor: 32 spatial sectors x 11 cosine bins.
pub const SHOT_DIM: usize = 352;
/// Cosine bins per sector (PCL: `nr_shape_bins + 1` with 10 shape bins).
pub const COS_BINS: usize = 11;
/// Default support radius as a fraction of `sqrt(area)` of the full shape (see module doc).
pub const DEFAULT_RADIUS_FRACTION: f64 = 9.0 / 140.0;
/// Default minimum number of support points (reference implementation: 3).
pub const DEFAULT_MIN_NEIGHBORS: usize = 3;

/// The default support radius for a pair (full shape, partial shape):
/// [`DEFAULT_RADIUS_FRACTION`]` * sqrt(area(full))`. Use it for both shapes.
#[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
pub fn default_shot_radius(full: &TriMesh) -> f64 {
    DEFAULT_RADIUS_FRACTION * full.area().sqrt()
}

/// A local reference frame of SHOT.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalFrame {
    /// Rows `x`, `y`, `z` (orthonormal, right-handed).
    pub axes: [[f64; 3]; 3],
    /// Covariance eigenvalues for `x`, `y`, `z` (decreasing). The frame is unstable under
    /// perturbation when two of them are close.
    pub eigenvalues: [f64; 3],
    /// Number of support points (excluding the vertex itself).
    pub support: usize,
    /// `true` when a sign vote (for `x` or `z`) was tied and fell back to the median rule.
    pub tied_sign: bool,
}

/// SHOT descriptors with their frames.
#[derive(Debug, Clone)]
pub struct Shot {
    /// `n x 352`, unit rows (zero rows where `frames[i]` is `None`).
    pub descriptors: Mat<f64>,
    /// The local reference frame of each vertex, `None` where the support was too small.
    #[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
    pub frames: Vec<Option<LocalFrame>>,
}

/// Unit vertex normals: the sum of the incident faces' `(b - a) x (c - a)` (area-weighted
/// face normals), normalised. Orientation follows the face winding. A vertex whose sum
/// vanishes gets the zero vector.
pub fn vertex_normals(mesh: &TriMesh) -> Vec<[f64; 3]> {
    let v = mesh.vertices();
    let mut n = vec![[0.0f64; 3]; v.len()];
    for f in mesh.faces() {
        let [a, b, c] = f.map(|i| v[i as usize]);
        let u = sub(b, a);
        let w = sub(c, a);
        let x = cross(u, w);
        for &i in f {
            for d in 0..3 {
                n[i as usize][d] += x[d];
            }
        }
    }
    for x in &mut n {
        let l = norm(*x);
        if l > 0.0 {
            *x = [x[0] / l, x[1] / l, x[2] / l];
        }
    }
    n
}

/// SHOT descriptors of every vertex of `mesh` (`n x 352`, unit rows; zero rows where the
/// support has fewer than `min_neighbors` points). `radius` is absolute (see
/// [`default_shot_radius`]). Errors if `radius` is not finite and positive.
pub fn shot_descriptors(mesh: &TriMesh, radius: f64, min_neighbors: usize) -> Result<Mat<f64>> {
    Ok(shot_with_frames(mesh, radius, min_neighbors)?.descriptors)
}

/// As [`shot_descriptors`], also returning the local reference frames.
pub fn shot_with_frames(mesh: &TriMesh, radius: f64, min_neighbors: usize) -> Result<Shot> {
    shot_points(
        mesh.vertices(),
        &vertex_normals(mesh),
        radius,
        min_neighbors,
    )
}

/// SHOT of a point set with given unit normals (`points.len() == normals.len()`); the
/// mesh functions call this with the vertices and [`vertex_normals`].
pub fn shot_points(
    points: &[[f64; 3]],
    normals: &[[f64; 3]],
    radius: f64,
    min_neighbors: usize,
) -> Result<Shot> {
    check_radius(radius)?;
    if points.len() != normals.len() {
        return Err(Error::InvalidArgument(format!(
            "{} points but {} normals",
            points.len(),
            normals.len()
        )));
    }
    if let Some(i) = normals
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(Error::InvalidArgument(format!(
            "normal {i} has a non-finite coordinate"
        )));
    }
    let all: Vec<u32> = (0..points.len() as u32).collect();
    describe_keypoints(points, normals, &all, radius, min_neighbors, MAX_SUPPORT_CLOUD)
}

/// SHOT of the `keypoints` of a mesh, each described by its support on the whole mesh (row
/// `r` for vertex `keypoints[r]`): the classic keypoint use of SHOT (Salti et al. 2014,
/// sec. 5). The localizer describes the vertices of its decimated mesh this way, with the
/// support at the data's resolution, as the partial shape's descriptors are. Errors as
/// [`shot_descriptors`], and on a keypoint out of range.
pub fn shot_keypoint_descriptors(mesh: &TriMesh, keypoints: &[u32], radius: f64, min_neighbors: usize) -> Result<Mat<f64>> {
    shot_keypoint_descriptors_thinned(mesh, keypoints, radius, min_neighbors, MAX_SUPPORT_CLOUD)
}

/// [`shot_keypoint_descriptors`] with the support cloud thinned to at most `max_cloud` points
/// (at most [`MAX_SUPPORT_CLOUD`]; see [`support_cloud`]).
pub(crate) fn shot_keypoint_descriptors_thinned(
    mesh: &TriMesh,
    keypoints: &[u32],
    radius: f64,
    min_neighbors: usize,
    max_cloud: usize,
) -> Result<Mat<f64>> {
    if let Some(&k) = keypoints.iter().find(|&&k| k as usize >= mesh.n_vertices()) {
        return Err(Error::InvalidArgument(format!("keypoint {k} out of range ({} vertices)", mesh.n_vertices())));
    }
    check_radius(radius)?;
    let max_cloud = max_cloud.clamp(1, MAX_SUPPORT_CLOUD);
    Ok(describe_keypoints(mesh.vertices(), &vertex_normals(mesh), keypoints, radius, min_neighbors, max_cloud)?.descriptors)
}

/// SHOT of a shape at a sample of its vertices, each vertex represented by its nearest
/// sampled vertex: what the localizer describes a partial by ([`sampled_shot`]).
#[derive(Debug, Clone)]
pub struct SampledShot {
    /// One row per sampled vertex (`n_samples x 352`), as [`shot_keypoint_descriptors`].
    pub descriptors: Mat<f64>,
    /// For each vertex of the mesh, the row of its nearest sampled vertex (Euclidean; a
    /// sampled vertex is its own row).
    pub row_of_vertex: Vec<u32>,
    /// The vertex each row describes.
    pub samples: Vec<u32>,
}

impl SampledShot {
    /// Where each row was described: the positions of its vertex in `mesh` (the mesh described).
    pub fn positions(&self, mesh: &TriMesh) -> Vec<[f64; 3]> {
        self.samples.iter().map(|&i| mesh.vertices()[i as usize]).collect()
    }
}

/// SHOT of every `ceil(n / max_samples)`-th vertex of `mesh` (every vertex when it has at
/// most `max_samples`), each described with its support on the whole mesh, and every vertex's
/// nearest sampled vertex. The sample is by vertex index, so it does not depend on the
/// shape's pose. Errors as [`shot_keypoint_descriptors`].
pub fn sampled_shot(mesh: &TriMesh, max_samples: usize, radius: f64, min_neighbors: usize) -> Result<SampledShot> {
    let n = mesh.n_vertices();
    let step = n.div_ceil(max_samples.max(1)).max(1);
    let samples: Vec<u32> = (0..n as u32).step_by(step).collect();
    let descriptors = shot_keypoint_descriptors(mesh, &samples, radius, min_neighbors)?;
    let row_of_vertex = if step == 1 {
        samples.clone()
    } else {
        let at: Vec<[f64; 3]> = samples.iter().map(|&i| mesh.vertices()[i as usize]).collect();
        let mut rows = crate::mesh::nearest::nearest_vertices(&at, mesh.vertices())?;
        // A sampled vertex is its own row even where another sample coincides with it.
        for (row, &i) in samples.iter().enumerate() {
            rows[i as usize] = row as u32;
        }
        rows
    };
    Ok(SampledShot { descriptors, row_of_vertex, samples })
}

fn check_radius(radius: f64) -> Result<()> {
    if radius > 0.0 && radius.is_finite() {
        Ok(())
    } else {
        Err(Error::InvalidArgument(format!("SHOT radius must be finite and positive, got {radius}")))
    }
}

/// Descriptors and frames of `keypoints` (indices into `points`), in parallel, each with
/// its support among `points` (thinned to [`MAX_SUPPORT_CLOUD`] points, see
/// [`support_cloud`]).
fn describe_keypoints(
    points: &[[f64; 3]],
    normals: &[[f64; 3]],
    keypoints: &[u32],
    radius: f64,
    min_neighbors: usize,
    max_cloud: usize,
) -> Result<Shot> {
    let cloud = support_cloud(points, radius, max_cloud);
    let (cloud_points, cloud_normals): (Vec<[f64; 3]>, Vec<[f64; 3]>) = match &cloud {
        Some(kept) => kept.iter().map(|&i| (points[i as usize], normals[i as usize])).unzip(),
        None => (Vec::new(), Vec::new()),
    };
    let (support_points, support_normals) = match cloud {
        Some(_) => (cloud_points.as_slice(), cloud_normals.as_slice()),
        None => (points, normals),
    };
    let tree = KdTree::new(support_points)?;
    let mut flat = vec![0.0f64; keypoints.len() * SHOT_DIM];
    let frames: Vec<Option<LocalFrame>> = flat
        .par_chunks_mut(SHOT_DIM)
        .zip(keypoints.par_iter())
        .map_init(Vec::new, |buf, (row, &i)| {
            let p = points[i as usize];
            tree.within_radius_into(p, radius, buf);
            thin_support(buf, MAX_SUPPORT_POINTS);
            describe(support_points, support_normals, p, buf, radius, min_neighbors, row)
        })
        .collect();
    let descriptors = Mat::from_fn(keypoints.len(), SHOT_DIM, |i, j| flat[i * SHOT_DIM + j]);
    Ok(Shot {
        descriptors,
        frames,
    })
}

/// Most points one vertex's support holds: above it, every `ceil(count / this)`-th of the
/// points within the radius (in index order; the points at distance 0 always). On a surface
/// meshed far more densely than the radius (a scanned face), a support holds thousands of
/// points and describing costs their square; the histograms are normalised, so an even
/// thinning keeps their shape. Every SHREC'16 and PFAUST shape and the PFARM template stay
/// below it (at most 837 points), as do all but one PFARM scan (3,889 points per vertex on
/// `cut-2--victoria12`).
pub const MAX_SUPPORT_POINTS: usize = 1000;

/// `found` (the points within the radius, ascending indices, with squared distances) thinned
/// to about `max` points: every `ceil(len / max)`-th, and every point at distance 0.
fn thin_support(found: &mut Vec<(u32, f64)>, max: usize) {
    if found.len() <= max || max == 0 {
        return;
    }
    let step = found.len().div_ceil(max);
    let mut k = 0;
    found.retain(|&(_, d2)| {
        let keep = k % step == 0 || d2 == 0.0;
        k += 1;
        keep
    });
}

/// Most points a SHOT support cloud holds. A vertex's support is every cloud point within
/// the radius, so dense scans (a face scanned at 10x the density of the rest) cost the
/// square of their local density; above this many points the support comes from a
/// uniform thinning of the cloud instead (see [`support_cloud`]). At or below it (every
/// SHREC'16 shape) the support is every vertex, as in the reference implementation.
pub const MAX_SUPPORT_CLOUD: usize = 12_000;

/// The points of a uniform thinning of `points` when there are more than `max_points`,
/// else `None` (use them all): one point per cell of a cubic grid, the one nearest the
/// cell's centre (ties by index), with the cell edge grown by 1.25x from `radius / 16`
/// until at most `max_points` remain. Indices increasing; deterministic.
pub fn support_cloud(points: &[[f64; 3]], radius: f64, max_points: usize) -> Option<Vec<u32>> {
    use std::collections::HashMap;
    if points.len() <= max_points || max_points == 0 {
        return None;
    }
    let mut h = radius / 16.0;
    loop {
        let mut best: HashMap<[i64; 3], (f64, u32)> = HashMap::new();
        for (i, p) in points.iter().enumerate() {
            let cell = p.map(|c| (c / h).floor() as i64);
            let centre = [0, 1, 2].map(|d| (cell[d] as f64 + 0.5) * h);
            let d2 = (0..3).map(|d| (p[d] - centre[d]).powi(2)).sum::<f64>();
            let e = best.entry(cell).or_insert((f64::INFINITY, u32::MAX));
            if d2 < e.0 {
                *e = (d2, i as u32);
            }
        }
        if best.len() <= max_points {
            let mut kept: Vec<u32> = best.into_values().map(|(_, i)| i).collect();
            kept.sort_unstable();
            return Some(kept);
        }
        h *= 1.25;
    }
}

/// One vertex: frame, histogram into `row` (already zero), normalisation.
fn describe(
    points: &[[f64; 3]],
    normals: &[[f64; 3]],
    p: [f64; 3],
    found: &[(u32, f64)],
    radius: f64,
    min_neighbors: usize,
    row: &mut [f64],
) -> Option<LocalFrame> {
    // Support without the vertex itself (and without coincident points): (offset, distance).
    let mut support: Vec<([f64; 3], f64, u32)> = found
        .iter()
        .filter(|&&(_, d2)| d2 > 0.0)
        .map(|&(j, d2)| (sub(points[j as usize], p), d2.sqrt(), j))
        .collect();
    if support.len() < min_neighbors.max(1) {
        return None;
    }
    let n_coincident = found.len() - support.len();
    let frame = local_frame(&mut support, radius, n_coincident)?;
    let [x, y, z] = frame.axes;
    let q_angle = std::f64::consts::FRAC_PI_4;
    for &(d, dist, j) in &support {
        let (lx, ly, lz) = (dot(d, x), dot(d, y), dot(d, z));
        // Cosine of the angle between the neighbour's normal and z: 11 bins centred at k/5 - 1.
        let cos = dot(normals[j as usize], z).clamp(-1.0, 1.0);
        let t = (1.0 + cos) * 5.0;
        let k0 = (t.floor() as usize).min(COS_BINS - 2);
        let fc = t - k0 as f64;
        let cos_w = [(k0, 1.0 - fc), (k0 + 1, fc)];
        // Radial shells, centres R/4 and 3R/4.
        let u = dist / radius;
        let fr = ((u - 0.25) / 0.5).clamp(0.0, 1.0);
        let rad_w = [(0usize, 1.0 - fr), (1usize, fr)];
        // Elevation from z: upper half (index 0) centred at 45°, lower (1) at 135°.
        let theta = (lz / dist).clamp(-1.0, 1.0).acos();
        let fe = ((theta - q_angle) / (2.0 * q_angle)).clamp(0.0, 1.0);
        let el_w = [(0usize, 1.0 - fe), (1usize, fe)];
        // Azimuth: sector s covers [-pi + s pi/4, -pi + (s+1) pi/4), centre at + pi/8.
        let phi = ly.atan2(lx);
        let a = (phi + std::f64::consts::PI) / q_angle - 0.5;
        let s0 = a.floor();
        let fa = a - s0;
        let s0 = (s0 as i64).rem_euclid(8) as usize;
        let az_w = [(s0, 1.0 - fa), ((s0 + 1) % 8, fa)];
        for &(ai, aw) in &az_w {
            for &(ei, ew) in &el_w {
                for &(ri, rw) in &rad_w {
                    let w3 = aw * ew * rw;
                    if w3 == 0.0 {
                        continue;
                    }
                    let base = ((ai * 2 + ei) * 2 + ri) * COS_BINS;
                    for &(ci, cw) in &cos_w {
                        row[base + ci] += w3 * cw;
                    }
                }
            }
        }
    }
    let l = row.iter().map(|v| v * v).sum::<f64>().sqrt();
    if !(l > 0.0) {
        row.iter_mut().for_each(|v| *v = 0.0);
        return None;
    }
    row.iter_mut().for_each(|v| *v /= l);
    Some(frame)
}

/// The SHOT local reference frame (see the module doc). `support` is sorted here by
/// (distance, index) for the median tie rule. `n_coincident` points at distance 0 (the
/// vertex itself) add weight `R` each to the normaliser.
fn local_frame(
    support: &mut [([f64; 3], f64, u32)],
    radius: f64,
    n_coincident: usize,
) -> Option<LocalFrame> {
    let mut m = [[0.0f64; 3]; 3];
    let mut wsum = radius * n_coincident as f64;
    for &(d, dist, _) in support.iter() {
        let w = radius - dist;
        wsum += w;
        for r in 0..3 {
            for c in 0..3 {
                m[r][c] += w * d[r] * d[c];
            }
        }
    }
    if !(wsum > 0.0) {
        return None;
    }
    for row in &mut m {
        for v in row.iter_mut() {
            *v /= wsum;
        }
    }
    let (vals, vecs) = sym_eigen3(m);
    let mut x = vecs[0];
    let mut z = vecs[2];
    support.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.2.cmp(&b.2)));
    let (fx, tx) = sign_vote(support, x);
    let (fz, tz) = sign_vote(support, z);
    if fx {
        x = x.map(|c| -c);
    }
    if fz {
        z = z.map(|c| -c);
    }
    let y = cross(z, x);
    Some(LocalFrame {
        axes: [x, y, z],
        eigenvalues: vals,
        support: support.len(),
        tied_sign: tx || tz,
    })
}

/// Whether `axis` should be flipped so that most offsets project non-negatively on it,
/// and whether the vote was tied (PCL: the five points around the median distance decide).
fn sign_vote(support: &[([f64; 3], f64, u32)], axis: [f64; 3]) -> (bool, bool) {
    let n = support.len() as i64;
    let plus = support.iter().filter(|s| dot(s.0, axis) >= 0.0).count() as i64;
    let balance = 2 * plus - n;
    if balance != 0 {
        return (balance < 0, false);
    }
    let mid = support.len() / 2;
    let lo = mid.saturating_sub(2);
    let hi = (mid + 3).min(support.len());
    let votes = support[lo..hi]
        .iter()
        .filter(|s| dot(s.0, axis) > 0.0)
        .count();
    (2 * votes < hi - lo, true)
}

/// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations:
/// eigenvalues decreasing and the matching unit eigenvectors (right-handed triple).
pub(crate) fn sym_eigen3(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]; // columns = eigenvectors
    let scale = (0..3)
        .map(|i| (0..3).map(|j| a[i][j].abs()).sum::<f64>())
        .fold(0.0, f64::max);
    for _ in 0..64 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off <= f64::EPSILON * 1e-3 * scale || off == 0.0 {
            break;
        }
        for (p, q) in [(0usize, 1usize), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A <- J^T A J with the rotation in the (p, q) plane.
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|&i, &j| a[j][j].total_cmp(&a[i][i]));
    let vals = idx.map(|i| a[i][i]);
    let mut vecs = idx.map(|i| [v[0][i], v[1][i], v[2][i]]);
    for e in &mut vecs {
        let l = norm(*e);
        *e = e.map(|c| c / l);
    }
    (vals, vecs)
}

#[inline]
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline]
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
#[inline]
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
#[inline]
fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {

    /// The thinned support: at most the bound, spread over the shape (no cell of the
    /// bounding grid empty where the shape is), `None` under the bound; descriptors with
    /// thinned support stay close to the full-support ones (a bumpy sphere, so that
    /// histograms differ from vertex to vertex).
    #[test]
    fn a_support_above_the_cap_keeps_every_kth_point_and_the_vertex_itself() {
        let mut found: Vec<(u32, f64)> = (0..2500u32).map(|i| (i, if i == 1234 { 0.0 } else { 1.0 + f64::from(i) })).collect();
        thin_support(&mut found, 1000);
        // ceil(2500 / 1000) = 3: indices 0, 3, 6, ... (834 of them) and the coincident point.
        assert_eq!(found.len(), 835);
        assert!(found.iter().any(|&(i, d)| i == 1234 && d == 0.0));
        assert!(found.windows(2).all(|w| w[0].0 < w[1].0), "still in index order");
        let mut small: Vec<(u32, f64)> = (0..1000u32).map(|i| (i, 1.0)).collect();
        thin_support(&mut small, 1000);
        assert_eq!(small.len(), 1000, "at the cap nothing is dropped");
    }

    #[test]
    fn thinned_support_is_bounded_uniform_and_keeps_descriptors_close() {
        let sphere = crate::mesh::generate::icosphere(5);
        let mesh = sphere
            .map_positions(|p| {
                let bump = 1.0 + 0.15 * (3.0 * p[0]).sin() * (2.0 * p[1]).cos();
                p.map(|c| c * bump)
            })
            .unwrap();
        let points = mesh.vertices();
        assert!(support_cloud(points, 0.5, points.len()).is_none());
        let kept = support_cloud(points, 0.5, 3000).unwrap();
        assert!(kept.len() <= 3000 && kept.len() > 1500, "{}", kept.len());
        assert!(kept.windows(2).all(|w| w[0] < w[1]));
        // Every vertex has a kept point within a few grid cells.
        let tree = KdTree::new(&kept.iter().map(|&i| points[i as usize]).collect::<Vec<_>>()).unwrap();
        let worst = points.iter().map(|&p| tree.nearest(p).1).fold(0.0f64, f64::max).sqrt();
        assert!(worst < 0.1, "farthest vertex from the cloud: {worst}");
        let normals = vertex_normals(&mesh);
        let all: Vec<u32> = (0..points.len() as u32).collect();
        let full = describe_keypoints(points, &normals, &all, 0.5, 3, MAX_SUPPORT_CLOUD).unwrap().descriptors;
        let thinned = {
            let cloud: Vec<[f64; 3]> = kept.iter().map(|&i| points[i as usize]).collect();
            let cloud_n: Vec<[f64; 3]> = kept.iter().map(|&i| normals[i as usize]).collect();
            let tree = KdTree::new(&cloud).unwrap();
            let mut rows = Mat::<f64>::zeros(points.len(), SHOT_DIM);
            let mut buf = Vec::new();
            let mut row = vec![0.0; SHOT_DIM];
            for (i, &p) in points.iter().enumerate() {
                row.iter_mut().for_each(|v| *v = 0.0);
                tree.within_radius_into(p, 0.5, &mut buf);
                describe(&cloud, &cloud_n, p, &buf, 0.5, 3, &mut row);
                row.iter().enumerate().for_each(|(c, &v)| rows[(i, c)] = v);
            }
            rows
        };
        let cosine: f64 = (0..points.len())
            .map(|i| (0..SHOT_DIM).map(|c| full[(i, c)] * thinned[(i, c)]).sum::<f64>())
            .sum::<f64>()
            / points.len() as f64;
        assert!(cosine > 0.9, "mean cosine of full and thinned-support descriptors {cosine}");
    }

    use super::*;

    #[test]
    fn jacobi_eigen_reconstructs() {
        let a = [[4.0, 1.0, -2.0], [1.0, 2.0, 0.5], [-2.0, 0.5, 3.0]];
        let (vals, vecs) = sym_eigen3(a);
        assert!(vals[0] >= vals[1] && vals[1] >= vals[2]);
        for k in 0..3 {
            for r in 0..3 {
                let av: f64 = (0..3).map(|c| a[r][c] * vecs[k][c]).sum();
                assert!((av - vals[k] * vecs[k][r]).abs() < 1e-13);
            }
            for l in 0..3 {
                let d = dot(vecs[k], vecs[l]);
                assert!((d - if k == l { 1.0 } else { 0.0 }).abs() < 1e-14);
            }
        }
        let trace = a[0][0] + a[1][1] + a[2][2];
        assert!((vals.iter().sum::<f64>() - trace).abs() < 1e-13);
        let (vals, _) = sym_eigen3([[2.0, 0.0, 0.0], [0.0, 5.0, 0.0], [0.0, 0.0, -1.0]]);
        assert_eq!(vals, [5.0, 2.0, -1.0]);
    }

    #[test]
    fn unit_norm_and_right_handed_frame() {
        let points = [
            [0.0, 0.0, 0.0],
            [0.3, 0.1, 0.05],
            [-0.2, 0.4, -0.1],
            [0.1, -0.3, 0.2],
        ];
        let normals = [[0.0, 0.0, 1.0]; 4];
        let mut row = vec![0.0; SHOT_DIM];
        let found: Vec<(u32, f64)> = (0..4u32)
            .map(|j| {
                (
                    j,
                    dot(
                        sub(points[j as usize], points[0]),
                        sub(points[j as usize], points[0]),
                    ),
                )
            })
            .collect();
        let f = describe(&points, &normals, points[0], &found, 1.0, 3, &mut row).unwrap();
        assert_eq!(f.support, 3);
        let l2: f64 = row.iter().map(|v| v * v).sum();
        assert!((l2 - 1.0).abs() < 1e-14);
        // Frame is orthonormal and right-handed.
        let [x, y, z] = f.axes;
        assert!((dot(cross(x, y), z) - 1.0).abs() < 1e-14);
    }

    /// A cloud limit above the vertex count changes nothing; below it the support is thinned
    /// (other, still unit, histograms; how close they stay is
    /// `thinned_support_is_bounded_uniform_and_keeps_descriptors_close`); a keypoint out of
    /// range is an error.
    #[test]
    fn thinned_support_keeps_the_descriptors() {
        let mesh = crate::mesh::generate::grid(1.0, 1.0, 30, 30);
        let keypoints: Vec<u32> = (0..mesh.n_vertices() as u32).step_by(37).collect();
        let full = shot_keypoint_descriptors(&mesh, &keypoints, 0.4, 3).unwrap();
        let same = shot_keypoint_descriptors_thinned(&mesh, &keypoints, 0.4, 3, 10_000).unwrap();
        assert_eq!(full, same);
        let thin = shot_keypoint_descriptors_thinned(&mesh, &keypoints, 0.4, 3, 300).unwrap();
        assert_ne!(full, thin);
        for i in 0..keypoints.len() {
            let norm: f64 = (0..SHOT_DIM).map(|j| thin[(i, j)].powi(2)).sum::<f64>().sqrt();
            assert!((norm - 1.0).abs() < 1e-9 || norm == 0.0, "row {i}: norm {norm}");
        }
        assert!(shot_keypoint_descriptors_thinned(&mesh, &[10_000], 0.4, 3, 300).is_err());
    }

    #[test]
    fn bad_input_is_an_error() {
        let m = crate::mesh::generate::icosphere(1);
        assert!(shot_descriptors(&m, 0.0, 3).is_err());
        assert!(shot_descriptors(&m, f64::NAN, 3).is_err());
        assert!(shot_points(&[[0.0; 3]], &[], 1.0, 3).is_err());
    }

    #[test]
    fn too_small_support_gives_zero_rows() {
        let m = crate::mesh::generate::icosphere(2);
        let shot = shot_with_frames(&m, 1e-6, 3).unwrap();
        assert!(shot.frames.iter().all(|f| f.is_none()));
        assert!((0..m.n_vertices()).all(|i| (0..SHOT_DIM).all(|j| shot.descriptors[(i, j)] == 0.0)));
    }
}
