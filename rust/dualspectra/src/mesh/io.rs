//! Reading and writing triangle meshes: OFF, OBJ and PLY (ASCII and binary).
//!
//! [`read_mesh`] picks the format from the file extension (`.off`, `.obj`, `.ply`, any
//! case) and returns a validated [`TriMesh`] whose vertex numbers are the file's
//! (0-based). [`read_mesh_with_report`] also says what was changed on the way.
//!
//! # What reading does to a file
//!
//! | In the file | Result |
//! |---|---|
//! | polygon with `n > 3` vertices `(p0, ..., p{n-1})` | **repaired**: fan-triangulated into `(p0, pk, pk+1)`, `k = 1..n-2`; counted in [`ReadReport::polygons_triangulated`] |
//! | vertex in no face (isolated) | **error** [`MeshError::IsolatedVertex`] by default; **repaired** (dropped, index map in [`ReadReport::kept_vertices`]) with [`ReadOptions::drop_isolated`] |
//! | the same triangle more than once | **repaired** by default ([`ReadOptions::remove_duplicate_faces`]): a copy and a reversed copy cancel (a two-sided "flap"), what remains is kept once; vertices used only by removed copies are dropped; counted in [`ReadReport::duplicate_faces_removed`] and [`ReadReport::flap_vertices_dropped`] |
//! | unreadable file | [`Error::Io`] |
//! | bad header, bad number, truncated data, face with fewer than 3 vertices, unknown extension | [`Error::Parse`] (with the line number for text formats) |
//! | face index out of range, NaN/inf coordinate, no faces, repeated vertex in a face, zero-area face, edge in more than two faces | [`Error::InvalidMeshFile`] with the [`MeshError`] |
//!
//! The duplicate-face repair exists for real data: SHREC'16 `null/cat.off` has twelve
//! two-sided flaps (a triangle listed in both orientations, its tip vertex in no other
//! face), which make their base edges non-manifold. Removing both copies and the tip
//! leaves a manifold mesh and changes no other face.
//!
//! Isolated vertices are an error by default because dropping them renumbers the
//! vertices, and per-vertex data tied to the file (ground-truth correspondences,
//! colours) would silently stop matching. Degenerate faces and non-manifold edges are
//! never repaired: removing faces changes the topology (it opens holes, so the
//! Dirichlet boundary changes), which would change the spectra the file is read for.
//!
//! Numbering in messages: face and vertex numbers are 0-based records of the file
//! (the `k`-th face line of an OFF, the `k`-th face of a PLY), also after triangulation
//! or dropping; OBJ messages give the line number and the index as written (1-based).
//!
//! Writers produce files the readers read back to the same mesh bit for bit:
//! coordinates are written with Rust's shortest round-trip formatting (text formats) or
//! as `double` (binary PLY).

mod obj;
mod off;
mod ply;

use super::TriMesh;
use crate::error::{Error, MeshError, Result};
use std::collections::HashMap;
use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// A mesh file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshFormat {
    /// Object File Format (Princeton / Geomview), text. `OFF`, `COFF`, `NOFF`, `CNOFF`,
    /// `STOFF` headers; extra per-vertex values (colours, normals) are ignored.
    Off,
    /// Wavefront OBJ: `v` and `f` records (other records are ignored).
    Obj,
    /// Stanford PLY, ASCII or binary little/big endian.
    Ply,
}

impl MeshFormat {
    /// The format named by the file's extension (case-insensitive).
    pub fn from_path(path: &Path) -> Result<MeshFormat> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase());
        match ext.as_deref() {
            Some("off") => Ok(MeshFormat::Off),
            Some("obj") => Ok(MeshFormat::Obj),
            Some("ply") => Ok(MeshFormat::Ply),
            Some(other) => Err(parse_error(
                path,
                format!("unknown mesh format '.{other}' (expected .off, .obj or .ply)"),
            )),
            None => Err(parse_error(
                path,
                "no file extension to tell the mesh format (expected .off, .obj or .ply)",
            )),
        }
    }
}

/// How to read a mesh file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReadOptions {
    /// Drop vertices that belong to no face instead of rejecting the file. The mesh
    /// is then renumbered; [`ReadReport::kept_vertices`] maps new to file indices.
    /// Default `false`.
    pub drop_isolated: bool,
    /// Remove repeated triangles (same three vertices): pairs of opposite orientation
    /// cancel, the rest is kept once; vertices used only by removed triangles are
    /// dropped. Default `true`. With `false`, repeated triangles usually fail validation
    /// as [`MeshError::NonManifoldEdge`].
    pub remove_duplicate_faces: bool,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            drop_isolated: false,
            remove_duplicate_faces: true,
        }
    }
}

/// What reading changed between the file and the returned mesh.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReadReport {
    pub format: MeshFormat,
    /// Vertex records in the file.
    pub file_vertices: usize,
    /// Face records (polygons) in the file.
    pub file_faces: usize,
    /// Face records with more than three vertices, fan-triangulated.
    pub polygons_triangulated: usize,
    /// Isolated vertices of the file dropped (only with [`ReadOptions::drop_isolated`]).
    pub isolated_dropped: usize,
    /// Triangles removed as repeated copies (see [`ReadOptions::remove_duplicate_faces`]).
    pub duplicate_faces_removed: usize,
    /// Vertices dropped because only removed duplicate triangles used them (flap tips).
    pub flap_vertices_dropped: usize,
    /// `kept_vertices[v]` = file index of mesh vertex `v` (the identity unless dropped).
    pub kept_vertices: Vec<u32>,
    /// `face_origin[t]` = file face record that mesh triangle `t` comes from.
    pub face_origin: Vec<u32>,
}

/// Read a mesh, choosing the format from the extension, with default [`ReadOptions`]
/// (isolated vertices are an error). See the module doc for what is checked.
pub fn read_mesh(path: &Path) -> Result<TriMesh> {
    read_mesh_with_report(path, &ReadOptions::default()).map(|(m, _)| m)
}

/// Read a mesh and report what was triangulated or dropped.
pub fn read_mesh_with_report(path: &Path, options: &ReadOptions) -> Result<(TriMesh, ReadReport)> {
    let format = MeshFormat::from_path(path)?;
    let bytes = fs::read(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    read_mesh_from_bytes(&bytes, format, path, options)
}

/// Parse a mesh held in memory. `path` only names the source in error messages.
pub fn read_mesh_from_bytes(
    bytes: &[u8],
    format: MeshFormat,
    path: &Path,
    options: &ReadOptions,
) -> Result<(TriMesh, ReadReport)> {
    let raw = match format {
        MeshFormat::Off => off::parse(bytes, path)?,
        MeshFormat::Obj => obj::parse(bytes, path)?,
        MeshFormat::Ply => ply::parse(bytes, path)?,
    };
    build(raw, format, path, options)
}

/// Vertices and polygons as read, before triangulation and validation.
/// Indices are 0-based but not yet range-checked (except by the OBJ parser).
#[derive(Debug, Default)]
pub(crate) struct RawMesh {
    pub positions: Vec<[f64; 3]>,
    /// Polygon `p` is `indices[offsets[p]..offsets[p + 1]]`; `offsets[0] = 0`.
    pub indices: Vec<u64>,
    pub offsets: Vec<usize>,
}

impl RawMesh {
    pub(crate) fn new() -> Self {
        RawMesh {
            positions: Vec::new(),
            indices: Vec::new(),
            offsets: vec![0],
        }
    }
    pub(crate) fn n_polygons(&self) -> usize {
        self.offsets.len() - 1
    }
    pub(crate) fn end_polygon(&mut self) {
        self.offsets.push(self.indices.len());
    }
}

pub(crate) fn parse_error(path: &Path, message: impl Into<String>) -> Error {
    Error::Parse {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

fn mesh_error(path: &Path, source: MeshError) -> Error {
    Error::InvalidMeshFile {
        path: path.to_path_buf(),
        source,
    }
}

/// Range-check, fan-triangulate, optionally drop isolated vertices, validate; every
/// error is translated back to the file's numbering.
fn build(raw: RawMesh, format: MeshFormat, path: &Path, options: &ReadOptions) -> Result<(TriMesh, ReadReport)> {
    let n = raw.positions.len();
    if n > u32::MAX as usize {
        return Err(parse_error(
            path,
            format!("{n} vertices is more than the 2^32 - 1 supported"),
        ));
    }
    if n == 0 {
        return Err(mesh_error(path, MeshError::NoVertices));
    }
    let mut faces: Vec<[u32; 3]> = Vec::with_capacity(raw.n_polygons());
    let mut face_origin: Vec<u32> = Vec::with_capacity(raw.n_polygons());
    let mut polygons_triangulated = 0;
    for p in 0..raw.n_polygons() {
        let poly = &raw.indices[raw.offsets[p]..raw.offsets[p + 1]];
        if poly.len() < 3 {
            return Err(parse_error(
                path,
                format!("face {p} has {} vertices; a face needs at least 3", poly.len()),
            ));
        }
        if let Some(&index) = poly.iter().find(|&&i| i >= n as u64) {
            return Err(mesh_error(
                path,
                MeshError::IndexOutOfRange {
                    face: p,
                    index,
                    n_vertices: n,
                },
            ));
        }
        if poly.len() > 3 {
            polygons_triangulated += 1;
        }
        let p32 = u32::try_from(p).map_err(|_| parse_error(path, "more than 2^32 - 1 faces"))?;
        for k in 1..poly.len() - 1 {
            faces.push([poly[0] as u32, poly[k] as u32, poly[k + 1] as u32]);
            face_origin.push(p32);
        }
    }
    let file_vertices = n;
    let mut used_in_file = vec![false; n];
    faces.iter().flatten().for_each(|&i| used_in_file[i as usize] = true);
    let mut duplicate_faces_removed = 0;
    if options.remove_duplicate_faces {
        let keep = duplicate_free(&faces);
        duplicate_faces_removed = keep.iter().filter(|&&k| !k).count();
        if duplicate_faces_removed > 0 {
            let mut it = keep.iter();
            faces.retain(|_| *it.next().unwrap_or(&true));
            let mut it = keep.iter();
            face_origin.retain(|_| *it.next().unwrap_or(&true));
        }
    }
    if faces.is_empty() {
        return Err(mesh_error(path, MeshError::NoFaces));
    }
    let mut used = vec![false; n];
    faces.iter().flatten().for_each(|&i| used[i as usize] = true);
    // Drop flap tips always, file-isolated vertices only when asked.
    let drop = |i: usize| !used[i] && (used_in_file[i] || options.drop_isolated);
    let flap_vertices_dropped = (0..n).filter(|&i| !used[i] && used_in_file[i]).count();
    let isolated_dropped = if options.drop_isolated {
        used_in_file.iter().filter(|&&u| !u).count()
    } else {
        0
    };
    let mut positions = raw.positions;
    let mut kept_vertices: Vec<u32> = (0..n as u32).collect();
    if (0..n).any(drop) {
        kept_vertices.retain(|&i| !drop(i as usize));
        let mut new_index = vec![u32::MAX; n];
        for (new, &old) in kept_vertices.iter().enumerate() {
            new_index[old as usize] = new as u32;
        }
        positions = kept_vertices.iter().map(|&i| positions[i as usize]).collect();
        for f in &mut faces {
            *f = f.map(|i| new_index[i as usize]);
        }
    }
    let mesh = TriMesh::new(positions, faces)
        .map_err(|e| mesh_error(path, to_file_numbering(e, &face_origin, &kept_vertices)))?;
    let report = ReadReport {
        format,
        file_vertices,
        file_faces: raw.offsets.len() - 1,
        polygons_triangulated,
        isolated_dropped,
        duplicate_faces_removed,
        flap_vertices_dropped,
        kept_vertices,
        face_origin,
    };
    Ok((mesh, report))
}

/// `keep[t]` for every triangle: a triangle and its reverse cancel (oriented 2-chains);
/// of the copies left, all in one orientation, the first is kept.
fn duplicate_free(faces: &[[u32; 3]]) -> Vec<bool> {
    // Rotate the smallest index first: same set and same orientation <=> same rotation.
    let rotated = |f: [u32; 3]| {
        let m = (0..3).min_by_key(|&c| f[c]).unwrap_or(0);
        [f[m], f[(m + 1) % 3], f[(m + 2) % 3]]
    };
    let mut copies: HashMap<[u32; 3], Vec<usize>> = HashMap::new();
    for (t, f) in faces.iter().enumerate() {
        let mut key = *f;
        key.sort_unstable();
        copies.entry(key).or_default().push(t);
    }
    let mut keep = vec![true; faces.len()];
    for group in copies.values().filter(|g| g.len() > 1) {
        let first = rotated(faces[group[0]]);
        let (same, other): (Vec<usize>, Vec<usize>) = group.iter().partition(|&&t| rotated(faces[t]) == first);
        group.iter().for_each(|&t| keep[t] = false);
        if same.len() != other.len() {
            let survivor = if same.len() > other.len() { same[0] } else { other[0] };
            keep[survivor] = true;
        }
    }
    keep
}

/// Rewrite the element numbers of a validation error from mesh to file numbering.
fn to_file_numbering(e: MeshError, face_origin: &[u32], kept: &[u32]) -> MeshError {
    let f = |face: usize| face_origin.get(face).map_or(face, |&o| o as usize);
    let v = |vertex: usize| kept.get(vertex).map_or(vertex, |&o| o as usize);
    match e {
        MeshError::NonFiniteCoordinate { vertex } => MeshError::NonFiniteCoordinate { vertex: v(vertex) },
        MeshError::RepeatedVertexInFace { face } => MeshError::RepeatedVertexInFace { face: f(face) },
        MeshError::DegenerateFace { face } => MeshError::DegenerateFace { face: f(face) },
        MeshError::NonManifoldEdge { a, b, count } => {
            let (a, b) = (v(a as usize) as u32, v(b as usize) as u32);
            MeshError::NonManifoldEdge {
                a: a.min(b),
                b: a.max(b),
                count,
            }
        }
        MeshError::IsolatedVertex { vertex, count } => MeshError::IsolatedVertex {
            vertex: v(vertex),
            count,
        },
        MeshError::NonManifoldVertex { vertex, fans } => MeshError::NonManifoldVertex {
            vertex: v(vertex),
            fans,
        },
        MeshError::IndexOutOfRange {
            face,
            index,
            n_vertices,
        } => MeshError::IndexOutOfRange {
            face: f(face),
            index,
            n_vertices,
        },
        other => other,
    }
}

/// Write a mesh in the format named by the extension (`.ply` is written binary).
pub fn write_mesh(path: &Path, mesh: &TriMesh) -> Result<()> {
    match MeshFormat::from_path(path)? {
        MeshFormat::Off => write_off(path, mesh),
        MeshFormat::Obj => write_obj(path, mesh),
        MeshFormat::Ply => write_ply(path, mesh, None, true),
    }
}

/// Write an ASCII OFF file (`OFF`, counts, one vertex and one `3 i j k` face per line).
pub fn write_off(path: &Path, mesh: &TriMesh) -> Result<()> {
    write_file(path, |w| off::write(w, mesh))
}

/// Write a Wavefront OBJ file (`v x y z` and 1-based `f i j k` lines).
pub fn write_obj(path: &Path, mesh: &TriMesh) -> Result<()> {
    write_file(path, |w| obj::write(w, mesh))
}

/// Write a PLY file, binary little endian or ASCII, with `double` coordinates,
/// optional per-vertex `uchar red, green, blue`, and `list uchar int vertex_indices` faces.
/// `vertex_colors`, if given, must have one entry per vertex ([`Error::InvalidArgument`] otherwise).
pub fn write_ply(path: &Path, mesh: &TriMesh, vertex_colors: Option<&[[u8; 3]]>, binary: bool) -> Result<()> {
    if let Some(c) = vertex_colors {
        if c.len() != mesh.n_vertices() {
            return Err(Error::InvalidArgument(format!(
                "{} vertex colours given for a mesh with {} vertices",
                c.len(),
                mesh.n_vertices()
            )));
        }
    }
    write_file(path, |w| ply::write(w, mesh, vertex_colors, binary))
}

fn write_file(path: &Path, body: impl FnOnce(&mut BufWriter<fs::File>) -> std::io::Result<()>) -> Result<()> {
    let io = |source| Error::Io {
        path: PathBuf::from(path),
        source,
    };
    let file = fs::File::create(path).map_err(io)?;
    let mut w = BufWriter::new(file);
    body(&mut w).map_err(io)?;
    w.flush().map_err(io)
}

/// Text lines with 1-based line numbers, `#` comments removed, blank lines skipped.
pub(crate) fn content_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines().enumerate().filter_map(|(i, l)| {
        let l = l.split('#').next().unwrap_or("").trim();
        (!l.is_empty()).then_some((i + 1, l))
    })
}
