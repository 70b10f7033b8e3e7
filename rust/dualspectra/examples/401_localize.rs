//! Chapter 4, localization: find the region of a full shape that a partial shape is.
//!
//! `cargo run --release --example 401_localize -- [FULL PARTIAL]` (without files: a procedural
//! figure and a part cut off a bent copy of it, with the true region to compare).
//! One [`Localizer`] prepares the full shape once; `locate` may then be called for many
//! partials.

use dualspectra::evaluation::metrics::scores;
use dualspectra::evaluation::synthetic::{synthetic_pair, SyntheticParams};
use dualspectra::mesh::io::read_mesh;
use dualspectra::{Localizer, Options, Progress};

fn main() -> dualspectra::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (full, partial, truth) = if let [full, partial] = args.as_slice() {
        (read_mesh(full.as_ref())?, read_mesh(partial.as_ref())?, None)
    } else {
        let pair = synthetic_pair(&SyntheticParams::default())?;
        (pair.full, pair.partial, Some(pair.gt))
    };
    let localizer = Localizer::new(&full, &Options::default())?;
    let progress = Progress::new(|fraction, stage| {
        eprint!("\r{:3.0}% {stage:<16}", 100.0 * fraction);
        true // false cancels
    });
    let found = localizer.locate(&partial, &progress)?;
    eprintln!();
    let size = found.region.iter().filter(|&&inside| inside).count();
    println!("region: {size} of {} vertices, {:.2} s, chosen start {}", full.n_vertices(), found.timings.total, found.candidates[found.selected_start].label);
    if let Some(truth) = truth {
        let s = scores(&found.region, &truth)?;
        println!("against the truth: precision {:.3}, recall {:.3}, IoU {:.3}", s.precision, s.recall, s.iou);
    }
    for warning in &found.warnings {
        println!("warning: {warning}");
    }
    Ok(())
}
