//! A procedural articulated shape and a partial, deformed, cut copy of it with exact
//! ground truth, for the demo and for end-to-end tests that need no data files.
//!
//! - **Shape** ([`figure`]): a closed genus-0 surface made by displacing a unit icosphere
//!   radially, $p(u) = r(u)\,u$ with $r(u) = 1 + \sum_j h_j \exp(-(\theta_j(u)/\sigma_j)^2)$,
//!   $\theta_j$ the angle between $u$ and limb direction $d_j$: a torso with a head, two
//!   arms (of different lengths, so the shape has no left-right symmetry) and two legs.
//!   A radial graph over the sphere is always an embedded manifold.
//! - **Pose** ([`pose`]): the longer arm is bent at its elbow by the arc map of a bend
//!   with curvature $\kappa = \beta / L$ over a length $L$ of the arm's axis: a point at
//!   axial coordinate $x$ and offset $h$ in the bending plane maps to
//!   $c(x) + h\,n(x)$ with $c(x) = (\sin\kappa x, 1 - \cos\kappa x)/\kappa$ and
//!   $n(x) = (-\sin\kappa x, \cos\kappa x)$ (rigid beyond $L$). The axis keeps its length
//!   and the strain is $h\kappa$ only inside the bend, so the pose is near-isometric.
//! - **Cut** ([`cut_by_plane`]): the faces of the posed copy whose centroid lies on the
//!   positive side of a plane, largest connected component. The partial keeps the vertex
//!   identities, so the ground truth is exact: the full mesh's vertices it kept.

use crate::error::{Error, Result};
use crate::mesh::{generate, topology, TriMesh};

type V3 = [f64; 3];

/// A point of a full shape as SHREC'16 ground truth gives it: a triangle (0-based) and
/// barycentric weights in it (one row of a `.baryc_gt` file).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BarycentricRow {
    pub triangle: u32,
    pub weights: [f64; 3],
}

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn normalize(a: V3) -> V3 {
    scale(a, 1.0 / dot(a, a).sqrt())
}

/// One limb of [`figure`]: direction, height and angular width (radians) of its bump.
#[derive(Debug, Clone, Copy)]
pub struct Limb {
    pub direction: V3,
    pub height: f64,
    pub width: f64,
}

/// The limbs of the default figure: head (+z), long arm (+x), short arm (-x), two legs.
pub fn default_limbs() -> Vec<Limb> {
    vec![
        Limb {
            direction: [0.0, 0.0, 1.0],
            height: 0.55,
            width: 0.38,
        },
        Limb {
            direction: normalize([1.0, 0.0, 0.12]),
            height: 1.25,
            width: 0.24,
        },
        Limb {
            direction: normalize([-1.0, 0.0, 0.12]),
            height: 0.8,
            width: 0.26,
        },
        Limb {
            direction: normalize([0.42, 0.0, -1.0]),
            height: 1.1,
            width: 0.26,
        },
        Limb {
            direction: normalize([-0.42, 0.0, -1.0]),
            height: 1.1,
            width: 0.26,
        },
    ]
}

/// The limbs of a figure unlike the default one: a four-legged body with a head and a tail
/// (search tests rank it against the default figure).
pub fn quadruped_limbs() -> Vec<Limb> {
    let limb = |direction: V3, height: f64, width: f64| Limb { direction: normalize(direction), height, width };
    vec![
        limb([1.0, 0.0, 0.3], 0.6, 0.35),
        limb([0.5, 0.5, -1.0], 0.9, 0.2),
        limb([0.5, -0.5, -1.0], 0.9, 0.2),
        limb([-0.5, 0.5, -1.0], 0.9, 0.2),
        limb([-0.5, -0.5, -1.0], 0.9, 0.2),
        limb([-1.0, 0.0, 0.4], 1.4, 0.12),
    ]
}

/// The limbs of another figure unlike the default one: one long thin horn up, a wide stump
/// down.
pub fn horned_limbs() -> Vec<Limb> {
    vec![
        Limb { direction: [0.0, 0.0, 1.0], height: 2.0, width: 0.15 },
        Limb { direction: [0.0, 0.0, -1.0], height: 0.4, width: 0.6 },
    ]
}

/// The articulated figure: icosphere of subdivision `level` (`10 * 4^level + 2` vertices)
/// displaced radially by the limbs (module doc), then flattened front-to-back (y * 0.7).
pub fn figure(level: u32, limbs: &[Limb]) -> Result<TriMesh> {
    if level > 6 {
        return Err(Error::InvalidArgument(format!(
            "icosphere level {level} too large (at most 6)"
        )));
    }
    let sphere = generate::icosphere(level);
    let mesh = sphere.map_positions(|u| {
        let r = 1.0
            + limbs
                .iter()
                .map(|l| {
                    let theta = dot(u, l.direction).clamp(-1.0, 1.0).acos();
                    l.height * (-(theta / l.width).powi(2)).exp()
                })
                .sum::<f64>();
        let p = scale(u, r);
        [p[0], 0.7 * p[1], p[2]]
    })?;
    Ok(mesh)
}

/// A bend of the part of a mesh beyond a joint (module doc): points with axial coordinate
/// `t = p . axis > joint` are bent by `angle` radians towards `towards` (made orthogonal to
/// `axis`) over the axial length `length`.
#[derive(Debug, Clone, Copy)]
pub struct Bend {
    pub axis: V3,
    pub towards: V3,
    pub joint: f64,
    pub length: f64,
    pub angle: f64,
}

impl Bend {
    /// Apply the bend to one point.
    pub fn apply(&self, p: V3) -> V3 {
        let a = normalize(self.axis);
        let b = normalize(add(self.towards, scale(a, -dot(self.towards, a))));
        let t = dot(p, a);
        if t <= self.joint || self.angle == 0.0 || self.length <= 0.0 {
            return p;
        }
        let h = dot(p, b);
        let rest = add(p, add(scale(a, -t), scale(b, -h)));
        let kappa = self.angle / self.length;
        let x = t - self.joint;
        let s = x.min(self.length);
        let (sn, cs) = (kappa * s).sin_cos();
        let mut c = [sn / kappa, (1.0 - cs) / kappa];
        if x > self.length {
            c = [c[0] + (x - self.length) * cs, c[1] + (x - self.length) * sn];
        }
        let n = [-sn, cs];
        let (xa, xb) = (c[0] + h * n[0], c[1] + h * n[1]);
        add(rest, add(scale(a, self.joint + xa), scale(b, xb)))
    }
}

/// The default pose: the long (+x) arm bent up by 50 degrees over its outer part
/// (axial coordinate 1.1 to 2.2; the arm's tip is at about 2.25). Measured on level 4:
/// mean relative edge-length change 0.34 %, max 29 % (inside the bend, where the arm is
/// thickest: strain $h\kappa$), tip moved by 0.5.
pub fn default_bend() -> Bend {
    Bend {
        axis: normalize([1.0, 0.0, 0.12]),
        towards: [0.0, 0.0, 1.0],
        joint: 1.1,
        length: 1.1,
        angle: 50f64.to_radians(),
    }
}

/// Pose `mesh` by `bend` (same connectivity and vertex identities).
pub fn pose(mesh: &TriMesh, bend: &Bend) -> Result<TriMesh> {
    Ok(mesh.map_positions(|p| bend.apply(p))?)
}

/// Keep the faces of `mesh` whose centroid `c` has `c . normal > offset`, then the largest
/// connected component. Returns the partial mesh and `kept[new vertex] = old vertex`.
/// Errors if nothing is kept or the cut leaves a non-manifold vertex.
pub fn cut_by_plane(mesh: &TriMesh, normal: V3, offset: f64) -> Result<(TriMesh, Vec<u32>)> {
    let v = mesh.vertices();
    let faces: Vec<[u32; 3]> = mesh
        .faces()
        .iter()
        .copied()
        .filter(|f| {
            let c = scale(
                add(add(v[f[0] as usize], v[f[1] as usize]), v[f[2] as usize]),
                1.0 / 3.0,
            );
            dot(c, normal) > offset
        })
        .collect();
    if faces.is_empty() {
        return Err(Error::InvalidArgument(
            "the cutting plane keeps no face".into(),
        ));
    }
    let (side, kept) = TriMesh::new_dropping_isolated(v.to_vec(), faces)?;
    // Largest connected component.
    let (comp, n_comp) = topology::connected_components(&side);
    let (part, kept) = if n_comp > 1 {
        let mut count = vec![0usize; n_comp];
        comp.iter().for_each(|&c| count[c as usize] += 1);
        let best = (0..n_comp).max_by_key(|&c| count[c]).unwrap_or(0) as u32;
        let faces: Vec<[u32; 3]> = side
            .faces()
            .iter()
            .copied()
            .filter(|f| comp[f[0] as usize] == best)
            .collect();
        let (part, kept2) = TriMesh::new_dropping_isolated(side.vertices().to_vec(), faces)?;
        let kept = kept2.iter().map(|&i| kept[i as usize]).collect();
        (part, kept)
    } else {
        (side, kept)
    };
    // Each boundary vertex of a manifold-with-boundary mesh has exactly two boundary edges.
    let mut boundary_degree = vec![0u32; part.n_vertices()];
    for (&(a, b), &c) in &topology::edge_face_counts(&part) {
        if c == 1 {
            boundary_degree[a as usize] += 1;
            boundary_degree[b as usize] += 1;
        }
    }
    if let Some(bad) = boundary_degree.iter().position(|&d| d > 2) {
        return Err(Error::Numerical(format!(
            "the cut leaves vertex {bad} non-manifold"
        )));
    }
    Ok((part, kept))
}

/// Settings of [`synthetic_pair`]; `Default` gives the demo's pair.
#[derive(Debug, Clone)]
pub struct SyntheticParams {
    /// Icosphere subdivision level of the full shape (4: 2562 vertices).
    pub level: u32,
    pub limbs: Vec<Limb>,
    pub bend: Bend,
    /// The partial keeps the faces with centroid `c . cut_normal > cut_offset`.
    pub cut_normal: V3,
    pub cut_offset: f64,
    /// Keeps the struct extensible (construct with `..Default::default()`).
    #[doc(hidden)]
    pub non_exhaustive: crate::NonExhaustive,
}

impl Default for SyntheticParams {
    fn default() -> Self {
        SyntheticParams {
            level: 4,
            limbs: default_limbs(),
            bend: default_bend(),
            cut_normal: normalize([0.35, 0.15, 1.0]),
            cut_offset: -0.35,
            non_exhaustive: crate::NonExhaustive::default(),
        }
    }
}

/// A full shape, its posed copy, and the partial cut from the posed copy.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct SyntheticPair {
    pub full: TriMesh,
    pub posed: TriMesh,
    pub partial: TriMesh,
    /// `partial_to_full[i]` = vertex of `full` that partial vertex `i` is.
    pub partial_to_full: Vec<u32>,
    /// Ground truth over `full`'s vertices: `true` on the vertices the partial kept.
    pub gt: Vec<bool>,
}

impl SyntheticPair {
    /// Ground truth as SHREC'16 barycentric rows (one per partial vertex): a triangle of
    /// `full` containing the vertex, with weight 1 on it. Marking that triangle's three
    /// vertices (the SHREC'16 convention) grows the region by at most one ring.
    pub fn barycentric_gt(&self) -> Vec<BarycentricRow> {
        let mut tri_of = vec![(u32::MAX, 0usize); self.full.n_vertices()];
        for (t, f) in self.full.faces().iter().enumerate() {
            for (k, &v) in f.iter().enumerate() {
                if tri_of[v as usize].0 == u32::MAX {
                    tri_of[v as usize] = (t as u32, k);
                }
            }
        }
        self.partial_to_full
            .iter()
            .map(|&v| {
                let (t, k) = tri_of[v as usize];
                let mut w = [0.0; 3];
                w[k] = 1.0;
                BarycentricRow {
                    triangle: t,
                    weights: w,
                }
            })
            .collect()
    }
}

/// Build the synthetic pair (module doc).
pub fn synthetic_pair(params: &SyntheticParams) -> Result<SyntheticPair> {
    let full = figure(params.level, &params.limbs)?;
    let posed = pose(&full, &params.bend)?;
    let (partial, partial_to_full) = cut_by_plane(&posed, params.cut_normal, params.cut_offset)?;
    let mut gt = vec![false; full.n_vertices()];
    partial_to_full.iter().for_each(|&v| gt[v as usize] = true);
    Ok(SyntheticPair {
        full,
        posed,
        partial,
        partial_to_full,
        gt,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edge_lengths(m: &TriMesh) -> Vec<(u32, u32, f64)> {
        let mut e: Vec<(u32, u32)> = topology::edge_face_counts(m).keys().copied().collect();
        e.sort();
        let v = m.vertices();
        e.into_iter()
            .map(|(a, b)| {
                let d = add(v[a as usize], scale(v[b as usize], -1.0));
                (a, b, dot(d, d).sqrt())
            })
            .collect()
    }

    #[test]
    fn figure_is_a_closed_sphere() {
        let m = figure(4, &default_limbs()).unwrap();
        assert_eq!(m.n_vertices(), 2562);
        assert!(topology::boundary_vertices(&m).is_empty());
        assert_eq!(topology::euler_characteristic(&m), 2);
    }

    #[test]
    fn pair_is_valid_with_boundary_and_exact_ground_truth() {
        let p = synthetic_pair(&SyntheticParams::default()).unwrap();
        assert_eq!(p.gt.len(), p.full.n_vertices());
        assert_eq!(p.gt.iter().filter(|&&b| b).count(), p.partial.n_vertices());
        assert!(!topology::boundary_vertices(&p.partial).is_empty());
        let (_, n_comp) = topology::connected_components(&p.partial);
        assert_eq!(n_comp, 1);
        // The partial is the posed copy restricted to the kept vertices.
        for (i, &v) in p.partial_to_full.iter().enumerate() {
            assert_eq!(p.partial.vertices()[i], p.posed.vertices()[v as usize]);
        }
        let frac = p.partial.area() / p.posed.area();
        assert!(frac > 0.3 && frac < 0.8, "partial area fraction {frac}");
        // Barycentric rows reproduce the vertex identities.
        for (i, r) in p.barycentric_gt().iter().enumerate() {
            let f = p.full.faces()[r.triangle as usize];
            let k = r.weights.iter().position(|&w| w == 1.0).unwrap();
            assert_eq!(f[k], p.partial_to_full[i]);
        }
    }

    #[test]
    fn pose_is_near_isometric_and_not_rigid() {
        let full = figure(4, &default_limbs()).unwrap();
        let posed = pose(&full, &default_bend()).unwrap();
        let (a, b) = (edge_lengths(&full), edge_lengths(&posed));
        let rel: Vec<f64> = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (y.2 - x.2).abs() / x.2)
            .collect();
        let mean = rel.iter().sum::<f64>() / rel.len() as f64;
        let max = rel.iter().cloned().fold(0.0, f64::max);
        assert!(mean < 0.01, "mean relative edge change {mean}");
        assert!(max < 0.35, "max relative edge change {max}");
        // It moved something substantially (not the identity).
        let moved = full
            .vertices()
            .iter()
            .zip(posed.vertices())
            .map(|(p, q)| {
                let d = add(*q, scale(*p, -1.0));
                dot(d, d).sqrt()
            })
            .fold(0.0, f64::max);
        assert!(moved > 0.3, "max displacement {moved}");
        assert!((posed.area() / full.area() - 1.0).abs() < 0.01);
    }

    #[test]
    fn bend_is_continuous_at_the_joint_and_length_preserving_on_the_axis() {
        let b = default_bend();
        let a = normalize(b.axis);
        let at = |t: f64| b.apply(scale(a, t));
        let d = |p: V3, q: V3| {
            let e = add(p, scale(q, -1.0));
            dot(e, e).sqrt()
        };
        assert!(d(at(b.joint), scale(a, b.joint)) < 1e-12);
        // Arc length along the bent axis equals the straight length.
        let n = 2000;
        let (t0, t1) = (b.joint, b.joint + 1.5 * b.length);
        let len: f64 = (0..n)
            .map(|i| {
                let (s0, s1) = (
                    t0 + (t1 - t0) * i as f64 / n as f64,
                    t0 + (t1 - t0) * (i + 1) as f64 / n as f64,
                );
                d(at(s0), at(s1))
            })
            .sum();
        assert!((len - (t1 - t0)).abs() < 1e-6, "{len}");
    }

    #[test]
    fn a_plane_that_keeps_nothing_is_an_error() {
        let m = generate::icosphere(2);
        assert!(cut_by_plane(&m, [0.0, 0.0, 1.0], 2.0).is_err());
    }
}
