//! The one-call API: find the region of a full mesh that a partial mesh is.

pub use crate::alignment::cost::HessianModel;
use crate::error::{Error, Result};
use crate::mesh::TriMesh;
use crate::progress::Progress;
use serde::{Deserialize, Serialize};

/// Which spectra the alignment matches (the paper's ablation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// `k` regular + `k` scale-invariant eigenvalues (the paper's method).
    #[default]
    Dual,
    /// `2k` regular (Laplace-Beltrami) eigenvalues only.
    Lbo,
    /// `2k` scale-invariant eigenvalues only.
    Si,
}

impl std::str::FromStr for Mode {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "dual" => Ok(Mode::Dual),
            "lbo" => Ok(Mode::Lbo),
            "si" => Ok(Mode::Si),
            _ => Err(Error::InvalidArgument(format!(
                "unknown mode '{s}' (expected dual, lbo or si)"
            ))),
        }
    }
}

impl std::fmt::Display for Mode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Mode::Dual => "dual",
            Mode::Lbo => "lbo",
            Mode::Si => "si",
        })
    }
}

/// Parameters of [`localize`]. `Options::default()` gives the paper's settings
/// (construct with `Options { k: 10, ..Options::default() }`: fields may be added).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(default)]
pub struct Options {
    pub mode: Mode,
    /// Eigenvalues per spectrum (`dual` uses k + k, `lbo`/`si` use 2k).
    pub k: usize,
    /// Exponent of the scale-invariant factor.
    pub alpha: f64,
    /// Seed for every random choice (results are deterministic for a given seed).
    pub seed: u64,
    /// Vertices of the decimated full shape the potential is optimised on
    /// (0: no decimation). The paper decimates to 50% (~5,000 on SHREC'16); 1,000 (default)
    /// is ~2.5x faster than 2,500 per evaluation and gave comparable regions on the dev pairs.
    pub resolution: usize,
    /// Farthest-point centres of the starts (each gives
    /// [`StartShape::starts_per_centre`] starts, 3 by default; the [`Options::plane_cuts`] come
    /// on top). The paper uses 10 (40 starts); with the default 4 (12 starts, before plane cuts
    /// were added) a SHREC'16 pair took ~3.8 s on 2 cores (with 16 starts,
    /// 6 centres of `BallsAndWideGaussians` against 4: symmetry-aware IoU 0.719 against 0.712
    /// on all 80 pairs, best start 0.787 against 0.772, ~1.5x the time).
    pub centers: usize,
    /// Trust-region iterations of a start that runs to the end. The reference uses 100; the
    /// default 25 (with the Gauss-Newton model, 26 cost evaluations per start). From the
    /// area-matched starts (see [`StartShape`]) later iterations no longer find better regions:
    /// on all 80 SHREC'16 pairs, symmetry-aware IoU chosen / best start 0.686 / 0.770 with 50,
    /// 0.705 / 0.770 with 35, 0.712 / 0.772 with 25, 0.698 / 0.762 with 15, at a median 7.9,
    /// 6.0, 4.7 and ~3.5 s per pair; the procedural demo pair reached IoU 0.968, 0.965 and
    /// 0.890 with 50, 25 and 15.
    pub max_iterations: usize,
    /// Further trust-region iterations for the starts still converging after
    /// `max_iterations` (cost down by more than 10% over their last 10 iterations; in practice
    /// the bump starts, which begin far from any spectrum). 0: none.
    pub extra_iterations: usize,
    /// Successive halving of the starts: all starts run `max_iterations / 8` iterations, then
    /// the better half (by cost) continues to `/4`, then to `/2`, then to the end; a round never
    /// keeps fewer than `finalists` starts; each kind of start (wells, bumps) is ranked
    /// separately, as their costs start at different scales. `0` (default): no pruning, every
    /// start runs to the end. Off by default until it is measured not to lose quality: on the
    /// small undeformed test pairs, early costs mispredicted the best start (IoU 0.84-0.90
    /// with 4 finalists against > 0.9 without), since the cost of the right basin often
    /// falls late.
    pub finalists: usize,
    /// Add the descriptor baseline start (SHOT nearest neighbours, never pruned). Off by
    /// default: on 4 SHREC'16 dev pairs it ended at IoU 0.39, 0.29, 0.04, 0.41, never the
    /// best start (SHOT of a decimated full shape against a differently meshed, deformed
    /// partial is too noisy vertex by vertex; it discriminates well only integrated over a
    /// region, as in the selection).
    pub descriptor_start: bool,
    /// Worker threads (0: all cores).
    pub threads: usize,
    /// How the result is chosen among the optimised starts.
    pub selection: Selection,
    /// The trust region's model Hessian: Gauss-Newton (default; one evaluation per
    /// iteration) or finite differences (Manopt's, ~4 evaluations per iteration), see
    /// [`HessianModel`].
    pub hessian: HessianModel,
    /// The shape of the starting potentials (see [`StartShape`]).
    pub start_shape: StartShape,
    /// Eigenfunctions of the full shape whose level sets give starts, two each (the region on
    /// either side with the partial's area; see
    /// [`crate::alignment::starts::spectral_cut_starts`]), besides the starts around the
    /// centres. 0: none; at most [`MAX_SPECTRAL_CUTS`].
    pub spectral_cuts: usize,
    /// Plane-cut starts, one per direction: the side of a plane with the partial's area, for
    /// the first `plane_cuts` directions of [`crate::alignment::starts::plane_cut_directions`]
    /// (6: both ways along each principal axis; 14: and the 8 diagonals; at most
    /// [`MAX_PLANE_CUTS`]). A partial cut off across the body (a half, a torso's front), which no
    /// ball around an extremity approximates, starts close to its region. Default 6: on all 80
    /// SHREC'16 pairs (every start logged, 4 centres), symmetry-aware IoU 0.791 against 0.714
    /// without (halves 0.824 / 0.758 against 0.748 / 0.680), best start 0.832 against 0.765;
    /// 14: 0.803, 26: 0.813, at 1.5x, 2.2x and 3.2x the optimisation time. SHREC'16's partials
    /// were cut by planes, so other partials (scans, holes) may gain less; the balls stay.
    pub plane_cuts: usize,
}

/// The shape of the starting potentials around each farthest-point centre.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum StartShape {
    /// The reference's Gaussians: two widths ($\sigma = \sqrt{A_N}$, $2\sigma$), both signs;
    /// 4 starts per centre.
    Gaussian,
    /// Area-matched balls: a well on the ball of the partial's area around the centre, and a
    /// well on everything but the ball of the rest of the area
    /// ([`crate::alignment::starts::area_ball_starts`]); 2 starts per centre.
    AreaBall,
    /// The two area-matched balls and the wide Gaussians ($2\sigma$, both signs): 4 starts per
    /// centre. On all 80 SHREC'16 pairs (4 centres, 16 starts each, gated selection, 50
    /// iterations) symmetry-aware IoU 0.686 against 0.662 with [`StartShape::Gaussian`]
    /// (halves of 40: 0.721 / 0.651 against 0.733 / 0.591), best start 0.770 against 0.748,
    /// in the same time (16 pairs, same run: median 7.93 s against 7.90 s); `AreaBall` alone
    /// at 8 centres: 0.643 (best start 0.751). The balls suit partials cut off by one cut (a limb,
    /// the rest of the body); the wide Gaussians win where no ball around a centre fits the
    /// cut (e.g. a cut across the torso).
    BallsAndWideGaussians,
    /// The two area-matched balls and the wide Gaussian bump: 3 starts per centre. The
    /// default: the wide Gaussian well was the least useful start (the best start of 10 of 80
    /// SHREC'16 pairs, the chosen one of 15); without it, on the same optimised starts (25
    /// iterations), symmetry-aware IoU 0.714 against 0.712 (halves 0.688 / 0.740 against
    /// 0.675 / 0.749), best start 0.765 against 0.772, with 12 starts instead of 16: 0.78x the
    /// time (16 pairs, same run: median 3.8 s against 4.9 s). On smooth, nearly symmetric
    /// shapes the wide well still helps (an undeformed cap of the Python tests' bumpy
    /// ellipsoid: IoU 0.76 against 0.82).
    #[default]
    BallsAndWideBumps,
}

impl StartShape {
    /// Every start shape, the default first.
    pub const ALL: [StartShape; 4] = [
        StartShape::BallsAndWideBumps,
        StartShape::BallsAndWideGaussians,
        StartShape::Gaussian,
        StartShape::AreaBall,
    ];

    /// The name used by serde, the CLI (`--starts`) and Python (`starts=`).
    pub fn name(self) -> &'static str {
        match self {
            StartShape::Gaussian => "gaussian",
            StartShape::AreaBall => "area-ball",
            StartShape::BallsAndWideGaussians => "balls-and-wide-gaussians",
            StartShape::BallsAndWideBumps => "balls-and-wide-bumps",
        }
    }

    /// Starts per farthest-point centre.
    pub fn starts_per_centre(self) -> usize {
        match self {
            StartShape::Gaussian | StartShape::BallsAndWideGaussians => 4,
            StartShape::BallsAndWideBumps => 3,
            StartShape::AreaBall => 2,
        }
    }
}

/// The variant of `all` whose `name` is `s` (any case); else an error naming `what` and
/// listing the names. Serves the `FromStr` of the named option enums.
fn parse_by_name<T: Copy>(all: &[T], name: fn(T) -> &'static str, what: &str, s: &str) -> Result<T> {
    let lower = s.to_ascii_lowercase();
    all.iter().copied().find(|&v| name(v) == lower).ok_or_else(|| {
        let names: Vec<&str> = all.iter().map(|&v| name(v)).collect();
        Error::InvalidArgument(format!("unknown {what} '{s}' (expected {})", names.join(", ")))
    })
}

impl std::str::FromStr for StartShape {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        parse_by_name(&StartShape::ALL, StartShape::name, "start shape", s)
    }
}

impl std::fmt::Display for StartShape {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Rule choosing among the optimised starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Selection {
    /// SHOT descriptors projected on the first eigenfunctions (ALGORITHM.md; the paper's rule).
    Descriptors,
    /// The lowest final alignment cost.
    Cost,
    /// The lowest region cost: the alignment cost of the candidate's extracted region as a
    /// step potential $\tau(1 - R)$, i.e. how well the region itself (not the relaxed
    /// potential that produced it) reproduces the partial's spectra.
    Region,
    /// The lowest descriptor score times the squared partial fit (times a boundary-length
    /// misfit factor, [`BOUNDARY_WEIGHT`]) among the candidates whose region cost is at most
    /// [`REGION_COST_GATE`] times the lowest (or within [`REGION_COST_FLOOR_RMS`]): the region
    /// cost rules out regions that do not
    /// reproduce the partial's spectra, the descriptors choose among the rest. On 16 SHREC'16
    /// pairs (the `_1` and `_6` cuts, 16 starts each) it was never worse than descriptors
    /// alone: mean IoU 0.675 against 0.636 (descriptors), 0.640 (region cost), 0.55 (cost),
    /// best start 0.765. The partial fit
    /// ([`crate::alignment::selection::partial_fits`], the mean distance from the partial's
    /// SHOT descriptors to the nearest in the region; exponent
    /// [`crate::alignment::selection::PARTIAL_FIT_EXPONENT`]) tells a region from its mirror
    /// twin, which the projections, averaged over the region, cannot: on all 80 SHREC'16 pairs
    /// (18 starts each, every start logged) IoU 0.800 against 0.733 (symmetry-aware 0.811
    /// against 0.791; halves 0.809 / 0.792 against 0.722 / 0.743); exponent 1: 0.794, 4: 0.801.
    #[default]
    Gated,
}

impl Selection {
    /// Every rule, the default first.
    pub const ALL: [Selection; 4] = [
        Selection::Gated,
        Selection::Region,
        Selection::Descriptors,
        Selection::Cost,
    ];

    /// The name used by serde, the CLI (`--selection`) and Python (`selection=`).
    pub fn name(self) -> &'static str {
        match self {
            Selection::Descriptors => "descriptors",
            Selection::Cost => "cost",
            Selection::Region => "region",
            Selection::Gated => "gated",
        }
    }
}

impl std::str::FromStr for Selection {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        parse_by_name(&Selection::ALL, Selection::name, "selection", s)
    }
}

impl std::fmt::Display for Selection {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// See [`Selection::Gated`] (2 and 5 gave 0.661 and 0.675 on the same pairs).
pub const REGION_COST_GATE: f64 = 3.0;

/// Weight $\beta$ of the boundary-length misfit in [`Selection::Gated`]: the descriptor score
/// is multiplied by $(L_R/L_N)^{\pm\beta}$, penalising regions whose boundary is much longer
/// or shorter than the partial's cut (see [`crate::alignment::selection::boundary_misfit`]).
/// On all 80 SHREC'16 pairs (same optimised starts, two halves of 40): symmetry-aware IoU
/// 0.584 / 0.630 with 0, 0.613 / 0.626 with 0.5, 0.614 / 0.607 with 1, 0.637 / 0.603 with 2;
/// +0.029 on one half, -0.004 on the other: a small gain, not uniform; the mildest weight
/// with a gain (on the previous, warm-chained scores: 0.607 -> 0.640 on all 80).
pub const BOUNDARY_WEIGHT: f64 = 0.5;

/// The gate of [`Selection::Gated`] always admits regions whose eigenvalues match the
/// partial's to this root-mean-square relative error (region cost <= n * 0.1^2): where several
/// regions fit almost exactly (the lowest region cost is tiny, e.g. a near-symmetric shape),
/// a multiple of the lowest would wrongly exclude good fits. On SHREC'16 the lowest region
/// cost per pair was 0.14-35 and floors up to 2.0 changed no choice.
pub const REGION_COST_FLOOR_RMS: f64 = 0.1;

impl Default for Options {
    fn default() -> Self {
        Options {
            mode: Mode::Dual,
            k: 20,
            alpha: crate::geometry::metric::DEFAULT_ALPHA,
            seed: 0,
            resolution: 1000,
            centers: 4,
            max_iterations: 25,
            extra_iterations: 0,
            finalists: 0,
            descriptor_start: false,
            threads: 0,
            selection: Selection::Gated,
            hessian: HessianModel::default(),
            start_shape: StartShape::default(),
            spectral_cuts: 0,
            plane_cuts: 6,
        }
    }
}

/// Wall-clock seconds per stage.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Timings {
    pub preprocessing: f64,
    pub starts: f64,
    pub optimisation: f64,
    pub selection: f64,
    pub region: f64,
    pub total: f64,
}

/// Result of [`localize`]. Per-vertex arrays are indexed by the full mesh's vertices.
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
    /// Index of the selected start and number of starts run.
    pub selected_start: usize,
    pub n_starts: usize,
    pub timings: Timings,
    /// Every optimised start (the selected one is `candidates[selected_start]`), for inspection.
    pub candidates: Vec<Candidate>,
    /// Notes on repairs made to the input (e.g. a disconnected partial reduced to its largest component).
    pub warnings: Vec<String>,
}

/// One optimised start: its label, final cost, selection score and region on the full mesh.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Candidate {
    pub label: String,
    pub cost: f64,
    /// Descriptor-projection score (lower is better; NaN where not computed).
    pub selection_score: f64,
    /// Alignment cost of the candidate's region as a step potential (NaN where not computed).
    pub region_cost: f64,
    /// $|\ln(L_R / L_N)|$: boundary length of the region against the partial's (NaN if either is 0).
    pub boundary_misfit: f64,
    /// Partial fit of the region ([`crate::alignment::selection::partial_fits`]; NaN if not
    /// scored: scored for the finalists under [`Selection::Gated`] only).
    pub partial_fit: f64,
    pub iterations: usize,
    pub evaluations: usize,
    /// Whether the start survived every round of the successive halving (only finalists are
    /// selected from).
    pub finalist: bool,
    /// Region on the full mesh's vertices.
    pub region: Vec<bool>,
}

/// What one start produced.
#[derive(Debug, Clone)]
pub(crate) struct StartOutcome {
    pub label: String,
    pub w: Vec<f64>,
    pub cost: f64,
    pub iterations: usize,
    pub evaluations: usize,
    pub finalist: bool,
    /// Eigenvalues per term at the optimum, and the eigenvector energy per vertex of the optimisation mesh.
    pub eigenvalues: Vec<Vec<f64>>,
    pub energy: Vec<f64>,
}

/// Check the options; each problem is a clear `InvalidArgument`.
/// The coarsest optimisation mesh accepted (a region of a few percent of it must still hold
/// enough vertices for `k` eigenvalues).
pub const MIN_RESOLUTION: usize = 200;

/// Upper bound of [`Options::spectral_cuts`]: beyond the first few dozen eigenfunctions the
/// level sets are fine-scale ripples, not cuts, and each adds two full optimisations.
pub const MAX_SPECTRAL_CUTS: usize = 50;

/// Upper bound of [`Options::plane_cuts`]: the directions of
/// [`crate::alignment::starts::plane_cut_directions`].
pub const MAX_PLANE_CUTS: usize = crate::alignment::starts::MAX_PLANE_CUTS;

pub(crate) fn check_options(o: &Options) -> Result<()> {
    if o.k == 0 || o.k > 500 {
        return Err(Error::InvalidArgument(format!(
            "k = {} must be in 1..=500",
            o.k
        )));
    }
    if !(o.alpha.is_finite() && (0.0..=2.0).contains(&o.alpha)) {
        return Err(Error::InvalidArgument(format!(
            "alpha = {} must be in [0, 2]",
            o.alpha
        )));
    }
    if o.max_iterations == 0 {
        return Err(Error::InvalidArgument(
            "max_iterations must be at least 1".into(),
        ));
    }
    if o.spectral_cuts > MAX_SPECTRAL_CUTS {
        return Err(Error::InvalidArgument(format!(
            "spectral_cuts = {} must be at most {MAX_SPECTRAL_CUTS} (two starts each)",
            o.spectral_cuts
        )));
    }
    if o.plane_cuts > MAX_PLANE_CUTS {
        return Err(Error::InvalidArgument(format!(
            "plane_cuts = {} must be at most {MAX_PLANE_CUTS} (the principal axes, diagonals and face diagonals, both ways)",
            o.plane_cuts
        )));
    }
    if o.resolution != 0 && o.resolution < MIN_RESOLUTION {
        return Err(Error::InvalidArgument(format!(
            "resolution = {} is too coarse: use 0 (no decimation) or at least {MIN_RESOLUTION} vertices",
            o.resolution
        )));
    }
    Ok(())
}

/// Keep the largest connected component (by area) of a mesh; returns it and whether anything was dropped.
pub(crate) fn largest_component(mesh: &TriMesh) -> Result<(TriMesh, bool)> {
    let (comp, count) = crate::mesh::topology::connected_components(mesh);
    if count <= 1 {
        return Ok((mesh.clone(), false));
    }
    let mut area = vec![0.0; count];
    let v = mesh.vertices();
    for f in mesh.faces() {
        area[comp[f[0] as usize] as usize] +=
            crate::mesh::triangle_area(v[f[0] as usize], v[f[1] as usize], v[f[2] as usize]);
    }
    let best = (0..count)
        .max_by(|&a, &b| area[a].total_cmp(&area[b]).then(b.cmp(&a)))
        .unwrap_or(0) as u32;
    let faces: Vec<[u32; 3]> = mesh
        .faces()
        .iter()
        .filter(|f| comp[f[0] as usize] == best)
        .copied()
        .collect();
    let (m, _) = TriMesh::new_dropping_isolated(mesh.vertices().to_vec(), faces)?;
    Ok((m, true))
}

/// Find the region of `full` that `partial` corresponds to (ALGORITHM.md, whole pipeline).
///
/// Both meshes are first scaled by the same factor so that `full` has unit area: the result
/// does not depend on the units the shapes are given in.
///
/// Documented behaviours on unusual input: a partial without boundary is rejected (a closed
/// surface has no Dirichlet spectrum to match: compare whole shapes with the similarity
/// tools instead); a partial larger than 1.1x the full shape's area is rejected; a
/// disconnected partial is reduced to its largest connected component (a warning says so).
pub fn localize(
    full: &TriMesh,
    partial: &TriMesh,
    options: &Options,
    progress: &Progress,
) -> Result<Localization> {
    crate::pipeline::run(full, partial, options, &[], progress)
}

/// [`localize`] with extra starts: each mask (one `bool` per vertex of `full`) is a guess of
/// the region, started from as the descriptor baseline is ($w_0 = 2 - 4R_0$). Such starts are
/// labelled `given#i` in [`Localization::candidates`] and are never pruned by the halving.
pub fn localize_with_initial_regions(
    full: &TriMesh,
    partial: &TriMesh,
    options: &Options,
    initial_regions: &[Vec<bool>],
    progress: &Progress,
) -> Result<Localization> {
    for (i, r) in initial_regions.iter().enumerate() {
        if r.len() != full.n_vertices() {
            return Err(Error::InvalidArgument(format!(
                "initial region {i} has {} entries, the full mesh {} vertices",
                r.len(),
                full.n_vertices()
            )));
        }
    }
    crate::pipeline::run(full, partial, options, initial_regions, progress)
}

pub(crate) mod internal {
    pub(crate) use super::{check_options, largest_component};
}
