//! What a localization returns.

pub use crate::selection::CandidateScore;
use crate::mesh::intake::HostNumbering;
use serde::{Deserialize, Deserializer, Serialize};

/// Wall-clock seconds per stage.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[non_exhaustive]
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
#[non_exhaustive]
pub struct Candidate {
    /// Where it started: `planeJ` (the j-th plane cut), `descriptor-fit`, `descriptor-vote`,
    /// or `given#i` (the i-th given region).
    pub label: String,
    /// Final alignment cost.
    pub cost: f64,
    /// The scores the choice ranks by ([`crate::selection::choose`]).
    #[serde(flatten)]
    pub scores: CandidateScore,
    pub iterations: usize,
    pub evaluations: usize,
    /// The cost after each trust-region iteration (how early the start's outcome shows): on the
    /// warm-up mesh for the first iterations, then on the optimisation mesh (where it may
    /// start higher; never rising within either; docs/algorithm.md, "Optimisation").
    #[serde(default)]
    pub cost_history: Vec<f64>,
    /// Region on the full mesh's vertices.
    pub region: Vec<bool>,
}

/// Result of a localization. Per-vertex arrays are indexed by the full mesh's vertices.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[non_exhaustive]
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
    /// How much to trust the region, in [0, 1]: the estimated probability that the partial is
    /// part of this full shape and the region overlaps the true one with IoU >= 0.5
    /// ([`crate::selection::confidence`], from the partial fit and the region cost; calibration in
    /// docs/benchmarks/confidence/). Reject matches below a threshold of your choice.
    pub confidence: f64,
    /// How similar the partial is to the full shape, lower is more similar
    /// ([`crate::selection::similarity_score`]: the best partial fit among the candidates);
    /// comparable across full shapes, what [`crate::search()`] ranks by. `+inf` when no
    /// candidate region has a fit (serialized as `null`).
    #[serde(default = "infinity", deserialize_with = "null_as_infinity")]
    pub similarity_score: f64,
    /// Vertices of the optimisation mesh the potential was optimised on (the finer one for a
    /// partial with holes: twice the `resolution` option).
    #[serde(default)]
    pub optimisation_vertices: usize,
    /// The factor the partial's coordinates were multiplied by to bring it to the full shape's
    /// units: 1 with `scale = same`, the given factor, or the estimate with `scale = auto`.
    #[serde(default = "unit_scale")]
    pub scale: f64,
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

fn unit_scale() -> f64 {
    1.0
}

impl Localization {
    /// This result with its per-vertex arrays in the caller's numbering of the full mesh
    /// (`host`, e.g. [`crate::mesh::intake::MeshIntake::host_numbering`] or a prepared
    /// shape's [`crate::Localizer::host_numbering`]): `region` and every candidate's region
    /// hold a host vertex when they hold any of its copies; `score` and `potential` take its
    /// first copy's value; host vertices no mesh vertex names read `false` / 0. What every
    /// front end returns, so the rule is written once ([`HostNumbering`]).
    pub fn to_host(mut self, host: &HostNumbering) -> Localization {
        self.region = host.region_to_host(&self.region);
        self.score = host.values_to_host(&self.score, 0.0);
        self.potential = host.values_to_host(&self.potential, 0.0);
        for c in &mut self.candidates {
            c.region = host.region_to_host(&c.region);
        }
        self
    }
}

fn infinity() -> f64 {
    f64::INFINITY
}

/// A number, or `null` (how serde_json writes a non-finite float) as `+inf`.
fn null_as_infinity<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
}
