//! Procedural meshes for tests, demos and benchmarks (no data files needed).

use super::TriMesh;
use std::collections::HashMap;

/// Unit icosphere: an icosahedron subdivided `level` times, vertices projected on the
/// unit sphere. `10 * 4^level + 2` vertices.
pub fn icosphere(level: u32) -> TriMesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<[f64; 3]> = vec![
        [-1.0, t, 0.0], [1.0, t, 0.0], [-1.0, -t, 0.0], [1.0, -t, 0.0],
        [0.0, -1.0, t], [0.0, 1.0, t], [0.0, -1.0, -t], [0.0, 1.0, -t],
        [t, 0.0, -1.0], [t, 0.0, 1.0], [-t, 0.0, -1.0], [-t, 0.0, 1.0],
    ];
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
        [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
        [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
        [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
    ];
    let normalize = |p: [f64; 3]| {
        let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        [p[0] / n, p[1] / n, p[2] / n]
    };
    for p in &mut v {
        *p = normalize(*p);
    }
    for _ in 0..level {
        let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
        let mut nf = Vec::with_capacity(f.len() * 4);
        for tri in &f {
            let mut m = [0u32; 3];
            for e in 0..3 {
                let (a, b) = (tri[e], tri[(e + 1) % 3]);
                let key = (a.min(b), a.max(b));
                m[e] = *mid.entry(key).or_insert_with(|| {
                    let (pa, pb) = (v[a as usize], v[b as usize]);
                    v.push(normalize([(pa[0] + pb[0]) / 2.0, (pa[1] + pb[1]) / 2.0, (pa[2] + pb[2]) / 2.0]));
                    (v.len() - 1) as u32
                });
            }
            nf.push([tri[0], m[0], m[2]]);
            nf.push([tri[1], m[1], m[0]]);
            nf.push([tri[2], m[2], m[1]]);
            nf.push([m[0], m[1], m[2]]);
        }
        f = nf;
    }
    TriMesh::new(v, f).expect("icosphere is a valid mesh")
}

/// Flat disk of the given radius in the z = 0 plane, `rings` concentric rings of
/// vertices (ring r has 6 r vertices), boundary on the outer ring.
pub fn disk(radius: f64, rings: u32) -> TriMesh {
    assert!(rings >= 1);
    let mut v = vec![[0.0, 0.0, 0.0]];
    let mut ring_start = vec![0u32];
    for r in 1..=rings {
        ring_start.push(v.len() as u32);
        let n = 6 * r;
        for j in 0..n {
            let th = 2.0 * std::f64::consts::PI * j as f64 / n as f64;
            let rad = radius * r as f64 / rings as f64;
            v.push([rad * th.cos(), rad * th.sin(), 0.0]);
        }
    }
    let mut f = Vec::new();
    // Ring 0 -> 1: a fan.
    for j in 0..6u32 {
        f.push([0, 1 + j, 1 + (j + 1) % 6]);
    }
    for r in 1..rings {
        let (a0, na) = (ring_start[r as usize], 6 * r);
        let (b0, nb) = (ring_start[r as usize + 1], 6 * (r + 1));
        // Walk both rings by angle, emitting triangles (merge of two sorted angle lists).
        let (mut i, mut j) = (0u32, 0u32);
        while i < na || j < nb {
            let ai = a0 + i % na;
            let bj = b0 + j % nb;
            let ta = (i + 1) as f64 / na as f64;
            let tb = (j + 1) as f64 / nb as f64;
            if j < nb && (i >= na || tb <= ta) {
                f.push([ai, bj, b0 + (j + 1) % nb]);
                j += 1;
            } else {
                f.push([ai, bj, a0 + (i + 1) % na]);
                i += 1;
            }
        }
    }
    TriMesh::new(v, f).expect("disk is a valid mesh")
}

/// Regular grid over `[0, w] x [0, h]` in z = 0 with `nx x ny` quads, each split in two.
pub fn grid(w: f64, h: f64, nx: u32, ny: u32) -> TriMesh {
    let mut v = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            v.push([w * i as f64 / nx as f64, h * j as f64 / ny as f64, 0.0]);
        }
    }
    let id = |i: u32, j: u32| j * (nx + 1) + i;
    let mut f = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            f.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            f.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    TriMesh::new(v, f).expect("grid is a valid mesh")
}
