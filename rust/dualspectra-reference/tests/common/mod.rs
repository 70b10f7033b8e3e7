//! Test meshes (grouped by kind: closed, with boundary) and small helpers shared by the tests.
//! The procedural meshes are generated here rather than taken from the core, so that the tests
//! use only its documented toolkit (TriMesh, readers, geometry, operators, spectra).
#![allow(dead_code)]

use dualspectra::operators::SparseMatrix;
use dualspectra::TriMesh;
use std::collections::HashMap;
use std::path::PathBuf;

/// Unit icosphere, `level` midpoint subdivisions of an icosahedron projected on the sphere.
pub fn icosphere(level: u32) -> TriMesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let unit = |p: [f64; 3]| {
        let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        [p[0] / n, p[1] / n, p[2] / n]
    };
    let mut v: Vec<[f64; 3]> = [
        [-1.0, t, 0.0], [1.0, t, 0.0], [-1.0, -t, 0.0], [1.0, -t, 0.0],
        [0.0, -1.0, t], [0.0, 1.0, t], [0.0, -1.0, -t], [0.0, 1.0, -t],
        [t, 0.0, -1.0], [t, 0.0, 1.0], [-t, 0.0, -1.0], [-t, 0.0, 1.0],
    ]
    .map(unit)
    .to_vec();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
        [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
        [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
    ];
    for _ in 0..level {
        let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
        let mut next = Vec::with_capacity(4 * f.len());
        for t in &f {
            let mut m = [0u32; 3];
            for e in 0..3 {
                let (a, b) = (t[e], t[(e + 1) % 3]);
                m[e] = *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    let (p, q) = (v[a as usize], v[b as usize]);
                    v.push(unit([p[0] + q[0], p[1] + q[1], p[2] + q[2]]));
                    (v.len() - 1) as u32
                });
            }
            next.extend([[t[0], m[0], m[2]], [t[1], m[1], m[0]], [t[2], m[2], m[1]], [m[0], m[1], m[2]]]);
        }
        f = next;
    }
    TriMesh::new(v, f).unwrap()
}

/// The icosphere with a radial bump $r = 1 + 0.25 \sin 3x \sin 4y \cos 5z$: uneven, partly
/// obtuse triangles and curvature of both signs.
pub fn bumpy_sphere(level: u32) -> TriMesh {
    icosphere(level)
        .map_positions(|p| {
            let r = 1.0 + 0.25 * (3.0 * p[0]).sin() * (4.0 * p[1]).sin() * (5.0 * p[2]).cos();
            [r * p[0], r * p[1], r * p[2]]
        })
        .unwrap()
}

/// Unit disk in z = 0: `rings` rings of `6 r` vertices, each ring joined to the next by a
/// strip of triangles; the boundary is the outer ring.
pub fn disk(rings: u32) -> TriMesh {
    let mut v = vec![[0.0, 0.0, 0.0]];
    let mut start = vec![0u32];
    for r in 1..=rings {
        start.push(v.len() as u32);
        for j in 0..6 * r {
            let th = std::f64::consts::TAU * j as f64 / (6 * r) as f64;
            let rad = r as f64 / rings as f64;
            v.push([rad * th.cos(), rad * th.sin(), 0.0]);
        }
    }
    let mut f: Vec<[u32; 3]> = (0..6).map(|j| [0, 1 + j, 1 + (j + 1) % 6]).collect();
    for r in 1..rings {
        let (a0, na, b0, nb) = (start[r as usize], 6 * r, start[r as usize + 1], 6 * (r + 1));
        let (mut i, mut j) = (0u32, 0u32);
        while i < na || j < nb {
            // Advance on the ring whose next vertex comes first by angle.
            if j < nb && (i >= na || (j + 1) * na <= (i + 1) * nb) {
                f.push([a0 + i % na, b0 + j % nb, b0 + (j + 1) % nb]);
                j += 1;
            } else {
                f.push([a0 + i % na, b0 + j % nb, a0 + (i + 1) % na]);
                i += 1;
            }
        }
    }
    TriMesh::new(v, f).unwrap()
}

/// An `n x n` grid over the unit square with every interior vertex moved by up to 0.4 of the
/// spacing (a fixed pseudo-random sequence) and lifted to a wavy height: irregular triangles,
/// obtuse ones among them, with a boundary.
pub fn jittered_patch(n: u32) -> TriMesh {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut rand = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let h = 1.0 / n as f64;
    let mut v = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let inner = i > 0 && j > 0 && i < n && j < n;
            let (dx, dy) = if inner { (0.8 * h * rand(), 0.8 * h * rand()) } else { (0.0, 0.0) };
            let (x, y) = (i as f64 * h + dx, j as f64 * h + dy);
            v.push([x, y, 0.3 * (3.0 * x).sin() * (2.0 * y).cos()]);
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let mut f = Vec::new();
    for j in 0..n {
        for i in 0..n {
            f.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            f.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    TriMesh::new(v, f).unwrap()
}

/// A mesh of `tests/data/`.
pub fn data_mesh(name: &str) -> TriMesh {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/data").join(name);
    dualspectra::mesh::io::read_mesh(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Closed meshes, then meshes with a boundary, by name.
pub fn closed_meshes() -> Vec<(&'static str, TriMesh)> {
    vec![
        ("icosphere(3)", icosphere(3)),
        ("bumpy_sphere(3)", bumpy_sphere(3)),
        ("tetrahedron.off", data_mesh("tetrahedron.off")),
        ("square_pyramid.off", data_mesh("square_pyramid.off")),
        ("cube_quads.obj", data_mesh("cube_quads.obj")),
    ]
}

pub fn boundary_meshes() -> Vec<(&'static str, TriMesh)> {
    vec![("disk(8)", disk(8)), ("jittered_patch(16)", jittered_patch(16))]
}

pub fn all_meshes() -> Vec<(&'static str, TriMesh)> {
    let mut all = closed_meshes();
    all.extend(boundary_meshes());
    all
}

/// Vertices on a boundary edge (an edge of one face).
pub fn boundary_mask(mesh: &TriMesh) -> Vec<bool> {
    let mut count: HashMap<(u32, u32), u32> = HashMap::new();
    for t in mesh.faces() {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut mask = vec![false; mesh.n_vertices()];
    for ((a, b), c) in count {
        if c == 1 {
            mask[a as usize] = true;
            mask[b as usize] = true;
        }
    }
    mask
}

/// Euler characteristic $V - E + F$.
pub fn euler_characteristic(mesh: &TriMesh) -> i64 {
    let mut edges = std::collections::HashSet::new();
    for t in mesh.faces() {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            edges.insert((a.min(b), a.max(b)));
        }
    }
    mesh.n_vertices() as i64 - edges.len() as i64 + mesh.n_faces() as i64
}

/// The entries of a sparse matrix, duplicates summed.
pub fn entries(w: &SparseMatrix) -> HashMap<(usize, usize), f64> {
    let mut out = HashMap::new();
    for j in 0..w.ncols() {
        for (&i, &x) in w.row_idx_of_col_raw(j).iter().zip(w.val_of_col(j)) {
            *out.entry((i, j)).or_insert(0.0) += x;
        }
    }
    out
}

/// Triplets as entries, duplicates summed.
pub fn summed(triplets: &[(usize, usize, f64)]) -> HashMap<(usize, usize), f64> {
    let mut out = HashMap::new();
    for &(i, j, x) in triplets {
        *out.entry((i, j)).or_insert(0.0) += x;
    }
    out
}

/// The `k` smallest eigenvalues of $W\phi = \lambda M\phi$ by the core.
// Field assignment rather than struct update syntax: still compiles if `EigenParams` becomes
// `#[non_exhaustive]`.
#[allow(clippy::field_reassign_with_default)]
pub fn core_eigenvalues(w: &SparseMatrix, mass: &[f64], k: usize) -> Vec<f64> {
    let mut params = dualspectra::spectra::EigenParams::default();
    params.k = k;
    let s = dualspectra::spectra::generalized_eigen(w, mass, &params).unwrap();
    assert!(s.info.converged, "{:?}", s.info);
    s.values
}

/// Largest of `|a - b|` over the vector pair, divided by `scale`.
pub fn max_rel(a: &[f64], b: &[f64], scale: f64) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale
}

/// Largest magnitude of a vector.
pub fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, x| m.max(x.abs()))
}
