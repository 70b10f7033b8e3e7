//! Splitting non-manifold edges and vertices: raw scans become manifold meshes with
//! boundary, by adding vertex copies and changing no position and no face.
//!
//! The rule is the standard "cut the non-manifold edges, then split every vertex into its
//! face fans": MeshLab's filter *Repair non Manifold Vertices by splitting* (vcglib
//! `tri::Clean::SplitNonManifoldVertex`, which callers loop until nothing changes), libigl's
//! `split_nonmanifold` (which also cuts edges between inconsistently oriented faces; here
//! those stay joined). Made deterministic and done in one pass:
//!
//! 1. **Edges.** Two faces are *glued* across the undirected edge `{a, b}` when exactly
//!    two faces contain it. When more do (a non-manifold edge, counted in
//!    [`NonManifoldSplit::edges_split`]), the first face (in face order) using `a -> b` is
//!    glued to the first using `b -> a` (`a < b`), a consistently oriented pair, if there
//!    is one; every other face of the edge is glued to none. If that pair would still leave
//!    three faces on one new edge (the pair links two sheets that also meet around both
//!    ends), the edge is cut completely instead.
//! 2. **Vertices.** The corners at a vertex fall into *fans*: classes of corners joined
//!    through glued edges that contain the vertex (a union-find over the `3m` corners, no
//!    iteration). The fan holding the lowest face keeps the vertex; each other fan gets a new
//!    vertex, a copy of it appended after the input vertices in the order its fan's first
//!    face comes. Vertices given at least one copy are counted in
//!    [`NonManifoldSplit::vertices_split`].
//!
//! The result has every edge in one or two faces and the faces at every vertex forming one
//! fan (a disk or a half-disk): what [`TriMesh::new`](super::TriMesh::new) checks. Each
//! vertex's link (its neighbours joined by its faces) keeps degree at most two after step 1,
//! so its fans are paths and cycles, and a fully cut edge ends at most two faces of a fan.
//! A manifold input is returned unchanged (zero counts, no copy). Time `O(m log d)` for `m`
//! faces and vertex degree `d`; memory 24 bytes per face for the edges and 12 for the corners,
//! besides the output.
//!
//! Faces that repeat a vertex are left as they are (and glued to nothing): the mesh's own
//! validation reports them. Indices must be below the vertex count (else nothing is split).

use crate::error::MeshError;

/// A mesh after [`split_non_manifold`]: the input vertices then the copies, the faces in
/// the input's order (same count), and what was split.
#[derive(Debug, Clone, PartialEq)]
pub struct NonManifoldSplit {
    /// Positions: the `n` input vertices, then one per copy (its original's position).
    pub vertices: Vec<[f64; 3]>,
    /// The input faces, in order, with corners of split fans renumbered to copies.
    pub faces: Vec<[u32; 3]>,
    /// `origin[v]`: the input vertex that vertex `v` is (the identity for `v < n`).
    pub origin: Vec<u32>,
    /// Edges that were in more than two faces.
    pub edges_split: usize,
    /// Input vertices given at least one copy (`origin.len() - n` copies in all).
    pub vertices_split: usize,
}

/// Split the non-manifold edges and vertices of `(vertices, faces)` (see the module doc).
pub fn split_non_manifold(vertices: &[[f64; 3]], faces: &[[u32; 3]]) -> NonManifoldSplit {
    let n = vertices.len();
    let mut faces = faces.to_vec();
    let split = split_faces(n, &mut faces);
    let mut out = Vec::with_capacity(n + split.copies.len());
    out.extend_from_slice(vertices);
    out.extend(split.copies.iter().map(|&o| vertices[o as usize]));
    let origin = (0..n as u32).chain(split.copies.iter().copied()).collect();
    NonManifoldSplit {
        vertices: out,
        faces,
        origin,
        edges_split: split.edges_split,
        vertices_split: split.vertices_split,
    }
}

/// What [`split_faces`] did: `copies[i]` is the input vertex that new vertex `n + i` copies.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(super) struct FaceSplit {
    pub copies: Vec<u32>,
    pub edges_split: usize,
    pub vertices_split: usize,
    /// Whether the split ran, so that the faces are manifold (`false` for indices out of
    /// range or more than [`MAX_FACES`] faces: then nothing was changed).
    pub manifold: bool,
}

/// [`split_non_manifold`] in place on the faces of a mesh of `n_vertices` vertices: the
/// corners of split fans are renumbered to `n_vertices + i`, a copy of `copies[i]`. Copies
/// neither positions nor faces (for the file reader).
pub(super) fn split_faces(n_vertices: usize, faces: &mut [[u32; 3]]) -> FaceSplit {
    let n = n_vertices;
    let fits = faces.len() <= MAX_FACES
        && n + 3 * faces.len() <= u32::MAX as usize
        && faces.iter().flatten().all(|&i| (i as usize) < n);
    if !fits {
        return FaceSplit::default();
    }
    let edges = EdgeRuns::new(n, faces);
    // Non-manifold edges (by their start in `edges.keys`) cut completely, sorted.
    let mut cut: Vec<usize> = Vec::new();
    loop {
        let mut fans = Fans::new(faces.len());
        let mut split_edges = Vec::new();
        for run in edges.runs() {
            match run.keys {
                [_] => {}
                &[x, y] => fans.glue(x, y),
                many => {
                    split_edges.push(run.start..run.start + many.len());
                    if cut.binary_search(&run.start).is_err() {
                        let a_to_b = many.iter().find(|&&k| forward(k));
                        let b_to_a = many.iter().find(|&&k| !forward(k));
                        if let (Some(&x), Some(&y)) = (a_to_b, b_to_a) {
                            fans.glue(x, y);
                        }
                    }
                }
            }
        }
        let mut split = fans.label(n, faces);
        split.edges_split = split_edges.len();
        let crowded: Vec<usize> = split_edges
            .into_iter()
            .filter(|r| crowded_edge(faces, &edges.keys[r.clone()]))
            .map(|r| r.start)
            .collect();
        if crowded.iter().all(|s| cut.binary_search(s).is_ok()) {
            split.manifold = true;
            return split;
        }
        // Undo the renumbering and cut those edges completely.
        for f in faces.iter_mut().filter(|f| !repeats_vertex(f)) {
            *f = f.map(|i| if (i as usize) < n { i } else { split.copies[i as usize - n] });
        }
        cut.extend(crowded);
        cut.sort_unstable();
        cut.dedup();
    }
}

/// Whether three of the half-edges `keys` (one edge of the input) lie on one edge of the
/// renumbered `faces`.
fn crowded_edge(faces: &[[u32; 3]], keys: &[u64]) -> bool {
    let mut ends: Vec<(u32, u32)> = keys
        .iter()
        .map(|&k| {
            let (p, q) = (vertex(faces, corner(k)), vertex(faces, next(corner(k))));
            (p.min(q), p.max(q))
        })
        .collect();
    ends.sort_unstable();
    ends.windows(3).any(|w| w[0] == w[2])
}

/// Check that every edge is in at most two faces and the faces at every vertex form one
/// fan, for [`TriMesh::new`](super::TriMesh::new) (faces already checked: indices in range,
/// no repeated vertex). Reports the smallest offending edge `(a, b)`, then the smallest
/// offending vertex. `O(m log d)` time; 36 bytes per face and 4 per vertex. Meshes of more
/// than [`MAX_FACES`] faces are checked for edges only.
pub(super) fn check_manifold(n: usize, faces: &[[u32; 3]]) -> Result<(), MeshError> {
    if faces.len() > MAX_FACES {
        return check_edges_only(n, faces);
    }
    let edges = EdgeRuns::new(n, faces);
    let mut fans = Fans::new(faces.len());
    for run in edges.runs() {
        match run.keys {
            [_] => {}
            &[x, y] => fans.glue(x, y),
            many => return Err(MeshError::NonManifoldEdge { a: run.a, b: run.b, count: many.len() }),
        }
    }
    drop(edges);
    match fans.first_with_several(n, faces) {
        Some((vertex, fans)) => Err(MeshError::NonManifoldVertex { vertex, fans }),
        None => Ok(()),
    }
}

/// The edge check of [`check_manifold`] for meshes of more than [`MAX_FACES`] faces.
fn check_edges_only(n: usize, faces: &[[u32; 3]]) -> Result<(), MeshError> {
    let edge = |f: &[u32; 3], e: usize| (f[e].min(f[(e + 1) % 3]), f[e].max(f[(e + 1) % 3]));
    let mut start = vec![0usize; n + 1];
    faces.iter().for_each(|f| (0..3).for_each(|e| start[edge(f, e).0 as usize] += 1));
    for a in 1..=n {
        start[a] += start[a - 1];
    }
    let mut other = vec![0u32; 3 * faces.len()];
    for f in faces {
        for e in 0..3 {
            let (a, b) = edge(f, e);
            start[a as usize] -= 1;
            other[start[a as usize]] = b;
        }
    }
    for a in 0..n {
        let bucket = &mut other[start[a]..start[a + 1]];
        bucket.sort_unstable();
        if let Some(run) = bucket.chunk_by(|x, y| x == y).find(|run| run.len() > 2) {
            return Err(MeshError::NonManifoldEdge { a: a as u32, b: run[0], count: run.len() });
        }
    }
    Ok(())
}

/// Most faces handled: corner numbers `3 f + k` fit in 31 bits.
const MAX_FACES: usize = (i32::MAX / 3) as usize;

/// Corner `c = 3 f + k` is position `k` of face `f`; its half-edge goes to the next corner.
fn next(c: u32) -> u32 {
    if c % 3 == 2 {
        c - 2
    } else {
        c + 1
    }
}

fn vertex(faces: &[[u32; 3]], c: u32) -> u32 {
    faces[c as usize / 3][c as usize % 3]
}

fn repeats_vertex(f: &[u32; 3]) -> bool {
    f[0] == f[1] || f[1] == f[2] || f[0] == f[2]
}

/// Half-edges grouped by undirected edge `{a, b}`, `a < b`: bucket `a` holds the keys
/// `b << 32 | corner << 1 | forward` (`forward`: the half-edge goes `a -> b`), sorted, so
/// each edge is a run in face order. Faces that repeat a vertex are left out.
struct EdgeRuns {
    /// Bucket `a` is `keys[start[a]..start[a + 1]]`.
    start: Vec<u32>,
    keys: Vec<u64>,
}

/// One undirected edge `{a, b}` (`a < b`): its half-edges' keys, from `start` in
/// [`EdgeRuns::keys`].
struct Run<'a> {
    a: u32,
    b: u32,
    start: usize,
    keys: &'a [u64],
}

/// The corner of a half-edge key, and whether the half-edge goes from the smaller end.
fn corner(key: u64) -> u32 {
    (key as u32) >> 1
}

fn forward(key: u64) -> bool {
    key & 1 == 1
}

impl EdgeRuns {
    /// For at most [`MAX_FACES`] faces with indices below `n`.
    fn new(n: usize, faces: &[[u32; 3]]) -> Self {
        // Counting sort by `a`: counts, inclusive prefix sums, then filled downwards.
        let mut start = vec![0u32; n + 1];
        for f in faces.iter().filter(|f| !repeats_vertex(f)) {
            for k in 0..3 {
                start[f[k].min(f[(k + 1) % 3]) as usize] += 1;
            }
        }
        for a in 1..=n {
            start[a] += start[a - 1];
        }
        let mut keys = vec![0u64; start[n] as usize];
        for (fi, f) in faces.iter().enumerate() {
            if repeats_vertex(f) {
                continue;
            }
            for k in 0..3 {
                let (p, q) = (f[k], f[(k + 1) % 3]);
                let a = p.min(q) as usize;
                start[a] -= 1;
                keys[start[a] as usize] = (p.max(q) as u64) << 32 | ((3 * fi + k) as u64) << 1 | (p < q) as u64;
            }
        }
        for a in 0..n {
            keys[start[a] as usize..start[a + 1] as usize].sort_unstable();
        }
        EdgeRuns { start, keys }
    }

    /// The edges, by `a` then `b`.
    fn runs(&self) -> impl Iterator<Item = Run<'_>> + '_ {
        (0..self.start.len() - 1).flat_map(move |a| {
            let from = self.start[a] as usize;
            let bucket = &self.keys[from..self.start[a + 1] as usize];
            let mut at = from;
            bucket.chunk_by(|x, y| x >> 32 == y >> 32).map(move |keys| {
                at += keys.len();
                Run { a: a as u32, b: (keys[0] >> 32) as u32, start: at - keys.len(), keys }
            })
        })
    }
}

/// Corners joined into fans: a union-find whose root is the smallest corner of its class,
/// every parent an earlier corner.
struct Fans {
    parent: Vec<u32>,
}

impl Fans {
    fn new(n_faces: usize) -> Self {
        Fans { parent: (0..3 * n_faces as u32).collect() }
    }

    fn find(&mut self, mut c: u32) -> u32 {
        // Path halving; most corners are a root or a root's child.
        loop {
            let up = self.parent[c as usize];
            let top = self.parent[up as usize];
            if up == top {
                return up;
            }
            self.parent[c as usize] = top;
            c = top;
        }
    }

    fn union(&mut self, c: u32, d: u32) {
        let (r, s) = (self.find(c), self.find(d));
        self.parent[r.max(s) as usize] = r.min(s);
    }

    /// Glue the faces of half-edges `x` and `y` (keys of one undirected edge) across it:
    /// their corners at each end join.
    fn glue(&mut self, x: u64, y: u64) {
        let (c, d) = (corner(x), corner(y));
        if forward(x) == forward(y) {
            self.union(c, d);
            self.union(next(c), next(d));
        } else {
            self.union(c, next(d));
            self.union(next(c), d);
        }
    }

    /// Give each fan its vertex: the first fan of a vertex (in corner order) keeps it, each
    /// other gets a copy numbered from `n` on. Faces that repeat a vertex are left as they are.
    fn label(&self, n: usize, faces: &mut [[u32; 3]]) -> FaceSplit {
        // 0: not seen, 1: kept by its first fan, 2: copied too.
        let mut state = vec![0u8; n];
        let mut split = FaceSplit::default();
        for fi in 0..faces.len() {
            if repeats_vertex(&faces[fi]) {
                continue;
            }
            for k in 0..3 {
                let c = 3 * fi + k;
                let up = self.parent[c];
                if up as usize != c {
                    // Parents are earlier corners, so this one is already labelled.
                    faces[fi][k] = vertex(faces, up);
                    continue;
                }
                let v = faces[fi][k];
                match state[v as usize] {
                    0 => state[v as usize] = 1,
                    s => {
                        if s == 1 {
                            state[v as usize] = 2;
                            split.vertices_split += 1;
                        }
                        faces[fi][k] = (n + split.copies.len()) as u32;
                        split.copies.push(v);
                    }
                }
            }
        }
        split
    }

    /// The smallest vertex with more than one fan, and its number of fans.
    fn first_with_several(&self, n: usize, faces: &[[u32; 3]]) -> Option<(usize, usize)> {
        let mut count = vec![0u32; n];
        let mut several = false;
        for c in 0..3 * faces.len() as u32 {
            // A root is its own parent (and the first corner of its fan).
            if self.parent[c as usize] == c {
                let v = vertex(faces, c) as usize;
                count[v] += 1;
                several |= count[v] > 1;
            }
        }
        if !several {
            return None;
        }
        count.iter().position(|&k| k > 1).map(|v| (v, count[v] as usize))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::{disk, icosphere};
    use crate::mesh::topology::connected_components;
    use crate::mesh::TriMesh;

    /// The laws of every split: same faces through `origin`, copies at their original's
    /// position, and a mesh [`TriMesh::new`] accepts (when the input has no other defect).
    fn check(v: &[[f64; 3]], f: &[[u32; 3]]) -> (NonManifoldSplit, TriMesh) {
        let s = split_non_manifold(v, f);
        assert_eq!(s.faces.len(), f.len());
        assert_eq!(s.origin.len(), s.vertices.len());
        assert!(s.origin[..v.len()].iter().enumerate().all(|(i, &o)| o as usize == i));
        let back: Vec<[u32; 3]> = s.faces.iter().map(|t| t.map(|i| s.origin[i as usize])).collect();
        assert_eq!(back, f);
        assert!(s.origin.iter().enumerate().all(|(i, &o)| s.vertices[i] == v[o as usize]));
        let copied = s.origin[v.len()..].iter().collect::<std::collections::BTreeSet<_>>().len();
        assert_eq!(copied, s.vertices_split);
        let mesh = TriMesh::new(s.vertices.clone(), s.faces.clone()).unwrap_or_else(|e| panic!("{e}: {s:?}"));
        (s, mesh)
    }

    /// Six points around the edge (0, 1): 2, 3, 4, 5 off it in four directions.
    fn star() -> Vec<[f64; 3]> {
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 1.0, 0.0], [0.5, -1.0, 0.0], [0.5, 0.0, 1.0], [0.5, 0.0, -1.0]]
    }

    #[test]
    fn an_edge_of_four_faces_keeps_one_oriented_pair_and_cuts_off_the_others() {
        let f = [[0, 1, 2], [1, 0, 3], [0, 1, 4], [1, 0, 5]];
        assert!(TriMesh::new(star(), f.to_vec()).is_err());
        let (s, mesh) = check(&star(), &f);
        assert_eq!((s.edges_split, s.vertices_split), (1, 2));
        // Faces 0 and 1 (0 -> 1 and 1 -> 0) stay glued; faces 2 and 3 get copies of 0 and 1.
        assert_eq!(s.faces, vec![[0, 1, 2], [1, 0, 3], [6, 7, 4], [8, 9, 5]]);
        assert_eq!(s.origin, vec![0, 1, 2, 3, 4, 5, 0, 1, 1, 0]);
        assert_eq!(connected_components(&mesh).1, 3);
    }

    #[test]
    fn an_edge_of_faces_in_one_orientation_is_cut_completely() {
        let f = [[0, 1, 2], [0, 1, 3], [0, 1, 4]];
        let (s, mesh) = check(&star()[..5], &f);
        assert_eq!((s.edges_split, s.vertices_split, s.vertices.len()), (1, 2, 9));
        assert_eq!(connected_components(&mesh).1, 3);
    }

    #[test]
    fn a_vertex_joining_two_fans_gets_one_copy() {
        // Bow tie: two triangles sharing vertex 0 only.
        let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [-1.0, -1.0, 0.0]];
        let f = [[0, 1, 2], [0, 3, 4]];
        assert_eq!(TriMesh::new(v.to_vec(), f.to_vec()), Err(MeshError::NonManifoldVertex { vertex: 0, fans: 2 }));
        let (s, _) = check(&v, &f);
        assert_eq!((s.edges_split, s.vertices_split), (0, 1));
        assert_eq!(s.faces, vec![[0, 1, 2], [5, 3, 4]]);
        assert_eq!(s.origin, vec![0, 1, 2, 3, 4, 0]);
        // Two closed fans: tetrahedra sharing their vertex 0.
        let mut v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        v.extend([[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]);
        let tet = |b: u32, c: u32, d: u32| [[0, c, b], [0, b, d], [0, d, c], [b, c, d]];
        let f: Vec<[u32; 3]> = tet(1, 2, 3).into_iter().chain(tet(4, 5, 6)).collect();
        assert!(matches!(TriMesh::new(v.clone(), f.clone()), Err(MeshError::NonManifoldVertex { vertex: 0, fans: 2 })));
        let (s, mesh) = check(&v, &f);
        assert_eq!((s.edges_split, s.vertices_split, s.origin[7..].to_vec()), (0, 1, vec![0]));
        assert_eq!(connected_components(&mesh).1, 2);
    }

    #[test]
    fn two_closed_sheets_on_one_edge_come_apart_whatever_the_face_order() {
        // Tetrahedra (0, 1, 2, 3) and (0, 1, 4, 5) share the edge (0, 1). In this order the
        // first 0 -> 1 face is of one and the first 1 -> 0 face of the other: the pair would
        // leave four faces on one edge, so the edge is cut completely.
        let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 1.0, 0.2], [0.5, 0.5, 1.0], [0.5, -1.0, 0.2], [0.5, -0.5, -1.0]];
        let tet = |c: u32, d: u32| [[0, c, 1], [0, 1, d], [0, d, c], [1, c, d]];
        let (t1, t2) = (tet(2, 3), tet(4, 5));
        let interleaved = vec![t1[1], t2[0], t1[0], t2[1], t1[2], t1[3], t2[2], t2[3]];
        let grouped: Vec<[u32; 3]> = t1.into_iter().chain(t2).collect();
        for f in [interleaved, grouped] {
            let (s, mesh) = check(&v, &f);
            assert_eq!((s.edges_split, s.vertices_split, s.vertices.len()), (1, 2, 8));
            assert_eq!(connected_components(&mesh).1, 2);
        }
    }

    #[test]
    fn a_manifold_mesh_is_returned_unchanged() {
        for m in [icosphere(2), disk(1.0, 4)] {
            let s = split_non_manifold(m.vertices(), m.faces());
            assert_eq!((s.edges_split, s.vertices_split), (0, 0));
            assert_eq!((s.vertices.as_slice(), s.faces.as_slice()), (m.vertices(), m.faces()));
            assert_eq!(s.origin, (0..m.n_vertices() as u32).collect::<Vec<_>>());
        }
    }

    #[test]
    fn random_triangles_on_a_sphere_always_split_into_a_valid_mesh() {
        // Any three distinct points of a sphere make a proper triangle, so the only defects
        // of these soups are non-manifold edges and vertices (repeated triangles are left
        // out, as the readers and the intake remove them before the split).
        let sphere = icosphere(1);
        let v = sphere.vertices();
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut rand = |n: usize| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % n as u64) as u32
        };
        let (mut edges, mut vertices, mut checked) = (0, 0, 0);
        for case in 0..200 {
            let mut f: Vec<[u32; 3]> = sphere.faces().iter().filter(|_| rand(4) > 0).copied().collect();
            for _ in 0..1 + case % 20 {
                let t = [rand(v.len()), rand(v.len()), rand(v.len())];
                let same_set = |a: &[u32; 3]| {
                    let (mut x, mut y) = (*a, t);
                    x.sort_unstable();
                    y.sort_unstable();
                    x == y
                };
                if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] && !f.iter().any(same_set) {
                    f.push(t);
                }
            }
            let used: std::collections::BTreeSet<u32> = f.iter().flatten().copied().collect();
            let (vv, ff) = if used.len() == v.len() { (v.to_vec(), f) } else { continue };
            let (s, _) = check(&vv, &ff);
            (edges, vertices, checked) = (edges + s.edges_split, vertices + s.vertices_split, checked + 1);
        }
        assert!(checked > 150 && edges > 100 && vertices > 500, "{checked} soups, {edges} edges and {vertices} vertices split");
    }

    #[test]
    fn out_of_range_indices_and_repeated_vertices_are_left_to_validation() {
        let v = star();
        let s = split_non_manifold(&v, &[[0, 1, 9], [0, 1, 2], [0, 1, 3], [0, 1, 4]]);
        assert_eq!((s.edges_split, s.vertices.len()), (0, 6));
        let s = split_non_manifold(&v, &[[0, 0, 1], [0, 1, 2], [0, 1, 3], [0, 1, 4]]);
        assert_eq!(s.faces[0], [0, 0, 1]);
        assert_eq!(s.edges_split, 1);
        assert!(matches!(TriMesh::new(s.vertices, s.faces), Err(MeshError::RepeatedVertexInFace { face: 0 })));
    }
}
