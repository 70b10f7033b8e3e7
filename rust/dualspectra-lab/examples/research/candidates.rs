//! Every candidate of every pair, scored against the ground truth (a research harness: the
//! logs behind the selection studies in docs/benchmarks/options.md; the user-facing benchmark is
//! `dualspectra bench`).
//!
//! `cargo run -p dualspectra-lab --release --example research_candidates -- DATASET [STRIDE] [OFFSET] [OPTIONS_JSON] [--gt-start]`
//!
//! One line per candidate: pair, label, final cost, the five selection scores, its
//! symmetry-aware IoU, `*` on the chosen one (`-` otherwise), its number of cost evaluations,
//! and its cost after each trust-region iteration (comma-separated: the early-pruning study
//! of docs/benchmarks/options.md, "Where the time goes"). One [`Localizer`] per full shape.
//!
//! `--gt-start` adds the ground-truth region as one more start (`given#0`): whether the
//! optimiser keeps a right region and the choice recognises it (docs/benchmarks/options.md).

use dualspectra_lab::datasets::Dataset;
use dualspectra::evaluation::metrics::{scores, symmetry_aware};
use dualspectra::lab::locate_with_initial_regions;
use dualspectra::{Localizer, Options, Progress};
use std::collections::HashMap;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = dualspectra_lab::args::from_env();
    let gt_start = dualspectra_lab::args::take_flag(&mut args, "--gt-start");
    let root = args.first().ok_or("usage: research_candidates DATASET [STRIDE] [OFFSET] [OPTIONS_JSON] [--gt-start]")?;
    let stride: usize = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(1).max(1);
    let offset: usize = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(0);
    let options = match args.get(3) {
        Some(json) => Options::from_json(json)?,
        None => Options::default(),
    };
    let show = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.4}"));
    println!("pair label cost descriptor_score region_cost boundary_misfit partial_fit vote_share iou_sym chosen evaluations history closest_earlier");
    let mut prepared: HashMap<std::path::PathBuf, Localizer> = HashMap::new();
    for pair in Dataset::open(root)?.pairs()?.iter().skip(offset).step_by(stride) {
        let data = pair.load()?;
        if !prepared.contains_key(&pair.full) {
            prepared.insert(pair.full.clone(), Localizer::new(&data.full, &options)?);
        }
        let given = if gt_start { vec![data.gt.clone()] } else { Vec::new() };
        let found = locate_with_initial_regions(&prepared[&pair.full], &data.partial, &given, &Progress::none())?;
        for (i, c) in found.candidates.iter().enumerate() {
            let iou = match &data.gt_sym {
                Some(sym) => symmetry_aware(&c.region, &data.gt, sym, None)?.0.iou,
                None => scores(&c.region, &data.gt)?.iou,
            };
            let s = c.scores;
            println!(
                "{} {} {:.4e} {} {} {} {} {} {iou:.3} {} {} {} {}",
                pair.name,
                c.label,
                c.cost,
                show(s.descriptor_score),
                show(s.region_cost),
                show(s.boundary_misfit),
                show(s.partial_fit),
                show(s.vote_share),
                if i == found.selected_start { "*" } else { "-" },
                c.evaluations,
                c.cost_history.iter().map(|h| format!("{h:.4e}")).collect::<Vec<_>>().join(","),
                closest_earlier(&found.candidates, i)?
            );
        }
    }
    Ok(())
}

/// The earlier candidate whose full-shape region is closest to candidate `i`'s, as
/// `index:IoU` (`-` for the first): how many starts end in the same region.
fn closest_earlier(candidates: &[dualspectra::Candidate], i: usize) -> dualspectra::Result<String> {
    let mut closest: Option<(usize, f64)> = None;
    for j in 0..i {
        let iou = scores(&candidates[i].region, &candidates[j].region)?.iou;
        if closest.is_none_or(|(_, best)| iou >= best) {
            closest = Some((j, iou));
        }
    }
    Ok(closest.map_or("-".to_string(), |(j, v)| format!("{j}:{v:.3}")))
}
