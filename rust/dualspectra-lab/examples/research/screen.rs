//! The library screen on the model library (a research harness for `search`'s screen;
//! docs/algorithm.md, "Screening a library").
//!
//! `cargo run -p dualspectra-lab --release --example research_screen -- ROOT [SET:STRIDE ...] [--dims D,D..] [--scale same|auto]...`
//!
//! ROOT is the datasets folder (`library/` and the dev sets). Every library model is
//! described once ([`ScreenEntry`]); each dev partial (SHREC'16 CUTS and HOLES: the right
//! answer is its class; PFAUST: the person, with the query's own source mesh left out) is
//! screened against the whole library. Prints, per set, scale and dimensions: the rank of the
//! first right model (1-based), recall of the right class within the first 1, 5, 10, 20
//! models, and the median screen time per query; one JSON line per query with `--log FILE`.

use dualspectra::lab::{screen_entry_with_keypoints, screen_rank, screen_with_dimensions};
use dualspectra::mesh::io::{read_mesh_with_report, ReadOptions};
use dualspectra::Scale;
use dualspectra_lab::datasets::Dataset;
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

fn median(mut x: Vec<f64>) -> f64 {
    x.sort_by(f64::total_cmp);
    if x.is_empty() { f64::NAN } else { x[x.len() / 2] }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let root = PathBuf::from(args.first().ok_or("usage: research_screen ROOT [SET:STRIDE ...] [--dims 32,352] [--scale same|auto] [--log FILE]")?);
    let mut sets: Vec<(String, usize)> = Vec::new();
    let mut dims = vec![32usize];
    let mut scales = vec![Scale::Same, Scale::Auto];
    let mut relative = true;
    let mut fuse = false;
    let mut log: Option<std::fs::File> = None;
    let mut keypoints = 512;
    let mut i = 1;
    while i < args.len() {
        match args[i].as_str() {
            "--dims" => { dims = args[i + 1].split(',').map(|d| d.parse()).collect::<Result<_, _>>()?; i += 1; }
            "--scale" => { scales = vec![if args[i + 1] == "auto" { Scale::Auto } else { Scale::Same }]; i += 1; }
            "--keypoints" => { keypoints = args[i + 1].parse()?; i += 1; }
            "--absolute" => relative = false,
            "--fuse" => fuse = true,
            "--log" => { log = Some(std::fs::File::create(&args[i + 1])?); i += 1; }
            s => {
                let (name, stride) = s.split_once(':').unwrap_or((s, "1"));
                sets.push((name.to_string(), stride.parse()?));
            }
        }
        i += 1;
    }
    if sets.is_empty() {
        sets = ["shrec16", "shrec16_holes", "pfaust_m", "pfaust_h"].iter().map(|s| (s.to_string(), 1)).collect();
    }
    // The library.
    let labels = std::fs::read_to_string(root.join("library/labels.tsv"))?;
    let mut names = Vec::new();
    let mut classes = Vec::new();
    let mut entries = Vec::new();
    let t = Instant::now();
    for line in labels.lines().filter(|l| !l.trim().is_empty()) {
        let (file, class) = line.split_once('\t').ok_or("labels.tsv: file<TAB>class")?;
        let (mesh, _) = read_mesh_with_report(&root.join("library/shapes").join(file), &ReadOptions::default())?;
        entries.push(screen_entry_with_keypoints(&mesh, keypoints)?);
        names.push(file.trim_end_matches(".off").to_string());
        classes.push(class.to_string());
    }
    let describe = t.elapsed().as_secs_f64();
    println!("library: {} models described in {:.1} s ({:.3} s per model)", entries.len(), describe, describe / entries.len() as f64);
    let screens: Vec<_> = dims.iter().map(|&d| screen_with_dimensions(&entries, d)).collect::<Result<_, _>>()?;
    for (d, s) in dims.iter().zip(&screens) {
        let (per_model, basis) = s.bytes();
        println!("dims {d}: {per_model} bytes per model, basis {basis} bytes");
    }
    println!("| set | scale | dims | queries | first right rank (median / mean) | recall@1 | @5 | @10 | @20 | median s/query |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for (set, stride) in &sets {
        let ds = Dataset::open(root.join(set))?;
        let pairs: Vec<_> = ds.pairs()?.into_iter().step_by(*stride).collect();
        for &scale in &scales {
            for (d, screen) in dims.iter().zip(&screens) {
                let (mut ranks, mut times) = (Vec::new(), Vec::new());
                for pair in &pairs {
                    let (partial, _) = read_mesh_with_report(&pair.partial, &ReadOptions::default())?;
                    let (right, own): (String, Option<String>) = if set.starts_with("pfaust") {
                        // The partial `tr_reg_0PQ` is cut from the library's `faust_tr_reg_0PQ`
                        // (person P, pose Q), which is left out.
                        let person = pair.name.trim_start_matches("tr_reg_").chars().nth(1).unwrap_or('?');
                        (format!("faust_person_{person}"), Some(format!("faust_{}", pair.name)))
                    } else {
                        (pair.class.clone(), None)
                    };
                    let t = Instant::now();
                    let ranked = if fuse && scale == Scale::Auto {
                        // Borda: the mean of the positions under the absolute and relative scores.
                        let a = screen_rank(screen, &partial, scale, false)?;
                        let b = screen_rank(screen, &partial, scale, true)?;
                        let mut pos = vec![0.0f64; names.len()];
                        for (p, r) in a.iter().enumerate() { pos[r.0] += p as f64; }
                        for (p, r) in b.iter().enumerate() { pos[r.0] += p as f64; }
                        let mut v: Vec<(usize, f64)> = pos.into_iter().enumerate().collect();
                        v.sort_by(|x, y| x.1.total_cmp(&y.1).then(x.0.cmp(&y.0)));
                        v
                    } else {
                        screen_rank(screen, &partial, scale, relative)?
                    };
                    times.push(t.elapsed().as_secs_f64());
                    let order: Vec<usize> = ranked.iter().map(|r| r.0).filter(|&m| Some(&names[m]) != own.as_ref()).collect();
                    let rank = order.iter().position(|&m| classes[m] == right).map_or(usize::MAX, |p| p + 1);
                    ranks.push(rank);
                    if let Some(f) = log.as_mut() {
                        let top: Vec<String> = order.iter().take(10).map(|&m| names[m].clone()).collect();
                        writeln!(f, "{}", serde_json::json!({"set": set, "partial": pair.name, "scale": format!("{scale:?}"), "dims": d, "right": right, "rank": rank, "top": top}))?;
                    }
                }
                let n = ranks.len() as f64;
                let at = |k: usize| ranks.iter().filter(|&&r| r <= k).count() as f64 / n;
                let mean = ranks.iter().map(|&r| r.min(names.len()) as f64).sum::<f64>() / n;
                println!(
                    "| {set} | {scale:?} | {d} | {} | {} / {:.1} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} |",
                    ranks.len(), median(ranks.iter().map(|&r| r as f64).collect()), mean, at(1), at(5), at(10), at(20), median(times)
                );
            }
        }
    }
    Ok(())
}
