//! Reading and writing triangle meshes: OFF, OBJ and PLY (ASCII and binary).
//!
//! [`read_mesh`] picks the format from the file extension (`.off`, `.obj`, `.ply`, any
//! case) and returns a validated [`TriMesh`] whose vertex numbers are the file's
//! (0-based; copies made by splitting non-manifold vertices follow them).
//! [`read_mesh_with_report`] also says what was changed on the way.
//!
//! # What reading does to a file
//!
//! | In the file | Result |
//! |---|---|
//! | polygon with `n > 3` vertices `(p0, ..., p{n-1})` | **repaired**: fan-triangulated into `(p0, pk, pk+1)`, `k = 1..n-2`; counted in [`ReadReport::polygons_triangulated`] |
//! | vertex in no face (isolated) | **error** [`MeshError::IsolatedVertex`] by default; **repaired** (dropped, index map in [`ReadReport::kept_vertices`]) with [`ReadOptions::drop_isolated`] |
//! | edge in more than two faces; vertex whose faces form several fans (non-manifold) | **repaired** by default ([`ReadOptions::split_non_manifold`]): split as in [`super::repair`] (vertex copies appended after the file's vertices, no face removed or reordered); counted in [`ReadReport::non_manifold_edges_split`] and [`ReadReport::non_manifold_vertices_split`]; each copy maps to its file vertex in [`ReadReport::kept_vertices`] |
//! | the same triangle more than once | **repaired** by default ([`ReadOptions::remove_duplicate_faces`]): a copy and a reversed copy cancel (a two-sided "flap"), what remains is kept once; vertices used only by removed copies are dropped; counted in [`ReadReport::duplicate_faces_removed`] and [`ReadReport::flap_vertices_dropped`], listed in [`ReadReport::removed_triangles`] |
//! | unreadable file; not a regular file (a directory, a device such as `/dev/zero`, a pipe; symbolic links are followed to their target) | [`Error::Io`] |
//! | bad header, bad number, truncated data, face with fewer than 3 vertices, unknown extension | [`Error::Parse`] (with the line number for text formats) |
//! | more than the header declares (OFF records after the faces, PLY data after the last element), a second PLY `vertex` or `face` element, an OBJ corner other than `v`, `v/vt`, `v//vn`, `v/vt/vn` with integers | [`Error::Parse`]: the counts or the syntax do not describe the file, and guessing would change the mesh |
//! | face index out of range, NaN/inf coordinate, no faces, repeated vertex in a face, zero-area face (relative to its longest edge, at any scale); a non-manifold edge or vertex with [`ReadOptions::split_non_manifold`] off | [`Error::InvalidMeshFile`] with the [`MeshError`] |
//!
//! The duplicate-face repair exists for real data: SHREC'16 `null/cat.off` has twelve
//! two-sided flaps (a triangle listed in both orientations, its tip vertex in no other
//! face), which make their base edges non-manifold. Removing both copies and the tip
//! leaves a manifold mesh and changes no other face.
//!
//! Isolated vertices are an error by default because dropping them renumbers the
//! vertices, and per-vertex data tied to the file (ground-truth correspondences,
//! colours) would silently stop matching. Degenerate faces are never repaired: removing
//! faces changes the topology (it opens holes, so the Dirichlet boundary changes), which
//! would change the spectra the file is read for. Non-manifold edges and vertices are
//! split, not removed: raw scans have them (PFARM cuts have edges of four faces), and the
//! split keeps every face and position, changing only which faces are joined. Sheets that
//! touched at an edge or a vertex become separate (each gets its own boundary there).
//!
//! Bounded work on any input: only regular files are read, into one buffer of the file's
//! size; faces are checked (vertex count, index range) and triangulated as they are read,
//! so the first bad face ends the read; arrays are reserved from the declared counts only
//! as far as the rest of the file can hold them; repairs and validation sort instead of
//! hashing. A valid file takes about 1.5x (text) to 2.8x (binary PLY) its size in memory,
//! a file of one triangle repeated about 4x (the `io_memory` test measures it). Tokens
//! quoted in messages are cut to 40 characters.
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

use super::repair::{split_faces, FaceSplit};
use super::TriMesh;
use crate::error::{Error, MeshError, Result};
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
    /// dropped. Default `true`. With `false`, a repeated triangle fails validation as
    /// [`MeshError::RepeatedFace`].
    pub remove_duplicate_faces: bool,
    /// Split non-manifold edges and vertices ([`super::repair`]): copies of their vertices
    /// are appended, mapped to the file's in [`ReadReport::kept_vertices`]. Default `true`.
    /// With `false` they fail validation as [`MeshError::NonManifoldEdge`] or
    /// [`MeshError::NonManifoldVertex`].
    pub split_non_manifold: bool,
    /// Keeps the struct extensible (construct with `..Default::default()`).
    #[doc(hidden)]
    pub non_exhaustive: crate::NonExhaustive,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            drop_isolated: false,
            remove_duplicate_faces: true,
            split_non_manifold: true,
            non_exhaustive: crate::NonExhaustive::default(),
        }
    }
}

/// What reading changed between the file and the returned mesh.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
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
    /// Edges of the file in more than two faces, cut ([`ReadOptions::split_non_manifold`]).
    pub non_manifold_edges_split: usize,
    /// Vertices of the file whose faces formed several fans, given copies.
    pub non_manifold_vertices_split: usize,
    /// `kept_vertices[v]` = file index of mesh vertex `v`: the file's vertices the mesh
    /// kept, increasing (the identity unless some were dropped), then the copies made by
    /// the non-manifold split, each the file index of the vertex it copies. Several mesh
    /// vertices may so name one file vertex; data per file vertex applies to all of them.
    pub kept_vertices: Vec<u32>,
    /// `face_origin[t]` = file face record that mesh triangle `t` comes from.
    pub face_origin: Vec<u32>,
    /// The triangles removed as repeated copies, in file order: `(face record, its three
    /// vertices in the file's numbering)`. Data tied to the file's triangles (SHREC'16
    /// ground truth) finds their vertices here; those the mesh kept are in `kept_vertices`
    /// (a flap's tip is not).
    pub removed_triangles: Vec<(u32, [u32; 3])>,
}

impl ReadReport {
    /// Mesh vertices that are copies made by the non-manifold split (the last ones of
    /// [`ReadReport::kept_vertices`], where it stops increasing).
    pub fn n_copies(&self) -> usize {
        let k = &self.kept_vertices;
        k.len() - (1..k.len()).find(|&i| k[i] <= k[i - 1]).unwrap_or(k.len())
    }

    /// What the non-manifold split did, as a sentence for the user (`None` if nothing).
    pub fn non_manifold_warning(&self) -> Option<String> {
        (self.non_manifold_edges_split > 0 || self.non_manifold_vertices_split > 0).then(|| {
            format!(
                "split {} non-manifold edge(s) and {} non-manifold vertex(es): {} vertex copies added, \
                 the sheets that met there are no longer joined",
                self.non_manifold_edges_split,
                self.non_manifold_vertices_split,
                self.n_copies()
            )
        })
    }
}

/// Read a mesh, choosing the format from the extension, with default [`ReadOptions`]
/// (isolated vertices are an error). See the module doc for what is checked.
pub fn read_mesh(path: &Path) -> Result<TriMesh> {
    read_mesh_with_report(path, &ReadOptions::default()).map(|(m, _)| m)
}

/// Read a mesh and report what was triangulated or dropped.
pub fn read_mesh_with_report(path: &Path, options: &ReadOptions) -> Result<(TriMesh, ReadReport)> {
    let format = MeshFormat::from_path(path)?;
    let bytes = read_regular_file(path)?;
    let raw = parse(&bytes, format, path)?;
    // The text is not needed any more: free it before the mesh is checked.
    drop(bytes);
    build(raw, format, path, options)
}

/// Parse a mesh held in memory. `path` only names the source in error messages.
pub fn read_mesh_from_bytes(
    bytes: &[u8],
    format: MeshFormat,
    path: &Path,
    options: &ReadOptions,
) -> Result<(TriMesh, ReadReport)> {
    build(parse(bytes, format, path)?, format, path, options)
}

fn parse(bytes: &[u8], format: MeshFormat, path: &Path) -> Result<RawMesh> {
    match format {
        MeshFormat::Off => off::parse(bytes, path),
        MeshFormat::Obj => obj::parse(bytes, path),
        MeshFormat::Ply => ply::parse(bytes, path),
    }
}

/// The bytes of `path`, which must be (or be a symbolic link to) a regular file: a
/// device (`/dev/zero`), a pipe or a socket could be read without end, a directory not at
/// all. The buffer is sized from the file's length, and a file that grows while it is
/// read is an error rather than a partial read.
fn read_regular_file(path: &Path) -> Result<Vec<u8>> {
    use std::io::Read;
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    let not_regular = |meta: &fs::Metadata| {
        let kind = file_kind(meta);
        let target = match fs::symlink_metadata(path) {
            Ok(m) if m.file_type().is_symlink() => match fs::canonicalize(path) {
                Ok(t) => format!(" (a symbolic link to {}, {kind})", t.display()),
                Err(_) => format!(" (a symbolic link to {kind})"),
            },
            _ => format!(" ({kind})"),
        };
        io(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("not a regular file{target}; only regular files are read"),
        ))
    };
    // Checked before opening: opening a FIFO would block.
    let meta = fs::metadata(path).map_err(io)?;
    if !meta.is_file() {
        return Err(not_regular(&meta));
    }
    let mut file = fs::File::open(path).map_err(io)?;
    let meta = file.metadata().map_err(io)?;
    if !meta.is_file() {
        return Err(not_regular(&meta));
    }
    let len = usize::try_from(meta.len()).map_err(|_| {
        io(std::io::Error::new(
            std::io::ErrorKind::OutOfMemory,
            format!("the file's {} bytes do not fit in memory", meta.len()),
        ))
    })?;
    let mut bytes = Vec::new();
    bytes.try_reserve_exact(len).map_err(|_| {
        io(std::io::Error::new(
            std::io::ErrorKind::OutOfMemory,
            format!("cannot allocate {len} bytes to read the file"),
        ))
    })?;
    (&mut file).take(len as u64).read_to_end(&mut bytes).map_err(io)?;
    let mut probe = [0u8; 1];
    if file.read(&mut probe).map_err(io)? > 0 {
        return Err(io(std::io::Error::other(format!(
            "the file grew beyond its {len} bytes while being read"
        ))));
    }
    Ok(bytes)
}

/// What a file that is not a regular file is, for messages.
fn file_kind(meta: &fs::Metadata) -> &'static str {
    let t = meta.file_type();
    if t.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_fifo() {
            return "a named pipe";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    "a special file"
}

/// Vertices and triangles as read, before repairs and validation. The parsers stream
/// into it: each polygon is checked (at least 3 vertices, indices below the declared
/// vertex count) and fan-triangulated as soon as it is read, so a bad face fails the
/// read there instead of after the whole file is held in memory twice.
#[derive(Debug)]
pub(crate) struct RawMesh {
    pub positions: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
    /// `face_origin[t]` = face record of triangle `t`.
    pub face_origin: Vec<u32>,
    /// Face records read so far.
    pub n_polygons: usize,
    pub polygons_triangulated: usize,
    /// Vertex count the indices are checked against (the header's, or counted ahead).
    n_vertices: u64,
    /// Triangles to reserve room for once the first face is accepted.
    triangles_hint: usize,
}

impl RawMesh {
    /// An empty mesh whose faces may use vertices `0..n_vertices` (at most 2^32 - 1).
    pub(crate) fn new(n_vertices: usize, path: &Path) -> Result<Self> {
        if n_vertices > u32::MAX as usize {
            return Err(parse_error(
                path,
                format!("{n_vertices} vertices is more than the 2^32 - 1 supported"),
            ));
        }
        Ok(RawMesh {
            positions: Vec::new(),
            triangles: Vec::new(),
            face_origin: Vec::new(),
            n_polygons: 0,
            polygons_triangulated: 0,
            n_vertices: n_vertices as u64,
            triangles_hint: 0,
        })
    }

    /// Reserve room for `vertices` now and for `triangles` when the first face is accepted
    /// (a file whose first face is bad reserves nothing for faces): hints the caller has
    /// capped by what the rest of the file can hold, so a lying header cannot exhaust memory.
    pub(crate) fn reserve(&mut self, vertices: usize, triangles: usize) {
        self.positions.reserve_exact(vertices);
        self.triangles_hint = self.triangles_hint.max(triangles);
    }

    /// Add face record `n_polygons` with vertex indices `poly`, fan-triangulated into
    /// `(p0, pk, pk+1)`. `line` (text formats) prefixes the message of a short face.
    pub(crate) fn push_polygon(&mut self, poly: &[u64], path: &Path, line: Option<usize>) -> Result<()> {
        let p = self.n_polygons;
        if poly.len() < 3 {
            let at = line.map_or(String::new(), |l| format!("line {l}: "));
            return Err(parse_error(
                path,
                format!("{at}face {p} has {} vertices; a face needs at least 3", poly.len()),
            ));
        }
        if let Some(&index) = poly.iter().find(|&&i| i >= self.n_vertices) {
            return Err(mesh_error(
                path,
                MeshError::IndexOutOfRange {
                    face: p,
                    index,
                    n_vertices: self.n_vertices as usize,
                },
            ));
        }
        let p32 = u32::try_from(p).map_err(|_| parse_error(path, "more than 2^32 - 1 faces"))?;
        if poly.len() > 3 {
            self.polygons_triangulated += 1;
        }
        if self.triangles_hint > 0 {
            self.triangles.reserve_exact(self.triangles_hint);
            self.face_origin.reserve_exact(self.triangles_hint);
            self.triangles_hint = 0;
        }
        for k in 1..poly.len() - 1 {
            self.triangles.push([poly[0] as u32, poly[k] as u32, poly[k + 1] as u32]);
            self.face_origin.push(p32);
        }
        self.n_polygons += 1;
        Ok(())
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

/// Longest text quoted from a file in a message; longer tokens are cut with `...`.
const QUOTE_CHARS: usize = 40;

/// `'text'` for a message: at most [`QUOTE_CHARS`] characters, then `...` and the length,
/// so that a 20 MB token does not become a 20 MB error line.
pub(crate) fn quote(text: &str) -> String {
    match text.char_indices().nth(QUOTE_CHARS) {
        None => format!("'{text}'"),
        Some((cut, _)) => format!("'{}...' ({} bytes)", &text[..cut], text.len()),
    }
}

/// Check, repair and validate: remove duplicate triangles, drop flap tips (and isolated
/// vertices when asked), split non-manifold edges and vertices, build the [`TriMesh`];
/// every error is translated back to the file's numbering. Works in place: besides the
/// mesh and the report it allocates about 5 bytes per triangle and 6 per vertex, 16 per
/// removed triangle (listed in the report), and the split (or validation, when the split
/// is off) 36 per triangle and 5 per vertex.
fn build(raw: RawMesh, format: MeshFormat, path: &Path, options: &ReadOptions) -> Result<(TriMesh, ReadReport)> {
    let RawMesh {
        mut positions,
        triangles: mut faces,
        mut face_origin,
        n_polygons,
        polygons_triangulated,
        ..
    } = raw;
    let n = positions.len();
    if n > u32::MAX as usize {
        return Err(parse_error(
            path,
            format!("{n} vertices is more than the 2^32 - 1 supported"),
        ));
    }
    if n == 0 {
        return Err(mesh_error(path, MeshError::NoVertices));
    }
    // The parsers checked indices against the declared count; the count read must agree.
    if let Some((t, &index)) = faces
        .iter()
        .enumerate()
        .find_map(|(t, f)| f.iter().find(|&&i| i as usize >= n).map(|i| (t, i)))
    {
        return Err(mesh_error(
            path,
            MeshError::IndexOutOfRange {
                face: face_origin[t] as usize,
                index: index as u64,
                n_vertices: n,
            },
        ));
    }
    let mut used_in_file = vec![false; n];
    faces.iter().flatten().for_each(|&i| used_in_file[i as usize] = true);
    let mut duplicate_faces_removed = 0;
    let mut removed_triangles = Vec::new();
    if options.remove_duplicate_faces {
        let keep = duplicate_free(&faces);
        duplicate_faces_removed = keep.iter().filter(|&&k| !k).count();
        if duplicate_faces_removed > 0 {
            removed_triangles.reserve_exact(duplicate_faces_removed);
            removed_triangles.extend((0..faces.len()).filter(|&t| !keep[t]).map(|t| (face_origin[t], faces[t])));
            let mut it = keep.iter();
            faces.retain(|_| *it.next().unwrap_or(&true));
            let mut it = keep.iter();
            face_origin.retain(|_| *it.next().unwrap_or(&true));
        }
    }
    faces.shrink_to_fit();
    face_origin.shrink_to_fit();
    if faces.is_empty() {
        return Err(mesh_error(path, MeshError::NoFaces));
    }
    let mut used = vec![false; n];
    faces.iter().flatten().for_each(|&i| used[i as usize] = true);
    // Drop flap tips always, file-isolated vertices only when asked.
    let dropped = |i: usize| !used[i] && (used_in_file[i] || options.drop_isolated);
    let flap_vertices_dropped = (0..n).filter(|&i| !used[i] && used_in_file[i]).count();
    let isolated_dropped = if options.drop_isolated {
        used_in_file.iter().filter(|&&u| !u).count()
    } else {
        0
    };
    let mut kept_vertices: Vec<u32> = (0..n as u32).collect();
    if (0..n).any(dropped) {
        kept_vertices.retain(|&i| !dropped(i as usize));
        kept_vertices.shrink_to_fit();
        let mut new_index = vec![u32::MAX; n];
        for (new, &old) in kept_vertices.iter().enumerate() {
            new_index[old as usize] = new as u32;
        }
        // In place: kept vertices move down, in order.
        for (new, &old) in kept_vertices.iter().enumerate() {
            positions[new] = positions[old as usize];
        }
        positions.truncate(kept_vertices.len());
        positions.shrink_to_fit();
        for f in &mut faces {
            *f = f.map(|i| new_index[i as usize]);
        }
    }
    drop(used_in_file);
    let mut split = FaceSplit::default();
    if options.split_non_manifold {
        split = split_faces(positions.len(), &mut faces);
        if !split.copies.is_empty() {
            positions.reserve_exact(split.copies.len());
            kept_vertices.reserve_exact(split.copies.len());
            for &o in &split.copies {
                positions.push(positions[o as usize]);
                kept_vertices.push(kept_vertices[o as usize]);
            }
        }
    }
    let build = if split.manifold { TriMesh::new_split } else { TriMesh::new };
    let mesh = build(positions, faces)
        .map_err(|e| mesh_error(path, to_file_numbering(e, &face_origin, &kept_vertices)))?;
    let report = ReadReport {
        format,
        file_vertices: n,
        file_faces: n_polygons,
        polygons_triangulated,
        isolated_dropped,
        duplicate_faces_removed,
        flap_vertices_dropped,
        non_manifold_edges_split: split.edges_split,
        non_manifold_vertices_split: split.vertices_split,
        kept_vertices,
        face_origin,
        removed_triangles,
    };
    Ok((mesh, report))
}

/// `keep[t]` for every triangle: a triangle and its reverse cancel (oriented 2-chains);
/// of the copies left, all in one orientation, the first is kept. Copies are found by
/// sorting triangle numbers by vertex set (4 bytes per triangle, no hash table).
pub(super) fn duplicate_free(faces: &[[u32; 3]]) -> Vec<bool> {
    // Rotate the smallest index first: same set and same orientation <=> same rotation.
    let rotated = |f: [u32; 3]| {
        let m = (0..3).min_by_key(|&c| f[c]).unwrap_or(0);
        [f[m], f[(m + 1) % 3], f[(m + 2) % 3]]
    };
    let set = |t: u32| {
        let mut key = faces[t as usize];
        key.sort_unstable();
        key
    };
    let mut keep = vec![true; faces.len()];
    let Ok(m) = u32::try_from(faces.len()) else {
        return keep;
    };
    let mut order: Vec<u32> = (0..m).collect();
    // By vertex set, then by file order within a set.
    order.sort_unstable_by(|&s, &t| set(s).cmp(&set(t)).then(s.cmp(&t)));
    for group in order.chunk_by(|&s, &t| set(s) == set(t)).filter(|g| g.len() > 1) {
        let first = rotated(faces[group[0] as usize]);
        let same = group.iter().filter(|&&t| rotated(faces[t as usize]) == first).count();
        let other = group.len() - same;
        group.iter().for_each(|&t| keep[t as usize] = false);
        if same != other {
            let survivor = group
                .iter()
                .find(|&&t| (rotated(faces[t as usize]) == first) == (same > other))
                .copied()
                .unwrap_or(group[0]);
            keep[survivor as usize] = true;
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
        MeshError::RepeatedFace { face, first } => MeshError::RepeatedFace { face: f(face), first: f(first) },
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
