//! Retrieval on the dev sets: which of a set's full shapes is a partial part of? Every
//! partial (on a stride) is located on each of the set's full shapes (`null/`), and the raw
//! numbers of every (partial, full) localization are logged once, as JSON lines, so that
//! every similarity score can be evaluated offline from one run; the baseline is the
//! full-shape dual ShapeDNA distance of the partial ([`similarity`]). A research harness;
//! its numbers are the study behind the similarity score (docs/algorithm.md, "Why this score").
//!
//! ```text
//! research_retrieval [--threads N] run ROOT LOG.jsonl [SET:STRIDE[:OFFSET] ...]   (default shrec16:4 shrec16_holes:4 pfaust_m:11:1 pfaust_h:11:1)
//! research_retrieval analyse LOG.jsonl                     top-1 and mean reciprocal rank per set and score
//! research_retrieval time SET_DIR [REPEATS]                 preparing vs loading each full shape (median of REPEATS)
//! ```
//!
//! `run` appends to LOG.jsonl and skips the pairs already in it (a stopped run resumes, and
//! overlapping strides of one set localize a shared partial once);
//! `--threads N` (anywhere) sets the localizer's threads (default 2), `--max-iterations N`
//! the trust-region iterations per start (default: the localizer's).

use dualspectra_lab::datasets::Dataset;
use dualspectra::evaluation::metrics::{scores, symmetry_aware};
use dualspectra::evaluation::similarity::{dual_shape_dna, Descriptor};
use dualspectra::mesh::io::{read_mesh_with_report, ReadOptions};
use dualspectra::lab::selection::{agreement, similarity_score};
use dualspectra::localizer::CandidateScore;
use dualspectra::{Localizer, Options, Progress};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashSet};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Sets with the stride and offset of the partials taken (pairs sorted by class and name).
/// PFAUST's pairs are person-major with the pose last and pose 0 is the full shape's own
/// pose: stride 11 from 1 takes one partial per person, poses 1 to 8.
const DEFAULT_SETS: [(&str, usize, usize); 4] = [("shrec16", 4, 0), ("shrec16_holes", 4, 0), ("pfaust_m", 11, 1), ("pfaust_h", 11, 1)];

/// Eigenvalues per metric of the dual ShapeDNA baseline (the `similarity` command's default).
const DNA_K: usize = 20;

/// One candidate (optimised start) of a localization.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct CandidateLog {
    label: String,
    cost: Option<f64>,
    #[serde(flatten)]
    scores: CandidateScore,
    region_vertices: usize,
}

/// The raw numbers of one (partial, full) localization.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct PairLog {
    set: String,
    partial: String,
    full: String,
    /// The full shape the partial is a part of.
    truth: String,
    /// Dual ShapeDNA distance of the partial to the full shape (the baseline).
    dna_distance: Option<f64>,
    /// Area of the partial over the full shape's.
    area_ratio: f64,
    seconds: f64,
    error: Option<String>,
    #[serde(default)]
    n_full: usize,
    #[serde(default)]
    region_vertices: usize,
    /// Final relaxed alignment cost of the chosen start (`None`: failed, or NaN).
    #[serde(default)]
    cost: Option<f64>,
    #[serde(default)]
    confidence: f64,
    #[serde(default)]
    selected: usize,
    #[serde(default)]
    consensus: f64,
    #[serde(default)]
    margin: f64,
    #[serde(default)]
    candidates: Vec<CandidateLog>,
    #[serde(default)]
    target_regular: Vec<f64>,
    #[serde(default)]
    target_si: Vec<f64>,
    #[serde(default)]
    eigenvalues_regular: Vec<f64>,
    #[serde(default)]
    eigenvalues_si: Vec<f64>,
    /// Symmetry-aware IoU with the ground truth, on the true full shape.
    #[serde(default)]
    iou: Option<f64>,
}

fn stem(path: &Path) -> String {
    path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()
}

fn off_files(dir: &Path) -> Result<Vec<PathBuf>, Box<dyn std::error::Error>> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("off")))
        .collect();
    out.sort();
    Ok(out)
}

fn run(root: &Path, log: &Path, sets: &[(String, usize, usize)], options: &Options) -> Result<(), Box<dyn std::error::Error>> {
    let mut done: HashSet<(String, String, String)> = read_log(log)
        .unwrap_or_default()
        .into_iter()
        .map(|p| (p.set, p.partial, p.full))
        .collect();
    let mut out = std::fs::OpenOptions::new().create(true).append(true).open(log)?;
    let read = ReadOptions { drop_isolated: true, ..ReadOptions::default() };
    for (set, stride, offset) in sets {
        let dataset = Dataset::open(root.join(set))?;
        let pairs: Vec<_> = dataset.pairs()?.into_iter().skip(*offset).step_by((*stride).max(1)).collect();
        let full_paths = off_files(&root.join(set).join("null"))?;
        let t0 = Instant::now();
        let mut fulls = Vec::new();
        for path in &full_paths {
            let (mesh, _) = read_mesh_with_report(path, &read)?;
            let dna = dual_shape_dna(&mesh, DNA_K)?.descriptor(Descriptor::Dual)?;
            let localizer = Localizer::new(&mesh, options)?;
            fulls.push((stem(path), mesh.area(), dna, localizer));
        }
        println!("{set}: {} partials x {} full shapes, prepared in {:.1} s", pairs.len(), fulls.len(), t0.elapsed().as_secs_f64());
        for pair in &pairs {
            let data = pair.load()?;
            let truth = stem(&pair.full);
            let partial_dna = dual_shape_dna(&data.partial, DNA_K).and_then(|d| d.descriptor(Descriptor::Dual));
            for (name, area, dna, localizer) in &fulls {
                if done.contains(&(set.clone(), pair.name.clone(), name.clone())) {
                    continue;
                }
                let dna_distance = partial_dna
                    .as_ref()
                    .ok()
                    .map(|p| p.iter().zip(dna).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt());
                let t = Instant::now();
                let found = localizer.locate(&data.partial, &Progress::none());
                let mut entry = PairLog {
                    set: set.clone(),
                    partial: pair.name.clone(),
                    full: name.clone(),
                    truth: truth.clone(),
                    dna_distance,
                    area_ratio: data.partial.area() / area,
                    seconds: t.elapsed().as_secs_f64(),
                    error: None,
                    n_full: localizer.n_vertices(),
                    region_vertices: 0,
                    cost: None,
                    confidence: 0.0,
                    selected: 0,
                    consensus: 0.0,
                    margin: 0.0,
                    candidates: Vec::new(),
                    target_regular: Vec::new(),
                    target_si: Vec::new(),
                    eigenvalues_regular: Vec::new(),
                    eigenvalues_si: Vec::new(),
                    iou: None,
                };
                match found {
                    Err(e) => entry.error = Some(e.to_string()),
                    Ok(loc) => {
                        let regions: Vec<&[bool]> = loc.candidates.iter().map(|c| c.region.as_slice()).collect();
                        let all: Vec<CandidateScore> = loc.candidates.iter().map(|c| c.scores).collect();
                        let g = agreement(&regions, &all, loc.selected_start);
                        if *name == truth {
                            entry.iou = Some(match &data.gt_sym {
                                Some(sym) => symmetry_aware(&loc.region, &data.gt, sym, None)?.0.iou,
                                None => scores(&loc.region, &data.gt)?.iou,
                            });
                        }
                        entry.region_vertices = loc.region.iter().filter(|&&b| b).count();
                        entry.cost = (!loc.cost.is_nan()).then_some(loc.cost);
                        entry.confidence = loc.confidence;
                        entry.selected = loc.selected_start;
                        entry.consensus = g.consensus;
                        entry.margin = g.margin;
                        entry.candidates = loc
                            .candidates
                            .iter()
                            .map(|c| CandidateLog {
                                label: c.label.clone(),
                                cost: (!c.cost.is_nan()).then_some(c.cost),
                                scores: c.scores,
                                region_vertices: c.region.iter().filter(|&&b| b).count(),
                            })
                            .collect();
                        entry.target_regular = loc.target_regular;
                        entry.target_si = loc.target_si;
                        entry.eigenvalues_regular = loc.eigenvalues_regular;
                        entry.eigenvalues_si = loc.eigenvalues_si;
                    }
                }
                println!(
                    "{set} {} on {name}{}: {:.1} s, cost {:.3e}, confidence {:.2}{}",
                    pair.name,
                    if *name == truth { " (true)" } else { "" },
                    entry.seconds,
                    entry.cost.unwrap_or(f64::NAN),
                    entry.confidence,
                    entry.error.as_ref().map(|e| format!(", error: {e}")).unwrap_or_default()
                );
                writeln!(out, "{}", serde_json::to_string(&entry)?)?;
                done.insert((set.clone(), pair.name.clone(), name.clone()));
                out.flush()?;
            }
        }
    }
    Ok(())
}

fn read_log(path: &Path) -> Result<Vec<PairLog>, Box<dyn std::error::Error>> {
    let text = std::fs::read_to_string(path)?;
    let mut out = Vec::new();
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        // A line cut by a stopped run is skipped (its pair is run again).
        if let Ok(entry) = serde_json::from_str::<PairLog>(line) {
            out.push(entry);
        }
    }
    Ok(out)
}

/// A score candidate: a name and a lower-is-better value of one localization (`None`: the
/// localization failed; ranks last).
type Scorer = (&'static str, fn(&PairLog) -> Option<f64>);

fn chosen(p: &PairLog) -> Option<&CandidateLog> {
    p.candidates.get(p.selected)
}

/// Number of matched eigenvalues.
fn n_mu(p: &PairLog) -> f64 {
    (p.target_regular.len() + p.target_si.len()).max(1) as f64
}

fn finite(x: Option<f64>) -> Option<f64> {
    x.filter(|v| v.is_finite())
}

const SCORERS: &[Scorer] = &[
    ("dna_distance (baseline)", |p| finite(p.dna_distance)),
    ("dna_distance, area-feasible first", |p| {
        let d = finite(p.dna_distance)?;
        Some(if p.area_ratio > AREA_LIMIT { 1e6 + d } else { d })
    }),
    ("cost (relaxed misfit)", |p| finite(p.cost)),
    ("region_cost (chosen)", |p| finite(chosen(p)?.scores.region_cost)),
    ("min region_cost", |p| {
        let m = p.candidates.iter().filter_map(|c| finite(c.scores.region_cost)).fold(f64::INFINITY, f64::min);
        finite(Some(m))
    }),
    ("partial_fit (chosen)", |p| finite(chosen(p)?.scores.partial_fit)),
    ("min partial_fit", |p| {
        let m = p.candidates.iter().filter_map(|c| finite(c.scores.partial_fit)).fold(f64::INFINITY, f64::min);
        finite(Some(m))
    }),
    ("min partial_fit, gated", |p| {
        // Among the candidates the region-cost gate of the earlier selection (3x the lowest,
        // floor n_mu * 0.1^2) admitted.
        let best = p.candidates.iter().filter_map(|c| finite(c.scores.region_cost)).fold(f64::INFINITY, f64::min);
        let gate = (3.0 * best).max(n_mu(p) * 0.01);
        let m = p
            .candidates
            .iter()
            .filter(|c| c.scores.region_cost.is_some_and(|r| r <= gate))
            .filter_map(|c| finite(c.scores.partial_fit))
            .fold(f64::INFINITY, f64::min);
        finite(Some(m))
    }),
    ("descriptor_score (chosen)", |p| finite(chosen(p)?.scores.descriptor_score)),
    ("ranking (chosen)", |p| finite(chosen(p)?.scores.ranking())),
    ("1 - confidence", |p| p.error.is_none().then_some(1.0 - p.confidence)),
    ("rms rel. misfit x partial_fit", |p| {
        let c = chosen(p)?;
        finite(Some((c.scores.region_cost? / n_mu(p)).sqrt() * c.scores.partial_fit?))
    }),
    ("rms rel. misfit x partial_fit^2", |p| {
        let c = chosen(p)?;
        finite(Some((c.scores.region_cost? / n_mu(p)).sqrt() * c.scores.partial_fit?.powi(2)))
    }),
    ("rms rel. misfit + partial_fit", |p| {
        let c = chosen(p)?;
        finite(Some((c.scores.region_cost? / n_mu(p)).sqrt() + c.scores.partial_fit?))
    }),
    ("library score", |p| p.error.is_none().then(|| library_score(p)).and_then(|s| finite(Some(s)))),
    ("sqrt(cost/n) x partial_fit", |p| {
        let c = chosen(p)?;
        finite(Some((p.cost? / n_mu(p)).sqrt() * c.scores.partial_fit?))
    }),
];

/// The largest partial-to-full area ratio the localizer accepts.
const AREA_LIMIT: f64 = 1.1;

/// The library's similarity score from the logged candidates' scores.
fn library_score(p: &PairLog) -> f64 {
    similarity_score(&p.candidates.iter().map(|c| c.scores).collect::<Vec<_>>())
}

/// Rank of the true full shape among a partial's (1 = first; ties broken by full-shape
/// name, as search breaks them by index) for each scorer.
fn analyse(log: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let entries = read_log(log)?;
    // set -> partial -> entries
    let mut by_set: BTreeMap<String, BTreeMap<String, Vec<&PairLog>>> = BTreeMap::new();
    for e in &entries {
        by_set.entry(e.set.clone()).or_default().entry(e.partial.clone()).or_default().push(e);
    }
    // Only partials located on every full shape of their set count.
    for partials in by_set.values_mut() {
        let most = partials.values().map(Vec::len).max().unwrap_or(0);
        partials.retain(|_, list| list.len() == most);
    }
    let mut header = format!("{:<34}", "score");
    for set in by_set.keys() {
        header.push_str(&format!(" | {:>16}", set));
    }
    println!("{header}\n{:<34}{}", "", " |  top-1      MRR".repeat(by_set.len()));
    for (name, f) in SCORERS {
        let mut line = format!("{name:<34}");
        for partials in by_set.values() {
            let (mut top1, mut rr, mut n) = (0.0, 0.0, 0.0);
            for list in partials.values() {
                let mut ranked: Vec<(f64, &str, bool)> =
                    list.iter().map(|e| (f(e).unwrap_or(f64::INFINITY), e.full.as_str(), e.full == e.truth)).collect();
                if !ranked.iter().any(|r| r.2) {
                    continue;
                }
                ranked.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(b.1)));
                let rank = ranked.iter().position(|r| r.2).unwrap_or(0) + 1;
                top1 += (rank == 1) as u8 as f64;
                rr += 1.0 / rank as f64;
                n += 1.0;
            }
            line.push_str(&format!(" | {:>6.3} {:>8.3}", top1 / n, rr / n));
        }
        println!("{line}");
    }
    for (set, partials) in &by_set {
        let pairs: usize = partials.values().map(Vec::len).sum();
        let errors = partials.values().flatten().filter(|e| e.error.is_some()).count();
        let seconds: f64 = partials.values().flatten().map(|e| e.seconds).sum();
        let ious: Vec<f64> = partials.values().flatten().filter_map(|e| e.iou).collect();
        println!(
            "{set}: {} partials, {pairs} localizations ({errors} failed), {:.1} s each, mean IoU on the true shape {:.3}",
            partials.len(),
            seconds / pairs.max(1) as f64,
            ious.iter().sum::<f64>() / ious.len().max(1) as f64
        );
    }
    Ok(())
}

/// Seconds to prepare each full shape of `set/null` ([`Localizer::new`]) against saving it
/// and loading it again ([`Localizer::load`]), interleaved, the median of `repeats`.
fn time(set: &Path, repeats: usize, threads: usize) -> Result<(), Box<dyn std::error::Error>> {
    let options = Options { threads, ..Options::default() };
    let read = ReadOptions { drop_isolated: true, ..ReadOptions::default() };
    let file = std::env::temp_dir().join(format!("research_retrieval_{}.dsprep", std::process::id()));
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (mut total_prepare, mut total_load) = (0.0, 0.0);
    println!("{:<12} {:>10} {:>10} {:>8}", "shape", "prepare_s", "load_s", "MB");
    for path in off_files(&set.join("null"))? {
        let (mesh, _) = read_mesh_with_report(&path, &read)?;
        let (mut prepare, mut load) = (Vec::new(), Vec::new());
        for _ in 0..repeats.max(1) {
            let t = Instant::now();
            let localizer = Localizer::new(&mesh, &options)?;
            prepare.push(t.elapsed().as_secs_f64());
            localizer.save(&file)?;
            let t = Instant::now();
            let loaded = Localizer::load(&file)?;
            load.push(t.elapsed().as_secs_f64());
            assert!(loaded.to_bytes() == localizer.to_bytes());
        }
        let (p, l) = (median(prepare), median(load));
        total_prepare += p;
        total_load += l;
        let mb = std::fs::metadata(&file)?.len() as f64 / 1e6;
        println!("{:<12} {p:>10.3} {l:>10.3} {mb:>8.2}", stem(&path));
    }
    println!("{:<12} {total_prepare:>10.3} {total_load:>10.3}", "total");
    let _ = std::fs::remove_file(&file);
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = dualspectra_lab::args::from_env();
    let threads: usize = dualspectra_lab::args::take_value(&mut args, "--threads")?.unwrap_or(2);
    let mut options = Options { threads, ..Options::default() };
    if let Some(iterations) = dualspectra_lab::args::take_value(&mut args, "--max-iterations")? {
        options.max_iterations = iterations;
    }
    let usage = "usage: research_retrieval [--threads N] run ROOT LOG.jsonl [SET:STRIDE ...] | analyse LOG.jsonl | time SET_DIR [REPEATS]";
    match args.first().map(String::as_str) {
        Some("run") if args.len() >= 3 => {
            let sets: Vec<(String, usize, usize)> = if args.len() > 3 {
                args[3..]
                    .iter()
                    .map(|s| {
                        let mut parts = s.split(':');
                        let name = parts.next().unwrap_or_default().to_string();
                        let stride = parts.next().unwrap_or("1").parse()?;
                        let offset = parts.next().unwrap_or("0").parse()?;
                        Ok((name, stride, offset))
                    })
                    .collect::<Result<_, std::num::ParseIntError>>()?
            } else {
                DEFAULT_SETS.iter().map(|(s, k, o)| (s.to_string(), *k, *o)).collect()
            };
            run(Path::new(&args[1]), Path::new(&args[2]), &sets, &options)
        }
        Some("analyse") if args.len() == 2 => analyse(Path::new(&args[1])),
        Some("time") if args.len() >= 2 => time(Path::new(&args[1]), args.get(2).map(|r| r.parse()).transpose()?.unwrap_or(3), threads),
        _ => Err(usage.into()),
    }
}
