//! Chapter 1, meshes: read a mesh file (OFF, OBJ or PLY), or make one, and look at it.
//!
//! `cargo run --example 101_read_mesh -- [MESH]` (without MESH: an icosphere).

use dualspectra::mesh::generate::icosphere;
use dualspectra::mesh::io::{read_mesh_with_report, ReadOptions};
use dualspectra::mesh::topology::{boundary_vertex_mask, connected_components, euler_characteristic};

fn main() -> dualspectra::Result<()> {
    let mesh = match std::env::args().nth(1) {
        Some(path) => {
            // Polygons are fan-triangulated and repeated triangles removed; the report says what
            // was repaired and maps the mesh's vertices back to the file's.
            let (mesh, report) = read_mesh_with_report(path.as_ref(), &ReadOptions { drop_isolated: true, ..Default::default() })?;
            println!("{path}: {} vertex records, {} face records ({:?})", report.file_vertices, report.file_faces, report.format);
            mesh
        }
        None => icosphere(3),
    };
    let boundary = boundary_vertex_mask(&mesh).iter().filter(|&&b| b).count();
    println!(
        "{} vertices, {} triangles, area {:.4}, {} boundary vertices, {} component(s), Euler characteristic {}",
        mesh.n_vertices(),
        mesh.n_faces(),
        mesh.area(),
        boundary,
        connected_components(&mesh).1,
        euler_characteristic(&mesh)
    );
    Ok(())
}
