//! What a localization returns.

use crate::selection::CandidateScore;
use serde::{Deserialize, Serialize};

/// Wall-clock seconds per stage.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Timings {
    /// Preparing the full shape ([`crate::Localizer::new`]); 0 when a prepared
    /// [`crate::Localizer`] was reused.
    pub preparation: f64,
    /// The partial's spectra and descriptors.
    pub preprocessing: f64,
    pub starts: f64,
    pub optimisation: f64,
    /// Each candidate's region on the full shape.
    pub region: f64,
    /// Scoring the candidates and choosing one.
    pub selection: f64,
    pub total: f64,
}

/// One optimised start: its label, final cost, scores and region on the full mesh.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Candidate {
    /// Where it started: `ball@c`, `coball@c`, `bump@c/sigma1` (around optimisation-mesh
    /// vertex `c`), `planeJ`, or `given#i` (the i-th given region).
    pub label: String,
    /// Final alignment cost.
    pub cost: f64,
    /// The scores the choice ranks by ([`crate::selection::choose`]).
    #[serde(flatten)]
    pub scores: CandidateScore,
    pub iterations: usize,
    pub evaluations: usize,
    /// Region on the full mesh's vertices.
    pub region: Vec<bool>,
}

/// Result of a localization. Per-vertex arrays are indexed by the full mesh's vertices.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Localization {
    /// `true` for vertices of the full mesh in the matched region.
    pub region: Vec<bool>,
    /// Soft membership score in [0, 1] per vertex (higher = more likely in the region).
    pub score: Vec<f64>,
    /// Optimised potential `v >= 0` per vertex (transferred to the full mesh).
    pub potential: Vec<f64>,
    /// Hamiltonian eigenvalues at the optimum (regular metric; empty in `si` mode).
    pub eigenvalues_regular: Vec<f64>,
    /// Hamiltonian eigenvalues at the optimum (scale-invariant metric; empty in `lbo` mode).
    pub eigenvalues_si: Vec<f64>,
    /// Target Dirichlet spectra of the partial shape.
    pub target_regular: Vec<f64>,
    pub target_si: Vec<f64>,
    /// Final alignment cost of the selected start.
    pub cost: f64,
    /// How much to trust the region, in [0, 1]: the estimated probability that it overlaps
    /// the true region with IoU >= 0.5 ([`crate::selection::confidence`]; calibration in
    /// docs/benchmarks/confidence/). Reject matches below a threshold of your choice.
    pub confidence: f64,
    /// Vertices of the optimisation mesh the potential was optimised on (the finer one for a
    /// partial with holes, [`crate::localizer::FINE_RESOLUTION_FACTOR`]).
    #[serde(default)]
    pub optimisation_vertices: usize,
    /// Index of the selected start in `candidates`, and the number of starts run.
    pub selected_start: usize,
    pub n_starts: usize,
    pub timings: Timings,
    /// Every optimised start (the selected one is `candidates[selected_start]`).
    pub candidates: Vec<Candidate>,
    /// Notes on what was repaired or skipped (e.g. a disconnected partial reduced to its
    /// largest component); every front end shows them.
    pub warnings: Vec<String>,
}
