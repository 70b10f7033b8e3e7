//! The screen's distance between every two library models (`Screen::model_distance`), and how
//! well it tells models of one class from models of others (a study for the search's
//! confidence across models).
//!
//! `research_model_distances ROOT OUT.json`: ROOT is the datasets folder (`library/`); OUT gets
//! `{"names": [...], "classes": [...], "distances": [[...], ...]}`. Prints the AUC of
//! same-class pairs against other-class pairs (a lower distance counting as same class).

use dualspectra::mesh::io::{read_mesh_with_report, ReadOptions};
use dualspectra::{lab, Screen, ScreenEntry};
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: research_model_distances ROOT OUT.json";
    let root = PathBuf::from(args.first().ok_or(usage)?);
    let out = PathBuf::from(args.get(1).ok_or(usage)?);
    let labels = std::fs::read_to_string(root.join("library/labels.tsv"))?;
    let (mut names, mut classes, mut entries) = (Vec::new(), Vec::new(), Vec::new());
    for line in labels.lines().filter(|l| !l.trim().is_empty()) {
        let (file, class) = line.split_once('\t').ok_or("labels.tsv: file<TAB>class")?;
        let (mesh, _) = read_mesh_with_report(&root.join("library/shapes").join(file), &ReadOptions::default())?;
        entries.push(ScreenEntry::new(&mesh)?);
        names.push(file.trim_end_matches(".off").to_string());
        classes.push(class.to_string());
    }
    let screen = Screen::new(&entries)?;
    let n = names.len();
    let distances: Vec<Vec<f64>> = (0..n).map(|i| (0..n).map(|j| lab::screen_model_distance(&screen, i, j).unwrap_or(f64::INFINITY)).collect()).collect();
    let (mut same, mut other) = (Vec::new(), Vec::new());
    for i in 0..n {
        for j in i + 1..n {
            if classes[i] == classes[j] { same.push(distances[i][j]) } else { other.push(distances[i][j]) }
        }
    }
    let wins: f64 = same.iter().map(|s| other.iter().map(|o| if s < o { 1.0 } else if s == o { 0.5 } else { 0.0 }).sum::<f64>()).sum();
    println!("{} same-class pairs, {} other; AUC {:.3}", same.len(), other.len(), wins / (same.len() * other.len()) as f64);
    std::fs::write(out, serde_json::to_string(&serde_json::json!({"names": names, "classes": classes, "distances": distances}))?)?;
    Ok(())
}
