//! Every start of every pair, before optimisation, scored against the ground truth (a research
//! harness: how good the regions are that the optimisation begins from; docs/benchmarks/options.md).
//!
//! `cargo run -p dualspectra-lab --release --example research_starts -- DATASET [STRIDE] [OFFSET] [OPTIONS_JSON]`
//!
//! One line per start: pair, label, its symmetry-aware IoU. One [`Localizer`] per full shape.

use dualspectra_lab::datasets::Dataset;
use dualspectra::evaluation::metrics::{scores, symmetry_aware};
use dualspectra::lab::start_regions;
use dualspectra::{Localizer, Options};
use std::collections::HashMap;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let root = args.get(1).ok_or("usage: research_starts DATASET [STRIDE] [OFFSET] [OPTIONS_JSON]")?;
    let stride: usize = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(1).max(1);
    let offset: usize = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(0);
    let options = match args.get(4) {
        Some(json) => Options::from_json(json)?,
        None => Options::default(),
    };
    println!("pair label iou_sym");
    let mut prepared: HashMap<std::path::PathBuf, Localizer> = HashMap::new();
    for pair in Dataset::open(root)?.pairs()?.iter().skip(offset).step_by(stride) {
        let data = pair.load()?;
        if !prepared.contains_key(&pair.full) {
            prepared.insert(pair.full.clone(), Localizer::new(&data.full, &options)?);
        }
        for (label, region) in start_regions(&prepared[&pair.full], &data.partial)? {
            let iou = match &data.gt_sym {
                Some(sym) => symmetry_aware(&region, &data.gt, sym, None)?.0.iou,
                None => scores(&region, &data.gt)?.iou,
            };
            println!("{} {label} {iou:.3}", pair.name);
        }
    }
    Ok(())
}
