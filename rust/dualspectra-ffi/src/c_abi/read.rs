//! Mesh files in the C ABI (and, through [`read_mesh_file`], the C++ API): `ds_mesh_read`
//! reads an OFF, OBJ or PLY file as the core's reader does (`dualspectra::mesh::io`, the
//! command line's and Python's `read_mesh`), and `ds_mesh_vertices` / `ds_mesh_faces` give any
//! mesh's arrays back in the layout `ds_mesh_create` takes. Conversion only.

use super::{c_string, ds_mesh, ds_status, guard, handle, make, path_in, reserve, slice_out, Failure};
use crate::HostMesh;
use dualspectra::mesh::io::{read_mesh_with_report, ReadOptions, ReadReport};
use dualspectra::shape::Shape;
use dualspectra::Error;
use std::ffi::c_char;
use std::path::Path;

/// Bytes of memory the reader takes per byte of file at most (`dualspectra::mesh::io`: 1.5x a
/// text file, 2.8x a binary PLY, about 4x a file of one triangle repeated).
const READ_BYTES_PER_FILE_BYTE: u64 = 4;

/// What reading changed between the file and the mesh, as one line naming the file (`None`:
/// nothing): the repeated triangles removed with the vertices only they used (two-sided
/// flaps), and the non-manifold edges and vertices split ([`ReadReport`]).
pub(crate) fn read_note(path: &Path, report: &ReadReport) -> Option<String> {
    let mut parts = Vec::new();
    if report.duplicate_faces_removed > 0 {
        parts.push(format!(
            "removed {} repeated triangle(s) and the {} vertex(es) only they used",
            report.duplicate_faces_removed, report.flap_vertices_dropped
        ));
    }
    parts.extend(report.non_manifold_warning());
    (!parts.is_empty()).then(|| {
        format!(
            "{}: {}; vertex numbers are the mesh's (copies after the file's vertices), not the file's",
            path.display(),
            parts.join("; ")
        )
    })
}

/// Read a mesh file with the core's reader and default [`ReadOptions`] (polygons
/// fan-triangulated, two-sided flaps removed, non-manifold edges and vertices split; a vertex
/// in no face, a zero-area face and the rest of the module doc's cases are errors naming the
/// file). The mesh's numbering is its own: the host's arrays are the mesh's.
pub(crate) fn read_mesh_file(path: &Path) -> Result<(HostMesh, Option<String>), Error> {
    let (mesh, report) = read_mesh_with_report(path, &ReadOptions::default())?;
    let note = read_note(path, &report);
    Ok((HostMesh { shape: Shape::new(mesh), intake: None, numbering: None }, note))
}

/// Read a triangle mesh from an OFF, OBJ or PLY file (ASCII or binary; the format from the
/// extension, any case). On success `*out` receives a mesh handle, as from `ds_mesh_create`,
/// to release with `ds_mesh_destroy`; `ds_mesh_vertices` and `ds_mesh_faces` copy its arrays.
///
/// Reading repairs what raw files hold, as the command line and Python's `read_mesh` do:
/// polygons are fan-triangulated; a triangle listed twice in opposite orientations (a
/// two-sided flap) is removed with the vertices only it used; non-manifold edges (in more
/// than two faces) and vertices (faces in several fans) are split, each extra fan getting a
/// copy of the vertex appended after the file's vertices. `ds_mesh_warning` then says what
/// was changed, naming the file (NULL if nothing): the mesh's vertex numbers are its own, not
/// the file's.
///
/// Errors (the message names the file): `DS_IO` (the file cannot be read, is not a regular
/// file, or is not a mesh of its format: bad header, number or count, truncated, unknown
/// extension), `DS_INVALID_MESH` (index out of range, non-finite coordinate, no faces, a
/// zero-area face or one repeating a vertex, a vertex in no face), `DS_INVALID_ARGUMENT`
/// (NULL or empty path, NULL `out`), `DS_OUT_OF_MEMORY` (the memory reading needs, up to
/// four times the file's size, cannot be reserved).
///
/// # Safety
/// `path` a NUL-terminated string (any bytes on Unix, as the file system takes them; UTF-8
/// elsewhere); `out` valid for writing one pointer.
#[no_mangle]
pub unsafe extern "C" fn ds_mesh_read(path: *const c_char, out: *mut *mut ds_mesh) -> ds_status {
    unsafe {
        make(out, || {
            let path = path_in(path, "path")?;
            if let Ok(meta) = std::fs::metadata(&path) {
                let bytes = meta.len().saturating_mul(READ_BYTES_PER_FILE_BYTE);
                reserve(usize::try_from(bytes).ok(), || format!("reading the mesh file {}", path.display()))?;
            }
            let (mesh, note) = read_mesh_file(&path)?;
            Ok(ds_mesh { mesh, warning: note.map(|n| c_string(&n)) })
        })
    }
}

/// Copy the positions of the mesh the core works on, `x0 y0 z0 x1 ...`, into `xyz`
/// (`xyz_len == 3 * ds_mesh_n_used_vertices(mesh)`): for a mesh from `ds_mesh_read` or
/// `ds_mesh_create`, all its vertices (`ds_mesh_n_vertices`); from `ds_mesh_create_from_host`,
/// the used host vertices then the copies of split ones (`ds_mesh_used_vertices` maps them to
/// the host's).
///
/// # Safety
/// `mesh` any pointer (a handle argument, checked); `xyz` valid for `xyz_len` writes.
#[no_mangle]
pub unsafe extern "C" fn ds_mesh_vertices(mesh: *const ds_mesh, xyz: *mut f64, xyz_len: usize) -> ds_status {
    guard(|| {
        let m = unsafe { handle(mesh, "mesh")? };
        copy_out(m.mesh.mesh().vertices().as_flattened(), xyz, xyz_len, "xyz", "3 * ds_mesh_n_used_vertices")
    })
}

/// Copy the triangles of the mesh the core works on, `i0 j0 k0 i1 ...` (0-based, into the
/// vertices of `ds_mesh_vertices`), into `tri` (`tri_len == 3 * ds_mesh_n_faces(mesh)`).
///
/// # Safety
/// `mesh` any pointer (a handle argument, checked); `tri` valid for `tri_len` writes.
#[no_mangle]
pub unsafe extern "C" fn ds_mesh_faces(mesh: *const ds_mesh, tri: *mut u32, tri_len: usize) -> ds_status {
    guard(|| {
        let m = unsafe { handle(mesh, "mesh")? };
        copy_out(m.mesh.mesh().faces().as_flattened(), tri, tri_len, "tri", "3 * ds_mesh_n_faces")
    })
}

/// Copy `values` to a caller's array of `len` elements, which must be exactly as long.
fn copy_out<T: Copy>(values: &[T], out: *mut T, len: usize, what: &str, expected: &str) -> Result<(), Failure> {
    if len != values.len() {
        return Err(super::invalid(format!("{what}_len is {len}, expected {expected} = {}", values.len())));
    }
    // SAFETY: the caller's contract (`out` valid for `len` writes); checked for NULL/alignment.
    unsafe { slice_out(out, len, what)? }.copy_from_slice(values);
    Ok(())
}
