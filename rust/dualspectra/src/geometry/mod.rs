//! Per-face and per-vertex geometry: angles, areas, Gaussian curvature, the scale-invariant
//! metric, area-matched level sets and SHOT descriptors.

pub mod angles;
pub mod curvature;
pub mod level_set;
pub mod metric;
pub mod shot;

pub use angles::{corner_angles, face_areas};
pub use curvature::{gaussian_curvature, smooth_one_ring, smoothed_gaussian_curvature};
pub use level_set::area_matched_set;
pub use metric::{scale_invariant_factor, transfer_factor};
