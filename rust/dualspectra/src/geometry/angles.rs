//! Corner angles and face areas.

use crate::mesh::{triangle_area, TriMesh};

/// Interior angle at each corner: `angles[f][c]` is the angle of face `f` at vertex `F[f][c]`,
/// computed as `atan2(|u x v|, u . v)` (accurate for small and obtuse angles).
pub fn corner_angles(mesh: &TriMesh) -> Vec<[f64; 3]> {
    let v = mesh.vertices();
    mesh.faces()
        .iter()
        .map(|f| {
            let mut a = [0.0; 3];
            for c in 0..3 {
                let p = v[f[c] as usize];
                let q = v[f[(c + 1) % 3] as usize];
                let r = v[f[(c + 2) % 3] as usize];
                a[c] = angle_between(sub(q, p), sub(r, p));
            }
            a
        })
        .collect()
}

/// Area of every face.
pub fn face_areas(mesh: &TriMesh) -> Vec<f64> {
    let v = mesh.vertices();
    mesh.faces().iter().map(|f| triangle_area(v[f[0] as usize], v[f[1] as usize], v[f[2] as usize])).collect()
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
pub(crate) fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
fn angle_between(u: [f64; 3], v: [f64; 3]) -> f64 {
    norm(cross(u, v)).atan2(dot(u, v))
}

/// Barycentric vertex areas $a_i = \tfrac13 \sum_{f \ni i} |f|$ (the lumped mass,
/// [`crate::operators::lumped_mass`], is their diagonal matrix).
pub fn vertex_areas(mesh: &crate::mesh::TriMesh) -> Vec<f64> {
    let mut a = vec![0.0; mesh.n_vertices()];
    for (f, area) in mesh.faces().iter().zip(face_areas(mesh)) {
        for &i in f {
            a[i as usize] += area / 3.0;
        }
    }
    a
}
