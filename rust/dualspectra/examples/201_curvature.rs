//! Chapter 2, geometry: Gaussian curvature (angle defect over the barycentric area) and the
//! scale-invariant metric factor $s = (\epsilon + K^2)^{\alpha/2}$ built on it.
//!
//! `cargo run --example 201_curvature`: on a unit sphere $K = 1$ everywhere, so the total
//! curvature is $4\pi$ (Gauss-Bonnet).

use dualspectra::geometry::metric::{scale_invariant_factor, DEFAULT_ALPHA, DEFAULT_EPS};
use dualspectra::geometry::{gaussian_curvature, smoothed_gaussian_curvature};
use dualspectra::mesh::generate::icosphere;
use dualspectra::operators::lumped_mass;

fn main() {
    let sphere = icosphere(4);
    let k = gaussian_curvature(&sphere);
    let area = lumped_mass(&sphere);
    let total: f64 = k.iter().zip(&area).map(|(k, a)| k * a).sum();
    let mean = k.iter().sum::<f64>() / k.len() as f64;
    println!("unit sphere, {} vertices: mean K {mean:.4} (exact 1), total curvature {total:.6} (4 pi = {:.6})", sphere.n_vertices(), 4.0 * std::f64::consts::PI);
    let s = scale_invariant_factor(&smoothed_gaussian_curvature(&sphere), DEFAULT_ALPHA, DEFAULT_EPS);
    println!("scale-invariant factor s = (eps + K^2)^(alpha/2) with alpha = {DEFAULT_ALPHA}: mean {:.4}", s.iter().sum::<f64>() / s.len() as f64);
}
