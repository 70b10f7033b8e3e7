//! `dualspectra bench DATASET [options] [--json OUT] [--svg OUT] [--limit N] [--filter SUBSTR]
//! [--stride N]`, `dualspectra bench --all [ROOT] ...`
//!
//! Runs the localizer on every pair of a dataset (SHREC'16 CUTS or HOLES, PFARM or PFAUST
//! layout, see `dualspectra_lab::datasets`; the work is `dualspectra_lab::bench`), one pair after another (the localizer
//! is itself parallel), and scores each region against the ground truth:
//! precision, recall and IoU by vertex counts, also symmetry-aware (the better of the
//! direct and the left-right mirrored ground truth, as SHREC'16 accepts symmetric
//! matches). Prints a table and the means; a pair that fails scores 0 and is listed with
//! its error. `--json` writes every pair's scores, `--svg` the cumulative IoU curve (the
//! paper's Fig. 5: fraction of pairs with IoU >= x; its area is the mean IoU). `--all` runs
//! every dev set found under ROOT (default `$DUALSPECTRA_DATA`): a table per set, then one
//! line per set and the means across sets; `--json` then holds every set, `--svg OUT`
//! writes one plot per set (`OUT` with `-<set>` before the extension).

use super::localize::{progress_bar, LocalizeOptions};
use crate::error::CliError;
use crate::output::{check_output_path, to_json_line, write_text};
use dualspectra::{Mode, Options};
use dualspectra_lab::bench::{
    failed_pair, mean_of_sets, per_set_path, run_pair, summarize, AllReport, PairResult, Prepared, Report, Selection, Transform,
    SetReport, Summary,
};
use dualspectra_lab::datasets::{data_root_from_env, Dataset, Pair, DATA_ENV, DEV_SETS};
use std::path::PathBuf;

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
    /// Change each partial before locating it: none, rigid (a random rotation and
    /// translation), units (rigid, times a factor in [1e-3, 1e3]) or size (rigid, times a
    /// factor in [0.8, 1.25]); deterministic per pair. For measuring `--scale`.
    #[arg(long, value_name = "KIND", default_value = "none")]
    pub transform: Transform,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

fn print_row(r: &PairResult) {
    match &r.error {
        None => outln!(
            "{:<28} {:>6} {:>6} {:>6.3} {:>6.3} {:>6.3} {:>8.3} {:>5.2} {:>8.2}{}",
            r.name,
            r.region_size,
            r.gt_size,
            r.scores.precision,
            r.scores.recall,
            r.scores.iou,
            r.scores_sym.iou,
            r.confidence,
            r.seconds,
            // The scale left after the transform and the localizer's factor (1: undone).
            if r.applied_factor != 1.0 || r.scale != 1.0 { format!("  scale x{:.3}", r.scale * r.applied_factor) } else { String::new() }
        ),
        Some(e) => outln!("{:<28} failed: {e}", r.name),
    }
}

/// The pairs of `dataset` after `--filter`, `--stride` and `--limit`.
fn select_pairs(dataset: &Dataset, args: &Args) -> Result<Vec<Pair>, CliError> {
    let selection = Selection { filter: args.filter.clone(), stride: args.stride, limit: args.limit };
    Ok(dualspectra_lab::bench::select_pairs(dataset, &selection)?)
}

/// The cumulative IoU plot of one set's results.
fn set_svg(results: &[PairResult], mode: Mode, title: &str) -> Result<String, CliError> {
    dualspectra_lab::bench::set_svg(results, mode, title)
        .map_err(|e| CliError::Internal(format!("cannot draw the SVG plot: {e}")))
}

/// Run and print one set; `Err` only for cancellation or a dataset that cannot be listed.
fn run_set(dataset: &Dataset, pairs: &[Pair], options: &Options, transform: Transform, quiet: bool) -> Result<Vec<PairResult>, CliError> {
    outln!(
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
        let r = run_pair(pair, options, transform, &mut prepared, &sub).unwrap_or_else(|e| failed_pair(pair, &e));
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
    outln!(
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
    outln!(
        "median seconds per stage: preparation of the full shape {:.2} (once per shape), preprocessing {:.2}, starts {:.2}, optimisation {:.2}, regions {:.2}, selection {:.2}",
        t.preparation, t.preprocessing, t.starts, t.optimisation, t.region, t.selection
    );
}

fn print_set_line(set: &str, s: &Summary) {
    outln!(
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
    let results = run_set(&dataset, &pairs, &options, args.transform, args.quiet)?;
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
            outln!("== {set}: no pairs selected");
            continue;
        }
        outln!("== {set} ({} pairs, {})", pairs.len(), dataset.root().display());
        let results = run_set(&dataset, &pairs, options, args.transform, args.quiet)?;
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
    outln!("\n== summary (mode {})", options.mode);
    outln!("{:<16} {:>5} {:>6} {:>6} {:>6} {:>6} {:>8} {:>9}", "set", "pairs", "failed", "prec", "recall", "IoU", "IoU_sym", "median_s");
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
