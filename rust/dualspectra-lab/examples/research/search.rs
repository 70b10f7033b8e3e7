//! The screened library search on every library query (a research harness for `search`;
//! docs/benchmarks/options.md, "Two-stage search").
//!
//! ```text
//! research_search ROOT LOG.jsonl [SET[:STRIDE[:OFFSET]] ...] [--shortlist N] [--one-stage] [--threads N]
//! research_search analyse LOG.jsonl
//! ```
//!
//! ROOT is the datasets folder (`library/` and the dev sets). Every library model is prepared
//! once, in memory; each dev partial (SHREC'16 CUTS and HOLES with `scale = same`: the right
//! answer is its class; PFAUST with `scale = auto`: the person, with the query's own source
//! mesh left out of the screen and the search) is searched with [`search_screened`]
//! (`--one-stage`: every shortlisted model localized in full, the search before the two-stage
//! one), and located once on its own full shape of the dev set, prepared in the same run (the
//! time of one `localize`). One JSON line per query in LOG.jsonl (appended; queries already in
//! it are skipped, so a stopped run resumes): the ranking with each model's class, score,
//! confidence and whether it was quick, the seconds of the search and of the one
//! localization (and, for PFAUST, of one localization with `scale = auto`). `analyse` prints per set (and kind of run): top-1, top-5, mean reciprocal
//! rank, the screen's recall (the right class shortlisted), the confidence AUC of right
//! against wrong models' localizations, and the median seconds per query against one
//! localization.

use dualspectra::mesh::io::{read_mesh_with_report, ReadOptions};
use dualspectra::search::search_confidences;
use dualspectra::{localize, search_screened, search_with, Localizer, Options, Progress, Scale, Screen, ScreenEntry};
use dualspectra_lab::datasets::Dataset;
use std::collections::HashSet;
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

fn median(mut x: Vec<f64>) -> f64 {
    x.sort_by(f64::total_cmp);
    if x.is_empty() { f64::NAN } else { x[x.len() / 2] }
}

/// The probability that a right model's value beats (is above) a wrong one's, ties half.
fn auc(right: &[f64], wrong: &[f64]) -> f64 {
    let mut wins = 0.0;
    for r in right {
        for w in wrong {
            wins += if r > w { 1.0 } else if r == w { 0.5 } else { 0.0 };
        }
    }
    wins / (right.len() * wrong.len()) as f64
}

fn analyse(log: &str) -> Result<(), Box<dyn std::error::Error>> {
    let rows: Vec<serde_json::Value> = std::fs::read_to_string(log)?.lines().filter_map(|l| serde_json::from_str(l).ok()).collect();
    let mut groups: Vec<(String, bool, u64)> = Vec::new();
    for r in &rows {
        let key = (r["set"].as_str().unwrap_or_default().to_string(), r["one_stage"].as_bool().unwrap_or(false), r["shortlist"].as_u64().unwrap_or(0));
        if !groups.contains(&key) {
            groups.push(key);
        }
    }
    println!("| set | search | queries | top-1 | top-5 | MRR | screen recall | confidence AUC (all located / in full) | score AUC (in full) | median s/query | x one localization | x one with `auto` |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut search_aucs = Vec::new();
    for (set, one_stage, shortlist) in groups {
        let rs: Vec<&serde_json::Value> = rows.iter().filter(|r| r["set"] == set.as_str() && r["one_stage"] == one_stage && r["shortlist"] == shortlist).collect();
        let n = rs.len() as f64;
        let rank = |r: &serde_json::Value| r["rank"].as_u64().unwrap_or(u64::MAX);
        let top = |k: u64| rs.iter().filter(|r| rank(r) <= k).count() as f64 / n;
        let mrr = rs.iter().map(|r| r["rank"].as_u64().map_or(0.0, |k| 1.0 / k as f64)).sum::<f64>() / n;
        let recall = rs
            .iter()
            .filter(|r| r["ranking"].as_array().is_some_and(|a| a.iter().take(shortlist as usize).any(|m| m["class"] == r["right"])))
            .count() as f64
            / n;
        let (mut right, mut wrong, mut right_full, mut wrong_full) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let (mut right_score, mut wrong_score) = (Vec::new(), Vec::new());
        for r in &rs {
            for m in r["ranking"].as_array().into_iter().flatten() {
                let Some(c) = m["confidence"].as_f64() else { continue };
                let is_right = m["class"] == r["right"];
                if is_right { right.push(c) } else { wrong.push(c) }
                if m["quick"] == false {
                    if is_right { right_full.push(c) } else { wrong_full.push(c) }
                    // Lower is more similar: negated, so that higher is better as for the confidence.
                    let score = -m["score"].as_f64().unwrap_or(f64::INFINITY);
                    if is_right { right_score.push(score) } else { wrong_score.push(score) }
                }
            }
        }
        // The search's confidence (`search_confidences`, recomputed from each query's located
        // scores and localization confidences): right against wrong models, and the answers
        // (each query's first model) right against wrong.
        let (mut right_search, mut wrong_search, mut right_answer, mut wrong_answer) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let (mut right_answer_own, mut wrong_answer_own) = (Vec::new(), Vec::new());
        for r in &rs {
            let located: Vec<&serde_json::Value> =
                r["ranking"].as_array().into_iter().flatten().filter(|m| m["located"] == true && m["score"].is_number()).collect();
            let pairs: Vec<(f64, f64)> = located.iter().map(|m| (m["score"].as_f64().unwrap_or(f64::INFINITY), m["confidence"].as_f64().unwrap_or(0.0))).collect();
            for (k, (m, c)) in located.iter().zip(search_confidences(&pairs)).enumerate() {
                let is_right = m["class"] == r["right"];
                if is_right { right_search.push(c) } else { wrong_search.push(c) }
                if k == 0 {
                    let own = m["confidence"].as_f64().unwrap_or(0.0);
                    if is_right { right_answer.push(c); right_answer_own.push(own) } else { wrong_answer.push(c); wrong_answer_own.push(own) }
                }
            }
        }
        search_aucs.push(format!(
            "| {set} | {:.3} | {:.3} | {:.3} | {} |",
            auc(&right_search, &wrong_search),
            auc(&right_answer, &wrong_answer),
            auc(&right_answer_own, &wrong_answer_own),
            wrong_answer.len()
        ));
        let seconds = median(rs.iter().filter_map(|r| r["search_seconds"].as_f64()).collect());
        let ratio = median(rs.iter().filter_map(|r| Some(r["search_seconds"].as_f64()? / r["one_seconds"].as_f64()?)).collect());
        let ratio_auto = median(rs.iter().filter_map(|r| Some(r["search_seconds"].as_f64()? / r["one_auto_seconds"].as_f64()?)).collect());
        println!(
            "| {set} | {} shortlist {shortlist} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.2} / {:.2} | {:.2} | {seconds:.1} | {ratio:.1} | {ratio_auto:.1} |",
            if one_stage { "one-stage" } else { "two-stage" },
            rs.len(),
            top(1),
            top(5),
            mrr,
            recall,
            auc(&right, &wrong),
            auc(&right_full, &wrong_full),
            auc(&right_score, &wrong_score)
        );
    }
    println!("\n| set | search confidence AUC, right against wrong models | the answers' (first models') | their localization confidence's | wrong answers |\n|---|---|---|---|---|");
    for line in search_aucs {
        println!("{line}");
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("analyse") {
        return analyse(args.get(1).ok_or("usage: research_search analyse LOG.jsonl")?);
    }
    let usage = "usage: research_search ROOT LOG.jsonl [SET[:STRIDE[:OFFSET]] ...] [--shortlist N] [--one-stage] [--threads N]";
    let root = PathBuf::from(args.first().ok_or(usage)?);
    let log_path = PathBuf::from(args.get(1).ok_or(usage)?);
    let (mut sets, mut shortlist, mut one_stage, mut threads) = (Vec::new(), 10usize, false, 2usize);
    let mut i = 2;
    while i < args.len() {
        match args[i].as_str() {
            "--shortlist" => { shortlist = args[i + 1].parse()?; i += 1; }
            "--threads" => { threads = args[i + 1].parse()?; i += 1; }
            "--one-stage" => one_stage = true,
            s => {
                let mut it = s.split(':');
                let name = it.next().unwrap_or_default().to_string();
                let stride = it.next().map_or(Ok(1), str::parse)?;
                let offset = it.next().map_or(Ok(0), str::parse)?;
                sets.push((name, stride, offset));
            }
        }
        i += 1;
    }
    if sets.is_empty() {
        sets = ["shrec16", "shrec16_holes", "pfaust_m", "pfaust_h"].iter().map(|s| (s.to_string(), 1, 0)).collect();
    }
    let done: HashSet<(String, String)> = std::fs::read_to_string(&log_path)
        .unwrap_or_default()
        .lines()
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .map(|v| (v["set"].as_str().unwrap_or_default().to_string(), v["partial"].as_str().unwrap_or_default().to_string()))
        .collect();
    let mut log = std::fs::OpenOptions::new().create(true).append(true).open(&log_path)?;

    let options = Options { threads, ..Options::default() };
    let labels = std::fs::read_to_string(root.join("library/labels.tsv"))?;
    let (mut names, mut classes, mut entries, mut models) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let t = Instant::now();
    for line in labels.lines().filter(|l| !l.trim().is_empty()) {
        let (file, class) = line.split_once('\t').ok_or("labels.tsv: file<TAB>class")?;
        let (mesh, _) = read_mesh_with_report(&root.join("library/shapes").join(file), &ReadOptions::default())?;
        entries.push(ScreenEntry::new(&mesh)?);
        models.push(Localizer::new(&mesh, &options)?);
        names.push(file.trim_end_matches(".off").to_string());
        classes.push(class.to_string());
    }
    eprintln!("library: {} models prepared in {:.1} s", models.len(), t.elapsed().as_secs_f64());
    let whole_screen = Screen::new(&entries)?;

    for (set, stride, offset) in &sets {
        let ds = Dataset::open(root.join(set))?;
        let pfaust = set.starts_with("pfaust");
        let scale = if pfaust { Scale::Auto } else { Scale::Same };
        for m in &mut models {
            m.set_scale(scale)?;
        }
        for pair in ds.pairs()?.into_iter().skip(*offset).step_by(*stride) {
            if done.contains(&(set.clone(), pair.name.clone())) {
                continue;
            }
            let (partial, _) = read_mesh_with_report(&pair.partial, &ReadOptions::default())?;
            // PFAUST's partial `tr_reg_0PQ` is cut from the library's `faust_tr_reg_0PQ`
            // (person P, pose Q), which is left out.
            let (right, own) = if pfaust {
                let person = pair.name.trim_start_matches("tr_reg_").chars().nth(1).unwrap_or('?');
                (format!("faust_person_{person}"), Some(format!("faust_{}", pair.name)))
            } else {
                (pair.class.clone(), None)
            };
            let kept: Vec<usize> = (0..names.len()).filter(|&m| Some(&names[m]) != own.as_ref()).collect();
            let screen = if own.is_some() { Screen::new(&kept.iter().map(|&m| entries[m].clone()).collect::<Vec<_>>())? } else { whole_screen.clone() };
            let open = |i: usize, _: &Progress| Ok::<_, dualspectra::Error>(&models[kept[i]]);
            let t = Instant::now();
            let found = if one_stage {
                let ranked = screen.rank(&partial, scale, &Progress::none())?;
                let chosen: Vec<usize> = ranked.iter().take(shortlist).map(|r| r.0).collect();
                let mut found = search_with(&partial, chosen.len(), |i, p| open(chosen[i], p), usize::MAX, &Progress::none())?;
                for m in &mut found {
                    m.index = chosen[m.index];
                }
                let mut template = found[0].clone();
                (template.score, template.localization, template.error) = (f64::INFINITY, None, None);
                found.extend(ranked.iter().skip(shortlist).map(|&(index, _)| {
                    let mut m = template.clone();
                    m.index = index;
                    m
                }));
                found
            } else {
                search_screened(&partial, &screen, scale, shortlist, open, usize::MAX, &Progress::none())?
            };
            let search_seconds = t.elapsed().as_secs_f64();
            // The quick localization of each model refined in full (the search keeps only the
            // full one): what the quick ranking saw, for studying which models to refine.
            let refined_quick: Vec<Option<f64>> = found
                .iter()
                .map(|m| (!one_stage && !m.quick && m.localization.is_some()).then(|| dualspectra::search::locate_prepared(&models[kept[m.index]], &dualspectra::search::PreparedPartial::new(partial.clone()), true, &Progress::none()).ok().map(|l| l.similarity_score)).flatten())
                .collect();
            let t = Instant::now();
            screen.rank(&partial, scale, &Progress::none())?;
            let screen_seconds = t.elapsed().as_secs_f64();
            let (full, _) = read_mesh_with_report(&pair.full, &ReadOptions::default())?;
            let t = Instant::now();
            let one = localize(&full, &partial, &Options { scale: Scale::Same, ..options.clone() }, &Progress::none());
            let one_seconds = t.elapsed().as_secs_f64();
            // With `scale = auto`, also one localization in the search's units: what a user who
            // knew the model but not the units would run.
            let one_auto_seconds = (scale == Scale::Auto).then(|| {
                let t = Instant::now();
                let _ = localize(&full, &partial, &Options { scale: Scale::Auto, ..options.clone() }, &Progress::none());
                t.elapsed().as_secs_f64()
            });
            let ranking: Vec<serde_json::Value> = found
                .iter()
                .zip(&refined_quick)
                .map(|(m, refined_quick)| {
                    let model = kept[m.index];
                    serde_json::json!({
                        "model": names[model], "class": classes[model], "score": m.score.is_finite().then_some(m.score),
                        "confidence": m.localization.as_ref().map(|l| l.confidence), "quick": m.quick, "located": m.localization.is_some(),
                        "seconds": m.localization.as_ref().map(|l| l.timings.total), "timings": m.localization.as_ref().map(|l| serde_json::to_value(&l.timings).unwrap_or_default()),
                        "cost": m.localization.as_ref().map(|l| l.cost), "factor": m.localization.as_ref().map(|l| l.scale),
                        "screen_score": m.screen_score, "quick_score": refined_quick, "search_confidence": m.localization.is_some().then_some(m.confidence),
                        "chosen": m.localization.as_ref().and_then(|l| l.candidates.get(l.selected_start)).map(|c| serde_json::to_value(c.scores).unwrap_or_default()),
                    })
                })
                .collect();
            let rank = ranking.iter().position(|r| r["class"] == right.as_str()).map(|p| p + 1);
            writeln!(
                log,
                "{}",
                serde_json::json!({
                    "set": set, "partial": pair.name, "right": right, "rank": rank, "one_stage": one_stage, "shortlist": shortlist,
                    "search_seconds": search_seconds, "screen_seconds": screen_seconds, "one_seconds": one_seconds, "one_auto_seconds": one_auto_seconds, "one_error": one.err().map(|e| e.to_string()),
                    "ranking": ranking,
                })
            )?;
            eprintln!("{set} {}: right {right} at {rank:?}, {search_seconds:.1} s (one localization {one_seconds:.1} s)", pair.name);
        }
    }
    Ok(())
}
