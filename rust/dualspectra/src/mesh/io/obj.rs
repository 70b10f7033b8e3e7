//! Wavefront OBJ reader and writer (geometry only).
//!
//! Read: `v x y z [w] [r g b]` (first three values kept) and `f a b c ...`, each corner
//! `v`, `v/vt`, `v//vn` or `v/vt/vn` (the `vt`, `vn` parts must be integers, and are not
//! used); positive indices are 1-based, negative ones count back from the last vertex
//! defined so far. All other records (`vt`, `vn`, `o`, `g`,
//! `s`, `usemtl`, `mtllib`, `l`, `p`) are ignored.
//!
//! Why not `tobj` (which the workspace depends on): `tobj` renumbers vertices in order
//! of first use, silently drops vertices no face uses, and numbers each `o`/`g` group
//! separately, duplicating the vertices groups share. A mesh with groups would come
//! back cut along group borders (a spurious boundary, hence a different Dirichlet
//! spectrum), and vertex numbers would no longer be the file's. This reader keeps the
//! file's numbering; the tests check it against `tobj` on the triangles' coordinates.

use super::{content_lines, parse_error, quote, RawMesh};
use crate::error::Result;
use crate::mesh::TriMesh;
use std::io::Write;
use std::path::Path;

pub(super) fn parse(bytes: &[u8], path: &Path) -> Result<RawMesh> {
    let text = String::from_utf8_lossy(bytes);
    // A first pass counts the records: positive indices (which may point forward) are
    // then checked as they are read, and the arrays are allocated once, at their size.
    let (mut n_vertices, mut n_triangles) = (0usize, 0usize);
    for (_, line) in content_lines(&text) {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => n_vertices += 1,
            Some("f") => {
                n_triangles += it.count().saturating_sub(2);
            }
            _ => {}
        }
    }
    let mut raw = RawMesh::new(n_vertices, path)?;
    raw.reserve(n_vertices, n_triangles);
    let n = n_vertices as i64;
    let mut poly: Vec<u64> = Vec::new();
    for (l, line) in content_lines(&text) {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let mut xyz = [0.0; 3];
                for c in &mut xyz {
                    let tok = it.next().ok_or_else(|| {
                        parse_error(
                            path,
                            format!("line {l}: vertex has fewer than 3 coordinates: {}", quote(line)),
                        )
                    })?;
                    *c = tok.parse::<f64>().map_err(|_| {
                        parse_error(path, format!("line {l}: vertex coordinate {} is not a number", quote(tok)))
                    })?;
                }
                raw.positions.push(xyz);
            }
            Some("f") => {
                let face = raw.n_polygons;
                let defined = raw.positions.len() as i64;
                poly.clear();
                for corner in it {
                    let bad = |m: String| parse_error(path, format!("line {l}: face vertex {}: {m}", quote(corner)));
                    let mut parts = corner.split('/');
                    let tok = parts.next().unwrap_or("");
                    let i: i64 = tok
                        .parse()
                        .map_err(|_| bad("does not start with an integer index".into()))?;
                    // `v/vt/vn`: the texture and normal indices are not used, but a corner
                    // that is not one of the four forms is an error, not a guess.
                    for (what, part) in ["texture", "normal"].iter().zip(parts.by_ref()) {
                        if !part.is_empty() && part.parse::<i64>().is_err() {
                            return Err(bad(format!("{what} index {} is not an integer", quote(part))));
                        }
                    }
                    if parts.next().is_some() {
                        return Err(bad("has more than three '/'-separated indices (v/vt/vn)".into()));
                    }
                    let zero_based = match i {
                        0 => {
                            return Err(parse_error(
                                path,
                                format!("line {l}: face vertex index 0 (OBJ indices start at 1)"),
                            ))
                        }
                        i if i > n => {
                            return Err(parse_error(
                                path,
                                format!("line {l}: face {face} refers to vertex {i}, but the file has {n} vertices"),
                            ))
                        }
                        i if i > 0 => i - 1,
                        // Negative: counts back from the last vertex defined (-1 is the last).
                        // `i < -defined` cannot overflow (0 <= defined < 2^32), unlike `-i`.
                        i if i < -defined => {
                            return Err(parse_error(
                                path,
                                format!(
                                    "line {l}: face {face} refers to vertex {i}, but only {defined} vertices \
                                     are defined before it"
                                ),
                            ))
                        }
                        i => defined + i,
                    };
                    poly.push(zero_based as u64);
                }
                raw.push_polygon(&poly, path, Some(l))?;
            }
            _ => {}
        }
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
