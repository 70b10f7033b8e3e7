//! The benchmark: run the localizer on every pair of a dataset and score each region
//! against the ground truth (precision, recall and IoU by vertex counts, also
//! symmetry-aware: the better of the direct and the left-right mirrored ground truth, as
//! SHREC'16 accepts symmetric matches; IoU weighted by vertex area), summarise a set and
//! several sets, and draw the cumulative IoU curve (the paper's Fig. 5). The CLI's `bench`
//! command prints and writes what these functions compute.

use crate::datasets::{Dataset, Pair};
use dualspectra::evaluation::metrics::{self, cumulative_iou, Match, Scores};
use dualspectra::operators::lumped_mass;
use dualspectra::localizer::CandidateScore;
use dualspectra::{Localizer, Mode, Options, Progress, Timings};
use serde::Serialize;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Scores of one pair.
#[derive(Debug, Clone, Serialize)]
pub struct PairResult {
    pub name: String,
    pub class: String,
    pub region_size: usize,
    pub gt_size: usize,
    /// Against the direct ground truth, by vertex counts.
    pub scores: Scores,
    /// Symmetry-aware, by vertex counts.
    pub scores_sym: Scores,
    pub matched: Match,
    /// IoU against the direct ground truth weighted by vertex area.
    pub area_iou: f64,
    pub cost: f64,
    /// The localizer's confidence in the region (0 for a failed pair).
    pub confidence: f64,
    /// Vertices of the optimisation mesh used (0 for a failed pair).
    pub optimisation_vertices: usize,
    /// The factor the bench's [`Transform`] multiplied the partial by (1: none).
    pub applied_factor: f64,
    /// The localizer's factor ([`dualspectra::Localization::scale`]); `scale * applied_factor`
    /// is 1 when an estimate undoes the transform exactly.
    pub scale: f64,
    pub seconds: f64,
    /// Seconds per stage of the localizer (zero for a failed pair).
    pub timings: Timings,
    /// Set if the pair failed (then all scores are 0).
    pub error: Option<String>,
    /// The region (0-based vertex indices of the full shape).
    pub region: Vec<usize>,
    /// Index of the chosen candidate in `candidates`.
    pub selected: usize,
    /// Every candidate the localizer scored, with its IoU against the ground truth (for
    /// studies of the choice and of confidence measures from the JSON).
    pub candidates: Vec<CandidateLog>,
}

/// One candidate of a pair: the localizer's scores and how good it was.
#[derive(Debug, Clone, Serialize)]
pub struct CandidateLog {
    pub label: String,
    pub cost: f64,
    #[serde(flatten)]
    pub scores: CandidateScore,
    pub region_size: usize,
    /// Against the ground truth, direct and symmetry-aware.
    pub iou: f64,
    pub iou_sym: f64,
    /// Against the chosen candidate's region.
    pub iou_with_chosen: f64,
    /// Against every candidate's region, in the order of `candidates` (studies of choices
    /// that weigh how the starts agree).
    pub iou_with_candidates: Vec<f64>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    pub pairs: usize,
    pub failed: usize,
    pub mean: Scores,
    pub mean_sym: Scores,
    pub mean_area_iou: f64,
    pub median_seconds: f64,
    pub total_seconds: f64,
    /// Median seconds of each stage over the pairs that ran (where the time goes).
    pub median_stage_seconds: Timings,
}

/// The JSON report of one set (`bench DATASET --json`).
#[derive(Serialize)]
pub struct Report<'a> {
    pub dataset: String,
    pub options: &'a Options,
    pub summary: &'a Summary,
    pub pairs: &'a [PairResult],
}

/// One set's results in the `--all` report.
#[derive(Serialize)]
pub struct SetReport {
    pub set: String,
    pub dataset: String,
    pub summary: Summary,
    pub pairs: Vec<PairResult>,
}

/// The JSON report of every set (`bench --all --json`).
#[derive(Serialize)]
pub struct AllReport<'a> {
    pub root: String,
    pub options: &'a Options,
    /// Unweighted means of the sets' means (each set counts once).
    pub mean_of_sets: &'a Summary,
    pub sets: &'a [SetReport],
}

pub const ZERO: Scores = Scores {
    precision: 0.0,
    recall: 0.0,
    iou: 0.0,
};

/// A change made to each partial before it is located: how users' partials differ from the
/// dev sets' (other poses in space, other units, other bodies' sizes). Deterministic per pair
/// (seeded by the pair's name).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Transform {
    /// The partial as given.
    #[default]
    None,
    /// A random rotation and translation.
    Rigid,
    /// Rigid, then multiplied by a factor log-uniform in [1e-3, 1e3] (other units).
    Units,
    /// Rigid, then multiplied by a factor log-uniform in [0.8, 1.25] (another body's size).
    Size,
}

impl std::str::FromStr for Transform {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "none" => Ok(Transform::None),
            "rigid" => Ok(Transform::Rigid),
            "units" => Ok(Transform::Units),
            "size" => Ok(Transform::Size),
            _ => Err(format!("unknown transform '{s}' (none, rigid, units or size)")),
        }
    }
}

impl Transform {
    /// `mesh` moved, turned and scaled for the pair `name`; returns it and the factor.
    pub fn apply(self, mesh: &dualspectra::TriMesh, name: &str) -> dualspectra::Result<(dualspectra::TriMesh, f64)> {
        if self == Transform::None {
            return Ok((mesh.clone(), 1.0));
        }
        // FNV-1a of the name, then a 64-bit LCG.
        let mut state = name.bytes().fold(0xcbf29ce484222325u64, |h, b| (h ^ b as u64).wrapping_mul(0x100000001b3));
        let mut uniform = move || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        let mut gaussian = || (-2.0 * uniform().ln()).sqrt() * (std::f64::consts::TAU * uniform()).cos();
        let q: [f64; 4] = [gaussian(), gaussian(), gaussian(), gaussian()];
        let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        let [w, x, y, z] = q.map(|c| c / n);
        let r = [
            [1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y)],
            [2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x)],
            [2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)],
        ];
        let t = [gaussian(), gaussian(), gaussian()];
        let factor = match self {
            Transform::Units => 10f64.powf(-3.0 + 6.0 * uniform()),
            Transform::Size => (0.8f64.ln() + (1.25f64 / 0.8).ln() * uniform()).exp(),
            _ => 1.0,
        };
        let extent = mesh.area().sqrt();
        let moved = mesh.map_positions(|p| {
            let mut out = [0.0; 3];
            for i in 0..3 {
                out[i] = factor * ((0..3).map(|j| r[i][j] * p[j]).sum::<f64>() + extent * t[i]);
            }
            out
        })?;
        Ok((moved, factor))
    }
}

/// Prepared full shapes, one per file: every partial of a full shape reuses its
/// [`Localizer`].
pub type Prepared = HashMap<PathBuf, Localizer>;

/// Locate one pair's partial (preparing its full shape once in `prepared`) and score it.
pub fn run_pair(
    pair: &Pair,
    options: &Options,
    transform: Transform,
    prepared: &mut Prepared,
    progress: &Progress,
) -> Result<PairResult, dualspectra::Error> {
    let mut data = pair.load()?;
    let (partial, applied_factor) = transform.apply(&data.partial, &pair.name)?;
    data.partial = partial;
    let t = Instant::now();
    if !prepared.contains_key(&pair.full) {
        let localizer = Localizer::with_progress(&data.full, options, &progress.sub(0.0, 0.05))?;
        prepared.insert(pair.full.clone(), localizer);
    }
    let loc = prepared[&pair.full].locate(&data.partial, &progress.sub(0.05, 1.0))?;
    let seconds = t.elapsed().as_secs_f64();
    let scores = metrics::scores(&loc.region, &data.gt)?;
    let (scores_sym, matched) = match &data.gt_sym {
        Some(sym) => metrics::symmetry_aware(&loc.region, &data.gt, sym, None)?,
        None => (scores, Match::Direct),
    };
    let area_iou = metrics::weighted_scores(&loc.region, &data.gt, &lumped_mass(&data.full))?.iou;
    let mut candidates = Vec::with_capacity(loc.candidates.len());
    for c in &loc.candidates {
        let iou = metrics::scores(&c.region, &data.gt)?.iou;
        let iou_sym = match &data.gt_sym {
            Some(sym) => metrics::symmetry_aware(&c.region, &data.gt, sym, None)?.0.iou,
            None => iou,
        };
        candidates.push(CandidateLog {
            label: c.label.clone(),
            cost: c.cost,
            scores: c.scores,
            region_size: c.region.iter().filter(|&&b| b).count(),
            iou,
            iou_sym,
            iou_with_chosen: metrics::scores(&c.region, &loc.region)?.iou,
            iou_with_candidates: loc
                .candidates
                .iter()
                .map(|o| Ok(metrics::scores(&c.region, &o.region)?.iou))
                .collect::<Result<_, dualspectra::Error>>()?,
        });
    }
    Ok(PairResult {
        name: pair.name.clone(),
        class: pair.class.clone(),
        region_size: loc.region.iter().filter(|&&b| b).count(),
        gt_size: data.gt.iter().filter(|&&b| b).count(),
        scores,
        scores_sym,
        matched,
        area_iou,
        cost: loc.cost,
        confidence: loc.confidence,
        optimisation_vertices: loc.optimisation_vertices,
        applied_factor,
        scale: loc.scale,
        seconds,
        timings: {
            let mut t = loc.timings.clone();
            t.preparation = seconds - loc.timings.total;
            t
        },
        error: None,
        region: loc.region.iter().enumerate().filter(|(_, &inside)| inside).map(|(i, _)| i).collect(),
        selected: loc.selected_start,
        candidates,
    })
}

fn mean_scores(rs: &[PairResult], f: impl Fn(&PairResult) -> Scores) -> Scores {
    let v: Vec<Scores> = rs.iter().map(f).collect();
    Scores {
        precision: metrics::mean(&v.iter().map(|s| s.precision).collect::<Vec<_>>()),
        recall: metrics::mean(&v.iter().map(|s| s.recall).collect::<Vec<_>>()),
        iou: metrics::mean(&v.iter().map(|s| s.iou).collect::<Vec<_>>()),
    }
}

/// Timings whose every stage is `stat` of that stage's field.
fn per_stage(stat: impl Fn(fn(&Timings) -> f64) -> f64) -> Timings {
    let mut t = Timings::default();
    t.preparation = stat(|t| t.preparation);
    t.preprocessing = stat(|t| t.preprocessing);
    t.starts = stat(|t| t.starts);
    t.optimisation = stat(|t| t.optimisation);
    t.selection = stat(|t| t.selection);
    t.region = stat(|t| t.region);
    t.total = stat(|t| t.total);
    t
}

/// Summary over the pairs (failed pairs count with scores 0).
pub fn summarize(results: &[PairResult]) -> Summary {
    let secs: Vec<f64> = results
        .iter()
        .filter(|r| r.error.is_none())
        .map(|r| r.seconds)
        .collect();
    let ran: Vec<&Timings> = results.iter().filter(|r| r.error.is_none()).map(|r| &r.timings).collect();
    let stage = |f: fn(&Timings) -> f64| metrics::median(&ran.iter().map(|t| f(t)).collect::<Vec<_>>());
    Summary {
        pairs: results.len(),
        failed: results.iter().filter(|r| r.error.is_some()).count(),
        mean: mean_scores(results, |r| r.scores),
        mean_sym: mean_scores(results, |r| r.scores_sym),
        mean_area_iou: metrics::mean(&results.iter().map(|r| r.area_iou).collect::<Vec<_>>()),
        median_seconds: metrics::median(&secs),
        total_seconds: secs.iter().sum(),
        median_stage_seconds: per_stage(stage),
    }
}

/// The cumulative IoU plot (direct and symmetry-aware curves) as an SVG document.
/// Errors are plotters' messages.
pub fn cumulative_iou_svg(title: &str, curves: &[(String, Vec<f64>)]) -> Result<String, String> {
    use plotters::prelude::*;
    let draw_err = |e: &dyn std::fmt::Display| e.to_string();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (640, 480)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| draw_err(&e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 20))
            .margin(15)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(0f64..1f64, 0f64..1.02f64)
            .map_err(|e| draw_err(&e))?;
        chart
            .configure_mesh()
            .x_desc("IoU")
            .y_desc("fraction of pairs with IoU >= x")
            .draw()
            .map_err(|e| draw_err(&e))?;
        let palette = [
            RGBColor(200, 30, 30),
            RGBColor(30, 90, 200),
            RGBColor(30, 150, 60),
            RGBColor(120, 60, 160),
        ];
        for (i, (label, ious)) in curves.iter().enumerate() {
            let curve = cumulative_iou(ious);
            let color = palette[i % palette.len()];
            chart
                .draw_series(LineSeries::new(curve.steps(), color.stroke_width(2)))
                .map_err(|e| draw_err(&e))?
                .label(format!("{label} (mean IoU {:.3})", curve.area()))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerLeft)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| draw_err(&e))?;
        root.present().map_err(|e| draw_err(&e))?;
    }
    Ok(svg)
}

/// Which pairs of a set to run: `filter` (name contains), then every `stride`-th, then the
/// first `limit`.
#[derive(Debug, Clone, Default)]
pub struct Selection {
    pub filter: Option<String>,
    pub stride: Option<usize>,
    pub limit: Option<usize>,
}

/// The pairs of `dataset` after the selection.
pub fn select_pairs(dataset: &Dataset, selection: &Selection) -> dualspectra::Result<Vec<Pair>> {
    let mut pairs = dataset.pairs()?;
    if let Some(f) = &selection.filter {
        pairs.retain(|p| p.name.contains(f.as_str()));
    }
    if let Some(s) = selection.stride {
        pairs = pairs.into_iter().step_by(s.max(1)).collect();
    }
    if let Some(n) = selection.limit {
        pairs.truncate(n);
    }
    Ok(pairs)
}

/// The result of a pair that failed with `error` (scores 0, the message on one line).
pub fn failed_pair(pair: &Pair, error: &dualspectra::Error) -> PairResult {
    PairResult {
        name: pair.name.clone(),
        class: pair.class.clone(),
        region_size: 0,
        gt_size: 0,
        scores: ZERO,
        scores_sym: ZERO,
        matched: Match::Direct,
        area_iou: 0.0,
        cost: f64::NAN,
        confidence: 0.0,
        optimisation_vertices: 0,
        applied_factor: f64::NAN,
        scale: f64::NAN,
        seconds: 0.0,
        timings: Timings::default(),
        error: Some(error.to_string().split_whitespace().collect::<Vec<_>>().join(" ")),
        region: vec![],
        selected: 0,
        candidates: vec![],
    }
}

/// The cumulative IoU plot of one set's results.
pub fn set_svg(results: &[PairResult], mode: Mode, title: &str) -> Result<String, String> {
    let mode = match mode {
        Mode::Dual => "dual spectra",
        Mode::Lbo => "LBO only",
        Mode::Si => "SI-LBO only",
    };
    let curves = vec![
        (format!("{mode}, symmetry-aware"), results.iter().map(|r| r.scores_sym.iou).collect()),
        (format!("{mode}, direct"), results.iter().map(|r| r.scores.iou).collect()),
    ];
    cumulative_iou_svg(&format!("{title}: cumulative IoU ({} pairs)", results.len()), &curves)
}

/// `OUT` with `-<set>` before its extension.
pub fn per_set_path(out: &Path, set: &str) -> PathBuf {
    let stem = out.file_stem().map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let ext = out.extension().map_or_else(String::new, |e| format!(".{}", e.to_string_lossy()));
    out.with_file_name(format!("{stem}-{set}{ext}"))
}

/// Unweighted mean over sets of their summaries (each set counts once); seconds are the
/// median of the sets' medians.
pub fn mean_of_sets(summaries: &[&Summary]) -> Summary {
    let m = |f: &dyn Fn(&Summary) -> f64| metrics::mean(&summaries.iter().map(|s| f(s)).collect::<Vec<_>>());
    let med = |f: &dyn Fn(&Summary) -> f64| metrics::median(&summaries.iter().map(|s| f(s)).collect::<Vec<_>>());
    let sc = |g: fn(&Summary) -> Scores| Scores {
        precision: m(&|s| g(s).precision),
        recall: m(&|s| g(s).recall),
        iou: m(&|s| g(s).iou),
    };
    let t = |g: fn(&Timings) -> f64| med(&|s| g(&s.median_stage_seconds));
    Summary {
        pairs: summaries.iter().map(|s| s.pairs).sum(),
        failed: summaries.iter().map(|s| s.failed).sum(),
        mean: sc(|s| s.mean),
        mean_sym: sc(|s| s.mean_sym),
        mean_area_iou: m(&|s| s.mean_area_iou),
        median_seconds: med(&|s| s.median_seconds),
        total_seconds: summaries.iter().map(|s| s.total_seconds).sum(),
        median_stage_seconds: per_stage(t),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn svg_plot_has_the_curves_and_labels() {
        let svg = cumulative_iou_svg(
            "t",
            &[("a".into(), vec![0.2, 0.9, 0.5]), ("b".into(), vec![1.0])],
        )
        .unwrap();
        assert!(svg.starts_with("<svg"), "{}", &svg[..60.min(svg.len())]);
        assert!(svg.contains("mean IoU 0.533"));
        assert!(svg.contains("mean IoU 1.000"));
        assert!(svg.matches("<polyline").count() >= 2);
    }

    #[test]
    fn failed_pairs_count_as_zero_and_median_skips_them() {
        let ok = PairResult {
            name: "a".into(),
            class: "c".into(),
            region_size: 1,
            gt_size: 1,
            scores: Scores {
                precision: 1.0,
                recall: 1.0,
                iou: 1.0,
            },
            scores_sym: Scores {
                precision: 1.0,
                recall: 1.0,
                iou: 1.0,
            },
            matched: Match::Direct,
            area_iou: 1.0,
            cost: 0.0,
            applied_factor: 1.0,
            scale: 1.0,
            confidence: 1.0,
            optimisation_vertices: 1000,
            seconds: 3.0,
            timings: {
                let mut t = Timings::default();
                (t.optimisation, t.total) = (2.5, 3.0);
                t
            },
            error: None,
            region: vec![0],
            selected: 0,
            candidates: vec![],
        };
        let bad = PairResult {
            error: Some("x".into()),
            scores: ZERO,
            scores_sym: ZERO,
            area_iou: 0.0,
            seconds: 0.0,
            ..ok.clone()
        };
        let s = summarize(&[ok, bad]);
        assert_eq!((s.pairs, s.failed), (2, 1));
        assert_eq!(s.mean.iou, 0.5);
        assert_eq!(s.median_seconds, 3.0);
        // Stage medians over the pairs that ran (the failed one's zeros do not count).
        assert_eq!((s.median_stage_seconds.optimisation, s.median_stage_seconds.total), (2.5, 3.0));
    }
}
