//! Evaluation: region scores (precision, recall, IoU, cumulative IoU), benchmark dataset
//! loading (SHREC'16 layout), spectral shape similarity (dual ShapeDNA + MDS, paper
//! section 3) and a procedural articulated test pair with exact ground truth.

pub mod datasets;
pub mod metrics;
pub mod similarity;
pub mod synthetic;

pub use metrics::{
    area_scores, cumulative_iou, scores, symmetry_aware, weighted_scores, CumulativeIou, Scores,
};
