//! Stability under input noise at the last bits: every coordinate of both shapes moved by a
//! uniform random offset of relative size `EPS` (of the bounding-box diagonal), `RUNS`
//! times per pair; prints each run's symmetry-aware IoU, the spread (max - min) per pair
//! and the start each run chose. A research harness; numbers go to docs/benchmarks/options.md.
//!
//! `cargo run -p dualspectra-lab --release --example research_jitter -- ROOT [PAIRS_PER_SET] [RUNS] [EPS|f32] [both|partial|full]`
//!
//! `f32` instead of EPS rounds the coordinates to single precision (what a host such as
//! Blender stores) in every moved run, run r first moved by (r - 1) * 1e-12 of the diagonal.
//!
//! ROOT holds the dev sets (`$DUALSPECTRA_DATA`); pairs are spread evenly over each set.
//! The last argument moves only one of the shapes (default both), to tell where the
//! sensitivity comes from; each run also prints the optimisation mesh's vertex count,
//! starred where its vertices differ from the unmoved run's.

use dualspectra_lab::datasets::{Dataset, DEV_SETS};
use dualspectra::evaluation::metrics::{scores, symmetry_aware};
use dualspectra::{Localizer, Options, Progress, TriMesh};

/// A deterministic uniform offset in [-1, 1] per (seed, index) (SplitMix64).
fn unit_noise(seed: u64, i: u64) -> f64 {
    let mut z = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ i.wrapping_add(0xD1B5_4A32_D192_ED03);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

fn jitter(mesh: &TriMesh, eps: f64, seed: u64, single: bool) -> Result<TriMesh, dualspectra::Error> {
    let h = eps * mesh.bbox_diagonal();
    let (mut v, f) = mesh.clone().into_parts();
    for (i, p) in v.iter_mut().enumerate() {
        for (d, c) in p.iter_mut().enumerate() {
            *c += h * unit_noise(seed, (3 * i + d) as u64);
            if single {
                *c = *c as f32 as f64;
            }
        }
    }
    TriMesh::new(v, f).map_err(Into::into)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let root = std::path::PathBuf::from(args.get(1).ok_or("usage: research_jitter ROOT [PAIRS_PER_SET] [RUNS] [EPS|f32] [both|partial|full]")?);
    let per_set: usize = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(2);
    let runs: u64 = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(5);
    let single = args.get(4).is_some_and(|s| s == "f32");
    let eps: f64 = if single { 0.0 } else { args.get(4).map(|s| s.parse()).transpose()?.unwrap_or(1e-9) };
    let moved = args.get(5).map_or("both", String::as_str);
    let (move_full, move_partial) = match moved {
        "both" => (true, true),
        "partial" => (false, true),
        "full" => (true, false),
        other => return Err(format!("moved shapes: both, partial or full, not {other:?}").into()),
    };
    let options = Options::default();
    let mut spreads = Vec::new();
    for set in DEV_SETS.iter().filter(|s| root.join(s).is_dir()) {
        let pairs = Dataset::open(root.join(set))?.pairs()?;
        let step = (pairs.len() / per_set.max(1)).max(1);
        for pair in pairs.iter().step_by(step).take(per_set) {
            let data = pair.load()?;
            let mut ious = Vec::new();
            let mut chosen = Vec::new();
            let mut coarse = Vec::new();
            let mut first_kept: Option<Vec<u32>> = None;
            for run in 0..=runs {
                // Run 0 is the input as read; runs 1.. are jittered.
                let full = if run > 0 && move_full { jitter(&data.full, if single { 1e-12 * (run - 1) as f64 } else { eps }, 2 * run, single)? } else { data.full.clone() };
                let partial = if run > 0 && move_partial { jitter(&data.partial, if single { 1e-12 * (run - 1) as f64 } else { eps }, 2 * run + 1, single)? } else { data.partial.clone() };
                let localizer = Localizer::new(&full, &options)?;
                // The decimation's kept vertices, compared with the unmoved run's.
                let kept = dualspectra::lab::optimisation_vertex_origins(&localizer).to_vec();
                let same = first_kept.get_or_insert_with(|| kept.clone()) == &kept;
                let found = localizer.locate(&partial, &Progress::none())?;
                // The mesh the partial was optimised on (the finer one for a partial with holes;
                // `*`: the prepared mesh's kept vertices differ from the unmoved run's).
                coarse.push(format!("{}{}", found.optimisation_vertices, if same { "" } else { "*" }));
                let iou = match &data.gt_sym {
                    Some(sym) => symmetry_aware(&found.region, &data.gt, sym, None)?.0.iou,
                    None => scores(&found.region, &data.gt)?.iou,
                };
                ious.push(iou);
                chosen.push(found.candidates[found.selected_start].label.clone());
            }
            let (lo, hi) = ious.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| (l.min(x), h.max(x)));
            let shown: Vec<String> = ious.iter().map(|x| format!("{x:.3}")).collect();
            println!(
                "{set} {} spread {:.3} iou [{}] chosen [{}] optimisation vertices [{}]",
                pair.name,
                hi - lo,
                shown.join(" "),
                chosen.join(" "),
                coarse.join(" ")
            );
            spreads.push(hi - lo);
        }
    }
    let n = spreads.len().max(1) as f64;
    println!(
        "pairs {} mean spread {:.3} max spread {:.3}",
        spreads.len(),
        spreads.iter().sum::<f64>() / n,
        spreads.iter().cloned().fold(0.0, f64::max)
    );
    Ok(())
}
