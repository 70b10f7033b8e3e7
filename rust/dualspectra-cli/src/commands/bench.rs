//! `dualspectra bench DATASET [options] [--json OUT] [--svg OUT] [--limit N] [--filter SUBSTR]
//! [--stride N]`, `dualspectra bench --all [ROOT] ...`
//!
//! Runs the localizer on every pair of a dataset (SHREC'16 CUTS or HOLES, PFARM or PFAUST
//! layout, see `dualspectra::evaluation::datasets`), one pair after another (the localizer
//! is itself parallel), and scores each region against the ground truth:
//! precision, recall and IoU by vertex counts, also symmetry-aware (the better of the
//! direct and the left-right mirrored ground truth, as SHREC'16 accepts symmetric
//! matches). Prints a table and the means; a pair that fails scores 0 and is listed with
//! its error. `--json` writes every pair's scores, `--svg` the cumulative IoU curve (the
//! paper's Fig. 5: fraction of pairs with IoU >= x; its area is the mean IoU). `--all` runs
//! every dev set found under ROOT (default `$DUALSPECTRA_DATA`): a table per set, then one
//! line per set and the means across sets; `--json` then holds every set, `--svg OUT`
//! writes one plot per set (`OUT` with `-<set>` before the extension).

use super::localize::{progress_bar, region_indices, LocalizeOptions};
use crate::error::CliError;
use crate::output::{check_output_path, to_json_line, write_text};
use dualspectra::evaluation::datasets::{data_root_from_env, Dataset, Pair, DATA_ENV, DEV_SETS};
use dualspectra::evaluation::metrics::{self, cumulative_iou, Match, Scores};
use dualspectra::operators::lumped_mass;
use dualspectra::{Localizer, Mode, Options, Progress, Timings};
use std::collections::HashMap;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Dataset folder (SHREC'16 cuts/ or holes/, PFARM, PFAUST layout), e.g.
    /// $DUALSPECTRA_DATA/shrec16; with --all, the folder holding the dev sets
    /// (default $DUALSPECTRA_DATA).
    #[arg(value_name = "DATASET")]
    pub dataset: Option<PathBuf>,
    /// Run every dev set present under DATASET: shrec16, shrec16_holes, pfarm, pfaust_m,
    /// pfaust_h (--filter, --stride and --limit apply within each set).
    #[arg(long)]
    pub all: bool,
    #[command(flatten)]
    pub options: LocalizeOptions,
    /// Write per-pair scores and the summary as JSON.
    #[arg(long, value_name = "OUT")]
    pub json: Option<PathBuf>,
    /// Write the cumulative IoU plot as SVG.
    #[arg(long, value_name = "OUT")]
    pub svg: Option<PathBuf>,
    /// Run only the first N pairs (after --filter and --stride).
    #[arg(long, value_name = "N")]
    pub limit: Option<usize>,
    /// Run every N-th pair (after --filter), e.g. `--stride 5` for a spread 16 of the 80.
    #[arg(long, value_name = "N")]
    pub stride: Option<usize>,
    /// Run only pairs whose name contains SUBSTR (e.g. `cat`, `shape_1`).
    #[arg(long, value_name = "SUBSTR")]
    pub filter: Option<String>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

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
    pub scores: dualspectra::selection::CandidateScore,
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

#[derive(Serialize)]
struct Report<'a> {
    dataset: String,
    options: &'a Options,
    summary: &'a Summary,
    pairs: &'a [PairResult],
}

/// One set's results in the `--all` report.
#[derive(Serialize)]
struct SetReport {
    set: String,
    dataset: String,
    summary: Summary,
    pairs: Vec<PairResult>,
}

#[derive(Serialize)]
struct AllReport<'a> {
    root: String,
    options: &'a Options,
    /// Unweighted means of the sets' means (each set counts once).
    mean_of_sets: &'a Summary,
    sets: &'a [SetReport],
}

const ZERO: Scores = Scores {
    precision: 0.0,
    recall: 0.0,
    iou: 0.0,
};

/// Prepared full shapes, one per file: every partial of a full shape reuses its
/// [`Localizer`].
type Prepared = HashMap<PathBuf, Localizer>;

fn run_pair(
    pair: &Pair,
    options: &Options,
    prepared: &mut Prepared,
    progress: &Progress,
) -> Result<PairResult, dualspectra::Error> {
    let data = pair.load()?;
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
        seconds,
        timings: Timings { preparation: seconds - loc.timings.total, ..loc.timings.clone() },
        error: None,
        region: region_indices(&loc.region),
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
    Timings {
        preparation: stat(|t| t.preparation),
        preprocessing: stat(|t| t.preprocessing),
        starts: stat(|t| t.starts),
        optimisation: stat(|t| t.optimisation),
        selection: stat(|t| t.selection),
        region: stat(|t| t.region),
        total: stat(|t| t.total),
    }
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
pub fn cumulative_iou_svg(title: &str, curves: &[(String, Vec<f64>)]) -> Result<String, CliError> {
    use plotters::prelude::*;
    let draw_err =
        |e: &dyn std::fmt::Display| CliError::Internal(format!("cannot draw the SVG plot: {e}"));
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

fn print_row(r: &PairResult) {
    match &r.error {
        None => println!(
            "{:<28} {:>6} {:>6} {:>6.3} {:>6.3} {:>6.3} {:>8.3} {:>5.2} {:>8.2}",
            r.name,
            r.region_size,
            r.gt_size,
            r.scores.precision,
            r.scores.recall,
            r.scores.iou,
            r.scores_sym.iou,
            r.confidence,
            r.seconds
        ),
        Some(e) => println!("{:<28} failed: {e}", r.name),
    }
}

/// The pairs of `dataset` after `--filter`, `--stride` and `--limit`.
fn select_pairs(dataset: &Dataset, args: &Args) -> Result<Vec<Pair>, CliError> {
    let mut pairs = dataset.pairs()?;
    if let Some(f) = &args.filter {
        pairs.retain(|p| p.name.contains(f.as_str()));
    }
    if let Some(s) = args.stride {
        pairs = pairs.into_iter().step_by(s).collect();
    }
    if let Some(n) = args.limit {
        pairs.truncate(n);
    }
    Ok(pairs)
}

/// Run and print one set; `Err` only for cancellation or a dataset that cannot be listed.
fn run_set(dataset: &Dataset, pairs: &[Pair], options: &Options, quiet: bool) -> Result<Vec<PairResult>, CliError> {
    println!(
        "{:<28} {:>6} {:>6} {:>6} {:>6} {:>6} {:>8} {:>5} {:>8}",
        "pair", "|R|", "|G|", "prec", "recall", "IoU", "IoU_sym", "conf", "seconds"
    );
    let n = pairs.len();
    let set = dataset.root().file_name().map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let (bar, progress) = progress_bar(quiet, "bench");
    let mut results = Vec::with_capacity(n);
    let mut prepared = Prepared::new();
    for (i, pair) in pairs.iter().enumerate() {
        bar.set_prefix(format!("bench {set} {}/{n} {}", i + 1, pair.name));
        let sub = progress.sub(i as f64 / n as f64, (i + 1) as f64 / n as f64);
        let r = run_pair(pair, options, &mut prepared, &sub).unwrap_or_else(|e| PairResult {
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
            seconds: 0.0,
            timings: Timings::default(),
            error: Some(e.to_string().split_whitespace().collect::<Vec<_>>().join(" ")),
            region: vec![],
            selected: 0,
            candidates: vec![],
        });
        if matches!(r.error.as_deref(), Some("cancelled")) {
            bar.finish_and_clear();
            return Err(CliError::Core(dualspectra::Error::Cancelled));
        }
        bar.suspend(|| print_row(&r));
        results.push(r);
    }
    bar.finish_and_clear();
    Ok(results)
}

fn print_summary(s: &Summary, mode: Mode) {
    println!(
        "mean ({} pairs, {} failed, mode {}): precision {:.3} recall {:.3} IoU {:.3} | symmetry-aware: precision {:.3} recall {:.3} IoU {:.3} | area-weighted IoU {:.3} | median {:.2} s/pair",
        s.pairs,
        s.failed,
        mode,
        s.mean.precision,
        s.mean.recall,
        s.mean.iou,
        s.mean_sym.precision,
        s.mean_sym.recall,
        s.mean_sym.iou,
        s.mean_area_iou,
        s.median_seconds
    );
    let t = &s.median_stage_seconds;
    println!(
        "median seconds per stage: preparation of the full shape {:.2} (once per shape), preprocessing {:.2}, starts {:.2}, optimisation {:.2}, regions {:.2}, selection {:.2}",
        t.preparation, t.preprocessing, t.starts, t.optimisation, t.region, t.selection
    );
}

/// The cumulative IoU plot of one set's results.
fn set_svg(results: &[PairResult], mode: Mode, title: &str) -> Result<String, CliError> {
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
fn per_set_path(out: &Path, set: &str) -> PathBuf {
    let stem = out.file_stem().map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let ext = out.extension().map_or_else(String::new, |e| format!(".{}", e.to_string_lossy()));
    out.with_file_name(format!("{stem}-{set}{ext}"))
}

/// Unweighted mean over sets of their summaries (each set counts once); seconds are the
/// median of the sets' medians.
fn mean_of_sets(summaries: &[&Summary]) -> Summary {
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

fn print_set_line(set: &str, s: &Summary) {
    println!(
        "{:<16} {:>5} {:>6} {:>6} {:>6} {:>6} {:>8} {:>9}",
        set, s.pairs, s.failed, format!("{:.3}", s.mean.precision), format!("{:.3}", s.mean.recall), format!("{:.3}", s.mean.iou), format!("{:.3}", s.mean_sym.iou), format!("{:.2}", s.median_seconds)
    );
}

pub fn run(args: Args) -> Result<(), CliError> {
    let options = args.options.to_options()?;
    for out in [&args.json, &args.svg].into_iter().flatten() {
        check_output_path(out, &[])?;
    }
    if args.stride == Some(0) {
        return Err(CliError::Usage("--stride must be at least 1".into()));
    }
    if args.all {
        return run_all(&args, &options);
    }
    let Some(root) = &args.dataset else {
        return Err(CliError::Usage("give a DATASET folder, or --all for every dev set".into()));
    };
    let dataset = Dataset::open(root)?;
    let pairs = select_pairs(&dataset, &args)?;
    if pairs.is_empty() {
        return Err(CliError::Usage(format!("{}: no pairs to run (check --filter / --limit)", root.display())));
    }
    let results = run_set(&dataset, &pairs, &options, args.quiet)?;
    let s = summarize(&results);
    print_summary(&s, options.mode);
    if let Some(path) = &args.json {
        let report = Report {
            dataset: root.display().to_string(),
            options: &options,
            summary: &s,
            pairs: &results,
        };
        write_text(path, &to_json_line(&report)?)?;
    }
    if let Some(path) = &args.svg {
        write_text(path, &set_svg(&results, options.mode, "all pairs")?)?;
    }
    Ok(())
}

fn run_all(args: &Args, options: &Options) -> Result<(), CliError> {
    let root = match (&args.dataset, data_root_from_env()) {
        (Some(r), _) => r.clone(),
        (None, Some(r)) => r,
        (None, None) => return Err(CliError::Usage(format!("--all needs the folder holding the dev sets: give it, or set {DATA_ENV}"))),
    };
    let present: Vec<&str> = DEV_SETS.iter().copied().filter(|s| root.join(s).is_dir()).collect();
    if present.is_empty() {
        return Err(CliError::Usage(format!("{}: none of the dev sets {} is there", root.display(), DEV_SETS.join(", "))));
    }
    let mut sets = Vec::new();
    for set in present {
        let dataset = Dataset::open(root.join(set))?;
        let pairs = select_pairs(&dataset, args)?;
        if pairs.is_empty() {
            println!("== {set}: no pairs selected");
            continue;
        }
        println!("== {set} ({} pairs, {})", pairs.len(), dataset.root().display());
        let results = run_set(&dataset, &pairs, options, args.quiet)?;
        let summary = summarize(&results);
        print_summary(&summary, options.mode);
        if let Some(out) = &args.svg {
            write_text(&per_set_path(out, set), &set_svg(&results, options.mode, set)?)?;
        }
        sets.push(SetReport { set: set.to_string(), dataset: dataset.root().display().to_string(), summary, pairs: results });
    }
    if sets.is_empty() {
        return Err(CliError::Usage(format!("{}: no pairs to run (check --filter / --limit)", root.display())));
    }
    let overall = mean_of_sets(&sets.iter().map(|s| &s.summary).collect::<Vec<_>>());
    println!("\n== summary (mode {})", options.mode);
    println!("{:<16} {:>5} {:>6} {:>6} {:>6} {:>6} {:>8} {:>9}", "set", "pairs", "failed", "prec", "recall", "IoU", "IoU_sym", "median_s");
    for s in &sets {
        print_set_line(&s.set, &s.summary);
    }
    print_set_line("mean of sets", &overall);
    if let Some(path) = &args.json {
        let report = AllReport { root: root.display().to_string(), options, mean_of_sets: &overall, sets: &sets };
        write_text(path, &to_json_line(&report)?)?;
    }
    Ok(())
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
            confidence: 1.0,
            optimisation_vertices: 1000,
            seconds: 3.0,
            timings: Timings { optimisation: 2.5, total: 3.0, ..Timings::default() },
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
