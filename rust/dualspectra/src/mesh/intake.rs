//! One mesh intake for every front end: a host's arrays (an editor's mesh, a file) become a
//! [`TriMesh`], with what was left out counted and an index map back to the host's vertices.
//!
//! Editors keep vertices no face uses (loose points, deleted elements) and zero-area
//! triangles; the core's [`TriMesh`] has neither. The intake drops faces that repeat a vertex
//! or have zero area (`area <= 1e-14 * longest_edge^2`, the test [`TriMesh::new`] applies),
//! then the vertices no remaining face uses, and keeps `kept[new] = host index`. Results
//! computed on the mesh go back to the host's indices with [`MeshIntake::to_host`].
//! Anything else invalid (an index out of range, a non-finite coordinate, a non-manifold
//! edge, no face left) is an error.

use super::{triangle_area, TriMesh};
use crate::error::{MeshError, Result};

/// Relative area under which a triangle is degenerate (as in [`TriMesh::new`]).
pub const DEGENERATE_RATIO: f64 = 1e-14;

/// A host mesh taken in: the mesh, the map back, and what was dropped.
#[derive(Debug, Clone)]
pub struct MeshIntake {
    pub mesh: TriMesh,
    /// `kept[i]`: the host index of mesh vertex `i` (increasing).
    pub kept: Vec<u32>,
    /// Vertices in the host's arrays.
    pub n_host_vertices: usize,
    /// Host faces left out as degenerate (repeated vertex or zero area).
    pub dropped_faces: usize,
    /// Host vertices left out (used by no kept face).
    pub dropped_vertices: usize,
}

impl MeshIntake {
    /// Take in `vertices` and `faces` (0-based indices into `vertices`).
    pub fn new(vertices: Vec<[f64; 3]>, faces: Vec<[u32; 3]>) -> Result<Self> {
        let n = vertices.len();
        if let Some(v) = vertices.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(MeshError::NonFiniteCoordinate { vertex: v }.into());
        }
        for (fi, f) in faces.iter().enumerate() {
            if let Some(&i) = f.iter().find(|&&i| i as usize >= n) {
                return Err(MeshError::IndexOutOfRange { face: fi, index: i as u64, n_vertices: n }.into());
            }
        }
        let good: Vec<[u32; 3]> = faces.iter().copied().filter(|f| !is_degenerate(&vertices, f)).collect();
        let dropped_faces = faces.len() - good.len();
        if good.is_empty() && !faces.is_empty() {
            return Err(crate::error::Error::InvalidArgument(format!("all {} faces are degenerate (zero area)", faces.len())));
        }
        let (mesh, kept) = TriMesh::new_dropping_isolated(vertices, good)?;
        let dropped_vertices = n - kept.len();
        Ok(MeshIntake { mesh, kept, n_host_vertices: n, dropped_faces, dropped_vertices })
    }

    /// From flat arrays `xyz` (3 per vertex) and `tri` (3 per face).
    pub fn from_flat(xyz: &[f64], tri: &[u32]) -> Result<Self> {
        if xyz.len() % 3 != 0 {
            return Err(MeshError::BadArrayLength { len: xyz.len(), stride: 3 }.into());
        }
        if tri.len() % 3 != 0 {
            return Err(MeshError::BadArrayLength { len: tri.len(), stride: 3 }.into());
        }
        Self::new(
            xyz.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
            tri.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        )
    }

    /// Per-vertex `values` of the mesh at the host's indices; `fill` at dropped vertices.
    pub fn to_host<T: Clone>(&self, values: &[T], fill: T) -> Vec<T> {
        let mut out = vec![fill; self.n_host_vertices];
        for (&host, v) in self.kept.iter().zip(values) {
            out[host as usize] = v.clone();
        }
        out
    }

    /// Per-host-vertex `values` read at the mesh's vertices.
    pub fn from_host<T: Clone>(&self, values: &[T]) -> Vec<T> {
        self.kept.iter().map(|&h| values[h as usize].clone()).collect()
    }

    /// What was dropped, as a sentence for the user (`None` if nothing was).
    pub fn warning(&self, what: &str) -> Option<String> {
        if self.dropped_faces == 0 && self.dropped_vertices == 0 {
            return None;
        }
        Some(format!(
            "{what}: left out {} degenerate face(s) and {} vertex(es) in no face; results at those vertices are empty",
            self.dropped_faces, self.dropped_vertices
        ))
    }
}

fn is_degenerate(vertices: &[[f64; 3]], f: &[u32; 3]) -> bool {
    if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
        return true;
    }
    let [a, b, c] = f.map(|i| vertices[i as usize]);
    let l2 = |p: [f64; 3], q: [f64; 3]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2);
    let longest = l2(a, b).max(l2(b, c)).max(l2(c, a));
    !(triangle_area(a, b, c) > DEGENERATE_RATIO * longest)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drops_degenerate_faces_and_loose_vertices_and_maps_back() {
        // Two triangles of a square, a loose vertex (2), a repeated-index face and a
        // zero-area face (collinear 0, 1, 5).
        let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [9.0, 9.0, 9.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [2.0, 0.0, 0.0]];
        let f = vec![[0, 1, 3], [0, 3, 4], [1, 1, 3], [0, 1, 5]];
        let intake = MeshIntake::new(v, f).unwrap();
        assert_eq!(intake.mesh.n_faces(), 2);
        assert_eq!(intake.kept, vec![0, 1, 3, 4]);
        assert_eq!((intake.dropped_faces, intake.dropped_vertices), (2, 2));
        assert_eq!(intake.to_host(&[1, 2, 3, 4], 0), vec![1, 2, 0, 3, 4, 0]);
        assert_eq!(intake.from_host(&[10, 11, 12, 13, 14, 15]), vec![10, 11, 13, 14]);
        assert!(intake.warning("full mesh").unwrap().contains("2 degenerate face(s) and 2 vertex(es)"));
        let clean = MeshIntake::new(vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]]).unwrap();
        assert!(clean.warning("mesh").is_none());
    }

    #[test]
    fn refuses_what_cannot_be_repaired() {
        let tri = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        assert!(MeshIntake::new(tri.clone(), vec![[0, 1, 3]]).unwrap_err().to_string().contains("vertex 3"));
        assert!(MeshIntake::new(vec![[f64::NAN; 3]], vec![]).is_err());
        assert!(MeshIntake::new(tri.clone(), vec![[0, 0, 1]]).unwrap_err().to_string().contains("degenerate"));
        assert!(MeshIntake::new(tri, vec![]).is_err());
        assert!(MeshIntake::from_flat(&[0.0; 4], &[]).is_err());
    }
}
