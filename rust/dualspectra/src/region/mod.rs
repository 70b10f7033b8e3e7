//! From an optimised potential to a vertex region: eigenvector energy, thresholding, closing, transfer.

pub mod boundary;
pub mod closing;
pub mod energy;

/// Rings of the morphological closing applied on the full shape (docs/algorithm.md: grow 4, shrink 4).
pub const CLOSING_RINGS: usize = 4;
