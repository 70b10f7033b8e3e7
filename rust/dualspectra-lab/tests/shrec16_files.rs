//! Every SHREC'16 file reads with the counts of its header, flaps (two-sided triangles)
//! being the only repair (needs the data: `#[ignore]`d, run with `--include-ignored`).

use dualspectra::mesh::io::{read_mesh_with_report, ReadOptions};
use dualspectra_lab::datasets::data_root_for_tests;
use std::path::{Path, PathBuf};

/// `(vertices, faces)` from an OFF header, read directly from the text.
fn off_header_counts(path: &Path) -> (usize, usize) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'));
    let first = lines.next().unwrap();
    let counts_line = if first.split_whitespace().count() > 1 {
        &first[3..]
    } else {
        lines.next().unwrap()
    };
    let c: Vec<usize> = counts_line.split_whitespace().map(|t| t.parse().unwrap()).collect();
    (c[0], c[1])
}

#[test]
#[ignore = "needs ../shared/datasets (set DUALSPECTRA_DATA)"]
fn shrec16_files_read_with_the_header_counts() {
    let root = data_root_for_tests().join("shrec16");
    let mut n = 0;
    for sub in ["null", "cuts"] {
        let mut paths: Vec<PathBuf> = std::fs::read_dir(root.join(sub))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "off"))
            .collect();
        paths.sort();
        for path in paths {
            let (nv, nf) = off_header_counts(&path);
            let (mesh, report) =
                read_mesh_with_report(&path, &ReadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(
                (report.file_vertices, report.file_faces),
                (nv, nf),
                "{}",
                path.display()
            );
            // Flaps (null/cat.off has 12) are the only repair these files need.
            assert_eq!(
                (
                    mesh.n_vertices() + report.flap_vertices_dropped,
                    mesh.n_faces() + report.duplicate_faces_removed
                ),
                (nv, nf),
                "{}",
                path.display()
            );
            assert_eq!(report.duplicate_faces_removed, 2 * report.flap_vertices_dropped);
            assert_eq!(report.polygons_triangulated, 0);
            if path.ends_with("null/cat.off") {
                assert_eq!(report.flap_vertices_dropped, 12);
            } else {
                assert_eq!(report.duplicate_faces_removed, 0, "{}", path.display());
            }
            n += 1;
        }
    }
    assert!(n > 0, "no .off files under {}", root.display());
    println!("read {n} SHREC'16 files");
}
