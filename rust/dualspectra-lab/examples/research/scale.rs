//! How well the partial's scale can be told from descriptors (a research harness for the
//! `scale = auto` option; docs/algorithm.md, "Units").
//!
//! `cargo run -p dualspectra-lab --release --example research_scale -- DATASET [STRIDE] [FACTOR_LOG10_RANGE] [SEED]`
//!
//! For each pair: the partial is multiplied by a random factor f (log-uniform in
//! 10^[-R, R]); the estimate scans area hypotheses a (the partial's area as a fraction of the
//! full shape's) and keeps the one whose SHOT descriptors, at the full shape's support radius,
//! lie nearest the full shape's. One line per pair: the true and estimated area fraction and
//! the factor's error (estimate / truth).

use dualspectra::lab::shot::{shot_keypoint_descriptors, DEFAULT_MIN_NEIGHBORS, DEFAULT_RADIUS_FRACTION};
use dualspectra_lab::datasets::Dataset;
use faer::Mat;

fn keypoints(n: usize, count: usize) -> Vec<u32> {
    let step = n.div_ceil(count).max(1);
    (0..n as u32).step_by(step).collect()
}

/// Mean over the partial's rows of the distance to the nearest full row.
fn mean_nearest(full: &Mat<f64>, partial: &Mat<f64>) -> f64 {
    let d = full.ncols();
    let mut total = 0.0;
    let mut dot = Mat::<f64>::zeros(full.nrows(), partial.nrows());
    faer::linalg::matmul::matmul(dot.as_mut(), faer::Accum::Replace, full.as_ref(), partial.transpose(), 1.0, faer::Par::Seq);
    let f2: Vec<f64> = (0..full.nrows()).map(|i| (0..d).map(|c| full[(i, c)].powi(2)).sum()).collect();
    for j in 0..partial.nrows() {
        let p2: f64 = (0..d).map(|c| partial[(j, c)].powi(2)).sum();
        let dist: Vec<f64> = (0..full.nrows()).map(|i| (f2[i] + p2 - 2.0 * dot[(i, j)]).max(0.0).sqrt()).collect();
        let best = dist.iter().cloned().fold(f64::INFINITY, f64::min);
        if std::env::var("SCALE_RATIO").is_ok() {
            let mean = dist.iter().sum::<f64>() / dist.len() as f64;
            total += best / mean.max(1e-300);
        } else {
            total += best;
        }
    }
    total / partial.nrows() as f64
}

/// Rows side by side.
fn concat(parts: &[Mat<f64>]) -> Mat<f64> {
    let rows = parts[0].nrows();
    let cols: usize = parts.iter().map(|m| m.ncols()).sum();
    Mat::from_fn(rows, cols, |i, j| {
        let mut j = j;
        for m in parts {
            if j < m.ncols() {
                return m[(i, j)];
            }
            j -= m.ncols();
        }
        0.0
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let root = args.get(1).ok_or("usage: research_scale DATASET [STRIDE] [LOG10_RANGE] [SEED]")?;
    let stride: usize = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(1).max(1);
    let range: f64 = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(3.0);
    let mut state: u64 = args.get(4).map(|s| s.parse()).transpose()?.unwrap_or(1);
    let mut uniform = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let hypotheses: Vec<f64> = (0..=24).map(|i| 10f64.powf(-2.0 + 2.0 * i as f64 / 24.0)).collect();
    println!("pair true_fraction estimated_fraction factor_error seconds");
    let mut errors = Vec::new();
    let mut cache: Option<(std::path::PathBuf, Mat<f64>)> = None;
    for pair in Dataset::open(root)?.pairs()?.iter().step_by(stride) {
        let data = pair.load()?;
        let t0 = std::time::Instant::now();
        let norm = 1.0 / data.full.area().sqrt();
        let full_n = data.full.map_positions(|p| p.map(|c| c * norm))?;
        let radius = DEFAULT_RADIUS_FRACTION;
        let radii: Vec<f64> = std::env::var("SCALE_RADII").unwrap_or("1".into()).split(',').map(|x| x.parse().unwrap()).collect();
        if cache.as_ref().map(|(p, _)| p != &pair.full).unwrap_or(true) {
            let kp = keypoints(full_n.n_vertices(), 2000);
            let all: Vec<Mat<f64>> = radii.iter().map(|r| shot_keypoint_descriptors(&full_n, &kp, radius * r, DEFAULT_MIN_NEIGHBORS).unwrap()).collect();
            cache = Some((pair.full.clone(), concat(&all)));
        }
        let full_desc = &cache.as_ref().unwrap().1;
        let true_fraction = data.partial.area() * norm * norm;
        let f = 10f64.powf(range * (2.0 * uniform() - 1.0));
        let mut given = data.partial.map_positions(|p| p.map(|c| c * f * norm))?;
        if let Ok(cap) = std::env::var("SCALE_CAP").map(|v| v.parse::<usize>().unwrap()) {
            if given.n_vertices() > cap {
                given = dualspectra::lab::decimate::decimate(&given, cap as f64 / given.n_vertices() as f64)?.mesh;
            }
        }
        let given_area = given.area();
        let kp = keypoints(given.n_vertices(), 200);
        let costs: Vec<f64> = hypotheses
            .iter()
            .map(|&a| {
                let s = (a / given_area).sqrt();
                let m = given.map_positions(|p| p.map(|c| c * s)).unwrap();
                let all: Vec<Mat<f64>> = radii.iter().map(|r| shot_keypoint_descriptors(&m, &kp, radius * r, DEFAULT_MIN_NEIGHBORS).unwrap()).collect();
                mean_nearest(full_desc, &concat(&all))
            })
            .collect();
        let best = (0..costs.len()).min_by(|&a, &b| costs[a].total_cmp(&costs[b])).unwrap();
        let est = hypotheses[best];
        let error = (est / true_fraction).sqrt();
        errors.push(error.ln().abs());
        println!("{} {true_fraction:.4} {est:.4} {error:.3} {:.2}  {}", pair.name, t0.elapsed().as_secs_f64(),
            costs.iter().map(|c| format!("{c:.3}")).collect::<Vec<_>>().join(" "));
    }
    errors.sort_by(f64::total_cmp);
    let median = errors[errors.len() / 2].exp();
    let within = |x: f64| errors.iter().filter(|&&e| e <= x.ln()).count() as f64 / errors.len() as f64;
    println!("median factor error x{median:.3}; within 10%: {:.2}; within 25%: {:.2}", within(1.1), within(1.25));
    Ok(())
}
