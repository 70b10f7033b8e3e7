//! Nearest-point queries in 3-D: a static kd-tree, nearest-vertex maps between two
//! meshes, and transfer of per-vertex values along such a map.
//!
//! Used to carry a mask or a score from the decimated full shape back to the full shape
//! (docs/algorithm.md, "Optimisation": "transferred back to the full mesh by nearest
//! neighbours") and for the fixed-radius searches of the SHOT descriptor.
//!
//! The tree is hand-written rather than taken from a crate (e.g. `kiddo`): 3-D only,
//! ~150 lines, no dependencies, and it fixes the tie rules the pipeline needs to be
//! deterministic: among equidistant points [`KdTree::nearest`] returns the smallest
//! index, and [`KdTree::within_radius`] returns indices in ascending order.

use crate::error::{Error, Result};

/// Points per leaf; below this a linear scan is faster than further splitting.
const LEAF_SIZE: usize = 8;

#[derive(Debug, Clone)]
enum Node {
    /// `order[start..end]` are the points of this leaf.
    Leaf { start: usize, end: usize },
    /// Points with `p[axis] <= split` are in `left`, the others in `right`.
    Split {
        axis: usize,
        split: f64,
        left: usize,
        right: usize,
    },
}

/// A balanced kd-tree over a fixed set of 3-D points (median splits on the axis of
/// largest extent). Construction `O(n log n)`; a nearest query `O(log n)` on average.
#[derive(Debug, Clone)]
pub struct KdTree {
    points: Vec<[f64; 3]>,
    order: Vec<u32>,
    nodes: Vec<Node>,
}

#[inline]
fn dist2(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
}

impl KdTree {
    /// Build a tree over `points` (indices into `points` are what queries return).
    ///
    /// Errors: no points, a non-finite coordinate, or more than `u32::MAX` points.
    pub fn new(points: &[[f64; 3]]) -> Result<Self> {
        if points.is_empty() {
            return Err(Error::InvalidArgument("kd-tree needs at least one point".into()));
        }
        if points.len() > u32::MAX as usize {
            return Err(Error::InvalidArgument(format!(
                "too many points for a kd-tree: {}",
                points.len()
            )));
        }
        if let Some(i) = points.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(Error::InvalidArgument(format!("point {i} has a non-finite coordinate")));
        }
        let mut tree = KdTree {
            points: points.to_vec(),
            order: (0..points.len() as u32).collect(),
            nodes: Vec::new(),
        };
        tree.build(0, points.len());
        Ok(tree)
    }

    /// Number of points in the tree.
    #[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Always `false` (a tree has at least one point); for API completeness.
    #[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The points the tree was built on.
    #[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
    pub fn points(&self) -> &[[f64; 3]] {
        &self.points
    }

    fn build(&mut self, start: usize, end: usize) -> usize {
        let id = self.nodes.len();
        if end - start <= LEAF_SIZE {
            self.nodes.push(Node::Leaf { start, end });
            return id;
        }
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for &i in &self.order[start..end] {
            let p = self.points[i as usize];
            for d in 0..3 {
                lo[d] = lo[d].min(p[d]);
                hi[d] = hi[d].max(p[d]);
            }
        }
        let axis = (0..3)
            .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
            .unwrap_or(0);
        if !(hi[axis] > lo[axis]) {
            // All points coincide: no split can separate them.
            self.nodes.push(Node::Leaf { start, end });
            return id;
        }
        let mid = start + (end - start) / 2;
        let pts = &self.points;
        // Total order (coordinate, index) makes the tree independent of the input's
        // incidental ordering of equal coordinates.
        self.order[start..end].select_nth_unstable_by(mid - start, |&a, &b| {
            pts[a as usize][axis].total_cmp(&pts[b as usize][axis]).then(a.cmp(&b))
        });
        let split = self.points[self.order[mid] as usize][axis];
        // Points equal to `split` can be on either side of `mid`; queries handle this by
        // visiting the far side whenever the splitting plane is within the search radius.
        self.nodes.push(Node::Leaf { start: 0, end: 0 }); // placeholder
        let left = self.build(start, mid + 1);
        let right = self.build(mid + 1, end);
        self.nodes[id] = Node::Split {
            axis,
            split,
            left,
            right,
        };
        id
    }

    /// The point nearest to `q` (Euclidean) as `(index, squared distance)`; among
    /// equidistant points the smallest index.
    pub fn nearest(&self, q: [f64; 3]) -> (u32, f64) {
        let mut best = (u32::MAX, f64::INFINITY);
        self.nearest_in(0, &q, &mut best);
        best
    }

    fn nearest_in(&self, node: usize, q: &[f64; 3], best: &mut (u32, f64)) {
        match self.nodes[node] {
            Node::Leaf { start, end } => {
                for &i in &self.order[start..end] {
                    let d = dist2(&self.points[i as usize], q);
                    if d < best.1 || (d == best.1 && i < best.0) {
                        *best = (i, d);
                    }
                }
            }
            Node::Split {
                axis,
                split,
                left,
                right,
            } => {
                let delta = q[axis] - split;
                let (near, far) = if delta <= 0.0 { (left, right) } else { (right, left) };
                self.nearest_in(near, q, best);
                if delta * delta <= best.1 {
                    self.nearest_in(far, q, best);
                }
            }
        }
    }

    /// Indices of all points `p` with `|p - q| <= r`, ascending, with their squared
    /// distances. `r` must be finite and non-negative (otherwise nothing is returned).
    #[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
    pub fn within_radius(&self, q: [f64; 3], r: f64) -> Vec<(u32, f64)> {
        let mut out = Vec::new();
        self.within_radius_into(q, r, &mut out);
        out
    }

    /// As [`within_radius`](Self::within_radius), reusing `out` (cleared first).
    pub fn within_radius_into(&self, q: [f64; 3], r: f64, out: &mut Vec<(u32, f64)>) {
        out.clear();
        if !(r >= 0.0 && r.is_finite()) {
            return;
        }
        self.radius_in(0, &q, r * r, out);
        out.sort_unstable_by_key(|&(i, _)| i);
    }

    fn radius_in(&self, node: usize, q: &[f64; 3], r2: f64, out: &mut Vec<(u32, f64)>) {
        match self.nodes[node] {
            Node::Leaf { start, end } => {
                for &i in &self.order[start..end] {
                    let d = dist2(&self.points[i as usize], q);
                    if d <= r2 {
                        out.push((i, d));
                    }
                }
            }
            Node::Split {
                axis,
                split,
                left,
                right,
            } => {
                let delta = q[axis] - split;
                if delta <= 0.0 || delta * delta <= r2 {
                    self.radius_in(left, q, r2, out);
                }
                if delta >= 0.0 || delta * delta <= r2 {
                    self.radius_in(right, q, r2, out);
                }
            }
        }
    }
}

/// For every point of `queries`, the index of the nearest point of `targets`
/// (Euclidean; ties to the smallest index). Parallel over queries, deterministic.
///
/// Typical use: `nearest_vertices(decimated.vertices(), full.vertices())` gives, for each
/// vertex of the full mesh, the decimated vertex whose value it inherits.
pub fn nearest_vertices(targets: &[[f64; 3]], queries: &[[f64; 3]]) -> Result<Vec<u32>> {
    use rayon::prelude::*;
    if let Some(i) = queries.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        return Err(Error::InvalidArgument(format!(
            "query point {i} has a non-finite coordinate"
        )));
    }
    let tree = KdTree::new(targets)?;
    Ok(queries.par_iter().map(|&q| tree.nearest(q).0).collect())
}

/// Pull per-vertex values back along a map: `out[i] = values[map[i]]`.
///
/// With `map = nearest_vertices(source_vertices, target_vertices)` this transfers a
/// mask or score from the source mesh to the target mesh by nearest neighbour.
#[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
pub fn transfer<T: Copy>(values: &[T], map: &[u32]) -> Result<Vec<T>> {
    map.iter()
        .enumerate()
        .map(|(i, &j)| {
            values.get(j as usize).copied().ok_or_else(|| {
                Error::InvalidArgument(format!(
                    "map entry {i} = {j} is out of range for {} values",
                    values.len()
                ))
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SplitMix64: a tiny deterministic generator for test points.
    fn rng(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = s;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            (z >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    fn random_points(n: usize, seed: u64) -> Vec<[f64; 3]> {
        let mut r = rng(seed);
        (0..n).map(|_| [r() * 2.0 - 1.0, r() * 3.0, r() * 0.5]).collect()
    }

    fn brute_nearest(pts: &[[f64; 3]], q: [f64; 3]) -> (u32, f64) {
        let mut best = (u32::MAX, f64::INFINITY);
        for (i, p) in pts.iter().enumerate() {
            let d = dist2(p, &q);
            if d < best.1 {
                best = (i as u32, d);
            }
        }
        best
    }

    #[test]
    fn nearest_matches_brute_force() {
        let pts = random_points(2000, 1);
        let queries = random_points(500, 2);
        let tree = KdTree::new(&pts).unwrap();
        for q in &queries {
            assert_eq!(tree.nearest(*q), brute_nearest(&pts, *q));
        }
        let map = nearest_vertices(&pts, &queries).unwrap();
        for (q, &m) in queries.iter().zip(&map) {
            assert_eq!(m, brute_nearest(&pts, *q).0);
        }
        // A point of the set is its own nearest neighbour.
        for (i, p) in pts.iter().enumerate().step_by(37) {
            assert_eq!(tree.nearest(*p), (i as u32, 0.0));
        }
    }

    #[test]
    fn radius_matches_brute_force() {
        let pts = random_points(3000, 3);
        let tree = KdTree::new(&pts).unwrap();
        for (k, q) in random_points(200, 4).into_iter().enumerate() {
            let r = 0.05 + 0.3 * (k % 5) as f64;
            let got: Vec<u32> = tree.within_radius(q, r).into_iter().map(|(i, _)| i).collect();
            let want: Vec<u32> = (0..pts.len() as u32)
                .filter(|&i| dist2(&pts[i as usize], &q) <= r * r)
                .collect();
            assert_eq!(got, want);
        }
    }

    #[test]
    fn duplicates_and_ties_pick_smallest_index() {
        // Many coincident points (no split possible) plus a lattice with exact ties.
        let mut pts = vec![[1.0, 1.0, 1.0]; 50];
        for i in 0..10 {
            for j in 0..10 {
                pts.push([i as f64, j as f64, 0.0]);
            }
        }
        let tree = KdTree::new(&pts).unwrap();
        assert_eq!(tree.nearest([1.0, 1.0, 1.0]).0, 0);
        // (0.5, 0.5, 0) is equidistant from four lattice points; the smallest index wins.
        let (i, _) = tree.nearest([0.5, 0.5, 0.0]);
        assert_eq!(i, brute_nearest(&pts, [0.5, 0.5, 0.0]).0);
        assert_eq!(tree.within_radius([1.0, 1.0, 1.0], 0.0).len(), 50);
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(KdTree::new(&[]).is_err());
        assert!(KdTree::new(&[[0.0, f64::NAN, 0.0]]).is_err());
        assert!(nearest_vertices(&[[0.0; 3]], &[[f64::INFINITY, 0.0, 0.0]]).is_err());
        assert!(transfer(&[1, 2], &[0, 2]).is_err());
        assert_eq!(transfer(&[true, false], &[1, 1, 0]).unwrap(), vec![false, false, true]);
    }
}
