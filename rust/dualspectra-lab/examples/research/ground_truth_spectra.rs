//! How well the ground-truth region reproduces the partial's spectra (a development tool):
//! per SHREC'16 pair, the alignment cost $\sum_i ((\lambda_i - \mu_i)/\mu_i)^2$ of the step
//! potential $\tau(1 - G)$ on the (decimated) full shape against the partial's Dirichlet
//! spectra, regular and scale-invariant, $k = 20$, $\tau = 50\,\mu_k$.
//!
//! `cargo run -p dualspectra-lab --release --example research_ground_truth_spectra -- DATASET [STRIDE] [OFFSET] [--res N] [--si local]`
//! `--res`: optimisation mesh size (default 1000; 0: full resolution). `--si local`: the
//! scale-invariant factor from the decimated mesh's own curvature instead of the one carried
//! from the full resolution (`geometry::metric::transfer_factor`, what the localizer does).
//!
//! The ground-truth mask (triangles hit by the partial's vertices) has holes where the partial
//! is coarser than the full shape; it is closed as the localizer closes its regions.
use dualspectra_lab::datasets::Dataset;
use dualspectra::geometry::metric::{transfer_factor, DEFAULT_ALPHA, DEFAULT_EPS};
use dualspectra::shape::{Metric, Shape};
use dualspectra::spectra::{EigenParams, HamiltonianSolver};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = dualspectra_lab::args::from_env();
    let res: usize = dualspectra_lab::args::take_value(&mut args, "--res")?.unwrap_or(1000);
    let local_si = match dualspectra_lab::args::take_value::<String>(&mut args, "--si")?.as_deref() {
        None | Some("transferred") => false,
        Some("local") => true,
        Some(other) => return Err(format!("--si {other}: expected local or transferred").into()),
    };
    let root = args.first().ok_or("usage: research_ground_truth_spectra DATASET [STRIDE] [OFFSET] [--res N] [--si local]")?;
    let stride: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(1);
    let offset: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(0);
    let k = 20;
    let data = Dataset::open(root)?;
    let (mut total_regular, mut total_si, mut n) = (0.0, 0.0, 0);
    for pair in data.pairs()?.iter().skip(offset).step_by(stride) {
        let p = pair.load()?;
        let scale = 1.0 / p.full.area().sqrt();
        let full = p.full.map_positions(|q| q.map(|c| c * scale))?;
        let part = Shape::new(p.partial.map_positions(|q| q.map(|c| c * scale))?);
        let neighbors = dualspectra::mesh::topology::vertex_neighbors(&full);
        let gt = dualspectra::lab::region::closing::close(&p.gt, &neighbors, dualspectra::lab::region::CLOSING_RINGS)?;
        let (shape, gt) = if res > 0 && res < full.n_vertices() {
            let d = dualspectra::lab::decimate::decimate(&full, res as f64 / full.n_vertices() as f64)?;
            let gt: Vec<bool> = d.original_vertex.iter().map(|&j| gt[j as usize]).collect();
            let shape = if local_si {
                Shape::new(d.mesh)
            } else {
                let fine = Shape::new(full.clone());
                let cell = dualspectra::lab::nearest::nearest_vertices(d.mesh.vertices(), full.vertices())?;
                let fallback: Vec<f64> = d.original_vertex.iter().map(|&j| fine.scale_invariant_factor()[j as usize]).collect();
                let s = transfer_factor(fine.scale_invariant_factor(), fine.mass(), &cell, &fallback);
                Shape::with_scale_invariant_factor(d.mesh, DEFAULT_ALPHA, DEFAULT_EPS, s)?
            };
            (shape, gt)
        } else {
            (Shape::new(full), gt)
        };
        let mut line = format!("{:<24} partial area {:.3} region area {:.3}", pair.name, part.mesh().area(),
            shape.mass().iter().zip(&gt).filter(|(_, &g)| g).map(|(a, _)| a).sum::<f64>());
        for metric in [Metric::Regular, Metric::ScaleInvariant] {
            let mu = part.dirichlet_spectrum(metric, k)?.values;
            let tau = 50.0 * mu[k - 1];
            let mut solver = HamiltonianSolver::new(shape.stiffness(), shape.metric_mass(metric), EigenParams { k, ..EigenParams::default() })?;
            let v: Vec<f64> = gt.iter().map(|&g| if g { 0.0 } else { tau }).collect();
            let lambda = &solver.solve_cold(&v)?.values;
            let cost: f64 = lambda.iter().zip(&mu).map(|(l, m)| ((l - m) / m).powi(2)).sum();
            match metric {
                Metric::Regular => total_regular += cost,
                Metric::ScaleInvariant => total_si += cost,
            }
            line += &format!(" | {metric:?} cost {cost:.3}");
        }
        println!("{line}");
        n += 1;
    }
    println!("MEAN over {n}: regular {:.3} scale-invariant {:.3}", total_regular / n as f64, total_si / n as f64);
    Ok(())
}
