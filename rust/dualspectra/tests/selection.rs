//! Laws of the choice among candidate regions (selection) on an undeformed cut.

use dualspectra::lab::alignment::cost::{AlignmentCost, SpectrumTerm};
use dualspectra::lab::selection::{partial_signatures, selection_scores, signatures_from_spectra};
use dualspectra::lab::shot::{shot_descriptors, DEFAULT_MIN_NEIGHBORS, DEFAULT_RADIUS_FRACTION};
use dualspectra::mesh::generate::icosphere;
use dualspectra::shape::{Metric, Shape};
use dualspectra::TriMesh;

/// A unit-area icosphere with two bumps (so the two caps below differ).
fn bumpy_sphere() -> TriMesh {
    let bumps = [([0.0, 0.0, 1.0], 0.6, 0.08), ([0.0, -1.0, 0.2], 0.5, 0.12)];
    let m = icosphere(3)
        .map_positions(|p| {
            let r: f64 = 1.0
                + bumps
                    .iter()
                    .map(|(c, h, s)| h * (-(0..3).map(|i| (p[i] - c[i]).powi(2)).sum::<f64>() / (2.0 * s)).exp())
                    .sum::<f64>();
            p.map(|x| x * r)
        })
        .unwrap();
    let s = 1.0 / m.area().sqrt();
    m.map_positions(|p| p.map(|x| x * s)).unwrap()
}

/// The bumpy sphere cut at its equator: the top cap as the partial, everything the
/// selection's scores need, and the two candidate regions (the true top, the wrong bottom).
struct TopCut {
    full_shape: Shape,
    d_full: faer::Mat<f64>,
    metrics: [Metric; 2],
    targets: Vec<faer::Mat<f64>>,
    mu: Vec<Vec<f64>>,
    heights: Vec<f64>,
    regions: Vec<Vec<bool>>,
}

impl TopCut {
    /// With the partial's `k` lowest Dirichlet eigenvalues per metric.
    fn new(k: usize) -> Self {
        let full = bumpy_sphere();
        let v = full.vertices();
        let top: Vec<bool> = v.iter().map(|p| p[2] > 0.03).collect();
        let bottom: Vec<bool> = v.iter().map(|p| p[2] < -0.03).collect();
        let faces: Vec<[u32; 3]> = full.faces().iter().filter(|f| f.iter().all(|&i| top[i as usize])).copied().collect();
        let (part, _) = TriMesh::new_dropping_isolated(v.to_vec(), faces).unwrap();
        let part_shape = Shape::new(part.clone());
        let metrics = [Metric::Regular, Metric::ScaleInvariant];
        let mu: Vec<Vec<f64>> = metrics.iter().map(|&m| part_shape.dirichlet_spectrum(m, k).unwrap().values).collect();
        let heights: Vec<f64> = mu.iter().map(|m| 50.0 * m[k - 1]).collect();
        let d_full = shot_descriptors(&full, DEFAULT_RADIUS_FRACTION, DEFAULT_MIN_NEIGHBORS).unwrap();
        let d_part = shot_descriptors(&part, DEFAULT_RADIUS_FRACTION, DEFAULT_MIN_NEIGHBORS).unwrap();
        let targets = partial_signatures(&part_shape, &d_part, &metrics).unwrap();
        TopCut { full_shape: Shape::new(full), d_full, metrics, targets, mu, heights, regions: vec![top, bottom] }
    }

    /// [`selection_scores`] of the two regions, each solve seeded by `seeds` (none: cold).
    fn scores(&self, seeds: &[Vec<Option<faer::Mat<f64>>>]) -> dualspectra::lab::selection::RegionScores {
        selection_scores(&self.full_shape, &self.d_full, &self.metrics, &self.targets, &self.mu, &self.heights, &self.regions, seeds).unwrap()
    }
}

#[test]
fn the_true_region_reproduces_the_partials_spectra_and_descriptors() {
    let k = 10;
    let cut = TopCut::new(k);
    let s = cut.scores(&[]);
    let (rc, desc) = (&s.region_cost, &s.descriptors);
    eprintln!("region cost {rc:?}, descriptor score {desc:?}");
    // The true region's step potential gives the partial's spectra up to the leak through the
    // finite wall (50 mu_k) and the region's boundary ring, which the partial holds at zero
    // (Dirichlet) but the mask leaves open: measured 15% RMS over the 2k eigenvalues, bound 20%.
    // (Walling that ring gives 2% here, but chose worse on SHREC'16 pairs at 1000 vertices,
    // where one ring is a large part of a limb: mean IoU 0.661 against 0.695 on 15 pairs.)
    assert!(rc[0] < 2.0 * k as f64 * 0.2f64.powi(2), "true region cost {}", rc[0]);
    assert!(rc[1] > 1.5 * rc[0], "wrong region cost {} vs true {}", rc[1], rc[0]);
    assert!(3.0 * desc[0] < desc[1], "descriptor scores {desc:?}");
    assert!(rc.iter().chain(desc).all(|x| x.is_finite() && *x >= 0.0));
}

#[test]
fn seeded_selection_solves_score_as_cold_ones() {
    let cut = TopCut::new(10);
    // A run's last blocks: the relaxed potential of a region (tanh(-2) inside, tanh(2) out).
    let blocks_near = |region: &[bool]| {
        let terms = cut.metrics.iter().zip(&cut.mu).zip(&cut.heights).map(|((&metric, m), &h)| SpectrumTerm { metric, target: m.clone(), height: 0.5 * h }).collect();
        let mut cost = AlignmentCost::new(&cut.full_shape, terms).unwrap();
        cost.evaluate(&region.iter().map(|&inside| if inside { -2.0 } else { 2.0 }).collect::<Vec<_>>()).unwrap();
        cost.blocks()
    };
    let cold = cut.scores(&[]);
    // Each region seeded by its own run, then each by the *other* region's (eigenvectors
    // living elsewhere: the inertia check must catch what they miss).
    let own = vec![blocks_near(&cut.regions[0]), blocks_near(&cut.regions[1])];
    let crossed = vec![own[1].clone(), own[0].clone()];
    for seeds in [own, crossed] {
        let seeded = cut.scores(&seeds);
        for (a, b) in cold.region_cost.iter().zip(&seeded.region_cost).chain(cold.descriptors.iter().zip(&seeded.descriptors)) {
            // Both solved to a relative residual of ~1e-4: eigenvalues to ~1e-8, the
            // descriptor projections (squared eigenfunctions) to ~1e-4.
            assert!((a - b).abs() <= 1e-3 * a.abs().max(1e-12), "cold {a} against seeded {b}");
        }
    }
}

#[test]
fn signatures_from_an_already_solved_spectrum_equal_those_solved_afresh() {
    let full = bumpy_sphere();
    let v = full.vertices();
    let faces: Vec<[u32; 3]> = full.faces().iter().filter(|f| f.iter().all(|&i| v[i as usize][2] > 0.03)).copied().collect();
    let (part, _) = TriMesh::new_dropping_isolated(v.to_vec(), faces).unwrap();
    let shape = Shape::new(part.clone());
    let d_part = shot_descriptors(&part, DEFAULT_RADIUS_FRACTION, DEFAULT_MIN_NEIGHBORS).unwrap();
    let metrics = [Metric::Regular, Metric::ScaleInvariant];
    let fresh = partial_signatures(&shape, &d_part, &metrics).unwrap();
    // The target's spectra (k = 12 > 5) reused, and one too short to reuse (k = 3: solved again).
    let long: Vec<_> = metrics.iter().map(|&m| shape.dirichlet_spectrum(m, 12).unwrap()).collect();
    let short = shape.dirichlet_spectrum(Metric::Regular, 3).unwrap();
    let known = [(Metric::Regular, Some(&long[0])), (Metric::ScaleInvariant, Some(&long[1]))];
    let reused = signatures_from_spectra(&shape, &d_part, &known).unwrap();
    let fallback = signatures_from_spectra(&shape, &d_part, &[(Metric::Regular, Some(&short)), (Metric::ScaleInvariant, None)]).unwrap();
    for (a, b) in fresh.iter().zip(&reused).chain(fresh.iter().zip(&fallback)) {
        assert_eq!((a.nrows(), a.ncols()), (b.nrows(), b.ncols()));
        let scale = (0..a.nrows()).flat_map(|i| (0..a.ncols()).map(move |j| (i, j))).map(|(i, j)| a[(i, j)].abs()).fold(0.0, f64::max);
        for i in 0..a.nrows() {
            for j in 0..a.ncols() {
                // Squared eigenfunctions: the sign convention does not matter; eigensolver
                // tolerance does (the eigenvalues here are simple).
                assert!((a[(i, j)] - b[(i, j)]).abs() <= 1e-6 * scale, "({i},{j}): {} vs {}", a[(i, j)], b[(i, j)]);
            }
        }
    }
}
