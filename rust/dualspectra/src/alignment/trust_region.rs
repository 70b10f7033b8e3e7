//! Riemannian trust-region method on Euclidean space, as Manopt's `trustregions` (Absil,
//! Baker, Gallivan 2007); each subproblem is solved by Steihaug-Toint truncated CG. The model
//! Hessian is the one the objective returns with its gradient ([`Point::hessian`], e.g. a
//! Gauss-Newton model, no further evaluation) or, where it returns none, finite differences
//! of the gradient as Manopt does when no Hessian is given,
//! $H\eta \approx (\nabla f(x + t\eta) - \nabla f(x))/t$ with $t = 2^{-14}/\|\eta\|$ (one
//! evaluation per inner iteration).
//!
//! Hand-written because the crates we looked at need an explicit Hessian matrix
//! (`argmin`'s `TrustRegion` takes `Hessian` as a matrix type); here `n` is thousands and
//! only Hessian-vector products are affordable.

use crate::error::Result;

/// Parameters (Manopt's defaults where they exist).
#[derive(Debug, Clone)]
pub struct TrustRegionParams {
    pub max_iterations: usize,
    /// Hard budget on cost/gradient evaluations (each is a pair of eigensolves).
    pub max_evaluations: usize,
    /// Stop when $\|\nabla f\| \le$ this.
    pub gradient_tolerance: f64,
    /// Stop when the cost is below this (an exact match).
    pub cost_tolerance: f64,
    /// Inner truncated-CG iterations per step (each costs one evaluation).
    pub max_inner: usize,
    pub kappa: f64,
    pub theta: f64,
    /// Acceptance threshold on the model agreement $\rho$.
    pub rho_prime: f64,
    /// Largest trust radius $\bar\Delta$ (default $\sqrt n$) and the initial one ($\bar\Delta / 8$).
    pub delta_bar: Option<f64>,
    /// Initial trust radius (default $\bar\Delta / 8$); a resumed run passes the radius it
    /// stopped with ([`TrustRegionInfo::delta`]).
    pub initial_delta: Option<f64>,
    pub fd_step: f64,
}

impl Default for TrustRegionParams {
    fn default() -> Self {
        TrustRegionParams {
            max_iterations: 100,
            max_evaluations: 400,
            gradient_tolerance: 1e-10,
            cost_tolerance: 0.0,
            max_inner: 10,
            kappa: 0.1,
            theta: 1.0,
            rho_prime: 0.1,
            delta_bar: None,
            initial_delta: None,
            fd_step: 2f64.powi(-14),
        }
    }
}

/// Why and where the optimisation stopped.
#[derive(Debug, Clone, Default)]
pub struct TrustRegionInfo {
    pub iterations: usize,
    pub evaluations: usize,
    pub cost: f64,
    pub gradient_norm: f64,
    /// Cost after each outer iteration.
    pub history: Vec<f64>,
    pub stop_reason: &'static str,
    /// Trust radius at the end (to resume the run).
    pub delta: f64,
}

/// A model Hessian at a point, applied to a direction.
pub type HessianOperator = Box<dyn Fn(&[f64]) -> Vec<f64> + Send>;

/// The objective at one point: value, gradient and optionally a model Hessian there
/// (`None`: finite differences of the gradient).
pub struct Point {
    pub cost: f64,
    pub gradient: Vec<f64>,
    pub hessian: Option<HessianOperator>,
}

impl Point {
    /// Value and gradient only (the model Hessian by finite differences).
    #[cfg_attr(not(feature = "lab"), allow(dead_code))] // used by the lab and the tests
    pub fn new(cost: f64, gradient: Vec<f64>) -> Self {
        Point { cost, gradient, hessian: None }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
fn axpy(y: &mut [f64], a: f64, x: &[f64]) {
    y.iter_mut().zip(x).for_each(|(yi, xi)| *yi += a * xi);
}

/// Minimise `f` from `x0`. `f(x)` returns the [`Point`] at `x`; `on_iteration(iter, cost)` is
/// called after each outer step and may return `Err` (e.g. cancellation) or `Ok(false)` to stop.
pub fn minimize(
    mut f: impl FnMut(&[f64]) -> Result<Point>,
    x0: Vec<f64>,
    params: &TrustRegionParams,
    mut on_iteration: impl FnMut(usize, f64) -> Result<bool>,
) -> Result<(Vec<f64>, TrustRegionInfo)> {
    let n = x0.len();
    let delta_bar = params.delta_bar.unwrap_or((n as f64).sqrt());
    let mut delta = params.initial_delta.unwrap_or(delta_bar / 8.0).min(delta_bar);
    let mut x = x0;
    let Point { cost: mut fx, gradient: mut gx, hessian: mut hx } = f(&x)?;
    let mut info = TrustRegionInfo { evaluations: 1, ..Default::default() };
    info.stop_reason = "max iterations";
    for iter in 0..params.max_iterations {
        let gnorm = dot(&gx, &gx).sqrt();
        if gnorm <= params.gradient_tolerance {
            info.stop_reason = "gradient tolerance";
            break;
        }
        if fx <= params.cost_tolerance {
            info.stop_reason = "cost tolerance";
            break;
        }
        if info.evaluations + if hx.is_some() { 1 } else { 2 } > params.max_evaluations {
            info.stop_reason = "evaluation budget";
            break;
        }
        // --- Truncated CG on the model m(eta) = f + <g, eta> + 1/2 <eta, H eta>.
        let mut eta = vec![0.0; n];
        let mut h_eta = vec![0.0; n];
        let mut r = gx.clone();
        let mut z_r = dot(&r, &r);
        let mut d_pd = z_r;
        let mut e_pe = 0.0;
        let mut e_pd = 0.0;
        let mut mdelta: Vec<f64> = r.iter().map(|v| -v).collect();
        let norm_r0 = z_r.sqrt();
        let inner_budget = match hx {
            Some(_) => params.max_inner,
            None => params.max_inner.min(params.max_evaluations.saturating_sub(info.evaluations + 1)).max(1),
        };
        let mut hit_boundary = false;
        for _ in 0..inner_budget {
            let nd = dot(&mdelta, &mdelta).sqrt();
            if nd == 0.0 {
                break;
            }
            let h_d: Vec<f64> = match &hx {
                Some(h) => h(&mdelta),
                None => {
                    // Finite-difference Hessian-vector product along mdelta.
                    let t = params.fd_step / nd;
                    let mut xt = x.clone();
                    axpy(&mut xt, t, &mdelta);
                    let gt = f(&xt)?.gradient;
                    info.evaluations += 1;
                    gt.iter().zip(&gx).map(|(a, b)| (a - b) / t).collect()
                }
            };
            let d_hd = dot(&mdelta, &h_d);
            let alpha = z_r / d_hd;
            let e_pe_new = e_pe + 2.0 * alpha * e_pd + alpha * alpha * d_pd;
            if d_hd <= 0.0 || e_pe_new >= delta * delta {
                let tau = (-e_pd + (e_pd * e_pd + d_pd * (delta * delta - e_pe)).max(0.0).sqrt()) / d_pd;
                axpy(&mut eta, tau, &mdelta);
                axpy(&mut h_eta, tau, &h_d);
                hit_boundary = true;
                break;
            }
            e_pe = e_pe_new;
            axpy(&mut eta, alpha, &mdelta);
            axpy(&mut h_eta, alpha, &h_d);
            axpy(&mut r, alpha, &h_d);
            let norm_r = dot(&r, &r).sqrt();
            if norm_r <= norm_r0 * norm_r0.powf(params.theta).min(params.kappa) {
                break;
            }
            let z_r_old = z_r;
            z_r = dot(&r, &r);
            let beta = z_r / z_r_old;
            mdelta.iter_mut().zip(&r).for_each(|(d, ri)| *d = -ri + beta * *d);
            e_pd = beta * (e_pd + alpha * d_pd);
            d_pd = z_r + beta * beta * d_pd;
        }
        if dot(&eta, &eta) == 0.0 {
            // Degenerate model: fall back to a Cauchy-like steepest-descent step.
            let s = delta / gnorm;
            eta = gx.iter().map(|g| -s * g).collect();
            h_eta = vec![0.0; n];
        }
        // --- Accept or reject.
        let mut x_prop = x.clone();
        axpy(&mut x_prop, 1.0, &eta);
        let Point { cost: f_prop, gradient: g_prop, hessian: h_prop } = f(&x_prop)?;
        info.evaluations += 1;
        let model_decrease = -(dot(&gx, &eta) + 0.5 * dot(&eta, &h_eta));
        let rho_reg = f64::EPSILON.max(1e-3) * fx.abs().max(1.0);
        let rho = if model_decrease > 0.0 { (fx - f_prop + rho_reg) / (model_decrease + rho_reg) } else { -1.0 };
        let norm_eta = dot(&eta, &eta).sqrt();
        if rho < 0.25 || !f_prop.is_finite() {
            delta = 0.25 * norm_eta.min(delta);
        } else if rho > 0.75 && (hit_boundary || norm_eta >= 0.99 * delta) {
            delta = (2.0 * delta).min(delta_bar);
        }
        if rho > params.rho_prime && f_prop.is_finite() && f_prop <= fx {
            x = x_prop;
            fx = f_prop;
            gx = g_prop;
            hx = h_prop;
        }
        info.iterations = iter + 1;
        info.history.push(fx);
        if !on_iteration(iter, fx)? {
            info.stop_reason = "stopped by caller";
            break;
        }
        if delta < 1e-12 {
            info.stop_reason = "trust radius collapsed";
            break;
        }
    }
    info.cost = fx;
    info.delta = delta;
    info.gradient_norm = dot(&gx, &gx).sqrt();
    Ok((x, info))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rosenbrock's function at `x`: value, gradient and Hessian (row-major 2 x 2).
    fn rosenbrock(x: &[f64]) -> (f64, Vec<f64>, [f64; 4]) {
        let (a, b) = (x[0], x[1]);
        let f = (1.0 - a).powi(2) + 100.0 * (b - a * a).powi(2);
        let g = vec![-2.0 * (1.0 - a) - 400.0 * a * (b - a * a), 200.0 * (b - a * a)];
        let h = [2.0 - 400.0 * (b - 3.0 * a * a), -400.0 * a, -400.0 * a, 200.0];
        (f, g, h)
    }

    /// Rosenbrock in 2-D and a convex quadratic in 50-D reach their minima.
    #[test]
    fn minimises_rosenbrock_and_quadratic() {
        let rosen = |x: &[f64]| {
            let (f, g, _) = rosenbrock(x);
            Ok(Point::new(f, g))
        };
        let p = TrustRegionParams { max_iterations: 500, max_evaluations: 5000, ..Default::default() };
        let (x, info) = minimize(rosen, vec![-1.2, 1.0], &p, |_, _| Ok(true)).unwrap();
        assert!((x[0] - 1.0).abs() < 1e-4 && (x[1] - 1.0).abs() < 1e-4, "{x:?} {info:?}");

        let n = 50;
        let quad = |x: &[f64]| {
            let f: f64 = x.iter().enumerate().map(|(i, v)| (i + 1) as f64 * (v - 1.0).powi(2)).sum();
            let g = x.iter().enumerate().map(|(i, v)| 2.0 * (i + 1) as f64 * (v - 1.0)).collect();
            Ok(Point::new(f, g))
        };
        let p = TrustRegionParams { max_inner: 60, ..Default::default() };
        let (x, info) = minimize(quad, vec![0.0; n], &p, |_, _| Ok(true)).unwrap();
        assert!(info.cost < 1e-10, "{info:?}");
        assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-5));
        // Monotone: accepted steps never increase the cost.
        assert!(info.history.windows(2).all(|w| w[1] <= w[0]));
    }

    /// With the exact Hessian supplied, every iteration costs one evaluation (no finite
    /// differences) and Rosenbrock converges as well.
    #[test]
    fn a_supplied_hessian_costs_no_evaluations() {
        let rosen = |x: &[f64]| {
            let (f, g, h) = rosenbrock(x);
            let hessian: HessianOperator = Box::new(move |e: &[f64]| vec![h[0] * e[0] + h[1] * e[1], h[2] * e[0] + h[3] * e[1]]);
            Ok(Point { cost: f, gradient: g, hessian: Some(hessian) })
        };
        let p = TrustRegionParams { max_iterations: 500, max_evaluations: 5000, ..Default::default() };
        let (x, info) = minimize(rosen, vec![-1.2, 1.0], &p, |_, _| Ok(true)).unwrap();
        assert!((x[0] - 1.0).abs() < 1e-6 && (x[1] - 1.0).abs() < 1e-6, "{x:?} {info:?}");
        assert_eq!(info.evaluations, info.iterations + 1, "{info:?}");
    }
}
