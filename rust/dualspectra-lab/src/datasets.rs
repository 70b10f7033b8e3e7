//! Benchmark datasets on disk, in the layouts of the shipped dev sets (`$DUALSPECTRA_DATA`,
//! see its README). [`Dataset::open`] tells them apart by their folders:
//!
//! ```text
//! SHREC'16 CUTS / HOLES (Cosmo, Rodolà et al. 2016)
//!   <root>/null/<class>.off                       full shapes
//!   <root>/{cuts,holes}/<set>_<class>_shape_<i>.off  partial shapes
//!   <root>/{cuts,holes}/<name>.baryc_gt[_sym]     per partial vertex: <full triangle, 1-based> w1 w2 w3
//! PFARM (Attaiki et al. 2021): one template, scans of other people
//!   <root>/null/<template>.off                    the one full shape
//!   <root>/cuts/<name>.off
//!   <root>/gt/<name>_<template>.vertex_gt[_sym]   the region: 0-based full vertices, one per line
//! PFAUST-M / -H (Bracha, Dagès, Kimmel 2023): FAUST people with holes
//!   <root>/null/tr_reg_<P>0.off                   person P in pose 0
//!   <root>/partials/tr_reg_<PQ>.off               person P, pose Q, with holes
//!   <root>/partials/<name>.vertex_gt[_sym]
//! ```
//!
//! A `.baryc_gt` region marks the three vertices of every row's triangle (marking only the
//! largest-weight vertex leaves holes where the partial is coarser than the full shape).
//! `_sym` is the left-right mirrored match. Ground truth names the files' elements and is
//! mapped through the reader's report onto the mesh it returns. The dataset root is an
//! argument; [`data_root_from_env`] reads `$DUALSPECTRA_DATA`.

use dualspectra::mesh::io::{read_mesh_with_report, ReadOptions, ReadReport};
use dualspectra::mesh::TriMesh;
use dualspectra::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

pub use dualspectra::evaluation::synthetic::BarycentricRow;

/// Environment variable naming the folder that holds the datasets (`shrec16/`, ...).
pub const DATA_ENV: &str = "DUALSPECTRA_DATA";

/// The dev sets under `$DUALSPECTRA_DATA`, in the order `bench --all` runs them.
pub const DEV_SETS: [&str; 5] = ["shrec16", "shrec16_holes", "pfarm", "pfaust_m", "pfaust_h"];

/// `$DUALSPECTRA_DATA` if set and non-empty.
pub fn data_root_from_env() -> Option<PathBuf> {
    std::env::var_os(DATA_ENV)
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
}

/// The folder holding the dev sets: `$DUALSPECTRA_DATA` if set, else `../shared/datasets`
/// beside the repository if it exists (where the setup puts them).
pub fn data_root() -> Option<PathBuf> {
    data_root_from_env().or_else(|| {
        let beside = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/datasets");
        beside.is_dir().then_some(beside)
    })
}

/// [`data_root`] for the tests that need the data (`#[ignore]`d, run with
/// `--include-ignored`): panics with what to set when the data is absent, since a test that
/// was asked to run must not pass without it.
pub fn data_root_for_tests() -> PathBuf {
    data_root().unwrap_or_else(|| panic!("the dev sets are not at ../shared/datasets beside the repository; set {DATA_ENV}"))
}

/// How a dataset's files are laid out (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Layout {
    Shrec16,
    Pfarm,
    Pfaust,
}

/// Which kind of ground-truth file a pair has.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GroundTruthKind {
    /// `.baryc_gt`: per partial vertex, a 1-based triangle of the full shape and weights.
    Barycentric,
    /// `.vertex_gt`: the region, 0-based vertices of the full shape.
    Vertices,
}

/// One partial/full pair of a dataset (paths only; see [`Pair::load`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Pair {
    /// File stem of the partial shape, e.g. `cuts_cat_shape_1`.
    pub name: String,
    /// Class: the SHREC'16 class (`cat`), else the full shape's file stem.
    pub class: String,
    /// Index `i` of SHREC'16's `..._shape_<i>` (0 in the other layouts).
    pub index: u32,
    pub full: PathBuf,
    pub partial: PathBuf,
    pub gt: PathBuf,
    pub gt_sym: PathBuf,
    pub gt_kind: GroundTruthKind,
}

/// A loaded pair: both meshes and the ground-truth masks over the full mesh's vertices.
#[derive(Debug, Clone)]
pub struct LoadedPair {
    pub full: TriMesh,
    pub partial: TriMesh,
    /// `true` on the full mesh's vertices covered by the partial shape.
    pub gt: Vec<bool>,
    /// The same for the left-right mirrored correspondence (`None` if the file is absent).
    pub gt_sym: Option<Vec<bool>>,
    /// What reading repaired in the full and the partial shape.
    pub full_report: ReadReport,
    pub partial_report: ReadReport,
}

/// Split `<prefix>_<class>_shape_<i>` into `(class, i)`. The prefix is the part before the
/// first `_` (`cuts`, `holes`); classes may themselves contain `_`.
pub fn parse_pair_name(name: &str) -> Option<(String, u32)> {
    let (_, rest) = name.split_once('_')?;
    let (class, index) = rest.rsplit_once("_shape_")?;
    if class.is_empty() {
        return None;
    }
    Some((class.to_string(), index.parse().ok()?))
}

/// A dataset folder: `null/` with the full shapes and one folder of partial shapes.
#[derive(Debug, Clone)]
pub struct Dataset {
    root: PathBuf,
    partial_dir: PathBuf,
    layout: Layout,
}

fn io_err(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source,
    }
}

fn parse_err(path: &Path, message: impl Into<String>) -> Error {
    Error::Parse {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// The `.off` files of `dir` (sorted by path).
fn off_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| io_err(dir, e))? {
        let path = entry.map_err(|e| io_err(dir, e))?.path();
        let is_off = path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("off"));
        if is_off && path.is_file() {
            out.push(path);
        }
    }
    out.sort();
    Ok(out)
}

fn stem(path: &Path) -> Option<String> {
    path.file_stem().and_then(|s| s.to_str()).map(str::to_string)
}

impl Dataset {
    /// Open `root`, which must hold `null/` and `cuts/`, `holes/` or `partials/`: PFARM
    /// when `gt/` is there too, PFAUST for `partials/`, SHREC'16 otherwise.
    pub fn open(root: impl AsRef<Path>) -> Result<Self> {
        let root = root.as_ref().to_path_buf();
        if !root.is_dir() {
            return Err(parse_err(&root, "dataset folder not found (expected a folder with null/ and cuts/, holes/ or partials/)"));
        }
        if !root.join("null").is_dir() {
            return Err(parse_err(&root, "not a dataset folder: no null/ subfolder (full shapes)"));
        }
        let (dir, layout) = if root.join("partials").is_dir() {
            ("partials", Layout::Pfaust)
        } else if root.join("cuts").is_dir() && root.join("gt").is_dir() {
            ("cuts", Layout::Pfarm)
        } else if root.join("cuts").is_dir() {
            ("cuts", Layout::Shrec16)
        } else if root.join("holes").is_dir() {
            ("holes", Layout::Shrec16)
        } else {
            return Err(parse_err(&root, "not a dataset folder: no cuts/, holes/ or partials/ subfolder"));
        };
        Ok(Dataset { partial_dir: root.join(dir), root, layout })
    }

    /// `$DUALSPECTRA_DATA/shrec16`, if the variable is set (the folder may still be invalid).
    pub fn from_env() -> Option<Result<Self>> {
        Self::from_env_named("shrec16")
    }

    /// `$DUALSPECTRA_DATA/<set>`, if the variable is set (the folder may still be invalid).
    pub fn from_env_named(set: &str) -> Option<Result<Self>> {
        data_root_from_env().map(|r| Self::open(r.join(set)))
    }

    pub fn root(&self) -> &Path {
        &self.root
    }

    pub fn layout(&self) -> Layout {
        self.layout
    }

    /// Every pair with a partial `.off` (SHREC'16: whose name parses, see
    /// [`parse_pair_name`]), sorted by class, index and name. Missing full shapes or
    /// ground-truth files are reported when the pair is loaded, not here, so a listing
    /// never fails on one bad pair.
    pub fn pairs(&self) -> Result<Vec<Pair>> {
        let null = self.root.join("null");
        let template = match self.layout {
            Layout::Pfarm => {
                let fulls = off_files(&null)?;
                let [one] = fulls.as_slice() else {
                    return Err(parse_err(&null, format!("a PFARM folder holds one full shape (the template); found {} .off files", fulls.len())));
                };
                Some(one.clone())
            }
            _ => None,
        };
        let mut pairs = Vec::new();
        for path in off_files(&self.partial_dir)? {
            let Some(name) = stem(&path) else { continue };
            let with_ext = |dir: &Path, file: String| (dir.join(&file), dir.join(format!("{file}_sym")));
            let pair = match self.layout {
                Layout::Shrec16 => {
                    let Some((class, index)) = parse_pair_name(&name) else { continue };
                    let (gt, gt_sym) = with_ext(&self.partial_dir, format!("{name}.baryc_gt"));
                    Pair { full: null.join(format!("{class}.off")), gt, gt_sym, gt_kind: GroundTruthKind::Barycentric, partial: path, name, class, index }
                }
                Layout::Pfarm => {
                    let full = template.clone().unwrap_or_default();
                    let class = stem(&full).unwrap_or_default();
                    let (gt, gt_sym) = with_ext(&self.root.join("gt"), format!("{name}_{class}.vertex_gt"));
                    Pair { full, gt, gt_sym, gt_kind: GroundTruthKind::Vertices, partial: path, name, class, index: 0 }
                }
                Layout::Pfaust => {
                    // tr_reg_<P><Q> against tr_reg_<P>0: the last digit is the pose.
                    let Some(person) = name.strip_suffix(|c: char| c.is_ascii_digit()) else { continue };
                    let class = format!("{person}0");
                    let (gt, gt_sym) = with_ext(&self.partial_dir, format!("{name}.vertex_gt"));
                    Pair { full: null.join(format!("{class}.off")), gt, gt_sym, gt_kind: GroundTruthKind::Vertices, partial: path, name, class, index: 0 }
                }
            };
            pairs.push(pair);
        }
        pairs.sort_by(|a, b| (&a.class, a.index, &a.name).cmp(&(&b.class, b.index, &b.name)));
        Ok(pairs)
    }
}

/// Parse a `.baryc_gt` / `.baryc_gt_sym` file (whitespace-separated rows
/// `<1-based triangle> w1 w2 w3`; blank lines ignored). The triangle index is written as a
/// float in the original files (`1.4700000e+02`) and must be a positive integer.
pub fn read_barycentric_gt(path: &Path) -> Result<Vec<BarycentricRow>> {
    let text = std::fs::read_to_string(path).map_err(|e| io_err(path, e))?;
    parse_barycentric_gt(&text, path)
}

/// [`read_barycentric_gt`] on text in memory (`path` only names the source in errors).
pub fn parse_barycentric_gt(text: &str, path: &Path) -> Result<Vec<BarycentricRow>> {
    let mut rows = Vec::new();
    for (lineno, line) in text.lines().enumerate() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields.is_empty() {
            continue;
        }
        let at = |msg: String| parse_err(path, format!("line {}: {msg}", lineno + 1));
        if fields.len() != 4 {
            return Err(at(format!(
                "expected 4 numbers (triangle w1 w2 w3), found {}",
                fields.len()
            )));
        }
        let mut v = [0.0; 4];
        for (k, f) in fields.iter().enumerate() {
            v[k] = f
                .parse::<f64>()
                .map_err(|_| at(format!("'{f}' is not a number")))?;
            if !v[k].is_finite() {
                return Err(at(format!("'{f}' is not finite")));
            }
        }
        let t = v[0];
        if t < 1.0 || t.fract() != 0.0 || t > u32::MAX as f64 {
            return Err(at(format!(
                "triangle index {} is not a positive integer (indices are 1-based)",
                fields[0]
            )));
        }
        rows.push(BarycentricRow {
            triangle: t as u32 - 1,
            weights: [v[1], v[2], v[3]],
        });
    }
    if rows.is_empty() {
        return Err(parse_err(path, "no ground-truth rows"));
    }
    Ok(rows)
}

/// Row `r`'s triangle (0-based), or an error naming the row if it is not below `n_records`.
fn checked_triangle(row: &BarycentricRow, r: usize, n_records: usize, path: &Path) -> Result<usize> {
    let t = row.triangle as usize;
    if t >= n_records {
        return Err(parse_err(
            path,
            format!("row {}: triangle {} is out of range (the full shape has {n_records} faces; indices are 1-based)", r + 1, t + 1),
        ));
    }
    Ok(t)
}

/// Ground-truth mask over `full`'s vertices: the three vertices of every row's triangle.
/// `face_groups[r]` lists the mesh triangles of file face record `r` (the identity for a
/// pure triangle file; a polygon record maps to its fan triangles). Errors name the row
/// whose triangle is out of range.
pub fn ground_truth_mask(
    full: &TriMesh,
    rows: &[BarycentricRow],
    face_groups: Option<&[Vec<u32>]>,
    path: &Path,
) -> Result<Vec<bool>> {
    let n_records = face_groups.map_or(full.n_faces(), |g| g.len());
    let mut mask = vec![false; full.n_vertices()];
    for (r, row) in rows.iter().enumerate() {
        let t = checked_triangle(row, r, n_records, path)?;
        let mut mark = |tri: usize| {
            full.faces()[tri]
                .iter()
                .for_each(|&v| mask[v as usize] = true)
        };
        match face_groups {
            Some(groups) => groups[t].iter().for_each(|&tri| mark(tri as usize)),
            None => mark(t),
        }
    }
    Ok(mask)
}

/// Ground-truth mask over the vertices of a full shape read from a file, for rows that
/// name the file's triangles: each row's triangle goes through the read report, so the
/// mask is right when reading triangulated polygons, removed repeated triangles or
/// two-sided flaps (which renumbers the later triangles), dropped vertices, or split
/// non-manifold vertices. A row whose triangle reading removed marks the triangle's
/// vertices the mesh kept, each with all its copies (a flap's base, not its tip); a row
/// none of whose vertices is left is an error, as is a row out of range.
pub fn ground_truth_mask_in_file(
    full: &TriMesh,
    report: &ReadReport,
    rows: &[BarycentricRow],
    path: &Path,
) -> Result<Vec<bool>> {
    let n_records = report.file_faces;
    // Mesh triangles of record r: first[r]..first[r + 1] (face_origin is in record order).
    let mut first = vec![0usize; n_records + 1];
    for &r in &report.face_origin {
        if let Some(c) = first.get_mut(r as usize + 1) {
            *c += 1;
        }
    }
    for r in 0..n_records {
        first[r + 1] += first[r];
    }
    // File vertex -> mesh vertex, and (file vertex, mesh vertex) of the copies made by the
    // non-manifold split, sorted: a file vertex stands for all its copies.
    let mut mesh_vertex = vec![u32::MAX; report.file_vertices];
    let mut copies: Vec<(u32, u32)> = Vec::new();
    for (m, &f) in report.kept_vertices.iter().enumerate() {
        match mesh_vertex.get_mut(f as usize) {
            Some(slot) if *slot == u32::MAX => *slot = m as u32,
            Some(_) => copies.push((f, m as u32)),
            None => {}
        }
    }
    copies.sort_unstable();
    let mut mask = vec![false; full.n_vertices()];
    for (r, row) in rows.iter().enumerate() {
        let t = checked_triangle(row, r, n_records, path)?;
        let mut marked = false;
        let mut mark = |v: u32| {
            if let Some(m) = mask.get_mut(v as usize) {
                *m = true;
                marked = true;
            }
        };
        for tri in &full.faces()[first[t]..first[t + 1]] {
            tri.iter().for_each(|&v| mark(v));
        }
        // `removed_triangles` is in file order, hence sorted by record.
        let removed = &report.removed_triangles;
        let from = removed.partition_point(|&(rec, _)| (rec as usize) < t);
        for (_, tri) in removed[from..].iter().take_while(|&&(rec, _)| rec as usize == t) {
            for &v in tri {
                mark(mesh_vertex[v as usize]);
                let at = copies.partition_point(|&(f, _)| f < v);
                copies[at..].iter().take_while(|&&(f, _)| f == v).for_each(|&(_, m)| mark(m));
            }
        }
        if !marked {
            return Err(parse_err(
                path,
                format!("row {}: triangle {} of the full shape was removed by reading, with all its vertices", r + 1, t + 1),
            ));
        }
    }
    Ok(mask)
}

/// Read a full shape together with the grouping of its triangles by file face record
/// (`face_groups` of [`ground_truth_mask`]). A record whose triangle reading removed (a
/// repeated copy, a two-sided flap) has an empty group; [`ground_truth_mask_in_file`]
/// handles those too.
pub fn read_full_shape(path: &Path) -> Result<(TriMesh, Vec<Vec<u32>>)> {
    let (mesh, report) = read_mesh_with_report(path, &ReadOptions::default())?;
    let mut groups = vec![Vec::new(); report.file_faces];
    for (t, &r) in report.face_origin.iter().enumerate() {
        if let Some(g) = groups.get_mut(r as usize) {
            g.push(t as u32);
        }
    }
    Ok((mesh, groups))
}

/// Parse a `.vertex_gt` / `.vertex_gt_sym` file: one 0-based vertex index of the full
/// shape per line (blank lines ignored).
pub fn parse_vertex_gt(text: &str, path: &Path) -> Result<Vec<u32>> {
    let mut rows = Vec::new();
    for (lineno, line) in text.lines().enumerate() {
        let field = line.trim();
        if field.is_empty() {
            continue;
        }
        let v = field.parse::<u32>().map_err(|_| {
            let shown: String = field.chars().take(40).collect();
            parse_err(path, format!("line {}: '{shown}' is not a vertex index (0-based, one per line)", lineno + 1))
        })?;
        rows.push(v);
    }
    if rows.is_empty() {
        return Err(parse_err(path, "no ground-truth rows"));
    }
    Ok(rows)
}

/// Ground-truth mask over the vertices of a full shape read from a file, for a region
/// given as the file's vertices: every mesh vertex read from a listed file vertex is
/// marked. A listed vertex out of the file's range is an error naming it.
pub fn vertex_mask_in_file(full: &TriMesh, report: &ReadReport, region: &[u32], path: &Path) -> Result<Vec<bool>> {
    let mut listed = vec![false; report.file_vertices];
    for (r, &v) in region.iter().enumerate() {
        match listed.get_mut(v as usize) {
            Some(l) => *l = true,
            None => {
                return Err(parse_err(
                    path,
                    format!("line {}: vertex {v} is out of range (the full shape's file has {} vertices; indices are 0-based)", r + 1, report.file_vertices),
                ))
            }
        }
    }
    let mut mask = vec![false; full.n_vertices()];
    for (m, &f) in report.kept_vertices.iter().enumerate() {
        if let (Some(out), Some(&l)) = (mask.get_mut(m), listed.get(f as usize)) {
            *out = l;
        }
    }
    Ok(mask)
}

impl Pair {
    /// Load both meshes and the ground truth. Errors name the missing or bad file; a
    /// `.baryc_gt` must have one row per vertex record of the partial shape's file.
    pub fn load(&self) -> Result<LoadedPair> {
        for p in [&self.full, &self.partial, &self.gt] {
            if !p.is_file() {
                return Err(Error::Io {
                    path: p.clone(),
                    source: std::io::Error::new(
                        std::io::ErrorKind::NotFound,
                        format!("file of pair {} not found", self.name),
                    ),
                });
            }
        }
        // Scans keep loose points: dropped, and the ground truth follows the index map.
        let read = ReadOptions { drop_isolated: true, ..ReadOptions::default() };
        let (full, full_report) = read_mesh_with_report(&self.full, &read)?;
        let (partial, partial_report) = read_mesh_with_report(&self.partial, &read)?;
        let load_gt = |path: &Path| -> Result<Vec<bool>> {
            match self.gt_kind {
                GroundTruthKind::Barycentric => {
                    let rows = read_barycentric_gt(path)?;
                    if rows.len() != partial_report.file_vertices {
                        return Err(parse_err(
                            path,
                            format!("{} rows, but the partial shape's file has {} vertices (one row per vertex expected)", rows.len(), partial_report.file_vertices),
                        ));
                    }
                    ground_truth_mask_in_file(&full, &full_report, &rows, path)
                }
                GroundTruthKind::Vertices => {
                    let text = std::fs::read_to_string(path).map_err(|e| io_err(path, e))?;
                    vertex_mask_in_file(&full, &full_report, &parse_vertex_gt(&text, path)?, path)
                }
            }
        };
        let gt = load_gt(&self.gt)?;
        let gt_sym = if self.gt_sym.is_file() {
            Some(load_gt(&self.gt_sym)?)
        } else {
            None
        };
        Ok(LoadedPair { full, partial, gt, gt_sym, full_report, partial_report })
    }
}

/// Write a SHREC'16-layout dataset with one pair (used to build small test datasets):
/// `root/null/<class>.off`, `root/cuts/cuts_<class>_shape_<index>.off` and its `.baryc_gt`
/// (and `.baryc_gt_sym` if given), each row a triangle of `full` (0-based here, written
/// 1-based) and barycentric weights.
pub fn write_shrec16_pair(
    root: &Path,
    class: &str,
    index: u32,
    full: &TriMesh,
    partial: &TriMesh,
    gt: &[BarycentricRow],
    gt_sym: Option<&[BarycentricRow]>,
) -> Result<Pair> {
    use std::fmt::Write as _;
    if gt.len() != partial.n_vertices() {
        return Err(Error::InvalidArgument(format!(
            "{} ground-truth rows for a partial shape with {} vertices",
            gt.len(),
            partial.n_vertices()
        )));
    }
    let (null, cuts) = (root.join("null"), root.join("cuts"));
    for d in [&null, &cuts] {
        std::fs::create_dir_all(d).map_err(|e| io_err(d, e))?;
    }
    let name = format!("cuts_{class}_shape_{index}");
    let full_path = null.join(format!("{class}.off"));
    let partial_path = cuts.join(format!("{name}.off"));
    dualspectra::mesh::io::write_off(&full_path, full)?;
    dualspectra::mesh::io::write_off(&partial_path, partial)?;
    let write_rows = |path: &Path, rows: &[BarycentricRow]| -> Result<()> {
        let mut s = String::new();
        for r in rows {
            let _ = writeln!(
                s,
                "{} {:e} {:e} {:e}",
                r.triangle + 1,
                r.weights[0],
                r.weights[1],
                r.weights[2]
            );
        }
        std::fs::write(path, s).map_err(|e| io_err(path, e))
    };
    let gt_path = cuts.join(format!("{name}.baryc_gt"));
    let sym_path = cuts.join(format!("{name}.baryc_gt_sym"));
    write_rows(&gt_path, gt)?;
    if let Some(s) = gt_sym {
        write_rows(&sym_path, s)?;
    }
    Ok(Pair {
        name,
        class: class.into(),
        index,
        full: full_path,
        partial: partial_path,
        gt: gt_path,
        gt_sym: sym_path,
        gt_kind: GroundTruthKind::Barycentric,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertex_rows_parse_and_reject_bad_lines() {
        let p = Path::new("t.vertex_gt");
        assert_eq!(parse_vertex_gt("2\n\n 0 \n7\n", p).unwrap(), vec![2, 0, 7]);
        for bad in ["", "1 2\n", "-1\n", "x\n", "1.5\n"] {
            assert!(matches!(parse_vertex_gt(bad, p), Err(Error::Parse { .. })), "{bad:?}");
        }
    }

    /// A PFARM and a PFAUST folder with one pair each are told apart and loaded, the
    /// vertex ground truth following the reader's index map (a loose file vertex dropped).
    #[test]
    fn pfarm_and_pfaust_layouts_list_and_load_their_pairs() {
        let dir = std::env::temp_dir().join(format!("ds-layouts-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        // Full: a loose vertex 0, then a square (1..=4) of two triangles.
        let full = "OFF\n5 2 0\n9 9 9\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 1 2 3\n3 1 3 4\n";
        let partial = "OFF\n3 1 0\n0 0 0\n1 0 0\n1 1 0\n3 0 1 2\n";
        let write = |rel: &str, text: &str| {
            let path = dir.join(rel);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, text).unwrap();
        };
        write("pfarm/null/tpl.off", full);
        write("pfarm/cuts/cut-1--a.off", partial);
        write("pfarm/gt/cut-1--a_tpl.vertex_gt", "1\n2\n3\n");
        write("pfaust/null/tr_reg_030.off", full);
        write("pfaust/partials/tr_reg_034.off", partial);
        write("pfaust/partials/tr_reg_034.vertex_gt", "2\n3\n4\n");
        write("pfaust/partials/tr_reg_034.vertex_gt_sym", "1\n3\n4\n");
        let pfarm = Dataset::open(dir.join("pfarm")).unwrap();
        assert_eq!(pfarm.layout(), Layout::Pfarm);
        let pairs = pfarm.pairs().unwrap();
        assert_eq!(pairs.len(), 1);
        assert_eq!((pairs[0].name.as_str(), pairs[0].class.as_str()), ("cut-1--a", "tpl"));
        let data = pairs[0].load().unwrap();
        assert_eq!(data.gt, vec![true, true, true, false]);
        assert!(data.gt_sym.is_none());
        let pfaust = Dataset::open(dir.join("pfaust")).unwrap();
        assert_eq!(pfaust.layout(), Layout::Pfaust);
        let pairs = pfaust.pairs().unwrap();
        assert_eq!(pairs[0].full, dir.join("pfaust/null/tr_reg_030.off"));
        let data = pairs[0].load().unwrap();
        assert_eq!(data.gt, vec![false, true, true, true]);
        assert_eq!(data.gt_sym, Some(vec![true, false, true, true]));
        write("pfaust/partials/tr_reg_034.vertex_gt", "5\n");
        let e = pairs[0].load().unwrap_err().to_string();
        assert!(e.contains("vertex 5 is out of range"), "{e}");
        assert!(Dataset::open(dir.join("nowhere")).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn pair_names() {
        assert_eq!(parse_pair_name("cuts_cat_shape_1"), Some(("cat".into(), 1)));
        assert_eq!(
            parse_pair_name("holes_big_dog_shape_12"),
            Some(("big_dog".into(), 12))
        );
        assert_eq!(parse_pair_name("cuts_cat"), None);
        assert_eq!(parse_pair_name("cuts__shape_1"), None);
        assert_eq!(parse_pair_name("cuts_cat_shape_x"), None);
    }

    #[test]
    fn barycentric_rows_parse_and_reject_bad_lines() {
        let p = Path::new("t.baryc_gt");
        let rows = parse_barycentric_gt(
            "   1.4700000e+02   1.6768015e-03   2.1508433e-03   9.9617236e-01\n\n2 0 1 0\n",
            p,
        )
        .unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].triangle, 146);
        assert_eq!(
            rows[1],
            BarycentricRow {
                triangle: 1,
                weights: [0.0, 1.0, 0.0]
            }
        );
        for bad in [
            "1 0 1\n",
            "0 1 0 0\n",
            "1.5 1 0 0\n",
            "x 1 0 0\n",
            "",
            "1 nan 0 0\n",
        ] {
            let e = parse_barycentric_gt(bad, p).unwrap_err();
            assert!(matches!(e, Error::Parse { .. }), "{bad:?}: {e}");
        }
        let e = parse_barycentric_gt("1 1 0 0\n3 1 0 0 5\n", p)
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 2"), "{e}");
    }

    #[test]
    fn mask_marks_the_three_vertices_and_checks_range() {
        let m = dualspectra::mesh::generate::grid(1.0, 1.0, 2, 2);
        let rows = [BarycentricRow {
            triangle: 0,
            weights: [1.0, 0.0, 0.0],
        }];
        let mask = ground_truth_mask(&m, &rows, None, Path::new("x")).unwrap();
        let f = m.faces()[0];
        assert_eq!(mask.iter().filter(|&&b| b).count(), 3);
        assert!(f.iter().all(|&v| mask[v as usize]));
        let bad = [BarycentricRow {
            triangle: 8,
            weights: [1.0, 0.0, 0.0],
        }];
        assert!(ground_truth_mask(&m, &bad, None, Path::new("x"))
            .unwrap_err()
            .to_string()
            .contains("out of range"));
    }

    #[test]
    fn open_rejects_non_dataset_folders() {
        let dir = std::env::temp_dir().join(format!("ds_eval_open_{}", std::process::id()));
        let _ = std::fs::create_dir_all(&dir);
        assert!(Dataset::open(dir.join("missing")).is_err());
        assert!(Dataset::open(&dir)
            .unwrap_err()
            .to_string()
            .contains("null/"));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
