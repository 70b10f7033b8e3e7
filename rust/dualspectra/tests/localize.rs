//! End-to-end laws of the localizer on small generated shapes (seconds, not minutes).

use dualspectra::mesh::generate::icosphere;
use dualspectra::{localize, Error, Mode, Options, Progress, Selection, StartShape, TriMesh};

/// An asymmetric closed shape: a unit icosphere with three bumps of different sizes.
fn bumpy_sphere(level: u32) -> TriMesh {
    let bumps = [([0.0, 0.0, 1.0], 0.6, 0.08), ([1.0, 0.0, 0.0], 0.35, 0.05), ([0.0, -1.0, 0.2], 0.5, 0.12)];
    icosphere(level)
        .map_positions(|p| {
            let r: f64 = 1.0
                + bumps
                    .iter()
                    .map(|(c, h, s)| {
                        let d2: f64 = (0..3).map(|i| (p[i] - c[i]).powi(2)).sum();
                        h * (-d2 / (2.0 * s)).exp()
                    })
                    .sum::<f64>();
            p.map(|x| x * r)
        })
        .unwrap()
}

/// The faces whose three vertices satisfy `keep`, as a new mesh, and the full-mesh mask of its vertices.
fn cut(mesh: &TriMesh, keep: impl Fn([f64; 3]) -> bool) -> (TriMesh, Vec<bool>) {
    let v = mesh.vertices();
    let faces: Vec<[u32; 3]> =
        mesh.faces().iter().filter(|f| f.iter().all(|&i| keep(v[i as usize]))).copied().collect();
    let mut mask = vec![false; v.len()];
    faces.iter().flatten().for_each(|&i| mask[i as usize] = true);
    let (part, _) = TriMesh::new_dropping_isolated(v.to_vec(), faces).unwrap();
    (part, mask)
}

fn iou(a: &[bool], b: &[bool]) -> f64 {
    let i = a.iter().zip(b).filter(|(x, y)| **x && **y).count() as f64;
    let u = a.iter().zip(b).filter(|(x, y)| **x || **y).count() as f64;
    i / u
}

fn quick() -> Options {
    Options { k: 10, centers: 4, max_iterations: 40, resolution: 0, ..Options::default() }
}

#[test]
fn finds_an_undeformed_cut() {
    let full = bumpy_sphere(3);
    let (part, truth) = cut(&full, |p| p[2] > 0.1);
    let res = localize(&full, &part, &quick(), &Progress::none()).unwrap();
    let score = iou(&res.region, &truth);
    assert!(score > 0.9, "IoU {score}, cost {}", res.cost);
    assert_eq!(
        res.n_starts,
        StartShape::default().starts_per_centre() * quick().centers + 6,
        "3 starts per centre and 6 plane cuts by default"
    );
    assert_eq!(Options::default().plane_cuts, 6);
    assert_eq!(StartShape::default().starts_per_centre(), 3);
    assert_eq!(res.region.len(), full.n_vertices());
    assert_eq!(res.eigenvalues_regular.len(), 10);
    assert_eq!(res.eigenvalues_si.len(), 10);
    assert!(res.score.iter().all(|s| (0.0..=1.0).contains(s)));
}

#[test]
fn every_start_shape_finds_an_undeformed_cut() {
    // The cut of `finds_an_undeformed_cut` (which runs the default, `BallsAndWideBumps`),
    // with the other shapes of starts: each finds it and gives its documented number of starts.
    let full = bumpy_sphere(3);
    let (part, truth) = cut(&full, |p| p[2] > 0.1);
    for (shape, per_centre) in
        [(StartShape::Gaussian, 4), (StartShape::AreaBall, 2), (StartShape::BallsAndWideGaussians, 4)]
    {
        let o = Options { start_shape: shape, ..quick() };
        let res = localize(&full, &part, &o, &Progress::none()).unwrap();
        assert_eq!(shape.starts_per_centre(), per_centre);
        assert_eq!(res.n_starts, per_centre * o.centers + o.plane_cuts, "{shape:?}");
        let score = iou(&res.region, &truth);
        assert!(score > 0.9, "{shape:?}: IoU {score}, cost {}", res.cost);
    }
}

#[test]
fn plane_cuts_find_an_oblique_half() {
    // The bumpy sphere stretched along x and cut obliquely (x + y > 0.4): about a third of
    // it, on no ball around an extremity. With one centre and no plane cuts the balls miss
    // it; the 14 plane cuts (principal axes and diagonals) find it.
    let full = bumpy_sphere(3).map_positions(|p| [2.0 * p[0], p[1], p[2]]).unwrap();
    let (part, truth) = cut(&full, |p| p[0] + p[1] > 0.4);
    let o = Options { centers: 1, plane_cuts: 14, ..quick() };
    let res = localize(&full, &part, &o, &Progress::none()).unwrap();
    assert_eq!(res.n_starts, StartShape::default().starts_per_centre() + 14);
    let labels: Vec<&str> = res.candidates.iter().map(|c| c.label.as_str()).collect();
    assert!((0..14).all(|j| labels.contains(&format!("plane{j}").as_str())), "{labels:?}");
    let score = iou(&res.region, &truth);
    // An oblique cut through 642 vertices: its jagged edge (one ring, ~0.1 of the part's
    // vertices) bounds the IoU at ~0.9.
    assert!(score > 0.8, "IoU {score} ({}), cost {}", labels[res.selected_start], res.cost);
    let without = localize(&full, &part, &Options { plane_cuts: 0, ..o }, &Progress::none()).unwrap();
    let before = iou(&without.region, &truth);
    assert!(before < score, "without plane cuts IoU {before}, with {score}");
    eprintln!("oblique half: IoU {score:.3} with plane cuts, {before:.3} without");
}

#[test]
fn spectral_cuts_find_the_end_of_an_elongated_shape() {
    // The bumpy sphere stretched 2.5x along x and cut at x > 0.8: a cut across the long axis,
    // which the first eigenfunction's level sets follow. The spectral-cut starts (two per
    // eigenfunction, labelled cut{j}+ / cut{j}-) run beside the centres' and the cut is found.
    let full = bumpy_sphere(3).map_positions(|p| [2.5 * p[0], p[1], p[2]]).unwrap();
    let (part, truth) = cut(&full, |p| p[0] > 0.8);
    let o = Options { centers: 1, spectral_cuts: 2, ..quick() };
    let res = localize(&full, &part, &o, &Progress::none()).unwrap();
    assert_eq!(res.n_starts, StartShape::default().starts_per_centre() + o.plane_cuts + 4);
    let labels: Vec<&str> = res.candidates.iter().map(|c| c.label.as_str()).collect();
    for l in ["cut1+", "cut1-", "cut2+", "cut2-"] {
        assert!(labels.contains(&l), "{labels:?}");
    }
    let score = iou(&res.region, &truth);
    assert!(score > 0.9, "IoU {score} ({}), cost {}", labels[res.selected_start], res.cost);
}

/// A named option enum: `all` starts with the default; each name parses back (any case), is
/// its `Display` and its serde form; `bad` is an error listing every name.
fn assert_names_round_trip<T>(all: &[T], name: fn(T) -> &'static str, bad: &str)
where
    T: Copy + Default + PartialEq + std::fmt::Debug + std::fmt::Display + serde::Serialize,
    T: std::str::FromStr<Err = Error>,
{
    assert_eq!(all[0], T::default());
    for &v in all {
        assert_eq!(name(v).parse::<T>().unwrap(), v);
        assert_eq!(name(v).to_ascii_uppercase().parse::<T>().unwrap(), v);
        assert_eq!(v.to_string(), name(v));
        assert_eq!(serde_json::to_value(v).unwrap(), serde_json::Value::String(name(v).into()));
    }
    let err = bad.parse::<T>().unwrap_err().to_string();
    assert!(all.iter().all(|&v| err.contains(name(v))), "{err}");
}

#[test]
fn start_shape_names_round_trip_and_match_serde() {
    assert_names_round_trip(&StartShape::ALL, StartShape::name, "balls");
    assert_eq!("Area-Ball".parse::<StartShape>().unwrap(), StartShape::AreaBall);
}

#[test]
fn selection_names_round_trip_and_match_serde() {
    assert_names_round_trip(&Selection::ALL, Selection::name, "best");
    assert_eq!("Gated".parse::<Selection>().unwrap(), Selection::Gated);
}

#[test]
fn finds_an_undeformed_cut_on_a_decimated_optimisation_mesh() {
    // The optimisation runs on ~300 of the 2562 vertices, with the scale-invariant factor and
    // the descriptors carried from the full resolution; the region comes back to all vertices.
    // Bound: the region's edge is only known to one coarse ring (edge ~0.22 on the unit
    // sphere at 300 vertices): a band of ~0.7 of the part's area ~5.6, so IoU ~0.85-0.88 is
    // the resolution limit (the good starts land at 0.83-0.87), and 0.8 leaves room for it.
    let full = bumpy_sphere(4);
    let (part, truth) = cut(&full, |p| p[2] > 0.1);
    // Without plane cuts: at 300 vertices the start on the first principal axis's side ends
    // at IoU 0.72 with a descriptor score 5% below the best ball's (0.85), and is chosen; the
    // choice's noise at that resolution, not the decimation this test is about.
    let o = Options { resolution: 300, plane_cuts: 0, ..quick() };
    let res = localize(&full, &part, &o, &Progress::none()).unwrap();
    let score = iou(&res.region, &truth);
    assert!(score > 0.8, "IoU {score}, cost {}", res.cost);
    assert_eq!(res.region.len(), full.n_vertices());
}

#[test]
fn result_does_not_depend_on_units() {
    let full = bumpy_sphere(2);
    let (part, _) = cut(&full, |p| p[0] > 0.0);
    let o = Options { mode: Mode::Lbo, ..quick() };
    let a = localize(&full, &part, &o, &Progress::none()).unwrap();
    let s = 1000.0;
    let b = localize(
        &full.map_positions(|p| p.map(|x| x * s)).unwrap(),
        &part.map_positions(|p| p.map(|x| x * s)).unwrap(),
        &o,
        &Progress::none(),
    )
    .unwrap();
    // The shapes are normalised to unit area first: the targets agree to rounding, and the
    // optimisation (a chaotic path, not bitwise reproducible under rescaling) lands on the same region.
    for (x, y) in a.target_regular.iter().zip(&b.target_regular) {
        assert!((x - y).abs() <= 1e-8 * x.abs(), "{x} vs {y}");
    }
    assert!(iou(&a.region, &b.region) > 0.9, "IoU between units {}", iou(&a.region, &b.region));
}

#[test]
fn deterministic_for_a_seed() {
    let full = bumpy_sphere(2);
    let (part, _) = cut(&full, |p| p[1] < 0.2);
    let o = Options { seed: 3, ..quick() };
    let a = localize(&full, &part, &o, &Progress::none()).unwrap();
    let b = localize(&full, &part, &o, &Progress::none()).unwrap();
    assert_eq!(a.region, b.region);
    assert_eq!(a.cost.to_bits(), b.cost.to_bits());
}

#[test]
fn bad_inputs_give_clear_errors() {
    let full = bumpy_sphere(2);
    // Closed partial (no boundary).
    let e = localize(&full, &full, &quick(), &Progress::none()).unwrap_err();
    assert!(e.to_string().contains("no boundary"), "{e}");
    // Partial larger than the full shape.
    let (part, _) = cut(&full, |p| p[2] > 0.0);
    let big = part.map_positions(|p| p.map(|x| x * 3.0)).unwrap();
    let e = localize(&full, &big, &quick(), &Progress::none()).unwrap_err();
    assert!(e.to_string().contains("area"), "{e}");
    // Bad options.
    let e = localize(&full, &part, &Options { k: 0, ..quick() }, &Progress::none()).unwrap_err();
    assert!(matches!(e, Error::InvalidArgument(_)), "{e}");
    let e = localize(&full, &part, &Options { spectral_cuts: 1_000_000, ..quick() }, &Progress::none()).unwrap_err();
    assert!(e.to_string().contains("spectral_cuts"), "{e}");
    let e = localize(&full, &part, &Options { plane_cuts: 27, ..quick() }, &Progress::none()).unwrap_err();
    assert!(e.to_string().contains("plane_cuts = 27 must be at most 26"), "{e}");
    // Too many eigenvalues for a tiny partial.
    let (tiny, _) = cut(&full, |p| p[2] > 0.93);
    let e = localize(&full, &tiny, &Options { k: 200, ..quick() }, &Progress::none()).unwrap_err();
    assert!(matches!(e, Error::InvalidArgument(_)), "{e}");
}

#[test]
fn disconnected_partial_keeps_largest_component_with_a_warning() {
    let full = bumpy_sphere(3);
    let (part, truth) = cut(&full, |p| p[2] > 0.1 || p[2] < -0.95);
    let res = localize(&full, &part, &quick(), &Progress::none()).unwrap();
    assert!(res.warnings.iter().any(|w| w.contains("disconnected")), "{:?}", res.warnings);
    let (_, main) = cut(&full, |p| p[2] > 0.1);
    let _ = truth;
    assert!(iou(&res.region, &main) > 0.85);
}

#[test]
fn progress_is_reported_and_cancel_stops() {
    let full = bumpy_sphere(2);
    let (part, _) = cut(&full, |p| p[0] > 0.0);
    let seen = std::sync::Arc::new(std::sync::Mutex::new(Vec::<f64>::new()));
    let s2 = seen.clone();
    let p = Progress::new(move |f, _| {
        s2.lock().unwrap().push(f);
        true
    });
    localize(&full, &part, &quick(), &p).unwrap();
    let v = seen.lock().unwrap().clone();
    assert!(v.windows(2).all(|w| w[1] >= w[0] - 1e-12), "progress not monotone");
    assert_eq!(v.last().copied(), Some(1.0));

    let p = Progress::new(|f, _| f < 0.1);
    let e = localize(&full, &part, &quick(), &p).unwrap_err();
    assert!(matches!(e, Error::Cancelled));
}

/// Successive halving: of 16 starts (8 wells, 8 bumps), `finalists` run to the end and only they are
/// selected from; a given region is never pruned, and starting from the truth keeps it.
#[test]
fn halving_keeps_finalists_and_given_regions() {
    let full = bumpy_sphere(3);
    let (part, truth) = cut(&full, |p| p[0] + 0.3 * p[1] > 0.2);
    let o = Options { finalists: 4, start_shape: StartShape::BallsAndWideGaussians, plane_cuts: 0, ..quick() };
    let res = dualspectra::localize_with_initial_regions(&full, &part, &o, &[truth.clone()], &Progress::none()).unwrap();
    assert_eq!(res.candidates.len(), 17);
    let given = &res.candidates[0];
    assert_eq!(given.label, "given#0");
    assert!(given.finalist && given.iterations > 0);
    assert!(iou(&given.region, &truth) > 0.9, "IoU from the truth {}", iou(&given.region, &truth));
    let finalists: Vec<_> = res.candidates.iter().filter(|c| c.finalist).collect();
    assert_eq!(finalists.len(), 5, "2 wells + 2 bumps + the given region");
    assert!(res.candidates[res.selected_start].finalist);
    // Pruned starts stopped early; finalists ran longer.
    let max_pruned = res.candidates.iter().filter(|c| !c.finalist).map(|c| c.iterations).max().unwrap();
    assert!(max_pruned < o.max_iterations / 2 + 1, "pruned ran {max_pruned}");
    // Survivors of a round had the lowest costs of that round: every finalist's cost is
    // below the worst pruned one.
    let worst_pruned = res.candidates.iter().filter(|c| !c.finalist).map(|c| c.cost).fold(0.0, f64::max);
    assert!(finalists.iter().all(|c| c.cost <= worst_pruned));

    // A mask of the wrong length is a clear error.
    let err = dualspectra::localize_with_initial_regions(&full, &part, &o, &[vec![true; 3]], &Progress::none());
    assert!(matches!(err, Err(Error::InvalidArgument(_))), "{err:?}");
}


/// Extra iterations go only to the starts still converging (cost down by > 10% over their
/// last 10 iterations), at most `extra_iterations` more; the others stop at `max_iterations`.
#[test]
fn extra_iterations_go_to_the_starts_still_converging() {
    let full = bumpy_sphere(3);
    let (part, truth) = cut(&full, |p| p[2] > 0.1);
    let base = quick();
    let more = Options { extra_iterations: 20, ..base.clone() };
    let m = base.max_iterations;
    let a = localize(&full, &part, &base, &Progress::none()).unwrap();
    let b = localize(&full, &part, &more, &Progress::none()).unwrap();
    let mut extended = 0;
    for (ca, cb) in a.candidates.iter().zip(&b.candidates) {
        assert_eq!(ca.label, cb.label);
        assert!(cb.iterations <= m + 20, "{}: {} iterations", cb.label, cb.iterations);
        if ca.iterations < m {
            // Converged before the budget: nothing to extend.
            assert_eq!(ca.iterations, cb.iterations, "{}", cb.label);
        } else if cb.iterations > m {
            extended += 1;
            assert!(cb.cost <= ca.cost, "{}: cost {} -> {}", cb.label, ca.cost, cb.cost);
        } else {
            assert_eq!(ca.cost, cb.cost, "{}: not extended, same run", cb.label);
        }
    }
    assert!(extended > 0, "no start was still converging after {m} iterations");
    assert!(extended < b.candidates.len(), "every start was extended");
    assert!(iou(&b.region, &truth) > 0.9, "IoU {}", iou(&b.region, &truth));
}
