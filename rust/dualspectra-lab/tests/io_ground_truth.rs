//! Ground truth tied to a file's triangles after reading repaired the file (issue 23):
//! SHREC'16 `.baryc_gt` rows name triangles of the FILE (1-based). When reading removes a
//! two-sided flap, the later triangles are renumbered and the flap's tip vertex is dropped;
//! the ground-truth mask must still mark the vertices of the triangles the rows name. When it
//! splits a non-manifold vertex, a file vertex stands for all its copies.

use dualspectra_lab::datasets::{ground_truth_mask, ground_truth_mask_in_file, parse_barycentric_gt, vertex_mask_in_file, Pair};
use dualspectra::mesh::io::{read_mesh, read_mesh_with_report, ReadOptions};
use dualspectra::Error;
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data").join(name)
}

/// The vertices and faces of an OFF file as written (no repair), for an independent check.
fn file_records(path: &Path) -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.trim().is_empty() && !l.starts_with('#')).skip(1);
    let counts: Vec<usize> = lines.next().unwrap().split_whitespace().map(|t| t.parse().unwrap()).collect();
    let numbers = |l: &str| -> Vec<f64> { l.split_whitespace().map(|t| t.parse().unwrap()).collect() };
    let v = (0..counts[0]).map(|_| numbers(lines.next().unwrap())).map(|c| [c[0], c[1], c[2]]).collect();
    let f = (0..counts[1])
        .map(|_| numbers(lines.next().unwrap()))
        .map(|c| [c[1] as usize, c[2] as usize, c[3] as usize])
        .collect();
    (v, f)
}

/// A SHREC'16 layout in a fresh folder: `null/<class>.off` copied from `full`, the
/// tetrahedron as the partial shape, and `rows` as its `.baryc_gt` (1-based triangles).
fn dataset(name: &str, full: &Path, rows: &[usize]) -> Pair {
    let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("io_ground_truth").join(name);
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(root.join("null")).unwrap();
    std::fs::create_dir_all(root.join("cuts")).unwrap();
    std::fs::copy(full, root.join("null/shape.off")).unwrap();
    std::fs::copy(data("tetrahedron.off"), root.join("cuts/cuts_shape_shape_1.off")).unwrap();
    let gt: String = rows.iter().map(|t| format!("{t} 0.2 0.3 0.5\n")).collect();
    std::fs::write(root.join("cuts/cuts_shape_shape_1.baryc_gt"), gt).unwrap();
    let pairs = dualspectra_lab::datasets::Dataset::open(&root).unwrap().pairs().unwrap();
    assert_eq!(pairs.len(), 1);
    pairs.into_iter().next().unwrap()
}

#[test]
fn issue23_shrec16_flap_before_ground_truth() {
    let full = data("issue23_shrec16_flap_before_ground_truth.off");
    let (file_vertices, file_faces) = file_records(&full);
    let (mesh, report) = read_mesh_with_report(&full, &ReadOptions::default()).unwrap();
    // Reading removed records 0 and 1 (the flap) and vertex 0 (its tip): every later
    // triangle and vertex is renumbered.
    assert_eq!((report.duplicate_faces_removed, report.flap_vertices_dropped), (2, 1));
    assert_eq!(report.face_origin, (2..10).collect::<Vec<u32>>());
    assert_eq!(report.kept_vertices, (1..7).collect::<Vec<u32>>());

    // The partial's four vertices lie on file triangles 3 and 4 (1-based): corners 1, 2,
    // 3 and 5 of the file, not 4 and 6.
    let rows = [3, 4, 4, 3];
    let pair = dataset("flap_first", &full, &rows);
    let loaded = pair.load().unwrap();
    assert_eq!(loaded.full, mesh);
    // Expected: the positions of the named file triangles' corners, found in the mesh.
    let mut expected = vec![false; mesh.n_vertices()];
    for &t in &rows {
        for &fv in &file_faces[t - 1] {
            let m = mesh.vertices().iter().position(|p| *p == file_vertices[fv]).unwrap();
            expected[m] = true;
        }
    }
    assert_eq!(expected.iter().filter(|&&b| b).count(), 4);
    assert_eq!(loaded.gt, expected);
    // Without the mapping (row t read as mesh triangle t - 1) the mask is wrong...
    let gt_rows = parse_barycentric_gt(&std::fs::read_to_string(&pair.gt).unwrap(), &pair.gt).unwrap();
    assert_ne!(ground_truth_mask(&mesh, &gt_rows, None, &pair.gt).unwrap(), expected);
    // ... and the file's last triangle (10) is out of range of the mesh's 8.
    let last = parse_barycentric_gt("10 1 0 0\n", &pair.gt).unwrap();
    assert!(ground_truth_mask(&mesh, &last, None, &pair.gt).is_err());
    let mask = ground_truth_mask_in_file(&mesh, &report, &last, &pair.gt).unwrap();
    let want: Vec<usize> = file_faces[9].iter().map(|&fv| fv - 1).collect::<std::collections::BTreeSet<_>>().into_iter().collect();
    assert_eq!((0..mesh.n_vertices()).filter(|&v| mask[v]).collect::<Vec<_>>(), want);

    // A row naming a removed flap copy marks the flap's base (kept), not its tip (dropped).
    let at = Path::new("rows");
    let flap_row = parse_barycentric_gt("1 1 0 0\n", at).unwrap();
    let mask = ground_truth_mask_in_file(&mesh, &report, &flap_row, at).unwrap();
    let base: Vec<usize> = [1, 2].iter().map(|&fv| fv - 1).collect();
    assert_eq!(mask.iter().enumerate().filter(|(_, &b)| b).map(|(v, _)| v).collect::<Vec<_>>(), base);
    // Rows out of the file's range are errors naming the row.
    let out = parse_barycentric_gt("1 1 0 0\n11 1 0 0\n", at).unwrap();
    let e = ground_truth_mask_in_file(&mesh, &report, &out, at).unwrap_err();
    assert!(matches!(&e, Error::Parse { message, .. } if message.contains("row 2: triangle 11 is out of range")), "{e}");
}

#[test]
fn issue23_repeated_triangle_copy_in_ground_truth_marks_the_kept_copy() {
    // duplicate_face.off: the tetrahedron with two of its triangles listed twice (same
    // orientation); the second copies are removed, the first kept.
    let path = data("duplicate_face.off");
    let (file_vertices, file_faces) = file_records(&path);
    let (mesh, report) = read_mesh_with_report(&path, &ReadOptions::default()).unwrap();
    assert_eq!(report.removed_triangles.len(), 2);
    assert_eq!(mesh, read_mesh(&data("tetrahedron.off")).unwrap());
    for &(record, tri) in &report.removed_triangles {
        let t = record as usize;
        assert_eq!(tri.map(|v| v as usize), file_faces[t]);
        let rows = parse_barycentric_gt(&format!("{} 1 0 0\n", t + 1), Path::new("rows")).unwrap();
        let mask = ground_truth_mask_in_file(&mesh, &report, &rows, Path::new("rows")).unwrap();
        let marked: Vec<[f64; 3]> = (0..mesh.n_vertices()).filter(|&v| mask[v]).map(|v| mesh.vertices()[v]).collect();
        let mut want: Vec<[f64; 3]> = file_faces[t].iter().map(|&v| file_vertices[v]).collect();
        want.sort_by(|a, b| a.partial_cmp(b).unwrap());
        let mut got = marked;
        got.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(got, want, "record {t}");
    }
}

#[test]
fn ground_truth_follows_a_split_non_manifold_vertex_to_all_its_copies() {
    // A bow tie (vertex 0 joins two triangles) whose first triangle is listed twice: reading
    // removes the copy (record 2) and gives vertex 0 a copy, mesh vertex 5, for the second fan.
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join("io_ground_truth_bow_tie.off");
    std::fs::write(&path, "OFF\n5 3 0\n0 0 0\n1 0 0\n1 1 0\n-1 0 0\n-1 -1 0\n3 0 1 2\n3 0 3 4\n3 0 1 2\n").unwrap();
    let (mesh, report) = read_mesh_with_report(&path, &ReadOptions::default()).unwrap();
    assert_eq!(report.kept_vertices, vec![0, 1, 2, 3, 4, 0]);
    assert_eq!(mesh.faces(), &[[0, 1, 2], [5, 3, 4]]);
    let at = Path::new("rows");
    let marked = |mask: Vec<bool>| (0..mask.len()).filter(|&v| mask[v]).collect::<Vec<_>>();
    // A kept triangle marks its own corners: the first fan's vertex 0 only.
    let rows = parse_barycentric_gt("1 1 0 0\n2 1 0 0\n", at).unwrap();
    assert_eq!(marked(ground_truth_mask_in_file(&mesh, &report, &rows[..1], at).unwrap()), [0, 1, 2]);
    assert_eq!(marked(ground_truth_mask_in_file(&mesh, &report, &rows[1..], at).unwrap()), [3, 4, 5]);
    // The removed copy is known by its file vertices: file vertex 0 is both 0 and 5.
    let removed = parse_barycentric_gt("3 1 0 0\n", at).unwrap();
    assert_eq!(marked(ground_truth_mask_in_file(&mesh, &report, &removed, at).unwrap()), [0, 1, 2, 5]);
    // So is a region given as file vertices.
    let region = vertex_mask_in_file(&mesh, &report, &[0, 3], at).unwrap();
    assert_eq!(marked(region), [0, 3, 5]);
}
