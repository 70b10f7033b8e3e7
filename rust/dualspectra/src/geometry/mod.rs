//! Per-face and per-vertex geometry: angles, areas, Gaussian curvature, the scale-invariant metric.

pub mod angles;
pub mod curvature;
pub mod metric;

pub use angles::{corner_angles, face_areas};
pub use curvature::{gaussian_curvature, smooth_one_ring, smoothed_gaussian_curvature};
pub use metric::{scale_invariant_factor, transfer_factor};
