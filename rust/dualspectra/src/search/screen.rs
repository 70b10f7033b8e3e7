//! The library screen: rank many full shapes for a partial from a few SHOT descriptors of
//! each, so that only the most promising are localized (docs/algorithm.md, "Screening a
//! library").
//!
//! A full shape is kept as the SHOT descriptors (Tombari et al. 2010) of
//! [`MODEL_KEYPOINTS`] vertices spread over it by farthest-point sampling, on the shape
//! scaled to unit area with the localizer's support radius $r_0$ ([`ScreenEntry`]). A
//! [`Screen`] projects every entry on the library's [`DIMENSIONS`] principal directions.
//! The partial is described at [`QUERY_KEYPOINTS`] vertices, at the radius its units call
//! for, and a model $m$ is scored by
//! $$d_m = \min_{a \in H_m} \frac{1}{|P|}\sum_{p \in P} \min_{q} \lVert D_N(p;\, r_0\sqrt{A_N/a}) - D_m(q) \rVert,$$
//! the mean distance of the partial's keypoints to their nearest model keypoint, where the
//! area-fraction hypotheses $H_m$ are the one the units give ($a = A_N s^2 / A_m$ with
//! `scale = same` ($s = 1$) or a factor $s$, snapped to the grid of
//! [`crate::alignment::scale`]) or that whole grid (`scale = auto`). A small area fraction
//! describes the partial with a small support, at which every model looks alike (a small
//! model draws every partial in known units; with `scale = auto` any model may pick such a
//! scale), so distances are weighed against what they are at the same hypothesis: the
//! score is the mean of the model's positions in the library by
//! $\min_{a \in H_m} d_m(a) / \operatorname{median}_{m'} d_{m'}(a)$ (against the library's
//! median model) and by $\min_{a \in H_m} d_m(a) / \sigma(a)$, where $\sigma(a)$ is the mean
//! distance from each of the partial's keypoints to its nearest other keypoint in descriptor
//! space (how alike the partial's own points look at that support). Lower is more similar; a
//! partial larger than the model in the same units scores `+inf` (measured in
//! docs/benchmarks/options.md, "`shortlist`").

use crate::alignment::scale::{area_grid, nearest_distances};
use crate::error::{Error, Result};
use crate::geometry::shot;
use crate::localizer::persist::{crc32, Reader, Writer};
use crate::localizer::Scale;
use crate::mesh::TriMesh;
use crate::progress::Progress;
use faer::Mat;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// Keypoints described per full shape.
pub(crate) const MODEL_KEYPOINTS: usize = 512;
/// Keypoints described on the partial (per area hypothesis).
pub(crate) const QUERY_KEYPOINTS: usize = 100;
/// Principal directions the descriptors are projected on.
pub(crate) const DIMENSIONS: usize = 32;
/// Rows of the library's descriptors the principal directions are computed from (a stride
/// over all rows above it: bounded memory for any library size).
const PCA_ROWS: usize = 20_000;
/// At most about this many models (an even stride of the library above it) give the library's
/// median distance under each hypothesis: the screen's time then grows with the library's size
/// as one hypothesis per model.
const MEDIAN_MODELS: usize = 1000;
/// Largest area of the partial over the model's, in known units, that the screen scores
/// (the localizer refuses a partial above it: `MeshError::PartialLargerThanFull`).
const LARGEST_AREA_RATIO: f64 = 1.1;
/// A descriptor row is used if its norm is at least this (SHOT rows are unit vectors, or
/// zero where the support has too few points).
const LIVE_ROW: f64 = 0.5;

/// What the screen keeps of one full shape: SHOT descriptors of [`MODEL_KEYPOINTS`] vertices
/// (farthest-point sampling) of the shape scaled to unit area, and the shape's area in its
/// own units.
#[derive(Debug, Clone)]
pub struct ScreenEntry {
    descriptors: Mat<f64>,
    area: f64,
}

impl ScreenEntry {
    /// Describe `full` (any units).
    pub fn new(full: &TriMesh) -> Result<Self> {
        Self::with_keypoints(full, MODEL_KEYPOINTS)
    }

    /// As [`ScreenEntry::new`] with `keypoints` keypoints.
    pub(crate) fn with_keypoints(full: &TriMesh, keypoints: usize) -> Result<Self> {
        let area = full.area();
        if !(area > 0.0 && area.is_finite()) {
            return Err(Error::InvalidArgument("screen: the full shape has no area".into()));
        }
        let keypoints = farthest_points(full, keypoints);
        let radius = shot::DEFAULT_RADIUS_FRACTION * area.sqrt();
        let descriptors = shot::shot_keypoint_descriptors(full, &keypoints, radius, shot::DEFAULT_MIN_NEIGHBORS)?;
        Ok(ScreenEntry { descriptors: live_rows(&descriptors), area })
    }

    /// The full shape's area, in its own units.
    pub fn area(&self) -> f64 {
        self.area
    }
}

/// One model, projected.
#[derive(Debug, Clone)]
struct Projected {
    /// Keypoints x dimensions.
    rows: Mat<f32>,
    norms2: Vec<f32>,
    area: f64,
}

/// A library of full shapes ready to be screened: every [`ScreenEntry`] projected on the
/// library's principal directions, with a label per model (e.g. its file).
///
/// On disk ([`Screen::save`], extension [`SCREEN_EXTENSION`]; little-endian): magic
/// `"DSSCREEN"` | format version u32 | payload length u64 | CRC-32 of the payload u32 |
/// payload: dimensions u64 | basis (`352 x dimensions` f64, row-major) | models u64 | per
/// model: label (u32 length, UTF-8), area f64, keypoints u64, `keypoints x dimensions` f32.
#[derive(Debug, Clone)]
pub struct Screen {
    /// `SHOT_DIM x dimensions`.
    basis: Mat<f64>,
    models: Vec<Projected>,
    labels: Vec<String>,
}

/// The first bytes of a screen file.
const SCREEN_MAGIC: [u8; 8] = *b"DSSCREEN";
/// Version of the screen file's layout and of what it holds (bump when either changes).
/// Version 2: SHOT supports thinned above [`crate::geometry::shot::MAX_SUPPORT_POINTS`] points.
const SCREEN_FORMAT: u32 = 2;
/// The conventional extension of screen files (without the dot).
pub const SCREEN_EXTENSION: &str = "dsscreen";

impl Screen {
    /// The screen of `entries` (model `i` is `entries[i]`), with [`DIMENSIONS`] principal
    /// directions.
    pub fn new(entries: &[ScreenEntry]) -> Result<Self> {
        Self::with_dimensions(entries, DIMENSIONS)
    }

    /// As [`Screen::new`] with `dimensions` principal directions (at most the descriptor's
    /// 352; the full descriptor is kept at 352).
    pub(crate) fn with_dimensions(entries: &[ScreenEntry], dimensions: usize) -> Result<Self> {
        if entries.is_empty() {
            return Err(Error::InvalidArgument("screen: no full shape".into()));
        }
        let basis = principal_directions(entries, dimensions.clamp(1, shot::SHOT_DIM));
        let models = entries.iter().map(|e| project(&e.descriptors, &basis, e.area)).collect();
        Ok(Screen { basis, models, labels: vec![String::new(); entries.len()] })
    }

    /// Each model's label (empty unless set).
    pub fn labels(&self) -> &[String] {
        &self.labels
    }

    /// Set the models' labels (one per model, in order).
    pub fn set_labels(&mut self, labels: Vec<String>) -> Result<()> {
        if labels.len() != self.models.len() {
            return Err(Error::InvalidArgument(format!("screen: {} labels for {} models", labels.len(), self.models.len())));
        }
        self.labels = labels;
        Ok(())
    }

    /// The screen as bytes (the format above).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut p = Writer::default();
        p.u64(self.basis.ncols() as u64);
        for r in 0..self.basis.nrows() {
            for c in 0..self.basis.ncols() {
                p.f64(self.basis[(r, c)]);
            }
        }
        p.u64(self.models.len() as u64);
        for (m, label) in self.models.iter().zip(&self.labels) {
            p.string(label);
            p.f64(m.area);
            p.u64(m.rows.nrows() as u64);
            for r in 0..m.rows.nrows() {
                for c in 0..m.rows.ncols() {
                    p.0.extend_from_slice(&m.rows[(r, c)].to_le_bytes());
                }
            }
        }
        let mut out = Writer::default();
        out.0.extend_from_slice(&SCREEN_MAGIC);
        out.u32(SCREEN_FORMAT);
        out.u64(p.0.len() as u64);
        out.u32(crc32(&p.0));
        out.0.extend_from_slice(&p.0);
        out.0
    }

    /// A screen from [`Screen::to_bytes`]; a foreign, stale, truncated or corrupted input is
    /// an [`Error::PreparedShape`] saying which (`path` names the source in messages).
    pub fn from_bytes(bytes: &[u8], path: Option<&Path>) -> Result<Self> {
        let fail = |reason: String| Error::PreparedShape { path: path.map_or_else(|| PathBuf::from("<bytes>"), Path::to_path_buf), message: reason };
        if bytes.len() < 8 || bytes[..8] != SCREEN_MAGIC {
            return Err(fail("not a dualspectra screen file (no DSSCREEN header)".into()));
        }
        let mut r = Reader { bytes, at: 8 };
        let header = (|| -> std::result::Result<(u32, u64, u32), String> { Ok((r.u32()?, r.u64()?, r.u32()?)) })().map_err(fail)?;
        let (version, length, crc) = header;
        if version != SCREEN_FORMAT {
            return Err(fail(format!("screen format {version}, this library reads {SCREEN_FORMAT}: make the screen again")));
        }
        let payload = &bytes[r.at..];
        if (payload.len() as u64) < length {
            return Err(fail(format!("truncated: {} payload bytes of {length}", payload.len())));
        }
        let payload = &payload[..length as usize];
        if crc32(payload) != crc {
            return Err(fail("corrupted (checksum mismatch)".into()));
        }
        read_screen(&mut Reader { bytes: payload, at: 0 }).map_err(fail)
    }

    /// Write the screen to `path`.
    pub fn save(&self, path: &Path) -> Result<()> {
        std::fs::write(path, self.to_bytes()).map_err(|source| Error::Io { path: path.to_path_buf(), source })
    }

    /// Read a screen written by [`Screen::save`].
    pub fn load(path: &Path) -> Result<Self> {
        let bytes = std::fs::read(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
        Self::from_bytes(&bytes, Some(path))
    }

    /// Models in the screen.
    pub fn len(&self) -> usize {
        self.models.len()
    }

    /// Whether the screen has no model (never: [`Screen::new`] refuses that).
    pub fn is_empty(&self) -> bool {
        self.models.is_empty()
    }

    /// Bytes the screen holds per model (its projected keypoints) and for the basis.
    pub fn bytes(&self) -> (usize, usize) {
        let per_model = self.models.first().map_or(0, |m| m.rows.nrows() * m.rows.ncols() * 4 + m.norms2.len() * 4 + 8);
        (per_model, self.basis.nrows() * self.basis.ncols() * 8)
    }

    /// Every model's screen score for `partial` under `scale` (see the module's formula):
    /// `(model index, score)`, lowest (most similar) first, ties by the lowest distance $d_m$,
    /// then by index, `+inf` (cannot hold the partial in the given units) last. Cancelling
    /// `progress` returns [`Error::Cancelled`].
    pub fn rank(&self, partial: &TriMesh, scale: Scale, progress: &Progress) -> Result<Vec<(usize, f64)>> {
        self.rank_with(partial, scale, true, progress)
    }

    /// [`Screen::rank`]; with `relative` false, by the absolute distance alone (for studies).
    pub(crate) fn rank_with(&self, partial: &TriMesh, scale: Scale, relative: bool, progress: &Progress) -> Result<Vec<(usize, f64)>> {
        let (component, _) = crate::localizer::stages::largest_component(partial)?;
        let area = component.area();
        if !(area > 0.0 && area.is_finite()) {
            return Err(Error::InvalidArgument("screen: the partial shape has no area".into()));
        }
        let grid = area_grid();
        let factor = match scale {
            Scale::Same => Some(1.0),
            Scale::Factor(f) => Some(f),
            Scale::Auto => None,
        };
        // The hypotheses each model needs: the grid point nearest its area fraction, or all.
        let hypotheses: Vec<Option<usize>> = self
            .models
            .iter()
            .map(|m| factor.map(|f| area * f * f / m.area))
            .map(|a| a.map(|a| if a > LARGEST_AREA_RATIO { usize::MAX } else { nearest_grid_point(&grid, a) }))
            .collect();
        let mut needed = vec![factor.is_none(); grid.len()];
        for h in hypotheses.iter().flatten().filter(|&&h| h != usize::MAX) {
            needed[*h] = true;
        }
        progress.report(0.0, "describing the partial")?;
        let keypoints = farthest_points(&component, QUERY_KEYPOINTS);
        // Query rows per grid point (projected), and their offsets in one stacked matrix.
        let mut blocks: Vec<Option<(usize, usize)>> = vec![None; grid.len()];
        let mut spreads = vec![f64::INFINITY; grid.len()];
        let mut stacked: Vec<Mat<f32>> = Vec::new();
        let mut offset = 0;
        for (h, &la) in grid.iter().enumerate().filter(|(h, _)| needed[*h]) {
            let s = (10f64.powf(la) / area).sqrt();
            let d = shot::shot_keypoint_descriptors(&component, &keypoints, shot::DEFAULT_RADIUS_FRACTION / s, shot::DEFAULT_MIN_NEIGHBORS)?;
            let p = project(&live_rows(&d), &self.basis, 0.0);
            spreads[h] = own_spread(&p.rows);
            if p.rows.nrows() > 0 {
                blocks[h] = Some((offset, p.rows.nrows()));
                offset += p.rows.nrows();
                stacked.push(p.rows);
            }
        }
        let dims = self.basis.ncols();
        let mut query = Mat::<f32>::zeros(offset, dims);
        let mut row = 0;
        for block in &stacked {
            query.as_mut().subrows_mut(row, block.nrows()).copy_from(block);
            row += block.nrows();
        }
        progress.report(0.2, "screening")?;
        let chunk = 64;
        // Each model's hypotheses: the one its units give, none, or the whole grid.
        let own = |i: usize| -> Vec<usize> {
            match hypotheses[i] {
                Some(usize::MAX) => Vec::new(),
                Some(h) => vec![h],
                None => (0..grid.len()).collect(),
            }
        };
        // The models the library's median is taken over: all of them up to MEDIAN_MODELS, else
        // an even stride of about that many.
        let stride = self.models.len().div_ceil(MEDIAN_MODELS);
        let sampled = |i: usize| i.is_multiple_of(stride);
        // Per model, the mean nearest distance under its own hypotheses and, for the sampled
        // models, under every hypothesis some model needs (+inf elsewhere).
        let mut per_hypothesis = vec![vec![f64::INFINITY; grid.len()]; self.models.len()];
        for (c, out) in per_hypothesis.chunks_mut(chunk).enumerate() {
            progress.report(0.2 + 0.8 * (c * chunk) as f64 / self.models.len() as f64, "screening")?;
            out.par_iter_mut().enumerate().for_each(|(j, costs)| {
                let i = c * chunk + j;
                let model = &self.models[i];
                let wanted: Vec<usize> = if sampled(i) { (0..grid.len()).filter(|&h| needed[h]).collect() } else { own(i) };
                for h in wanted {
                    if let Some((start, rows)) = blocks[h] {
                        let d = nearest_distances(&model.rows, &model.norms2, query.as_ref().subrows(start, rows));
                        costs[h] = d.iter().map(|&x| x as f64).sum::<f64>() / rows as f64;
                    }
                }
            });
        }
        // Under each hypothesis, the library's median model: the partial described with a small
        // support looks like every model, and a scale at which every model looks alike does not
        // make any of them look right.
        let medians: Vec<f64> = (0..grid.len())
            .map(|h| {
                let mut column: Vec<f64> =
                    per_hypothesis.iter().enumerate().filter(|&(i, _)| sampled(i)).map(|(_, c)| c[h]).filter(|x| x.is_finite()).collect();
                column.sort_by(f64::total_cmp);
                column.get(column.len() / 2).copied().unwrap_or(f64::INFINITY)
            })
            .collect();
        let lowest = |i: usize, value: &dyn Fn(usize) -> f64| own(i).into_iter().map(value).fold(f64::INFINITY, f64::min);
        let absolute: Vec<f64> = (0..self.models.len()).map(|i| lowest(i, &|h| per_hypothesis[i][h])).collect();
        let scores: Vec<f64> = if !relative {
            absolute.clone()
        } else {
            // Each model's lowest distance over its hypotheses in units of `unit` there.
            let relative_to = |unit: &[f64]| -> Vec<usize> {
                let usable = |h: usize| unit[h] > 0.0 && unit[h].is_finite();
                positions(&(0..self.models.len()).map(|i| lowest(i, &|h| if usable(h) { per_hypothesis[i][h] / unit[h] } else { f64::INFINITY })).collect::<Vec<_>>())
            };
            let (by_library, by_partial) = (relative_to(&medians), relative_to(&spreads));
            (0..absolute.len()).map(|i| if absolute[i].is_finite() { 0.5 * (by_library[i] + by_partial[i]) as f64 } else { f64::INFINITY }).collect()
        };
        progress.report(1.0, "screened")?;
        let mut order: Vec<(usize, f64)> = scores.into_iter().enumerate().collect();
        order.sort_by(|a, b| a.1.total_cmp(&b.1).then(absolute[a.0].total_cmp(&absolute[b.0])).then(a.0.cmp(&b.0)));
        Ok(order)
    }
}

impl Screen {
    /// How alike models `i` and `j` look to the screen: the mean distance from each model's
    /// keypoint descriptors to the other's nearest, averaged both ways (0 for a model and
    /// itself; deformed copies of one shape are near, other shapes far). `None` for an index
    /// out of range.
    #[cfg_attr(not(feature = "lab"), allow(dead_code))] // a study of the search's confidence
    pub(crate) fn model_distance(&self, i: usize, j: usize) -> Option<f64> {
        let (a, b) = (self.models.get(i)?, self.models.get(j)?);
        let one_way = |from: &Projected, to: &Projected| {
            let d = nearest_distances(&to.rows, &to.norms2, from.rows.as_ref());
            if d.is_empty() { f64::INFINITY } else { d.iter().map(|&x| x as f64).sum::<f64>() / d.len() as f64 }
        };
        Some(0.5 * (one_way(a, b) + one_way(b, a)))
    }
}

/// The payload of a screen file, every count checked against the bytes left.
fn read_screen(r: &mut Reader<'_>) -> std::result::Result<Screen, String> {
    let dim = shot::SHOT_DIM;
    let dims = r.count(0, "dimensions")?;
    if dims == 0 || dims > dim {
        return Err(format!("{dims} dimensions (1 to {dim})"));
    }
    let values = r.f64_array(dim * dims)?;
    let basis = Mat::from_fn(dim, dims, |i, j| values[i * dims + j]);
    let n = r.count(20, "models")?;
    let mut models = Vec::with_capacity(n);
    let mut labels = Vec::with_capacity(n);
    for i in 0..n {
        labels.push(r.string()?);
        let area = r.f64()?;
        if !(area > 0.0 && area.is_finite()) {
            return Err(format!("model {i}: area {area}"));
        }
        let rows = r.count(4 * dims, "keypoints")?;
        let raw = r.take(rows * dims * 4)?;
        let v: Vec<f32> = raw.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
        if v.iter().any(|x| !x.is_finite()) {
            return Err(format!("model {i}: a non-finite descriptor value"));
        }
        let m = Mat::from_fn(rows, dims, |a, b| v[a * dims + b]);
        let norms2 = (0..rows).map(|a| (0..dims).map(|b| m[(a, b)] * m[(a, b)]).sum()).collect();
        models.push(Projected { rows: m, norms2, area });
    }
    if r.remaining() != 0 {
        return Err(format!("{} bytes after the last model", r.remaining()));
    }
    if models.is_empty() {
        return Err("no model".into());
    }
    Ok(Screen { basis, models, labels })
}

/// Each value's position (0 = lowest) in `values` sorted ascending, ties by index.
fn positions(values: &[f64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]).then(a.cmp(&b)));
    let mut out = vec![0; values.len()];
    for (p, &i) in order.iter().enumerate() {
        out[i] = p;
    }
    out
}

/// How alike the partial's own keypoints look under one hypothesis: the mean distance from
/// each row of `rows` to the nearest other row (`+inf` below two rows).
fn own_spread(rows: &Mat<f32>) -> f64 {
    let n = rows.nrows();
    if n < 2 {
        return f64::INFINITY;
    }
    let total: f64 = (0..n)
        .map(|a| {
            let d2 = |b: usize| (0..rows.ncols()).map(|c| f64::from(rows[(a, c)] - rows[(b, c)]).powi(2)).sum::<f64>();
            (0..n).filter(|&b| b != a).map(d2).fold(f64::INFINITY, f64::min).sqrt()
        })
        .sum();
    total / n as f64
}

/// The grid point (an index of `grid`, in $\log_{10}$ area fraction) nearest `fraction`,
/// clamped to the grid.
fn nearest_grid_point(grid: &[f64], fraction: f64) -> usize {
    let la = fraction.max(1e-300).log10();
    (0..grid.len()).min_by(|&a, &b| (grid[a] - la).abs().total_cmp(&(grid[b] - la).abs())).unwrap_or(0)
}

/// The rows of `d` with a norm of at least [`LIVE_ROW`].
fn live_rows(d: &Mat<f64>) -> Mat<f64> {
    let live: Vec<usize> = (0..d.nrows()).filter(|&i| (0..d.ncols()).map(|c| d[(i, c)].powi(2)).sum::<f64>() >= LIVE_ROW * LIVE_ROW).collect();
    Mat::from_fn(live.len(), d.ncols(), |i, c| d[(live[i], c)])
}

/// `d` (rows x SHOT_DIM) times `basis`, in single precision, with the rows' squared norms.
fn project(d: &Mat<f64>, basis: &Mat<f64>, area: f64) -> Projected {
    let p = d * basis;
    let rows = Mat::from_fn(p.nrows(), p.ncols(), |i, j| p[(i, j)] as f32);
    let norms2 = (0..rows.nrows()).map(|i| (0..rows.ncols()).map(|j| rows[(i, j)] * rows[(i, j)]).sum()).collect();
    Projected { rows, norms2, area }
}

/// The `dimensions` leading principal directions (`SHOT_DIM x dimensions`) of the entries'
/// rows (at most [`PCA_ROWS`] of them, on a stride); the identity's first columns when
/// `dimensions` is the full descriptor.
fn principal_directions(entries: &[ScreenEntry], dimensions: usize) -> Mat<f64> {
    let dim = shot::SHOT_DIM;
    if dimensions >= dim {
        return Mat::identity(dim, dim);
    }
    let total: usize = entries.iter().map(|e| e.descriptors.nrows()).sum();
    let stride = total.div_ceil(PCA_ROWS).max(1);
    let rows: Vec<(usize, usize)> = entries
        .iter()
        .enumerate()
        .flat_map(|(e, entry)| (0..entry.descriptors.nrows()).map(move |r| (e, r)))
        .step_by(stride)
        .collect();
    let x = Mat::from_fn(rows.len(), dim, |i, c| entries[rows[i].0].descriptors[(rows[i].1, c)]);
    let n = x.nrows().max(1) as f64;
    let mean: Vec<f64> = (0..dim).map(|c| (0..x.nrows()).map(|i| x[(i, c)]).sum::<f64>() / n).collect();
    let centered = Mat::from_fn(x.nrows(), dim, |i, c| x[(i, c)] - mean[c]);
    let covariance = centered.transpose() * &centered;
    match covariance.self_adjoint_eigen(faer::Side::Lower) {
        // Eigenvalues ascending: the last columns are the leading directions.
        Ok(eig) => Mat::from_fn(dim, dimensions, |r, c| eig.U()[(r, dim - 1 - c)]),
        Err(_) => Mat::from_fn(dim, dimensions, |r, c| if r == c { 1.0 } else { 0.0 }),
    }
}

/// `n` vertices of `mesh` spread by farthest-point sampling (Euclidean), from the vertex
/// farthest from the centroid (ties: the lowest index); all of them when `n` is at least
/// their number.
pub(crate) fn farthest_points(mesh: &TriMesh, n: usize) -> Vec<u32> {
    let v = mesh.vertices();
    if n >= v.len() {
        return (0..v.len() as u32).collect();
    }
    let count = v.len() as f64;
    let centroid = (0..3).map(|c| v.iter().map(|p| p[c]).sum::<f64>() / count).collect::<Vec<_>>();
    let d2 = |a: [f64; 3], b: &[f64]| (0..3).map(|c| (a[c] - b[c]).powi(2)).sum::<f64>();
    let first = (0..v.len()).max_by(|&a, &b| d2(v[a], &centroid).total_cmp(&d2(v[b], &centroid)).then(b.cmp(&a))).unwrap_or(0);
    let mut chosen = vec![first as u32];
    let mut nearest: Vec<f64> = v.iter().map(|p| d2(*p, &v[first])).collect();
    while chosen.len() < n {
        let next = (0..v.len()).max_by(|&a, &b| nearest[a].total_cmp(&nearest[b]).then(b.cmp(&a))).unwrap_or(0);
        chosen.push(next as u32);
        for (i, p) in v.iter().enumerate() {
            nearest[i] = nearest[i].min(d2(*p, &v[next]));
        }
    }
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluation::synthetic::{cut_by_plane, default_limbs, figure};

    /// Farthest points are distinct and spread: the first `n` of a grid cover it.
    #[test]
    fn farthest_points_are_distinct_and_deterministic() {
        let mesh = crate::mesh::generate::grid(1.0, 1.0, 10, 10);
        let a = farthest_points(&mesh, 12);
        assert_eq!(a, farthest_points(&mesh, 12));
        let mut sorted = a.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), 12);
        assert_eq!(farthest_points(&mesh, 1000).len(), mesh.n_vertices());
    }

    /// A cut of one shape, in its units and in other units, ranks that shape first among
    /// differently shaped ones.
    #[test]
    fn a_cut_ranks_its_own_shape_first() {
        let own = figure(4, &default_limbs()).unwrap();
        let sphere = crate::mesh::generate::icosphere(3);
        let sheet = crate::mesh::generate::grid(2.0, 1.0, 30, 15);
        let shapes = [sheet, own.map_positions(|p| p.map(|c| c * 3.0)).unwrap(), sphere];
        let entries: Vec<ScreenEntry> = shapes.iter().map(|s| ScreenEntry::new(s).unwrap()).collect();
        let screen = Screen::new(&entries).unwrap();
        assert_eq!(screen.len(), 3);
        let (cut, _) = cut_by_plane(&own, [0.3, 1.0, 0.2], 0.0).unwrap();
        let in_units = cut.map_positions(|p| p.map(|c| c * 3.0)).unwrap();
        let ranked = screen.rank(&in_units, Scale::Same, &Progress::none()).unwrap();
        assert_eq!(ranked[0].0, 1, "{ranked:?}");
        let other_units = cut.map_positions(|p| p.map(|c| c * 1e-3)).unwrap();
        let ranked = screen.rank(&other_units, Scale::Auto, &Progress::none()).unwrap();
        assert_eq!(ranked[0].0, 1, "{ranked:?}");
        // In the same units, a partial larger than a model cannot be in it.
        let big = cut.map_positions(|p| p.map(|c| c * 1e3)).unwrap();
        let ranked = screen.rank(&big, Scale::Same, &Progress::none()).unwrap();
        assert!(ranked.iter().all(|r| r.1.is_infinite()), "{ranked:?}");
    }

    /// Above [`MEDIAN_MODELS`] models the library's median comes from a stride of them, and
    /// the ranking still puts a copy of the partial's own shape first.
    #[test]
    fn a_library_above_the_median_sample_ranks_its_own_shape_first() {
        let own = figure(3, &default_limbs()).unwrap();
        let shapes = [crate::mesh::generate::grid(2.0, 1.0, 30, 15), own.clone(), crate::mesh::generate::icosphere(3)];
        let entries: Vec<ScreenEntry> = shapes.iter().map(|s| ScreenEntry::new(s).unwrap()).collect();
        let copies = MEDIAN_MODELS / shapes.len() + 1;
        let library: Vec<ScreenEntry> = (0..copies).flat_map(|_| entries.iter().cloned()).collect();
        assert!(library.len() > MEDIAN_MODELS);
        let screen = Screen::new(&library).unwrap();
        let (cut, _) = cut_by_plane(&own, [0.3, 1.0, 0.2], 0.0).unwrap();
        let ranked = screen.rank(&cut, Scale::Same, &Progress::none()).unwrap();
        assert_eq!(ranked.len(), library.len());
        assert!(ranked[..copies].iter().all(|&(m, _)| m % shapes.len() == 1), "{:?}", &ranked[..5]);
    }

    /// A saved screen loads equal (same ranking), and damaged bytes are refused.
    #[test]
    fn a_saved_screen_ranks_the_same_and_damage_is_refused() {
        let shapes = [crate::mesh::generate::icosphere(2), figure(3, &default_limbs()).unwrap()];
        let entries: Vec<ScreenEntry> = shapes.iter().map(|s| ScreenEntry::new(s).unwrap()).collect();
        let mut screen = Screen::new(&entries).unwrap();
        assert!(screen.set_labels(vec!["a".into()]).is_err());
        screen.set_labels(vec!["sphere".into(), "figure".into()]).unwrap();
        let bytes = screen.to_bytes();
        let loaded = Screen::from_bytes(&bytes, None).unwrap();
        assert_eq!(loaded.labels(), screen.labels());
        let (cut, _) = cut_by_plane(&shapes[1], [0.3, 1.0, 0.2], 0.0).unwrap();
        let a = screen.rank(&cut, Scale::Same, &Progress::none()).unwrap();
        let b = loaded.rank(&cut, Scale::Same, &Progress::none()).unwrap();
        assert_eq!(a, b);
        for damaged in [bytes[..bytes.len() - 3].to_vec(), { let mut d = bytes.clone(); let n = d.len(); d[n - 5] ^= 1; d }, b"DSPREP\r\n....".to_vec()] {
            assert!(matches!(Screen::from_bytes(&damaged, None), Err(Error::PreparedShape { .. })));
        }
    }

    #[test]
    fn empty_library_and_flat_shapes_are_errors() {
        assert!(Screen::new(&[]).is_err());
        let flat = TriMesh::new(vec![[0.0; 3]; 3], vec![[0, 1, 2]]);
        if let Ok(flat) = flat {
            assert!(ScreenEntry::new(&flat).is_err());
        }
    }
}
