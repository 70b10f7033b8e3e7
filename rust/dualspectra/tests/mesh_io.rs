//! Mesh file formats: round trips, fan triangulation, the isolated-vertex repair,
//! binary PLY built byte by byte, the OBJ reader against `tobj`, and the SHREC'16 files.

use dualspectra::mesh::generate::{disk, grid, icosphere};
use dualspectra::mesh::io::{
    read_mesh, read_mesh_from_bytes, read_mesh_with_report, write_mesh, write_obj, write_off, write_ply, MeshFormat,
    ReadOptions,
};
use dualspectra::mesh::topology::{boundary_vertices, euler_characteristic};
use dualspectra::{Error, TriMesh};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data")
        .join(name)
}

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mesh_io");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Meshes whose coordinates need every bit: irrational values, tiny and huge scales, a boundary.
fn test_meshes() -> Vec<(&'static str, TriMesh)> {
    let ico = icosphere(2);
    vec![
        ("icosphere", ico.clone()),
        ("disk", disk(1.0, 4)),
        (
            "tiny",
            ico.map_positions(|p| [p[0] * 1e-70 / 3.0, p[1] * 7e-71, p[2] * std::f64::consts::PI * 1e-69])
                .unwrap(),
        ),
        (
            "huge",
            ico.map_positions(|p| [p[0] * 1e70 / 3.0, p[1] * 1e69, p[2] * 1e70])
                .unwrap(),
        ),
        (
            "grid",
            grid(std::f64::consts::E, 1.0 / 3.0, 5, 3)
                .map_positions(|p| [p[0], p[1], (p[0] * 7.0).sin() * 0.1])
                .unwrap(),
        ),
    ]
}

type Writer = fn(&Path, &TriMesh) -> dualspectra::Result<()>;

#[test]
fn round_trip_every_format_is_bit_exact() {
    for (name, mesh) in test_meshes() {
        let writers: [(&str, Writer); 4] = [
            ("off", write_off),
            ("obj", write_obj),
            ("ply", |p, m| write_ply(p, m, None, false)),
            ("ply", |p, m| write_ply(p, m, None, true)),
        ];
        for (k, (ext, write)) in writers.iter().enumerate() {
            let path = tmp(&format!("{name}_{k}.{ext}"));
            write(&path, &mesh).unwrap();
            let back = read_mesh(&path).unwrap();
            assert_eq!(back, mesh, "{name} through {}", path.display());
        }
        let path = tmp(&format!("{name}_dispatch.ply"));
        write_mesh(&path, &mesh).unwrap();
        assert_eq!(read_mesh(&path).unwrap(), mesh);
    }
}

#[test]
fn ply_with_vertex_colors_reads_back_the_mesh_and_writes_the_colors() {
    let mesh = icosphere(1);
    let colors: Vec<[u8; 3]> = (0..mesh.n_vertices())
        .map(|i| [i as u8, 255 - i as u8, (i * 7) as u8])
        .collect();
    for binary in [false, true] {
        let path = tmp(&format!("colored_{binary}.ply"));
        write_ply(&path, &mesh, Some(&colors), binary).unwrap();
        assert_eq!(read_mesh(&path).unwrap(), mesh);
        let bytes = std::fs::read(&path).unwrap();
        let header_end = find(&bytes, b"end_header\n").unwrap() + 11;
        let header = std::str::from_utf8(&bytes[..header_end]).unwrap();
        assert!(header.contains("property uchar red\nproperty uchar green\nproperty uchar blue\n"));
        if binary {
            // Vertex record = 3 doubles + 3 bytes.
            for (i, c) in colors.iter().enumerate() {
                let at = header_end + i * 27 + 24;
                assert_eq!(&bytes[at..at + 3], c);
            }
        } else {
            let body = std::str::from_utf8(&bytes[header_end..]).unwrap();
            for (line, c) in body.lines().zip(&colors) {
                assert!(line.ends_with(&format!(" {} {} {}", c[0], c[1], c[2])), "{line}");
            }
        }
    }
    let err = write_ply(&tmp("wrong_colors.ply"), &mesh, Some(&colors[1..]), true).unwrap_err();
    assert!(matches!(err, Error::InvalidArgument(_)), "{err}");
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

#[test]
fn quads_are_fan_triangulated_and_reported() {
    let (mesh, report) = read_mesh_with_report(&data("square_pyramid.off"), &ReadOptions::default()).unwrap();
    assert_eq!((mesh.n_vertices(), mesh.n_faces()), (5, 6));
    assert_eq!(
        (report.file_vertices, report.file_faces, report.polygons_triangulated),
        (5, 5, 1)
    );
    assert_eq!(report.format, MeshFormat::Off);
    // Fan of "4 0 3 2 1" from its first vertex, then the triangles.
    assert_eq!(&mesh.faces()[..2], &[[0, 3, 2], [0, 2, 1]]);
    assert_eq!(report.face_origin, vec![0, 0, 1, 2, 3, 4]);
    assert_eq!(euler_characteristic(&mesh), 2);
    assert!(boundary_vertices(&mesh).is_empty());
    // Area of the pyramid: base 1 + four sides of base 1 and slant height sqrt(1.25).
    let expected = 1.0 + 4.0 * 0.5 * 1.25f64.sqrt();
    assert!((mesh.area() - expected).abs() < 8.0 * f64::EPSILON * expected);
}

#[test]
fn ascii_ply_with_extra_properties_and_elements_equals_the_off() {
    let off = read_mesh(&data("square_pyramid.off")).unwrap();
    let (ply, report) = read_mesh_with_report(&data("square_pyramid.ply"), &ReadOptions::default()).unwrap();
    assert_eq!(ply, off);
    assert_eq!(report.polygons_triangulated, 1);
}

/// The square pyramid as binary PLY, built by hand (independent of the writer): float
/// coordinates with an interleaved `uchar` property, `uchar`/`int` index lists, a quad.
fn pyramid_binary_ply(big_endian: bool) -> Vec<u8> {
    let format = if big_endian {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut b = format!(
        "ply\nformat {format} 1.0\nelement vertex 5\nproperty float x\nproperty uchar quality\nproperty float y\n\
         property float z\nelement face 5\nproperty list uchar int vertex_indices\nend_header\n"
    )
    .into_bytes();
    let f32b = |x: f32| if big_endian { x.to_be_bytes() } else { x.to_le_bytes() };
    let i32b = |x: i32| if big_endian { x.to_be_bytes() } else { x.to_le_bytes() };
    let v: [[f32; 3]; 5] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, 1.0],
    ];
    for (i, p) in v.iter().enumerate() {
        b.extend(f32b(p[0]));
        b.push(i as u8 * 50);
        b.extend(f32b(p[1]));
        b.extend(f32b(p[2]));
    }
    let faces: [&[i32]; 5] = [&[0, 3, 2, 1], &[0, 1, 4], &[1, 2, 4], &[2, 3, 4], &[3, 0, 4]];
    for f in faces {
        b.push(f.len() as u8);
        for &i in f {
            b.extend(i32b(i));
        }
    }
    b
}

#[test]
fn binary_ply_both_endiannesses_equal_the_off() {
    let off = read_mesh(&data("square_pyramid.off")).unwrap();
    for big in [false, true] {
        let path = tmp(&format!("pyramid_be_{big}.ply"));
        std::fs::write(&path, pyramid_binary_ply(big)).unwrap();
        assert_eq!(read_mesh(&path).unwrap(), off, "big endian: {big}");
    }
}

#[test]
fn truncated_binary_ply_names_the_element_and_record() {
    let full = pyramid_binary_ply(false);
    let path = tmp("truncated_binary.ply");
    // Cut in the middle of face 4 (last face: 1 + 3 * 4 bytes).
    std::fs::write(&path, &full[..full.len() - 5]).unwrap();
    let err = read_mesh(&path).unwrap_err();
    match &err {
        Error::Parse { path: p, message } => {
            assert_eq!(p, &path);
            assert!(
                message.contains("face 4 of 5") && message.contains("truncated"),
                "{message}"
            );
        }
        other => panic!("expected a parse error, got {other:?}"),
    }
    // Cut inside the vertices.
    let header_len = find(&full, b"end_header\n").unwrap() + 11;
    std::fs::write(&path, &full[..header_len + 20]).unwrap();
    let msg = read_mesh(&path).unwrap_err().to_string();
    assert!(msg.contains("vertex 1 of 5"), "{msg}");
}

#[test]
fn obj_quads_in_groups_stay_one_closed_mesh_with_the_files_numbering() {
    let (mesh, report) = read_mesh_with_report(&data("cube_quads.obj"), &ReadOptions::default()).unwrap();
    assert_eq!((mesh.n_vertices(), mesh.n_faces()), (8, 12));
    assert_eq!(report.polygons_triangulated, 6);
    assert_eq!(mesh.vertices()[6], [1.0, 1.0, 1.0]); // "v 1 1 1" is the 7th vertex line
    assert!(boundary_vertices(&mesh).is_empty(), "groups must not cut the mesh");
    assert_eq!(euler_characteristic(&mesh), 2);
    assert_eq!(mesh.faces()[6..8], [[3, 7, 6], [3, 6, 2]]); // "f -5 -1 -2 -6" after 8 vertices
    assert!((mesh.area() - 6.0).abs() < 8.0 * f64::EPSILON);
}

/// Every triangle as its three corner positions (bit patterns), sorted: equal for two
/// readers that agree on geometry whatever their vertex numbering.
fn triangle_soup(positions: &[[f64; 3]], faces: impl Iterator<Item = [usize; 3]>) -> Vec<[[u64; 3]; 3]> {
    let mut soup: Vec<_> = faces.map(|f| f.map(|i| positions[i].map(f64::to_bits))).collect();
    soup.sort();
    soup
}

#[test]
fn obj_reader_agrees_with_tobj_on_the_triangles() {
    let options = tobj::LoadOptions {
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let mut paths = vec![data("cube_quads.obj")];
    let p = tmp("ico_for_tobj.obj");
    write_obj(&p, &icosphere(2)).unwrap();
    paths.push(p);
    for path in paths {
        let ours = read_mesh(&path).unwrap();
        let ours_soup = triangle_soup(ours.vertices(), ours.faces().iter().map(|f| f.map(|i| i as usize)));
        let (models, _) = tobj::load_obj(&path, &options).unwrap();
        let mut theirs = Vec::new();
        for m in &models {
            let pos: Vec<[f64; 3]> = m.mesh.positions.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            theirs.extend(triangle_soup(
                &pos,
                m.mesh
                    .indices
                    .chunks_exact(3)
                    .map(|c| [c[0] as usize, c[1] as usize, c[2] as usize]),
            ));
        }
        theirs.sort();
        assert_eq!(ours_soup, theirs, "{}", path.display());
    }
}

#[test]
fn isolated_vertices_are_an_error_unless_dropped_then_the_map_is_reported() {
    let path = data("isolated.off");
    match read_mesh(&path).unwrap_err() {
        Error::InvalidMeshFile { source, .. } => {
            assert_eq!(source, dualspectra::MeshError::IsolatedVertex { vertex: 2, count: 1 })
        }
        other => panic!("{other:?}"),
    }
    let (mesh, report) = read_mesh_with_report(
        &path,
        &ReadOptions {
            drop_isolated: true,
            ..ReadOptions::default()
        },
    )
    .unwrap();
    assert_eq!(report.isolated_dropped, 1);
    assert_eq!(report.kept_vertices, vec![0, 1, 3, 4]);
    assert_eq!(report.file_vertices, 5);
    // Same geometry as the tetrahedron file, which lists the same faces without the extra vertex.
    let tet = read_mesh(&data("tetrahedron.off")).unwrap();
    assert_eq!(mesh.vertices(), tet.vertices());
    assert_eq!(
        triangle_soup(mesh.vertices(), mesh.faces().iter().map(|f| f.map(|i| i as usize))),
        triangle_soup(tet.vertices(), tet.faces().iter().map(|f| f.map(|i| i as usize)))
    );
}

#[test]
fn two_sided_flaps_are_removed_with_their_tip() {
    let tet = read_mesh(&data("tetrahedron.off")).unwrap();
    let (mesh, report) = read_mesh_with_report(&data("flap.off"), &ReadOptions::default()).unwrap();
    assert_eq!((report.duplicate_faces_removed, report.flap_vertices_dropped), (2, 1));
    assert_eq!(report.kept_vertices, vec![0, 1, 2, 3]);
    assert_eq!(report.face_origin, vec![0, 1, 3, 4]);
    assert_eq!(mesh, tet);
    let strict = ReadOptions {
        remove_duplicate_faces: false,
        split_non_manifold: false,
        ..ReadOptions::default()
    };
    let err = read_mesh_with_report(&data("flap.off"), &strict).unwrap_err();
    assert!(
        matches!(
            err,
            Error::InvalidMeshFile {
                source: dualspectra::MeshError::RepeatedFace { face: 5, first: 2 },
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn an_edge_of_four_faces_is_split_with_counts_and_a_many_to_one_map() {
    // A square (0, 2, 1, 3) and two flaps (0, 1, 4), (1, 0, 5) on its diagonal edge (0, 1),
    // and a loose vertex 6 (dropped): faces 0 and 1 (0 -> 1, then 1 -> 0) stay joined, the
    // flaps get copies of 0 and 1 and come off as two triangles.
    let path = tmp("edge_of_four_faces.off");
    std::fs::write(
        &path,
        "OFF\n7 4 0\n0 0 0\n1 1 0\n1 0 0\n0 1 0\n0.5 0.5 1\n0.5 0.5 -1\n9 9 9\n\
         3 0 1 3\n3 1 0 2\n3 0 1 4\n3 1 0 5\n",
    )
    .unwrap();
    let options = ReadOptions { drop_isolated: true, ..ReadOptions::default() };
    let (mesh, report) = read_mesh_with_report(&path, &options).unwrap();
    assert_eq!((report.non_manifold_edges_split, report.non_manifold_vertices_split), (1, 2));
    assert_eq!((report.isolated_dropped, report.n_copies()), (1, 4));
    assert_eq!(report.kept_vertices, vec![0, 1, 2, 3, 4, 5, 0, 1, 1, 0]);
    assert_eq!(mesh.faces(), &[[0, 1, 3], [1, 0, 2], [6, 7, 4], [8, 9, 5]]);
    assert_eq!(report.face_origin, vec![0, 1, 2, 3]);
    // Copies sit at their file vertex; the mesh is the square plus two loose triangles.
    let file = [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.5, 1.0], [0.5, 0.5, -1.0]];
    for (m, &f) in report.kept_vertices.iter().enumerate() {
        assert_eq!(mesh.vertices()[m], file[f as usize]);
    }
    assert_eq!(dualspectra::mesh::topology::connected_components(&mesh).1, 3);
    let w = report.non_manifold_warning().unwrap();
    assert!(w.contains("split 1 non-manifold edge(s) and 2 non-manifold vertex(es): 4 vertex copies"), "{w}");
    // Off, the file is refused in its own numbering.
    let strict = ReadOptions { split_non_manifold: false, ..options };
    match read_mesh_with_report(&path, &strict).unwrap_err() {
        Error::InvalidMeshFile { source, .. } => {
            assert_eq!(source, dualspectra::MeshError::NonManifoldEdge { a: 0, b: 1, count: 4 })
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn repeated_triangles_in_one_orientation_are_kept_once() {
    let tet = read_mesh(&data("tetrahedron.off")).unwrap();
    let (mesh, report) = read_mesh_with_report(&data("duplicate_face.off"), &ReadOptions::default()).unwrap();
    assert_eq!((report.duplicate_faces_removed, report.flap_vertices_dropped), (2, 0));
    assert_eq!(mesh, tet);
}

#[test]
fn format_comes_from_the_extension_in_any_case() {
    let src = std::fs::read(data("tetrahedron.off")).unwrap();
    let p = tmp("UPPER.OFF");
    std::fs::write(&p, &src).unwrap();
    assert_eq!(read_mesh(&p).unwrap().n_faces(), 4);
    let (m, _) = read_mesh_from_bytes(&src, MeshFormat::Off, Path::new("<memory>"), &ReadOptions::default()).unwrap();
    assert_eq!(m.n_vertices(), 4);
}
