//! Boundary length of a vertex region: the total length of the edges that bound the faces
//! lying wholly in the region. Of a whole open mesh (the partial shape): its boundary length.

use crate::mesh::TriMesh;
use std::collections::HashMap;

/// Length of the boundary of $\{f : \text{all three vertices of } f \in R\}$ (edges of one
/// such face only); `region: None` is the whole mesh. Errors never: a region with no whole
/// face has length 0. Panics if `region` is shorter than the vertex count.
pub fn region_boundary_length(mesh: &TriMesh, region: Option<&[bool]>) -> f64 {
    let mut count: HashMap<(u32, u32), u32> = HashMap::new();
    for f in mesh.faces() {
        if region.is_some_and(|r| !f.iter().all(|&i| r[i as usize])) {
            continue;
        }
        for e in 0..3 {
            let (a, b) = (f[e], f[(e + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let v = mesh.vertices();
    // Sum in a fixed order (HashMap iteration order is not deterministic).
    let mut edges: Vec<(u32, u32)> = count
        .into_iter()
        .filter(|&(_, c)| c == 1)
        .map(|(e, _)| e)
        .collect();
    edges.sort_unstable();
    edges.iter().map(|&(a, b)| crate::mesh::distance(v[a as usize], v[b as usize])).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit square grid has perimeter 4; the region x <= 0.5 of it is a 0.5 x 1 rectangle
    /// (perimeter 3); a closed sphere has none; a region without a whole face has none.
    #[test]
    fn boundary_lengths_of_known_shapes() {
        let g = crate::mesh::generate::grid(1.0, 1.0, 10, 10);
        assert!((region_boundary_length(&g, None) - 4.0).abs() < 1e-12);
        let half: Vec<bool> = g.vertices().iter().map(|p| p[0] <= 0.5 + 1e-9).collect();
        assert!((region_boundary_length(&g, Some(&half)) - 3.0).abs() < 1e-12);
        let s = crate::mesh::generate::icosphere(2);
        assert_eq!(region_boundary_length(&s, None), 0.0);
        let one = (0..s.n_vertices()).map(|i| i == 0).collect::<Vec<_>>();
        assert_eq!(region_boundary_length(&s, Some(&one)), 0.0);
    }
}
