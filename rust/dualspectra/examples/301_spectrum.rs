//! Chapter 3, spectra: the Dirichlet Laplace-Beltrami eigenvalues of a shape, in the regular
//! and the scale-invariant metric: what the localizer matches.
//!
//! `cargo run --example 301_spectrum`: a unit square with Dirichlet boundary has eigenvalues
//! $\pi^2 (m^2 + n^2)$: $2\pi^2 \approx 19.74$, $5\pi^2 \approx 49.35$ (twice), ...

use dualspectra::mesh::generate::grid;
use dualspectra::shape::{Metric, Shape};

fn main() -> dualspectra::Result<()> {
    let square = Shape::new(grid(1.0, 1.0, 40, 40));
    let regular = square.dirichlet_spectrum(Metric::Regular, 6)?;
    let exact = [2.0, 5.0, 5.0, 8.0, 10.0, 10.0].map(|m| m * std::f64::consts::PI.powi(2));
    for (i, (l, e)) in regular.values.iter().zip(exact).enumerate() {
        println!("lambda_{i} = {l:8.3}   exact {e:8.3}");
    }
    let si = square.dirichlet_spectrum(Metric::ScaleInvariant, 6)?;
    println!("scale-invariant metric: {:?}", si.values.iter().map(|x| (x * 1e3).round() / 1e3).collect::<Vec<_>>());
    Ok(())
}
