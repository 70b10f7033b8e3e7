//! The scale-invariant metric $\tilde g = s\,g$ with $s_i = (\sqrt{\epsilon + K_i^2})^{\alpha}$
//! (paper eq. 4 relaxed, ALGORITHM.md "Discrete operators"). $\alpha = 0$ is the regular
//! metric, $\alpha = 1$ the full scale-invariant one.
//!
//! Units: $K$ scales as 1/length^2, so $\epsilon$ is in 1/length^4. [`scale_invariant_factor`]
//! takes $K$ as given; callers that want unit-independence normalise the mesh first (the
//! localizer scales both shapes so that the full one has unit area).

/// Paper defaults.
pub const DEFAULT_ALPHA: f64 = 0.33;
pub const DEFAULT_EPS: f64 = 1e-8;

/// $s_i = (\epsilon + K_i^2)^{\alpha/2}$ per vertex.
pub fn scale_invariant_factor(curvature: &[f64], alpha: f64, eps: f64) -> Vec<f64> {
    curvature.iter().map(|k| (eps + k * k).powf(alpha / 2.0)).collect()
}
