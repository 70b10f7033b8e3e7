//! # dualspectra
//!
//! Partial shape localization by multi-metric Hamiltonian spectra matching
//! (Bracha, Halimi, Kimmel; the algorithm is restated in `shared/paper/ALGORITHM.md`).
//!
//! The pipeline is the module tree, each module using only the ones above it:
//!
//! `mesh` -> `geometry` (curvature, metric) -> `operators` (stiffness, mass,
//! Dirichlet, Hamiltonian) -> `spectra` (eigensolver) -> `alignment` (cost,
//! gradient, optimiser, starts, SHOT, selection) -> `region` -> `evaluation`.
//!
//! The one-call entry point is [`localize`].

pub mod error;
pub mod progress;
pub mod mesh;
pub mod geometry;
pub mod operators;
pub mod spectra;
pub mod shape;
pub mod alignment;
pub mod region;
pub mod localize;
pub mod evaluation;
mod pipeline;

pub use error::{Error, MeshError, Result};
pub use mesh::TriMesh;
pub use progress::Progress;
pub use localize::{
    localize, localize_with_initial_regions, Candidate, Localization, Mode, Options, Selection, StartShape, Timings,
};

/// Version of the core library (the crate version).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
