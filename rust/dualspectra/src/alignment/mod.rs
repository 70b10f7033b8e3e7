//! Alignment: the dual-spectra cost and gradient, the trust-region optimiser, the starts
//! and the choice among them (ALGORITHM.md "Cost and gradient" .. "Choosing among the starts").

pub mod cost;
pub mod trust_region;
pub mod starts;
pub mod selection;
pub mod shot;
pub mod descriptor_start;
