//! numpy arrays -> core meshes. Shapes and index ranges are checked here (not only in
//! Python); every geometric invariant is checked by the core.
//!
//! Two entries: [`trimesh`] for the operators, whose results are indexed by the given
//! vertices, so the mesh must already be clean (`TriMesh::new`); [`intake`] for the
//! localizer, which takes a host's arrays as they are (`MeshIntake`: degenerate faces and
//! vertices in no face are dropped, results mapped back to the caller's numbering).

use crate::errors::{intake_error, mesh_array_error, mesh_error};
use dualspectra::mesh::intake::MeshIntake;
use dualspectra::TriMesh;
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::PyResult;

/// Vertex positions and triangles as the core takes them.
type MeshVectors = (Vec<[f64; 3]>, Vec<[u32; 3]>);

/// Positions and triangles from `V (n, 3) float64` and `F (m, 3) int64`; `what` names the
/// mesh in error messages.
fn arrays(
    what: &str,
    vertices: &PyReadonlyArray2<'_, f64>,
    faces: &PyReadonlyArray2<'_, i64>,
) -> PyResult<MeshVectors> {
    let (vs, fs) = (vertices.shape(), faces.shape());
    if vs[1] != 3 {
        return Err(mesh_array_error(what, format!("vertices must have shape (n, 3), got ({}, {})", vs[0], vs[1])));
    }
    if fs[1] != 3 {
        return Err(mesh_array_error(what, format!("faces must have shape (m, 3), got ({}, {})", fs[0], fs[1])));
    }
    let n = vs[0];
    let verts: Vec<[f64; 3]> = vertices.as_array().outer_iter().map(|r| [r[0], r[1], r[2]]).collect();
    let mut tris: Vec<[u32; 3]> = Vec::with_capacity(fs[0]);
    for (fi, r) in faces.as_array().outer_iter().enumerate() {
        let mut t = [0u32; 3];
        for c in 0..3 {
            let i = r[c];
            if i < 0 {
                return Err(mesh_array_error(what, format!("face {fi} has a negative vertex index {i}")));
            }
            if i as u64 >= n as u64 || i > u32::MAX as i64 {
                return Err(mesh_error(
                    what,
                    dualspectra::MeshError::IndexOutOfRange { face: fi, index: i as u64, n_vertices: n },
                ));
            }
            t[c] = i as u32;
        }
        tris.push(t);
    }
    Ok((verts, tris))
}

/// A validated [`TriMesh`] (nothing dropped: every vertex in a face, no degenerate face).
pub fn trimesh(what: &str, vertices: &PyReadonlyArray2<'_, f64>, faces: &PyReadonlyArray2<'_, i64>) -> PyResult<TriMesh> {
    let (v, f) = arrays(what, vertices, faces)?;
    TriMesh::new(v, f).map_err(|e| mesh_error(what, e))
}

/// The core intake of the caller's arrays: degenerate faces and loose vertices dropped, the
/// map back kept. Every failure is a `MeshError` naming the mesh.
pub fn intake(what: &str, vertices: &PyReadonlyArray2<'_, f64>, faces: &PyReadonlyArray2<'_, i64>) -> PyResult<MeshIntake> {
    let (v, f) = arrays(what, vertices, faces)?;
    if f.is_empty() && !v.is_empty() {
        // The intake would drop every vertex first and report "no vertices"; say what is
        // missing. (Workaround in the binding; the core's MeshIntake could check it first.)
        return Err(mesh_error(what, dualspectra::MeshError::NoFaces));
    }
    MeshIntake::new(v, f).map_err(|e| intake_error(what, e))
}
