//! Every way a mesh file can be bad gives its own typed error naming the file, in the
//! file's own numbering; nothing panics. One small file per case in `tests/data/`.

use dualspectra::mesh::generate::icosphere;
use dualspectra::mesh::intake::MeshIntake;
use dualspectra::mesh::io::{read_mesh, read_mesh_with_report, ReadOptions};
use dualspectra::shape::{Metric, Shape};
use dualspectra::{Error, MeshError, TriMesh};
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
fn non_manifold_edge_is_split_by_default_and_rejected_without_the_split() {
    let path = data("nonmanifold_edge.off");
    let strict = ReadOptions { split_non_manifold: false, ..ReadOptions::default() };
    match read_mesh_with_report(&path, &strict).unwrap_err() {
        Error::InvalidMeshFile { source, .. } => assert_eq!(source, MeshError::NonManifoldEdge { a: 0, b: 1, count: 3 }),
        other => panic!("{other:?}"),
    }
    // Faces 0 (0 -> 1) and 1 (1 -> 0) stay joined; face 2 gets copies of 0 and 1.
    let (mesh, report) = read_mesh_with_report(&path, &ReadOptions::default()).unwrap();
    assert_eq!((report.non_manifold_edges_split, report.non_manifold_vertices_split), (1, 2));
    assert_eq!(report.kept_vertices, vec![0, 1, 2, 3, 4, 0, 1]);
    assert_eq!(mesh.faces(), &[[0, 1, 2], [1, 0, 3], [5, 6, 4]]);
}

/// A bow tie: two triangles sharing vertex 0 and nothing else.
fn bow_tie() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [-1.0, -1.0, 0.0]];
    (v, vec![[0, 1, 2], [0, 3, 4]])
}

#[test]
fn non_manifold_vertex_is_rejected_by_the_strict_constructor_and_split_by_the_reader() {
    let (v, f) = bow_tie();
    assert_eq!(TriMesh::new(v.clone(), f.clone()), Err(MeshError::NonManifoldVertex { vertex: 0, fans: 2 }));
    // The smallest such vertex is named, with its number of fans: here vertex 1 has three.
    let v3 = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0], [3.0, 0.0, 1.0], [3.0, 1.0, 1.0]];
    let f3 = vec![[1, 2, 0], [1, 3, 4], [1, 5, 6]];
    assert_eq!(TriMesh::new(v3, f3), Err(MeshError::NonManifoldVertex { vertex: 1, fans: 3 }));
    // A file with the bow tie reads split, and without the split is refused.
    let path = tmp("bow_tie.off");
    std::fs::write(&path, "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n-1 0 0\n-1 -1 0\n3 0 1 2\n3 0 3 4\n").unwrap();
    let (mesh, report) = read_mesh_with_report(&path, &ReadOptions::default()).unwrap();
    assert_eq!((report.non_manifold_edges_split, report.non_manifold_vertices_split), (0, 1));
    assert_eq!((mesh.n_vertices(), report.kept_vertices[5]), (6, 0));
    let strict = ReadOptions { split_non_manifold: false, ..ReadOptions::default() };
    match read_mesh_with_report(&path, &strict).unwrap_err() {
        Error::InvalidMeshFile { source, .. } => assert_eq!(source, MeshError::NonManifoldVertex { vertex: 0, fans: 2 }),
        other => panic!("{other:?}"),
    }
}

/// Issue 23, item 5: two spheres glued at one vertex were accepted as one surface, and its
/// Laplace spectrum `[0, 0.152, 2, 2, 2]` had an artefact (0.152) from the pinch. Through the
/// intake the vertex is split and reported, and the spectrum is that of two spheres.
#[test]
fn hostile_05_glued_spheres_are_split_and_reported() {
    let sphere = icosphere(2);
    let n = sphere.n_vertices() as u32;
    // The second sphere: the first reflected through its vertex 0 (faces reversed to keep
    // the orientation), its vertex 0 the first's.
    let p = sphere.vertices()[0];
    let mut v = sphere.vertices().to_vec();
    v.extend(sphere.vertices()[1..].iter().map(|q| [2.0 * p[0] - q[0], 2.0 * p[1] - q[1], 2.0 * p[2] - q[2]]));
    let other = |i: u32| if i == 0 { 0 } else { n + i - 1 };
    let mut f = sphere.faces().to_vec();
    f.extend(sphere.faces().iter().map(|t| [other(t[0]), other(t[2]), other(t[1])]));
    assert_eq!(TriMesh::new(v.clone(), f.clone()), Err(MeshError::NonManifoldVertex { vertex: 0, fans: 2 }));
    let intake = MeshIntake::new(v, f).unwrap();
    let w = intake.warning("mesh").unwrap();
    assert!(w.contains("split 0 non-manifold edge(s) and 1 non-manifold vertex(es) (1 vertex copies"), "{w}");
    assert_eq!((intake.mesh.n_vertices(), intake.kept[2 * n as usize - 1]), (2 * n as usize, 0));
    let values = Shape::new(intake.mesh).dirichlet_spectrum(Metric::Regular, 5).unwrap().values;
    eprintln!("glued spheres, split: spectrum {values:?}");
    // Two components: two zero eigenvalues, then the sphere's l = 1 triple near 2.
    assert!(values[0].abs() < 1e-8 && values[1].abs() < 1e-8, "{values:?}");
    assert!(values[2..].iter().all(|&l| (l - 2.0).abs() < 0.1), "{values:?}");
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

// ---------------------------------------------------------------------------------------
// Issue 23 (adversarial review of the readers): one regression test per finding, named
// after it; the inputs are `tests/data/issue23_*` or generated here when large.

/// The result of `f`, run on its own thread; a hang fails after `limit` instead of
/// blocking the test suite, and a panic fails with its message.
fn within<T: Send + 'static>(limit: std::time::Duration, what: &str, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    match rx.recv_timeout(limit) {
        Ok(v) => v,
        Err(std::sync::mpsc::RecvTimeoutError::Timeout) => panic!("{what}: no answer within {limit:?}"),
        Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => panic!("{what}: the reader panicked"),
    }
}

const SECONDS_5: std::time::Duration = std::time::Duration::from_secs(5);

/// Read bytes as a file of `format` (in memory), within 5 s.
fn read_bytes(bytes: Vec<u8>, ext: &'static str) -> dualspectra::Result<dualspectra::TriMesh> {
    within(SECONDS_5, ext, move || {
        let path = PathBuf::from(format!("<memory>.{ext}"));
        let format = dualspectra::mesh::io::MeshFormat::from_path(&path).unwrap();
        dualspectra::mesh::io::read_mesh_from_bytes(&bytes, format, &path, &ReadOptions::default()).map(|(m, _)| m)
    })
}

fn parse_message_of(result: dualspectra::Result<dualspectra::TriMesh>) -> String {
    match result {
        Err(Error::Parse { message, .. }) => message,
        other => panic!("expected a parse error, got {other:?}"),
    }
}

/// The tetrahedron as binary PLY (the writer's layout: 3 doubles, `uchar int` lists),
/// with `extra` header lines inserted before `element face`.
fn tetrahedron_binary_ply(extra: &str) -> Vec<u8> {
    let tet = read_mesh(&data("tetrahedron.off")).unwrap();
    let path = tmp("tet_binary.ply");
    dualspectra::mesh::io::write_ply(&path, &tet, None, true).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let at = bytes.windows(12).position(|w| w == b"element face").unwrap();
    [&bytes[..at], extra.as_bytes(), &bytes[at..]].concat()
}

#[test]
fn issue23_ply_empty_element_huge_count() {
    let tet = read_mesh(&data("tetrahedron.off")).unwrap();
    // ASCII: each record of a property-less element is a line; 2^64 - 1 lines cannot fit.
    let path = data("issue23_ply_empty_element_huge_count.ply");
    let p = path.clone();
    let m = within(SECONDS_5, "2^64 - 1 empty ASCII records", move || parse_message(&p));
    assert!(
        m.contains("element 'junk' declares 18446744073709551615 records") && m.contains("bytes of data are left"),
        "{m}"
    );
    let text = std::fs::read_to_string(&path).unwrap();
    let m = parse_message_of(read_bytes(text.replace("18446744073709551615", "1000000000").into_bytes(), "ply"));
    assert!(m.contains("declares 1000000000 records"), "{m}");
    // A count the data can hold (the element's records are empty lines) reads.
    let fits = text.replace("18446744073709551615", "3").into_bytes();
    assert_eq!(read_bytes(fits, "ply").unwrap(), tet);
    // Binary: a record of no properties has zero bytes, so any count is skipped in O(1).
    for count in ["18446744073709551615", "1000000000"] {
        let bytes = tetrahedron_binary_ply(&format!("element junk {count}\n"));
        assert_eq!(read_bytes(bytes, "ply").unwrap(), tet, "binary, {count} empty records");
    }
}

#[test]
fn issue23_off_faces_beyond_header_count() {
    let path = data("issue23_off_faces_beyond_header_count.off");
    let m = parse_message(&path);
    assert!(
        m.contains("line 12") && m.contains("'3 1 3 2'") && m.contains("4 vertices and 3 faces the header declares"),
        "{m}"
    );
    // With the count corrected, the same records are the closed tetrahedron.
    let fixed = std::fs::read_to_string(&path).unwrap().replace("4 3 0", "4 4 0");
    let mesh = read_bytes(fixed.into_bytes(), "off").unwrap();
    assert_eq!(mesh, read_mesh(&data("tetrahedron.off")).unwrap());
    assert!(dualspectra::mesh::topology::boundary_vertices(&mesh).is_empty());
    // Trailing comments and blank lines are not records.
    let tail = std::fs::read_to_string(data("tetrahedron.off")).unwrap() + "\n# end\n\n   \n";
    assert!(read_bytes(tail.into_bytes(), "off").is_ok());
}

#[test]
fn issue23_ply_trailing_data() {
    let m = parse_message(&data("issue23_ply_trailing_data.ply"));
    assert!(
        m.contains("line 18") && m.contains("data after the last element 'face': '3'"),
        "{m}"
    );
    // Binary: any byte after the last record.
    let mut bytes = tetrahedron_binary_ply("");
    assert!(read_bytes(bytes.clone(), "ply").is_ok());
    bytes.extend([0u8; 13]);
    let m = parse_message_of(read_bytes(bytes, "ply"));
    assert!(m.contains("13 bytes of data after the last element 'face'"), "{m}");
    // Trailing whitespace after ASCII data is not data.
    let text = std::fs::read_to_string(data("square_pyramid.ply")).unwrap() + "\n \n\t\n";
    assert!(read_bytes(text.into_bytes(), "ply").is_ok());
}

#[test]
fn issue23_ply_second_vertex_element() {
    let m = parse_message(&data("issue23_ply_second_vertex_element.ply"));
    assert!(
        m.contains("line 10") && m.contains("a second 'vertex' element (the first is on line 4)"),
        "{m}"
    );
    let two_faces = tetrahedron_binary_ply("element face 1\nproperty list uchar int vertex_indices\n");
    let m = parse_message_of(read_bytes(two_faces, "ply"));
    assert!(m.contains("a second 'face' element"), "{m}");
}

#[test]
fn issue23_obj_non_numeric_texture_index() {
    let m = parse_message(&data("issue23_obj_non_numeric_texture_index.obj"));
    assert!(m.contains("line 7") && m.contains("'1/a/b'") && m.contains("texture index 'a' is not an integer"), "{m}");
    let obj = |corner: &str| format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nf {corner} 2 3\n").into_bytes();
    let m = parse_message_of(read_bytes(obj("1//x"), "obj"));
    assert!(m.contains("normal index 'x' is not an integer"), "{m}");
    let m = parse_message_of(read_bytes(obj("1/2/3/4"), "obj"));
    assert!(m.contains("more than three"), "{m}");
    // The four legal forms read.
    for corner in ["1", "1/2", "1//3", "1/2/3", "-3/-1/-1"] {
        assert!(read_bytes(obj(corner), "obj").is_ok(), "{corner}");
    }
}

#[test]
fn issue23_obj_most_negative_index() {
    let m = parse_message(&data("issue23_obj_most_negative_index.obj"));
    assert!(
        m.contains("line 6: face 0 refers to vertex -9223372036854775808, but only 3 vertices are defined before it"),
        "{m}"
    );
    let obj = |i: &str| format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 {i}\n").into_bytes();
    let m = parse_message_of(read_bytes(obj("9223372036854775807"), "obj"));
    assert!(m.contains("refers to vertex 9223372036854775807, but the file has 3 vertices"), "{m}");
    let m = parse_message_of(read_bytes(obj("-4"), "obj"));
    assert!(m.contains("refers to vertex -4, but only 3 vertices"), "{m}");
    assert!(read_bytes(obj("-1"), "obj").is_ok());
}

#[test]
fn issue23_long_token_is_quoted_short() {
    let long = "9".repeat(10 << 20) + "x";
    let cases: [(&str, String); 6] = [
        ("off", format!("OFF\n3 1 0\n0 0 {long}\n1 0 0\n0 1 0\n3 0 1 2\n")),
        ("off", format!("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 {long}\n")),
        ("off", format!("OFF\n{long} 1 0\n")),
        ("obj", format!("v 0 0 {long}\n")),
        ("obj", format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/{long}\n")),
        (
            "ply",
            format!("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 {long}\n"),
        ),
    ];
    for (k, (ext, text)) in cases.into_iter().enumerate() {
        let m = parse_message_of(read_bytes(text.into_bytes(), ext));
        assert!(m.len() < 200 && m.contains("9999...' (") && m.contains(" bytes)"), "case {k}: {m}");
    }
}

#[test]
fn issue23_scaled_mesh_is_not_degenerate() {
    use dualspectra::mesh::intake::MeshIntake;
    let ico = dualspectra::mesh::generate::icosphere(1);
    for s in [1e160, 1e-160, 1e300, 1e-300, 1e-310] {
        // A valid mesh stays valid at any scale: its area underflows (1e-320) or overflows
        // (1e320) in the unscaled formula.
        let scaled = ico.map_positions(|p| p.map(|x| x * s));
        assert!(scaled.is_ok(), "scale {s:e}: {:?}", scaled.err());
        let (v, f) = scaled.unwrap().into_parts();
        let intake = MeshIntake::new(v, f).unwrap();
        assert_eq!((intake.dropped_faces, intake.dropped_vertices), (0, 0), "scale {s:e}");
        // ... and a degenerate face stays degenerate: degenerate.off, scaled.
        let off = format!("OFF\n4 2 0\n0 0 0\n{s:e} 0 0\n0 {s:e} 0\n{:e} 0 0\n3 0 1 2\n3 0 3 1\n", 2.0 * s);
        match read_bytes(off.into_bytes(), "off") {
            Err(Error::InvalidMeshFile { source, .. }) => {
                assert_eq!(source, MeshError::DegenerateFace { face: 1 }, "scale {s:e}")
            }
            other => panic!("scale {s:e}: {other:?}"),
        }
    }
    // Coordinates near f64::MAX: the edge vectors overflow unless halved first.
    let big = 1.5e308;
    let tri = dualspectra::TriMesh::new(vec![[big, 0.0, 0.0], [-big, 0.0, 0.0], [0.0, big, 0.0]], vec![[0, 1, 2]]);
    assert!(tri.is_ok(), "{:?}", tri.err());
    let flat = dualspectra::TriMesh::new(vec![[big, 0.0, 0.0], [-big, 0.0, 0.0], [0.0, 0.0, 0.0]], vec![[0, 1, 2]]);
    assert_eq!(flat.unwrap_err(), MeshError::DegenerateFace { face: 0 });
}

#[test]
fn issue23_no_interior_vertex_message() {
    use dualspectra::shape::{Metric, Shape};
    // A single triangle: every vertex is on the boundary.
    let tri = dualspectra::TriMesh::new(vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]]).unwrap();
    let e = Shape::new(tri).dirichlet_spectrum(Metric::Regular, 1).unwrap_err().to_string();
    assert!(e.contains("the mesh has no interior vertex (every vertex is on the boundary)"), "{e}");
    assert!(!e.contains("0 < k < 0"), "{e}");
    // With interior vertices, the count and the range.
    let disk = dualspectra::mesh::generate::disk(1.0, 3);
    let e = Shape::new(disk).dirichlet_spectrum(Metric::Regular, 10_000).unwrap_err().to_string();
    assert!(e.contains("interior vertices (need 0 < k <"), "{e}");
}

#[test]
fn issue23_non_regular_file_is_refused() {
    #[cfg(unix)]
    {
        // A symbolic link to /dev/zero was read without bound.
        let link = tmp("zero.off");
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        let l = link.clone();
        match within(SECONDS_5, "symlink to /dev/zero", move || read_mesh(&l)) {
            Err(Error::Io { path, source }) => {
                assert_eq!(path, link);
                let m = source.to_string();
                assert!(m.contains("not a regular file") && m.contains("/dev/zero") && m.contains("character device"), "{m}");
            }
            other => panic!("{other:?}"),
        }
        // A named pipe: refused without opening it (opening would block).
        let fifo = tmp("pipe.off");
        let _ = std::fs::remove_file(&fifo);
        if std::process::Command::new("mkfifo").arg(&fifo).status().is_ok_and(|s| s.success()) {
            let f = fifo.clone();
            let m = within(SECONDS_5, "named pipe", move || read_mesh(&f)).unwrap_err().to_string();
            assert!(m.contains("not a regular file (a named pipe)"), "{m}");
        } else {
            println!("mkfifo not available: the named-pipe case is not checked");
        }
        // A symbolic link to a regular file reads.
        let good = tmp("link_to_tet.off");
        let _ = std::fs::remove_file(&good);
        std::os::unix::fs::symlink(data("tetrahedron.off"), &good).unwrap();
        assert_eq!(read_mesh(&good).unwrap().n_faces(), 4);
    }
    let dir = tmp("a_directory_23.off");
    std::fs::create_dir_all(&dir).unwrap();
    let m = read_mesh(&dir).unwrap_err().to_string();
    assert!(m.contains("not a regular file (a directory)"), "{m}");
}

#[test]
fn issue23_first_bad_face_fails_the_read() {
    // Faces are checked as they are read: face 0 fails before the bad token on line 7
    // (which used to be reported first, after everything was held in memory).
    let off = "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n0\n3 0 1 x\n";
    let m = parse_message_of(read_bytes(off.into(), "off"));
    assert!(m.contains("line 6: face 0 has 0 vertices"), "{m}");
    // 10^7 zero-length binary faces: an error at face 0, not after reading them all.
    let header = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                  property float z\nelement face 10000000\nproperty list uchar int vertex_indices\nend_header\n";
    let mut bytes = header.as_bytes().to_vec();
    bytes.extend([0u8; 36]);
    bytes.resize(bytes.len() + 10_000_000, 0);
    let m = parse_message_of(read_bytes(bytes, "ply"));
    assert_eq!(m, "face 0 has 0 vertices; a face needs at least 3");
    // A face before the vertex element is checked against the declared vertex count.
    let ply = "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nelement vertex 3\n\
               property float x\nproperty float y\nproperty float z\nend_header\n3 0 1 7\n0 0 0\n1 0 0\n0 1 0\n";
    match read_bytes(ply.into(), "ply") {
        Err(Error::InvalidMeshFile { source, .. }) => {
            assert_eq!(source, MeshError::IndexOutOfRange { face: 0, index: 7, n_vertices: 3 })
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn ply_ascii_integers_must_fit_their_declared_type() {
    // A value its declared type cannot hold is malformed (a binary file could not hold it),
    // not read as written: here an index 300 declared `uchar`, a list length 256 declared `uchar`.
    let ply = |face: &str| {
        format!(
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
             element face 1\nproperty list uchar uchar vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n{face}\n"
        )
        .into_bytes()
    };
    assert!(read_bytes(ply("3 0 1 2"), "ply").is_ok());
    let m = parse_message_of(read_bytes(ply("3 0 1 300"), "ply"));
    assert!(m.contains("face 0, vertex_indices: '300' is not an integer in [0, 255]"), "{m}");
    let m = parse_message_of(read_bytes(ply("256 0 1 2"), "ply"));
    assert!(m.contains("'256' is not an integer in [0, 255]"), "{m}");
}
