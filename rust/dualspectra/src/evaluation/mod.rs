//! Evaluation: region scores (precision, recall, IoU, cumulative IoU), spectral shape
//! similarity (dual ShapeDNA + MDS, paper section 3) and a procedural articulated test pair
//! with exact ground truth. (The benchmark datasets' layouts are in the `dualspectra-lab`
//! crate.)

pub mod metrics;
pub mod similarity;
pub mod synthetic;

pub use metrics::{
    area_scores, cumulative_iou, scores, symmetry_aware, weighted_scores, CumulativeIou, Scores,
};
