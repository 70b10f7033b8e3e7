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

use super::TriMesh;
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
        if faces.is_empty() {
            return Err(MeshError::NoFaces.into());
        }
        // Host index of each kept face, for errors in the host's numbering.
        let good_faces: Vec<usize> = (0..faces.len()).filter(|&i| !is_degenerate(&vertices, &faces[i])).collect();
        let good: Vec<[u32; 3]> = good_faces.iter().map(|&i| faces[i]).collect();
        let dropped_faces = faces.len() - good.len();
        if good.is_empty() {
            return Err(MeshError::AllFacesDegenerate { count: faces.len() }.into());
        }
        let (mesh, kept) = TriMesh::new_dropping_isolated(vertices, good.clone()).map_err(|e| {
            // The mesh's numbering back to the host's: the vertices the kept faces use.
            let mut used = vec![false; n];
            good.iter().flatten().for_each(|&i| used[i as usize] = true);
            let kept: Vec<u32> = (0..n as u32).filter(|&i| used[i as usize]).collect();
            let vertex = |v: u32| kept.get(v as usize).copied().unwrap_or(v);
            let face = |f: usize| good_faces.get(f).copied().unwrap_or(f);
            match e {
                MeshError::NonManifoldEdge { a, b, count } => MeshError::NonManifoldEdge { a: vertex(a), b: vertex(b), count },
                MeshError::NonManifoldVertex { vertex: v, fans } => MeshError::NonManifoldVertex { vertex: vertex(v as u32) as usize, fans },
                MeshError::DegenerateFace { face: f } => MeshError::DegenerateFace { face: face(f) },
                MeshError::RepeatedVertexInFace { face: f } => MeshError::RepeatedVertexInFace { face: face(f) },
                other => other,
            }
        })?;
        let dropped_vertices = n - kept.len();
        Ok(MeshIntake { mesh, kept, n_host_vertices: n, dropped_faces, dropped_vertices })
    }

    /// From flat arrays `xyz` (3 per vertex) and `tri` (3 per face).
    pub fn from_flat(xyz: &[f64], tri: &[u32]) -> Result<Self> {
        if !xyz.len().is_multiple_of(3) {
            return Err(MeshError::BadArrayLength { len: xyz.len(), stride: 3 }.into());
        }
        if !tri.len().is_multiple_of(3) {
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

/// Whether face `f` repeats a vertex or has zero area relative to its longest edge:
/// `area <= DEGENERATE_RATIO * longest_edge^2`, the test [`TriMesh::new`] applies.
///
/// Scale-free in floating point too: the edge vectors are divided by their largest
/// component before the cross product, so the test gives the same answer for a triangle
/// and for it scaled by 1e-160 or 1e160 (where the area itself would underflow to 0 or
/// overflow to infinity). Coordinates must be finite.
pub(super) fn is_degenerate(vertices: &[[f64; 3]], f: &[u32; 3]) -> bool {
    if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
        return true;
    }
    let [a, b, c] = f.map(|i| vertices[i as usize]);
    let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let mut edges = [sub(b, a), sub(c, a), sub(c, b)];
    if edges.iter().flatten().any(|x| !x.is_finite()) {
        // Differences of coordinates near f64::MAX overflow; halving is exact there.
        let half = |p: [f64; 3]| p.map(|x| 0.5 * x);
        let [a, b, c] = [half(a), half(b), half(c)];
        edges = [sub(b, a), sub(c, a), sub(c, b)];
    }
    let scale = edges.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    if !(scale > 0.0) {
        return true;
    }
    let [u, v, w] = edges.map(|e| e.map(|x| x / scale));
    let cross = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    let area = 0.5 * (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt();
    let norm2 = |e: [f64; 3]| e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
    let longest = norm2(u).max(norm2(v)).max(norm2(w));
    !(area > DEGENERATE_RATIO * longest)
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
        assert!(MeshIntake::new(tri.clone(), vec![[0, 0, 1]]).unwrap_err().to_string().contains("all 1 faces are degenerate"));
        assert!(MeshIntake::new(tri, vec![]).unwrap_err().to_string().contains("no faces"));
        // Errors name the host's vertices: a loose vertex 0 shifts the mesh's numbering by one.
        let mut v = vec![[9.0; 3]];
        v.extend([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]]);
        let fan = vec![[1, 2, 3], [2, 1, 4], [1, 2, 5]];
        let e = MeshIntake::new(v, fan).unwrap_err().to_string();
        assert!(e.contains("edge (1, 2) is shared by 3 faces"), "{e}");
        assert!(MeshIntake::from_flat(&[0.0; 4], &[]).is_err());
    }
}
