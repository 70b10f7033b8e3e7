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

/// Connected components (through faces): `(component id per vertex, number of components)`.
pub fn connected_components(mesh: &TriMesh) -> (Vec<u32>, usize) {
    let n = mesh.n_vertices();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn find(p: &mut [u32], mut x: u32) -> u32 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    for f in mesh.faces() {
        for e in 1..3 {
            let (ra, rb) = (find(&mut parent, f[0]), find(&mut parent, f[e]));
            if ra != rb {
                parent[ra.max(rb) as usize] = ra.min(rb);
            }
        }
    }
    let mut id = vec![u32::MAX; n];
    let mut comp = vec![0u32; n];
    let mut count = 0;
    for v in 0..n {
        let r = find(&mut parent, v as u32) as usize;
        if id[r] == u32::MAX {
            id[r] = count;
            count += 1;
        }
        comp[v] = id[r];
    }
    (comp, count as usize)
}

/// Euler characteristic `chi = V - E + F`.
pub fn euler_characteristic(mesh: &TriMesh) -> i64 {
    mesh.n_vertices() as i64 - edge_face_counts(mesh).len() as i64 + mesh.n_faces() as i64
}
