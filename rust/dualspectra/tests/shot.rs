//! Laws of the SHOT descriptor (`geometry::shot`): rigid-motion and scale invariance,
//! unit norm, equality on a sphere (agreement at true correspondences of SHREC'16 pairs:
//! dualspectra-lab's `tests/shot_shrec16.rs`).

use dualspectra::lab::shot::{
    shot_descriptors, shot_keypoint_descriptors, shot_with_frames, LocalFrame, Shot,
    DEFAULT_MIN_NEIGHBORS, SHOT_DIM,
};
use dualspectra::mesh::generate::icosphere;
use dualspectra::mesh::TriMesh;

/// A sphere with smooth, non-symmetric bumps: generic geometry, well-separated frames.
fn bumpy_sphere(level: u32) -> TriMesh {
    icosphere(level)
        .map_positions(|p| {
            let r = 1.0
                + 0.15 * (3.0 * p[0] + 1.0).sin() * (2.0 * p[1] - 0.5).cos()
                + 0.1 * (4.0 * p[2] + p[0]).sin();
            [r * p[0] * 1.3, r * p[1], r * p[2] * 0.8]
        })
        .unwrap()
}

/// A rotation (unit quaternion, generic axis) and a translation.
fn rigid(p: [f64; 3]) -> [f64; 3] {
    let (w, x, y, z) = {
        let q = [0.9, 0.3, -0.25, 0.2];
        let n = q.iter().map(|v: &f64| v * v).sum::<f64>().sqrt();
        (q[0] / n, q[1] / n, q[2] / n, q[3] / n)
    };
    let r = [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - z * w),
            2.0 * (x * z + y * w),
        ],
        [
            2.0 * (x * y + z * w),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - x * w),
        ],
        [
            2.0 * (x * z - y * w),
            2.0 * (y * z + x * w),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ];
    let t = [3.0, -1.5, 0.25];
    [0, 1, 2].map(|i| r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2] + t[i])
}

/// A frame is "stable" when its eigenvalues are well separated and no sign vote tied:
/// only there is the descriptor a continuous function of the geometry.
fn stable(f: &Option<LocalFrame>) -> bool {
    match f {
        Some(f) => {
            let [a, b, c] = f.eigenvalues;
            (a - b) > 1e-3 * a && (b - c) > 1e-3 * a && !f.tied_sign
        }
        None => false,
    }
}

fn row_dist(a: &Shot, i: usize, b: &Shot, j: usize) -> f64 {
    (0..SHOT_DIM)
        .map(|k| (a.descriptors[(i, k)] - b.descriptors[(j, k)]).powi(2))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn invariant_to_rigid_motion() {
    let m = bumpy_sphere(3);
    let moved = m.map_positions(rigid).unwrap();
    let radius = 0.35;
    let a = shot_with_frames(&m, radius, DEFAULT_MIN_NEIGHBORS).unwrap();
    let b = shot_with_frames(&moved, radius, DEFAULT_MIN_NEIGHBORS).unwrap();
    let mut n_stable = 0;
    for i in 0..m.n_vertices() {
        if stable(&a.frames[i]) && stable(&b.frames[i]) {
            n_stable += 1;
            let d = row_dist(&a, i, &b, i);
            assert!(
                d < 1e-9,
                "vertex {i}: descriptors differ by {d} after a rigid motion"
            );
        }
    }
    eprintln!("{n_stable} stable frames of {}", m.n_vertices());
    // Ties of the sign vote are frequent with ~20 support points (even counts).
    assert!(
        n_stable * 3 >= 2 * m.n_vertices(),
        "only {n_stable} of {} frames are stable",
        m.n_vertices()
    );
}

#[test]
fn invariant_to_uniform_scale_with_the_radius() {
    let m = bumpy_sphere(3);
    let radius = 0.35;
    let a = shot_with_frames(&m, radius, DEFAULT_MIN_NEIGHBORS).unwrap();
    for s in [1e-4, 1e4] {
        let scaled = m.map_positions(|p| p.map(|c| c * s)).unwrap();
        let b = shot_with_frames(&scaled, radius * s, DEFAULT_MIN_NEIGHBORS).unwrap();
        for i in 0..m.n_vertices() {
            if stable(&a.frames[i]) && stable(&b.frames[i]) {
                let d = row_dist(&a, i, &b, i);
                assert!(d < 1e-9, "scale {s}, vertex {i}: descriptors differ by {d}");
            }
        }
    }
}

#[test]
fn rows_are_unit_or_zero_and_deterministic() {
    let m = bumpy_sphere(2);
    let shot = shot_with_frames(&m, 0.3, DEFAULT_MIN_NEIGHBORS).unwrap();
    assert_eq!(shot.descriptors.nrows(), m.n_vertices());
    assert_eq!(shot.descriptors.ncols(), SHOT_DIM);
    for i in 0..m.n_vertices() {
        let norm = (0..SHOT_DIM)
            .map(|k| shot.descriptors[(i, k)].powi(2))
            .sum::<f64>()
            .sqrt();
        match shot.frames[i] {
            Some(_) => assert!((norm - 1.0).abs() < 1e-14, "row {i} has norm {norm}"),
            None => assert_eq!(norm, 0.0),
        }
        assert!((0..SHOT_DIM).all(|k| shot.descriptors[(i, k)] >= 0.0));
    }
    let again = shot_descriptors(&m, 0.3, DEFAULT_MIN_NEIGHBORS).unwrap();
    assert!(again == shot.descriptors, "not deterministic");
}

#[test]
fn keypoint_descriptors_are_the_rows_of_the_full_ones() {
    let m = bumpy_sphere(2);
    let all = shot_descriptors(&m, 0.3, DEFAULT_MIN_NEIGHBORS).unwrap();
    let keys = [7u32, 0, 7, 41, (m.n_vertices() - 1) as u32];
    let some = shot_keypoint_descriptors(&m, &keys, 0.3, DEFAULT_MIN_NEIGHBORS).unwrap();
    assert_eq!((some.nrows(), some.ncols()), (keys.len(), SHOT_DIM));
    for (r, &k) in keys.iter().enumerate() {
        assert!((0..SHOT_DIM).all(|c| some[(r, c)] == all[(k as usize, c)]), "row {r} (vertex {k}) differs");
    }
    let bad = shot_keypoint_descriptors(&m, &[m.n_vertices() as u32], 0.3, DEFAULT_MIN_NEIGHBORS).unwrap_err();
    assert!(bad.to_string().contains("out of range"), "{bad}");
    assert!(shot_keypoint_descriptors(&m, &keys, -1.0, DEFAULT_MIN_NEIGHBORS).is_err());
}

#[test]
fn all_descriptors_nearly_equal_on_a_sphere() {
    // The sphere looks the same from every vertex, up to the (arbitrary) tangent axis
    // and the sampling; the histogram is nearly symmetric about z, so the rows agree.
    let m = icosphere(4);
    let shot = shot_with_frames(&m, 0.3, DEFAULT_MIN_NEIGHBORS).unwrap();
    let n = m.n_vertices();
    let mean: Vec<f64> = (0..SHOT_DIM)
        .map(|k| (0..n).map(|i| shot.descriptors[(i, k)]).sum::<f64>() / n as f64)
        .collect();
    let worst = (0..n)
        .map(|i| {
            (0..SHOT_DIM)
                .map(|k| (shot.descriptors[(i, k)] - mean[k]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .fold(0.0, f64::max);
    // On a bumpy shape rows differ a lot more (same radius, same resolution).
    let b = bumpy_sphere(4);
    let sb = shot_with_frames(&b, 0.3, DEFAULT_MIN_NEIGHBORS).unwrap();
    let mean_b: Vec<f64> = (0..SHOT_DIM)
        .map(|k| (0..n).map(|i| sb.descriptors[(i, k)]).sum::<f64>() / n as f64)
        .collect();
    let spread_b = (0..n)
        .map(|i| {
            (0..SHOT_DIM)
                .map(|k| (sb.descriptors[(i, k)] - mean_b[k]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .sum::<f64>()
        / n as f64;
    eprintln!(
        "sphere: max distance to the mean row {worst:.4}; bumpy shape: mean distance {spread_b:.4}"
    );
    assert!(worst < 0.25, "sphere descriptors spread {worst}");
    assert!(
        worst < spread_b,
        "sphere spread {worst} not below the bumpy shape's {spread_b}"
    );
    // Every vertex's normal points the same way relative to its frame: all the mass is in
    // one elevation/cosine regime, the same for every row (a strong equality check).
    for i in 0..n {
        let argmax = (0..SHOT_DIM)
            .max_by(|&a, &c| shot.descriptors[(i, a)].total_cmp(&shot.descriptors[(i, c)]))
            .unwrap();
        assert_eq!(
            argmax % 11,
            (0..SHOT_DIM)
                .max_by(|&a, &c| mean[a].total_cmp(&mean[c]))
                .unwrap()
                % 11
        );
    }
}
