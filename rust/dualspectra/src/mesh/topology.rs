//! Mesh connectivity: edges, boundary, one-ring adjacency, connected components.

use super::TriMesh;
use std::collections::HashMap;

/// For each undirected edge `(a < b)`, the number of faces containing it.
pub fn edge_face_counts(mesh: &TriMesh) -> HashMap<(u32, u32), u32> {
    let mut m = HashMap::with_capacity(mesh.n_faces() * 3 / 2 + 1);
    for f in mesh.faces() {
        for e in 0..3 {
            let (a, b) = (f[e], f[(e + 1) % 3]);
            *m.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    m
}

/// `true` for every vertex on a boundary edge (an edge with one incident face).
pub fn boundary_vertex_mask(mesh: &TriMesh) -> Vec<bool> {
    let mut mask = vec![false; mesh.n_vertices()];
    for ((a, b), c) in edge_face_counts(mesh) {
        if c == 1 {
            mask[a as usize] = true;
            mask[b as usize] = true;
        }
    }
    mask
}

/// Sorted indices of the boundary vertices.
pub fn boundary_vertices(mesh: &TriMesh) -> Vec<u32> {
    boundary_vertex_mask(mesh).iter().enumerate().filter(|(_, &b)| b).map(|(i, _)| i as u32).collect()
}

/// One-ring neighbours of every vertex, sorted ascending (deterministic).
pub fn vertex_neighbors(mesh: &TriMesh) -> Vec<Vec<u32>> {
    let mut nb: Vec<Vec<u32>> = vec![Vec::new(); mesh.n_vertices()];
    for f in mesh.faces() {
        for e in 0..3 {
            let (a, b) = (f[e], f[(e + 1) % 3]);
            nb[a as usize].push(b);
            nb[b as usize].push(a);
        }
    }
    for l in &mut nb {
        l.sort_unstable();
        l.dedup();
    }
    nb
}

/// Union-find over vertex indices: path halving, the smaller root wins (so a class's root
/// is its smallest vertex and the result does not depend on the order of the joins).
struct VertexSets(Vec<u32>);

impl VertexSets {
    fn new(n: usize) -> Self {
        VertexSets((0..n as u32).collect())
    }

    fn root(&mut self, mut x: u32) -> u32 {
        let p = &mut self.0;
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }

    fn join(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.root(a), self.root(b));
        if ra != rb {
            self.0[ra.max(rb) as usize] = ra.min(rb);
        }
    }
}

/// Connected components (through faces): `(component id per vertex, number of components)`.
pub fn connected_components(mesh: &TriMesh) -> (Vec<u32>, usize) {
    let n = mesh.n_vertices();
    let mut sets = VertexSets::new(n);
    for f in mesh.faces() {
        for e in 1..3 {
            sets.join(f[0], f[e]);
        }
    }
    let mut id = vec![u32::MAX; n];
    let mut comp = vec![0u32; n];
    let mut count = 0;
    for v in 0..n {
        let r = sets.root(v as u32) as usize;
        if id[r] == u32::MAX {
            id[r] = count;
            count += 1;
        }
        comp[v] = id[r];
    }
    (comp, count as usize)
}

/// Length of each boundary curve (a connected set of boundary edges: a hole's rim, or the
/// outer rim of a cut), longest first; empty for a closed mesh. Boundary curves that touch at
/// a vertex count as one.
pub fn boundary_curve_lengths(mesh: &TriMesh) -> Vec<f64> {
    let mut edges: Vec<(u32, u32)> = edge_face_counts(mesh).into_iter().filter(|&(_, c)| c == 1).map(|(e, _)| e).collect();
    // A fixed order: the sums do not depend on the hash map's iteration order.
    edges.sort_unstable();
    let mut sets = VertexSets::new(mesh.n_vertices());
    for &(a, b) in &edges {
        sets.join(a, b);
    }
    let v = mesh.vertices();
    let mut length: HashMap<u32, f64> = HashMap::new();
    for &(a, b) in &edges {
        *length.entry(sets.root(a)).or_insert(0.0) += super::distance(v[a as usize], v[b as usize]);
    }
    let mut out: Vec<f64> = length.into_values().collect();
    out.sort_unstable_by(|a, b| b.total_cmp(a));
    out
}

/// Euler characteristic `chi = V - E + F`.
pub fn euler_characteristic(mesh: &TriMesh) -> i64 {
    mesh.n_vertices() as i64 - edge_face_counts(mesh).len() as i64 + mesh.n_faces() as i64
}

/// Shortest-path distances along the mesh edges (Dijkstra, Euclidean edge lengths) from
/// `source` to every vertex; `f64::INFINITY` where unreachable. An upper bound of the geodesic
/// distance (by a few percent on regular triangulations); enough to grow regions in order.
pub fn edge_graph_distances(mesh: &TriMesh, neighbors: &[Vec<u32>], source: usize) -> Vec<f64> {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    let p = mesh.vertices();
    let mut dist = vec![f64::INFINITY; mesh.n_vertices()];
    if source >= dist.len() {
        return dist;
    }
    dist[source] = 0.0;
    // f64 distances are >= 0, so their bit patterns order like the values.
    let mut heap = BinaryHeap::from([Reverse((0u64, source as u32))]);
    while let Some(Reverse((d_bits, i))) = heap.pop() {
        let d = f64::from_bits(d_bits);
        if d > dist[i as usize] {
            continue;
        }
        for &j in &neighbors[i as usize] {
            let nd = d + super::distance(p[i as usize], p[j as usize]);
            if nd < dist[j as usize] {
                dist[j as usize] = nd;
                heap.push(Reverse((nd.to_bits(), j)));
            }
        }
    }
    dist
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::grid;

    /// A 1 x 1 grid has one boundary curve of length 4; without the faces around an inner
    /// vertex it gets a second curve, the hole's rim; a closed sphere has none.
    #[test]
    fn boundary_curves_of_a_square_with_a_hole() {
        let g = grid(1.0, 1.0, 10, 10);
        let lengths = boundary_curve_lengths(&g);
        assert_eq!(lengths.len(), 1);
        assert!((lengths[0] - 4.0).abs() < 1e-12);
        let centre = g.vertices().iter().position(|p| (p[0] - 0.5).abs() < 1e-9 && (p[1] - 0.5).abs() < 1e-9).unwrap() as u32;
        let faces: Vec<[u32; 3]> = g.faces().iter().filter(|f| !f.contains(&centre)).copied().collect();
        let (holed, _) = TriMesh::new_dropping_isolated(g.vertices().to_vec(), faces).unwrap();
        let lengths = boundary_curve_lengths(&holed);
        assert_eq!(lengths.len(), 2);
        assert!((lengths[0] - 4.0).abs() < 1e-12);
        assert!(lengths[1] > 0.3 && lengths[1] < 0.8, "hole rim {}", lengths[1]);
        assert!(boundary_curve_lengths(&crate::mesh::generate::icosphere(1)).is_empty());
    }

    #[test]
    fn edge_graph_distances_bound_the_euclidean_and_are_exact_along_grid_lines() {
        // 1 x 1 grid with 10 x 10 cells: vertex (i, j) at (i/10, j/10); edges along the rows
        // make the distance along the bottom row exact.
        let mesh = grid(1.0, 1.0, 10, 10);
        let nb = vertex_neighbors(&mesh);
        let p = mesh.vertices();
        let source = (0..p.len()).find(|&i| p[i][0] == 0.0 && p[i][1] == 0.0).unwrap();
        let d = edge_graph_distances(&mesh, &nb, source);
        assert_eq!(d[source], 0.0);
        for (i, q) in p.iter().enumerate() {
            let e = (q[0].powi(2) + q[1].powi(2)).sqrt();
            assert!(d[i] >= e - 1e-12, "graph distance {} below the Euclidean {e}", d[i]);
            // A grid path never exceeds the L1 distance.
            assert!(d[i] <= q[0].abs() + q[1].abs() + 1e-12);
            if q[1] == 0.0 {
                assert!((d[i] - q[0]).abs() < 1e-12);
            }
        }
        // Symmetric: the distance back to the source is the same.
        let far = d.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).unwrap().0;
        let back = edge_graph_distances(&mesh, &nb, far);
        assert!((back[source] - d[far]).abs() < 1e-12);
    }

    #[test]
    fn edge_graph_distances_are_infinite_across_components() {
        let a = grid(1.0, 1.0, 2, 2);
        let (mut v, mut f) = a.clone().into_parts();
        let off = v.len() as u32;
        let (v2, f2) = a.into_parts();
        v.extend(v2.iter().map(|p| [p[0] + 5.0, p[1], p[2]]));
        f.extend(f2.iter().map(|t| [t[0] + off, t[1] + off, t[2] + off]));
        let mesh = TriMesh::new(v, f).unwrap();
        let d = edge_graph_distances(&mesh, &vertex_neighbors(&mesh), 0);
        assert!(d[..off as usize].iter().all(|x| x.is_finite()));
        assert!(d[off as usize..].iter().all(|x| x.is_infinite()));
    }
}
