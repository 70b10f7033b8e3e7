//! numpy arrays -> checked core meshes. Shapes and index ranges are checked here (not only in
//! Python); every geometric invariant is checked by `TriMesh::new`.

use crate::errors::{mesh_array_error, mesh_error};
use dualspectra::TriMesh;
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::PyResult;

/// Build a validated [`TriMesh`] from `V (n, 3) float64` and `F (m, 3) int64`.
/// `what` names the mesh in error messages.
pub fn trimesh(what: &str, vertices: &PyReadonlyArray2<'_, f64>, faces: &PyReadonlyArray2<'_, i64>) -> PyResult<TriMesh> {
    let (vs, fs) = (vertices.shape(), faces.shape());
    if vs[1] != 3 {
        return Err(mesh_array_error(what, format!("vertices must have shape (n, 3), got ({}, {})", vs[0], vs[1])));
    }
    if fs[1] != 3 {
        return Err(mesh_array_error(what, format!("faces must have shape (m, 3), got ({}, {})", fs[0], fs[1])));
    }
    let v = vertices.as_array();
    let f = faces.as_array();
    let n = vs[0];
    let verts: Vec<[f64; 3]> = v.outer_iter().map(|r| [r[0], r[1], r[2]]).collect();
    let mut tris: Vec<[u32; 3]> = Vec::with_capacity(fs[0]);
    for (fi, r) in f.outer_iter().enumerate() {
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
    TriMesh::new(verts, tris).map_err(|e| mesh_error(what, e))
}
