//! Localize SHREC'16 pairs and print per-pair and per-start quality (a development tool;
//! the user-facing benchmark is `dualspectra bench`).
//!
//! `cargo run --release --example 401_localize_shrec -- DATASET [STRIDE] [OFFSET]`
//! Options from the environment: DS_MODE, DS_K, DS_RES, DS_CENTERS, DS_ITERS, DS_FINALISTS,
//! DS_SELECTION (gated, region, descriptors, cost), DS_DESC_START=1 (descriptor start),
//! DS_HESSIAN (finite-difference, gauss-newton), DS_EXTRA, DS_START_SHAPE (a `StartShape` name),
//! DS_SPECTRAL (spectral-cut eigenfunctions), DS_PLANES (plane cuts);
//! DS_VERBOSE lists every start (`*`: finalist; `sup`/`agree`: its region's mean IoU with the
//! other starts' regions and how many overlap it with IoU > 0.7; `iou` symmetry-aware,
//! `direct` against `.baryc_gt` only; `pf` its partial fit; with DS_CHIRAL=1 also `pr`/`rp`,
//! the fits at full resolution, see `chiral_fits`); DS_PAIRS=a,b runs only the
//! pairs whose name contains `a` or `b`; DS_REGION_STUDY prints the chosen start's region under
//! other rules (energy, potential or both ranked, area factors 0.8-1.2, with and without closing).

use dualspectra::evaluation::datasets::Shrec16;
use dualspectra::evaluation::metrics::{scores, symmetry_aware};
use dualspectra::mesh::topology::{connected_components, euler_characteristic};
use dualspectra::region::boundary::region_boundary_length;
use dualspectra::mesh::TriMesh;
use dualspectra::{localize_with_initial_regions, Options, Progress, Selection};

fn env<T: std::str::FromStr>(k: &str, d: T) -> T {
    std::env::var(k)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(d)
}

/// Shape of a vertex region (the faces with all three vertices in it) or of a whole mesh:
/// (Euler characteristic, connected components, boundary length). For the selection study.
fn region_shape(mesh: &TriMesh, region: Option<&[bool]>) -> (i64, usize, f64) {
    let faces: Vec<[u32; 3]> = mesh
        .faces()
        .iter()
        .filter(|f| region.is_none_or(|r| f.iter().all(|&i| r[i as usize])))
        .cloned()
        .collect();
    let Ok((sub, _)) = TriMesh::new_dropping_isolated(mesh.vertices().to_vec(), faces) else {
        return (0, 0, 0.0);
    };
    (
        euler_characteristic(&sub),
        connected_components(&sub).1,
        region_boundary_length(&sub, None),
    )
}

/// DS_REGION_STUDY: alternative region rules on the chosen start's per-vertex fields.
fn region_study(
    full: &TriMesh,
    partial: &TriMesh,
    res: &dualspectra::Localization,
    iou: &dyn Fn(&[bool]) -> f64,
) -> Result<(), Box<dyn std::error::Error>> {
    use dualspectra::operators::mass::lumped_mass;
    use dualspectra::region::closing::close;
    use dualspectra::region::energy::area_matched_region;
    let mass = lumped_mass(full);
    let nb = dualspectra::mesh::topology::vertex_neighbors(full);
    let area = partial.area();
    let pmax = res.potential.iter().cloned().fold(f64::MIN_POSITIVE, f64::max);
    let neg_v: Vec<f64> = res.potential.iter().map(|v| -v / pmax).collect();
    let mix: Vec<f64> = res.score.iter().zip(&neg_v).map(|(s, v)| s + v).collect();
    let mut line = format!("    region-study base {:.3}", iou(&res.region));
    for (name, field) in [("energy", &res.score), ("potential", &neg_v), ("mix", &mix)] {
        for f in [0.8, 0.9, 1.0, 1.1, 1.2] {
            let r = area_matched_region(field, &mass, f * area);
            let c = close(&r, &nb, dualspectra::region::CLOSING_RINGS)?;
            line += &format!(" {name}{f}:{:.3}/{:.3}", iou(&r), iou(&c));
        }
    }
    println!("{line}");
    Ok(())
}

/// DS_CHIRAL: descriptor fits of each candidate region, SHOT at the data's resolution (the
/// pipeline's radius): `pr` = mean over ~600 partial vertices of the distance to the nearest
/// descriptor in the region, `rp` = mean over the region's vertices (every 8th) of the distance
/// to the nearest of those partial descriptors. SHOT's frame is right-handed, so a mirrored
/// patch has a mirrored histogram: do the fits tell a region from its mirror twin?
fn chiral_fits(full: &TriMesh, partial: &TriMesh, regions: &[&[bool]]) -> Result<Vec<(f64, f64)>, Box<dyn std::error::Error>> {
    use dualspectra::alignment::shot::{shot_descriptors, DEFAULT_MIN_NEIGHBORS, DEFAULT_RADIUS_FRACTION};
    let area: f64 = dualspectra::shape::Shape::new(full.clone()).mass().iter().sum();
    let scale = 1.0 / area.sqrt();
    let f = full.map_positions(|p| p.map(|c| c * scale))?;
    let q = partial.map_positions(|p| p.map(|c| c * scale))?;
    let df = shot_descriptors(&f, DEFAULT_RADIUS_FRACTION, DEFAULT_MIN_NEIGHBORS)?;
    let dp = shot_descriptors(&q, DEFAULT_RADIUS_FRACTION, DEFAULT_MIN_NEIGHBORS)?;
    let step = (dp.nrows() / 600).max(1);
    let sample: Vec<usize> = (0..dp.nrows()).step_by(step).collect();
    let d = dp.ncols();
    let a = faer::Mat::<f64>::from_fn(sample.len(), d, |i, c| dp[(sample[i], c)]);
    let bt = faer::Mat::<f64>::from_fn(d, df.nrows(), |c, j| df[(j, c)]);
    let mut dot = faer::Mat::<f64>::zeros(sample.len(), df.nrows());
    faer::linalg::matmul::matmul(dot.as_mut(), faer::Accum::Replace, a.as_ref(), bt.as_ref(), 1.0, faer::Par::rayon(0));
    let a2: Vec<f64> = (0..sample.len()).map(|i| (0..d).map(|c| a[(i, c)].powi(2)).sum()).collect();
    let b2: Vec<f64> = (0..df.nrows()).map(|j| (0..d).map(|c| df[(j, c)].powi(2)).sum()).collect();
    let dist = |i: usize, j: usize| (a2[i] + b2[j] - 2.0 * dot[(i, j)]).max(0.0).sqrt();
    Ok(regions
        .iter()
        .map(|r| {
            let inside: Vec<usize> = (0..r.len()).filter(|&j| r[j]).collect();
            if inside.is_empty() {
                return (f64::NAN, f64::NAN);
            }
            let pr = (0..sample.len())
                .map(|i| inside.iter().map(|&j| dist(i, j)).fold(f64::INFINITY, f64::min))
                .sum::<f64>()
                / sample.len() as f64;
            let sub: Vec<usize> = inside.iter().copied().step_by(8).collect();
            let rp = sub
                .iter()
                .map(|&j| (0..sample.len()).map(|i| dist(i, j)).fold(f64::INFINITY, f64::min))
                .sum::<f64>()
                / sub.len() as f64;
            (pr, rp)
        })
        .collect())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let root = args
        .get(1)
        .ok_or("usage: 401_localize_shrec DATASET [STRIDE] [OFFSET]")?;
    let stride: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1);
    let offset: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(0);
    let mut o = Options::default();
    o.mode = env("DS_MODE", "dual".to_string()).parse()?;
    o.k = env("DS_K", o.k);
    o.resolution = env("DS_RES", o.resolution);
    o.centers = env("DS_CENTERS", o.centers);
    o.max_iterations = env("DS_ITERS", o.max_iterations);
    o.extra_iterations = env("DS_EXTRA", o.extra_iterations);
    o.spectral_cuts = env("DS_SPECTRAL", o.spectral_cuts);
    o.plane_cuts = env("DS_PLANES", o.plane_cuts);
    o.finalists = env("DS_FINALISTS", o.finalists);
    o.descriptor_start = env("DS_DESC_START", 0) != 0;
    match env("DS_SELECTION", String::new()).as_str() {
        "cost" => o.selection = Selection::Cost,
        "descriptors" => o.selection = Selection::Descriptors,
        "region" => o.selection = Selection::Region,
        "gated" => o.selection = Selection::Gated,
        _ => {}
    }
    if let Ok(h) = std::env::var("DS_START_SHAPE") {
        o.start_shape = h.parse()?;
    }
    if let Ok(h) = std::env::var("DS_HESSIAN") {
        o.hessian = serde_json::from_value(serde_json::Value::String(h))?;
    }
    let data = Shrec16::open(root)?;
    let pairs = data.pairs()?;
    let (mut sum_iou, mut sum_oracle, mut sum_cost_sel, mut count) = (0.0, 0.0, 0.0, 0);
    // DS_PAIRS=a,b: only the pairs whose name contains one of the comma-separated strings.
    let only: Vec<String> = std::env::var("DS_PAIRS")
        .map(|s| s.split(',').map(str::to_string).collect())
        .unwrap_or_default();
    for pair in pairs
        .iter()
        .skip(offset)
        .step_by(stride)
        .filter(|p| only.is_empty() || only.iter().any(|o| p.name.contains(o.as_str())))
    {
        let p = pair.load()?;
        let t = std::time::Instant::now();
        // DS_GT_START=1: also start from the ground truth (is the cost minimal there?).
        let given = if std::env::var("DS_GT_START").is_ok() {
            vec![p.gt.clone()]
        } else {
            vec![]
        };
        let res =
            localize_with_initial_regions(&p.full, &p.partial, &o, &given, &Progress::none())?;
        let secs = t.elapsed().as_secs_f64();
        let sym = p.gt_sym.clone().unwrap_or_else(|| p.gt.clone());
        let iou = |r: &[bool]| {
            symmetry_aware(r, &p.gt, &sym, None)
                .map(|(s, _)| s.iou)
                .unwrap_or(0.0)
        };
        let chosen = symmetry_aware(&res.region, &p.gt, &sym, None)?.0;
        let per_start: Vec<f64> = res.candidates.iter().map(|c| iou(&c.region)).collect();
        let oracle = per_start.iter().cloned().fold(0.0, f64::max);
        let by_cost = (0..res.candidates.len())
            .min_by(|&a, &b| res.candidates[a].cost.total_cmp(&res.candidates[b].cost))
            .map(|i| per_start[i])
            .unwrap_or(0.0);
        let direct = scores(&res.region, &p.gt)?;
        println!(
            "{:<22} iou {:.3} (direct {:.3}) P {:.3} R {:.3} | oracle {:.3} by-cost {:.3} | cost {:.3e} | {:.1}s (pre {:.2}s starts {:.2}s opt {:.1}s sel {:.2}s) evals/start {:.0}",
            pair.name, chosen.iou, direct.iou, chosen.precision, chosen.recall, oracle, by_cost, res.cost, secs,
            res.timings.preprocessing, res.timings.starts, res.timings.optimisation, res.timings.selection,
            res.candidates.iter().map(|c| c.evaluations as f64).sum::<f64>() / res.candidates.len() as f64
        );
        if std::env::var("DS_VERBOSE").is_ok() {
            let rel = |l: &[f64], m: &[f64]| -> Vec<String> {
                l.iter()
                    .zip(m)
                    .map(|(a, b)| format!("{:+.2}", (a - b) / b))
                    .collect()
            };
            let term = |l: &[f64], m: &[f64]| {
                l.iter()
                    .zip(m)
                    .map(|(a, b)| ((a - b) / b).powi(2))
                    .sum::<f64>()
            };
            println!(
                "    selected: regular cost {:.3e} SI cost {:.3e}\n    reg rel err {}\n    SI  rel err {}",
                term(&res.eigenvalues_regular, &res.target_regular),
                term(&res.eigenvalues_si, &res.target_si),
                rel(&res.eigenvalues_regular, &res.target_regular).join(" "),
                rel(&res.eigenvalues_si, &res.target_si).join(" ")
            );
            let (pchi, pcomp, plen) = region_shape(&p.partial, None);
            println!("    partial: chi {pchi} comp {pcomp} blen {plen:.3}");
            // Agreement of each candidate's region with the others' (mean IoU, and how many
            // overlap it with IoU > 0.7): regions several starts converge to.
            let support: Vec<(f64, usize)> = res
                .candidates
                .iter()
                .enumerate()
                .map(|(a, ca)| {
                    let o: Vec<f64> = res
                        .candidates
                        .iter()
                        .enumerate()
                        .filter(|&(b, _)| b != a)
                        .map(|(_, cb)| scores(&ca.region, &cb.region).map(|s| s.iou))
                        .collect::<Result<_, _>>()?;
                    Ok((o.iter().sum::<f64>() / o.len().max(1) as f64, o.iter().filter(|&&x| x > 0.7).count()))
                })
                .collect::<Result<_, dualspectra::Error>>()?;
            let chiral = if std::env::var("DS_CHIRAL").is_ok() {
                let regions: Vec<&[bool]> = res.candidates.iter().map(|c| c.region.as_slice()).collect();
                chiral_fits(&p.full, &p.partial, &regions)?
            } else {
                vec![(f64::NAN, f64::NAN); res.candidates.len()]
            };
            for (((c, i), (sup, agree)), (pr, rp)) in res.candidates.iter().zip(&per_start).zip(&support).zip(&chiral) {
                let (chi, comp, blen) = region_shape(&p.full, Some(&c.region));
                println!(
                    "  {} {:<20} cost {:10.3e} sel {:10.4e} rc {:10.3e} iou {:.3} it {} chi {chi} comp {comp} blen {blen:.3} sup {sup:.3} agree {agree} direct {:.3} pr {pr:.5} rp {rp:.5} pf {:.5}",
                    if c.finalist { '*' } else { ' ' },
                    c.label,
                    c.cost,
                    c.selection_score,
                    c.region_cost,
                    i,
                    c.iterations,
                    scores(&c.region, &p.gt)?.iou,
                    c.partial_fit
                );
            }
        }
        // DS_POLISH=1: re-optimise from the chosen region and from the best start's region (as
        // step potentials), one centre's starts beside them; prints their IoUs afterwards.
        if std::env::var("DS_POLISH").is_ok() {
            let best = (0..per_start.len()).max_by(|&a, &b| per_start[a].total_cmp(&per_start[b])).unwrap_or(0);
            let seeds = vec![res.region.clone(), res.candidates[best].region.clone()];
            let o2 = Options { centers: 1, ..o.clone() };
            let r2 = localize_with_initial_regions(&p.full, &p.partial, &o2, &seeds, &Progress::none())?;
            let c = &r2.candidates;
            println!(
                "    polish: chosen {:.3} -> {:.3} (cost {:.3e} -> {:.3e}), best {:.3} -> {:.3}; re-chosen {:.3} ({})",
                chosen.iou, iou(&c[0].region), res.cost, c[0].cost, oracle, iou(&c[1].region),
                iou(&r2.region), c[r2.selected_start].label
            );
        }
        if std::env::var("DS_REGION_STUDY").is_ok() {
            region_study(&p.full, &p.partial, &res, &iou)?;
        }
        sum_iou += chosen.iou;
        sum_oracle += oracle;
        sum_cost_sel += by_cost;
        count += 1;
    }
    let n = count.max(1) as f64;
    println!(
        "MEAN over {count}: iou {:.3} | oracle {:.3} | by-cost {:.3}",
        sum_iou / n,
        sum_oracle / n,
        sum_cost_sel / n
    );
    Ok(())
}
