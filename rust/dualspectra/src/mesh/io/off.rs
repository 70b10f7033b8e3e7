//! OFF reader and writer.
//!
//! Layout: a header keyword (`OFF`, optionally prefixed by `ST`, `C`, `N` for texture,
//! colour and normal variants), then `nv nf ne` (on the header line or the next), then
//! `nv` vertex lines (`x y z`, further values ignored), then `nf` face lines
//! (`n i0 .. i{n-1}`, further values such as a colour ignored). `#` starts a comment.
//! The reader is line-based (one record per line), as written by MeshLab, CGAL, libigl
//! and the SHREC'16 files. Binary OFF and 4-D/n-D OFF are rejected, and so is any record
//! after the declared faces (a header that undercounts the faces would otherwise drop some).

use super::{content_lines, parse_error, quote, RawMesh};
use crate::error::Result;
use crate::mesh::TriMesh;
use std::io::Write;
use std::path::Path;

/// Shortest vertex line (`0 0 0\n`) and face line (`3 0 1 2\n`), in bytes: the declared
/// counts reserve no more records than the rest of the file can hold.
const MIN_VERTEX_LINE: usize = 6;
const MIN_FACE_LINE: usize = 8;

pub(super) fn parse(bytes: &[u8], path: &Path) -> Result<RawMesh> {
    let text = String::from_utf8_lossy(bytes);
    let mut lines = content_lines(&text);
    let (line_no, header) = lines
        .next()
        .ok_or_else(|| parse_error(path, "bad header: the file is empty"))?;
    let mut tokens = header.split_whitespace();
    let keyword = tokens.next().unwrap_or("");
    check_keyword(keyword).map_err(|m| parse_error(path, format!("line {line_no}: bad header: {m}")))?;
    let rest: Vec<&str> = tokens.collect();
    if rest.first().is_some_and(|t| t.eq_ignore_ascii_case("BINARY")) {
        return Err(parse_error(
            path,
            format!("line {line_no}: binary OFF is not supported (save as ASCII OFF, or PLY)"),
        ));
    }
    let (count_line, counts) = if rest.is_empty() {
        let (l, c) = lines
            .next()
            .ok_or_else(|| parse_error(path, "bad header: the file ends before the vertex and face counts"))?;
        (l, c.split_whitespace().collect::<Vec<_>>())
    } else {
        (line_no, rest)
    };
    let count = |i: usize| counts.get(i).and_then(|t| t.parse::<usize>().ok());
    let (Some(nv), Some(nf)) = (count(0), count(1)) else {
        return Err(parse_error(
            path,
            format!(
                "line {count_line}: bad header: expected vertex, face and edge counts, found {}",
                quote(&counts.join(" "))
            ),
        ));
    };
    let mut raw = RawMesh::new(nv, path)?;
    let vertex_room = nv.min(bytes.len() / MIN_VERTEX_LINE);
    let face_room = nf.min((bytes.len() - vertex_room * MIN_VERTEX_LINE) / MIN_FACE_LINE + 1);
    raw.reserve(vertex_room, face_room);
    for v in 0..nv {
        let (l, line) = lines
            .next()
            .ok_or_else(|| parse_error(path, format!("the file ends after {v} of {nv} vertices (truncated?)")))?;
        let mut xyz = [0.0; 3];
        let mut it = line.split_whitespace();
        for c in &mut xyz {
            let tok = it.next().ok_or_else(|| {
                parse_error(
                    path,
                    format!("line {l}: vertex {v} has fewer than 3 coordinates: {}", quote(line)),
                )
            })?;
            *c = tok
                .parse::<f64>()
                .map_err(|_| parse_error(path, format!("line {l}: vertex {v}: {} is not a number", quote(tok))))?;
        }
        raw.positions.push(xyz);
    }
    let mut poly: Vec<u64> = Vec::new();
    for f in 0..nf {
        let (l, line) = lines
            .next()
            .ok_or_else(|| parse_error(path, format!("the file ends after {f} of {nf} faces (truncated?)")))?;
        let mut it = line.split_whitespace();
        let first = it.next().unwrap_or("");
        let k: usize = first.parse().map_err(|_| {
            parse_error(
                path,
                format!("line {l}: face {f}: vertex count {} is not a non-negative integer", quote(first)),
            )
        })?;
        poly.clear();
        for j in 0..k {
            let tok = it.next().ok_or_else(|| {
                parse_error(
                    path,
                    format!("line {l}: face {f} lists {k} vertices but gives only {j} indices"),
                )
            })?;
            let i: u64 = tok.parse().map_err(|_| {
                parse_error(
                    path,
                    format!("line {l}: face {f}: vertex index {} is not a non-negative integer", quote(tok)),
                )
            })?;
            poly.push(i);
        }
        raw.push_polygon(&poly, path, Some(l))?;
    }
    // A closed mesh whose header undercounts its faces would otherwise come back open.
    if let Some((l, line)) = lines.next() {
        return Err(parse_error(
            path,
            format!(
                "line {l}: {} after the {nv} vertices and {nf} faces the header declares \
                 (is the header's face count wrong?)",
                quote(line)
            ),
        ));
    }
    Ok(raw)
}

fn check_keyword(keyword: &str) -> std::result::Result<(), String> {
    let Some(prefix) = keyword.strip_suffix("OFF") else {
        return Err(format!("expected 'OFF', found '{keyword}'"));
    };
    let mut p = prefix.strip_prefix("ST").unwrap_or(prefix);
    p = p.strip_prefix('C').unwrap_or(p);
    p = p.strip_prefix('N').unwrap_or(p);
    match p {
        "" => Ok(()),
        "4" | "n" | "4n" => Err(format!("'{keyword}' (4-D or n-D OFF) is not supported")),
        _ => Err(format!("expected 'OFF', found '{keyword}'")),
    }
}

pub(super) fn write(w: &mut impl Write, mesh: &TriMesh) -> std::io::Result<()> {
    writeln!(w, "OFF")?;
    writeln!(w, "{} {} 0", mesh.n_vertices(), mesh.n_faces())?;
    for p in mesh.vertices() {
        writeln!(w, "{:?} {:?} {:?}", p[0], p[1], p[2])?;
    }
    for f in mesh.faces() {
        writeln!(w, "3 {} {} {}", f[0], f[1], f[2])?;
    }
    Ok(())
}
