//! The `scale = auto` estimate alone, on every pair of a dev set: how far it is from the
//! truth and how long it takes, without locating (docs/algorithm.md, "Units").
//!
//! `cargo run -p dualspectra-lab --release --example research_scale -- DATASET [TRANSFORM] [STRIDE]`
//!
//! Each partial is changed as `bench --transform TRANSFORM` changes it (none, rigid, units,
//! size; default none) and its factor estimated by the localizer's own step
//! (`lab::partial_factor`, the full shape prepared once). One line per pair: the factor
//! applied, the factor's error (estimate x applied: 1 is exact) and the seconds; then the
//! median error, the fractions within 10 % and 25 %, and the median seconds.

use dualspectra::{lab, Localizer, Options, Scale};
use dualspectra_lab::bench::Transform;
use dualspectra_lab::datasets::Dataset;
use std::collections::HashMap;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let root = args.get(1).ok_or("usage: research_scale DATASET [TRANSFORM] [STRIDE]")?;
    let transform: Transform = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or_default();
    let stride: usize = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(1).max(1);
    let options = Options { scale: Scale::Auto, ..Default::default() };
    let mut prepared: HashMap<std::path::PathBuf, Localizer> = HashMap::new();
    let (mut errors, mut seconds) = (Vec::new(), Vec::new());
    println!("pair applied_factor factor_error seconds");
    for pair in Dataset::open(root)?.pairs()?.iter().step_by(stride) {
        let data = pair.load()?;
        let (partial, applied) = transform.apply(&data.partial, &pair.name)?;
        if !prepared.contains_key(&pair.full) {
            prepared.insert(pair.full.clone(), Localizer::new(&data.full, &options)?);
        }
        let t0 = std::time::Instant::now();
        let factor = lab::partial_factor(&prepared[&pair.full], &partial)?;
        let t = t0.elapsed().as_secs_f64();
        let error = factor * applied;
        println!("{} {applied:.4e} {error:.4} {t:.3}", pair.name);
        errors.push(error.ln().abs());
        seconds.push(t);
    }
    if errors.is_empty() {
        return Err("no pair".into());
    }
    errors.sort_by(f64::total_cmp);
    seconds.sort_by(f64::total_cmp);
    let within = |x: f64| errors.iter().filter(|&&e| e <= x.ln()).count() as f64 / errors.len() as f64;
    println!(
        "pairs {}; median factor error {:.1} %; within 10 %: {:.2}; within 25 %: {:.2}; median s {:.3}",
        errors.len(),
        100.0 * (errors[errors.len() / 2].exp() - 1.0),
        within(1.1),
        within(1.25),
        seconds[seconds.len() / 2]
    );
    Ok(())
}
