//! Per-face and per-vertex geometry: angles, areas, Gaussian curvature, the scale-invariant
//! metric (and, for the pipeline, area-matched level sets and SHOT descriptors).

pub(crate) mod angles;
pub mod curvature;
pub(crate) mod level_set;
pub mod metric;
pub(crate) mod shot;

pub use angles::{corner_angles, face_areas};
pub use curvature::{gaussian_curvature, smooth_one_ring, smoothed_gaussian_curvature};
pub(crate) use level_set::area_matched_set;
pub use metric::{scale_invariant_factor, transfer_factor};
