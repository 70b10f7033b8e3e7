//! SHOT descriptors agree at true correspondences of SHREC'16 pairs (needs the data:
//! `#[ignore]`d, run with `--include-ignored`).

use dualspectra::lab::shot::{default_shot_radius, shot_with_frames, Shot, DEFAULT_MIN_NEIGHBORS, SHOT_DIM};
use dualspectra::mesh::io::read_mesh;
use dualspectra_lab::datasets::{data_root_for_tests, read_barycentric_gt, read_full_shape};

fn row_dist(a: &Shot, i: usize, b: &Shot, j: usize) -> f64 {
    (0..SHOT_DIM)
        .map(|k| (a.descriptors[(i, k)] - b.descriptors[(j, k)]).powi(2))
        .sum::<f64>()
        .sqrt()
}

#[test]
#[ignore = "needs ../shared/datasets (set DUALSPECTRA_DATA)"]
fn shrec16_correspondents_are_closer_than_random_vertices() {
    let root = data_root_for_tests().join("shrec16");
    for (class, i) in [("cat", 1), ("david", 2), ("horse", 3)] {
        let (full, groups) = read_full_shape(&root.join(format!("null/{class}.off"))).unwrap();
        let partial = read_mesh(&root.join(format!("cuts/cuts_{class}_shape_{i}.off"))).unwrap();
        let gt = read_barycentric_gt(&root.join(format!("cuts/cuts_{class}_shape_{i}.baryc_gt")))
            .unwrap();
        assert_eq!(gt.len(), partial.n_vertices());
        let radius = default_shot_radius(&full);
        let t = std::time::Instant::now();
        let sf = shot_with_frames(&full, radius, DEFAULT_MIN_NEIGHBORS).unwrap();
        let sp = shot_with_frames(&partial, radius, DEFAULT_MIN_NEIGHBORS).unwrap();
        eprintln!(
            "{class}: SHOT of {} + {} vertices in {:.2?}",
            full.n_vertices(),
            partial.n_vertices(),
            t.elapsed()
        );
        // Correspondent: the vertex of the ground-truth triangle with the largest weight.
        let mut s = 0x2545_F491_4F6C_DD1Du64;
        let (mut d_true, mut d_rand, mut count) = (0.0, 0.0, 0usize);
        for (pv, row) in gt.iter().enumerate() {
            let tri = groups[row.triangle as usize][0] as usize;
            let k = (0..3)
                .max_by(|&a, &b| row.weights[a].total_cmp(&row.weights[b]))
                .unwrap();
            let fv = full.faces()[tri][k] as usize;
            if sp.frames[pv].is_none() || sf.frames[fv].is_none() {
                continue;
            }
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let rv = (s % full.n_vertices() as u64) as usize;
            d_true += row_dist(&sp, pv, &sf, fv);
            d_rand += row_dist(&sp, pv, &sf, rv);
            count += 1;
        }
        let (d_true, d_rand) = (d_true / count as f64, d_rand / count as f64);
        eprintln!("{class} {i}: mean distance to the true correspondent {d_true:.3}, to a random vertex {d_rand:.3}");
        assert!(count * 10 >= 9 * partial.n_vertices());
        assert!(d_true < 0.85 * d_rand, "{class} {i}: {d_true} vs {d_rand}");
    }
}
