//! Every way a mesh file can be bad gives its own typed error naming the file, in the
//! file's own numbering; nothing panics. One small file per case in `tests/data/`.

use dualspectra::mesh::io::{read_mesh, read_mesh_with_report, ReadOptions};
use dualspectra::{Error, MeshError};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data")
        .join(name)
}

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mesh_validation");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The validation error of a file, checking that it names the file.
fn mesh_error(name: &str) -> MeshError {
    let path = data(name);
    match read_mesh(&path).unwrap_err() {
        Error::InvalidMeshFile { path: p, source } => {
            assert_eq!(p, path);
            source
        }
        other => panic!("{name}: expected InvalidMeshFile, got {other:?}"),
    }
}

/// The parse error message of a file, checking that the error names the file (also in its text).
fn parse_message(path: &Path) -> String {
    let err = read_mesh(path).unwrap_err();
    let text = err.to_string();
    assert!(text.starts_with(&path.display().to_string()), "{text}");
    assert!(!text.contains('\n'), "one line: {text}");
    match err {
        Error::Parse { path: p, message } => {
            assert_eq!(p, path);
            message
        }
        other => panic!("{}: expected Parse, got {other:?}", path.display()),
    }
}

#[test]
fn index_out_of_range_names_face_and_vertex() {
    let e = mesh_error("bad.off");
    assert_eq!(
        e,
        MeshError::IndexOutOfRange {
            face: 3,
            index: 99,
            n_vertices: 4
        }
    );
    let text = read_mesh(&data("bad.off")).unwrap_err().to_string();
    assert!(
        text.ends_with("bad.off: face 3 refers to vertex 99, but the mesh has 4 vertices"),
        "{text}"
    );
    assert_eq!(
        mesh_error("bad_index.ply"),
        MeshError::IndexOutOfRange {
            face: 3,
            index: 99,
            n_vertices: 4
        }
    );
    let m = parse_message(&data("bad_index.obj"));
    assert!(
        m.contains("line 6") && m.contains("vertex 9") && m.contains("4 vertices"),
        "{m}"
    );
    let m = parse_message(&data("zero_index.obj"));
    assert!(m.contains("line 4") && m.contains("index 0"), "{m}");
}

#[test]
fn non_finite_coordinates_name_the_vertex() {
    assert_eq!(mesh_error("nan.off"), MeshError::NonFiniteCoordinate { vertex: 2 });
    assert_eq!(mesh_error("inf.off"), MeshError::NonFiniteCoordinate { vertex: 1 });
}

#[test]
fn no_faces_is_rejected() {
    assert_eq!(mesh_error("no_faces.off"), MeshError::NoFaces);
}

#[test]
fn degenerate_and_repeated_vertex_faces_are_rejected_with_the_file_face_number() {
    assert_eq!(mesh_error("degenerate.off"), MeshError::DegenerateFace { face: 1 });
    assert_eq!(
        mesh_error("repeated_vertex.off"),
        MeshError::RepeatedVertexInFace { face: 1 }
    );
}

#[test]
fn non_manifold_edge_is_rejected() {
    assert_eq!(
        mesh_error("nonmanifold_edge.off"),
        MeshError::NonManifoldEdge { a: 0, b: 1, count: 3 }
    );
}

#[test]
fn isolated_vertex_is_rejected_by_default() {
    assert_eq!(
        mesh_error("isolated.off"),
        MeshError::IsolatedVertex { vertex: 2, count: 1 }
    );
}

#[test]
fn errors_after_dropping_and_triangulation_use_file_numbers() {
    // Vertex 1 is isolated and dropped; the collinear quad (face record 1) gives zero-area
    // fan triangles. The error must name face record 1, not triangle 1 or 2.
    let path = tmp("drop_then_degenerate.off");
    std::fs::write(
        &path,
        "OFF\n6 2 0\n0 0 0\n5 5 5\n1 0 0\n0 1 0\n2 0 0\n3 0 0\n3 0 2 3\n4 0 4 5 2\n",
    )
    .unwrap();
    match read_mesh_with_report(
        &path,
        &ReadOptions {
            drop_isolated: true,
            ..ReadOptions::default()
        },
    )
    .unwrap_err()
    {
        Error::InvalidMeshFile { source, .. } => assert_eq!(source, MeshError::DegenerateFace { face: 1 }),
        other => panic!("{other:?}"),
    }
    // Vertices 1 and 3 are dropped; the infinite one is vertex 4 of the file (2 of the mesh).
    std::fs::write(&path, "OFF\n5 1 0\n0 0 0\n5 5 5\n1 0 0\n0 1 0\ninf 0 0\n3 0 2 4\n").unwrap();
    match read_mesh_with_report(
        &path,
        &ReadOptions {
            drop_isolated: true,
            ..ReadOptions::default()
        },
    )
    .unwrap_err()
    {
        Error::InvalidMeshFile { source, .. } => assert_eq!(source, MeshError::NonFiniteCoordinate { vertex: 4 }),
        other => panic!("{other:?}"),
    }
}

#[test]
fn truncated_files_say_how_far_they_got() {
    let m = parse_message(&data("truncated.off"));
    assert!(m.contains("after 2 of 4 faces") && m.contains("truncated"), "{m}");
    let m = parse_message(&data("truncated_vertices.off"));
    assert!(m.contains("after 2 of 4 vertices"), "{m}");
    let m = parse_message(&data("truncated.ply"));
    assert!(m.contains("face 1 of 4") && m.contains("truncated"), "{m}");
}

#[test]
fn bad_headers_are_parse_errors() {
    for (name, expect) in [
        ("bad_header.off", "expected 'OFF', found 'OFX'"),
        ("bad_counts.off", "expected vertex, face and edge counts"),
        ("binary_header.off", "binary OFF is not supported"),
        ("empty.off", "empty"),
        ("bad_header.ply", "unsupported format line"),
        ("no_end_header.ply", "before 'end_header'"),
        ("no_z.ply", "no scalar property 'z'"),
    ] {
        let m = parse_message(&data(name));
        assert!(m.contains(expect), "{name}: {m}");
    }
}

#[test]
fn malformed_records_are_parse_errors_with_line_numbers() {
    let m = parse_message(&data("two_vertex_face.off"));
    assert!(m.contains("face 1 has 2 vertices"), "{m}");
    let m = parse_message(&data("negative_index.off"));
    assert!(m.contains("line 6") && m.contains("'-1'"), "{m}");
    let m = parse_message(&data("bad_number.off"));
    assert!(m.contains("line 4") && m.contains("'x' is not a number"), "{m}");
}

#[test]
fn unreadable_files_are_io_errors_naming_the_file() {
    let missing = data("does_not_exist.off");
    match read_mesh(&missing).unwrap_err() {
        Error::Io { path, source } => {
            assert_eq!(path, missing);
            assert_eq!(source.kind(), std::io::ErrorKind::NotFound);
        }
        other => panic!("{other:?}"),
    }
    let dir = tmp("a_directory.off");
    std::fs::create_dir_all(&dir).unwrap();
    assert!(matches!(read_mesh(&dir).unwrap_err(), Error::Io { .. }));
}

#[test]
fn unknown_extension_is_a_parse_error() {
    let m = parse_message(Path::new("mesh.stl"));
    assert!(m.contains("unknown mesh format '.stl'"), "{m}");
    let m = parse_message(Path::new("mesh"));
    assert!(m.contains("no file extension"), "{m}");
}

/// Every prefix of valid files and arbitrary byte flips give an error or a mesh, never a panic.
#[test]
fn corrupted_bytes_never_panic() {
    let mut sources: Vec<(String, Vec<u8>)> = ["tetrahedron.off", "square_pyramid.ply", "cube_quads.obj"]
        .iter()
        .map(|n| (n.to_string(), std::fs::read(data(n)).unwrap()))
        .collect();
    let bin = tmp("ico.ply");
    dualspectra::mesh::io::write_ply(&bin, &dualspectra::mesh::generate::icosphere(0), None, true).unwrap();
    sources.push(("ico.ply".into(), std::fs::read(&bin).unwrap()));
    let mut state = 0x9e3779b97f4a7c15u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for (name, bytes) in &sources {
        let format = dualspectra::mesh::io::MeshFormat::from_path(Path::new(name)).unwrap();
        let opts = ReadOptions::default();
        for cut in 0..bytes.len() {
            let _ = dualspectra::mesh::io::read_mesh_from_bytes(&bytes[..cut], format, Path::new(name), &opts);
        }
        for _ in 0..2000 {
            let mut b = bytes.clone();
            for _ in 0..1 + next() % 3 {
                let i = (next() % b.len() as u64) as usize;
                b[i] = next() as u8;
            }
            let _ = dualspectra::mesh::io::read_mesh_from_bytes(&b, format, Path::new(name), &opts);
        }
    }
}
