//! Triangle meshes: the checked [`TriMesh`], file I/O, topology, generators.

pub mod topology;
pub mod generate;
pub(crate) mod decimate;
pub(crate) mod nearest;
pub mod intake;
pub mod io;
pub mod repair;

use crate::error::MeshError;

/// A validated triangle mesh: finite vertex positions `V (n x 3)` and faces `F (m x 3)`,
/// 0-based, consistently usable by every later stage.
///
/// Invariants checked by [`TriMesh::new`]: at least one face; indices in range;
/// finite coordinates; no face repeating a vertex; no zero-area face; every edge in
/// at most two faces (edge-manifold); the faces at every vertex forming one fan, joined
/// through shared edges (vertex-manifold); every vertex in some face. Raw meshes that
/// fail only the manifold checks are repaired by [`repair::split_non_manifold`] (the
/// [`intake`] and the reader of [`io`] do it).
#[derive(Debug, Clone, PartialEq)]
pub struct TriMesh {
    vertices: Vec<[f64; 3]>,
    faces: Vec<[u32; 3]>,
}

impl TriMesh {
    /// Build and validate a mesh. See the type's invariants; each violation is a distinct [`MeshError`].
    pub fn new(vertices: Vec<[f64; 3]>, faces: Vec<[u32; 3]>) -> Result<Self, MeshError> {
        validate(&vertices, &faces, false)?;
        Ok(TriMesh { vertices, faces })
    }

    /// [`TriMesh::new`] for faces that [`repair::split_faces`] made manifold: the manifold
    /// checks are skipped (debug builds run them too).
    pub(in crate::mesh) fn new_split(vertices: Vec<[f64; 3]>, faces: Vec<[u32; 3]>) -> Result<Self, MeshError> {
        validate(&vertices, &faces, true)?;
        Ok(TriMesh { vertices, faces })
    }

    /// Build from flat arrays `[x0, y0, z0, x1, ...]` and `[i0, j0, k0, ...]` (as from C or numpy).
    pub fn from_flat(vertices: &[f64], faces: &[u32]) -> Result<Self, MeshError> {
        if !vertices.len().is_multiple_of(3) {
            return Err(MeshError::BadArrayLength { len: vertices.len(), stride: 3 });
        }
        if !faces.len().is_multiple_of(3) {
            return Err(MeshError::BadArrayLength { len: faces.len(), stride: 3 });
        }
        let v = vertices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let f = faces.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        Self::new(v, f)
    }

    /// Build from `nalgebra` points and faces (feature `nalgebra`); checks as in [`TriMesh::new`].
    #[cfg(feature = "nalgebra")]
    pub fn from_points(points: &[nalgebra::Point3<f64>], faces: Vec<[u32; 3]>) -> Result<Self, MeshError> {
        Self::new(points.iter().map(|p| [p.x, p.y, p.z]).collect(), faces)
    }

    /// Repair then build: drop vertices that belong to no face, and return the kept
    /// original indices (`kept[new] = old`). Other checks as in [`TriMesh::new`].
    pub fn new_dropping_isolated(
        vertices: Vec<[f64; 3]>,
        faces: Vec<[u32; 3]>,
    ) -> Result<(Self, Vec<u32>), MeshError> {
        let n = vertices.len();
        for (fi, f) in faces.iter().enumerate() {
            for &i in f {
                if i as usize >= n {
                    return Err(MeshError::IndexOutOfRange { face: fi, index: i as u64, n_vertices: n });
                }
            }
        }
        let mut used = vec![false; n];
        faces.iter().flatten().for_each(|&i| used[i as usize] = true);
        let kept: Vec<u32> = (0..n as u32).filter(|&i| used[i as usize]).collect();
        let mut new_index = vec![u32::MAX; n];
        for (new, &old) in kept.iter().enumerate() {
            new_index[old as usize] = new as u32;
        }
        let v = kept.iter().map(|&i| vertices[i as usize]).collect();
        let f = faces.iter().map(|f| f.map(|i| new_index[i as usize])).collect();
        Ok((Self::new(v, f)?, kept))
    }

    pub fn vertices(&self) -> &[[f64; 3]] {
        &self.vertices
    }
    pub fn faces(&self) -> &[[u32; 3]] {
        &self.faces
    }
    pub fn n_vertices(&self) -> usize {
        self.vertices.len()
    }
    pub fn n_faces(&self) -> usize {
        self.faces.len()
    }
    /// Consume into `(V, F)`.
    pub fn into_parts(self) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        (self.vertices, self.faces)
    }
    /// The same connectivity with every position mapped by `f` (validated again).
    pub fn map_positions(&self, f: impl Fn([f64; 3]) -> [f64; 3]) -> Result<Self, MeshError> {
        Self::new(self.vertices.iter().map(|&p| f(p)).collect(), self.faces.clone())
    }
    /// Total surface area.
    pub fn area(&self) -> f64 {
        self.faces.iter().map(|f| triangle_area(self.vertices[f[0] as usize], self.vertices[f[1] as usize], self.vertices[f[2] as usize])).sum()
    }
    /// Axis-aligned bounding box diagonal length.
    pub fn bbox_diagonal(&self) -> f64 {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &self.vertices {
            for d in 0..3 {
                lo[d] = lo[d].min(p[d]);
                hi[d] = hi[d].max(p[d]);
            }
        }
        ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2)).sqrt()
    }
}

/// Euclidean distance `|a - b|`.
pub fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Area of the triangle `(a, b, c)`: `|(b - a) x (c - a)| / 2`.
pub fn triangle_area(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let x = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    0.5 * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt()
}

fn validate(vertices: &[[f64; 3]], faces: &[[u32; 3]], split: bool) -> Result<(), MeshError> {
    let n = vertices.len();
    if n == 0 {
        return Err(MeshError::NoVertices);
    }
    if faces.is_empty() {
        return Err(MeshError::NoFaces);
    }
    if let Some(v) = vertices.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        return Err(MeshError::NonFiniteCoordinate { vertex: v });
    }
    for (fi, f) in faces.iter().enumerate() {
        for &i in f {
            if i as usize >= n {
                return Err(MeshError::IndexOutOfRange { face: fi, index: i as u64, n_vertices: n });
            }
        }
        if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
            return Err(MeshError::RepeatedVertexInFace { face: fi });
        }
    }
    // Degenerate: zero area relative to the squared longest edge, computed without
    // under/overflow at any scale (see `intake::is_degenerate`).
    if let Some(fi) = faces.iter().position(|f| intake::is_degenerate(vertices, f)) {
        return Err(MeshError::DegenerateFace { face: fi });
    }
    // A triangle given twice (in either orientation) would pass the edge test as a closed
    // two-face sheet; the first repeat in face order is reported.
    if let Some((face, first)) = repeated_face(faces) {
        return Err(MeshError::RepeatedFace { face, first });
    }
    // Edge- then vertex-manifold; the smallest offending edge, then vertex, is reported.
    if split {
        debug_assert_eq!(repair::check_manifold(n, faces), Ok(()));
    } else {
        repair::check_manifold(n, faces)?;
    }
    let mut used = vec![false; n];
    faces.iter().flatten().for_each(|&i| used[i as usize] = true);
    let isolated = used.iter().filter(|&&u| !u).count();
    if let Some(v) = used.iter().position(|&u| !u) {
        return Err(MeshError::IsolatedVertex { vertex: v, count: isolated });
    }
    Ok(())
}

/// The first face (in order) with the same vertex set as an earlier one, and that earlier
/// face: `(face, first)`. Sorting face numbers by vertex set, 4 bytes per face.
fn repeated_face(faces: &[[u32; 3]]) -> Option<(usize, usize)> {
    let set = |t: u32| {
        let mut key = faces[t as usize];
        key.sort_unstable();
        key
    };
    let m = u32::try_from(faces.len()).ok()?;
    let mut order: Vec<u32> = (0..m).collect();
    order.sort_unstable_by(|&s, &t| set(s).cmp(&set(t)).then(s.cmp(&t)));
    order
        .chunk_by(|&s, &t| set(s) == set(t))
        .filter(|g| g.len() > 1)
        .map(|g| (g[1] as usize, g[0] as usize))
        .min()
}
