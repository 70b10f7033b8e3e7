//! `dualspectra demo [--out DIR]`
//!
//! A self-contained run of the localizer, no data needed: builds the procedural articulated
//! figure of `dualspectra::evaluation::synthetic` (2562 vertices), a copy with one arm bent
//! (near-isometric) cut by a plane into a partial shape with exact ground truth, localizes
//! the partial on the full figure with the same defaults as `localize` (every option flag
//! applies) and prints precision, recall, IoU against the ground truth and the confidence.
//! Writes into DIR (default `demo_out/`): `full.off`, `partial.off`, `region.ply` (full
//! figure, region in red), `ground_truth.ply`, `demo.png` (the figure from the front and the
//! back with the found region, beside the same views with the true one), `result.json` (as
//! `localize --json`), and `dataset/` (the pair in the SHREC'16 layout, for
//! `dualspectra bench DIR/dataset`).

use super::localize::{localize_with_bar, write_region_ply, LocalizeOptions, Output};
use crate::error::CliError;
use crate::output::{to_json_line, write_text};
use crate::render::{demo_picture, write_png};
use dualspectra_lab::datasets::write_shrec16_pair;
use dualspectra::evaluation::metrics::{area_scores, scores};
use dualspectra::evaluation::synthetic::{synthetic_pair, SyntheticParams};
use dualspectra::mesh::io::write_off;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Output folder (created if missing).
    #[arg(long, value_name = "DIR", default_value = "demo_out")]
    pub out: PathBuf,
    #[command(flatten)]
    pub options: LocalizeOptions,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// Map a write failure to the output error (exit code 5).
fn out_err(e: dualspectra::Error) -> CliError {
    match e {
        dualspectra::Error::Io { path, source } => CliError::Output { path, source },
        other => CliError::Core(other),
    }
}

pub fn run(args: Args) -> Result<(), CliError> {
    let options = args.options.to_options_from(dualspectra::Options::default())?;
    std::fs::create_dir_all(&args.out).map_err(|source| CliError::Output {
        path: args.out.clone(),
        source,
    })?;
    let pair = synthetic_pair(&SyntheticParams::default())?;
    let (full_path, partial_path) = (args.out.join("full.off"), args.out.join("partial.off"));
    write_off(&full_path, &pair.full).map_err(out_err)?;
    write_off(&partial_path, &pair.partial).map_err(out_err)?;
    let dataset = args.out.join("dataset");
    write_shrec16_pair(
        &dataset,
        "figure",
        1,
        &pair.full,
        &pair.partial,
        &pair.barycentric_gt(),
        None,
    )
    .map_err(out_err)?;
    outln!(
        "synthetic pair: full {} vertices, partial {} vertices ({:.0}% of the area), one arm bent by 50 degrees",
        pair.full.n_vertices(),
        pair.partial.n_vertices(),
        100.0 * pair.partial.area() / pair.posed.area()
    );
    let (loc, seconds) =
        localize_with_bar((&pair.full, &full_path), (&pair.partial, &partial_path), &options, args.quiet, "localize")?;
    let s = scores(&loc.region, &pair.gt)?;
    let a = area_scores(&pair.full, &loc.region, &pair.gt)?;
    outln!(
        "localized in {seconds:.2} s ({} starts, mode {}): precision {:.3} recall {:.3} IoU {:.3} (area-weighted IoU {:.3}), confidence {:.2}",
        loc.n_starts, options.mode, s.precision, s.recall, s.iou, a.iou, loc.confidence
    );
    write_region_ply(&args.out.join("region.ply"), &pair.full, &loc.region)?;
    write_region_ply(&args.out.join("ground_truth.ply"), &pair.full, &pair.gt)?;
    let found_caption = format!("found: IoU {:.2}, confidence {:.2}", s.iou, loc.confidence);
    let picture = demo_picture(&pair.full, (&loc.region, &found_caption), (&pair.gt, "ground truth"))?;
    write_png(&args.out.join("demo.png"), &picture)?;
    let json = to_json_line(&Output::new(
        &loc,
        &options,
        seconds,
        &pair.full,
        &pair.partial,
    ))?;
    write_text(&args.out.join("result.json"), &json)?;
    outln!(
        "wrote {}/{{full.off, partial.off, region.ply, ground_truth.ply, demo.png, result.json, dataset/}}\n\
         demo.png: the found region (left, front and back) and the true one (right), in red",
        args.out.display()
    );
    Ok(())
}
