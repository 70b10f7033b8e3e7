//! Alignment: the dual-spectra cost and its gradient, the trust-region optimiser and the
//! starting potentials (docs/algorithm.md, "Cost and gradient", "Optimisation", "Starts").

pub mod cost;
pub mod scale;
pub mod starts;
pub mod trust_region;
