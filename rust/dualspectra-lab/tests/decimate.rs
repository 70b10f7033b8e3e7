//! Decimation of SHREC'16 null shapes (needs the data: `#[ignore]`d, run with
//! `--include-ignored`):
//! vertex count near the target, area kept, boundary kept, valid mesh, exact transfer at
//! kept vertices; and the timing of SHOT on the decimated shape.

use dualspectra::lab::shot::{default_shot_radius, shot_descriptors, DEFAULT_MIN_NEIGHBORS};
use dualspectra::lab::decimate::decimate;
use dualspectra::mesh::io::read_mesh;
use dualspectra::lab::nearest::{nearest_vertices, transfer};
use dualspectra::mesh::topology::{boundary_vertices, connected_components, euler_characteristic};
use dualspectra::mesh::TriMesh;
use dualspectra_lab::datasets::data_root_for_tests;
use std::path::PathBuf;

fn data_root() -> PathBuf {
    data_root_for_tests().join("shrec16")
}

#[test]
#[ignore = "needs ../shared/datasets (set DUALSPECTRA_DATA)"]
fn shrec16_null_shapes_decimate_to_half() {
    let root = data_root();
    for class in [
        "cat", "centaur", "david", "dog", "horse", "michael", "victoria", "wolf",
    ] {
        let m = read_mesh(&root.join(format!("null/{class}.off"))).unwrap();
        let t = std::time::Instant::now();
        let d = decimate(&m, 0.5).unwrap();
        let dt = t.elapsed();
        let target = m.n_vertices() as f64 / 2.0;
        let got = d.mesh.n_vertices() as f64;
        let area = (d.mesh.area() - m.area()).abs() / m.area();
        eprintln!(
            "{class}: {} -> {} vertices in {dt:.2?}, area change {:.3}%",
            m.n_vertices(),
            got,
            100.0 * area
        );
        assert!(
            (got - target).abs() <= 0.05 * target,
            "{class}: {got} vertices for target {target}"
        );
        assert!(area < 0.03, "{class}: area changed by {area}");
        // Valid (re-validate from parts) and topologically the same surface.
        let (v, f) = d.mesh.clone().into_parts();
        TriMesh::new(v, f).unwrap();
        assert_eq!(
            euler_characteristic(&d.mesh),
            euler_characteristic(&m),
            "{class}: topology changed"
        );
        assert_eq!(connected_components(&d.mesh).1, connected_components(&m).1);
        // Boundary kept vertex for vertex.
        let kept: Vec<u32> = boundary_vertices(&d.mesh)
            .iter()
            .map(|&i| d.original_vertex[i as usize])
            .collect();
        assert_eq!(kept, boundary_vertices(&m), "{class}: boundary changed");
        // Nearest-neighbour transfer back is exact at kept vertices.
        let map = nearest_vertices(d.mesh.vertices(), m.vertices()).unwrap();
        let ids: Vec<u32> = (0..d.mesh.n_vertices() as u32).collect();
        let back = transfer(&ids, &map).unwrap();
        for (i, &o) in d.original_vertex.iter().enumerate() {
            assert_eq!(back[o as usize], i as u32);
        }
    }
}

#[test]
#[ignore = "needs ../shared/datasets (set DUALSPECTRA_DATA)"]
fn shot_on_a_decimated_null_shape_timing() {
    let root = data_root();
    let m = read_mesh(&root.join("null/cat.off")).unwrap();
    let d = decimate(&m, 0.5).unwrap();
    let radius = default_shot_radius(&m);
    let t = std::time::Instant::now();
    let s = shot_descriptors(&d.mesh, radius, DEFAULT_MIN_NEIGHBORS).unwrap();
    eprintln!(
        "SHOT of {} vertices (radius {radius:.2}) in {:.2?}",
        d.mesh.n_vertices(),
        t.elapsed()
    );
    assert_eq!(s.nrows(), d.mesh.n_vertices());
}
