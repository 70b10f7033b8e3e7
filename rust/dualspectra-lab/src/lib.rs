//! The lab of dualspectra (not published): what the product does not ship.
//!
//! - [`datasets`]: the benchmark datasets' layouts on disk (SHREC'16 CUTS/HOLES, PFARM,
//!   PFAUST), the dev sets ([`datasets::DEV_SETS`]) and where the data is.
//! - [`bench`]: the benchmark behind the CLI's `bench` command (scores per pair, summaries,
//!   the cumulative IoU plot).
//! - `examples/research/`: the studies behind the defaults (`cargo run -p dualspectra-lab
//!   --release --example research_<name> -- --help`).
//!
//! It reaches the pipeline's internals through the core's unstable `lab` feature.

pub mod args;
pub mod bench;
pub mod datasets;
