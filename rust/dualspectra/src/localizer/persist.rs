//! Prepared shapes on disk: [`Localizer::save`] / [`Localizer::load`] (and
//! [`Localizer::to_bytes`] / [`Localizer::from_bytes`]), so that a library of full shapes is
//! prepared once and searched many times.
//!
//! **Format** (little-endian throughout; file extension `.dsprep` by convention):
//!
//! ```text
//! header   magic "DSPREP\r\n" (8 bytes) | format version u32 | library version (u32 length, UTF-8)
//!          | payload length u64 | CRC-32 (IEEE) of the payload u32
//! payload  options (JSON text) | constants the preparation used (SI epsilon, SHOT support
//!          radius, SHOT minimum neighbours) | scale | full-mesh vertex count
//!          | full mesh, scaled (vertices f64 x3, faces u32 x3) | optimisation mesh (same)
//!          | coarse_to_full u32 | cell_of_full u32 | scale-invariant factor of the optimisation
//!          mesh f64 | SHOT descriptors (rows, cols, f64 row-major)
//!          | plane heights (per direction f64)
//!          | warnings (strings) | host numbering (flag u8; host vertex count, kept u32)
//! ```
//!
//! Every sequence is a `u64` count then its items; strings are a `u32` byte length then UTF-8.
//!
//! **Stored and recomputed.** Stored: what [`Localizer::new`] computed and is expensive or
//! not a pure function of the stored inputs (the decimation, the nearest-vertex cells, the
//! transferred scale-invariant factor, the SHOT descriptors) and, to keep a loaded
//! localizer bit-identical to the fresh one without depending on the order of floating-point
//! work, the small start data (the plane heights). Recomputed on
//! load, deterministically from the stored meshes: the full mesh's vertex neighbours, the
//! optimisation mesh's operators, masses and symbolic Cholesky analysis, the thread pool.
//!
//! **Checks.** A file that does not start with the magic is *foreign*; another format
//! version is *stale* (prepare the shape again); a payload shorter than its header says is
//! *truncated*; a checksum mismatch is *corrupted*; then every count is checked against
//! the bytes left before anything is allocated, and every index and length against the
//! meshes. Each is an [`Error::PreparedShape`] naming the file and the problem. A file
//! written by another library version with the same format loads, with a warning
//! (repeated in every result).

use super::{Localizer, Options};
use crate::error::{Error, Result};
use crate::geometry::{metric, shot};
use crate::mesh::intake::HostNumbering;
use crate::mesh::TriMesh;
use crate::shape::{Metric, Shape};
use faer::Mat;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The first bytes of every prepared-shape file.
pub const MAGIC: [u8; 8] = *b"DSPREP\r\n";

/// Version of the layout and of what it holds. Bump it whenever either changes, and whenever
/// [`Localizer::new`] computes something stored here differently: files of another version
/// are refused as stale. Version 2 (0.3.0): no start centres (the `centers` and `seed`
/// options were removed). Version 3 (0.3.0): SHOT supports thinned above
/// [`crate::geometry::shot::MAX_SUPPORT_POINTS`] points (the descriptors of densely meshed
/// full shapes).
pub const FORMAT_VERSION: u32 = 3;

/// The conventional file extension of prepared shapes (without the dot).
pub const EXTENSION: &str = "dsprep";

/// Where bytes come from, for error messages.
fn source_name(path: Option<&Path>) -> PathBuf {
    path.map_or_else(|| PathBuf::from("<prepared shape in memory>"), Path::to_path_buf)
}

impl Localizer {
    /// The prepared shape as bytes (module doc: the format).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut p = Writer::default();
        p.string(&self.options.to_json());
        p.f64(metric::DEFAULT_EPS);
        p.f64(shot::DEFAULT_RADIUS_FRACTION);
        p.u64(shot::DEFAULT_MIN_NEIGHBORS as u64);
        p.f64(self.scale);
        p.u64(self.n_vertices as u64);
        p.mesh(&self.full);
        p.mesh(self.level.coarse.mesh());
        p.u32s(&self.level.coarse_to_full);
        p.u32s(&self.level.cell_of_full);
        p.f64s(self.level.coarse.scale_invariant_factor());
        let d = &self.level.coarse_descriptors;
        p.u64(d.nrows() as u64);
        p.u64(d.ncols() as u64);
        for i in 0..d.nrows() {
            for j in 0..d.ncols() {
                p.f64(d[(i, j)]);
            }
        }
        p.u64(self.level.plane_heights.len() as u64);
        self.level.plane_heights.iter().for_each(|v| p.f64s(v));
        p.u64(self.prepared_warnings.len() as u64);
        self.prepared_warnings.iter().for_each(|w| p.string(w));
        match &self.host {
            None => p.u8(0),
            Some(h) => {
                p.u8(1);
                p.u64(h.n_host_vertices as u64);
                p.u32s(&h.kept);
            }
        }
        let payload = p.0;
        let mut out = Writer::default();
        out.0.extend_from_slice(&MAGIC);
        out.u32(FORMAT_VERSION);
        out.string(crate::VERSION);
        out.u64(payload.len() as u64);
        out.u32(crc32(&payload));
        out.0.extend_from_slice(&payload);
        out.0
    }

    /// Write the prepared shape to `path` ([`Localizer::to_bytes`]).
    pub fn save(&self, path: impl AsRef<Path>) -> Result<()> {
        let path = path.as_ref();
        std::fs::write(path, self.to_bytes()).map_err(|source| Error::Io { path: path.to_path_buf(), source })
    }

    /// A prepared shape from bytes written by [`Localizer::to_bytes`]; errors as [`Localizer::load`].
    pub fn from_bytes(bytes: &[u8]) -> Result<Localizer> {
        decode(bytes, None)
    }

    /// Read a prepared shape written by [`Localizer::save`]. A foreign, stale (other format
    /// version), truncated or corrupted file is an [`Error::PreparedShape`] naming the file
    /// and the problem; a missing or unreadable one an [`Error::Io`].
    pub fn load(path: impl AsRef<Path>) -> Result<Localizer> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
        decode(&bytes, Some(path))
    }

    /// The caller's numbering of the full mesh's vertices, if one was set
    /// ([`Localizer::set_host_numbering`]); saved and loaded with the shape.
    pub fn host_numbering(&self) -> Option<&HostNumbering> {
        self.host.as_ref()
    }

    /// Keep the caller's numbering of the full mesh's vertices with the prepared shape
    /// (`None` removes it). `kept` must have one entry per vertex of the full mesh, each below
    /// `n_host_vertices`.
    pub fn set_host_numbering(&mut self, host: Option<HostNumbering>) -> Result<()> {
        if let Some(h) = &host {
            check_host(h, self.n_vertices).map_err(Error::InvalidArgument)?;
        }
        self.host = host;
        Ok(())
    }

    /// The full mesh in the units it was given in (the stored, unit-area mesh scaled back:
    /// coordinates equal to the given ones up to rounding), e.g. to draw a region on a shape
    /// that was loaded rather than read.
    pub fn full_mesh(&self) -> TriMesh {
        let back = 1.0 / self.scale;
        self.full.map_positions(|p| p.map(|c| c * back)).unwrap_or_else(|_| self.full.clone())
    }
}

fn check_host(h: &HostNumbering, n_vertices: usize) -> std::result::Result<(), String> {
    if h.kept.len() != n_vertices {
        return Err(format!("host numbering has {} entries for {n_vertices} vertices", h.kept.len()));
    }
    if let Some(i) = h.kept.iter().position(|&k| k as usize >= h.n_host_vertices) {
        return Err(format!("host numbering maps vertex {i} to {} of {} host vertices", h.kept[i], h.n_host_vertices));
    }
    Ok(())
}

fn decode(bytes: &[u8], path: Option<&Path>) -> Result<Localizer> {
    let t0 = Instant::now();
    let fail = |message: String| Error::PreparedShape { path: source_name(path), message };
    let mut header = Reader { bytes, at: 0 };
    let magic = header.take(MAGIC.len()).map_err(|_| fail(foreign(bytes)))?;
    if magic != MAGIC {
        return Err(fail(foreign(bytes)));
    }
    let truncated = |what: String| fail(format!("truncated: {what}"));
    let version = header.u32().map_err(truncated)?;
    if version != FORMAT_VERSION {
        return Err(fail(format!(
            "stale prepared shape: format version {version}, this library (dualspectra {}) reads version {FORMAT_VERSION}; prepare the shape again",
            crate::VERSION
        )));
    }
    let library = header
        .string()
        .map_err(|e| if e.contains("UTF-8") { fail(format!("corrupted: {e}")) } else { truncated(e) })?;
    let length = header.u64().map_err(truncated)?;
    let checksum = header.u32().map_err(truncated)?;
    let rest = header.remaining() as u64;
    if length > rest {
        return Err(truncated(format!("the header announces {length} bytes of data, {rest} are there")));
    }
    if length < rest {
        return Err(fail(format!("corrupted: {} bytes after the {length} bytes of data", rest - length)));
    }
    let payload = &bytes[header.at..];
    if crc32(payload) != checksum {
        return Err(fail("corrupted: the checksum of the data does not match".into()));
    }
    let mut localizer = read_payload(&mut Reader { bytes: payload, at: 0 }).map_err(fail)?;
    if library != crate::VERSION {
        localizer
            .warnings
            .push(format!("prepared by dualspectra {library}, used with dualspectra {}", crate::VERSION));
    }
    localizer.preparation_seconds = t0.elapsed().as_secs_f64();
    Ok(localizer)
}

/// Why bytes that do not start with the magic are not a prepared shape.
fn foreign(bytes: &[u8]) -> String {
    if bytes.is_empty() {
        "empty file, not a dualspectra prepared shape".into()
    } else if MAGIC.starts_with(bytes) {
        "truncated: the file ends inside its header".into()
    } else {
        let shown: String = bytes.iter().take(8).map(|&b| if b.is_ascii_graphic() { b as char } else { '.' }).collect();
        format!("not a dualspectra prepared shape (the file starts with '{shown}', not 'DSPREP'); write one with `dualspectra prepare` or Localizer::save")
    }
}

fn read_payload(r: &mut Reader<'_>) -> std::result::Result<Localizer, String> {
    let options = Options::from_json(&r.string()?).map_err(|e| format!("options: {e}"))?;
    let constants = (r.f64()?, r.f64()?, r.u64()?);
    let current = (metric::DEFAULT_EPS, shot::DEFAULT_RADIUS_FRACTION, shot::DEFAULT_MIN_NEIGHBORS as u64);
    if constants != current {
        return Err(format!(
            "stale prepared shape: prepared with (SI epsilon, SHOT radius, SHOT neighbours) = {constants:?}, this library uses {current:?}; prepare the shape again"
        ));
    }
    let scale = r.f64()?;
    if !(scale.is_finite() && scale > 0.0) {
        return Err(format!("scale {scale} is not positive"));
    }
    let n_vertices = r.count(0, "vertex count")?;
    let full = r.mesh("full mesh")?;
    let coarse_mesh = r.mesh("optimisation mesh")?;
    let (n_full, n_coarse) = (full.n_vertices(), coarse_mesh.n_vertices());
    if n_vertices != n_full {
        return Err(format!("{n_vertices} vertices announced, the full mesh has {n_full}"));
    }
    let coarse_to_full = r.indices(n_coarse, n_full, "coarse_to_full")?;
    let cell_of_full = r.indices(n_full, n_coarse, "cell_of_full")?;
    let factor = r.f64s()?;
    let coarse = Shape::with_scale_invariant_factor(coarse_mesh, options.alpha, metric::DEFAULT_EPS, factor)
        .map_err(|e| format!("optimisation mesh: {e}"))?;
    let rows = r.count(0, "descriptor rows")?;
    let cols = r.count(0, "descriptor columns")?;
    if rows != n_coarse || cols != shot::SHOT_DIM {
        return Err(format!("descriptors are {rows} x {cols}, expected {n_coarse} x {}", shot::SHOT_DIM));
    }
    let flat = r.f64_array(rows * cols)?;
    let coarse_descriptors = Mat::from_fn(rows, cols, |i, j| flat[i * cols + j]);
    let plane_heights = r.f64_rows(n_coarse, "plane heights")?;
    let n_warnings = r.count(4, "warnings")?;
    let warnings = (0..n_warnings).map(|_| r.string()).collect::<std::result::Result<Vec<_>, String>>()?;
    let host = match r.u8()? {
        0 => None,
        1 => {
            let n_host_vertices = r.count(0, "host vertices")?;
            let h = HostNumbering { n_host_vertices, kept: r.u32_array_counted(4)? };
            check_host(&h, n_full)?;
            Some(h)
        }
        flag => return Err(format!("host numbering flag {flag} is not 0 or 1")),
    };
    if r.remaining() != 0 {
        return Err(format!("{} bytes left after the data", r.remaining()));
    }
    // Recomputed: the caches every locate reads (as Localizer::new warms them).
    coarse.dirichlet_symbolic().map_err(|e| format!("optimisation mesh: {e}"))?;
    coarse.metric_mass(Metric::ScaleInvariant);
    let full_neighbors = crate::mesh::topology::vertex_neighbors(&full);
    let workers = rayon::ThreadPoolBuilder::new()
        .num_threads(options.threads)
        .build()
        .map_err(|e| format!("thread pool: {e}"))?;
    Ok(Localizer {
        options,
        n_vertices,
        scale,
        full,
        full_neighbors,
        level: std::sync::Arc::new(super::OptimisationMesh {
            coarse,
            coarse_to_full,
            cell_of_full,
            coarse_descriptors,
            plane_heights,
            warmup: Default::default(),
        }),
        fine_level: Default::default(),
        workers,
        warnings: warnings.clone(),
        prepared_warnings: warnings,
        host,
        preparation_seconds: 0.0,
    })
}

/// A growing little-endian byte buffer.
#[derive(Default)]
pub(crate) struct Writer(pub(crate) Vec<u8>);

impl Writer {
    pub(crate) fn u8(&mut self, x: u8) {
        self.0.push(x);
    }
    pub(crate) fn u32(&mut self, x: u32) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub(crate) fn u64(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub(crate) fn f64(&mut self, x: f64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub(crate) fn string(&mut self, s: &str) {
        self.u32(s.len() as u32);
        self.0.extend_from_slice(s.as_bytes());
    }
    pub(crate) fn f64s(&mut self, v: &[f64]) {
        self.u64(v.len() as u64);
        v.iter().for_each(|&x| self.f64(x));
    }
    pub(crate) fn u32s(&mut self, v: &[u32]) {
        self.u64(v.len() as u64);
        v.iter().for_each(|&x| self.u32(x));
    }
    pub(crate) fn mesh(&mut self, m: &TriMesh) {
        self.u64(m.n_vertices() as u64);
        m.vertices().iter().flatten().for_each(|&c| self.f64(c));
        self.u64(m.n_faces() as u64);
        m.faces().iter().flatten().for_each(|&i| self.u32(i));
    }
}

/// Reads the payload, checking every count against the bytes left before allocating.
pub(crate) struct Reader<'a> {
    pub(crate) bytes: &'a [u8],
    pub(crate) at: usize,
}

impl<'a> Reader<'a> {
    pub(crate) fn remaining(&self) -> usize {
        self.bytes.len() - self.at
    }
    pub(crate) fn take(&mut self, n: usize) -> std::result::Result<&'a [u8], String> {
        if n > self.remaining() {
            return Err(format!("needs {n} more bytes at offset {}, {} left", self.at, self.remaining()));
        }
        let out = &self.bytes[self.at..self.at + n];
        self.at += n;
        Ok(out)
    }
    pub(crate) fn array<const N: usize>(&mut self) -> std::result::Result<[u8; N], String> {
        let mut out = [0u8; N];
        out.copy_from_slice(self.take(N)?);
        Ok(out)
    }
    pub(crate) fn u8(&mut self) -> std::result::Result<u8, String> {
        Ok(self.array::<1>()?[0])
    }
    pub(crate) fn u32(&mut self) -> std::result::Result<u32, String> {
        Ok(u32::from_le_bytes(self.array()?))
    }
    pub(crate) fn u64(&mut self) -> std::result::Result<u64, String> {
        Ok(u64::from_le_bytes(self.array()?))
    }
    pub(crate) fn f64(&mut self) -> std::result::Result<f64, String> {
        Ok(f64::from_le_bytes(self.array()?))
    }
    /// A count of items of at least `item_bytes` bytes each (0: a plain number), checked
    /// against the bytes left.
    pub(crate) fn count(&mut self, item_bytes: usize, what: &str) -> std::result::Result<usize, String> {
        let n = self.u64()?;
        let fits = match item_bytes {
            0 => n <= u32::MAX as u64 * 4,
            b => n <= (self.remaining() / b) as u64,
        };
        if !fits {
            return Err(format!("{what}: {n} announced, more than the {} bytes left can hold", self.remaining()));
        }
        Ok(n as usize)
    }
    pub(crate) fn string(&mut self) -> std::result::Result<String, String> {
        let n = self.u32()? as usize;
        let start = self.at;
        let raw = self.take(n)?;
        String::from_utf8(raw.to_vec()).map_err(|_| format!("the string at offset {start} is not UTF-8"))
    }
    pub(crate) fn f64_array(&mut self, n: usize) -> std::result::Result<Vec<f64>, String> {
        let raw = self.take(n.checked_mul(8).ok_or("an array length overflows")?)?;
        Ok(raw.chunks_exact(8).map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8]))).collect())
    }
    pub(crate) fn f64s(&mut self) -> std::result::Result<Vec<f64>, String> {
        let n = self.count(8, "values")?;
        self.f64_array(n)
    }
    pub(crate) fn u32_array_counted(&mut self, item: usize) -> std::result::Result<Vec<u32>, String> {
        let n = self.count(item, "indices")?;
        let raw = self.take(n * 4)?;
        Ok(raw.chunks_exact(4).map(|c| u32::from_le_bytes(c.try_into().unwrap_or([0; 4]))).collect())
    }
    /// `len` indices, each below `bound`.
    pub(crate) fn indices(&mut self, len: usize, bound: usize, what: &str) -> std::result::Result<Vec<u32>, String> {
        let v = self.u32_array_counted(4)?;
        if v.len() != len {
            return Err(format!("{what}: {} entries, expected {len}", v.len()));
        }
        if let Some(i) = v.iter().position(|&x| x as usize >= bound) {
            return Err(format!("{what}: entry {i} is {}, not below {bound}", v[i]));
        }
        Ok(v)
    }
    /// Rows of `len` values each.
    pub(crate) fn f64_rows(&mut self, len: usize, what: &str) -> std::result::Result<Vec<Vec<f64>>, String> {
        let n = self.count(8, what)?;
        (0..n)
            .map(|i| {
                let row = self.f64s()?;
                if row.len() != len {
                    return Err(format!("{what}: row {i} has {} values, expected {len}", row.len()));
                }
                Ok(row)
            })
            .collect()
    }
    pub(crate) fn mesh(&mut self, what: &str) -> std::result::Result<TriMesh, String> {
        let nv = self.count(24, what)?;
        let coords = self.f64_array(3 * nv)?;
        let nf = self.count(12, what)?;
        let raw = self.take(12 * nf)?;
        let vertices: Vec<[f64; 3]> = coords.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let faces: Vec<[u32; 3]> = raw
            .chunks_exact(12)
            .map(|c| {
                let at = |k: usize| u32::from_le_bytes([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]]);
                [at(0), at(1), at(2)]
            })
            .collect();
        TriMesh::new(vertices, faces).map_err(|e| format!("{what}: {e}"))
    }
}

/// CRC-32 (IEEE 802.3, reflected, the one of zlib and PNG) of `bytes`.
pub fn crc32(bytes: &[u8]) -> u32 {
    const TABLE: [u32; 256] = {
        let mut table = [0u32; 256];
        let mut i = 0;
        while i < 256 {
            let mut c = i as u32;
            let mut k = 0;
            while k < 8 {
                c = if c & 1 != 0 { 0xEDB8_8320 ^ (c >> 1) } else { c >> 1 };
                k += 1;
            }
            table[i] = c;
            i += 1;
        }
        table
    };
    !bytes.iter().fold(!0u32, |c, &b| TABLE[((c ^ b as u32) & 0xFF) as usize] ^ (c >> 8))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc32_matches_the_standard_check_value() {
        // The check value of CRC-32/ISO-HDLC (zlib's crc32 of "123456789").
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
        assert_eq!(crc32(b""), 0);
    }

    #[test]
    fn counts_beyond_the_bytes_left_are_refused_before_allocating() {
        let mut w = Writer::default();
        w.u64(u64::MAX / 2);
        let bytes = w.0;
        let err = Reader { bytes: &bytes, at: 0 }.f64s().unwrap_err();
        assert!(err.contains("more than the 0 bytes left"), "{err}");
        let mut w = Writer::default();
        w.u64(1 << 40);
        w.u64(0);
        let bytes = w.0;
        assert!(Reader { bytes: &bytes, at: 0 }.mesh("m").unwrap_err().contains("m: "));
    }
}
