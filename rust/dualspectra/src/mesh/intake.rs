//! One mesh intake for every front end: a host's arrays (an editor's mesh, a file) become a
//! [`TriMesh`], with what was changed counted and an index map back to the host's vertices.
//!
//! Editors keep vertices no face uses (loose points, deleted elements) and zero-area
//! triangles, and scans have non-manifold edges and vertices; the core's [`TriMesh`] has
//! none of these. The intake drops faces that repeat a vertex or have zero area
//! (`area <= 1e-14 * longest_edge^2`, the test [`TriMesh::new`] applies), splits the
//! non-manifold edges and vertices ([`split_non_manifold`]: vertex copies, no face
//! removed), then drops the vertices no remaining face uses, and keeps `kept[new] = host
//! index`. Results computed on the mesh go back to the host's indices with
//! [`MeshIntake::to_host`] (values: the first copy's) and [`MeshIntake::to_host_any`]
//! (selections: any copy's). Anything else invalid (an index out of range, a non-finite
//! coordinate, no face left) is an error.
//!
//! [`HostNumbering`] is that map on its own ([`MeshIntake::host_numbering`]): what a prepared
//! shape keeps (and saves) so that every front end reports results in the caller's
//! numbering with the same rules, written once here.
//!
//! [`split_non_manifold`]: super::repair::split_non_manifold

use super::repair::split_faces;
use super::TriMesh;
use crate::error::{MeshError, Result};

/// Relative area under which a triangle is degenerate (as in [`TriMesh::new`]).
pub const DEGENERATE_RATIO: f64 = 1e-14;

/// A host mesh taken in: the mesh, the map back, and what was dropped.
#[derive(Debug, Clone)]
pub struct MeshIntake {
    pub mesh: TriMesh,
    /// `kept[i]`: the host index of mesh vertex `i`: the host vertices kept, increasing, then
    /// the copies made by splitting non-manifold vertices (several `i` may name one host vertex).
    pub kept: Vec<u32>,
    /// Vertices in the host's arrays.
    pub n_host_vertices: usize,
    /// Host faces left out as degenerate (repeated vertex or zero area).
    pub dropped_faces: usize,
    /// Host faces left out as repeated copies of another (see [`MeshIntake::new`]).
    pub repeated_faces: usize,
    /// Host vertices left out (used by no kept face).
    pub dropped_vertices: usize,
    /// Host edges that were in more than two faces, cut (see [`super::repair`]).
    pub non_manifold_edges_split: usize,
    /// Host vertices whose faces formed several fans, split into copies (see [`super::repair`]).
    pub non_manifold_vertices_split: usize,
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
        // Triangles given twice: removed as the readers do (a triangle and its reverse cancel,
        // of the copies left one is kept).
        let unique = super::io::duplicate_free(&good);
        let repeated_faces = unique.iter().filter(|&&k| !k).count();
        let (good_faces, good): (Vec<usize>, Vec<[u32; 3]>) =
            good_faces.into_iter().zip(good).zip(&unique).filter(|(_, &k)| k).map(|(p, _)| p).unzip();
        if good.is_empty() {
            return Err(MeshError::AllFacesDegenerate { count: faces.len() }.into());
        }
        let mut faces = good;
        let split = split_faces(n, &mut faces);
        // Vertex `i` of the split is host vertex `origin(i)`: itself, or the one it copies.
        let origin = |i: usize| if i < n { i as u32 } else { split.copies[i - n] };
        // Drop the vertices no face uses; `kept` maps to the host.
        let mut used = vec![false; n + split.copies.len()];
        faces.iter().flatten().for_each(|&i| used[i as usize] = true);
        let mut new_index = vec![u32::MAX; used.len()];
        let (mut kept, mut positions) = (Vec::new(), Vec::new());
        for i in (0..used.len()).filter(|&i| used[i]) {
            new_index[i] = kept.len() as u32;
            kept.push(origin(i));
            positions.push(vertices[origin(i) as usize]);
        }
        drop((used, vertices));
        faces.iter_mut().for_each(|f| *f = f.map(|i| new_index[i as usize]));
        let build = if split.manifold { TriMesh::new_split } else { TriMesh::new };
        let mesh = build(positions, faces).map_err(|e| {
            // Errors in the host's numbering.
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
        // Every copy has faces, and so has the vertex it copies: `kept` less the copies is
        // the host vertices kept.
        let dropped_vertices = n - (kept.len() - split.copies.len());
        Ok(MeshIntake {
            mesh,
            kept,
            n_host_vertices: n,
            dropped_faces,
            repeated_faces,
            dropped_vertices,
            non_manifold_edges_split: split.edges_split,
            non_manifold_vertices_split: split.vertices_split,
        })
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

    /// Per-vertex `values` of the mesh at the host's indices; `fill` at dropped vertices. A
    /// split host vertex takes its first copy's value (the fan of its lowest face): for
    /// values such as curvature, potential or score.
    pub fn to_host<T: Clone>(&self, values: &[T], fill: T) -> Vec<T> {
        first_copy_to_host(&self.kept, self.n_host_vertices, values, fill)
    }

    /// A selection of mesh vertices at the host's indices: a host vertex is selected if any
    /// of its copies is (`false` at dropped vertices). For regions.
    pub fn to_host_any(&self, selected: &[bool]) -> Vec<bool> {
        any_copy_to_host(&self.kept, self.n_host_vertices, selected)
    }

    /// Per-vertex amounts of the mesh summed at the host's indices (0 at dropped vertices):
    /// a split host vertex gets the sum over its copies, for additive quantities such as a
    /// lumped mass (the area around the vertex).
    pub fn to_host_sum(&self, values: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.n_host_vertices];
        for (&host, &v) in self.kept.iter().zip(values) {
            out[host as usize] += v;
        }
        out
    }

    /// The map back to the host's vertices on its own (to keep with a prepared shape).
    pub fn host_numbering(&self) -> HostNumbering {
        HostNumbering { n_host_vertices: self.n_host_vertices, kept: self.kept.clone() }
    }

    /// Per-host-vertex `values` read at the mesh's vertices (every copy reads its host vertex).
    pub fn from_host<T: Clone>(&self, values: &[T]) -> Vec<T> {
        self.kept.iter().map(|&h| values[h as usize].clone()).collect()
    }

    /// Copies the split added: mesh vertices beyond the host vertices kept.
    pub fn n_copies(&self) -> usize {
        self.kept.len() - (self.n_host_vertices - self.dropped_vertices)
    }

    /// What was changed, as a sentence for the user (`None` if nothing was).
    pub fn warning(&self, what: &str) -> Option<String> {
        let mut parts = Vec::new();
        if self.repeated_faces > 0 {
            parts.push(format!("removed {} repeated face(s) (a triangle given twice)", self.repeated_faces));
        }
        if self.dropped_faces > 0 || self.dropped_vertices > 0 {
            parts.push(format!(
                "left out {} degenerate face(s) and {} vertex(es) in no face; results at those vertices are empty",
                self.dropped_faces, self.dropped_vertices
            ));
        }
        if self.non_manifold_edges_split > 0 || self.non_manifold_vertices_split > 0 {
            parts.push(format!(
                "split {} non-manifold edge(s) and {} non-manifold vertex(es) ({} vertex copies; a split vertex's \
                 result is its first copy's, a region holds it if it holds any copy)",
                self.non_manifold_edges_split,
                self.non_manifold_vertices_split,
                self.n_copies()
            ));
        }
        (!parts.is_empty()).then(|| format!("{what}: {}", parts.join("; ")))
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

/// The caller's numbering of a mesh's vertices (a file's vertex records before reading
/// repaired them, an editor's arrays before the intake): `kept[i]` is the caller's index of
/// mesh vertex `i`. Kept with a prepared shape (and in its file) so that every front end
/// reports per-vertex results in the caller's numbering, by the intake's rules: a value at
/// host vertex $h$ is that of its first copy $\min\{i : \text{kept}_i = h\}$; a host vertex
/// is in a region when any of its copies is; vertices no copy names get the fill value.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct HostNumbering {
    /// Vertices in the caller's numbering.
    pub n_host_vertices: usize,
    /// `kept[i]`: the caller's index of mesh vertex `i` (several `i` may name one host
    /// vertex: the copies of a split non-manifold vertex).
    pub kept: Vec<u32>,
}

impl HostNumbering {
    /// The numbering of a mesh taken as it is: mesh vertex `i` is host vertex `i`.
    pub fn identity(n_vertices: usize) -> Self {
        HostNumbering { n_host_vertices: n_vertices, kept: (0..n_vertices as u32).collect() }
    }

    /// Whether mesh vertex `i` is host vertex `i` for every `i` (nothing dropped or split).
    pub fn is_identity(&self) -> bool {
        self.n_host_vertices == self.kept.len() && self.kept.iter().enumerate().all(|(i, &k)| k as usize == i)
    }

    /// Per-vertex `values` of the mesh at the caller's indices: a split vertex's first copy's
    /// value, `fill` where no mesh vertex names the host vertex (as [`MeshIntake::to_host`]).
    pub fn values_to_host<T: Clone>(&self, values: &[T], fill: T) -> Vec<T> {
        first_copy_to_host(&self.kept, self.n_host_vertices, values, fill)
    }

    /// A region (one flag per mesh vertex) in the caller's numbering: a host vertex is in it
    /// when any of its copies is (as [`MeshIntake::to_host_any`]).
    pub fn region_to_host(&self, region: &[bool]) -> Vec<bool> {
        any_copy_to_host(&self.kept, self.n_host_vertices, region)
    }
}

/// `out[kept[i]] = values[i]` for the first `i` naming each host vertex; `fill` elsewhere.
fn first_copy_to_host<T: Clone>(kept: &[u32], n_host: usize, values: &[T], fill: T) -> Vec<T> {
    let mut out = vec![fill; n_host];
    // Backwards, so that the first copy is written last.
    for (&host, v) in kept.iter().zip(values).rev() {
        out[host as usize] = v.clone();
    }
    out
}

/// `out[h]` = any `selected[i]` with `kept[i] = h`.
fn any_copy_to_host(kept: &[u32], n_host: usize, selected: &[bool]) -> Vec<bool> {
    let mut out = vec![false; n_host];
    for (&host, &s) in kept.iter().zip(selected) {
        out[host as usize] |= s;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 23 item 5: two identical copies of a triangle are one triangle, said so.
    #[test]
    fn hostile_05_a_triangle_given_twice_is_removed_and_reported() {
        let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
        let intake = MeshIntake::new(v.clone(), vec![[0, 1, 2], [1, 3, 2], [0, 1, 2]]).unwrap();
        assert_eq!((intake.mesh.n_faces(), intake.repeated_faces), (2, 1));
        assert!(intake.warning("mesh").unwrap().contains("removed 1 repeated face(s)"));
        // The strict constructor refuses it, naming both faces.
        let e = TriMesh::new(v, vec![[0, 1, 2], [1, 3, 2], [2, 0, 1]]).unwrap_err().to_string();
        assert!(e.contains("face 2 has the same three vertices as face 0"), "{e}");
    }

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
        assert!(MeshIntake::from_flat(&[0.0; 4], &[]).is_err());
    }

    #[test]
    fn splits_non_manifold_edges_and_vertices_and_maps_copies_back() {
        // A loose vertex 0; three triangles on the edge (1, 2) (the first two a consistently
        // oriented pair); a triangle touching the first only at vertex 3 (a bow tie).
        let mut v = vec![[9.0; 3]];
        v.extend([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]]);
        v.extend([[-1.0, 2.0, 0.0], [1.0, 2.0, 0.0]]);
        let f = vec![[1, 2, 3], [2, 1, 4], [1, 2, 5], [3, 6, 7]];
        let intake = MeshIntake::new(v, f).unwrap();
        assert_eq!((intake.non_manifold_edges_split, intake.non_manifold_vertices_split), (1, 3));
        assert_eq!((intake.dropped_faces, intake.dropped_vertices, intake.n_copies()), (0, 1, 3));
        // Host vertices 1..=7 kept in order, then the copies of 1 and 2 (face 2) and of 3 (face 3).
        assert_eq!(intake.kept, vec![1, 2, 3, 4, 5, 6, 7, 1, 2, 3]);
        assert_eq!(intake.mesh.faces(), &[[0, 1, 2], [1, 0, 3], [7, 8, 4], [9, 5, 6]]);
        // Values: the first copy's; selections: any copy's; amounts: the sum.
        let values: Vec<u32> = (10..20).collect();
        assert_eq!(intake.to_host(&values, 0), vec![0, 10, 11, 12, 13, 14, 15, 16]);
        let mut only_copies = vec![false; 10];
        only_copies[7] = true;
        only_copies[9] = true;
        assert_eq!(intake.to_host_any(&only_copies), vec![false, true, false, true, false, false, false, false]);
        assert_eq!(intake.to_host_sum(&[1.0; 10]), vec![0.0, 2.0, 2.0, 2.0, 1.0, 1.0, 1.0, 1.0]);
        assert_eq!(intake.from_host(&[0, 1, 2, 3, 4, 5, 6, 7]), vec![1, 2, 3, 4, 5, 6, 7, 1, 2, 3]);
        let w = intake.warning("partial mesh").unwrap();
        assert!(w.starts_with("partial mesh: left out 0 degenerate face(s) and 1 vertex(es)"), "{w}");
        assert!(w.contains("split 1 non-manifold edge(s) and 3 non-manifold vertex(es) (3 vertex copies"), "{w}");
        // The numbering on its own maps as the intake does.
        let host = intake.host_numbering();
        assert!(!host.is_identity());
        assert_eq!(host.values_to_host(&values, 0), intake.to_host(&values, 0));
        assert_eq!(host.region_to_host(&only_copies), intake.to_host_any(&only_copies));
    }

    #[test]
    fn the_identity_numbering_changes_nothing() {
        let id = HostNumbering::identity(5);
        assert!(id.is_identity());
        let values = [3.0, 1.0, 4.0, 1.0, 5.0];
        assert_eq!(id.values_to_host(&values, f64::NAN), values);
        let region = [true, false, false, true, true];
        assert_eq!(id.region_to_host(&region), region);
        // The same length but a permutation is not the identity; neither is a dropped vertex.
        assert!(!HostNumbering { n_host_vertices: 2, kept: vec![1, 0] }.is_identity());
        assert!(!HostNumbering { n_host_vertices: 3, kept: vec![0, 1] }.is_identity());
    }
}
