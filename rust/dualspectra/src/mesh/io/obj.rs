//! Wavefront OBJ reader and writer (geometry only).
//!
//! Read: `v x y z [w] [r g b]` (first three values kept) and `f a b c ...`, each corner
//! `v`, `v/vt`, `v//vn` or `v/vt/vn`; positive indices are 1-based, negative ones count
//! back from the last vertex defined so far. All other records (`vt`, `vn`, `o`, `g`,
//! `s`, `usemtl`, `mtllib`, `l`, `p`) are ignored.
//!
//! Why not `tobj` (which the workspace depends on): `tobj` renumbers vertices in order
//! of first use, silently drops vertices no face uses, and numbers each `o`/`g` group
//! separately, duplicating the vertices groups share. A mesh with groups would come
//! back cut along group borders (a spurious boundary, hence a different Dirichlet
//! spectrum), and vertex numbers would no longer be the file's. This reader keeps the
//! file's numbering; the tests check it against `tobj` on the triangles' coordinates.

use super::{content_lines, parse_error, RawMesh};
use crate::error::Result;
use crate::mesh::TriMesh;
use std::io::Write;
use std::path::Path;

pub(super) fn parse(bytes: &[u8], path: &Path) -> Result<RawMesh> {
    let text = String::from_utf8_lossy(bytes);
    let mut raw = RawMesh::new();
    // (line, face record, index as written) of every positive index, checked at the end.
    let mut forward: Vec<(usize, usize, i64)> = Vec::new();
    for (l, line) in content_lines(&text) {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let mut xyz = [0.0; 3];
                for c in &mut xyz {
                    let tok = it.next().ok_or_else(|| {
                        parse_error(path, format!("line {l}: vertex has fewer than 3 coordinates: '{line}'"))
                    })?;
                    *c = tok.parse::<f64>().map_err(|_| {
                        parse_error(path, format!("line {l}: vertex coordinate '{tok}' is not a number"))
                    })?;
                }
                raw.positions.push(xyz);
            }
            Some("f") => {
                let face = raw.n_polygons();
                let defined = raw.positions.len() as i64;
                for corner in it {
                    let tok = corner.split('/').next().unwrap_or("");
                    let i: i64 = tok.parse().map_err(|_| {
                        parse_error(
                            path,
                            format!("line {l}: face vertex '{corner}' does not start with an integer index"),
                        )
                    })?;
                    let zero_based = match i {
                        0 => {
                            return Err(parse_error(
                                path,
                                format!("line {l}: face vertex index 0 (OBJ indices start at 1)"),
                            ))
                        }
                        i if i > 0 => {
                            forward.push((l, face, i));
                            i - 1
                        }
                        i => {
                            if -i > defined {
                                return Err(parse_error(
                                    path,
                                    format!("line {l}: face {face} refers to vertex {i}, but only {defined} vertices are defined before it"),
                                ));
                            }
                            defined + i
                        }
                    };
                    raw.indices.push(zero_based as u64);
                }
                raw.end_polygon();
            }
            _ => {}
        }
    }
    let n = raw.positions.len() as i64;
    if let Some(&(l, face, i)) = forward.iter().find(|&&(_, _, i)| i > n) {
        return Err(parse_error(
            path,
            format!("line {l}: face {face} refers to vertex {i}, but the file has {n} vertices"),
        ));
    }
    Ok(raw)
}

pub(super) fn write(w: &mut impl Write, mesh: &TriMesh) -> std::io::Result<()> {
    writeln!(
        w,
        "# dualspectra {}: {} vertices, {} faces",
        crate::VERSION,
        mesh.n_vertices(),
        mesh.n_faces()
    )?;
    for p in mesh.vertices() {
        writeln!(w, "v {:?} {:?} {:?}", p[0], p[1], p[2])?;
    }
    for f in mesh.faces() {
        writeln!(w, "f {} {} {}", f[0] + 1, f[1] + 1, f[2] + 1)?;
    }
    Ok(())
}
