//! The scale-invariant factor carried from a fine mesh to a decimated one
//! (`geometry::metric::transfer_factor`, used by the localizer for its optimisation mesh),
//! against the analytic factor of an ellipsoid.

use dualspectra::geometry::metric::{scale_invariant_factor, transfer_factor, DEFAULT_ALPHA, DEFAULT_EPS};
use dualspectra::geometry::smoothed_gaussian_curvature;
use dualspectra::lab::decimate::decimate;
use dualspectra::mesh::generate::icosphere;
use dualspectra::lab::nearest::nearest_vertices;
use dualspectra::operators::lumped_mass;
use dualspectra::shape::{Metric, Shape};

const AXES: [f64; 3] = [1.0, 0.6, 0.35];

/// Gaussian curvature of the ellipsoid $x^2/a^2 + y^2/b^2 + z^2/c^2 = 1$ at a point of it:
/// $K = 1 / (a^2 b^2 c^2 (x^2/a^4 + y^2/b^4 + z^2/c^4)^2)$.
fn ellipsoid_curvature(p: [f64; 3]) -> f64 {
    let [a, b, c] = AXES;
    let q = p[0].powi(2) / a.powi(4) + p[1].powi(2) / b.powi(4) + p[2].powi(2) / c.powi(4);
    1.0 / ((a * b * c).powi(2) * q * q)
}

/// Area-weighted relative RMS error of `s` against the analytic factor at the mesh's vertices.
fn relative_error(s: &[f64], vertices: &[[f64; 3]], mass: &[f64]) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for ((&si, &p), &a) in s.iter().zip(vertices).zip(mass) {
        let exact = scale_invariant_factor(&[ellipsoid_curvature(p)], DEFAULT_ALPHA, DEFAULT_EPS)[0];
        num += a * ((si - exact) / exact).powi(2);
        den += a;
    }
    (num / den).sqrt()
}

#[test]
fn transferred_factor_is_closer_to_the_analytic_one_than_the_coarse_estimate() {
    let fine = icosphere(5).map_positions(|p| [p[0] * AXES[0], p[1] * AXES[1], p[2] * AXES[2]]).unwrap();
    let coarse = decimate(&fine, 1000.0 / fine.n_vertices() as f64).unwrap();
    let fine_s = scale_invariant_factor(&smoothed_gaussian_curvature(&fine), DEFAULT_ALPHA, DEFAULT_EPS);
    let fine_mass = lumped_mass(&fine);
    let cell = nearest_vertices(coarse.mesh.vertices(), fine.vertices()).unwrap();
    let fallback: Vec<f64> = coarse.original_vertex.iter().map(|&j| fine_s[j as usize]).collect();
    let transferred = transfer_factor(&fine_s, &fine_mass, &cell, &fallback);
    let local = scale_invariant_factor(&smoothed_gaussian_curvature(&coarse.mesh), DEFAULT_ALPHA, DEFAULT_EPS);

    let coarse_mass = lumped_mass(&coarse.mesh);
    let e_fine = relative_error(&fine_s, fine.vertices(), &fine_mass);
    let e_transferred = relative_error(&transferred, coarse.mesh.vertices(), &coarse_mass);
    let e_local = relative_error(&local, coarse.mesh.vertices(), &coarse_mass);
    eprintln!("relative RMS error of s: fine {e_fine:.4}, transferred {e_transferred:.4}, coarse estimate {e_local:.4}");
    assert!(e_fine < 0.05, "fine estimate off by {e_fine}");
    assert!(e_transferred < 0.03, "transferred factor off by {e_transferred}");
    assert!(e_transferred < e_local, "transfer ({e_transferred}) not better than the coarse estimate ({e_local})");

    // The shape built with it uses it for its scale-invariant mass.
    let shape = Shape::with_scale_invariant_factor(coarse.mesh.clone(), DEFAULT_ALPHA, DEFAULT_EPS, transferred.clone()).unwrap();
    for ((m, a), s) in shape.metric_mass(Metric::ScaleInvariant).iter().zip(shape.mass()).zip(&transferred) {
        assert!((m - a * s).abs() <= 1e-15 * m.abs());
    }
}

#[test]
fn a_given_factor_must_fit_the_mesh() {
    let mesh = icosphere(1);
    let n = mesh.n_vertices();
    let err = |f: Vec<f64>| Shape::with_scale_invariant_factor(mesh.clone(), DEFAULT_ALPHA, DEFAULT_EPS, f).unwrap_err().to_string();
    assert!(err(vec![1.0; n - 1]).contains("entries"));
    let mut bad = vec![1.0; n];
    bad[3] = 0.0;
    assert!(err(bad.clone()).contains("vertex 3"));
    bad[3] = f64::NAN;
    assert!(err(bad).contains("vertex 3"));
}
