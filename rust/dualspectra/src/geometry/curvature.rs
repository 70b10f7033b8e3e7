//! Discrete Gaussian curvature by the angle defect (Gauss-Bonnet), and one-ring smoothing.
//!
//! $K_i = (2\pi - \sum_{f \ni i} \theta_{f,i}) / a_i$ at interior vertices and
//! $K_i = (\pi - \sum_{f \ni i} \theta_{f,i}) / a_i$ on the boundary, with $a_i$ the lumped
//! (barycentric) area, one third of the incident faces' areas (docs/algorithm.md, "Discrete operators").
//! On a closed mesh $\sum_i K_i a_i = 2\pi\chi$.

use super::angles::{corner_angles, face_areas};
use crate::mesh::{topology, TriMesh};
use std::f64::consts::PI;

/// Angle defect per vertex, *not* divided by area: $2\pi - \sum\theta$ (interior), $\pi - \sum\theta$ (boundary).
pub fn angle_defect(mesh: &TriMesh) -> Vec<f64> {
    let boundary = topology::boundary_vertex_mask(mesh);
    let mut sum = vec![0.0; mesh.n_vertices()];
    for (f, a) in mesh.faces().iter().zip(corner_angles(mesh)) {
        for c in 0..3 {
            sum[f[c] as usize] += a[c];
        }
    }
    sum.iter().zip(&boundary).map(|(&s, &b)| if b { PI - s } else { 2.0 * PI - s }).collect()
}

/// Pointwise Gaussian curvature $K_i$ = angle defect / lumped area (units 1/length^2).
pub fn gaussian_curvature(mesh: &TriMesh) -> Vec<f64> {
    let areas = crate::geometry::angles::vertex_areas(mesh);
    angle_defect(mesh).iter().zip(&areas).map(|(d, a)| d / a).collect()
}

/// One-ring mean: each value becomes the mean of its neighbours' values (the vertex itself excluded),
/// as in docs/algorithm.md ("each K_i becomes the mean of K over its one-ring neighbours").
pub fn smooth_one_ring(mesh: &TriMesh, values: &[f64]) -> Vec<f64> {
    topology::vertex_neighbors(mesh)
        .iter()
        .map(|nb| nb.iter().map(|&j| values[j as usize]).sum::<f64>() / nb.len() as f64)
        .collect()
}

/// [`gaussian_curvature`] followed by [`smooth_one_ring`]: the curvature the scale-invariant metric uses.
pub fn smoothed_gaussian_curvature(mesh: &TriMesh) -> Vec<f64> {
    smooth_one_ring(mesh, &gaussian_curvature(mesh))
}

#[doc(hidden)]
pub fn _face_areas(mesh: &TriMesh) -> Vec<f64> {
    face_areas(mesh)
}
