//! The SHREC'16 loader on the real data (needs it: `#[ignore]`d, run with
//! `--include-ignored`).
//!
//! Law checked: the ground-truth region covers the part of the full shape that the partial
//! is, so the area of the faces whose three vertices are marked, relative to the full
//! shape, agrees with the partial/full area ratio (the dataset README: 0.506 vs 0.494 on
//! cuts_cat_shape_1; the shapes are near-isometric).

use dualspectra_lab::datasets::{data_root_for_tests, Dataset};

fn dataset() -> Dataset {
    let root = data_root_for_tests().join("shrec16");
    Dataset::open(&root).unwrap_or_else(|e| panic!("{}: {e}", root.display()))
}

fn marked_face_area_fraction(mesh: &dualspectra::TriMesh, mask: &[bool]) -> f64 {
    let v = mesh.vertices();
    let area = |f: &[u32; 3]| {
        dualspectra::mesh::triangle_area(v[f[0] as usize], v[f[1] as usize], v[f[2] as usize])
    };
    let marked: f64 = mesh
        .faces()
        .iter()
        .filter(|f| f.iter().all(|&i| mask[i as usize]))
        .map(area)
        .sum();
    marked / mesh.area()
}

#[test]
#[ignore = "needs ../shared/datasets (set DUALSPECTRA_DATA)"]
fn cat_1_ground_truth_area_matches_the_partial_area() {
    let ds = dataset();
    let pairs = ds.pairs().unwrap();
    assert!(pairs.len() >= 8, "{} pairs", pairs.len());
    let pair = pairs
        .iter()
        .find(|p| p.name == "cuts_cat_shape_1")
        .expect("cuts_cat_shape_1 listed");
    assert_eq!((pair.class.as_str(), pair.index), ("cat", 1));
    let data = pair.load().unwrap();
    let gt_frac = marked_face_area_fraction(&data.full, &data.gt);
    let ratio = data.partial.area() / data.full.area();
    assert!(
        (gt_frac - 0.506).abs() < 0.01,
        "GT face area fraction {gt_frac}"
    );
    assert!(
        (gt_frac - ratio).abs() < 0.03,
        "GT {gt_frac} vs partial/full area {ratio}"
    );
    let sym = data.gt_sym.expect("symmetric ground truth present");
    let sym_frac = marked_face_area_fraction(&data.full, &sym);
    assert!(
        (sym_frac - ratio).abs() < 0.05,
        "GT_sym {sym_frac} vs {ratio}"
    );
}

#[test]
#[ignore = "needs ../shared/datasets (set DUALSPECTRA_DATA)"]
fn every_pair_loads_with_a_plausible_ground_truth() {
    let ds = dataset();
    // Checks a sample (one pair per class) to keep the test fast.
    let pairs = ds.pairs().unwrap();
    let mut seen = std::collections::HashSet::new();
    for pair in pairs.iter().filter(|p| seen.insert(p.class.clone())) {
        let data = pair.load().unwrap_or_else(|e| panic!("{}: {e}", pair.name));
        let gt_frac = marked_face_area_fraction(&data.full, &data.gt);
        let ratio = data.partial.area() / data.full.area();
        assert!(
            (gt_frac - ratio).abs() < 0.1,
            "{}: GT {gt_frac} vs partial/full area {ratio}",
            pair.name
        );
    }
}
