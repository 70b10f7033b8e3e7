//! Every candidate of every pair, scored against the ground truth (a research harness: the
//! logs behind the selection studies in docs/benchmarks/; the user-facing benchmark is
//! `dualspectra bench`).
//!
//! `cargo run --release --example research_candidates -- DATASET [STRIDE] [OFFSET] [OPTIONS_JSON]`
//!
//! One line per candidate: pair, label, final cost, the five selection scores, its
//! symmetry-aware IoU, `*` on the chosen one. One [`Localizer`] per full shape.
//!
//! `DS_GT_START=1` adds the ground-truth region as one more start (`given#0`): whether the
//! optimiser keeps a right region and the choice recognises it (docs/benchmarks/).

use dualspectra::evaluation::datasets::Dataset;
use dualspectra::evaluation::metrics::{scores, symmetry_aware};
use dualspectra::{Localizer, Options, Progress};
use std::collections::HashMap;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let root = args.get(1).ok_or("usage: research_candidates DATASET [STRIDE] [OFFSET] [OPTIONS_JSON]")?;
    let stride: usize = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(1).max(1);
    let offset: usize = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(0);
    let options = match args.get(4) {
        Some(json) => Options::from_json(json)?,
        None => Options::default(),
    };
    let gt_start = std::env::var("DS_GT_START").is_ok_and(|v| v == "1");
    let show = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.4}"));
    println!("pair label cost descriptor_score region_cost boundary_misfit partial_fit vote_share iou_sym chosen");
    let mut prepared: HashMap<std::path::PathBuf, Localizer> = HashMap::new();
    for pair in Dataset::open(root)?.pairs()?.iter().skip(offset).step_by(stride) {
        let data = pair.load()?;
        if !prepared.contains_key(&pair.full) {
            prepared.insert(pair.full.clone(), Localizer::new(&data.full, &options)?);
        }
        let given = if gt_start { vec![data.gt.clone()] } else { Vec::new() };
        let found = prepared[&pair.full].locate_with_initial_regions(&data.partial, &given, &Progress::none())?;
        for (i, c) in found.candidates.iter().enumerate() {
            let iou = match &data.gt_sym {
                Some(sym) => symmetry_aware(&c.region, &data.gt, sym, None)?.0.iou,
                None => scores(&c.region, &data.gt)?.iou,
            };
            let s = c.scores;
            println!(
                "{} {} {:.4e} {} {} {} {} {} {iou:.3} {}",
                pair.name,
                c.label,
                c.cost,
                show(s.descriptor_score),
                show(s.region_cost),
                show(s.boundary_misfit),
                show(s.partial_fit),
                show(s.vote_share),
                if i == found.selected_start { "*" } else { "" }
            );
        }
    }
    Ok(())
}
