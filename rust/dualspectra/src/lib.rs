//! # dualspectra
//!
//! Partial shape localization by multi-metric Hamiltonian spectra matching (Bensaïd,
//! Bracha, Kimmel, "Partial Shape Similarity by Multi-metric Hamiltonian Spectra Matching",
//! SSVM 2023; the method as this crate implements it: `docs/algorithm.md`).
//!
//! Entry points: [`Localizer`] (prepare a full shape once, locate many partials; save and
//! load it), [`localize`] (one call) and [`search()`] (rank several prepared full shapes for
//! a partial), configured by [`Options`] (whose table [`localizer::OPTIONS`] front ends build
//! their parameters from).
//!
//! The toolkit the method is built from is public and documented: [`mesh`] (the checked
//! [`TriMesh`], readers and writers, repair, topology, generators), [`geometry`] (curvature,
//! the scale-invariant metric), [`operators`] (cotangent stiffness, lumped mass, Dirichlet
//! restriction), [`spectra`] (eigensolvers), [`shape`] (a mesh with cached operators) and
//! [`evaluation`] (region scores, spectral shape similarity, a synthetic test pair).
//!
//! The pipeline is the module tree; each module uses only the ones before it (a test keeps
//! it so): mesh -> geometry -> operators -> spectra -> shape -> alignment (cost, optimiser,
//! starts) -> region -> selection -> localizer -> search -> evaluation. The pipeline's
//! stages (alignment, region, selection) are internal.
//!
//! Cargo feature `lab` (unstable): the pipeline's internals for the `dualspectra-lab`
//! crate and the tests, not part of the API.

pub mod error;
pub mod progress;
pub mod mesh;
pub mod geometry;
pub mod operators;
pub mod spectra;
pub mod shape;
pub(crate) mod alignment;
pub(crate) mod region;
pub(crate) mod selection;
pub mod localizer;
pub mod search;
pub mod evaluation;

pub use error::{Error, MeshError, Result};
pub use localizer::{localize, Candidate, Localization, Localizer, Mode, Options, Scale, Timings};
pub use mesh::TriMesh;
pub use progress::Progress;
pub use search::{search, search_screened, search_shortlisted, search_with, Match, Screen, ScreenEntry};

/// The README's Rust example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;

/// The hidden field that keeps a public parameter struct extensible (faer's pattern): a
/// struct with a `pub non_exhaustive: NonExhaustive` field cannot be written out in full
/// outside this crate, so a new field is not a breaking change, while
/// `Options { k: 8, ..Default::default() }` works everywhere.
#[doc(hidden)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct NonExhaustive(());

/// The pipeline's internals, for the `dualspectra-lab` crate (benchmarks, studies) and this
/// crate's tests. Unstable: not part of the API, may change in any release.
#[cfg(feature = "lab")]
#[doc(hidden)]
pub mod lab {
    use crate::{Localization, Localizer, Progress, Result, TriMesh};

    /// `crate::alignment`: cost, optimiser, starts.
    pub mod alignment {
        pub use crate::alignment::*;
    }
    /// `crate::region`.
    pub mod region {
        pub use crate::region::*;
    }
    /// `crate::selection`.
    pub mod selection {
        pub use crate::selection::*;
    }
    /// `crate::geometry::shot`.
    pub mod shot {
        pub use crate::geometry::shot::*;
    }
    /// `crate::mesh::decimate`.
    pub mod decimate {
        pub use crate::mesh::decimate::*;
    }
    /// `crate::mesh::nearest`.
    pub mod nearest {
        pub use crate::mesh::nearest::*;
    }
    /// `crate::localizer::persist`: the file format's constants.
    pub mod persist {
        pub use crate::localizer::persist::{crc32, FORMAT_VERSION, MAGIC};
    }
    pub use crate::localizer::stages::{FINE_RESOLUTION_FACTOR, HOLE_RIM_FRACTION};

    /// [`crate::search::ScreenEntry::new`] with `keypoints` keypoints.
    pub fn screen_entry_with_keypoints(full: &TriMesh, keypoints: usize) -> Result<crate::search::ScreenEntry> {
        crate::search::ScreenEntry::with_keypoints(full, keypoints)
    }

    /// [`crate::search::Screen::rank`], choosing how `scale = auto` scores.
    pub fn screen_rank(screen: &crate::search::Screen, partial: &TriMesh, scale: crate::Scale, relative: bool) -> Result<Vec<(usize, f64)>> {
        screen.rank_with(partial, scale, relative, &Progress::none())
    }

    /// How alike models `i` and `j` of a screen look to it (`None`: an index out of range).
    pub fn screen_model_distance(screen: &crate::search::Screen, i: usize, j: usize) -> Option<f64> {
        screen.model_distance(i, j)
    }

    /// [`crate::search::Screen::new`] with `dimensions` principal directions (352: none).
    pub fn screen_with_dimensions(entries: &[crate::search::ScreenEntry], dimensions: usize) -> Result<crate::search::Screen> {
        crate::search::Screen::with_dimensions(entries, dimensions)
    }

    /// [`Localizer::locate`] with extra starts: each mask (one `bool` per vertex of the
    /// full mesh) is a guess of the region, started from as $w_0 = 2 - 4R_0$ (labelled
    /// `given#i` in the candidates).
    pub fn locate_with_initial_regions(
        localizer: &Localizer,
        partial: &TriMesh,
        initial_regions: &[Vec<bool>],
        progress: &Progress,
    ) -> Result<Localization> {
        localizer.locate_with_initial_regions(partial, initial_regions, progress)
    }

    /// [`crate::localize`] with extra starts (see [`locate_with_initial_regions`]).
    pub fn localize_with_initial_regions(
        full: &TriMesh,
        partial: &TriMesh,
        options: &crate::Options,
        initial_regions: &[Vec<bool>],
        progress: &Progress,
    ) -> Result<Localization> {
        crate::localizer::localize_with_initial_regions(full, partial, options, initial_regions, progress)
    }

    /// The regions the optimisation starts from for `partial`, labelled as the candidates
    /// are: a diagnostic of the starts, without optimising.
    pub fn start_regions(localizer: &Localizer, partial: &TriMesh) -> Result<Vec<(String, Vec<bool>)>> {
        localizer.start_regions(partial)
    }

    /// The factor [`Localizer::locate`] multiplies `partial` by (the `scale` option applied,
    /// or estimated with `auto`), without locating it.
    pub fn partial_factor(localizer: &Localizer, partial: &TriMesh) -> Result<f64> {
        localizer.partial_factor(partial)
    }

    /// For each optimisation vertex, the full-mesh vertex it is (increasing).
    pub fn optimisation_vertex_origins(localizer: &Localizer) -> &[u32] {
        localizer.optimisation_vertex_origins()
    }
}

/// Version of the core library (the crate version).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
