//! # dualspectra
//!
//! Partial shape localization by multi-metric Hamiltonian spectra matching (Bracha, Halimi,
//! Kimmel, "Partial Shape Similarity by Multi-metric Hamiltonian Spectra Matching"; the
//! method as this crate implements it: `docs/algorithm.md`).
//!
//! The pipeline is the module tree; each module uses only the ones before it (a test keeps
//! it so):
//!
//! [`mesh`] -> [`geometry`] (curvature, metric, SHOT) -> [`operators`] (stiffness, mass,
//! Dirichlet) -> [`spectra`] (eigensolvers) -> [`shape`] (a mesh with cached operators) ->
//! [`alignment`] (cost, optimiser, starts) -> [`region`] -> [`selection`] -> [`localizer`]
//! -> [`search`](mod@search) -> [`evaluation`].
//!
//! Entry points: [`Localizer`] (prepare a full shape once, locate many partials; save and
//! load it), [`localize`] (one call) and [`search()`] (rank several prepared full shapes for
//! a partial).

pub mod error;
pub mod progress;
pub mod mesh;
pub mod geometry;
pub mod operators;
pub mod spectra;
pub mod shape;
pub mod alignment;
pub mod region;
pub mod selection;
pub mod localizer;
pub mod search;
pub mod evaluation;

pub use error::{Error, MeshError, Result};
pub use localizer::{localize, localize_with_initial_regions, Candidate, Localization, Localizer, Mode, Options, Timings};
pub use mesh::TriMesh;
pub use progress::Progress;
pub use search::{search, search_with, Match};

/// The README's Rust example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;

/// Version of the core library (the crate version).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
