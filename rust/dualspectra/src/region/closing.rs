//! Morphological dilation, erosion and closing of a vertex mask on the mesh graph.
//!
//! The structuring element is the `r`-ring ball `B_r(v) = { u : d_G(u, v) <= r }`, with
//! `d_G` the hop distance on the edge graph (`mesh::topology::vertex_neighbors`):
//!
//! - dilation  `D_r(X) = { v : B_r(v) ∩ X ≠ ∅ }`
//! - erosion   `E_r(X) = { v : B_r(v) ⊆ X }` (the complement of `D_r` of the complement)
//! - closing   `C_r(X) = E_r(D_r(X))`
//!
//! Because `d_G` is symmetric, `(E_r, D_r)` is an adjunction, so the closing is
//! extensive (`X ⊆ C_r(X)`), increasing and idempotent. docs/algorithm.md, "Optimisation":
//! the region transferred to the full shape is grown by 4 rings and shrunk by 4 rings.
//!
//! Nothing lies beyond the mesh boundary: a boundary vertex is eroded only if some mesh
//! vertex within `r` rings of it is outside the mask.

use crate::error::{Error, Result};

fn check(mask: &[bool], neighbors: &[Vec<u32>]) -> Result<()> {
    if mask.len() != neighbors.len() {
        return Err(Error::InvalidArgument(format!(
            "mask has {} entries but the neighbour lists describe {} vertices",
            mask.len(),
            neighbors.len()
        )));
    }
    let n = neighbors.len();
    for (v, list) in neighbors.iter().enumerate() {
        if let Some(&u) = list.iter().find(|&&u| u as usize >= n) {
            return Err(Error::InvalidArgument(format!(
                "vertex {v} lists neighbour {u}, out of range for {n} vertices"
            )));
        }
    }
    Ok(())
}

/// Grow by one ring per step (breadth-first frontier), `rings` times.
fn grow(mask: &[bool], neighbors: &[Vec<u32>], rings: usize) -> Vec<bool> {
    let mut out = mask.to_vec();
    let mut frontier: Vec<u32> = (0..mask.len() as u32).filter(|&v| mask[v as usize]).collect();
    for _ in 0..rings {
        if frontier.is_empty() {
            break;
        }
        let mut next = Vec::new();
        for &v in &frontier {
            for &u in &neighbors[v as usize] {
                if !out[u as usize] {
                    out[u as usize] = true;
                    next.push(u);
                }
            }
        }
        frontier = next;
    }
    out
}

/// Dilation `D_r(X)`: every vertex within `rings` hops of the mask.
///
/// `mask[v]` is membership of vertex `v`; `neighbors[v]` its one ring (as from
/// `mesh::topology::vertex_neighbors`). Errors on a length mismatch or an out-of-range index.
#[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
pub fn dilate(mask: &[bool], neighbors: &[Vec<u32>], rings: usize) -> Result<Vec<bool>> {
    check(mask, neighbors)?;
    Ok(grow(mask, neighbors, rings))
}

/// Erosion `E_r(X)`: the vertices whose whole `rings`-ring ball lies in the mask.
#[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
pub fn erode(mask: &[bool], neighbors: &[Vec<u32>], rings: usize) -> Result<Vec<bool>> {
    check(mask, neighbors)?;
    let complement: Vec<bool> = mask.iter().map(|&b| !b).collect();
    Ok(grow(&complement, neighbors, rings).into_iter().map(|b| !b).collect())
}

/// Closing `C_r(X) = E_r(D_r(X))`: fills holes and gaps narrower than about `2 r` rings.
pub fn close(mask: &[bool], neighbors: &[Vec<u32>], rings: usize) -> Result<Vec<bool>> {
    check(mask, neighbors)?;
    let grown = grow(mask, neighbors, rings);
    let complement: Vec<bool> = grown.iter().map(|&b| !b).collect();
    Ok(grow(&complement, neighbors, rings).into_iter().map(|b| !b).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::{grid, icosphere};
    use crate::mesh::topology::vertex_neighbors;

    fn pseudo_random_mask(n: usize, seed: u64, density: u64) -> Vec<bool> {
        let mut s = seed;
        (0..n)
            .map(|_| {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                s % 100 < density
            })
            .collect()
    }

    #[test]
    fn closing_is_extensive_and_idempotent() {
        let m = icosphere(3);
        let nb = vertex_neighbors(&m);
        for (seed, density) in [(1u64, 10u64), (7, 40), (99, 70)] {
            let x = pseudo_random_mask(m.n_vertices(), seed, density);
            for r in 0..4 {
                let c = close(&x, &nb, r).unwrap();
                assert!(x.iter().zip(&c).all(|(&a, &b)| !a || b), "not extensive (r = {r})");
                assert_eq!(close(&c, &nb, r).unwrap(), c, "not idempotent (r = {r})");
                // Erosion is anti-extensive, dilation extensive.
                let e = erode(&x, &nb, r).unwrap();
                let d = dilate(&x, &nb, r).unwrap();
                assert!(e.iter().zip(&x).all(|(&a, &b)| !a || b));
                assert!(x.iter().zip(&d).all(|(&a, &b)| !a || b));
            }
            assert_eq!(close(&x, &nb, 0).unwrap(), x);
        }
    }

    #[test]
    fn closing_fills_a_one_ring_hole() {
        let m = grid(1.0, 1.0, 20, 20);
        let nb = vertex_neighbors(&m);
        let centre = 10 * 21 + 10;
        let mut x = vec![true; m.n_vertices()];
        x[centre] = false;
        for &u in &nb[centre] {
            x[u as usize] = false;
        }
        // A hole of radius 1 (a vertex and its ring) is filled by r = 2, not by r = 1.
        assert!(
            close(&x, &nb, 2).unwrap().iter().all(|&b| b),
            "the 1-ring hole should be filled"
        );
        assert!(!close(&x, &nb, 1).unwrap()[centre]);
        // A single missing vertex is filled by r = 1.
        let mut y = vec![true; m.n_vertices()];
        y[centre] = false;
        assert!(close(&y, &nb, 1).unwrap().iter().all(|&b| b));
        // Dilating then eroding the full mask leaves it full, boundary included.
        assert_eq!(
            erode(&vec![true; m.n_vertices()], &nb, 3).unwrap(),
            vec![true; m.n_vertices()]
        );
    }

    #[test]
    fn dilation_counts_rings() {
        let m = grid(1.0, 1.0, 10, 10);
        let nb = vertex_neighbors(&m);
        let mut x = vec![false; m.n_vertices()];
        x[0] = true;
        let d1 = dilate(&x, &nb, 1).unwrap();
        assert_eq!(d1.iter().filter(|&&b| b).count(), 1 + nb[0].len());
        assert_eq!(erode(&d1, &nb, 1).unwrap(), x);
    }

    #[test]
    fn bad_input_is_an_error() {
        let nb = vec![vec![1], vec![0]];
        assert!(close(&[true], &nb, 1).is_err());
        assert!(dilate(&[true, false], &[vec![5], vec![0]], 1).is_err());
    }
}
