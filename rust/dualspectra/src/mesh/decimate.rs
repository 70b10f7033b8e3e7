//! Quadric edge-collapse decimation of a [`TriMesh`] to a target fraction of its vertices.
//!
//! docs/algorithm.md, "Optimisation": the full shape is decimated (quadric edge collapse) to
//! 50% of its vertices before the optimisation, and the result is carried back to the
//! full mesh by nearest neighbours (`mesh::nearest`).
//!
//! The collapse is meshoptimizer's `meshopt_simplify` (Garland and Heckbert 1997,
//! "Surface simplification using quadric error metrics", with meshoptimizer's
//! topology rules), through the `meshopt` crate. It collapses edges onto one of their
//! endpoints, so the decimated vertices are a *subset* of the original ones at their
//! original (f64) positions: [`Decimated::original_vertex`] maps each kept vertex to its
//! index in the input, and a value transferred back is exact at kept vertices.
//!
//! Boundary vertices are locked (`SimplifyOptions::LockBorder`): the boundary of the full
//! shape is kept vertex for vertex. meshoptimizer works on `f32` positions; it is given each
//! coordinate's offset from the bounding box's lowest corner rounded to a grid of 4096 cells
//! per diagonal (finer ones where that opens a hole, [`SNAP_CELLS`]), so the collapse order
//! (a long greedy chain: a full shape of 10^4 vertices goes to 10^3) does not hinge on the
//! last bits of the coordinates: a 1e-9
//! relative jitter moves a coordinate to another cell with probability ~1e-5, where
//! unsnapped `f32` rounding changed in ~1% of the coordinates and with it the kept vertices
//! of every run (docs/benchmarks/options.md, "Snapped decimation"). Single-precision input
//! (a host's f32 positions) is still a larger move and can change the result. The kept
//! vertices keep their exact input positions.
//!
//! meshoptimizer can create an edge shared by three faces; the vertices of such faces and
//! their input one-rings are then locked and the simplification rerun. The output is checked by [`TriMesh::new`]:
//! degenerate faces (at `f64`) and repeated
//! faces are dropped, and a candidate with a non-manifold edge is rejected; the function
//! tries a few target counts and returns the valid result nearest the target, or
//! [`Error::Numerical`] if none is valid. Deterministic: same input, same output.

use super::TriMesh;
use crate::error::{Error, MeshError, Result};
use meshopt::SimplifyOptions;
use std::collections::HashSet;

/// A decimated mesh and where its vertices came from.
#[derive(Debug, Clone)]
pub struct Decimated {
    /// The decimated mesh (valid, edge-manifold, same boundary as the input).
    pub mesh: TriMesh,
    /// `original_vertex[i]` is the index in the input mesh of decimated vertex `i`
    /// (increasing, since the kept vertices keep their input order).
    pub original_vertex: Vec<u32>,
}

/// Decimate `mesh` to about `target_fraction * n_vertices` vertices (at least 4).
///
/// `target_fraction` must be in `(0, 1]`; `1` returns the input unchanged with the
/// identity map. The count reached is within about 1% of the target unless the locked
/// boundary or meshoptimizer's topology rules prevent it (then the nearest count reached).
///
/// Errors: [`Error::InvalidArgument`] for a bad fraction, [`Error::Numerical`] if every
/// candidate result failed validation (the message names the reason).
pub fn decimate(mesh: &TriMesh, target_fraction: f64) -> Result<Decimated> {
    if !(target_fraction > 0.0 && target_fraction <= 1.0) {
        return Err(Error::InvalidArgument(format!(
            "decimation fraction must be in (0, 1], got {target_fraction}"
        )));
    }
    let n = mesh.n_vertices();
    if target_fraction == 1.0 {
        return Ok(Decimated {
            mesh: mesh.clone(),
            original_vertex: (0..n as u32).collect(),
        });
    }
    // Snapping can make three collinear vertices look like a triangle to meshoptimizer (flat
    // synthetic meshes); its collapses may then leave a face that is degenerate at f64 and
    // dropped: a hole. Such a result is replaced by one on a finer grid, and in the end by
    // the unsnapped one. Where two vertices share a position (which meshoptimizer welds,
    // snapped or not: FAUST's remeshed shapes have a few) holes can appear either way, and
    // the first grid's result is kept.
    let input_boundary = super::topology::boundary_vertices(mesh).len();
    for cells in SNAP_CELLS {
        let positions = meshopt_positions(mesh, Some(cells));
        let welds = positions.len() - positions.iter().map(|p| p.map(f32::to_bits)).collect::<HashSet<_>>().len();
        match decimate_positions(mesh, &positions, target_fraction) {
            Ok(d) if welds > 0 || super::topology::boundary_vertices(&d.mesh).len() == input_boundary => return Ok(d),
            _ => {}
        }
    }
    decimate_positions(mesh, &meshopt_positions(mesh, None), target_fraction)
}

/// [`decimate`] with the positions meshoptimizer sees.
fn decimate_positions(mesh: &TriMesh, positions: &[[f32; 3]], target_fraction: f64) -> Result<Decimated> {
    let n = mesh.n_vertices();
    let target_vertices = ((target_fraction * n as f64).round() as usize).max(4);
    let indices: Vec<u32> = mesh.faces().iter().flatten().copied().collect();

    // Faces scale with vertices (F ~ 2V on a closed surface): start from the same fraction
    // of faces and correct the face target by the vertex ratio reached.
    let mut target_faces = (target_fraction * mesh.n_faces() as f64).round().max(2.0);
    let mut best: Option<(usize, Decimated)> = None;
    let mut last_error = String::new();
    let mut tried = HashSet::new();
    for _ in 0..8 {
        let target_index_count = 3 * (target_faces as usize).max(2);
        if !tried.insert(target_index_count) {
            break;
        }
        let out = simplify_manifold(mesh, &indices, positions, target_index_count);
        let reached = match assemble(mesh, &out) {
            Ok(d) => {
                let reached = d.mesh.n_vertices();
                let miss = reached.abs_diff(target_vertices);
                if best.as_ref().is_none_or(|(b, _)| miss < *b) {
                    best = Some((miss, d));
                }
                reached
            }
            Err(e) => {
                last_error = e.to_string();
                // Count the vertices anyway to steer the next target.
                let mut used = vec![false; n];
                out.iter().for_each(|&i| used[i as usize] = true);
                used.iter().filter(|&&u| u).count()
            }
        };
        if let Some((miss, _)) = &best {
            if *miss * 100 <= target_vertices {
                break;
            }
        }
        if reached == 0 {
            target_faces *= 1.5;
            continue;
        }
        target_faces = (target_faces * target_vertices as f64 / reached as f64)
            .round()
            .max(2.0);
    }
    best.map(|(_, d)| d).ok_or_else(|| {
        Error::Numerical(format!(
            "decimation produced no valid mesh (last candidate: {last_error})"
        ))
    })
}

/// Cells of the snapping grids per bounding-box diagonal, tried in order (the cell is the
/// power of two at or below diagonal / cells). On the first grid, typical edges of a shape
/// decimated here (10^3-10^5 vertices) are 10-200 cells long, so the collapse errors are
/// barely changed; the finer grids are for the meshes where the first opens a hole.
pub const SNAP_CELLS: [f64; 3] = [4096.0, 65536.0, 1048576.0];

/// The positions meshoptimizer sees, in `f32`. Unsnapped (`None`): centred on the bounding
/// box (translation invariance, `f32` precision). With `snap_cells`: each coordinate's
/// offset from the bounding box's lowest corner rounded to a whole number of grid cells
/// h = 2^floor(log2(diagonal / snap_cells)) (exact in `f32`: fewer than 2^24 cells). The
/// result moves only where one coordinate crosses a half cell or the diagonal a power of
/// two, not with every change of the last bits. (Rounding a centre to whole cells instead
/// shifted every coordinate at once when the centre crossed a half cell.)
fn meshopt_positions(mesh: &TriMesh, snap_cells: Option<f64>) -> Vec<[f32; 3]> {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in mesh.vertices() {
        for d in 0..3 {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    let centre: [f64; 3] = std::array::from_fn(|d| (lo[d] + hi[d]) / 2.0);
    let Some(cells) = snap_cells else {
        return mesh
            .vertices()
            .iter()
            .map(|p| std::array::from_fn(|d| (p[d] - centre[d]) as f32))
            .collect();
    };
    let diagonal = ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2)).sqrt();
    // A mesh has no degenerate bounding box (TriMesh::new rejects zero-area faces).
    let cell = (diagonal / cells).log2().floor().exp2();
    mesh.vertices()
        .iter()
        .map(|p| std::array::from_fn(|d| (((p[d] - lo[d]) / cell).round() * cell) as f32))
        .collect()
}

/// meshoptimizer's simplification with border locked; where the result has edges in more
/// than two faces, the vertices of those faces and their one-rings in the input are locked
/// and the simplification rerun
/// (up to 8 rounds, while the lock set grows). Returns the last index buffer.
fn simplify_manifold(
    mesh: &TriMesh,
    indices: &[u32],
    positions: &[[f32; 3]],
    target_index_count: usize,
) -> Vec<u32> {
    let mut locks = vec![false; mesh.n_vertices()];
    let mut out = Vec::new();
    let mut neighbors: Option<Vec<Vec<u32>>> = None;
    for _ in 0..8 {
        // target_error 1.0 = the whole mesh extent: the count, not the error, stops it.
        out = meshopt::simplify_with_locks_decoder(
            indices,
            positions,
            &locks,
            target_index_count,
            1.0,
            SimplifyOptions::LockBorder,
            None,
        );
        let faces = clean_faces(mesh, &out);
        let mut count: std::collections::HashMap<(u32, u32), u32> =
            std::collections::HashMap::new();
        for f in &faces {
            for e in 0..3 {
                let (a, b) = (f[e], f[(e + 1) % 3]);
                *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        let mut grew = false;
        for f in &faces {
            let bad = (0..3).any(|e| {
                let (a, b) = (f[e], f[(e + 1) % 3]);
                count[&(a.min(b), a.max(b))] > 2
            });
            if bad {
                // The offending faces' vertices and their rings in the input: the vertex
                // whose collapse made the edge was a neighbour of it.
                let nb = neighbors.get_or_insert_with(|| super::topology::vertex_neighbors(mesh));
                for &v in f {
                    for &u in nb[v as usize].iter().chain(std::iter::once(&v)) {
                        grew |= !locks[u as usize];
                        locks[u as usize] = true;
                    }
                }
            }
        }
        if !grew {
            break;
        }
    }
    out
}

/// Faces of meshoptimizer's index buffer without repeated-vertex, degenerate (at f64) or
/// repeated faces, in order.
fn clean_faces(mesh: &TriMesh, indices: &[u32]) -> Vec<[u32; 3]> {
    let v = mesh.vertices();
    let mut seen = HashSet::with_capacity(indices.len() / 3);
    let mut faces = Vec::with_capacity(indices.len() / 3);
    for t in indices.chunks_exact(3) {
        let f = [t[0], t[1], t[2]];
        if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
            continue;
        }
        let [a, b, c] = f.map(|i| v[i as usize]);
        let l2 = |p: [f64; 3], q: [f64; 3]| {
            (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)
        };
        let longest = l2(a, b).max(l2(b, c)).max(l2(c, a));
        // Twice the tolerance of `TriMesh::new`, so a kept face always passes it.
        if !(super::triangle_area(a, b, c) > 2e-14 * longest) {
            continue;
        }
        let mut key = f;
        key.sort_unstable();
        if seen.insert(key) {
            faces.push(f);
        }
    }
    faces
}

/// Build the decimated mesh from meshoptimizer's index buffer (original vertex indices):
/// drop degenerate and repeated faces, drop unreferenced vertices, validate.
fn assemble(mesh: &TriMesh, indices: &[u32]) -> Result<Decimated, MeshError> {
    let v = mesh.vertices();
    let faces = clean_faces(mesh, indices);
    if faces.is_empty() {
        return Err(MeshError::NoFaces);
    }
    let (mesh, original_vertex) = TriMesh::new_dropping_isolated(v.to_vec(), faces)?;
    Ok(Decimated {
        mesh,
        original_vertex,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::{disk, grid, icosphere};
    use crate::mesh::topology::{boundary_vertices, connected_components, euler_characteristic};

    fn check_decimation(m: &TriMesh, fraction: f64) -> Decimated {
        let d = decimate(m, fraction).unwrap();
        let target = (fraction * m.n_vertices() as f64).round();
        let got = d.mesh.n_vertices() as f64;
        assert!(
            (got - target).abs() <= 0.05 * target,
            "{got} vertices for target {target}"
        );
        // Kept vertices are original vertices at their original positions.
        assert_eq!(d.original_vertex.len(), d.mesh.n_vertices());
        for (i, &o) in d.original_vertex.iter().enumerate() {
            assert_eq!(d.mesh.vertices()[i], m.vertices()[o as usize]);
        }
        assert!(d.original_vertex.windows(2).all(|w| w[0] < w[1]));
        // Topology kept.
        assert_eq!(euler_characteristic(&d.mesh), euler_characteristic(m));
        assert_eq!(connected_components(&d.mesh).1, connected_components(m).1);
        // Deterministic.
        let again = decimate(m, fraction).unwrap();
        assert_eq!(again.mesh, d.mesh);
        d
    }

    #[test]
    fn icosphere_half() {
        let m = icosphere(4);
        let d = check_decimation(&m, 0.5);
        let rel = (d.mesh.area() - m.area()).abs() / m.area();
        assert!(rel < 0.03, "area changed by {rel}");
    }

    #[test]
    fn boundary_is_kept() {
        for m in [disk(1.0, 20), grid(2.0, 1.0, 40, 20)] {
            let d = check_decimation(&m, 0.5);
            let orig: Vec<u32> = boundary_vertices(&m);
            let kept: Vec<u32> = boundary_vertices(&d.mesh)
                .iter()
                .map(|&i| d.original_vertex[i as usize])
                .collect();
            assert_eq!(kept, orig, "boundary changed");
            let rel = (d.mesh.area() - m.area()).abs() / m.area();
            assert!(rel < 1e-9, "planar area changed by {rel}");
        }
    }

    #[test]
    fn fraction_one_is_identity_and_bad_fraction_is_error() {
        let m = icosphere(1);
        let d = decimate(&m, 1.0).unwrap();
        assert_eq!(d.mesh, m);
        for f in [0.0, -0.5, 1.5, f64::NAN] {
            assert!(decimate(&m, f).is_err());
        }
    }

    #[test]
    fn translation_does_not_change_connectivity() {
        let m = icosphere(3);
        let shifted = m
            .map_positions(|p| [p[0] + 0.25, p[1] - 0.5, p[2] + 0.125])
            .unwrap();
        let a = decimate(&m, 0.5).unwrap();
        let b = decimate(&shifted, 0.5).unwrap();
        assert_eq!(a.original_vertex, b.original_vertex);
        assert_eq!(a.mesh.faces(), b.mesh.faces());
    }

    /// A bumpy sphere (no exact ties between collapse errors) moved by `eps` of its
    /// diagonal, vertex by vertex, with a fixed pseudo-random pattern per seed.
    fn bumpy_jittered(eps: f64, seed: u64) -> TriMesh {
        let m = icosphere(4);
        let h = eps * m.bbox_diagonal();
        let (v, f) = m.into_parts();
        let v = v
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let r = 1.0 + 0.1 * (3.0 * p[0]).sin() * (2.0 * p[1]).cos() + 0.05 * (5.0 * p[2]).sin();
                std::array::from_fn(|d| {
                    let k = (3 * i + d) as u64 + 1;
                    let z = seed.wrapping_mul(1 << 32).wrapping_add(k).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11;
                    r * p[d] + h * (z as f64 / (1u64 << 53) as f64 - 0.5)
                })
            })
            .collect();
        TriMesh::new(v, f).unwrap()
    }

    #[test]
    fn last_bits_of_the_coordinates_do_not_change_the_result() {
        let base = decimate(&bumpy_jittered(0.0, 0), 0.2).unwrap();
        let mut unsnapped_moved = false;
        for seed in 1..=8 {
            let moved = bumpy_jittered(1e-9, seed);
            let d = decimate(&moved, 0.2).unwrap();
            assert_eq!(d.original_vertex, base.original_vertex, "seed {seed}");
            assert_eq!(d.mesh.faces(), base.mesh.faces(), "seed {seed}");
            // Without the snapping the same jitter changes which vertices are kept.
            let raw = |m: &TriMesh| decimate_positions(m, &meshopt_positions(m, None), 0.2).unwrap();
            unsnapped_moved |= raw(&moved).original_vertex != raw(&bumpy_jittered(0.0, 0)).original_vertex;
        }
        assert!(unsnapped_moved, "the jitter never reached meshoptimizer's f32 positions");
    }
}
